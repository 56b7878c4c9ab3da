//! Hot paths of the deferred crate, each with a baseline in the same group:
//!
//! - `gbuffer_pack` / `gbuffer_unpack`: one sample of each layout, against copying the
//!   unpacked `Surface` (the memory floor: a G-buffer write can't be cheaper than moving
//!   its inputs).
//! - `normal_encode`: octahedral nearest-code and precise encoders and KZ2's, against
//!   normalising the vector (what any encoder does first).
//! - `tile_culling`: the two culling passes on a 1920x1080 depth buffer, against the
//!   per-pixel brute force the tile lists stand in for (every light against every pixel).
//! - `cascades`: fitting four stable cascades.
//! - `msaa_edges`: the edge classifier over a 4x G-buffer, against copying the same bytes.
//!
//! `cargo bench -p deferred --bench deferred` (short runs: `-- --warm-up-time 1
//! --measurement-time 3`).

use std::hint::black_box;

use criterion::measurement::WallTime;
use criterion::{
    BenchmarkGroup, BenchmarkId, Criterion, Throughput, criterion_group, criterion_main,
};
use deferred::cascades::{CascadeCamera, CascadeParams, StableCascades};
use deferred::lights::{MAX_LIGHTS_PER_TILE, cull_tiles, tile_counts, tile_depth_ranges};
use deferred::msaa::{SampleCount, classify_edges};
use deferred::normal::{kz2_encode_view_normal, oct_encode_fast, oct_encode_precise};
use deferred::{
    DeferredLight, DeferredTileDepth, DepthMode, Kz2Texels, OctTexels, Perspective, Surface,
};
use glam::{DVec3, Vec2, Vec3};
use testkit::Rng;

