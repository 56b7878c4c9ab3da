//! criterion benches for water, each group with its baselines:
//! - `fbm_9_octaves`: 9-octave 2D FBM per sample over a 64 x 64 grid of points: water's
//!   texture FBM (all octaves; and with the octave LOD at 100 m) against fastnoise-lite
//!   (OpenSimplex2 and Perlin FBm) and noise-rs (`Fbm<Perlin>`, lacunarity 2), all with
//!   frequency doubling and gain 0.5.
//! - `edt_2048`: the exact signed distance transform of a 2048^2 shoreline mask,
//!   single-threaded and on all rayon threads, against imageproc's (unsigned, one side)
//!   `euclidean_squared_distance_transform`.
//! - `flow_bake_4096`: the SDF-guided flow bake of a 4096^2 world map (2 m texels, four
//!   rivers, FBM lakes), single-threaded and with rayon smoothing; its distance field is
//!   made once outside the timing.
//! - `world_query`: the water query at 4096 points of a world of 40 lakes (200-point
//!   outlines) and 8 rivers, against a naive scan (every lake's full even-odd test, every
//!   river's densely sampled centre line).
//! - `tiles_1080p`: both classification passes over a 1920 x 1080 data-word buffer,
//!   against a per-pixel count.
//! - `normals_512`: normals from a 512 x 512 depth buffer with 5 and 9 taps, against
//!   central differences.

use std::hint::black_box;
#[cfg(feature = "parallel")]
use std::ops::ControlFlow;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::{Vec2, Vec3};
use water::noise::{Fbm, FbmParams, NoiseTexture};

const GRID: usize = 64;

fn points() -> Vec<Vec2> {
    (0..GRID * GRID)
        .map(|i| {
            Vec2::new(
                (i % GRID) as f32 * 0.37 + 3.1,
                (i / GRID) as f32 * 0.37 - 7.3,
            )
        })
        .collect()
}

fn fbm(c: &mut Criterion) {
    let pts = points();
    let mut g = c.benchmark_group("fbm_9_octaves");
    g.throughput(Throughput::Elements(pts.len() as u64));
    let tex = NoiseTexture::default_water();
    let params = FbmParams {
        frequency: 1.0 / 16.0,
        ..FbmParams::default()
    };
    let f = Fbm::new(&tex, params).unwrap();
    g.bench_function("water_texture_fbm", |b| {
        b.iter(|| {
            let mut s = 0.0;
            for &p in &pts {
                s += f.height(black_box(p));
            }
            s
        })
    });
    g.bench_function("water_texture_fbm_lod_100m", |b| {
        b.iter(|| {
            let mut s = 0.0;
            for &p in &pts {
                s += f.height_lod(black_box(p), 100.0);
            }
            s
        })
    });
    g.bench_function("water_texture_fbm_with_gradient", |b| {
        b.iter(|| {
            let mut s = 0.0;
            for &p in &pts {
                s += f.sample(black_box(p), 0.0).height;
            }
            s
        })
    });
    for (name, ty) in [
        (
            "fastnoise_lite_opensimplex2",
            fastnoise_lite::NoiseType::OpenSimplex2,
        ),
        ("fastnoise_lite_perlin", fastnoise_lite::NoiseType::Perlin),
    ] {
        let mut n = fastnoise_lite::FastNoiseLite::new();
        n.set_noise_type(Some(ty));
        n.set_fractal_type(Some(fastnoise_lite::FractalType::FBm));
        n.set_fractal_octaves(Some(9));
        n.set_fractal_lacunarity(Some(2.0));
        n.set_fractal_gain(Some(0.5));
        n.set_frequency(Some(1.0 / 16.0));
        g.bench_function(name, |b| {
            b.iter(|| {
                let mut s = 0.0;
                for &p in &pts {
                    let p = black_box(p);
                    s += n.get_noise_2d(p.x, p.y);
                }
                s
            })
        });
    }
    {
        use noise::{MultiFractal, NoiseFn};
        let n = noise::Fbm::<noise::Perlin>::new(0)
            .set_octaves(9)
            .set_lacunarity(2.0)
            .set_persistence(0.5)
            .set_frequency(1.0 / 16.0);
        g.bench_function("noise_rs_fbm_perlin", |b| {
            b.iter(|| {
                let mut s = 0.0;
                for &p in &pts {
                    let p = black_box(p);
                    s += n.get([f64::from(p.x), f64::from(p.y)]);
                }
                s
            })
        });
    }
    g.finish();
}

// The synthetic masks come from the examples' `common` module, through `bake_example`
// below (a file can be loaded as a module only once).
use bake_example::common::shore_mask;

