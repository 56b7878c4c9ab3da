//! The offline water bake as a command-line tool with a progress bar: a synthetic
//! `size x size` landscape (FBM lakes and four river channels, 2 m per texel), its exact
//! signed distance field, the SDF-guided flow bake, and the flow atlas (8 m world map plus
//! 64 m sectors); prints the time of each step. Writes nothing.
//!
//! `cargo run -p water --release --features parallel --example bake -- 4096`
//! (add `--sequential` to run the single-threaded versions; `--help` for the limits).

use std::io::Write;
use std::ops::ControlFlow;
use std::time::Instant;

use clap::Parser;
use water::Progress;
use water::atlas::{FlowAtlas, FlowAtlasSettings};
use water::flowbake::{FlowBakeInput, FlowBakeSettings};
use water::glam::{Vec2, Vec3};
use water::world::{River, RiverPoint};

/// Public for `benches/water.rs`, which includes this file and reaches the masks through it.
pub mod common;

const TEXEL: f32 = 2.0;

/// A text progress bar on stderr, redrawn when the percentage changes.
fn bar() -> impl FnMut(Progress) -> ControlFlow<()> {
    let mut last = (None, u32::MAX);
    move |p: Progress| {
        let pct = (p.fraction() * 100.0) as u32;
        if last != (Some(p.stage), pct) {
            last = (Some(p.stage), pct);
            let filled = (pct / 4) as usize;
            eprint!(
                "\r{:>16} [{}{}] {pct:3}%",
                format!("{:?}", p.stage),
                "#".repeat(filled),
                " ".repeat(25 - filled)
            );
            if pct == 100 {
                eprintln!();
            }
            let _ = std::io::stderr().flush();
        }
        ControlFlow::Continue(())
    }
}

/// Four meandering rivers across the map (world metres).
pub fn rivers(size: u32) -> Vec<River> {
    let extent = size as f32 * TEXEL;
    (0..4)
        .map(|r| {
            let y0 = extent * (0.15 + 0.22 * r as f32);
            let points = (0..=12)
                .map(|k| {
                    let x = extent * k as f32 / 12.0;
                    let y = y0 + (k as f32 * 1.3 + r as f32).sin() * extent * 0.04;
                    RiverPoint {
                        position: Vec3::new(x, y, 100.0 - x * 0.01),
                        width: 24.0 + 8.0 * r as f32,
                        depth: 3.0,
                        speed: 2.0 + r as f32 * 0.5,
                    }
                })
                .collect();
            River {
                points,
                material: r,
            }
        })
        .collect()
}

/// Solid land (1) and water (0): FBM lakes plus the river channels.
pub fn landscape(size: u32, rivers: &[River]) -> Vec<u8> {
    let mut mask = common::fbm_mask(size, 7, 1.0 / 3000.0, -0.25, |p| (p + 0.5) * TEXEL);
    for r in rivers {
        for w in r.points.windows(2) {
            let (a, b) = (w[0].position.truncate(), w[1].position.truncate());
            let hw = w[0].width * 0.6;
            let lo = ((a.min(b) - hw) / TEXEL).max(Vec2::ZERO).as_uvec2();
            let hi = ((a.max(b) + hw) / TEXEL)
                .min(Vec2::splat(size as f32 - 1.0))
                .as_uvec2();
            for y in lo.y..=hi.y {
                for x in lo.x..=hi.x {
                    let p = (Vec2::new(x as f32, y as f32) + 0.5) * TEXEL;
                    let t = ((p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
                    if (a + (b - a) * t - p).length() <= hw {
                        mask[(y * size + x) as usize] = 0;
                    }
                }
            }
        }
    }
    mask
}

/// The offline water bake of a synthetic landscape (distance field, flow, flow atlas),
/// timed step by step. Writes nothing.
#[derive(Parser)]
#[command(name = "bake")]
struct Args {
    /// Map size in texels per side (2 m texels; about 40 bytes of memory per texel).
    #[arg(default_value_t = 2048, value_parser = clap::value_parser!(u32).range(64..=8192))]
    size: u32,
    /// Run the single-threaded versions (always, without the `parallel` feature).
    #[arg(long)]
    sequential: bool,
}

fn main() {
    if let Err(e) = run(Args::parse()) {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run(args: Args) -> Result<(), water::Error> {
    let size = args.size;
    let sequential = args.sequential || !cfg!(feature = "parallel");
    let rivers = rivers(size);
    let t = Instant::now();
    let mask = landscape(size, &rivers);
    let water = mask.iter().filter(|&&m| m == 0).count() as f64 / mask.len() as f64;
    eprintln!(
        "{size}x{size} texels of {TEXEL} m, {:.0}% water, made in {:.2?}",
        water * 100.0,
        t.elapsed()
    );

    let t = Instant::now();
    #[cfg(feature = "parallel")]
    let sdf = if sequential {
        water::edt::signed_edt(&mask, size, size, &mut bar())
    } else {
        water::parallel::signed_edt(&mask, size, size, &mut bar())
    };
    #[cfg(not(feature = "parallel"))]
    let sdf = water::edt::signed_edt(&mask, size, size, &mut bar());
    let sdf = sdf?;
    let edt_time = t.elapsed();

    let input = FlowBakeInput {
        sdf: &sdf,
        texel_size: TEXEL,
        origin: Vec2::ZERO,
        rivers: &rivers,
        sources: &[],
    };
    let settings = FlowBakeSettings::default();
    let t = Instant::now();
    #[cfg(feature = "parallel")]
    let field = if sequential {
        water::flowbake::bake_flow(&input, &settings, &mut bar())
    } else {
        water::parallel::bake_flow(&input, &settings, &mut bar())
    };
    #[cfg(not(feature = "parallel"))]
    let field = water::flowbake::bake_flow(&input, &settings, &mut bar());
    let field = field?;
    let flow_time = t.elapsed();

    let t = Instant::now();
    let s = FlowAtlasSettings {
        slots: 2048,
        width: 8192,
        tile_res: 32,
        ..Default::default()
    };
    // High-resolution tiles for the sectors in the middle of the map (around a player).
    let centre = (size as f32 * TEXEL / s.sector_size / 2.0) as u32;
    let atlas = FlowAtlas::build(
        &field,
        &s,
        |c| c.x.abs_diff(centre) <= 8 && c.y.abs_diff(centre) <= 8,
        &mut bar(),
    )?;
    let atlas_time = t.elapsed();
    let moving = field.flow().iter().filter(|v| v.length() > 0.0).count();
    eprintln!(
        "{}: distance transform {edt_time:.2?}, flow bake {flow_time:.2?} ({moving} texels flowing), atlas {}x{} with {} tiles {atlas_time:.2?}",
        if sequential {
            "1 thread"
        } else {
            "all threads"
        },
        atlas.width(),
        atlas.height(),
        atlas.resident_count()
    );
    Ok(())
}
