//! The WGSL twins run on testkit's device (lavapipe in CI, the H100 on the device machine)
//! and are compared with the CPU functions they mirror. A machine without any GPU driver
//! fails here, saying how to install one; a GPU test never passes silently. Tolerances
//! are stated per test; they cover the GPU's `exp`/`log2`/`sqrt` and division (a few ulp
//! in WGSL) and fused multiply-adds.

use testkit::device::Resource;
use water::glam::{UVec2, Vec2, Vec3};
use water::noise::{Fbm, FbmParams, NoiseTexture};

/// Bitcasts every binding-0 word reads and binding-1 word writes go through.
const HELPERS: &str = "
fn inf(i: u32) -> f32 { return bitcast<f32>(input[i]); }
fn outf(i: u32, v: f32) { output[i] = bitcast<u32>(v); }
";

/// Runs `body` for invocations `i < items` on testkit's device, after `#import` lines for
/// `imports` and `decl` (the texture and sampler bindings, from 2 on, that `extra` fills),
/// with `input` at binding 0; returns the `items * stride` output words.
fn run(
    imports: &[&str],
    decl: &str,
    body: &str,
    input: &[u32],
    items: usize,
    stride: usize,
    extra: &[Resource<'_>],
) -> Vec<u32> {
    let mut prelude: String = imports.iter().map(|m| format!("#import {m}\n")).collect();
    prelude.push_str(decl);
    prelude.push_str(HELPERS);
    // The layout comes from the shader: binding 0 must be used even by a kernel that
    // reads nothing from it.
    let body = format!("_ = input[0];\n    {body}");
    testkit::device::run_words(
        &[water::wgsl::MODULES],
        &prelude,
        &body,
        input,
        items as u32,
        stride,
        extra,
    )
}

/// An `R32Float` texture.
fn float_texture(width: u32, height: u32, texels: &[f32]) -> Resource<'_> {
    Resource::Texture {
        format: wgpu::TextureFormat::R32Float,
        width,
        height,
        texels: bytemuck::cast_slice(texels),
    }
}

/// An `R32Uint` texture.
fn uint_texture(width: u32, height: u32, texels: &[u32]) -> Resource<'_> {
    Resource::Texture {
        format: wgpu::TextureFormat::R32Uint,
        width,
        height,
        texels: bytemuck::cast_slice(texels),
    }
}

fn f(w: u32) -> f32 {
    f32::from_bits(w)
}

fn words(v: &[f32]) -> Vec<u32> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// `n` random points in `[-0.3, 0.7) * scale` squared.
fn points(n: usize, scale: f32, seed: u64) -> Vec<Vec2> {
    let mut rng = testkit::Rng::new(seed);
    (0..n)
        .map(|_| (Vec2::new(rng.f32(), rng.f32()) - 0.3) * scale)
        .collect()
}