/// A uniformly distributed unit vector.
fn unit(rng: &mut Rng) -> Vec3 {
    let z = rng.range(-1.0, 1.0);
    let phi = rng.range(0.0, std::f32::consts::TAU);
    let r = (1.0 - z * z).max(0.0).sqrt();
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

const N: usize = 4096;

fn surfaces() -> Vec<Surface> {
    let mut rng = Rng::new(0x1234_5678_9abc_def1);
    (0..N)
        .map(|_| {
            let mut n = unit(&mut rng);
            n.z = n.z.abs();
            Surface {
                lighting: Vec3::new(rng.f32(), rng.f32(), rng.f32()) * 1.5,
                albedo: Vec3::new(rng.f32(), rng.f32(), rng.f32()),
                normal: n,
                roughness: rng.f32(),
                specular: rng.f32(),
                metallic: rng.f32(),
                sun_shadow: rng.f32(),
                motion: Vec2::new(rng.range(-20.0, 20.0), rng.range(-20.0, 20.0)),
            }
        })
        .collect()
}

type Group<'a> = BenchmarkGroup<'a, WallTime>;

/// Times `out[i] = f(&input[i])` over the whole input as `name` (`out` made once, outside
/// the timing).
fn map<A, B: Clone + Default>(g: &mut Group, name: &str, input: &[A], f: impl Fn(&A) -> B) {
    g.bench_function(name, |b| {
        let mut out = vec![B::default(); input.len()];
        b.iter(|| {
            for (o, x) in out.iter_mut().zip(black_box(input)) {
                *o = f(x);
            }
            black_box(&out);
        })
    });
}

/// Times copying the surfaces as they are: the floor of any packing or unpacking.
fn copy_baseline(g: &mut Group, s: &[Surface]) {
    g.bench_function("baseline_copy_surface", |b| {
        let mut out = vec![Surface::default(); s.len()];
        b.iter(|| {
            out.copy_from_slice(black_box(s));
            black_box(&out);
        })
    });
}

fn gbuffer(c: &mut Criterion) {
    let s = surfaces();
    let mut g = c.benchmark_group("gbuffer_pack");
    g.throughput(Throughput::Elements(N as u64));
    copy_baseline(&mut g, &s);
    map(&mut g, "kz2", &s, Kz2Texels::pack);
    map(&mut g, "octahedral", &s, OctTexels::pack);
    g.finish();

    let kz2: Vec<_> = s.iter().map(Kz2Texels::pack).collect();
    let oct: Vec<_> = s.iter().map(OctTexels::pack).collect();
    let mut g = c.benchmark_group("gbuffer_unpack");
    g.throughput(Throughput::Elements(N as u64));
    copy_baseline(&mut g, &s);
    map(&mut g, "kz2", &kz2, Kz2Texels::unpack);
    map(&mut g, "octahedral", &oct, OctTexels::unpack);
    g.finish();

    let normals: Vec<Vec3> = s.iter().map(|s| s.normal * 1.3).collect();
    let mut g = c.benchmark_group("normal_encode");
    g.throughput(Throughput::Elements(N as u64));
    map(&mut g, "baseline_normalize", &normals, |n| n.normalize());
    for (name, f) in [
        ("oct_nearest", oct_encode_fast as fn(Vec3) -> u32),
        ("oct_precise", oct_encode_precise),
        ("kz2_view_xy_f16", kz2_encode_view_normal),
    ] {
        map(&mut g, name, &normals, |n| f(*n));
    }
    g.finish();
}

const W: u32 = 1920;
const H: u32 = 1080;

/// A 1080p depth buffer: a ground plane, slanted walls, and sky in the top fifth.
fn scene(p: &Perspective) -> Vec<f32> {
    let proj = p.gpu(Vec2::new(W as f32, H as f32));
    let mut depth = vec![p.mode.far_depth(); (W * H) as usize];
    for y in H / 5..H {
        for x in 0..W {
            // Ground at y = -1.7 m: distance from the ray; walls every 240 pixels.
            let ndc_y = 1.0 - (y as f32 + 0.5) / H as f32 * 2.0;
            let ground = if ndc_y < 0.0 {
                1.7 / (-ndc_y * proj.tan_half[1])
            } else {
                1e9
            };
            let band = (x / 240) as f32;
            let wall = 8.0 + band * 6.0 + (x % 240) as f32 * 0.02;
            depth[(y * W + x) as usize] = p.linearize().depth(ground.min(wall).min(150.0));
        }
    }
    depth
}

fn lights(n: usize) -> Vec<DeferredLight> {
    let mut rng = Rng::new(77);
    (0..n)
        .map(|i| {
            let d = rng.range(2.0, 60.0);
            let pos = Vec3::new(rng.range(-0.9, 0.9) * d, rng.range(-0.5, 0.4) * d, -d);
            let range = rng.range(0.5, 6.0);
            if i % 4 == 0 {
                DeferredLight::spot(pos, Vec3::new(0.0, -1.0, -0.3), range, 0.6, Vec3::ONE)
            } else {
                DeferredLight::point(pos, range, Vec3::ONE)
            }
        })
        .collect()
}

fn culling(c: &mut Criterion) {
    let p = Perspective::try_new(1.0, W as f32 / H as f32, 0.1, None, DepthMode::Reversed).unwrap();
    let proj = p.gpu(Vec2::new(W as f32, H as f32));
    let depth = scene(&p);
    let (tx, ty) = tile_counts(W, H);
    let n = (tx * ty) as usize;
    let mut tiles = vec![DeferredTileDepth::default(); n];
    let mut counts = vec![0u32; n];
    let mut indices = vec![0u32; n * MAX_LIGHTS_PER_TILE as usize];
    let mut g = c.benchmark_group("tile_culling");
    g.sample_size(10);
    g.bench_function("depth_ranges_1080p", |b| {
        b.iter(|| {
            tile_depth_ranges(black_box(&depth), W, H, DepthMode::Reversed, &mut tiles).unwrap()
        })
    });
    for count in [64usize, 256, 1024] {
        let l = lights(count);
        g.bench_with_input(BenchmarkId::new("cull_tiles_1080p", count), &l, |b, l| {
            b.iter(|| cull_tiles(&proj, black_box(&tiles), l, &mut counts, &mut indices).unwrap())
        });
    }
    // Baseline: every light against every pixel (the exact per-pixel answer).
    let positions: Vec<Vec3> = (0..W * H)
        .map(|i| {
            proj.view_position(
                Vec2::new((i % W) as f32 + 0.5, (i / W) as f32 + 0.5),
                depth[i as usize],
            )
        })
        .collect();
    let l = lights(64);
    g.bench_with_input(
        BenchmarkId::new("baseline_per_pixel_1080p", 64),
        &l,
        |b, l| {
            b.iter(|| {
                let mut pairs = 0u64;
                for p in black_box(&positions) {
                    for light in l {
                        pairs += u64::from(light.affects(*p));
                    }
                }
                pairs
            })
        },
    );
    g.finish();
}

fn cascades(c: &mut Criterion) {
    let cam = CascadeCamera {
        position: DVec3::new(1234.5, 20.0, -987.25),
        forward: DVec3::new(0.3, -0.1, -0.9).normalize(),
        fov_y: 1.0,
        aspect: 16.0 / 9.0,
    };
    let sun = DVec3::new(0.3, 0.8, -0.4).normalize();
    let params = CascadeParams::default();
    let mut g = c.benchmark_group("cascades");
    g.bench_function("fit_4", |b| {
        b.iter(|| StableCascades::fit(black_box(&cam), sun, &params).unwrap())
    });
    g.finish();
}

fn msaa(c: &mut Criterion) {
    // 1080p, 4x, the octahedral layout's 5 words per sample; 3% of pixels are edges.
    let pixels = (W * H) as usize;
    let wps = 5;
    let mut rng = Rng::new(5);
    let mut words = vec![0u32; pixels * 4 * wps];
    let mut depth = vec![0.5f32; pixels * 4];
    for p in 0..pixels {
        let edge = rng.f32() < 0.03;
        for s in 0..4 {
            for w in 0..wps {
                words[(p * 4 + s) * wps + w] = (p as u32).wrapping_mul(2654435761)
                    ^ w as u32
                    ^ if edge && s == 3 { 1 } else { 0 };
            }
            depth[p * 4 + s] = 0.5 + s as f32 * 1e-5;
        }
    }
    let mut edges = vec![0u32; pixels];
    let mut g = c.benchmark_group("msaa_edges");
    g.sample_size(10);
    g.throughput(Throughput::Elements(pixels as u64));
    g.bench_function("baseline_copy_1080p_4x", |b| {
        let mut copy = vec![0u32; words.len()];
        let mut dcopy = vec![0f32; depth.len()];
        b.iter(|| {
            copy.copy_from_slice(black_box(&words));
            dcopy.copy_from_slice(black_box(&depth));
            black_box((&copy, &dcopy));
        })
    });
    g.bench_function("classify_1080p_4x", |b| {
        b.iter(|| {
            classify_edges(
                black_box(&words),
                wps,
                &depth,
                SampleCount::X4,
                pixels,
                0.01,
                &mut edges,
            )
            .unwrap()
        })
    });
    g.finish();
}

criterion_group!(benches, gbuffer, culling, cascades, msaa);
criterion_main!(benches);
