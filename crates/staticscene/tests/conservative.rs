//! The frustum and occlusion tests are conservative: in random scenes, no instance that a
//! brute-force f64 test sees (its oriented box against the f64 frustum, then rasterised
//! in f64 against a CPU depth raster of the occluders) is ever culled.

mod common;

use std::collections::HashSet;

use common::*;
use glam::{Affine3A, DVec3, Mat3, Vec3};
use staticscene::demo::{box_hiz, raster_boxes};
use staticscene::{
    BuildConfig, Camera, DrawableSetupInstance, HiZ, PlacedObject, QueryOptions, QueryOutput,
    QueryParams, ViewDesc, WaveWidth, snap_origin,
};
use testkit::Rng;

struct Obj {
    position: DVec3,
    linear: Mat3,
    local: Affine3A,
    min: Vec3,
    max: Vec3,
}

fn random_scene(rng: &mut Rng, n: usize, centre: DVec3) -> (Vec<Obj>, staticscene::Scene) {
    let mut objs = Vec::new();
    let mut resources = Vec::new();
    let mut objects = Vec::new();
    for i in 0..n {
        let min = Vec3::new(
            rng.range(-3.0, 0.0),
            rng.range(-3.0, 0.0),
            rng.range(-3.0, 0.0),
        );
        let max = min
            + Vec3::new(
                rng.range(0.05, 4.0),
                rng.range(0.05, 4.0),
                rng.range(0.05, 4.0),
            );
        let local = Affine3A::from_scale_rotation_translation(
            Vec3::splat(rng.range(0.5, 2.0)),
            rotation(
                rng.range(0.0, 6.3),
                rng.range(0.0, 6.3),
                rng.range(0.0, 6.3),
            ),
            Vec3::new(
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
            ),
        );
        resources.push(placed(local, mesh(i as u64, min, max)));
        let position = centre
            + DVec3::new(
                f64::from(rng.range(-120.0, 120.0)) + 0.123_456,
                f64::from(rng.range(-30.0, 30.0)),
                f64::from(rng.range(-120.0, 120.0)),
            );
        let linear = Mat3::from_quat(rotation(rng.range(0.0, 6.3), rng.range(-1.0, 1.0), 0.0))
            * Mat3::from_diagonal(Vec3::new(
                rng.range(0.5, 3.0),
                rng.range(0.5, 3.0),
                rng.range(0.5, 3.0),
            ));
        let mut o = PlacedObject::new(i, position);
        o.linear = linear;
        objects.push(o);
        objs.push(Obj {
            position,
            linear,
            local,
            min,
            max,
        });
    }
    let config = BuildConfig {
        min_cluster: 64,
        orphan_below: 0,
        ..BuildConfig::default()
    };
    let scene = scene(&resources, &[group(0, objects)], config);
    (objs, scene)
}

fn world_corners(o: &Obj) -> [DVec3; 8] {
    let l = o.local;
    let lm = l.matrix3.as_dmat3();
    let lt = l.translation.as_dvec3();
    let ow = object_to_world(o.position, o.linear);
    corners(o.min, o.max, |p| ow(lm * p + lt))
}

fn visible_handles(out: &QueryOutput<DrawableSetupInstance>) -> HashSet<u64> {
    out.batches.iter().map(|b| b.setup).collect()
}

