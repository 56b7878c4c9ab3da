//! Times 9-octave FBM per sample (water's texture FBM against fastnoise-lite and noise-rs)
//! as the minimum and median over several runs of 4096 samples (the minimum is robust to
//! other load on the machine). The criterion group `fbm_9_octaves` is the reference; this
//! is the quick check.
//!
//! `cargo run -p water --release --example fbm_timing -- 200` (`--help` for the limits).

use std::hint::black_box;
use std::time::Instant;

use clap::Parser;
use water::glam::Vec2;
use water::noise::{Fbm, FbmParams, NoiseTexture};

fn time(name: &str, runs: usize, samples: usize, mut f: impl FnMut() -> f32) -> f64 {
    let mut t: Vec<f64> = (0..runs)
        .map(|_| {
            let s = Instant::now();
            black_box(f());
            s.elapsed().as_secs_f64() * 1e9 / samples as f64
        })
        .collect();
    t.sort_by(f64::total_cmp);
    println!(
        "{name:40} min {:7.1} ns  median {:7.1} ns per sample",
        t[0],
        t[runs / 2]
    );
    t[0]
}

/// Times 9-octave FBM per sample: water's texture FBM against fastnoise-lite and noise-rs.
#[derive(Parser)]
#[command(name = "fbm_timing")]
struct Args {
    /// Runs of 4096 samples each (the minimum and median are reported).
    #[arg(default_value_t = 200, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    runs: u32,
}

fn main() {
    let runs = Args::parse().runs as usize;
    let pts: Vec<Vec2> = (0..4096)
        .map(|i| Vec2::new((i % 64) as f32 * 0.37 + 3.1, (i / 64) as f32 * 0.37 - 7.3))
        .collect();
    let n = pts.len();
    let tex = NoiseTexture::default_water();
    let f = Fbm::new(
        &tex,
        FbmParams {
            frequency: 1.0 / 16.0,
            ..FbmParams::default()
        },
    )
    .unwrap();
    let w = time("water texture FBM", runs, n, || {
        pts.iter().map(|&p| f.height(black_box(p))).sum()
    });
    time("water texture FBM + gradient", runs, n, || {
        pts.iter()
            .map(|&p| f.sample(black_box(p), 0.0).height)
            .sum()
    });
    let mut best_peer = f64::INFINITY;
    for (name, ty) in [
        (
            "fastnoise-lite OpenSimplex2 FBm",
            fastnoise_lite::NoiseType::OpenSimplex2,
        ),
        (
            "fastnoise-lite Perlin FBm",
            fastnoise_lite::NoiseType::Perlin,
        ),
    ] {
        let mut fl = fastnoise_lite::FastNoiseLite::new();
        fl.set_noise_type(Some(ty));
        fl.set_fractal_type(Some(fastnoise_lite::FractalType::FBm));
        fl.set_fractal_octaves(Some(9));
        fl.set_fractal_lacunarity(Some(2.0));
        fl.set_fractal_gain(Some(0.5));
        fl.set_frequency(Some(1.0 / 16.0));
        let t = time(name, runs, n, || {
            pts.iter()
                .map(|&p| {
                    let p = black_box(p);
                    fl.get_noise_2d(p.x, p.y)
                })
                .sum()
        });
        best_peer = best_peer.min(t);
    }
    {
        use noise::{MultiFractal, NoiseFn};
        let nf = noise::Fbm::<noise::Perlin>::new(0)
            .set_octaves(9)
            .set_lacunarity(2.0)
            .set_persistence(0.5)
            .set_frequency(1.0 / 16.0);
        let t = time("noise-rs Fbm<Perlin>", runs, n, || {
            pts.iter()
                .map(|&p| {
                    let p = black_box(p);
                    nf.get([f64::from(p.x), f64::from(p.y)]) as f32
                })
                .sum()
        });
        best_peer = best_peer.min(t);
    }
    println!("fastest peer / water = {:.2}x", best_peer / w);
}
