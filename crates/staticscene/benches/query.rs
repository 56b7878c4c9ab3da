//! The static-scene query on a procedural city of 1.5M instances (the talk's upper
//! figure): tile building, and the per-view query with every test on (filter, LOD,
//! frustum, size, HiZ occlusion, LOD fade, batched output), sequential and on rayon's
//! threads, against two baselines in the same group: the query with the pre-cull off, and
//! a flat loop with no tiles, clusters or packing (one unpacked ~200-byte record per
//! instance in f32 world space, the same tests, one draw item per visible instance).
//!
//! `cargo bench -p staticscene --bench query --features parallel`

use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use rayon::prelude::*;
use staticscene::baseline::{Flat, flat_query, flatten_scene};
use staticscene::demo::{
    City, CityConfig, aerial_camera, box_hiz, city, raster_boxes, street_camera,
};
use staticscene::{
    BuildConfig, Camera, DrawableSetupBatch, DrawableSetupInstance, HiZ, QueryOptions, QueryOutput,
    QueryParams, ResourceLibrary, Scene, TileStreamer, ViewDesc, snap_origin,
};

const INSTANCES: usize = 1_500_000;
const VIEWPORT: [u32; 2] = [1920, 1080];

/// One sequential frame of the flat baseline over `flat` into `fo` and `fb` (cleared
/// first), the records in world space.
fn flat_frame(
    flat: &[Flat],
    fade: &mut [u8],
    params: &QueryParams,
    hiz: &HiZ,
    fo: &mut Vec<DrawableSetupInstance>,
    fb: &mut Vec<DrawableSetupBatch>,
) {
    fo.clear();
    fb.clear();
    flat_query(flat, fade, params, glam::IVec3::ZERO, Some(hiz), fo, fb, 0);
}

fn build_scene(c: &City) -> Scene {
    let mut streamer =
        TileStreamer::new(ResourceLibrary::new(&c.resources), BuildConfig::default());
    let mut scene = Scene::new();
    for g in &c.groups {
        scene.apply(streamer.add_group(g).unwrap());
    }
    scene
}

fn views(cfg: &CityConfig) -> Vec<(&'static str, Camera)> {
    vec![
        ("street", street_camera(cfg)),
        ("aerial", aerial_camera(cfg)),
    ]
}

fn bench(c: &mut Criterion) {
    let cfg = CityConfig::with_instances(INSTANCES);
    let city_data = city(&cfg);
    let mut scene = build_scene(&city_data);
    let n = scene.instance_count();
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!(
        "city: {n} instances, {} tiles, GPU bytes/instance {:.2} ({:.2} with fade states); load {}",
        scene.tiles().len(),
        scene.gpu_bytes(false) as f64 / n as f64,
        scene.gpu_bytes(true) as f64 / n as f64,
        load.trim()
    );

    let mut g = c.benchmark_group("build");
    g.sample_size(10).measurement_time(Duration::from_secs(10));
    g.throughput(Throughput::Elements(n as u64));
    g.bench_function("streamer_all_groups", |b| {
        b.iter(|| black_box(build_scene(&city_data)))
    });
    g.finish();

    let flat = flatten_scene(&scene, glam::IVec3::ZERO);
    for (name, cam) in views(&cfg) {
        let [w, h] = VIEWPORT;
        let hiz = box_hiz(&city_data.building_boxes, &cam, &cam, w, h, false).unwrap();
        let mut view = ViewDesc::camera(cam, VIEWPORT);
        view.occlusion_camera = Some(cam);
        let params = QueryParams::new(&view).unwrap();
        let on = QueryOptions::default();
        let off = QueryOptions {
            precull: false,
            ..QueryOptions::default()
        };
        let mut out = QueryOutput::<DrawableSetupInstance>::new();
        // Warm the fade states to their steady state, then report what a frame does.
        for _ in 0..10 {
            scene.query(&params, Some(&hiz), &on, &mut out).unwrap();
        }
        let s = out.stats;
        println!(
            "{name}: {} of {n} instances pass the pre-cull ({} of {} clusters); rejected: filter {}, LOD {}, frustum {}, size {}, occlusion {}; visible {} in {} batches: render items -{:.1}%",
            s.instances,
            s.clusters - s.clusters_culled,
            s.clusters,
            s.rejected_filter,
            s.rejected_lod,
            s.rejected_frustum,
            s.rejected_size,
            s.rejected_occlusion,
            s.visible,
            s.batches,
            100.0 * (1.0 - s.batches as f64 / s.visible.max(1) as f64)
        );

        let mut g = c.benchmark_group(format!("query_{name}"));
        g.sample_size(10)
            .measurement_time(Duration::from_secs(4))
            .warm_up_time(Duration::from_secs(1));
        g.throughput(Throughput::Elements(n as u64));
        g.bench_function(BenchmarkId::new("staticscene", "sequential"), |b| {
            b.iter(|| scene.query(&params, Some(&hiz), &on, &mut out).unwrap())
        });
        g.bench_function(BenchmarkId::new("staticscene", "parallel"), |b| {
            b.iter(|| scene.par_query(&params, Some(&hiz), &on, &mut out).unwrap())
        });
        g.bench_function(BenchmarkId::new("no_precull", "sequential"), |b| {
            b.iter(|| scene.query(&params, Some(&hiz), &off, &mut out).unwrap())
        });
        g.bench_function(BenchmarkId::new("no_precull", "parallel"), |b| {
            b.iter(|| {
                scene
                    .par_query(&params, Some(&hiz), &off, &mut out)
                    .unwrap()
            })
        });
        let mut fade = vec![0u8; flat.len()];
        let (mut fo, mut fb) = (Vec::new(), Vec::new());
        g.bench_function(BenchmarkId::new("flat_loop", "sequential"), |b| {
            b.iter(|| {
                flat_frame(&flat, &mut fade, &params, &hiz, &mut fo, &mut fb);
                black_box(fo.len())
            })
        });
        g.bench_function(BenchmarkId::new("flat_loop", "parallel"), |b| {
            b.iter(|| {
                let parts: Vec<(Vec<_>, Vec<_>)> = flat
                    .par_chunks(4096)
                    .zip(fade.par_chunks_mut(4096))
                    .enumerate()
                    .map(|(k, (items, f))| {
                        let (mut o, mut bt) = (Vec::new(), Vec::new());
                        flat_query(
                            items,
                            f,
                            &params,
                            glam::IVec3::ZERO,
                            Some(&hiz),
                            &mut o,
                            &mut bt,
                            (k * 4096) as u32,
                        );
                        (o, bt)
                    })
                    .collect();
                black_box(parts.len())
            })
        });
        g.finish();
        flat_frame(&flat, &mut fade, &params, &hiz, &mut fo, &mut fb);
        println!(
            "{name}: flat baseline draws {} items ({} bytes of records per instance)",
            fb.len(),
            size_of::<Flat>()
        );
    }

    let cam = views(&cfg)[0].1;
    let origin = snap_origin(cam.position);
    let [w, h] = VIEWPORT;
    let depth = raster_boxes(
        &city_data.building_boxes,
        origin,
        &cam.clip_from_floating(origin),
        w,
        h,
        false,
    );
    let mut g = c.benchmark_group("hiz_build");
    g.throughput(Throughput::Elements(u64::from(w * h)));
    g.bench_function("1920x1080", |b| {
        b.iter(|| black_box(HiZ::build(&depth, w, h, false).unwrap()))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
