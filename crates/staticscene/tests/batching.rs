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
            let world = |p: DVec3| {
                let r = &m.rows;
                DVec3::new(
                    f64::from(r[0][0]) * p.x
                        + f64::from(r[0][1]) * p.y
                        + f64::from(r[0][2]) * p.z
                        + f64::from(r[0][3]),
                    f64::from(r[1][0]) * p.x
                        + f64::from(r[1][1]) * p.y
                        + f64::from(r[1][2]) * p.z
                        + f64::from(r[1][3]),
                    f64::from(r[2][0]) * p.x
                        + f64::from(r[2][1]) * p.y
                        + f64::from(r[2][2]) * p.z
                        + f64::from(r[2][3]),
                )
            };
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
