//! CPU time per query on the 1.5M-instance city, the bench's views and settings (every
//! test on: fade, HiZ occlusion, size), sequential and parallel, pre-cull on and off.
//! Reports wall time and process CPU time per query, and CPU nanoseconds per instance:
//! the per-core cost, which other processes on a busy machine disturb far less than the
//! wall time. Linux only (reads /proc/self/stat).
//!
//! `cargo run -p staticscene --release --features parallel --example query_cpu`

use std::time::{Duration, Instant};

use clap::Parser;

use staticscene::baseline::{flat_query, flatten_scene};
use staticscene::demo::{CityConfig, aerial_camera, box_hiz, city, street_camera};
use staticscene::glam::IVec3;
use staticscene::{
    BuildConfig, DrawableSetupInstance, QueryOptions, QueryOutput, QueryParams, ResourceLibrary,
    Scene, TileStreamer, ViewDesc,
};

/// Process CPU time (user + system) from /proc/self/stat, in clock ticks of 10 ms.
fn cpu() -> Duration {
    let s = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let rest = s.rsplit(')').next().unwrap_or("");
    let f: Vec<u64> = rest
        .split_whitespace()
        .map(|x| x.parse().unwrap_or(0))
        .collect();
    // Fields after the command: state is [0], utime [11], stime [12].
    let ticks = f.get(11).copied().unwrap_or(0) + f.get(12).copied().unwrap_or(0);
    Duration::from_millis(ticks * 10)
}

/// CPU time per static-scene query on the 1.5M-instance demo city (Linux: reads
/// /proc/self/stat), sequential and parallel, pre-cull on and off.
#[derive(Parser)]
#[command(name = "query_cpu")]
struct Args {}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    Args::parse();
    let cfg = CityConfig::with_instances(1_500_000);
    let c = city(&cfg);
    let mut streamer =
        TileStreamer::new(ResourceLibrary::new(&c.resources), BuildConfig::default());
    let mut scene = Scene::new();
    let (w0, c0) = (Instant::now(), cpu());
    for g in &c.groups {
        scene.apply(streamer.add_group(g)?);
    }
    let n = scene.instance_count() as f64;
    println!(
        "build: {n} instances, wall {:.0} ms, CPU {:.0} ms ({:.0} ns/instance)",
        w0.elapsed().as_secs_f64() * 1e3,
        (cpu() - c0).as_secs_f64() * 1e3,
        (cpu() - c0).as_secs_f64() * 1e9 / n
    );
    println!("load: {}", std::fs::read_to_string("/proc/loadavg")?.trim());
    for (name, cam) in [
        ("street", street_camera(&cfg)),
        ("aerial", aerial_camera(&cfg)),
    ] {
        let (w, h) = (1920, 1080);
        let hiz = box_hiz(&c.building_boxes, &cam, &cam, w, h, false)?;
        let mut view = ViewDesc::camera(cam, [w, h]);
        view.occlusion_camera = Some(cam);
        let params = QueryParams::new(&view)?;
        let mut out = QueryOutput::<DrawableSetupInstance>::new();
        for precull in [true, false] {
            let options = QueryOptions {
                precull,
                ..QueryOptions::default()
            };
            for par in [false, true] {
                let run = |scene: &mut Scene, out: &mut QueryOutput<DrawableSetupInstance>| {
                    if par {
                        scene.par_query(&params, Some(&hiz), &options, out)
                    } else {
                        scene.query(&params, Some(&hiz), &options, out)
                    }
                };
                for _ in 0..5 {
                    run(&mut scene, &mut out)?;
                }
                let (w0, c0) = (Instant::now(), cpu());
                let mut k = 0u32;
                while w0.elapsed() < Duration::from_secs(3) {
                    run(&mut scene, &mut out)?;
                    k += 1;
                }
                let wall = w0.elapsed().as_secs_f64() / f64::from(k);
                let cpu_t = (cpu() - c0).as_secs_f64() / f64::from(k);
                println!(
                    "{name:6} precull {precull:5} {:10}: wall {:6.2} ms ({:5.1} ns/instance), CPU {:6.2} ms ({:5.1} ns/instance/core), {} visible, {} batches",
                    if par { "parallel" } else { "sequential" },
                    wall * 1e3,
                    wall * 1e9 / n,
                    cpu_t * 1e3,
                    cpu_t * 1e9 / n,
                    out.instances.len(),
                    out.batches.len()
                );
            }
        }
        // The flat baseline, sequential.
        let flat = flatten_scene(&scene, IVec3::ZERO);
        let mut fade = vec![0u8; flat.len()];
        let (mut fo, mut fb) = (Vec::new(), Vec::new());
        let (w0, c0) = (Instant::now(), cpu());
        let mut k = 0u32;
        while w0.elapsed() < Duration::from_secs(3) {
            fo.clear();
            fb.clear();
            flat_query(
                &flat,
                &mut fade,
                &params,
                IVec3::ZERO,
                Some(&hiz),
                &mut fo,
                &mut fb,
                0,
            );
            k += 1;
        }
        let wall = w0.elapsed().as_secs_f64() / f64::from(k);
        let cpu_t = (cpu() - c0).as_secs_f64() / f64::from(k);
        println!(
            "{name:6} flat loop (baseline) sequential: wall {:6.2} ms ({:5.1} ns/instance), CPU {:6.2} ms ({:5.1} ns/instance/core), {} visible, {} items",
            wall * 1e3,
            wall * 1e9 / n,
            cpu_t * 1e3,
            cpu_t * 1e9 / n,
            fo.len(),
            fb.len()
        );
    }
    Ok(())
}