#[test]
fn noise_texture_and_fbm_match_the_cpu() {
    let tex = NoiseTexture::generate(64, 8, 5).unwrap();
    // The generator: every texel within 2e-6.
    let n = 64 * 64;
    let out = run(
        &["water::noise"],
        "",
        "outf(i, water_noise_texel(i % 64u, i / 64u, 64u, 8u, 5u));",
        &[0],
        n,
        1,
        &[],
    );
    let worst = out
        .iter()
        .zip(tex.texels())
        .map(|(&a, &b)| (f(a) - b).abs())
        .fold(0.0, f32::max);
    eprintln!("noise texel: max |gpu - cpu| = {worst:e}");
    assert!(worst <= 2e-6, "{worst}");

    // FBM, exact loads: height with all octaves, and the LOD sample at a distance.
    let fbm = Fbm::new(
        &tex,
        FbmParams {
            frequency: 1.0 / 8.0,
            ..FbmParams::default()
        },
    )
    .unwrap();
    let prm = fbm.gpu_params();
    let pts = points(512, 300.0, 9);
    let mut input: Vec<u32> = bytemuck::cast_slice(&[prm]).to_vec();
    for (k, p) in pts.iter().enumerate() {
        input.extend(words(&[p.x, p.y, k as f32 * 0.7]));
    }
    let m = pts.len();
    let decl = "@group(0) @binding(2) var noise: texture_2d<f32>;";
    let body = "let prm = WaterFbmParams(inf(0u), inf(1u), inf(2u), inf(3u), input[4], input[5], inf(6u), 0u);
        let b = 8u + 3u * i;
        let p = vec2<f32>(inf(b), inf(b + 1u));
        let s = water_fbm_sample(noise, p, inf(b + 2u), prm);
        outf(6u * i, water_fbm(noise, p, prm));
        outf(6u * i + 1u, s.height);
        outf(6u * i + 2u, s.gradient.x);
        outf(6u * i + 3u, s.gradient.y);
        outf(6u * i + 4u, s.dropped_variance);
        outf(6u * i + 5u, s.octaves);";
    let out = run(
        &["water::noise"],
        decl,
        body,
        &input,
        m,
        6,
        &[float_texture(64, 64, tex.texels())],
    );
    let (mut eh, mut es, mut eg, mut ev, mut eo) = (0.0f32, 0.0f32, 0.0f32, 0.0f32, 0.0f32);
    for (k, p) in pts.iter().enumerate() {
        let o = &out[6 * k..6 * k + 6];
        let s = fbm.sample(*p, k as f32 * 0.7);
        eh = eh.max((f(o[0]) - fbm.height(*p)).abs());
        es = es.max((f(o[1]) - s.height).abs());
        eg = eg.max(
            (Vec2::new(f(o[2]), f(o[3])) - s.gradient).length() / s.gradient.length().max(1.0),
        );
        ev = ev.max((f(o[4]) - s.dropped_variance).abs() / s.dropped_variance.max(1e-6));
        eo = eo.max((f(o[5]) - s.octaves).abs());
    }
    eprintln!(
        "fbm: height {eh:e} m, lod height {es:e} m, gradient {eg:e} (rel), dropped variance {ev:e} (rel), octaves {eo:e}"
    );
    // Heights: 0.5 m total amplitude, f32 sums of 9 terms: 1e-6 m. The LOD path goes
    // through log2 (a few ulp on the GPU), which moves the fade weights by ~1e-6.
    assert!(eh <= 1e-6 && es <= 2e-5 && eg <= 1e-4 && ev <= 1e-4 && eo <= 1e-5);

    // FBM through the sampler (R16Float texels, hardware bilinear): the talk's one fetch
    // per octave. Error: the f16 texels (2^-11 relative) and the sampler's sub-texel
    // precision (8 bits on most GPUs: 1/256 of a texel step).
    let body = "let prm = WaterFbmParams(inf(0u), inf(1u), inf(2u), inf(3u), input[4], input[5], inf(6u), 0u);
        let b = 8u + 3u * i;
        outf(i, water_fbm_filtered(noise, samp, vec2<f32>(inf(b), inf(b + 1u)), prm));";
    let decl = "@group(0) @binding(2) var noise: texture_2d<f32>;\n@group(0) @binding(3) var samp: sampler;";
    let halves: Vec<u16> = tex
        .texels()
        .iter()
        .map(|&v| half::f16::from_f32(v).to_bits())
        .collect();
    let filtered = Resource::Texture {
        format: wgpu::TextureFormat::R16Float,
        width: 64,
        height: 64,
        texels: bytemuck::cast_slice(&halves),
    };
    let out = run(
        &["water::noise"],
        decl,
        body,
        &input,
        m,
        1,
        &[filtered, Resource::LinearSampler],
    );
    let worst = pts
        .iter()
        .enumerate()
        .map(|(k, p)| (f(out[k]) - fbm.height(*p)).abs())
        .fold(0.0, f32::max);
    eprintln!("fbm filtered: max |gpu - cpu| = {worst:e} m (amplitude sum 0.5 m)");
    assert!(worst <= 5e-3, "{worst}");
}

