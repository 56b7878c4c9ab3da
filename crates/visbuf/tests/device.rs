//! `visbuf`'s WGSL on testkit's device against its CPU functions: vis-ID decode and pack over many
//! words and every primitive-bit count, barycentrics and derivatives over random triangles,
//! the watertight ray-triangle fallback over random rays.

use glam::{Vec2, Vec3, Vec4};
use visbuf::{PrimitiveBits, VisFields, VisId, VisLayout};

use testkit::Rng;

#[test]
fn id_decode_and_pack_match_the_cpu_for_every_primitive_bit_count() {
    let mut rng = Rng::new(0x1234_5678);
    let mut input = Vec::new();
    for i in 0..20_000u32 {
        let word = match i % 4 {
            0 => rng.next_u32(),
            1 => visbuf::VIS_NONE,
            2 => i,
            _ => rng.next_u32() | 0xffff_0000,
        };
        input.extend_from_slice(&[word, i % 17]);
    }
    let n = (input.len() / 2) as u32;
    let body = "
    let word = input[2u * i];
    let p = input[2u * i + 1u];
    let mb = visbuf_micro_batch(word);
    let field = visbuf_instance_field(word, p);
    let prim = visbuf_primitive(word, p);
    output[5u * i] = mb;
    output[5u * i + 1u] = field;
    output[5u * i + 2u] = prim;
    output[5u * i + 3u] = visbuf_pack_id(mb, field, prim, p);
    output[5u * i + 4u] = select(0u, 1u, visbuf_is_none(word));";
    let out = testkit::device::run_words(
        &[visbuf::wgsl::MODULES],
        "#import visbuf::id",
        body,
        &input,
        n,
        5,
        &[],
    );
    for (k, pair) in input.chunks_exact(2).enumerate() {
        let (word, p) = (VisId(pair[0]), pair[1]);
        let bits = PrimitiveBits::new(p).expect("0..=16");
        let got = &out[5 * k..5 * k + 5];
        let want_mb = word.micro_batch(VisLayout::Standard);
        let (field, prim) = (word.instance_field(bits), word.primitive(bits));
        assert_eq!(got[0], want_mb, "word {:#x} p {p}", word.0);
        assert_eq!(got[1], field, "word {:#x} p {p}", word.0);
        assert_eq!(got[2], prim, "word {:#x} p {p}", word.0);
        let fields = VisFields {
            micro_batch: want_mb,
            instance: field,
            primitive: prim,
            rate: visbuf::ShadingRate::Rate1x1,
        };
        if let Ok(repacked) = VisId::pack(VisLayout::Standard, bits, fields) {
            assert_eq!(got[3], repacked.0, "repack of {:#x} p {p}", word.0);
        }
        assert_eq!(got[4] == 1, word.is_none());
    }
}

#[test]
fn barycentrics_derivatives_and_clamped_weights_match_the_cpu() {
    let mut rng = Rng::new(0xbeef);
    let viewport = Vec2::new(1920.0, 1080.0);
    let mut input: Vec<u32> = Vec::new();
    let mut cases = Vec::new();
    for _ in 0..4096 {
        let clip: [Vec4; 3] = std::array::from_fn(|_| {
            let w = rng.range(0.2, 60.0);
            Vec4::new(rng.range(-1.2, 1.2) * w, rng.range(-1.2, 1.2) * w, 0.1, w)
        });
        let pixel = Vec2::new(
            rng.range(0.0, 1920.0).floor() + 0.5,
            rng.range(0.0, 1080.0).floor() + 0.5,
        );
        for c in clip {
            input.extend(c.to_array().map(f32::to_bits));
        }
        input.extend([pixel.x.to_bits(), pixel.y.to_bits()]);
        cases.push((clip, pixel));
    }
    let body = "
    let b = 14u * i;
    let c0 = bitcast<vec4<f32>>(vec4<u32>(input[b], input[b + 1u], input[b + 2u], input[b + 3u]));
    let c1 = bitcast<vec4<f32>>(vec4<u32>(input[b + 4u], input[b + 5u], input[b + 6u], input[b + 7u]));
    let c2 = bitcast<vec4<f32>>(vec4<u32>(input[b + 8u], input[b + 9u], input[b + 10u], input[b + 11u]));
    let px = bitcast<vec2<f32>>(vec2<u32>(input[b + 12u], input[b + 13u]));
    let r = visbuf_barycentrics(c0, c1, c2, px, vec2<f32>(1920.0, 1080.0));
    let c = visbuf_clamp_barycentrics(r);
    let o = 12u * i;
    for (var k = 0u; k < 3u; k++) {
        output[o + k] = bitcast<u32>(r.lambda[k]);
        output[o + 3u + k] = bitcast<u32>(r.ddx[k]);
        output[o + 6u + k] = bitcast<u32>(r.ddy[k]);
        output[o + 9u + k] = bitcast<u32>(c.lambda[k]);
    }";
    let out = testkit::device::run_words(
        &[visbuf::wgsl::MODULES],
        "#import visbuf::bary",
        body,
        &input,
        cases.len() as u32,
        12,
        &[],
    );
    let mut worst = 0.0f32;
    for (k, (clip, pixel)) in cases.iter().enumerate() {
        let cpu = visbuf::bary::barycentrics(*clip, *pixel, viewport);
        let g: Vec<f32> = out[12 * k..12 * k + 12]
            .iter()
            .map(|&w| f32::from_bits(w))
            .collect();
        // Then the clamped weights (most pixels lie outside their random triangle).
        for (i, want) in [cpu.lambda, cpu.ddx, cpu.ddy, cpu.clamped().lambda]
            .iter()
            .flat_map(|v| v.to_array())
            .enumerate()
        {
            // Relative to the weights' own scale (they sum to 1, derivatives to 0); the
            // clamped ones divide that error by their positive weights' sum.
            let mut scale = 1.0 + cpu.lambda.abs().max_element();
            if i >= 9 {
                scale /= cpu.lambda.max(Vec3::ZERO).element_sum();
            }
            let err = (g[i] - want).abs() / scale;
            worst = worst.max(err);
            assert!(g[i].is_finite(), "case {k}: non-finite GPU value");
            assert!(err < 1e-4, "case {k} value {i}: gpu {} cpu {want}", g[i]);
        }
    }
    eprintln!("barycentrics: worst GPU/CPU difference {worst:e} (relative)");
}

