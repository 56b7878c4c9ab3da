//! criterion benches for water, each group with its baselines:
//! - `fbm_9_octaves`: 9-octave 2D FBM per sample over a 64 x 64 grid of points: water's
//!   texture FBM (all octaves; and with the octave LOD at 100 m) against fastnoise-lite
//!   (OpenSimplex2 and Perlin FBm) and noise-rs (`Fbm<Perlin>`, lacunarity 2), all with
//!   frequency doubling and gain 0.5.
//! - `edt_2048`: the exact signed distance transform of a 2048^2 shoreline mask,
//!   single-threaded and on all rayon threads, against imageproc's (unsigned, one side)
//!   `euclidean_squared_distance_transform`.
//! - further groups are listed in BENCHMARKS.md.

use std::hint::black_box;
#[cfg(feature = "parallel")]
use std::ops::ControlFlow;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec2;
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

/// A 2048^2 shoreline-and-rocks mask: FBM thresholded (about 40% solid).
pub fn shore_mask(size: u32) -> Vec<u8> {
    let tex = NoiseTexture::generate(256, 16, 11).unwrap();
    let f = Fbm::new(
        &tex,
        FbmParams {
            frequency: 1.0 / 1024.0,
            amplitude: 1.0,
            gain: 0.5,
            octaves_near: 6,
            octaves_far: 1,
            lod_distance: 1.0,
        },
    )
    .unwrap();
    (0..size * size)
        .map(|i| {
            let p = Vec2::new((i % size) as f32, (i / size) as f32);
            u8::from(f.height(p) > 0.15)
        })
        .collect()
}

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

criterion_group!(benches, fbm, edt);
criterion_main!(benches);
