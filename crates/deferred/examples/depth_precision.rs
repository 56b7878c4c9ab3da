//! Position-from-depth error with a 32-bit float depth buffer, reversed vs standard Z, for
//! points at a range of distances (near plane 0.1 m): the relative error of the
//! reconstructed view-space position against the f64 point. Figures for BENCHMARKS.md:
//!
//! `cargo run --release -p deferred --example depth_precision` (no arguments)

use clap::Parser;
use deferred::glam::{DVec3, DVec4, Vec2};
use deferred::{DepthMode, Perspective};

/// Position-from-depth error with an f32 depth buffer, reversed vs standard Z, as a
/// markdown table.
#[derive(Parser)]
#[command(name = "depth_precision")]
struct Args {}

fn main() {
    Args::parse();
    let vp = Vec2::new(1920.0, 1080.0);
    println!("| depth buffer | distance 1 m | 10 m | 100 m | 1000 m | 10000 m |");
    println!("| --- | --- | --- | --- | --- | --- |");
    for (name, far, mode) in [
        (
            "standard Z, far 10 km",
            Some(10_000.0f32),
            DepthMode::Standard,
        ),
        ("reversed Z, far 10 km", Some(10_000.0), DepthMode::Reversed),
        ("reversed Z, infinite far", None, DepthMode::Reversed),
    ] {
        let p = Perspective::try_new(1.0, vp.x / vp.y, 0.1, far, mode).unwrap();
        let m = p.matrix_f64();
        let mut row = format!("| {name} |");
        for d in [1.0f64, 10.0, 100.0, 1000.0, 9999.0] {
            let mut worst = 0.0f64;
            for i in 0..2000 {
                // Points over the screen at distance ~d (within 1%).
                let t = i as f64 / 2000.0;
                let dist = d * (1.0 + 0.01 * (t * 7.0).fract());
                let (nx, ny) = (
                    (t * 13.0).fract() * 1.8 - 0.9,
                    (t * 29.0).fract() * 1.8 - 0.9,
                );
                let ty = (0.5f64).tan();
                let v = DVec3::new(
                    nx * ty * f64::from(vp.x / vp.y) * dist,
                    ny * ty * dist,
                    -dist,
                );
                let c = m * DVec4::new(v.x, v.y, v.z, 1.0);
                let ndc = c.truncate() / c.w;
                let px = Vec2::new(
                    ((ndc.x + 1.0) * 0.5 * f64::from(vp.x)) as f32,
                    ((1.0 - ndc.y) * 0.5 * f64::from(vp.y)) as f32,
                );
                let r = p.view_position(px, vp, ndc.z as f32).as_dvec3();
                worst = worst.max((r - v).length() / dist);
            }
            row += &format!(" {worst:.1e} |");
        }
        println!("{row}");
    }
}
