//! Measures the angular error of every normal encoding over many random directions, and
//! the fraction of front-facing view-space normals KZ2's encoding flips (negative z).
//! The figures in BENCHMARKS.md's `deferred` section come from this program:
//!
//! `cargo run --release -p deferred --example normal_error -- [DIRECTIONS]` (`--help` for
//! the limits).

use clap::Parser;
use deferred::glam::{DVec3, Vec3};
use deferred::normal::{
    NormalWeighting, kz2_decode_view_normal, kz2_encode_view_normal, negative_z_fraction,
    oct_decode, oct_encode_fast, oct_encode_precise,
};
use testkit::Rng;

/// Uniform in `[0, 1)` with 53 bits (f64) from the test generator.
fn unit_f64(rng: &mut Rng) -> f64 {
    (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64
}

/// Uniform on the unit sphere (f64).
fn direction(rng: &mut Rng) -> DVec3 {
    let z = 2.0 * unit_f64(rng) - 1.0;
    let phi = std::f64::consts::TAU * unit_f64(rng);
    let r = (1.0 - z * z).max(0.0).sqrt();
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Angle in degrees between an f64 reference and a decoded f32 direction, in f64.
fn angle_deg(a: DVec3, b: Vec3) -> f64 {
    let b = b.as_dvec3().normalize();
    // atan2 of |cross| and dot: accurate for tiny angles.
    a.cross(b).length().atan2(a.dot(b)).to_degrees()
}

#[derive(Default)]
struct Stats {
    n: u64,
    sum: f64,
    max: f64,
}
impl Stats {
    fn add(&mut self, e: f64) {
        self.n += 1;
        self.sum += e;
        self.max = self.max.max(e);
    }
    fn row(&self, name: &str) {
        println!(
            "| {name} | {} | {:.4} | {:.4} |",
            self.n,
            self.sum / self.n as f64,
            self.max
        );
    }
}

/// Angular error of every normal encoding over uniformly random directions, and the
/// fraction of front-facing normals KZ2's view-space encoding flips.
#[derive(Parser)]
#[command(name = "normal_error")]
struct Args {
    /// Random directions to measure.
    #[arg(default_value_t = 10_000_000, value_parser = clap::value_parser!(u64).range(1..=10_000_000_000))]
    directions: u64,
}

fn main() {
    let count = Args::parse().directions;
    let mut rng = Rng::new(1);
    let (mut fast, mut precise, mut kz2) = (Stats::default(), Stats::default(), Stats::default());
    for _ in 0..count {
        let d = direction(&mut rng);
        let n = d.as_vec3();
        fast.add(angle_deg(d, oct_decode(oct_encode_fast(n))));
        precise.add(angle_deg(d, oct_decode(oct_encode_precise(n))));
        if d.z >= 0.0 {
            kz2.add(angle_deg(
                d,
                kz2_decode_view_normal(kz2_encode_view_normal(n)),
            ));
        }
    }
    println!("angular error over uniformly random directions, degrees\n");
    println!("| encoding | directions | mean | max |");
    println!("| --- | --- | --- | --- |");
    fast.row("octahedral 12+12, nearest code");
    precise.row("octahedral 12+12, precise");
    kz2.row("KZ2 view xy f16 (z >= 0 only; negative z is mirrored, error 2 asin|z|)");
    println!("\nKZ2: front-facing normals with negative view z (flipped by the decoder)\n");
    println!("| vertical fov | aspect | directions (uniform) | screen area (cosine-weighted) |");
    println!("| --- | --- | --- | --- |");
    for (fov, aspect) in [
        (60.0f32, 16.0 / 9.0f32),
        (75.0, 16.0 / 9.0),
        (90.0, 16.0 / 9.0),
        (110.0, 16.0 / 9.0),
        (60.0, 1.0),
        (90.0, 1.0),
    ] {
        let u = negative_z_fraction(
            fov.to_radians(),
            aspect,
            NormalWeighting::Uniform,
            4_000_000,
        );
        let c = negative_z_fraction(
            fov.to_radians(),
            aspect,
            NormalWeighting::ProjectedArea,
            4_000_000,
        );
        println!(
            "| {fov} deg | {aspect:.3} | {:.2}% | {:.2}% |",
            u * 100.0,
            c * 100.0
        );
    }
}
