//! Times the signed distance transform against imageproc on a shoreline mask, reporting the
//! minimum and median of several runs (the minimum is robust to other load on the machine).
//!
//! `cargo run -p water --release --features parallel --example edt_timing -- 2048 7`
//! (`--help` for the options and limits).

use std::time::Instant;

use clap::{Parser, ValueEnum};

mod common;
use common::shore_mask;

fn time(name: &str, runs: usize, mut f: impl FnMut()) -> f64 {
    let mut t: Vec<f64> = (0..runs)
        .map(|_| {
            let s = Instant::now();
            f();
            s.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    t.sort_by(f64::total_cmp);
    println!(
        "{name:40} min {:8.2} ms  median {:8.2} ms",
        t[0],
        t[runs / 2]
    );
    t[0]
}

/// One of the timed implementations.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Only {
    /// `water::edt::signed_edt`, one thread.
    Water,
    /// `water::parallel::signed_edt` (needs the `parallel` feature).
    Parallel,
    /// imageproc's squared EDT (unsigned).
    Imageproc,
}

/// Times the signed distance transform against imageproc on a shoreline mask.
#[derive(Parser)]
#[command(name = "edt_timing")]
struct Args {
    /// Mask size in texels per side.
    #[arg(default_value_t = 2048, value_parser = clap::value_parser!(u32).range(16..=8192))]
    size: u32,
    /// Runs of each implementation (the minimum and median are reported).
    #[arg(default_value_t = 7, value_parser = clap::value_parser!(u32).range(1..=1000))]
    runs: u32,
    /// Run only this implementation (for `perf stat`).
    #[arg(value_enum)]
    only: Option<Only>,
}

fn main() {
    let args = Args::parse();
    if args.only == Some(Only::Parallel) && !cfg!(feature = "parallel") {
        use clap::CommandFactory;
        Args::command()
            .error(
                clap::error::ErrorKind::InvalidValue,
                "`parallel` needs the example built with `--features parallel`",
            )
            .exit();
    }
    let (n, runs, only) = (args.size, args.runs as usize, args.only);
    let on = |o: Only| only.is_none_or(|x| x == o);
    let mask = shore_mask(n);
    let solid = mask.iter().filter(|&&m| m != 0).count() as f64 / mask.len() as f64;
    println!("{n}x{n} mask, {:.0}% solid", solid * 100.0);
    let mut a = f64::NAN;
    if on(Only::Water) {
        a = time("water signed_edt (1 thread)", runs, || {
            std::hint::black_box(
                water::edt::signed_edt(&mask, n, n, &mut water::no_progress).unwrap(),
            );
        });
    }
    #[cfg(feature = "parallel")]
    if on(Only::Parallel) {
        time(
            &format!(
                "water parallel::signed_edt ({} threads)",
                rayon::current_num_threads()
            ),
            runs,
            || {
                std::hint::black_box(
                    water::parallel::signed_edt(&mask, n, n, &mut water::no_progress).unwrap(),
                );
            },
        );
    }
    let img = imageproc::image::GrayImage::from_raw(n, n, mask.clone()).unwrap();
    let mut b = f64::NAN;
    if on(Only::Imageproc) {
        b = time("imageproc squared EDT (unsigned)", runs, || {
            std::hint::black_box(
                imageproc::distance_transform::euclidean_squared_distance_transform(&img),
            );
        });
    }
    if a.is_finite() && b.is_finite() {
        println!("water / imageproc = {:.2}", a / b);
    }
}
