//! HZD's static query through the renderer's `StaticQuery` (testkit's device; lavapipe in
//! CI) against `staticscene`'s CPU twin, while tiles stream in and out: the pooled
//! buffers are allocated on activation, released on removal and reused; sun shadow views
//! (the pass's shadow variant) between camera frames.

use std::collections::BTreeMap;

use gpu::statics::{QueryReadback, StaticQuery};
use gpu::staticscene::demo::{CityConfig, city, raster_boxes, street_camera};
use gpu::staticscene::glam::{DQuat, DVec3, Mat4};
use gpu::staticscene::{
    BuildConfig, Camera, DrawableSetupInstance, FILTER_SUN_SHADOW, HiZ, QueryOptions, QueryOutput,
    QueryParams, ResourceLibrary, Scene, TileStreamer, ViewDesc, WaveWidth, canonical_batches,
    snap_origin,
};
use testkit::device::ctx;

/// Streaming groups come and go over the frames (and one group comes back, reusing freed
/// pool space); every frame the GPU query equals the CPU query on the same tiles: the
/// batches (setup, flags, instances), each instance's fade, and the per-test statistics.
#[test]
fn streamed_tiles_keep_the_gpu_query_equal_to_the_cpu_twin() {
    let c = ctx();
    let mut cfg = CityConfig::with_instances(30_000);
    // Small sectors: many streaming groups.
    cfg.sector_lots = 2;
    let world = city(&cfg);
    assert!(world.groups.len() >= 4, "{} groups", world.groups.len());
    let mut streamer = TileStreamer::new(
        ResourceLibrary::new(&world.resources),
        BuildConfig::default(),
    );
    let mut cpu_scene = Scene::new();
    let mut gpu_scene = Scene::new();
    let mut query = StaticQuery::new(&c.device, &c.queue).unwrap();
    let (w, h) = (256u32, 144u32);
    let mut cpu_out = QueryOutput::<DrawableSetupInstance>::new();
    let n = world.groups.len();
    // Frame f: groups [f/2, f/2 + n/2) are loaded (a sliding window), and the first one
    // again at the end.
    let mut loaded: std::collections::BTreeSet<u64> = std::collections::BTreeSet::new();
    let mut prev_cam = street_camera(&cfg);
    let mut max_tiles = 0;
    let mut shadow_views = 0;
    // The twin batches at the GPU query's width (its subgroup size, or 64).
    let twin_options = QueryOptions {
        wave_width: query.wave_width().expect("a fixed subgroup size"),
        ..QueryOptions::default()
    };
    for frame in 0..10usize {
        let lo = frame / 2;
        let want: Vec<usize> = (lo..(lo + n / 2).min(n))
            .chain(if frame >= 8 { vec![0] } else { vec![] })
            .collect();
        let mut updates = Vec::new();
        for id in loaded.iter().copied().collect::<Vec<_>>() {
            if !want.contains(&(id as usize)) {
                updates.push(streamer.remove_group(id).unwrap());
                loaded.remove(&id);
            }
        }
        for &g in &want {
            if loaded.insert(g as u64) {
                let mut group = world.groups[g].clone();
                group.id = g as u64;
                updates.push(streamer.add_group(&group).unwrap());
            }
        }
        for u in updates {
            for id in &u.remove {
                query.deactivate(*id);
            }
            for t in &u.add {
                query.activate(&c.device, &c.queue, t.tile()).unwrap();
            }
            cpu_scene.apply(u.clone());
            gpu_scene.apply(u);
        }
        assert_eq!(query.tile_count(), cpu_scene.tiles().len());
        max_tiles = max_tiles.max(query.tile_count());

        let mut cam = street_camera(&cfg);
        cam.rotation *= DQuat::from_rotation_y(0.3 * frame as f64);
        let mut view = ViewDesc::camera(cam, [w, h]);
        view.fade_frames = 3;
        view.lod_scale = 0.4;
        let origin = snap_origin(cam.position);
        let depth = raster_boxes(
            &world.building_boxes,
            origin,
            &prev_cam.clip_from_floating(origin),
            w,
            h,
            false,
        );
        let hiz = HiZ::build(&depth, w, h, false).unwrap();
        view.occlusion_camera = Some(prev_cam);
        prev_cam = cam;
        let params = QueryParams::new(&view).unwrap();
        cpu_scene
            .query(&params, Some(&hiz), &twin_options, &mut cpu_out)
            .unwrap();
        query.set_hiz(&c.device, &c.queue, Some(&hiz)).unwrap();
        let gpu = query
            .run(
                &c.device,
                &c.queue,
                &mut gpu_scene,
                &params,
                &QueryOptions::default(),
                QueryReadback::Full,
            )
            .unwrap();
        assert!(gpu.skipped_tiles.is_empty());
        assert_eq!(
            canonical_batches(&gpu.instances, &gpu.batches),
            canonical_batches(&cpu_out.instances, &cpu_out.batches),
            "frame {frame}"
        );
        let fades: BTreeMap<_, _> = cpu_out
            .instances
            .iter()
            .map(|d| ((d.state.tile, d.state.instance), d.state.fade))
            .collect();
        for d in &gpu.instances {
            assert_eq!(
                fades[&(d.state.tile, d.state.instance)],
                d.state.fade,
                "frame {frame}"
            );
        }
        let (mut g, mut p) = (gpu.stats, cpu_out.stats);
        for s in [&mut g, &mut p] {
            (s.tiles_culled, s.clusters_culled) = (0, 0);
        }
        assert_eq!(g, p, "frame {frame}: statistics");
        assert!(gpu.stats.visible > 0, "frame {frame}: nothing visible");

        // A sun shadow view between camera frames (the pass's shadow variant): equal to the
        // twin, and the next frame's camera query still equals it (no camera state moved).
        if frame % 3 == 1 {
            let ahead = cam.rotation * DVec3::NEG_Z;
            let target = cam.position + ahead * 50.0;
            let sun_dir = DVec3::new(-0.3, -0.85, 0.4).normalize();
            let ortho = Mat4::orthographic_rh(-100.0, 100.0, -100.0, 100.0, 1.0, 1200.0);
            let sun = Camera::look_at(target - sun_dir * 600.0, target, DVec3::Y, ortho, false);
            let shadow = ViewDesc::shadow(sun, [512, 512], FILTER_SUN_SHADOW, cam.position);
            let sp = QueryParams::new(&shadow).unwrap();
            cpu_scene
                .query(&sp, None, &twin_options, &mut cpu_out)
                .unwrap();
            let gpu = query
                .run(
                    &c.device,
                    &c.queue,
                    &mut gpu_scene,
                    &sp,
                    &QueryOptions::default(),
                    QueryReadback::Full,
                )
                .unwrap();
            assert_eq!(
                canonical_batches(&gpu.instances, &gpu.batches),
                canonical_batches(&cpu_out.instances, &cpu_out.batches),
                "frame {frame}: sun view"
            );
            assert!(gpu.stats.visible > 0, "frame {frame}: the sun sees nothing");
            shadow_views += 1;
        }
    }
    assert!(max_tiles >= 3);
    assert!(shadow_views >= 3);
}