fn edt(c: &mut Criterion) {
    let n = 2048u32;
    let mask = shore_mask(n);
    let mut g = c.benchmark_group("edt_2048");
    g.sample_size(10);
    g.throughput(Throughput::Elements(u64::from(n) * u64::from(n)));
    g.bench_function("water_signed_edt", |b| {
        b.iter(|| water::edt::signed_edt(black_box(&mask), n, n, &mut water::no_progress).unwrap())
    });
    #[cfg(feature = "parallel")]
    g.bench_function(
        criterion::BenchmarkId::new("water_signed_edt_parallel", rayon::current_num_threads()),
        |b| {
            b.iter(|| {
                water::parallel::signed_edt(black_box(&mask), n, n, &mut |_| {
                    ControlFlow::Continue(())
                })
                .unwrap()
            })
        },
    );
    let img = imageproc::image::GrayImage::from_raw(n, n, mask.clone()).unwrap();
    g.bench_function("imageproc_squared_edt_unsigned", |b| {
        b.iter(|| {
            imageproc::distance_transform::euclidean_squared_distance_transform(black_box(&img))
        })
    });
    g.finish();
}

#[path = "../examples/bake.rs"]
#[allow(dead_code)]
mod bake_example;

fn flow_bake(c: &mut Criterion) {
    use water::flowbake::{FlowBakeInput, FlowBakeSettings, bake_flow};
    let n = 4096u32;
    let rivers = bake_example::rivers(n);
    let mask = bake_example::landscape(n, &rivers);
    let sdf = water::edt::signed_edt(&mask, n, n, &mut water::no_progress).unwrap();
    let input = FlowBakeInput {
        sdf: &sdf,
        texel_size: 2.0,
        origin: Vec2::ZERO,
        rivers: &rivers,
        sources: &[],
    };
    let s = FlowBakeSettings::default();
    let mut g = c.benchmark_group("flow_bake_4096");
    g.sample_size(10);
    g.throughput(Throughput::Elements(u64::from(n) * u64::from(n)));
    g.bench_function("water_bake_flow", |b| {
        b.iter(|| bake_flow(black_box(&input), &s, &mut water::no_progress).unwrap())
    });
    #[cfg(feature = "parallel")]
    g.bench_function(
        criterion::BenchmarkId::new("water_bake_flow_parallel", rayon::current_num_threads()),
        |b| {
            b.iter(|| {
                water::parallel::bake_flow(black_box(&input), &s, &mut water::no_progress).unwrap()
            })
        },
    );
    g.finish();
}

/// The naive query: every lake's full even-odd test and the nearest point of every river's
/// densely sampled centre line; the highest surface wins.
struct Naive {
    lakes: Vec<(Vec<Vec2>, f32)>,
    rivers: Vec<Vec<(Vec2, f32, f32)>>,
}

impl Naive {
    fn query(&self, p: Vec2) -> Option<f32> {
        let mut best: Option<f32> = None;
        for (poly, h) in &self.lakes {
            let mut inside = false;
            for i in 0..poly.len() {
                let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
                if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y)
                {
                    inside = !inside;
                }
            }
            if inside && best.is_none_or(|b| *h > b) {
                best = Some(*h);
            }
        }
        for samples in &self.rivers {
            let mut nearest = (f32::INFINITY, 0.0, 0.0);
            for &(c, hw, z) in samples {
                let d = (c - p).length();
                if d < nearest.0 {
                    nearest = (d, hw, z);
                }
            }
            if nearest.0 <= nearest.1 && best.is_none_or(|b| nearest.2 > b) {
                best = Some(nearest.2);
            }
        }
        best
    }
}

