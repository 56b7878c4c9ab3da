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
use glam::{Mat4, Vec3};
use rayon::prelude::*;
use staticscene::demo::{City, CityConfig, aerial_camera, city, raster_boxes, street_camera};
use staticscene::{
    BuildConfig, Camera, DrawableSetupBatch, DrawableSetupInstance, HiZ, InstanceState,
    QueryOptions, QueryOutput, QueryParams, ResourceLibrary, STATE_FADING, Scene, TileStreamer,
    Transform4x3, ViewDesc, box_outside_frustum, snap_origin, sort_key,
};

const INSTANCES: usize = 1_500_000;
const VIEWPORT: [u32; 2] = [1920, 1080];

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

/// One instance, unpacked, in f32 world space: what the flat baseline loops over.
#[derive(Clone, Copy)]
struct Flat {
    object_to_world: Transform4x3,
    local_to_world: Transform4x3,
    setup_min: Vec3,
    setup_max: Vec3,
    parent: (Vec3, Vec3, f32, f32),
    child: (Vec3, Vec3, f32, f32),
    lod_scale: f32,
    filter: u8,
    handle: u64,
}

/// Unpacks the built tiles into flat records (world = floating space of origin 0).
fn flatten_scene(scene: &Scene) -> Vec<Flat> {
    let mut out = Vec::with_capacity(scene.instance_count());
    for t in scene.tiles() {
        for q in t.instances() {
            let f = q.try_unpack().unwrap();
            let o = &t.objects()[f.object as usize];
            let o2w = o.object_to_floating(glam::IVec3::ZERO);
            let s = &t.setups()[f.setup as usize];
            let pb = &t.bounds()[f.parent_bounds as usize];
            let cb = &t.bounds()[f.child_bounds as usize];
            out.push(Flat {
                object_to_world: o2w,
                local_to_world: o2w.mul(&t.transforms()[f.matrix as usize]),
                setup_min: s.min(),
                setup_max: s.max(),
                parent: (
                    pb.min(),
                    pb.max(),
                    f.parent_lod.min.metres(),
                    f.parent_lod.max.metres(),
                ),
                child: (
                    cb.min(),
                    cb.max(),
                    f.child_lod.min.metres(),
                    f.child_lod.max.metres(),
                ),
                lod_scale: o.lod_scale(),
                filter: f.filter,
                handle: s.handle,
            });
        }
    }
    out
}

fn dist2(p: Vec3, min: Vec3, max: Vec3) -> f32 {
    let d = (min - p).max(p - max).max(Vec3::ZERO);
    d.dot(d)
}

/// The flat baseline: every instance, every test, in order, one item per visible one.
#[allow(clippy::too_many_arguments)]
fn flat_query(
    items: &[Flat],
    fade: &mut [u8],
    p: &QueryParams,
    hiz: &HiZ,
    out: &mut Vec<DrawableSetupInstance>,
    batches: &mut Vec<DrawableSetupBatch>,
    base: u32,
) {
    // World = floating space of origin 0: shift the view by the origin.
    let origin = p.origin().as_vec3();
    let lod_point = p.lod_point() + origin;
    let m = p.clip_from_floating() * Mat4::from_translation(-origin);
    let hm = p.hiz_clip_from_floating() * Mat4::from_translation(-origin);
    let planes: [[f32; 4]; 6] = std::array::from_fn(|i| {
        let pl = p.planes[i];
        [
            pl[0],
            pl[1],
            pl[2],
            pl[3] - (pl[0] * origin.x + pl[1] * origin.y + pl[2] * origin.z),
        ]
    });
    let w_row = m.row(3);
    let n = p.fade_frames as u8;
    for (i, (it, fs)) in items.iter().zip(fade.iter_mut()).enumerate() {
        if u32::from(it.filter) & p.filter_mask == 0 {
            continue;
        }
        let s2 = (it.lod_scale * p.lod_point[3]).powi(2);
        let sel = |(lo, hi, a, b): (Vec3, Vec3, f32, f32)| {
            let (mn, mx) = it.object_to_world.transform_aabb(lo, hi);
            let d2 = dist2(lod_point, mn, mx);
            d2 >= a * a * s2 && d2 < b * b * s2
        };
        let lod = sel(it.parent) && sel(it.child);
        if !lod && *fs == 0 {
            continue;
        }
        let (mn, mx) = it.local_to_world.transform_aabb(it.setup_min, it.setup_max);
        let in_frustum = !box_outside_frustum(&planes, mn, mx);
        let c = (mn + mx) * 0.5;
        let r = (mx - mn).length() * 0.5;
        let w = w_row.truncate().dot(c) + w_row.w - r * w_row.truncate().length();
        let big = w <= 0.0 || 2.0 * r * p.viewport[3] >= p.viewport[2] * w;
        let occluded = in_frustum && big && hiz.occluded(&hm, mn, mx, p.hiz_scan_levels);
        *fs = if !in_frustum {
            if lod { n } else { 0 }
        } else if lod {
            (*fs + 1).min(n)
        } else {
            fs.saturating_sub(1)
        };
        if !(in_frustum && big && !occluded && *fs > 0) {
            continue;
        }
        let fade = f32::from(*fs) / f32::from(n);
        let flags = if *fs < n { STATE_FADING } else { 0 };
        batches.push(DrawableSetupBatch {
            sort_key: sort_key(it.handle, 0.0),
            setup: it.handle,
            sphere: [c.x, c.y, c.z, r],
            first_instance: out.len() as u32,
            flags,
            count: 1,
            stride: 64,
        });
        out.push(DrawableSetupInstance {
            state: InstanceState {
                fade,
                flags,
                tile: 0,
                instance: base + i as u32,
            },
            local_to_floating: it.local_to_world,
        });
    }
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

    let flat = flatten_scene(&scene);
    for (name, cam) in views(&cfg) {
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
        let hiz = HiZ::build(&depth, w, h, false).unwrap();
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
                fo.clear();
                fb.clear();
                flat_query(&flat, &mut fade, &params, &hiz, &mut fo, &mut fb, 0);
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
                        flat_query(items, f, &params, &hiz, &mut o, &mut bt, (k * 4096) as u32);
                        (o, bt)
                    })
                    .collect();
                black_box(parts.len())
            })
        });
        g.finish();
        fo.clear();
        fb.clear();
        flat_query(&flat, &mut fade, &params, &hiz, &mut fo, &mut fb, 0);
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