/// The workgroup-wide batch output chosen on a device with subgroups
/// (`StaticQuery::with_subgroups(.., false)`): 64-lane batches, equal to the twin at W64.
#[test]
fn the_workgroup_batch_output_equals_the_twin_at_w64() {
    let c = ctx();
    let cfg = CityConfig::with_instances(20_000);
    let world = city(&cfg);
    let mut streamer = TileStreamer::new(
        ResourceLibrary::new(&world.resources),
        BuildConfig::default(),
    );
    let mut scene = Scene::new();
    let mut query = StaticQuery::with_subgroups(&c.device, &c.queue, false).unwrap();
    assert_eq!(query.wave_width(), Some(WaveWidth::W64));
    for g in &world.groups {
        let u = streamer.add_group(g).unwrap();
        for t in &u.add {
            query.activate(&c.device, &c.queue, t.tile()).unwrap();
        }
        scene.apply(u);
    }
    let params = QueryParams::new(&ViewDesc::camera(street_camera(&cfg), [256, 144])).unwrap();
    let mut twin = scene.clone();
    let mut cpu_out = QueryOutput::<DrawableSetupInstance>::new();
    twin.query(&params, None, &QueryOptions::default(), &mut cpu_out)
        .unwrap();
    let gpu = query
        .run(
            &c.device,
            &c.queue,
            &mut scene,
            &params,
            &QueryOptions::default(),
            QueryReadback::Full,
        )
        .unwrap();
    assert!(gpu.stats.visible > 100);
    assert_eq!(gpu.stats.batches, cpu_out.stats.batches);
    assert_eq!(
        canonical_batches(&gpu.instances, &gpu.batches),
        canonical_batches(&cpu_out.instances, &cpu_out.batches)
    );
}

/// What the query refuses or skips, as errors or reports, never a panic: a tile activated
/// twice (error naming the tile), a scene tile never activated on the GPU (skipped and
/// listed, the other tiles still queried), a HiZ larger than the query's viewport limit.
#[test]
fn bad_activations_and_sizes_are_errors_or_reports() {
    let c = ctx();
    let mut cfg = CityConfig::with_instances(20_000);
    cfg.sector_lots = 2;
    let world = city(&cfg);
    let mut streamer = TileStreamer::new(
        ResourceLibrary::new(&world.resources),
        BuildConfig::default(),
    );
    let mut scene = Scene::new();
    let mut query = StaticQuery::new(&c.device, &c.queue).unwrap();
    for g in &world.groups {
        scene.apply(streamer.add_group(g).unwrap());
    }
    assert!(scene.tiles().len() >= 2);
    let (first, rest) = scene.tiles().split_first().unwrap();
    for t in rest {
        query.activate(&c.device, &c.queue, t).unwrap();
    }
    let again = query.activate(&c.device, &c.queue, &rest[0]).unwrap_err();
    assert!(
        matches!(again, gpu::Error::Scene(gpu::SceneError::StaticTile { tile, .. }) if tile == rest[0].id().0),
        "{again}"
    );
    let skipped = first.id();
    let mut view = ViewDesc::camera(street_camera(&cfg), [256, 144]);
    view.size_threshold_px = 0.0;
    let params = QueryParams::new(&view).unwrap();
    let out = query
        .run(
            &c.device,
            &c.queue,
            &mut scene,
            &params,
            &QueryOptions {
                precull: false,
                ..QueryOptions::default()
            },
            QueryReadback::Full,
        )
        .unwrap();
    assert_eq!(out.skipped_tiles, vec![skipped]);
    assert!(out.stats.visible > 0);
    assert!(out.instances.iter().all(|d| d.state.tile != skipped.0));
    // A 20000-pixel-wide pyramid passes MAX_VIEWPORT.
    let wide = HiZ::build(&vec![0.5; 20_000], 20_000, 1, false).unwrap();
    let e = query.set_hiz(&c.device, &c.queue, Some(&wide)).unwrap_err();
    assert!(matches!(e, gpu::Error::StaticScene(_)), "{e}");
}
