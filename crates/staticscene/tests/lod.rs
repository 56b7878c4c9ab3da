//! LOD selection at boundaries: exactly one level of a switch is drawn on either side of
//! (and at) its boundary, the boundary moves with the object's and the view's LOD scales,
//! and parent and child brackets combine, all against distances computed in f64.

mod common;

use std::collections::HashSet;

use common::*;
use glam::{DVec3, Vec3};
use staticscene::{
    Aabb, DrawableSetupInstance, PlacedObject, QueryOptions, QueryOutput, QueryParams, Scene,
    ViewDesc,
};

const FAR: f32 = f32::INFINITY;

/// An object whose LOD box is the unit cube around its position, at `origin`; returns
/// the handles drawn by a camera at `origin + (d + 1, 0, 0)` looking at it (the box's
/// nearest face is `d` away).
fn drawn(scene: &mut Scene, origin: DVec3, d: f64, lod_scale: f32) -> HashSet<u64> {
    let eye = origin + DVec3::new(d + 1.0, 0.0, 0.0);
    let cam = perspective(eye, origin, 1.0, 1.0, false);
    let mut view = ViewDesc::camera(cam, [64, 64]);
    view.fade_frames = 0;
    view.size_threshold_px = 0.0;
    view.lod_scale = lod_scale;
    let params = QueryParams::new(&view).unwrap();
    let mut out = QueryOutput::<DrawableSetupInstance>::new();
    scene
        .query(&params, None, &QueryOptions::default(), &mut out)
        .unwrap();
    out.batches.iter().map(|b| b.setup).collect()
}

fn unit() -> Aabb {
    Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0))
}

fn one_switch(origin: DVec3, object_scale: f32, ignore_global: bool) -> Scene {
    let res = vec![lod(
        unit(),
        vec![
            (0.0, 50.0, mesh(1, Vec3::splat(-1.0), Vec3::splat(1.0))),
            (50.0, 200.0, mesh(2, Vec3::splat(-1.0), Vec3::splat(1.0))),
            (200.0, FAR, mesh(3, Vec3::splat(-1.0), Vec3::splat(1.0))),
        ],
    )];
    let mut o = PlacedObject::new(0, origin);
    o.lod_scale = object_scale;
    o.ignore_global_lod_scale = ignore_global;
    one_group_scene(&res, vec![o])
}

/// The level an f64 reference selects for distance `d` with brackets scaled by `s`.
fn reference(d: f64, s: f64) -> u64 {
    if d < 50.0 * s {
        1
    } else if d < 200.0 * s {
        2
    } else {
        3
    }
}

#[test]
fn exactly_one_level_on_each_side_of_the_boundary() {
    let origin = DVec3::new(-1_234_567.25, 3.0, 777_777.5);
    let mut scene = one_switch(origin, 1.0, false);
    // At the boundary itself: [50, 200) includes 50, [0, 50) does not.
    assert_eq!(drawn(&mut scene, origin, 50.0, 1.0), HashSet::from([2]));
    assert_eq!(drawn(&mut scene, origin, 200.0, 1.0), HashSet::from([3]));
    for d in [0.0, 10.0, 49.9, 49.99, 50.01, 120.0, 199.9, 200.1, 1500.0] {
        assert_eq!(
            drawn(&mut scene, origin, d, 1.0),
            HashSet::from([reference(d, 1.0)]),
            "d = {d}"
        );
    }
    // A fine sweep across the boundary: never two levels, never none.
    for i in 0..200 {
        let d = 49.0 + f64::from(i) * 0.01;
        let got = drawn(&mut scene, origin, d, 1.0);
        assert_eq!(got.len(), 1, "d = {d}: {got:?}");
        if (d - 50.0).abs() > 1e-3 {
            assert_eq!(got, HashSet::from([reference(d, 1.0)]), "d = {d}");
        }
    }
}

#[test]
fn scales_move_the_boundary() {
    let origin = DVec3::new(10.0, 0.0, 10.0);
    // Object scale 2: the 50 m boundary moves to 100 m.
    let mut scene = one_switch(origin, 2.0, false);
    for d in [99.0, 101.0, 399.0, 401.0] {
        assert_eq!(
            drawn(&mut scene, origin, d, 1.0),
            HashSet::from([reference(d, 2.0)]),
            "d = {d}"
        );
    }
    // And with the view's global scale 0.5 on top: back to 50 m.
    for d in [49.0, 51.0] {
        assert_eq!(
            drawn(&mut scene, origin, d, 0.5),
            HashSet::from([reference(d, 1.0)]),
            "d = {d}"
        );
    }
    // An object that ignores the global scale keeps its own.
    let mut scene = one_switch(origin, 2.0, true);
    for d in [99.0, 101.0] {
        assert_eq!(
            drawn(&mut scene, origin, d, 0.5),
            HashSet::from([reference(d, 2.0)]),
            "d = {d}"
        );
    }
}

#[test]
fn parent_and_child_brackets_combine() {
    // Parent [0, 100): blocks, each a child switch [0, 30) detail / [30, inf) simple.
    // Parent [100, inf): collapsed. Child bounds are the block's own box, 20 m towards the
    // camera from the parent's centre, so the child distance differs from the parent's.
    let block = placed(
        glam::Affine3A::from_translation(Vec3::new(20.0, 0.0, 0.0)),
        lod(
            unit(),
            vec![
                (0.0, 30.0, mesh(10, Vec3::splat(-1.0), Vec3::splat(1.0))),
                (30.0, FAR, mesh(11, Vec3::splat(-1.0), Vec3::splat(1.0))),
            ],
        ),
    );
    let parent_box = Aabb::new(Vec3::splat(-25.0), Vec3::splat(25.0));
    let res = vec![lod(
        parent_box,
        vec![
            (0.0, 100.0, block),
            (100.0, FAR, mesh(20, Vec3::splat(-25.0), Vec3::splat(25.0))),
        ],
    )];
    let origin = DVec3::new(5e5, 0.0, 0.0);
    let mut scene = one_group_scene(&res, vec![PlacedObject::new(0, origin)]);
    // Camera on +x at distance e from the origin: parent distance e - 25, child e - 21.
    let at = |scene: &mut Scene, e: f64| {
        let cam = perspective(origin + DVec3::new(e, 0.0, 0.0), origin, 1.2, 1.0, false);
        let mut view = ViewDesc::camera(cam, [64, 64]);
        view.fade_frames = 0;
        view.size_threshold_px = 0.0;
        let params = QueryParams::new(&view).unwrap();
        let mut out = QueryOutput::<DrawableSetupInstance>::new();
        scene
            .query(&params, None, &QueryOptions::default(), &mut out)
            .unwrap();
        out.batches
            .iter()
            .map(|b| b.setup)
            .collect::<HashSet<u64>>()
    };
    for (e, want) in [
        (40.0, 10),  // parent 15, child 19: detail
        (50.5, 10),  // child 29.5
        (51.5, 11),  // child 30.5: simple
        (124.0, 11), // parent 99
        (126.0, 20), // parent 101: collapsed
    ] {
        assert_eq!(at(&mut scene, e), HashSet::from([want]), "camera at {e}");
    }
}