fn world_query(c: &mut Criterion) {
    use water::world::{Lake, River, RiverPoint, WaterWorldBuilder};
    let mut b = WaterWorldBuilder::new();
    let mut naive = Naive {
        lakes: Vec::new(),
        rivers: Vec::new(),
    };
    let r = |k: u32, s: u32| water::hash::unit(water::hash::hash3(k, s, 77));
    for l in 0..40u32 {
        let centre = Vec2::new(r(l, 1), r(l, 2)) * 4000.0;
        let radius = 60.0 + 200.0 * r(l, 3);
        let polygon: Vec<Vec2> = (0..200)
            .map(|i| {
                let a = i as f32 / 200.0 * std::f32::consts::TAU;
                centre + Vec2::from_angle(a) * radius * (0.8 + 0.2 * (a * 5.0 + l as f32).sin())
            })
            .collect();
        naive.lakes.push((polygon.clone(), 10.0 + l as f32));
        b.lakes.push(Lake {
            polygon,
            height: 10.0 + l as f32,
            material: l,
        });
    }
    for k in 0..8u32 {
        let points: Vec<RiverPoint> = (0..10)
            .map(|i| RiverPoint {
                position: Vec3::new(
                    i as f32 * 400.0,
                    300.0 + 450.0 * k as f32 + 150.0 * r(i, k).sin(),
                    50.0 - i as f32,
                ),
                width: 20.0,
                depth: 2.0,
                speed: 2.0,
            })
            .collect();
        let dense: Vec<(Vec2, f32, f32)> = points
            .windows(2)
            .flat_map(|w| {
                (0..400).map(move |s| {
                    let t = s as f32 / 400.0;
                    (
                        w[0].position.truncate().lerp(w[1].position.truncate(), t),
                        10.0,
                        w[0].position.z,
                    )
                })
            })
            .collect();
        naive.rivers.push(dense);
        b.rivers.push(River {
            points,
            material: 100 + k,
        });
    }
    b.settings.texel_size = 2.0;
    let world = b.build(&mut water::no_progress).unwrap();
    let pts: Vec<Vec2> = (0..4096u32)
        .map(|i| Vec2::new(r(i, 11), r(i, 12)) * 4000.0)
        .collect();
    let mut g = c.benchmark_group("world_query");
    g.throughput(Throughput::Elements(pts.len() as u64));
    g.bench_function("water_world_query", |bch| {
        bch.iter(|| {
            pts.iter()
                .filter(|&&p| world.query(black_box(p)).is_some())
                .count()
        })
    });
    g.bench_function("naive_scan_baseline", |bch| {
        bch.iter(|| {
            pts.iter()
                .filter(|&&p| naive.query(black_box(p)).is_some())
                .count()
        })
    });
    g.finish();
}

fn tiles(c: &mut Criterion) {
    use water::tiles::{GridMesh, TileGrid, classify};
    let (w, h) = (1920u32, 1080u32);
    let grid = TileGrid::new(w, h, 32).unwrap();
    let mesh = GridMesh::new(16).unwrap();
    // Water in the lower 40% of the screen with ragged shores.
    let data: Vec<u32> = (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            let shore = 648 + (water::hash::hash2(x / 16, 5) % 64);
            if y > shore { 1 << 8 } else { 0 }
        })
        .collect();
    let mut g = c.benchmark_group("tiles_1080p");
    g.throughput(Throughput::Elements(u64::from(w * h)));
    g.bench_function("water_classify", |b| {
        b.iter(|| classify(&grid, black_box(&data), &mesh).unwrap())
    });
    g.bench_function("per_pixel_count_baseline", |b| {
        b.iter(|| {
            let mut counts = vec![0u32; grid.tile_count() as usize];
            for (i, &d) in black_box(&data).iter().enumerate() {
                if d & (1 << 8) != 0 {
                    let (x, y) = (i as u32 % w, i as u32 / w);
                    counts[(y / 32 * grid.tiles_x() + x / 32) as usize] += 1;
                }
            }
            counts
        })
    });
    g.finish();
}

fn normals(c: &mut Criterion) {
    use glam::UVec2;
    use water::normals::{DepthCamera, DepthView, Taps};
    let n = 512u32;
    let cam = DepthCamera {
        size: UVec2::splat(n),
        tan_half_fov: Vec2::splat(0.7),
    };
    let depth: Vec<f32> = (0..n * n)
        .map(|i| 4.0 + 0.01 * (i / n) as f32 + 0.2 * ((i % n) as f32 * 0.05).sin())
        .collect();
    let view = DepthView {
        depth: &depth,
        camera: cam,
    };
    let mut g = c.benchmark_group("normals_512");
    g.throughput(Throughput::Elements(u64::from(n * n)));
    for (name, taps) in [("water_5_taps", Taps::Five), ("water_9_taps", Taps::Nine)] {
        g.bench_function(name, |b| {
            b.iter(|| {
                let mut acc = 0.0;
                for y in 0..n {
                    for x in 0..n {
                        acc += view.normal(UVec2::new(x, y), 1, taps).map_or(0.0, |v| v.z);
                    }
                }
                acc
            })
        });
    }
    g.bench_function("central_differences_baseline", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for y in 0..n {
                for x in 0..n {
                    acc += view.normal_central(UVec2::new(x, y)).map_or(0.0, |v| v.z);
                }
            }
            acc
        })
    });
    g.finish();
}

criterion_group!(benches, fbm, edt, flow_bake, world_query, tiles, normals);
criterion_main!(benches);
