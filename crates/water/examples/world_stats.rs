//! Bakes a random lake and prints the quadtree's size (a quick check of the bake).
//!
//! `cargo run -p water --release --example world_stats -- 5000` (`--help` for the limits).

use clap::Parser;
use water::glam::Vec2;
use water::world::{Lake, WaterWorldBuilder};

/// Bakes one random star-shaped lake and prints the quadtree's size and the bake time.
#[derive(Parser)]
#[command(name = "world_stats")]
struct Args {
    /// Points of the lake's outline. The random star is jagged at every point, so the
    /// quadtree grows faster than the point count: 10 000 points bake to 18M words in
    /// seconds, 20 000 exceed `MAX_WORLD_WORDS`.
    #[arg(default_value_t = 50, value_parser = clap::value_parser!(u32).range(3..=10_000))]
    points: u32,
}

fn main() {
    if let Err(e) = run(Args::parse().points as usize) {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run(n: usize) -> Result<(), water::Error> {
    let mut rng = testkit::Rng::new(1);
    let mut r = || f64::from(rng.f32());
    let mut b = WaterWorldBuilder::new();
    let polygon = (0..n)
        .map(|i| {
            let a = i as f64 / n as f64 * std::f64::consts::TAU;
            let rr = 120.0 * (0.5 + 0.5 * r());
            Vec2::new((a.cos() * rr) as f32, (a.sin() * rr) as f32)
        })
        .collect();
    b.lakes.push(Lake {
        polygon,
        height: 1.0,
        material: 0,
    });
    let t = std::time::Instant::now();
    let w = b.build(&mut water::no_progress)?;
    println!(
        "{n} points: {} nodes, depth {}, {} words, {:?}",
        w.node_count(),
        w.depth(),
        w.words().len(),
        t.elapsed()
    );
    Ok(())
}
