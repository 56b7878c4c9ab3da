//! Runs the street-view query of the demo city in a loop (for `perf`).
//!
//! `cargo run -p staticscene --release --features parallel --example profile_query -- [iterations] [precull 0/1] [par 0/1]`

use glam::{DQuat, DVec3, Mat4};
use staticscene::demo::{CityConfig, city};
use staticscene::{
    BuildConfig, Camera, DrawableSetupInstance, QueryOptions, QueryOutput, QueryParams,
    ResourceLibrary, Scene, TileStreamer, ViewDesc,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let iters: usize = args.next().map(|s| s.parse()).transpose()?.unwrap_or(50);
    let precull = args.next().map(|s| s != "0").unwrap_or(false);
    let par = args.next().map(|s| s != "0").unwrap_or(false);
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
