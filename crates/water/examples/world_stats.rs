//! Bakes random lakes and prints the quadtree's size (a quick check of the bake).
use glam::Vec2;
use water::world::{Lake, WaterWorldBuilder};

fn main() {
    let n: usize = std::env::args().nth(1).map_or(50, |a| a.parse().unwrap());
    let mut s = 1u64;
    let mut r = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
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
    let w = b.build(&mut water::no_progress).unwrap();
    println!(
        "{n} points: {} nodes, depth {}, {} words, {:?}",
        w.node_count(),
        w.depth(),
        w.words().len(),
        t.elapsed()
    );
}