#[test]
fn flow_foam_optics_specaa_material_and_data_word_match_the_cpu() {
    use water::flow::{FlowParams, flow_layers, phase_noise};
    use water::foam::{FoamInputs, FoamParams, foam};
    use water::material::{WaterMaterial, blend_weight};
    use water::optics::{Medium, WaterType};
    let n = 256usize;
    let pts = points(n, 40.0, 3);
    let mut input = Vec::new();
    for (k, p) in pts.iter().enumerate() {
        let t = k as f32 * 0.37;
        input.extend(words(&[p.x, p.y, t, (k % 7) as f32 * 0.31 - 1.0]));
    }
    let body = "let b = 4u * i;
        let p = vec2<f32>(inf(b), inf(b + 1u));
        let t = inf(b + 2u);
        let s = inf(b + 3u);
        let prm = WaterFlowParams(1.3, 0.25, 1.0, 0.0);
        let nz = water_value_noise(p * 0.37, 11u);
        let l = water_flow_layers(p * 0.1, vec2<f32>(s, 0.5), t, nz, prm);
        let o = 16u * i;
        outf(o, nz); outf(o + 1u, l.uv0.x); outf(o + 2u, l.uv0.y); outf(o + 3u, l.uv1.x); outf(o + 4u, l.uv1.y); outf(o + 5u, l.w1);
        let fp = WaterFoamParams(3.0, 1.5, 4.0, 0.3, 0.15, 0.2, 1.0, 0.0);
        outf(o + 6u, water_foam(WaterFoamInputs(p.x * 0.1, abs(p.y) * 0.1, t, s, -s * 0.5, 0.1 * s), fp));
        let m = WaterMedium(vec4<f32>(0.4, 0.1, 0.05, 0.0), vec4<f32>(0.3, 0.35, 0.4, 0.0));
        let lt = water_light_transport(m, vec3<f32>(0.2, 0.5, 0.1), vec3<f32>(1.0, 0.9, 0.8), t);
        outf(o + 7u, lt.x); outf(o + 8u, lt.y); outf(o + 9u, lt.z);
        outf(o + 10u, water_filtered_alpha(0.1 + 0.001 * f32(i), s * s * 0.05, WATER_SPECAA_KAPPA, 0.6));
        outf(o + 11u, water_blend_weight(p.x * 0.1, 6.0));
        output[o + 12u] = water_pack_data(i & 255u, i & 7u, i * 7u, t * 0.1, s + 1.0);
        let dw = water_unpack_data(i * 2654435761u);
        output[o + 13u] = dw.material;
        outf(o + 14u, dw.foam_mip + 100.0 * dw.algae_mip);
        outf(o + 15u, water_decal_fade(vec3<f32>(p.x, p.y, s) * 0.03, 0.25));";
    // `water::flow` brings `water::noise` with it.
    let imports = [
        "water::flow",
        "water::foam",
        "water::optics",
        "water::specaa",
        "water::material",
        "water::gbuffer",
        "water::decal",
    ];
    let out = run(&imports, "", body, &input, n, 16, &[]);
    let fp = FlowParams {
        interval: 1.3,
        distance: 0.25,
        noise_strength: 1.0,
    };
    let medium = Medium::new(Vec3::new(0.4, 0.1, 0.05), Vec3::new(0.3, 0.35, 0.4));
    let mut worst = [0.0f32; 8];
    for (k, p) in pts.iter().enumerate() {
        let o = &out[16 * k..16 * k + 16];
        let (t, s) = (k as f32 * 0.37, (k % 7) as f32 * 0.31 - 1.0);
        let nz = phase_noise(*p * 0.37, 11);
        worst[0] = worst[0].max((f(o[0]) - nz).abs());
        let l = flow_layers(*p * 0.1, Vec2::new(s, 0.5), t, nz, &fp);
        let e = (Vec2::new(f(o[1]), f(o[2])) - l.uv0)
            .length()
            .max((Vec2::new(f(o[3]), f(o[4])) - l.uv1).length());
        worst[1] = worst[1].max(e.max((f(o[5]) - l.w1).abs()));
        let fi = FoamInputs {
            signed_distance: p.x * 0.1,
            flow_speed: p.y.abs() * 0.1,
            depth: t,
            detail_noise: s,
            mask_noise: -s * 0.5,
            displacement_foam: 0.1 * s,
        };
        worst[2] = worst[2].max((f(o[6]) - foam(&fi, &FoamParams::default())).abs());
        let lt = medium.light_transport(Vec3::new(0.2, 0.5, 0.1), Vec3::new(1.0, 0.9, 0.8), t);
        worst[3] = worst[3].max(
            (Vec3::new(f(o[7]), f(o[8]), f(o[9])) - lt)
                .abs()
                .max_element(),
        );
        let a = water::specaa::filtered_alpha(
            0.1 + 0.001 * k as f32,
            s * s * 0.05,
            water::specaa::DEFAULT_KAPPA,
            0.6,
        );
        worst[4] = worst[4].max((f(o[10]) - a).abs());
        worst[5] = worst[5].max((f(o[11]) - blend_weight(p.x * 0.1, 6.0)).abs());
        let i = k as u32;
        let fields = water::gbuffer::DataFields {
            shader_id: (i & 255) as u8,
            flags: water::gbuffer::DataFlags((i & 7) as u8),
            material: ((i * 7) & 2047) as u16,
            foam_mip: t * 0.1,
            algae_mip: s + 1.0,
        };
        assert_eq!(
            o[12],
            water::gbuffer::DataWord::pack(fields).unwrap().0,
            "data word {k}"
        );
        let dw = water::gbuffer::DataWord(i.wrapping_mul(2_654_435_761)).unpack();
        assert_eq!(o[13], u32::from(dw.material));
        assert_eq!(f(o[14]), dw.foam_mip + 100.0 * dw.algae_mip);
        let fade = water::decal::edge_fade(Vec3::new(p.x, p.y, s) * 0.03, 0.25);
        worst[6] = worst[6].max((f(o[15]) - fade).abs());
    }
    eprintln!(
        "phase noise {:e}, flow layers {:e}, foam {:e}, light {:e}, alpha {:e}, blend {:e}, decal fade {:e}",
        worst[0], worst[1], worst[2], worst[3], worst[4], worst[5], worst[6]
    );
    // exp and sqrt are a few ulp on GPUs; everything else is the same arithmetic.
    for (k, w) in worst.iter().enumerate() {
        assert!(*w <= 2e-5, "quantity {k}: {w}");
    }
    // The material blend: a record per weight.
    let a = WaterMaterial::from_type(&WaterType::RIVER).to_gpu();
    let mut b = WaterMaterial::from_type(&WaterType::MUDDY);
    b.shader_id = 5;
    b.roughness = 0.4;
    let b = b.to_gpu();
    let mut input: Vec<u32> = bytemuck::cast_slice(&[a, b]).to_vec();
    input.extend(words(&[0.0, 0.3, 0.5, 0.9]));
    let body = "var recs: array<WaterMaterialGpu, 2>;
        for (var r = 0u; r < 2u; r++) {
            let o = 16u * r;
            recs[r] = WaterMaterialGpu(vec4<f32>(inf(o), inf(o + 1u), inf(o + 2u), inf(o + 3u)), vec4<f32>(inf(o + 4u), inf(o + 5u), inf(o + 6u), inf(o + 7u)),
                inf(o + 8u), inf(o + 9u), inf(o + 10u), inf(o + 11u), input[o + 12u], input[o + 13u], input[o + 14u], 0u);
        }
        let m = water_material_blend(recs[0], recs[1], inf(32u + i));
        let o = 16u * i;
        outf(o, m.absorption.x); outf(o + 1u, m.absorption.y); outf(o + 2u, m.absorption.z); outf(o + 3u, m.absorption.w);
        outf(o + 4u, m.scattering.x); outf(o + 5u, m.scattering.y); outf(o + 6u, m.scattering.z); outf(o + 7u, m.scattering.w);
        outf(o + 8u, m.displacement_amplitude); outf(o + 9u, m.foam_intensity); outf(o + 10u, m.shore_width); outf(o + 11u, m.detail_weight);
        output[o + 12u] = m.ids; output[o + 13u] = m.foam_texture; output[o + 14u] = m.algae_texture;";
    let out = run(&["water::material"], "", body, &input, 4, 16, &[]);
    for (k, t) in [0.0f32, 0.3, 0.5, 0.9].into_iter().enumerate() {
        let cpu = WaterMaterial::from_gpu(&a)
            .blend(&WaterMaterial::from_gpu(&b), t)
            .to_gpu();
        let cpu_words: &[u32] = bytemuck::cast_slice(std::slice::from_ref(&cpu));
        // Floats within an ulp or two (GPUs may fuse the multiply-add), indices exact.
        for j in 0..12 {
            let (g, c) = (f(out[16 * k + j]), f(cpu_words[j]));
            assert!(
                (g - c).abs() <= 2e-7 * c.abs().max(1.0),
                "blend at {t}, field {j}: {g} vs {c}"
            );
        }
        assert_eq!(
            &out[16 * k + 12..16 * k + 15],
            &cpu_words[12..15],
            "blend at {t}"
        );
    }
}