#[test]
fn the_watertight_ray_matches_the_cpu() {
    let mut rng = Rng::new(0x4a7);
    let mut input: Vec<u32> = Vec::new();
    let mut cases = Vec::new();
    for _ in 0..4096 {
        let c = Vec3::new(
            rng.range(-4.0, 4.0),
            rng.range(-4.0, 4.0),
            rng.range(-50.0, -1.0),
        );
        let tri: [Vec3; 3] = std::array::from_fn(|_| {
            c + Vec3::new(
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
            )
        });
        // Aimed near the triangle: about half hit.
        let w = Vec3::new(rng.f32(), rng.f32(), rng.f32());
        let dir = (tri[0] * w.x + tri[1] * w.y + tri[2] * w.z) / (w.x + w.y + w.z)
            + Vec3::new(rng.range(-0.8, 0.8), rng.range(-0.8, 0.8), 0.0);
        for v in tri.iter().chain([&dir]) {
            input.extend(v.to_array().map(f32::to_bits));
        }
        cases.push((tri, dir));
    }
    let body = "
    let b = 12u * i;
    var v: array<vec3<f32>, 4>;
    for (var k = 0u; k < 4u; k++) {
        v[k] = bitcast<vec3<f32>>(vec3<u32>(input[b + 3u * k], input[b + 3u * k + 1u], input[b + 3u * k + 2u]));
    }
    let h = visbuf_intersect_watertight(vec3<f32>(0.0), v[3], v[0], v[1], v[2]);
    let o = 5u * i;
    output[o] = select(0u, 1u, h.hit);
    output[o + 1u] = bitcast<u32>(h.t);
    for (var k = 0u; k < 3u; k++) {
        output[o + 2u + k] = bitcast<u32>(h.barycentrics[k]);
    }";
    let out = testkit::device::run_words(
        &[visbuf::wgsl::MODULES],
        "#import visbuf::ray",
        body,
        &input,
        cases.len() as u32,
        5,
        &[],
    );
    let (mut hits, mut worst) = (0, 0.0f32);
    for (k, (tri, dir)) in cases.iter().enumerate() {
        let cpu = visbuf::ray::intersect_watertight(Vec3::ZERO, *dir, *tri);
        let g = &out[5 * k..5 * k + 5];
        let hit = g[0] == 1;
        match cpu {
            Some(h) => {
                assert!(hit, "case {k}: the CPU hits, the GPU misses");
                let b = Vec3::new(
                    f32::from_bits(g[2]),
                    f32::from_bits(g[3]),
                    f32::from_bits(g[4]),
                );
                let err = (b - h.barycentrics).abs().max_element();
                worst = worst.max(err);
                assert!(err < 1e-5, "case {k}: gpu {b} cpu {}", h.barycentrics);
                let t = f32::from_bits(g[1]);
                assert!((t - h.t).abs() <= 1e-5 * h.t.abs().max(1.0), "case {k}: t");
                hits += 1;
            }
            None => assert!(!hit, "case {k}: the GPU hits, the CPU misses"),
        }
    }
    assert!(hits > 1000 && hits < 4000, "{hits} hits");
    eprintln!(
        "ray: {hits} hits of {}, worst barycentric difference {worst:e}",
        cases.len()
    );
}