fn run_case(seed: u64, ortho: bool, reversed: bool, moved_hiz: bool) -> (u64, u64) {
    let mut rng = Rng::new(seed);
    let centre = DVec3::new(250_000.0, 10.0, -731_000.0);
    let (objs, mut scene) = random_scene(&mut rng, 400, centre);
    let (w, h) = (160u32, 96u32);
    let eye = centre
        + DVec3::new(
            f64::from(rng.range(-60.0, 60.0)),
            f64::from(rng.range(0.0, 40.0)),
            160.0,
        );
    let target = centre + DVec3::new(f64::from(rng.range(-40.0, 40.0)), 0.0, 0.0);
    let cam: Camera = if ortho {
        orthographic(eye, target, 90.0, reversed)
    } else {
        perspective(
            eye,
            target,
            rng.range(0.6, 1.6),
            w as f32 / h as f32,
            reversed,
        )
    };
    let occ_cam = if moved_hiz {
        let mut c = cam;
        c.position += DVec3::new(1.5, 0.3, -2.0);
        c
    } else {
        cam
    };
    // Occluders: walls and slabs across the view.
    let walls: Vec<(DVec3, DVec3)> = (0..12)
        .map(|_| {
            let c = centre
                + DVec3::new(
                    f64::from(rng.range(-80.0, 80.0)),
                    f64::from(rng.range(-10.0, 20.0)),
                    f64::from(rng.range(-20.0, 120.0)),
                );
            let e = DVec3::new(
                f64::from(rng.range(2.0, 40.0)),
                f64::from(rng.range(2.0, 30.0)),
                f64::from(rng.range(0.2, 3.0)),
            );
            (c - e, c + e)
        })
        .collect();
    let origin = snap_origin(cam.position);
    let depth = raster_boxes(
        &walls,
        origin,
        &occ_cam.clip_from_floating(origin),
        w,
        h,
        reversed,
    );
    let hiz = HiZ::build(&depth, w, h, reversed).unwrap();

    let mut view = ViewDesc::camera(cam, [w, h]);
    view.size_threshold_px = 0.0;
    view.fade_frames = 0;
    view.occlusion_camera = Some(occ_cam);
    view.hiz_scan_levels = (seed % 3) as u32;
    let params = QueryParams::new(&view).unwrap();
    let mut out = QueryOutput::<DrawableSetupInstance>::new();
    let options = QueryOptions {
        wave_width: WaveWidth::W32,
        precull: seed.is_multiple_of(2),
    };
    scene
        .query(&params, Some(&hiz), &options, &mut out)
        .unwrap();
    let seen = visible_handles(&out);

    let m = clip_from_world(&cam);
    let mo = clip_from_world(&occ_cam);
    let (mut truth_visible, mut culled_by_occlusion) = (0, 0);
    for (i, o) in objs.iter().enumerate() {
        let c = world_corners(o);
        if !frustum_visible_f64(&m, &c) {
            continue;
        }
        let visible = raster_visible_f64(&mo, &c, &depth, w, h, reversed, 1e-9);
        if !visible {
            culled_by_occlusion += 1;
            continue;
        }
        truth_visible += 1;
        assert!(
            seen.contains(&(i as u64)),
            "seed {seed} ortho {ortho} reversed {reversed} moved {moved_hiz}: object {i} is visible in f64 but was culled"
        );
    }
    // The scenes must exercise both tests.
    assert!(
        truth_visible > 10,
        "seed {seed}: only {truth_visible} visible"
    );
    (out.stats.rejected_occlusion, culled_by_occlusion)
}

#[test]
fn frustum_and_occlusion_never_cull_what_f64_sees() {
    let (mut culled, mut hidden) = (0, 0);
    for seed in 0..8 {
        for (ortho, reversed, moved) in [
            (false, false, false),
            (false, true, false),
            (false, false, true),
            (true, false, false),
            (true, true, true),
        ] {
            let (c, h) = run_case(seed * 7 + 1, ortho, reversed, moved);
            culled += c;
            hidden += h;
        }
    }
    // Not vacuous: occlusion did cull, a fair share of what is truly hidden.
    println!("occlusion culled {culled} of {hidden} hidden instances");
    assert!(culled * 4 > hidden, "occlusion culled {culled} of {hidden}");
}

#[test]
fn occlusion_culls_something() {
    // A wall right in front of the camera hides a box behind it; a box beside the wall stays.
    let resources = vec![
        mesh(1, Vec3::splat(-1.0), Vec3::splat(1.0)),
        mesh(2, Vec3::splat(-1.0), Vec3::splat(1.0)),
    ];
    let centre = DVec3::new(1e6, 0.0, 1e6);
    let objects = vec![
        PlacedObject::new(0, centre + DVec3::new(0.0, 0.0, -30.0)),
        PlacedObject::new(1, centre + DVec3::new(15.0, 0.0, -30.0)),
    ];
    let mut scene = one_group_scene(&resources, objects);
    for reversed in [false, true] {
        let cam = perspective(
            centre,
            centre + DVec3::new(0.0, 0.0, -1.0),
            1.2,
            1.5,
            reversed,
        );
        let (w, h) = (120, 80);
        let wall = [(
            centre + DVec3::new(-5.0, -5.0, -11.0),
            centre + DVec3::new(5.0, 5.0, -10.0),
        )];
        let hiz = box_hiz(&wall, &cam, &cam, w, h, reversed).unwrap();
        let mut view = ViewDesc::camera(cam, [w, h]);
        view.fade_frames = 0;
        view.occlusion_camera = Some(cam);
        let params = QueryParams::new(&view).unwrap();
        let mut out = QueryOutput::<DrawableSetupInstance>::new();
        scene
            .query(&params, Some(&hiz), &QueryOptions::default(), &mut out)
            .unwrap();
        let seen = visible_handles(&out);
        assert_eq!(seen, HashSet::from([2]), "reversed {reversed}");
        assert_eq!(out.stats.rejected_occlusion, 1);
        // Without the HiZ both are drawn.
        scene
            .query(&params, None, &QueryOptions::default(), &mut out)
            .unwrap();
        assert_eq!(visible_handles(&out), HashSet::from([1, 2]));
    }
}
