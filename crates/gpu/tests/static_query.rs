//! HZD's static query through the renderer's `StaticQuery` (testkit's device; lavapipe in
//! CI) against `staticscene`'s CPU twin, while tiles stream in and out: the pooled
//! buffers are allocated on activation, released on removal and reused.

use std::collections::BTreeMap;

use gpu::staticscene::demo::{CityConfig, city, raster_boxes, street_camera};
use gpu::staticscene::glam::DQuat;
use gpu::staticscene::{
    BuildConfig, DrawableSetupBatch, DrawableSetupInstance, HiZ, QueryOptions, QueryOutput,
    QueryParams, ResourceLibrary, Scene, TileStreamer, ViewDesc, snap_origin,
};
use gpu::{QueryReadback, StaticQuery};
use testkit::device::ctx;

/// (setup, flags, the instances' (tile, index) keys) per batch, sorted.
type Canonical = Vec<(u64, u32, Vec<(u32, u32)>)>;

fn canonical(instances: &[DrawableSetupInstance], batches: &[DrawableSetupBatch]) -> Canonical {
    let mut v: Canonical = batches
        .iter()
        .map(|b| {
            let keys = (b.first_instance..b.first_instance + b.count)
                .map(|i| {
                    let s = instances[i as usize].state;
                    (s.tile, s.instance)
                })
                .collect();
            (b.setup, b.flags, keys)
        })
        .collect();
    v.sort_by(|a, b| a.2.cmp(&b.2));
    v
}

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
            .query(&params, Some(&hiz), &QueryOptions::default(), &mut cpu_out)
            .unwrap();
        query.set_hiz(&c.device, &c.queue, Some(&hiz));
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
            canonical(&gpu.instances, &gpu.batches),
            canonical(&cpu_out.instances, &cpu_out.batches),
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
    }
    assert!(max_tiles >= 3);
}
