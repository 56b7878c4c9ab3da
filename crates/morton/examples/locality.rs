//! Morton or Hilbert? Prints the locality of both curves over random points (mean and
//! largest step between consecutive points, mean bounds of runs of consecutive points, as
//! a cluster builder would cut them) and the cost of computing each key.
//!
//! Run: `cargo run --release -p morton --example locality -- [POINTS] [BITS] [CHUNK]`
//! (defaults 1000000 points on a 2^10 grid per axis, runs of 256; `--help` for the limits).

use std::time::Instant;

use clap::Parser;
use morton::glam::UVec3;
use morton::locality::{Curve, curve_order3, measure3};

/// Locality and key cost of the Morton and Hilbert curves over random points.
#[derive(Parser)]
#[command(name = "locality")]
struct Args {
    /// Random points (about 40 bytes each).
    #[arg(default_value_t = 1_000_000, value_parser = clap::value_parser!(u32).range(2..=50_000_000))]
    points: u32,
    /// Bits per axis of the grid (a 2^BITS grid per axis; a 3D u64 code holds 21).
    #[arg(default_value_t = 10, value_parser = clap::value_parser!(u32).range(1..=21))]
    bits: u32,
    /// Points per run when measuring run bounds (a cluster's size).
    #[arg(default_value_t = 256, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    chunk: u32,
}

fn main() {
    let Args {
        points,
        bits,
        chunk,
    } = Args::parse();
    let (n, chunk) = (points as usize, chunk as usize);
    let mut rng = testkit::Rng::new(0x853c_49e6_748f_ea9b);
    let mut next = || rng.below(1 << bits) as u32;
    let cells: Vec<UVec3> = (0..n).map(|_| UVec3::new(next(), next(), next())).collect();
    let (xs, ys, zs): (Vec<u32>, Vec<u32>, Vec<u32>) = (
        cells.iter().map(|c| c.x).collect(),
        cells.iter().map(|c| c.y).collect(),
        cells.iter().map(|c| c.z).collect(),
    );
    let mut keys = vec![0u64; n];

    println!("{n} random points on a 2^{bits} grid per axis, runs of {chunk}");
    println!("curve    mean step  max step  mean run bounds (cells^2)  key ns (batch u64)");
    for curve in [Curve::Morton, Curve::Hilbert] {
        let t = Instant::now();
        for _ in 0..5 {
            match curve {
                Curve::Morton => morton::batch::encode3_u64_soa(&xs, &ys, &zs, &mut keys),
                Curve::Hilbert => morton::hilbert::encode3_u64_soa(&xs, &ys, &zs, &mut keys),
            }
            .expect("equal lengths");
        }
        let ns = t.elapsed().as_nanos() as f64 / (5 * n) as f64;
        let order = curve_order3(curve, &cells).expect("fewer than 2^32 points");
        let m = measure3(&cells, &order, chunk);
        println!(
            "{:8} {:9.1} {:9} {:26.0} {:18.2}",
            format!("{curve:?}"),
            m.mean_step,
            m.max_step,
            m.mean_chunk_bounds,
            ns
        );
    }
}
