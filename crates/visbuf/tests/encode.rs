//! The primitive-ID encoders against independent decoders, on structured and random meshes.

mod common;

use common::*;
use proptest::prelude::*;
use visbuf::{Error, encode_provoking, encode_provoking_greedy, encode_xor, encode_xor_greedy};

fn all_valid(src: &[u32], vc: u32) -> [u32; 4] {
    let p = encode_provoking(src, vc).unwrap();
    check_provoking(src, vc, &p);
    let pg = encode_provoking_greedy(src, vc).unwrap();
    check_provoking(src, vc, &pg);
    let x = encode_xor(src, vc).unwrap();
    check_xor(src, vc, &x);
    let xg = encode_xor_greedy(src, vc).unwrap();
    check_xor(src, vc, &xg);
    [
        p.added_vertices(),
        pg.added_vertices(),
        x.added_vertices(),
        xg.added_vertices(),
    ]
}

#[test]
fn grid_sphere_soup_and_bunny_decode_to_every_triangle() {
    let (g, gv) = grid(40);
    let (s, sv) = uv_sphere(30, 40);
    let (r, rv) = soup(3000, 1500, 7);
    let (_, b) = bunny();
    let bv = 1839;
    for (name, src, vc) in [
        ("grid", &g, gv),
        ("sphere", &s, sv),
        ("soup", &r, rv),
        ("bunny", &b, bv),
    ] {
        let [p, pg, x, xg] = all_valid(src, vc);
        let t = src.len() as u32 / 3;
        // Lower bound for any scheme: one own vertex (or payload) per triangle.
        assert!(p >= t.saturating_sub(vc), "{name}");
        assert!(pg >= p, "{name}: optimal provoking beats greedy");
        // XOR has no such bound (a copy's payload can serve several triangles), but
        // peeling should not lose to the greedy pass by more than a few vertices.
        assert!(
            x <= xg + xg / 50 + 2,
            "{name}: peeling XOR {x} vs greedy {xg}"
        );
    }
}

#[test]
fn provoking_is_optimal_against_a_simple_matching() {
    for seed in 1..30 {
        let (src, vc) = soup(60 + seed as u32 * 7, 20 + seed as u32, seed);
        let p = encode_provoking(&src, vc).unwrap();
        let t = src.len() as u32 / 3;
        assert_eq!(
            p.added_vertices(),
            t - kuhn_matching(&src, vc),
            "seed {seed}"
        );
    }
    let (src, vc) = grid(12);
    let p = encode_provoking(&src, vc).unwrap();
    assert_eq!(
        p.added_vertices(),
        src.len() as u32 / 3 - kuhn_matching(&src, vc)
    );
}

#[test]
fn degenerate_triangles_encode() {
    // Repeated corners: (a, a, b) and (a, a, a); the XOR of (a, a, b) is b's payload.
    let src = [0u32, 0, 1, 2, 2, 2, 1, 2, 0, 0, 0, 1, 1, 1, 1];
    all_valid(&src, 3);
    let x = encode_xor(&src, 3).unwrap();
    assert_eq!(x.xor_id(1), Some(1));
    assert_eq!(x.xor_id(5), None);
    let p = encode_provoking(&src, 3).unwrap();
    assert_eq!(p.provoking_id(4), Some(4));
}

#[test]
fn full_size_geometry_encodes() {
    // 65 536 triangles, the most a geometry may have: payloads use all 16 bits.
    let (src, vc) = soup(65536, 40000, 99);
    all_valid(&src, vc);
}

#[test]
fn bad_input_is_an_error_naming_the_limit() {
    assert_eq!(
        encode_xor(&[0u32, 1], 2),
        Err(Error::IndexCountNotMultipleOf3 { len: 2 })
    );
    assert_eq!(
        encode_provoking(&[0u32, 1, 2, 0, 1, 5], 3),
        Err(Error::IndexOutOfRange {
            triangle: 1,
            index: 5,
            vertex_count: 3
        })
    );
    let too_many = vec![0u32; 3 * 65537];
    assert_eq!(
        encode_provoking_greedy(&too_many, 1),
        Err(Error::TooManyPrimitives {
            count: 65537,
            limit: 65536
        })
    );
    assert_eq!(
        encode_xor_greedy(&[0u32, 1, 2], 65537),
        Err(Error::TooManyVertices {
            count: 65537,
            limit: 65536
        })
    );
    let msg = encode_xor(&too_many, 1).unwrap_err().to_string();
    assert!(
        msg.contains("MAX_PRIMITIVES_PER_GEOMETRY") && msg.contains("65537"),
        "{msg}"
    );
    // Empty meshes are fine and add nothing.
    assert_eq!(encode_xor::<u32>(&[], 0).unwrap().added_vertices(), 0);
}

#[test]
fn u16_indices_and_vertex_remap() {
    let src: Vec<u16> = vec![0, 1, 2, 2, 1, 3, 0, 2, 3, 1, 0, 3];
    let x = encode_xor(&src, 4).unwrap();
    let wide: Vec<u32> = src.iter().map(|&i| i as u32).collect();
    check_xor(&wide, 4, &x);
    let data = ["a", "b", "c", "d"];
    let out = x.remap_vertices(&data).unwrap();
    assert_eq!(out.len() as u32, x.vertex_count());
    assert_eq!(&out[..4], &data);
    assert_eq!(
        x.remap_vertices(&data[..3]),
        Err(Error::VertexDataTooShort { len: 3, needed: 4 })
    );
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn random_meshes_decode(vc in 1u32..40, raw in proptest::collection::vec(any::<u32>(), 0..300)) {
        let n = raw.len() / 3 * 3;
        let src: Vec<u32> = raw[..n].iter().map(|r| r % vc).collect();
        let [p, pg, x, xg] = all_valid(&src, vc);
        prop_assert!(p <= pg);
        let _ = (x, xg);
        prop_assert_eq!(p, n as u32 / 3 - kuhn_matching(&src, vc));
    }
}
