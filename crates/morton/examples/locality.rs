//! Morton or Hilbert? Prints the locality of both curves over random points (mean and
//! largest step between consecutive points, mean bounds of runs of consecutive points, as
//! a cluster builder would cut them) and the cost of computing each key.
//!
//! Run: `cargo run --release -p morton --example locality [points] [bits] [chunk]`
//! (defaults 1000000 points on a 2^10 grid per axis, runs of 256).

use std::time::Instant;

use glam::UVec3;
use morton::locality::{Curve, curve_order3, measure3};

fn main() {
    let mut args = std::env::args()
        .skip(1)
        .map(|a| a.parse::<usize>().expect("a number"));
    let n = args.next().unwrap_or(1_000_000);
    let bits = args.next().unwrap_or(10).clamp(1, 21) as u32;
    let chunk = args.next().unwrap_or(256);
    let mut s = 0x853c_49e6_748f_ea9bu64;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 40) as u32 & ((1 << bits) - 1)
    };
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
