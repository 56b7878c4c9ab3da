//! The noise texture and FBM against independent references: slope statistics by finite
//! differences, gradients by central differences, the octave LOD's continuity and its
//! conservation of slope variance, and the tiling.

use glam::Vec2;
use water::noise::{Fbm, FbmParams, NoiseTexture};

fn fbm_params() -> FbmParams {
    FbmParams {
        frequency: 1.0 / 32.0,
        amplitude: 0.4,
        gain: 0.5,
        octaves_near: 9,
        octaves_far: 3,
        lod_distance: 10.0,
    }
}

/// Mean squared finite-difference slope (per axis) of `h` over a grid of `n^2` points
/// `step` apart, with difference step `e`.
fn numeric_slope_variance(h: impl Fn(Vec2) -> f64, n: usize, step: f32, e: f32) -> f64 {
    let mut sum = 0.0;
    for j in 0..n {
        for i in 0..n {
            let p = Vec2::new(i as f32 * step + 0.123, j as f32 * step + 0.456);
            let dx = (h(p + Vec2::new(e, 0.0)) - h(p - Vec2::new(e, 0.0))) / (2.0 * e as f64);
            let dy = (h(p + Vec2::new(0.0, e)) - h(p - Vec2::new(0.0, e))) / (2.0 * e as f64);
            sum += 0.5 * (dx * dx + dy * dy);
        }
    }
    sum / (n * n) as f64
}

#[test]
fn texture_slope_variance_matches_finite_differences() {
    let t = NoiseTexture::default_water();
    // One period of the texture sampled on a grid finer than a texel.
    let h = |p: Vec2| f64::from(t.sample(p));
    let numeric = numeric_slope_variance(h, 512, 1.0 / 512.0, 1e-4);
    let exact = f64::from(t.slope_variance());
    eprintln!("texture slope variance: exact {exact:.2}, finite differences {numeric:.2}");
    assert!((numeric / exact - 1.0).abs() < 0.02, "{numeric} vs {exact}");
}

#[test]
fn gradient_matches_central_differences() {
    let t = NoiseTexture::default_water();
    let f = Fbm::new(&t, fbm_params()).unwrap();
    let mut agree = 0;
    for k in 0..500 {
        // Positions below 16 m, where f32 resolves 1 um.
        let p = Vec2::new(
            (k as f32 * 1.37 + 0.2) % 16.0,
            (k as f32 * 0.73 + 5.0) % 16.0,
        );
        let s = f.sample(p, 0.0);
        assert_eq!(s.height, f.height(p));
        // The bilinear surface is linear along an axis inside each texel cell and kinks at
        // cell edges (the finest octave's cells are 32 m / 256 / 256 = 0.5 mm). Along each
        // axis the gradient must match the central difference, or, where a cell edge lies
        // within the step, the one-sided difference on p's side of it. The step actually
        // taken is what f32 positions near p can represent; f32 heights (ulp 3e-8 m) over
        // a 2e-5 m step leave about 2e-3 m/m of noise.
        let e = 2e-5;
        let h0 = f.height(p);
        let axis_ok = |dir: Vec2, g: f32| {
            let (a, b) = (p + dir * e, p - dir * e);
            let (ta, tb) = ((a - p).dot(dir), (p - b).dot(dir));
            let (ha, hb) = (f.height(a), f.height(b));
            let central = (ha - hb) / (ta + tb);
            let forward = (ha - h0) / ta;
            let backward = (h0 - hb) / tb;
            [central, forward, backward]
                .iter()
                .any(|d| (d - g).abs() < 5e-3)
        };
        if axis_ok(Vec2::X, s.gradient.x) && axis_ok(Vec2::Y, s.gradient.y) {
            agree += 1;
        }
    }
    assert!(agree >= 490, "{agree} of 500");
}

