//! Builds the demo city and prints its tiles, bytes per instance and build time, and
//! compares the two cluster partitions (Morton buckets vs axis-aligned splits).
//!
//! `cargo run -p staticscene --release --example city -- [INSTANCES]` (default 1 500 000;
//! `--help` for the limits).

use std::time::Instant;

use clap::Parser;
use staticscene::demo::{CityConfig, city};
use staticscene::glam::{DQuat, DVec3, Mat4};
use staticscene::{
    BuildConfig, Camera, DrawableSetupInstance, Partition, QueryOptions, QueryOutput, QueryParams,
    ResourceLibrary, Scene, TileStreamer, ViewDesc,
};

fn street(size: f64, a: f64) -> ViewDesc {
    let pos = DVec3::new(size * 0.5, 1.7, size * 0.5);
    let cam = Camera {
        position: pos,
        rotation: DQuat::from_rotation_y(a),
        projection: Mat4::perspective_rh(1.2, 16.0 / 9.0, 0.1, 5000.0),
        reversed_depth: false,
    };
    let mut v = ViewDesc::camera(cam, [1920, 1080]);
    v.fade_frames = 0;
    v
}

/// Builds the demo city, prints its bytes per instance and build time, and compares the
/// two cluster partitions.
#[derive(Parser)]
#[command(name = "city")]
struct Args {
    /// About how many static instances the city has (the lot count is chosen for it; about
    /// 100 bytes of memory each while building).
    #[arg(default_value_t = 1_500_000, value_parser = clap::value_parser!(u32).range(1..=20_000_000))]
    instances: u32,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let cfg = CityConfig::with_instances(args.instances as usize);
    let t = Instant::now();
    let c = city(&cfg);
    println!(
        "city: {} lots, {} groups, {} objects, generated in {:.2?}",
        cfg.lots[0] * cfg.lots[1],
        c.groups.len(),
        c.object_count(),
        t.elapsed()
    );
    let lib = ResourceLibrary::new(&c.resources);
    for partition in [Partition::MortonBuckets, Partition::AxisSplit] {
        let config = BuildConfig {
            partition,
            ..BuildConfig::default()
        };
        let mut streamer = TileStreamer::new(lib.clone(), config);
        let mut scene = Scene::new();
        let mut dynamic = 0;
        let t = Instant::now();
        for g in &c.groups {
            let u = streamer.add_group(g)?;
            dynamic += u.dynamic.len();
            scene.apply(u);
        }
        let build = t.elapsed();
        let n = scene.instance_count();
        let (mut inst, mut obj, mut setup, mut mat, mut bnd, mut clusters, mut cpu) =
            (0, 0, 0, 0, 0, 0, 0);
        let mut volume = 0.0f64;
        let mut area = 0.0f64;
        for tile in scene.tiles() {
            inst += tile.instances().len() * 16;
            obj += tile.objects().len() * 64;
            setup += tile.setups().len() * 32;
            mat += tile.transforms().len() * 48;
            bnd += tile.bounds().len() * 12;
            clusters += tile.clusters().len();
            cpu += tile.cpu_bytes();
            for cl in tile.clusters() {
                let e = (cl.cull.bounds.max - cl.cull.bounds.min).as_dvec3();
                volume += e.x * e.y * e.z;
                area += 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x);
            }
        }
        let per = |b: usize| b as f64 / n as f64;
        println!(
            "\n{partition:?}: {n} instances in {} tiles ({} orphan), {clusters} clusters, {dynamic} dynamic objects, built in {build:.2?} ({:.0} ns/instance)",
            scene.tiles().len(),
            streamer.orphan_tiles().len(),
            build.as_nanos() as f64 / n as f64
        );
        println!(
            "  GPU bytes/instance: {:.2} (instances {:.2}, objects {:.2}, setups {:.2}, matrices {:.2}, bounds {:.2}); with fade states {:.2}; CPU clusters+tiles {:.3}",
            per(inst + obj + setup + mat + bnd),
            per(inst),
            per(obj),
            per(setup),
            per(mat),
            per(bnd),
            per(scene.gpu_bytes(true)),
            per(cpu)
        );
        println!(
            "  cluster bounds: total volume {:.3e} m^3, total surface {:.3e} m^2",
            volume, area
        );
        // Pre-cull efficiency over street-level views around the city.
        let size = cfg.lots[0] as f64 * f64::from(cfg.lot_size);
        let mut passed = 0u64;
        let mut visible = 0u64;
        let mut out = QueryOutput::<DrawableSetupInstance>::new();
        for k in 0..16 {
            let a = k as f64 * std::f64::consts::TAU / 16.0;
            let pos = DVec3::new(
                size * (0.5 + 0.3 * a.cos()),
                1.7,
                size * (0.5 + 0.3 * a.sin()),
            );
            let cam = Camera {
                position: pos,
                rotation: DQuat::from_rotation_y(a * 1.7),
                projection: Mat4::perspective_rh(1.2, 16.0 / 9.0, 0.1, 5000.0),
                reversed_depth: false,
            };
            let mut view = ViewDesc::camera(cam, [1920, 1080]);
            view.fade_frames = 0;
            let params = QueryParams::new(&view)?;
            scene.query(&params, None, &QueryOptions::default(), &mut out)?;
            passed += out.stats.instances;
            visible += out.stats.visible;
        }
        let t = Instant::now();
        for _ in 0..4 {
            scene.query(
                &QueryParams::new(&street(size, 0.3))?,
                None,
                &QueryOptions::default(),
                &mut out,
            )?;
        }
        let q = t.elapsed() / 4;
        let t = Instant::now();
        for _ in 0..4 {
            scene.query(
                &QueryParams::new(&street(size, 0.3))?,
                None,
                &QueryOptions {
                    precull: false,
                    ..QueryOptions::default()
                },
                &mut out,
            )?;
        }
        let q2 = t.elapsed() / 4;
        println!(
            "  one street view: query {q:.2?} ({:.1} ns/instance), pre-cull off {q2:.2?} ({:.1} ns/instance)",
            q.as_nanos() as f64 / n as f64,
            q2.as_nanos() as f64 / n as f64
        );
        println!(
            "  16 street views: {:.0} instances/view pass the pre-cull ({:.2}% of the scene), {:.0} visible",
            passed as f64 / 16.0,
            100.0 * passed as f64 / 16.0 / n as f64,
            visible as f64 / 16.0
        );
    }
    Ok(())
}
