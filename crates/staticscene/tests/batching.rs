//! The batched output equals a naive group-by of the visible instances: consecutive
//! visible instances of one setup within one wave of one cluster make one batch, and each
//! header's sphere, flags, stride and sort key describe its instances.

mod common;

use common::*;
use glam::{DQuat, DVec3, Mat4};
use staticscene::{
    Camera, DrawableSetupInstance, DrawableSetupInstancePrev, OutputInstance, QueryOptions,
    QueryOutput, QueryParams, Scene, ViewDesc, WaveWidth, sort_key,
};

fn street(size: f64, a: f64, x: f64) -> Camera {
    Camera {
        position: DVec3::new(size * x, 1.7, size * 0.5),
        rotation: DQuat::from_rotation_y(a),
        projection: Mat4::perspective_rh(1.2, 16.0 / 9.0, 0.1, 5000.0),
        reversed_depth: false,
    }
}

#[derive(Debug, PartialEq)]
struct Group {
    first: u32,
    count: u32,
    setup: u64,
}

fn check<I: OutputInstance>(
    scene: &Scene,
    out: &QueryOutput<I>,
    width: WaveWidth,
) -> (usize, usize) {
    // Naive group-by over the visible instances in output order.
    let mut groups: Vec<Group> = Vec::new();
    let mut prev_key = None;
    let mut prev_index: Option<(u32, u32)> = None;
    for (i, inst) in out.instances.iter().enumerate() {
        let s = inst.state();
        let tile = scene
            .tiles()
            .iter()
            .find(|t| t.id().0 == s.tile)
            .expect("tile exists");
        let q = tile.instances()[s.instance as usize];
        let handle = tile.setups()[q.setup() as usize].handle;
        let cluster = tile
            .clusters()
            .iter()
            .position(|c| c.first <= s.instance && s.instance < c.first + c.count)
            .unwrap();
        let wave = (s.instance - tile.clusters()[cluster].first) / width.lanes();
        if let Some((t, idx)) = prev_index
            && t == s.tile
        {
            assert!(s.instance > idx, "instances leave in thread order");
        }
        prev_index = Some((s.tile, s.instance));
        let key = (s.tile, cluster, wave, handle);
        if prev_key == Some(key) {
            groups.last_mut().unwrap().count += 1;
        } else {
            groups.push(Group {
                first: i as u32,
                count: 1,
                setup: handle,
            });
        }
        prev_key = Some(key);
    }
    let got: Vec<Group> = out
        .batches
        .iter()
        .map(|b| Group {
            first: b.first_instance,
            count: b.count,
            setup: b.setup,
        })
        .collect();
    assert_eq!(got, groups);
    // Each header describes its instances.
    for b in &out.batches {
        assert_eq!(b.stride, I::STRIDE);
        assert!(b.count <= width.lanes());
        let mut flags = 0;
        let c = DVec3::new(
            f64::from(b.sphere[0]),
            f64::from(b.sphere[1]),
            f64::from(b.sphere[2]),
        );
        let r = f64::from(b.sphere[3]);
        for inst in &out.instances[b.first_instance as usize..(b.first_instance + b.count) as usize]
        {
            let s = inst.state();
            flags |= s.flags;
            let tile = scene.tiles().iter().find(|t| t.id().0 == s.tile).unwrap();
            let setup = tile.setups()[tile.instances()[s.instance as usize].setup() as usize];
            let m = inst.local_to_floating();
            let world = |p: DVec3| rows_f64(&m.rows, p);
            for p in corners(setup.min(), setup.max(), world) {
                assert!(
                    p.distance(c) <= r * (1.0 + 1e-5) + 1e-3,
                    "corner outside the batch sphere"
                );
            }
        }
        assert_eq!(b.flags, flags);
        let depth = f32::from_bits(b.sort_key as u32);
        assert!(depth >= 0.0 && depth.is_finite());
        assert_eq!(sort_key(b.setup, depth), b.sort_key);
    }
    (out.instances.len(), out.batches.len())
}

fn run<I: OutputInstance>(scene: &mut Scene, size: f64, width: WaveWidth) -> (usize, usize) {
    let (mut items, mut batches) = (0, 0);
    for k in 0..6 {
        let cam = street(size, k as f64 * 1.1, 0.3 + 0.08 * k as f64);
        let mut view = ViewDesc::camera(cam, [1280, 720]);
        view.fade_frames = 0;
        let params = QueryParams::new(&view).unwrap();
        let mut out = QueryOutput::<I>::new();
        let options = QueryOptions {
            wave_width: width,
            precull: true,
        };
        scene.query(&params, None, &options, &mut out).unwrap();
        assert_eq!(out.stats.visible as usize, out.instances.len());
        assert_eq!(out.stats.dropped, 0);
        let (i, b) = check(scene, &out, width);
        items += i;
        batches += b;
    }
    (items, batches)
}

#[test]
fn batches_equal_a_naive_group_by() {
    let (mut scene, cfg) = city_scene(60_000, 3);
    let size = cfg.lots[0] as f64 * f64::from(cfg.lot_size);
    for width in [WaveWidth::W8, WaveWidth::W32, WaveWidth::W64] {
        let (items, batches) = run::<DrawableSetupInstance>(&mut scene, size, width);
        assert!(items > 1000, "views see something");
        println!(
            "wave {width}: {items} instances in {batches} batches, render items -{:.1}%",
            100.0 * (1.0 - batches as f64 / items as f64)
        );
    }
    let (items, _) = run::<DrawableSetupInstancePrev>(&mut scene, size, WaveWidth::W64);
    assert!(items > 1000);
}