#[test]
fn grid_vertices_and_normals_from_depth_match_the_cpu() {
    use water::normals::{DepthCamera, DepthView, Taps};
    use water::tiles::{GridMesh, GridVertex};
    let mesh = GridMesh::new(16).unwrap();
    let n = mesh.vertices().len();
    let input: Vec<u32> = mesh.vertices().iter().map(|&v| u32::from(v)).collect();
    let body = "let v = water_grid_vertex(input[i]);
        let p = water_grid_position(v);
        output[2u * i] = p.x | (p.y << 16u);
        let c = water_grid_corner_pixel(v, 2u, vec2<u32>(64u, 32u), 32u, 16u, vec2<u32>(96u, 64u));
        output[2u * i + 1u] = c.x | (c.y << 16u);";
    let out = run(&["water::tiles"], "", body, &input, n, 2, &[]);
    for (k, &w) in mesh.vertices().iter().enumerate() {
        let v = GridVertex::unpack(w);
        let p = v.position();
        assert_eq!(out[2 * k], p.x | p.y << 16);
        let c = (UVec2::new(64, 32) + v.triangle_corners()[2] * 32 / 16).min(UVec2::new(95, 63));
        assert_eq!(out[2 * k + 1], c.x | c.y << 16);
    }

    // Depth of a tilted plane in front of a farther wall (an edge down the middle).
    let size = UVec2::new(64, 48);
    let cam = DepthCamera {
        size,
        tan_half_fov: Vec2::new(0.8, 0.6),
    };
    let depth: Vec<f32> = (0..size.x * size.y)
        .map(|i| {
            let (x, y) = (i % size.x, i / size.x);
            if x < 30 {
                5.0 + 0.05 * y as f32 + 0.02 * x as f32
            } else {
                12.0
            }
        })
        .collect();
    let view = DepthView {
        depth: &depth,
        camera: cam,
    };
    let count = (size.x * size.y) as usize;
    let body = "let p = vec2<i32>(i32(i % 64u), i32(i / 64u));
        let a = water_normal_from_depth(depth, p, 1u, WATER_TAPS_FIVE, vec2<f32>(0.8, 0.6));
        let b = water_normal_from_depth(depth, p, 2u, WATER_TAPS_NINE, vec2<f32>(0.8, 0.6));
        outf(6u * i, a.x); outf(6u * i + 1u, a.y); outf(6u * i + 2u, a.z);
        outf(6u * i + 3u, b.x); outf(6u * i + 4u, b.y); outf(6u * i + 5u, b.z);";
    let decl = "@group(0) @binding(2) var depth: texture_2d<f32>;";
    let out = run(
        &["water::normals"],
        decl,
        body,
        &[0],
        count,
        6,
        &[float_texture(size.x, size.y, &depth)],
    );
    let mut worst: f32 = 0.0;
    for k in 0..count {
        let p = UVec2::new(k as u32 % size.x, k as u32 / size.x);
        for (o, taps, r) in [(0, Taps::Five, 1), (3, Taps::Nine, 2)] {
            let gpu = Vec3::new(
                f(out[6 * k + o]),
                f(out[6 * k + o + 1]),
                f(out[6 * k + o + 2]),
            );
            let cpu = view.normal(p, r, taps).unwrap_or(Vec3::ZERO);
            worst = worst.max((gpu - cpu).length());
        }
    }
    eprintln!("normals from depth: max |gpu - cpu| = {worst:e}");
    assert!(worst <= 1e-4, "{worst}");
}

