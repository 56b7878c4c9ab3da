//! The pass run by hand through `query_cluster`: a cluster dispatched whole gives the same
//! instances as its threads dispatched one by one (every thread is independent, and the
//! CPU twin's per-job memo of object transforms and parent LOD results changes nothing),
//! and short outputs drop what does not fit while the counters keep counting.

mod common;

use std::cell::Cell;

use common::*;
use glam::{DQuat, DVec3, Mat4};
use staticscene::{
    Camera, ClusterJob, DrawableSetupBatch, DrawableSetupInstance, QueryParams, QueryStats,
    ViewDesc, WaveWidth, query_cluster,
};

#[test]
fn whole_cluster_equals_threads_one_by_one() {
    let (scene, cfg) = city_scene(40_000, 21);
    let size = f64::from(cfg.lots[0]) * f64::from(cfg.lot_size);
    let cam = Camera {
        position: DVec3::new(size * 0.3, 40.0, size * 0.3),
        rotation: DQuat::from_euler(glam::EulerRot::YXZ, -2.3, -0.3, 0.0),
        projection: Mat4::perspective_rh(1.2, 16.0 / 9.0, 0.1, 5000.0),
        reversed_depth: false,
    };
    let mut view = ViewDesc::camera(cam, [640, 360]);
    view.lod_scale = 1.7;
    let params = QueryParams::new(&view).unwrap();
    let mut total = 0;
    for tile in scene.tiles() {
        let buffers = tile.buffers();
        for c in tile.clusters() {
            let n = c.count as usize;
            let mut fade_a = vec![3u8; n];
            let mut fade_b = fade_a.clone();
            let (ci, cb) = (Cell::new(0u32), Cell::new(0u32));
            let mut inst = vec![DrawableSetupInstance::default(); n];
            let mut bat = vec![DrawableSetupBatch::default(); n];
            let mut sa = QueryStats::default();
            let job = ClusterJob {
                first: c.first,
                count: c.count,
                snap_fade: false,
            };
            query_cluster(
                &params,
                &buffers,
                None,
                &mut fade_a,
                job,
                WaveWidth::W64,
                &ci,
                &mut inst,
                &cb,
                &mut bat,
                &mut sa,
            )
            .unwrap();
            let whole = &inst[..ci.get() as usize];

            let (ci1, cb1) = (Cell::new(0u32), Cell::new(0u32));
            let mut one = vec![DrawableSetupInstance::default(); n];
            let mut bat1 = vec![DrawableSetupBatch::default(); n];
            let mut sb = QueryStats::default();
            for i in 0..c.count {
                let job = ClusterJob {
                    first: c.first + i,
                    count: 1,
                    snap_fade: false,
                };
                let f = &mut fade_b[i as usize..i as usize + 1];
                query_cluster(
                    &params,
                    &buffers,
                    None,
                    f,
                    job,
                    WaveWidth::W64,
                    &ci1,
                    &mut one,
                    &cb1,
                    &mut bat1,
                    &mut sb,
                )
                .unwrap();
            }
            assert!(whole == &one[..ci1.get() as usize]);
            assert_eq!(fade_a, fade_b);
            assert_eq!(sa.visible, sb.visible);
            assert_eq!(
                (sa.rejected_lod, sa.rejected_frustum, sa.rejected_size),
                (sb.rejected_lod, sb.rejected_frustum, sb.rejected_size)
            );
            // One by one, every visible instance is its own batch.
            assert_eq!(u64::from(cb1.get()), sb.visible);
            total += whole.len();
        }
    }
    assert!(total > 100, "the view sees {total}");
}

#[test]
fn short_outputs_drop_and_count() {
    let (scene, cfg) = city_scene(20_000, 2);
    let size = f64::from(cfg.lots[0]) * f64::from(cfg.lot_size);
    let cam = Camera {
        position: DVec3::new(size * 0.5, 150.0, -50.0),
        rotation: DQuat::from_euler(glam::EulerRot::YXZ, std::f64::consts::PI, -0.4, 0.0),
        projection: Mat4::perspective_rh(1.2, 16.0 / 9.0, 0.1, 5000.0),
        reversed_depth: false,
    };
    let mut view = ViewDesc::camera(cam, [640, 360]);
    view.fade_frames = 0;
    let params = QueryParams::new(&view).unwrap();
    let mut checked = 0;
    for tile in scene.tiles() {
        for c in tile.clusters() {
            let job = ClusterJob {
                first: c.first,
                count: c.count,
                snap_fade: false,
            };
            let run = |ni: usize, nb: usize| {
                let (ci, cb) = (Cell::new(0u32), Cell::new(0u32));
                let mut inst = vec![DrawableSetupInstance::default(); ni];
                let mut bat = vec![DrawableSetupBatch::default(); nb];
                let mut s = QueryStats::default();
                query_cluster(
                    &params,
                    &tile.buffers(),
                    None,
                    &mut [],
                    job,
                    WaveWidth::W32,
                    &ci,
                    &mut inst,
                    &cb,
                    &mut bat,
                    &mut s,
                )
                .unwrap();
                (s, ci.get(), cb.get(), inst)
            };
            let (full, ni, nb, all) = run(c.count as usize, c.count as usize);
            if full.visible <= 3 {
                continue;
            }
            let (s, ci, cb, some) = run(3, 1);
            assert_eq!((ci, cb), (ni, nb), "the counters count past the end");
            assert_eq!(s.visible, full.visible);
            assert_eq!(s.dropped, (s.visible - 3) + (s.batches - 1));
            assert!(some[..] == all[..3], "what fits is written");
            checked += 1;
        }
    }
    assert!(checked > 0);
    let tile = &scene.tiles()[0];
    let (ci, cb) = (Cell::new(0u32), Cell::new(0u32));
    let mut inst = vec![DrawableSetupInstance::default(); 3];
    let mut bat = vec![DrawableSetupBatch::default(); 1];
    let mut s = QueryStats::default();
    // A job outside the tile is an error, not a panic.
    let bad = ClusterJob {
        first: tile.instances().len() as u32,
        count: 1,
        snap_fade: false,
    };
    assert!(
        query_cluster(
            &params,
            &tile.buffers(),
            None,
            &mut [],
            bad,
            WaveWidth::W32,
            &ci,
            &mut inst,
            &cb,
            &mut bat,
            &mut s
        )
        .is_err()
    );
}
