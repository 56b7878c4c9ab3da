//! LOD fade progression over frames: a new level fades in over N frames while the old one
//! fades out, their opacities summing to one; off-screen switches snap; flagged instances
//! and shadow views pop.

mod common;

use std::collections::BTreeMap;

use common::*;
use glam::{DQuat, DVec3, Vec3};
use staticscene::{
    Aabb, Camera, DrawableSetupInstance, FILTER_ALL, INSTANCE_FLAG_NO_FADE, MeshNode, PlacedObject,
    QueryOptions, QueryOutput, QueryParams, STATE_FADING, STATE_FADING_OUT, Scene, StaticMesh,
    ViewDesc, ViewKind,
};

const N: u32 = 4;

fn switch_scene(flags: u8) -> (Scene, DVec3) {
    let leaf = |h| {
        MeshNode::Static(StaticMesh {
            setup: h,
            bounds: Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0)),
            filter: FILTER_ALL,
            flags,
        })
    };
    let res = vec![lod(
        Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0)),
        vec![(0.0, 50.0, leaf(1)), (50.0, f32::INFINITY, leaf(2))],
    )];
    let origin = DVec3::new(300_000.0, 5.0, -2_000.0);
    let s = one_group_scene(&res, vec![PlacedObject::new(0, origin)]);
    (s, origin)
}

/// (fade, flags) of each drawn setup.
fn frame(
    scene: &mut Scene,
    cam: Camera,
    kind: ViewKind,
    precull: bool,
) -> BTreeMap<u64, (f32, u32)> {
    let mut view = ViewDesc::camera(cam, [64, 64]);
    view.kind = kind;
    view.fade_frames = N;
    view.size_threshold_px = 0.0;
    let params = QueryParams::new(&view).unwrap();
    let mut out = QueryOutput::<DrawableSetupInstance>::new();
    let options = QueryOptions {
        precull,
        ..QueryOptions::default()
    };
    scene.query(&params, None, &options, &mut out).unwrap();
    out.batches
        .iter()
        .map(|b| {
            let s = out.instances[b.first_instance as usize].state;
            assert_eq!(b.flags, s.flags, "one instance per batch here");
            (b.setup, (s.fade, s.flags))
        })
        .collect()
}

fn looking(origin: DVec3, d: f64, away: bool) -> Camera {
    let eye = origin + DVec3::new(d + 1.0, 0.0, 0.0);
    let mut c = perspective(eye, origin, 1.0, 1.0, false);
    if away {
        c.rotation = DQuat::from_rotation_y(std::f64::consts::PI) * c.rotation;
    }
    c
}

/// A camera view's frame, `d` in front of `origin` looking at it or (`away`) away from it.
fn camera_frame(
    scene: &mut Scene,
    origin: DVec3,
    d: f64,
    away: bool,
    precull: bool,
) -> BTreeMap<u64, (f32, u32)> {
    frame(scene, looking(origin, d, away), ViewKind::Camera, precull)
}

#[test]
fn cross_fade_sums_to_one() {
    for precull in [true, false] {
        let (mut scene, o) = switch_scene(0);
        // A fresh tile: the near level fades in.
        for k in 1..=N {
            let f = camera_frame(&mut scene, o, 40.0, false, precull);
            let want = k as f32 / N as f32;
            let flags = if k < N { STATE_FADING } else { 0 };
            assert_eq!(f, BTreeMap::from([(1, (want, flags))]), "fade-in frame {k}");
        }
        assert_eq!(
            camera_frame(&mut scene, o, 40.0, false, precull),
            BTreeMap::from([(1, (1.0, 0))])
        );
        // Cross the boundary: 1 fades out while 2 fades in.
        for k in 1..N {
            let f = camera_frame(&mut scene, o, 60.0, false, precull);
            let (a, fa) = f[&1];
            let (b, fb) = f[&2];
            assert_eq!(a, (N - k) as f32 / N as f32, "frame {k}");
            assert_eq!(b, k as f32 / N as f32, "frame {k}");
            assert_eq!(a + b, 1.0);
            assert_eq!((fa, fb), (STATE_FADING | STATE_FADING_OUT, STATE_FADING));
        }
        assert_eq!(
            camera_frame(&mut scene, o, 60.0, false, precull),
            BTreeMap::from([(2, (1.0, 0))])
        );
        let id = scene.tiles()[0].id();
        let mut states = [scene.fade_state(id, 0), scene.fade_state(id, 1)];
        states.sort();
        assert_eq!(states, [Some(0), Some(N as u8)]);
    }
}

#[test]
fn switches_off_screen_snap() {
    for precull in [true, false] {
        let (mut scene, o) = switch_scene(0);
        for _ in 0..N + 1 {
            camera_frame(&mut scene, o, 60.0, false, precull);
        }
        // Turn away, cross the boundary, turn back: the near level is simply there.
        assert!(camera_frame(&mut scene, o, 60.0, true, precull).is_empty());
        assert!(camera_frame(&mut scene, o, 40.0, true, precull).is_empty());
        assert_eq!(
            camera_frame(&mut scene, o, 40.0, false, precull),
            BTreeMap::from([(1, (1.0, 0))]),
            "precull {precull}"
        );
    }
}

#[test]
fn flagged_instances_and_shadow_views_pop() {
    let (mut scene, o) = switch_scene(INSTANCE_FLAG_NO_FADE);
    assert_eq!(
        camera_frame(&mut scene, o, 40.0, false, true),
        BTreeMap::from([(1, (1.0, 0))])
    );
    assert_eq!(
        camera_frame(&mut scene, o, 60.0, false, true),
        BTreeMap::from([(2, (1.0, 0))])
    );
    let (mut scene, o) = switch_scene(0);
    assert_eq!(
        frame(&mut scene, looking(o, 40.0, false), ViewKind::Shadow, true),
        BTreeMap::from([(1, (1.0, 0))])
    );
    assert_eq!(
        frame(&mut scene, looking(o, 60.0, false), ViewKind::Shadow, true),
        BTreeMap::from([(2, (1.0, 0))])
    );
}
