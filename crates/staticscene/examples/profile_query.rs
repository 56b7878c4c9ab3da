//! Runs the street-view query of the demo city in a loop (for `perf`).
//!
//! `cargo run -p staticscene --release --features parallel --example profile_query -- [ITERATIONS] [--precull] [--parallel]`

use clap::Parser;
use staticscene::demo::{CityConfig, city};
use staticscene::glam::{DQuat, DVec3, Mat4};
use staticscene::{
    BuildConfig, Camera, DrawableSetupInstance, QueryOptions, QueryOutput, QueryParams,
    ResourceLibrary, Scene, TileStreamer, ViewDesc,
};

/// Runs the street-view query of the 1.5M-instance demo city in a loop and prints the time
/// per query.
#[derive(Parser)]
#[command(name = "profile_query")]
struct Args {
    /// Queries to run.
    #[arg(default_value_t = 50, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    iterations: u32,
    /// Pre-cull tiles and clusters on the CPU first.
    #[arg(long)]
    precull: bool,
    /// Run the query on rayon's threads (needs the `parallel` feature).
    #[arg(long)]
    parallel: bool,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    if args.parallel && !cfg!(feature = "parallel") {
        use clap::CommandFactory;
        Args::command()
            .error(
                clap::error::ErrorKind::ArgumentConflict,
                "--parallel needs the example built with `--features parallel`",
            )
            .exit();
    }
    let (iters, precull, par) = (args.iterations as usize, args.precull, args.parallel);
    let cfg = CityConfig::with_instances(1_500_000);
    let c = city(&cfg);
    let mut streamer =
        TileStreamer::new(ResourceLibrary::new(&c.resources), BuildConfig::default());
    let mut scene = Scene::new();
    for g in &c.groups {
        scene.apply(streamer.add_group(g)?);
    }
    let size = cfg.lots[0] as f64 * f64::from(cfg.lot_size);
    let cam = Camera {
        position: DVec3::new(size * 0.5, 1.7, size * 0.5),
        rotation: DQuat::from_rotation_y(0.3),
        projection: Mat4::perspective_rh(1.2, 16.0 / 9.0, 0.1, 5000.0),
        reversed_depth: false,
    };
    let params = QueryParams::new(&ViewDesc::camera(cam, [1920, 1080]))?;
    let mut out = QueryOutput::<DrawableSetupInstance>::new();
    let options = QueryOptions {
        precull,
        ..QueryOptions::default()
    };
    let t = std::time::Instant::now();
    for _ in 0..iters {
        if par {
            #[cfg(feature = "parallel")]
            scene.par_query(&params, None, &options, &mut out)?;
        } else {
            scene.query(&params, None, &options, &mut out)?;
        }
    }
    let dt = t.elapsed() / iters as u32;
    println!(
        "{:?} per query, {:.1} ns/instance, {:?}",
        dt,
        dt.as_nanos() as f64 / scene.instance_count() as f64,
        out.stats
    );
    Ok(())
}
