//! `morton`'s WGSL on testkit's device against its CPU functions: 2D and 3D 32-bit encode and
//! decode over random and edge coordinates, and the quantise-then-encode key.

use glam::Vec3;

use testkit::Rng;

#[test]
fn encode_and_decode_match_the_cpu() {
    let mut rng = Rng::new(0x6d6f_7274);
    let mut input = Vec::new();
    for i in 0..20_000u32 {
        let (a, b, c) = match i % 4 {
            0 => (rng.next_u32(), rng.next_u32(), rng.next_u32()),
            1 => (u32::MAX, 0, u32::MAX),
            2 => (i, i >> 3, i * 7),
            _ => (
                rng.next_u32() & 0x3ff,
                rng.next_u32() & 0xffff,
                rng.next_u32() & 0x3ff,
            ),
        };
        input.extend_from_slice(&[a, b, c]);
    }
    let n = (input.len() / 3) as u32;
    let body = "
    let a = input[3u * i];
    let b = input[3u * i + 1u];
    let c = input[3u * i + 2u];
    output[8u * i] = morton_encode2_u32(a, b);
    let d2 = morton_decode2_u32(a);
    output[8u * i + 1u] = d2.x;
    output[8u * i + 2u] = d2.y;
    output[8u * i + 3u] = morton_encode3_u32(a, b, c);
    let d3 = morton_decode3_u32(a);
    output[8u * i + 4u] = d3.x;
    output[8u * i + 5u] = d3.y;
    output[8u * i + 6u] = d3.z;
    output[8u * i + 7u] = 0u;";
    let out = testkit::device::run_words(
        &[morton::wgsl::MODULES],
        "#import morton::codes",
        body,
        &input,
        n,
        8,
        &[],
    );
    for (k, t) in input.chunks_exact(3).enumerate() {
        let (a, b, c) = (t[0], t[1], t[2]);
        let got = &out[8 * k..8 * k + 7];
        // The CPU functions take coordinates within their bit budget: 16 bits per axis in
        // 2D, 10 in 3D; the WGSL masks the same way.
        let want2 = morton::encode2_u32(a & 0xffff, b & 0xffff);
        let d2 = morton::decode2_u32(a);
        let want3 = morton::encode3_u32(a & 0x3ff, b & 0x3ff, c & 0x3ff);
        let d3 = morton::decode3_u32(a);
        assert_eq!(
            got,
            &[want2, d2[0], d2[1], want3, d3[0], d3[1], d3[2]],
            "inputs {a:#x} {b:#x} {c:#x}"
        );
    }
}

#[test]
fn quantised_keys_match_the_cpu() {
    let mut rng = Rng::new(0x7175_616e);
    let q = morton::Quantizer3::new(
        Vec3::new(-100.0, -5.0, 20.0),
        Vec3::new(300.0, 45.0, 80.0),
        10,
    )
    .unwrap();
    let (min, scale) = (q.min(), q.scale());
    let mut input = Vec::new();
    let mut points = Vec::new();
    for _ in 0..20_000 {
        // Inside, on and beyond the box (clamped).
        let p = Vec3::new(
            rng.range(-150.0, 350.0),
            rng.range(-10.0, 50.0),
            rng.range(10.0, 90.0),
        );
        points.push(p);
        input.extend_from_slice(&[p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]);
    }
    let prelude = format!(
        "{}\nconst BOX_MIN = vec3<f32>({:?}, {:?}, {:?});\nconst SCALE = vec3<f32>({:?}, {:?}, {:?});",
        "#import morton::codes", min.x, min.y, min.z, scale.x, scale.y, scale.z
    );
    let body = "
    let p = vec3<f32>(bitcast<f32>(input[3u * i]), bitcast<f32>(input[3u * i + 1u]), bitcast<f32>(input[3u * i + 2u]));
    output[i] = morton_key3_u32(p, BOX_MIN, SCALE, 10u);";
    let out = testkit::device::run_words(
        &[morton::wgsl::MODULES],
        &prelude,
        body,
        &input,
        points.len() as u32,
        1,
        &[],
    );
    for (k, p) in points.iter().enumerate() {
        assert_eq!(out[k], q.morton_u32(*p).unwrap(), "point {p}");
    }
}
