//! CPU/GPU agreement: the WGSL twins run on testkit's device (lavapipe in CI) against the
//! Rust functions they mirror. A machine without any GPU driver fails here, saying how to
//! install one.
//!
//! Where the two sides may legitimately round differently (device `pow`/`log2`/division,
//! the precise normal encoder choosing between two codes at a near-tie) the tests allow
//! exactly that and count it; everything else must match bit for bit.

mod common;

use deferred::lights::{TileFrustum, tile_counts};
use deferred::normal::oct_decode;
use deferred::{
    DeferredLight, DeferredTileDepth, DepthMode, Kz2Texels, OctTexels, Perspective, Surface,
};
use glam::{Vec2, Vec3};
use testkit::Rng;

/// Runs `body` for `items` invocations on testkit's device, after `prelude` (whose
/// `#import` lines name this crate's modules); returns `items * out_stride` output words.
fn run(prelude: &str, body: &str, input: &[u32], items: u32, out_stride: usize) -> Vec<u32> {
    testkit::device::run_words(
        &[deferred::wgsl::MODULES],
        prelude,
        body,
        input,
        items,
        out_stride,
        &[],
    )
}

/// A uniformly distributed unit vector.
fn unit(rng: &mut Rng) -> Vec3 {
    let z = rng.range(-1.0, 1.0);
    let phi = rng.range(0.0, std::f32::consts::TAU);
    let r = (1.0 - z * z).max(0.0).sqrt();
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

const SURFACE_WGSL_READ: &str = "
fn read_surface(i: u32) -> DeferredSurface {
    let b = i * 15u;
    var s: DeferredSurface;
    s.lighting = vec3<f32>(bitcast<f32>(input[b]), bitcast<f32>(input[b + 1u]), bitcast<f32>(input[b + 2u]));
    s.albedo = vec3<f32>(bitcast<f32>(input[b + 3u]), bitcast<f32>(input[b + 4u]), bitcast<f32>(input[b + 5u]));
    s.normal = vec3<f32>(bitcast<f32>(input[b + 6u]), bitcast<f32>(input[b + 7u]), bitcast<f32>(input[b + 8u]));
    s.roughness = bitcast<f32>(input[b + 9u]);
    s.specular = bitcast<f32>(input[b + 10u]);
    s.sun_shadow = bitcast<f32>(input[b + 11u]);
    s.motion = vec2<f32>(bitcast<f32>(input[b + 12u]), bitcast<f32>(input[b + 13u]));
    s.metallic = bitcast<f32>(input[b + 14u]);
    return s;
}
fn write_surface(o: u32, s: DeferredSurface) {
    output[o] = bitcast<u32>(s.lighting.x); output[o + 1u] = bitcast<u32>(s.lighting.y);
    output[o + 2u] = bitcast<u32>(s.lighting.z); output[o + 3u] = bitcast<u32>(s.albedo.x);
    output[o + 4u] = bitcast<u32>(s.albedo.y); output[o + 5u] = bitcast<u32>(s.albedo.z);
    output[o + 6u] = bitcast<u32>(s.normal.x); output[o + 7u] = bitcast<u32>(s.normal.y);
    output[o + 8u] = bitcast<u32>(s.normal.z); output[o + 9u] = bitcast<u32>(s.roughness);
    output[o + 10u] = bitcast<u32>(s.specular); output[o + 11u] = bitcast<u32>(s.sun_shadow);
    output[o + 12u] = bitcast<u32>(s.motion.x); output[o + 13u] = bitcast<u32>(s.motion.y);
    output[o + 14u] = bitcast<u32>(s.metallic);
}
";

fn surface_words(s: &Surface) -> [u32; 15] {
    let f = [
        s.lighting.x,
        s.lighting.y,
        s.lighting.z,
        s.albedo.x,
        s.albedo.y,
        s.albedo.z,
        s.normal.x,
        s.normal.y,
        s.normal.z,
        s.roughness,
        s.specular,
        s.sun_shadow,
        s.motion.x,
        s.motion.y,
        s.metallic,
    ];
    f.map(f32::to_bits)
}

fn surface_from(w: &[u32]) -> Surface {
    let f = |i: usize| f32::from_bits(w[i]);
    Surface {
        lighting: Vec3::new(f(0), f(1), f(2)),
        albedo: Vec3::new(f(3), f(4), f(5)),
        normal: Vec3::new(f(6), f(7), f(8)),
        roughness: f(9),
        specular: f(10),
        sun_shadow: f(11),
        motion: Vec2::new(f(12), f(13)),
        metallic: f(14),
    }
}

fn surfaces(n: usize) -> Vec<Surface> {
    let mut rng = Rng::new(0x5eed_1234_abcd_0001);
    let mut out: Vec<Surface> = (0..n)
        .map(|_| Surface {
            lighting: Vec3::new(
                rng.range(0.0, 3.0),
                rng.range(0.0, 1.0),
                rng.range(0.0, 12.0),
            ),
            albedo: Vec3::new(
                rng.range(0.0, 1.0),
                rng.range(0.0, 1.0),
                rng.range(0.0, 1.0),
            ),
            normal: unit(&mut rng),
            roughness: rng.range(0.0, 1.0),
            specular: rng.range(0.0, 1.0),
            metallic: rng.range(-0.1, 1.1),
            sun_shadow: rng.range(0.0, 1.0),
            motion: Vec2::new(rng.range(-40.0, 40.0), rng.range(-3000.0, 3000.0)),
        })
        .collect();
    // Edge cases: bad values are sanitised the same way on both sides.
    out.push(common::bad_surface());
    out.push(Surface {
        normal: Vec3::ZERO,
        ..Surface::default()
    });
    out.push(Surface {
        normal: -Vec3::Z,
        roughness: 0.0,
        ..Surface::default()
    });
    out
}

#[test]
fn gbuffer_pack_matches_the_cpu() {
    let s = surfaces(20_000);
    let input: Vec<u32> = s.iter().flat_map(surface_words).collect();
    let prelude = format!("#import deferred::gbuffer\n{SURFACE_WGSL_READ}");
    let body = "
    let s = read_surface(i);
    let k = deferred_gbuffer_kz2_pack(s);
    let o = deferred_gbuffer_oct_pack(s);
    let b = i * 10u;
    output[b] = pack4x8unorm(k.rt0); output[b + 1u] = pack4x8unorm(k.rt1);
    output[b + 2u] = pack4x8unorm(k.rt2); output[b + 3u] = pack4x8unorm(k.rt3);
    output[b + 4u] = deferred_pack_half(o.rt0.x) | (deferred_pack_half(o.rt0.y) << 16u);
    output[b + 9u] = deferred_pack_half(o.rt0.z) | (deferred_pack_half(o.rt0.w) << 16u);
    output[b + 5u] = o.rt1.x | (o.rt1.y << 8u) | (o.rt1.z << 16u) | (o.rt1.w << 24u);
    output[b + 6u] = deferred_pack_half(o.rt2.x) | (deferred_pack_half(o.rt2.y) << 16u);
    output[b + 7u] = deferred_pack_half(o.rt2.z) | (deferred_pack_half(o.rt2.w) << 16u);
    output[b + 8u] = pack4x8unorm(o.rt3);";
    let out = run(&prelude, body, &input, s.len() as u32, 10);
    let (mut srgb_off, mut spec_off, mut glow_off, mut normal_ties) = (0, 0, 0, 0);
    for (i, s) in s.iter().enumerate() {
        let g = &out[i * 10..(i + 1) * 10];
        let k = Kz2Texels::pack(s);
        let o = OctTexels::pack(s);
        let gb = |w: u32| w.to_le_bytes();
        // KZ2: exact, but the log-range specular code may sit one off at a rounding tie.
        assert_eq!(gb(g[1]), k.rt1, "{i} KZ2 RT1 {s:?}");
        assert_eq!(gb(g[3]), k.rt3, "{i} KZ2 RT3");
        let (gr2, cr2) = (gb(g[2]), k.rt2);
        assert_eq!(
            [gr2[0], gr2[1], gr2[3]],
            [cr2[0], cr2[1], cr2[3]],
            "{i} KZ2 RT2"
        );
        if gr2[2] != cr2[2] {
            assert!(
                gr2[2].abs_diff(cr2[2]) == 1,
                "{i} spec {} vs {}",
                gr2[2],
                cr2[2]
            );
            spec_off += 1;
        }
        let gw = gb(g[0]);
        assert_eq!(gw[..3], k.rt0[..3], "{i} KZ2 RT0");
        if gw[3] != k.rt0[3] {
            assert!(gw[3].abs_diff(k.rt0[3]) == 1);
            glow_off += 1;
        }
        // Octahedral RT0: f16 lighting, exact.
        assert_eq!(
            [g[4], g[9]],
            [
                u32::from(o.rt0[0]) | u32::from(o.rt0[1]) << 16,
                u32::from(o.rt0[2]) | u32::from(o.rt0[3]) << 16
            ],
            "{i} octahedral RT0"
        );
        // Octahedral: the normal code may differ only between two equally good codes.
        let g1 = gb(g[5]);
        assert_eq!(g1[3], o.rt1[3], "{i} roughness");
        let (gcode, ccode) = (g[5] & 0xff_ffff, u32::from_le_bytes(o.rt1) & 0xff_ffff);
        if gcode != ccode {
            let n = s.normal.normalize();
            assert!(
                oct_decode(gcode).angle_between(n).to_degrees() < 0.0397,
                "{i}"
            );
            normal_ties += 1;
        }
        assert_eq!(
            g[6],
            u32::from(o.rt2[0]) | u32::from(o.rt2[1]) << 16,
            "{i} motion"
        );
        assert_eq!(
            g[7],
            u32::from(o.rt2[2]) | u32::from(o.rt2[3]) << 16,
            "{i} specular"
        );
        let g3 = gb(g[8]);
        assert_eq!(g3[3], o.rt3[3]);
        for (&gpu, &cpu) in g3[..3].iter().zip(&o.rt3[..3]) {
            if gpu != cpu {
                assert!(gpu.abs_diff(cpu) == 1, "{i} sRGB {gpu} vs {cpu}");
                srgb_off += 1;
            }
        }
    }
    eprintln!(
        "{} surfaces: sRGB codes one off {srgb_off}, spec codes one off {spec_off}, glow one off {glow_off}, normal near-ties {normal_ties}",
        s.len()
    );
    let n = s.len();
    assert!(
        srgb_off * 200 < 3 * n && spec_off * 100 < n && glow_off * 100 < n && normal_ties * 100 < n
    );
}

#[test]
fn gbuffer_unpack_matches_the_cpu() {
    let mut rng = Rng::new(99);
    let n = 20_000u32;
    // Six words an item: the octahedral layout's 24 bytes (RT0 two words, RT1, RT2 two,
    // RT3); KZ2 reads words 0, 2, 3 and 5 as its four RGBA8 targets.
    let input: Vec<u32> = (0..n * 6).map(|_| rng.next_u32()).collect();
    let prelude = format!("#import deferred::gbuffer\n{SURFACE_WGSL_READ}");
    // Texture reads: unorm channels as textureLoad returns them, f16 channels as floats.
    let body = "
    let b = i * 6u;
    let k = deferred_gbuffer_kz2_unpack(unpack4x8unorm(input[b]), unpack4x8unorm(input[b + 2u]),
        unpack4x8unorm(input[b + 3u]), unpack4x8unorm(input[b + 5u]));
    let r1 = input[b + 2u];
    let rt1 = vec4<u32>(r1 & 0xffu, (r1 >> 8u) & 0xffu, (r1 >> 16u) & 0xffu, r1 >> 24u);
    let halves = vec4<f32>(deferred_unpack_half(input[b] & 0xffffu), deferred_unpack_half(input[b] >> 16u),
        deferred_unpack_half(input[b + 1u] & 0xffffu), deferred_unpack_half(input[b + 1u] >> 16u));
    let rt2 = vec4<f32>(deferred_unpack_half(input[b + 3u] & 0xffffu), deferred_unpack_half(input[b + 3u] >> 16u),
        deferred_unpack_half(input[b + 4u] & 0xffffu), deferred_unpack_half(input[b + 4u] >> 16u));
    let o = deferred_gbuffer_oct_unpack(halves, rt1, rt2, unpack4x8unorm(input[b + 5u]));
    write_surface(i * 30u, k);
    write_surface(i * 30u + 15u, o);";
    let out = run(&prelude, body, &input, n, 30);
    let close = |a: f32, b: f32, what: &str, i: usize| {
        assert!(
            (a - b).abs() <= 2e-6 * a.abs().max(b.abs()).max(1.0),
            "{i} {what}: gpu {a} cpu {b}"
        );
    };
    for i in 0..n as usize {
        let w = &input[i * 6..(i + 1) * 6];
        let bytes: Vec<u8> = w.iter().flat_map(|x| x.to_le_bytes()).collect();
        let kz2: Kz2Texels =
            bytemuck::pod_read_unaligned(&[&bytes[..4], &bytes[8..16], &bytes[20..24]].concat());
        let oct: OctTexels = bytemuck::pod_read_unaligned(&bytes);
        for (cpu, gpu) in [
            (kz2.unpack(), surface_from(&out[i * 30..])),
            (oct.unpack(), surface_from(&out[i * 30 + 15..])),
        ] {
            for (a, b, what) in [
                (gpu.lighting, cpu.lighting, "lighting"),
                (gpu.albedo, cpu.albedo, "albedo"),
                (gpu.normal, cpu.normal, "normal"),
            ] {
                for c in 0..3 {
                    close(a[c], b[c], what, i);
                }
            }
            close(gpu.roughness, cpu.roughness, "roughness", i);
            close(gpu.specular, cpu.specular, "specular", i);
            close(gpu.metallic, cpu.metallic, "metallic", i);
            close(gpu.sun_shadow, cpu.sun_shadow, "sun", i);
            assert_eq!(gpu.motion, cpu.motion, "{i} motion");
        }
    }
}

#[test]
fn position_from_depth_matches_the_cpu() {
    let vp = Vec2::new(1920.0, 1080.0);
    let mut rng = Rng::new(5);
    for mode in [DepthMode::Reversed, DepthMode::Standard] {
        let p = Perspective::try_new(1.1, vp.x / vp.y, 0.1, Some(500.0), mode).unwrap();
        let proj = p.gpu(vp);
        let n = 4096u32;
        let mut input: Vec<u32> = bytemuck::cast_slice(&[proj]).to_vec();
        let items: Vec<(Vec2, f32)> = (0..n)
            .map(|_| {
                (
                    Vec2::new(rng.range(0.0, vp.x), rng.range(0.0, vp.y)),
                    p.linearize().depth(rng.range(0.2, 400.0)),
                )
            })
            .collect();
        for (px, d) in &items {
            input.extend([px.x.to_bits(), px.y.to_bits(), d.to_bits()]);
        }
        let body = "
    let p = DeferredProjection(vec2<f32>(bitcast<f32>(input[0]), bitcast<f32>(input[1])),
        bitcast<f32>(input[2]), bitcast<f32>(input[3]),
        vec4<f32>(bitcast<f32>(input[4]), bitcast<f32>(input[5]), bitcast<f32>(input[6]), bitcast<f32>(input[7])));
    let b = 8u + i * 3u;
    let v = deferred_view_position(p, vec2<f32>(bitcast<f32>(input[b]), bitcast<f32>(input[b + 1u])), bitcast<f32>(input[b + 2u]));
    output[i * 3u] = bitcast<u32>(v.x); output[i * 3u + 1u] = bitcast<u32>(v.y); output[i * 3u + 2u] = bitcast<u32>(v.z);";
        let out = run("#import deferred::depth", body, &input, n, 3);
        for (i, (px, d)) in items.iter().enumerate() {
            let cpu = proj.view_position(*px, *d);
            let gpu = Vec3::new(
                f32::from_bits(out[i * 3]),
                f32::from_bits(out[i * 3 + 1]),
                f32::from_bits(out[i * 3 + 2]),
            );
            assert!(
                (gpu - cpu).length() <= 1e-5 * cpu.length(),
                "{mode:?} {i}: {gpu} vs {cpu}"
            );
        }
    }
}

#[test]
fn light_tile_test_matches_the_cpu() {
    let vp = Vec2::new(1280.0, 720.0);
    let p = Perspective::try_new(1.0, vp.x / vp.y, 0.1, None, DepthMode::Reversed).unwrap();
    let proj = p.gpu(vp);
    let (tx, ty) = tile_counts(vp.x as u32, vp.y as u32);
    let mut rng = Rng::new(21);
    let lights: Vec<DeferredLight> = (0..64)
        .map(|i| {
            let d = rng.range(1.0, 40.0);
            let pos = Vec3::new(rng.range(-1.0, 1.0) * d, rng.range(-0.6, 0.6) * d, -d);
            let range = rng.range(0.3, 6.0);
            if i % 2 == 0 {
                DeferredLight::spot(pos, unit(&mut rng), range, rng.range(0.1, 1.4), Vec3::ONE)
            } else {
                DeferredLight::point(pos, range, Vec3::ONE)
            }
        })
        .collect();
    let l = p.linearize();
    let tiles: Vec<(u32, u32, DeferredTileDepth)> = (0..tx * ty)
        .map(|t| {
            let a = rng.range(0.5, 40.0);
            let b = a + rng.range(0.0, 20.0);
            (
                t % tx,
                t / tx,
                DeferredTileDepth {
                    nearest: l.depth(a),
                    farthest: l.depth(b),
                },
            )
        })
        .collect();
    let mut input: Vec<u32> = bytemuck::cast_slice(&[proj]).to_vec();
    input.extend_from_slice(bytemuck::cast_slice(&lights));
    for (x, y, d) in &tiles {
        input.extend([*x, *y, d.nearest.to_bits(), d.farthest.to_bits()]);
    }
    let base = input.len() - tiles.len() * 4;
    let body = format!(
        "
    let p = DeferredProjection(vec2<f32>(bitcast<f32>(input[0]), bitcast<f32>(input[1])),
        bitcast<f32>(input[2]), bitcast<f32>(input[3]),
        vec4<f32>(bitcast<f32>(input[4]), bitcast<f32>(input[5]), bitcast<f32>(input[6]), bitcast<f32>(input[7])));
    let t = {base}u + i * 4u;
    let f = deferred_tile_frustum(p, vec2<u32>(input[t], input[t + 1u]),
        DeferredTileDepth(bitcast<f32>(input[t + 2u]), bitcast<f32>(input[t + 3u])));
    var mask = vec2<u32>(0u);
    for (var k = 0u; k < 64u; k++) {{
        let o = 8u + k * 12u;
        var l: DeferredLight;
        l.position = vec3<f32>(bitcast<f32>(input[o]), bitcast<f32>(input[o + 1u]), bitcast<f32>(input[o + 2u]));
        l.range = bitcast<f32>(input[o + 3u]);
        l.direction = vec3<f32>(bitcast<f32>(input[o + 4u]), bitcast<f32>(input[o + 5u]), bitcast<f32>(input[o + 6u]));
        l.cos_outer = bitcast<f32>(input[o + 7u]);
        l.flags = input[o + 11u];
        if deferred_light_in_tile(f, l) {{
            mask[k / 32u] |= 1u << (k % 32u);
        }}
    }}
    output[i * 2u] = mask.x;
    output[i * 2u + 1u] = mask.y;"
    );
    let out = run(
        "#import deferred::lights",
        &body,
        &input,
        tiles.len() as u32,
        2,
    );
    let (mut differ, mut pairs) = (0, 0);
    for (i, (x, y, d)) in tiles.iter().enumerate() {
        let f = TileFrustum::new(&proj, *x, *y, *d);
        for (k, light) in lights.iter().enumerate() {
            let cpu = f.light_visible(light);
            let gpu = out[i * 2 + k / 32] >> (k % 32) & 1 == 1;
            pairs += usize::from(cpu);
            differ += usize::from(cpu != gpu);
        }
    }
    eprintln!(
        "{} tiles x {} lights: {pairs} pairs, {differ} decisions differ",
        tiles.len(),
        lights.len()
    );
    assert!(pairs > 100);
    // Only tangent cases may flip with the device's rounding.
    assert!(differ * 10_000 <= tiles.len() * lights.len(), "{differ}");
}

/// Lights in front of a camera: points and spots, `range` metres at most.
fn random_lights(rng: &mut Rng, n: usize, max_range: f32) -> Vec<DeferredLight> {
    (0..n)
        .map(|i| {
            let d = rng.range(1.0, 40.0);
            let pos = Vec3::new(rng.range(-1.0, 1.0) * d, rng.range(-0.6, 0.6) * d, -d);
            let range = rng.range(0.3, max_range);
            if i % 3 == 0 {
                DeferredLight::spot(pos, unit(rng), range, rng.range(0.1, 1.4), Vec3::ONE)
            } else {
                DeferredLight::point(pos, range, Vec3::ONE)
            }
        })
        .collect()
}

/// The culling pass on testkit's device: `(counts, indices, stats)`.
fn run_cull_pass(
    params: &deferred::pass::LightCullParams,
    tiles: &[DeferredTileDepth],
    lights: &[DeferredLight],
) -> (Vec<u32>, Vec<u32>, deferred::lights::CullStats) {
    use deferred::pass::{LIGHT_CULL_PASS, LightCullCounters};
    use testkit::device::{Data, run_pass};
    let n = params.tile_count() as usize;
    let words = params.index_words() as usize;
    let light_rows = if lights.is_empty() {
        vec![DeferredLight::default()]
    } else {
        lights.to_vec()
    };
    let out = run_pass(
        &LIGHT_CULL_PASS,
        &[],
        &[],
        params,
        &[
            ("params", Data::rows(std::slice::from_ref(params))),
            ("tile_depths", Data::rows(tiles)),
            ("lights", Data::rows(&light_rows)),
            ("counts", Data::Words(&vec![u32::MAX; n])),
            ("indices", Data::Zeros(words)),
            ("counters", Data::rows(&[LightCullCounters::default()])),
        ],
    );
    let counters: LightCullCounters = out.read("counters", 1)[0];
    (
        out.read("counts", n),
        out.read("indices", words),
        counters.stats(),
    )
}

/// The culling pass against `cull_tiles` (its CPU twin): every tile's list, ascending, the
/// same except where a tangent light flips with the device's rounding (bounded as in
/// `light_tile_test_matches_the_cpu`), in both depth conventions, on a viewport whose
/// last tile row and column are partial, with empty tiles.
#[test]
fn light_culling_pass_equals_cull_tiles() {
    use deferred::lights::{MAX_LIGHTS_PER_TILE, cull_tiles};
    use deferred::pass::LightCullParams;
    for (mode, seed) in [(DepthMode::Reversed, 31), (DepthMode::Standard, 32)] {
        let vp = Vec2::new(333.0, 190.0);
        let far = match mode {
            DepthMode::Reversed => None,
            DepthMode::Standard => Some(500.0),
        };
        let p = Perspective::try_new(1.0, vp.x / vp.y, 0.1, far, mode).unwrap();
        let proj = p.gpu(vp);
        let (tx, ty) = tile_counts(vp.x as u32, vp.y as u32);
        let mut rng = Rng::new(seed);
        let lights = random_lights(&mut rng, 300, 6.0);
        let l = p.linearize();
        let tiles: Vec<DeferredTileDepth> = (0..tx * ty)
            .map(|_| {
                if rng.below(5) == 0 {
                    return DeferredTileDepth::empty(mode);
                }
                let a = rng.range(0.5, 40.0);
                let b = a + rng.range(0.0, 20.0);
                DeferredTileDepth {
                    nearest: l.depth(a),
                    farthest: l.depth(b),
                }
            })
            .collect();
        let params = LightCullParams::new(proj, lights.len() as u32);
        assert_eq!(params.tiles, [tx, ty]);
        let (gpu_counts, gpu_indices, gpu_stats) = run_cull_pass(&params, &tiles, &lights);
        let n = tiles.len();
        let m = MAX_LIGHTS_PER_TILE as usize;
        let mut counts = vec![0; n];
        let mut indices = vec![0; n * m];
        let stats = cull_tiles(&proj, &tiles, &lights, &mut counts, &mut indices).unwrap();
        let mut differ = 0;
        for t in 0..n {
            let cpu: Vec<u32> = indices[t * m..t * m + counts[t] as usize].to_vec();
            let gpu: Vec<u32> = gpu_indices[t * m..t * m + gpu_counts[t] as usize].to_vec();
            assert!(
                gpu.windows(2).all(|w| w[0] < w[1]),
                "tile {t}: not ascending"
            );
            let a: std::collections::BTreeSet<u32> = cpu.iter().copied().collect();
            let b: std::collections::BTreeSet<u32> = gpu.iter().copied().collect();
            differ += a.symmetric_difference(&b).count();
        }
        eprintln!(
            "{mode:?}: {n} tiles x {} lights, {} pairs, {differ} decisions differ",
            lights.len(),
            stats.pairs
        );
        assert!(stats.pairs > 1000, "{stats:?}");
        assert!(differ * 10_000 <= n * lights.len(), "{differ}");
        assert_eq!(gpu_stats.tiles_with_geometry, stats.tiles_with_geometry);
        assert_eq!(gpu_stats.overflowed_tiles, stats.overflowed_tiles);
        assert!(gpu_stats.pairs.abs_diff(stats.pairs) <= differ as u64);
    }
}

/// More lights on a tile than its list holds: the first MAX_LIGHTS_PER_TILE (ascending)
/// are kept and the tile counts as overflowed, as on the CPU; no light at all gives empty
/// lists.
#[test]
fn light_culling_pass_overflows_as_cull_tiles() {
    use deferred::lights::{MAX_LIGHTS_PER_TILE, cull_tiles};
    use deferred::pass::LightCullParams;
    let vp = Vec2::new(64.0, 48.0);
    let p = Perspective::try_new(1.0, vp.x / vp.y, 0.1, None, DepthMode::Reversed).unwrap();
    let proj = p.gpu(vp);
    let l = p.linearize();
    // 700 big lights around a wall 10 m away: every tile sees all of them.
    let lights: Vec<DeferredLight> = (0..700)
        .map(|i| {
            DeferredLight::point(
                Vec3::new(0.0, 0.0, -10.0 - i as f32 * 0.001),
                50.0,
                Vec3::ONE,
            )
        })
        .collect();
    let (tx, ty) = tile_counts(64, 48);
    let tiles = vec![
        DeferredTileDepth {
            nearest: l.depth(10.0),
            farthest: l.depth(10.0),
        };
        (tx * ty) as usize
    ];
    let params = LightCullParams::new(proj, lights.len() as u32);
    let (counts, indices, stats) = run_cull_pass(&params, &tiles, &lights);
    let m = MAX_LIGHTS_PER_TILE as usize;
    let mut cpu_counts = vec![0; tiles.len()];
    let mut cpu_indices = vec![0; tiles.len() * m];
    let cpu = cull_tiles(&proj, &tiles, &lights, &mut cpu_counts, &mut cpu_indices).unwrap();
    assert_eq!(cpu.overflowed_tiles, tx * ty);
    assert_eq!(stats, cpu);
    assert_eq!(counts, cpu_counts);
    assert_eq!(indices, cpu_indices);
    let expected: Vec<u32> = (0..MAX_LIGHTS_PER_TILE).collect();
    assert_eq!(&indices[..m], &expected[..]);
    // No lights: every tile with geometry gets an empty list.
    let (counts, _, stats) = run_cull_pass(&LightCullParams::new(proj, 0), &tiles, &[]);
    assert!(counts.iter().all(|&c| c == 0));
    assert_eq!(stats.pairs, 0);
    assert_eq!(stats.tiles_with_geometry, tx * ty);
}