#[test]
fn previous_transform_follows_the_previous_origin() {
    let (mut scene, cfg) = city_scene(20_000, 5);
    let size = cfg.lots[0] as f64 * f64::from(cfg.lot_size);
    let cam = street(size, 0.4, 0.5);
    let mut view = ViewDesc::camera(cam, [640, 360]);
    view.fade_frames = 0;
    view.previous_origin =
        Some(staticscene::snap_origin(cam.position) + glam::IVec3::new(3, 0, -7));
    let params = QueryParams::new(&view).unwrap();
    let mut out = QueryOutput::<DrawableSetupInstancePrev>::new();
    scene
        .query(&params, None, &QueryOptions::default(), &mut out)
        .unwrap();
    assert!(!out.instances.is_empty());
    for i in &out.instances {
        // origin - previous origin = (-3, 0, 7): the same point sits there in the old space.
        let d = i.prev_local_to_floating.translation() - i.local_to_floating.translation();
        assert!(
            (d - glam::Vec3::new(-3.0, 0.0, 7.0)).abs().max_element() < 1e-3,
            "{d}"
        );
        assert_eq!(
            i.prev_local_to_floating.linear(),
            i.local_to_floating.linear()
        );
    }
}

#[test]
fn packed_query_draws_what_the_flat_loop_draws() {
    // The unpacked f32 baseline (no tiles, clusters, packing, memo) over the same scene
    // draws the same instances, fading and all, frame after frame. (With the pre-cull
    // off: a cluster the pre-cull skipped restarts its fades from the snapped state, one
    // frame's difference from per-instance fading when its LOD changed meanwhile.)
    use staticscene::baseline::{flat_query, flatten_scene};
    let (mut scene, cfg) = city_scene(60_000, 8);
    let size = cfg.lots[0] as f64 * f64::from(cfg.lot_size);
    // Flat record k is instance k of the tiles in scene order.
    let mut base = std::collections::HashMap::new();
    let mut k = 0u32;
    for t in scene.tiles() {
        base.insert(t.id().0, k);
        k += t.instances().len() as u32;
    }
    for frame in 0..8 {
        let cam = street(size, frame as f64 * 0.4, 0.3 + 0.05 * frame as f64);
        let mut view = ViewDesc::camera(cam, [640, 360]);
        view.fade_frames = 3;
        let params = QueryParams::new(&view).unwrap();
        let mut out = QueryOutput::<DrawableSetupInstance>::new();
        let options = QueryOptions {
            precull: false,
            ..QueryOptions::default()
        };
        // Both start the frame from the query's fade states, so any difference comes
        // from this frame's decisions.
        let mut fade: Vec<u8> = scene
            .tiles()
            .iter()
            .flat_map(|t| (0..t.instances().len()).map(|i| scene.fade_state(t.id(), i).unwrap()))
            .collect();
        scene.query(&params, None, &options, &mut out).unwrap();
        let mut got: Vec<(u32, u32, u32)> = out
            .instances
            .iter()
            .map(|i| {
                (
                    base[&i.state.tile] + i.state.instance,
                    i.state.fade.to_bits(),
                    i.state.flags,
                )
            })
            .collect();
        got.sort_unstable();
        let (mut fo, mut fb) = (Vec::new(), Vec::new());
        // Records in this frame's floating space: the same f32 arithmetic as the query.
        let flat = flatten_scene(&scene, params.origin());
        flat_query(
            &flat,
            &mut fade,
            &params,
            params.origin(),
            None,
            &mut fo,
            &mut fb,
            0,
        );
        let want: Vec<(u32, u32, u32)> = fo
            .iter()
            .map(|i| (i.state.instance, i.state.fade.to_bits(), i.state.flags))
            .collect();
        assert!(got.len() > 100);
        // Differences may only come from f32 rounding at a LOD boundary (the two loops
        // sum the same products in different orders): each differing instance must sit
        // within 1e-5 of one of its four LOD distances, measured in f64.
        let gs: std::collections::BTreeSet<_> = got.iter().copied().collect();
        let ws: std::collections::BTreeSet<_> = want.iter().copied().collect();
        let lod_point = params.lod_point().as_dvec3();
        let mut differing = 0;
        for &(k, _, _) in gs.symmetric_difference(&ws) {
            let f = &flat[k as usize];
            let s = f64::from(f.lod_scale * params.lod_point[3]);
            let near = |(lo, hi, a, b): (glam::Vec3, glam::Vec3, f32, f32)| {
                let c = corners(lo, hi, |p| rows_f64(&f.object_to_world.rows, p));
                let mn = c.iter().fold(DVec3::INFINITY, |m, p| m.min(*p));
                let mx = c.iter().fold(DVec3::NEG_INFINITY, |m, p| m.max(*p));
                let d = (mn - lod_point)
                    .max(lod_point - mx)
                    .max(DVec3::ZERO)
                    .length();
                [a, b].iter().any(|&x| {
                    let x = f64::from(x) * s;
                    x.is_finite() && (d - x).abs() <= 1e-5 * x.max(1.0)
                })
            };
            assert!(
                near(f.parent) || near(f.child),
                "frame {frame}: instance {k} differs away from any LOD boundary"
            );
            differing += 1;
        }
        assert!(
            differing * 1000 <= got.len(),
            "frame {frame}: {differing} differ"
        );
    }
}