#[test]
fn world_query_and_flow_atlas_match_the_cpu() {
    use water::atlas::{FlowAtlas, FlowAtlasSettings};
    use water::flowbake::FlowField;
    use water::world::{Lake, Ocean, River, RiverPoint, WaterWorldBuilder};
    let mut b = WaterWorldBuilder::new();
    b.ocean = Some(Ocean {
        level: -1.0,
        material: 9,
    });
    let star: Vec<Vec2> = (0..200)
        .map(|i| {
            let a = i as f32 / 200.0 * std::f32::consts::TAU;
            let r = 60.0 + 25.0 * (a * 7.0).sin();
            Vec2::new(100.0 + r * a.cos(), 80.0 + r * a.sin())
        })
        .collect();
    b.lakes.push(Lake {
        polygon: star.clone(),
        height: 4.0,
        material: 1,
    });
    let pt = |x: f32, y: f32, z: f32| RiverPoint {
        position: Vec3::new(x, y, z),
        width: 14.0,
        depth: 2.0,
        speed: 3.0,
    };
    b.rivers.push(River {
        points: vec![
            pt(-50.0, 0.0, 12.0),
            pt(40.0, 30.0, 10.0),
            pt(90.0, 100.0, 6.0),
            pt(95.0, 104.0, 4.5),
            pt(200.0, 160.0, 4.0),
        ],
        material: 2,
    });
    let world = b.build(&mut water::no_progress).unwrap();
    let (tex, tw, th) = world.to_texture(1024);
    let pts = points(4096, 330.0, 21);
    let n = pts.len();
    let input: Vec<u32> = pts
        .iter()
        .flat_map(|p| [p.x.to_bits(), p.y.to_bits()])
        .collect();
    let body = "let q = water_world_query(world, vec2<f32>(inf(2u * i), inf(2u * i + 1u)));
        let o = 7u * i;
        output[o] = q.found; outf(o + 1u, q.height); output[o + 2u] = q.body; output[o + 3u] = q.material;
        outf(o + 4u, q.depth); outf(o + 5u, q.flow.x); outf(o + 6u, q.flow.y);";
    let decl = "@group(0) @binding(2) var world: texture_2d<u32>;";
    let out = run(
        &["water::world"],
        decl,
        body,
        &input,
        n,
        7,
        &[uint_texture(tw, th, &tex)],
    );
    let (mut bodies, mut eh, mut ef) = (0, 0.0f32, 0.0f32);
    for (k, p) in pts.iter().enumerate() {
        let o = &out[7 * k..7 * k + 7];
        let cpu = world.query(*p).expect("the ocean is everywhere");
        assert_eq!(o[0], 1);
        if o[2] != cpu.body.0 {
            bodies += 1;
            continue;
        }
        assert_eq!(o[3], cpu.material);
        eh = eh.max((f(o[1]) - cpu.height).abs());
        if cpu.depth.is_finite() {
            eh = eh.max((f(o[4]) - cpu.depth).abs());
        } else {
            assert!(f(o[4]).is_infinite());
        }
        ef = ef.max((Vec2::new(f(o[5]), f(o[6])) - cpu.flow).length());
    }
    eprintln!(
        "world query: {bodies} of {n} points name another body (lake-edge rounding), height/depth {eh:e} m, flow {ef:e} m/s"
    );
    assert!(bodies <= 2, "{bodies}");
    assert!(eh <= 1e-4 && ef <= 1e-4);

    // The flow atlas.
    let fw = 256u32;
    let flow: Vec<Vec2> = (0..fw * fw)
        .map(|i| {
            Vec2::new(
                ((i % fw) as f32 * 0.05).sin(),
                ((i / fw) as f32 * 0.03).cos(),
            ) * 2.0
        })
        .collect();
    let field = FlowField::from_flow(fw, fw, 1.0, Vec2::new(-10.0, 5.0), flow).unwrap();
    let s = FlowAtlasSettings {
        tile_res: 32,
        width: 512,
        slots: 8,
        ..Default::default()
    };
    let atlas = FlowAtlas::build(&field, &s, |c| c.x != c.y, &mut water::no_progress).unwrap();
    let pts = points(4096, 300.0, 5);
    let input: Vec<u32> = pts
        .iter()
        .flat_map(|p| [p.x.to_bits(), p.y.to_bits()])
        .collect();
    let body = "let r = water_flow_atlas_sample(atlas, vec2<f32>(inf(2u * i), inf(2u * i + 1u)));
        outf(3u * i, r.x); outf(3u * i + 1u, r.y); outf(3u * i + 2u, r.z);";
    let decl = "@group(0) @binding(2) var atlas: texture_2d<u32>;";
    let out = run(
        &["water::atlas"],
        decl,
        body,
        &input,
        n,
        3,
        &[uint_texture(atlas.width(), atlas.height(), atlas.texels())],
    );
    let mut worst: f32 = 0.0;
    for (k, p) in pts.iter().enumerate() {
        match atlas.sample(*p) {
            Some(v) => {
                assert_eq!(f(out[3 * k + 2]), 1.0);
                worst = worst.max((Vec2::new(f(out[3 * k]), f(out[3 * k + 1])) - v).length());
            }
            None => assert_eq!(f(out[3 * k + 2]), 0.0),
        }
    }
    eprintln!("flow atlas: max |gpu - cpu| = {worst:e} m/s");
    assert!(worst <= 1e-4, "{worst}");
}
