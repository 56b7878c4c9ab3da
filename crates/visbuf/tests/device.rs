//! `visbuf`'s WGSL on testkit's device against its CPU functions: vis-ID decode and pack over many
//! words and every primitive-bit count, barycentrics and derivatives over random triangles.

use glam::{Vec2, Vec4};
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
fn barycentrics_and_derivatives_match_the_cpu() {
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
    let o = 9u * i;
    for (var k = 0u; k < 3u; k++) {
        output[o + k] = bitcast<u32>(r.lambda[k]);
        output[o + 3u + k] = bitcast<u32>(r.ddx[k]);
        output[o + 6u + k] = bitcast<u32>(r.ddy[k]);
    }";
    let out = testkit::device::run_words(
        &[visbuf::wgsl::MODULES],
        "#import visbuf::bary",
        body,
        &input,
        cases.len() as u32,
        9,
        &[],
    );
    let mut worst = 0.0f32;
    for (k, (clip, pixel)) in cases.iter().enumerate() {
        let cpu = visbuf::bary::barycentrics(*clip, *pixel, viewport);
        let g: Vec<f32> = out[9 * k..9 * k + 9]
            .iter()
            .map(|&w| f32::from_bits(w))
            .collect();
        for (i, want) in [cpu.lambda, cpu.ddx, cpu.ddy]
            .iter()
            .flat_map(|v| v.to_array())
            .enumerate()
        {
            // Relative to the weights' own scale (they sum to 1, derivatives to 0).
            let scale = 1.0 + cpu.lambda.abs().max_element();
            let err = (g[i] - want).abs() / scale;
            worst = worst.max(err);
            assert!(g[i].is_finite(), "case {k}: non-finite GPU value");
            assert!(err < 1e-4, "case {k} value {i}: gpu {} cpu {want}", g[i]);
        }
    }
    eprintln!("barycentrics: worst GPU/CPU difference {worst:e} (relative)");
}