#[test]
fn octave_lod_is_continuous_and_follows_distance() {
    let t = NoiseTexture::default_water();
    let f = Fbm::new(&t, fbm_params()).unwrap();
    assert_eq!(f.octave_count(0.0), 9.0);
    assert_eq!(f.octave_count(10.0), 9.0);
    assert_eq!(f.octave_count(20.0), 8.0);
    assert_eq!(f.octave_count(80.0), 6.0);
    assert_eq!(f.octave_count(1e9), 3.0);
    assert_eq!(f.octave_count(f32::NAN), 9.0);
    // Nothing pops: walking away from 5 m to 2 km in small steps, the height changes by at
    // most the fade of one octave over one step.
    let p = Vec2::new(12.3, -4.5);
    let mut d = 5.0f32;
    let mut last = f.height_lod(p, d);
    while d < 2000.0 {
        let next = d * 1.002;
        let h = f.height_lod(p, next);
        // d(weight)/d(log2 d) = 1 for the fading octave (amplitude <= 0.4): over a step of
        // log2(1.002) = 0.0029 that is at most 0.4 * 0.0029 m.
        assert!(
            (h - last).abs() <= 0.4 * 0.003 + 1e-6,
            "jump at {d} m: {last} -> {h}"
        );
        last = h;
        d = next;
    }
}

#[test]
fn lod_conserves_slope_variance() {
    // Kept + dropped slope variance equals the full FBM's, measured numerically from the
    // analytic gradients (octaves are nearly uncorrelated, so variances add).
    let t = NoiseTexture::default_water();
    let f = Fbm::new(&t, fbm_params()).unwrap();
    let n = 300;
    let mean = |distance: f32| {
        let (mut kept, mut dropped) = (0.0f64, 0.0f64);
        for j in 0..n {
            for i in 0..n {
                let p = Vec2::new(i as f32 * 0.731, j as f32 * 0.917);
                let s = f.sample(p, distance);
                kept += 0.5 * f64::from(s.gradient.length_squared());
                dropped += f64::from(s.dropped_variance);
            }
        }
        (kept / (n * n) as f64, dropped / (n * n) as f64)
    };
    let (full, none) = mean(0.0);
    assert_eq!(none, 0.0);
    for d in [25.0, 60.0, 150.0, 400.0] {
        let (kept, dropped) = mean(d);
        eprintln!(
            "at {d} m: kept {kept:.4} + dropped {dropped:.4} = {:.4}, full {full:.4}",
            kept + dropped
        );
        assert!(dropped > 0.0);
        assert!(
            ((kept + dropped) / full - 1.0).abs() < 0.03,
            "{kept} + {dropped} vs {full}"
        );
    }
    // Each octave's variance a^2 f^2 S, and the sum, as the model says.
    let total: f32 = (0..9).map(|k| f.octave_slope_variance(k)).sum();
    assert!((total - f.total_slope_variance()).abs() < 1e-3 * total);
    assert!(
        ((full / f64::from(total)) - 1.0).abs() < 0.1,
        "{full} vs model {total}"
    );
}

#[test]
fn fbm_tiles_with_the_noise_period() {
    let t = NoiseTexture::default_water();
    let f = Fbm::new(&t, fbm_params()).unwrap();
    // Positions on a 1/64 m grid, so p + one period is exact in f32.
    for k in 0..200 {
        let p = Vec2::new(k as f32 * 23.0 / 64.0, 3.0 - k as f32 * 13.0 / 64.0);
        assert_eq!(f.height(p), f.height(p + Vec2::new(32.0, -64.0)), "at {p}");
    }
}

#[test]
fn bad_parameters_are_errors() {
    let t = NoiseTexture::default_water();
    for bad in [
        FbmParams {
            frequency: 0.0,
            ..fbm_params()
        },
        FbmParams {
            gain: 1.5,
            ..fbm_params()
        },
        FbmParams {
            octaves_near: 17,
            ..fbm_params()
        },
        FbmParams {
            octaves_far: 0,
            ..fbm_params()
        },
        FbmParams {
            octaves_far: 10,
            ..fbm_params()
        },
        FbmParams {
            amplitude: f32::NAN,
            ..fbm_params()
        },
        FbmParams {
            lod_distance: -1.0,
            ..fbm_params()
        },
    ] {
        let e = Fbm::new(&t, bad).unwrap_err();
        assert!(!e.to_string().is_empty());
    }
}
