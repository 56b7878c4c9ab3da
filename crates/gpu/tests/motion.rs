//! Motion vectors: the G-buffer's motion (pixels, current minus previous, `+y` down) of a
//! still scene under a moving camera equals an f64 reprojection of each pixel's depth
//! through the two cameras, on both paths; a scene's first frame has none. Animated
//! foliage (HFW's wind) sits where the CPU reference of the animation puts it and its
//! motion vectors add the sway between the two frames' times.

mod common;

use demo::{DemoOptions, DemoScene};
use glam::{Affine3A, DMat4, DVec2, DVec3, DVec4, Vec2, Vec3, Vec4};
use gpu::scene::{AlbedoLayer, MaterialId, MeshId, ShaderKind, Wind};
use gpu::{Batch, Camera, FrameInput, Mesh, RenderPath, Scene};

const W: u32 = 240;
const H: u32 = 136;

/// World -> clip of `camera` (f64, reversed Z, infinite far plane).
fn view_proj(camera: &Camera) -> DMat4 {
    let aspect = f64::from(W) / f64::from(H);
    let view = DMat4::look_at_rh(
        camera.position.as_dvec3(),
        camera.target.as_dvec3(),
        camera.up.as_dvec3(),
    );
    let proj = DMat4::perspective_infinite_reverse_rh(
        f64::from(camera.fov_y),
        aspect,
        f64::from(camera.near),
    );
    proj * view
}

/// Clip of world point `p` through `camera` (f64).
fn clip(camera: &Camera, p: DVec3) -> DVec4 {
    view_proj(camera) * p.extend(1.0)
}

/// The world point at pixel centre `(x, y)` with depth `d` seen by `camera` (f64).
fn unproject(camera: &Camera, x: u32, y: u32, d: f32) -> DVec3 {
    let ndc = DVec4::new(
        (f64::from(x) + 0.5) / f64::from(W) * 2.0 - 1.0,
        1.0 - (f64::from(y) + 0.5) / f64::from(H) * 2.0,
        f64::from(d),
        1.0,
    );
    let p = view_proj(camera).inverse() * ndc;
    p.truncate() / p.w
}

fn pixels(c: DVec4) -> (f64, f64) {
    (
        (c.x / c.w * 0.5 + 0.5) * f64::from(W),
        (0.5 - c.y / c.w * 0.5) * f64::from(H),
    )
}

/// Per pixel, the motion (pixels, +y down) of the point at its depth in `now`, reprojected
/// through both cameras; None where nothing was drawn.
fn reprojected_motion(before: &Camera, now: &Camera, depth: &[f32]) -> Vec<Option<DVec2>> {
    (0..W * H)
        .map(|i| {
            let (x, y) = (i % W, i / W);
            let d = depth[i as usize];
            (d > 0.0).then(|| {
                let world = unproject(now, x, y, d);
                let (nx, ny) = pixels(clip(now, world));
                let (px, py) = pixels(clip(before, world));
                DVec2::new(nx - px, ny - py)
            })
        })
        .collect()
}

#[test]
fn motion_vectors_reproject_the_depth_through_both_cameras() {
    let (scene, frame) = demo::build(&DemoOptions {
        scene: DemoScene::Forest,
        seed: 7,
        density: 0.25,
    });
    let mut r = common::renderer(W, H, true);
    let prepared = r.prepare(&scene).unwrap();
    for path in [RenderPath::Deferred, RenderPath::Baseline] {
        // A scene's first frame for this renderer has no previous camera: no motion.
        let mut first = common::renderer(W, H, true);
        let p = first.prepare(&scene).unwrap();
        first.render(&p, &frame, path).unwrap();
        let still = first.inspect().read_gbuffer().unwrap();
        assert!(
            still.iter().all(|s| s.motion == Vec2::ZERO),
            "{path:?}: first frame"
        );

        // Frame 1, then frame 2 with the camera moved sideways, forwards and turned.
        let before = frame.camera;
        r.render(&prepared, &frame, path).unwrap();
        let mut moved = frame.clone();
        moved.camera.position += Vec3::new(0.6, 0.1, -0.4);
        moved.camera.target += Vec3::new(-1.5, 0.3, 0.0);
        r.render(&prepared, &moved, path).unwrap();
        let surfaces = r.inspect().read_gbuffer().unwrap();
        let depth = r.inspect().read_depth().unwrap();
        let (mut checked, mut off, mut moving) = (0, 0, 0);
        let mut worst: f64 = 0.0;
        let wanted = reprojected_motion(&before, &moved.camera, &depth);
        for (s, want) in surfaces.iter().zip(&wanted) {
            let Some(want) = want else { continue };
            let err = (s.motion.as_dvec2() - *want).length();
            let tolerance = 0.05 + 0.01 * want.length();
            checked += 1;
            moving += usize::from(want.length() > 1.0);
            if err > tolerance {
                off += 1;
                worst = worst.max(err);
            }
        }
        eprintln!(
            "{path:?}: {checked} pixels, {moving} moving over a pixel, {off} off by more than 0.05 px + 1% (worst {worst:.3} px)"
        );
        assert!(
            checked > 10_000 && moving * 2 > checked,
            "{checked} / {moving}"
        );
        // Silhouette pixels: the depth at the centre can belong to the other surface
        // of a quad's fragment interpolation (baseline) or be a tie; a handful at most.
        assert!(off * 200 <= checked, "{path:?}: {off} of {checked} off");
    }
}

/// The hillside's distant blades are sub-pixel and often edge-on: the pixel centre can lie
/// outside the triangle the resolve rebuilds from the vertex ring's f16 positions, where
/// unclamped weights put the surface far along its plane (here 0.93 px of motion off; at
/// 640x360, 20 px against its neighbours' 1). Clamped, every pixel's motion is its
/// depth's reprojection within a quarter pixel and a tenth, with the ring and without.
#[test]
fn sub_pixel_edge_on_blades_move_as_their_depth() {
    let (scene, frame) = demo::build(&DemoOptions {
        scene: DemoScene::Hillside,
        seed: 1,
        density: 0.5,
    });
    for ring in [None, Some(gpu::config::RING_BYTES_PS5)] {
        let mut r = common::renderer_with({
            let mut rc = gpu::RendererConfig::sized(W, H);
            rc.geometry.vertex_ring = ring;
            rc.lighting.shadows = common::test_shadows();
            rc
        });
        let prepared = r.prepare(&scene).unwrap();
        r.render(&prepared, &frame, RenderPath::Deferred).unwrap();
        let mut moved = frame.clone();
        moved.camera.position += Vec3::new(0.3, 0.0, 0.2);
        moved.camera.target += Vec3::new(0.3, 0.0, 0.2);
        r.render(&prepared, &moved, RenderPath::Deferred).unwrap();
        let surfaces = r.inspect().read_gbuffer().unwrap();
        let depth = r.inspect().read_depth().unwrap();
        let (mut checked, mut worst, mut at) = (0, 0.0f64, (0, 0));
        let wanted = reprojected_motion(&frame.camera, &moved.camera, &depth);
        for (i, (s, want)) in surfaces.iter().zip(&wanted).enumerate() {
            let Some(want) = want else { continue };
            let err = (s.motion.as_dvec2() - *want).length() - 0.1 * want.length();
            checked += 1;
            if err > worst {
                (worst, at) = (err, (i as u32 % W, i as u32 / W));
            }
        }
        eprintln!("ring {ring:?}: {checked} pixels, worst {worst:.3} px over 10% at {at:?}");
        assert!(checked > 10_000, "{checked}");
        assert!(worst < 0.25, "ring {ring:?}: {worst} px at {at:?}");
    }
}

/// A 4 m horizontal alpha-tested (fully opaque) quad at object height 1 m, swaying in a
/// strong wind; the wind itself, optional.
fn swaying_quad(wind: Option<Wind>) -> (Scene, Affine3A) {
    let h = 1.0;
    let corners = [
        Vec3::new(-2.0, h, -2.0),
        Vec3::new(2.0, h, -2.0),
        Vec3::new(2.0, h, 2.0),
        Vec3::new(-2.0, h, 2.0),
    ];
    let mesh = Mesh {
        name: "card".into(),
        positions: corners.to_vec(),
        normals: vec![Vec3::Y; 4],
        uvs: vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y],
        tangents: vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 4],
        indices: vec![0, 2, 1, 0, 3, 2],
    };
    let instance = Affine3A::from_translation(Vec3::new(0.3, 0.0, -0.2));
    let scene = Scene {
        data_layers: Vec::new(),
        meshes: vec![mesh],
        materials: vec![common::material("leaf", ShaderKind::AlphaTested)],
        albedo_layers: vec![AlbedoLayer {
            size: 4,
            texels: vec![[90, 160, 60, 255]; 16],
        }],
        batches: vec![Batch {
            mesh: MeshId(0),
            material: MaterialId(0),
            instances: vec![instance],
        }],
        static_setups: Vec::new(),
        wind,
    };
    (scene, instance)
}

/// Twice-signed area test: is `p` at least `margin` pixels inside (positive) or outside
/// (negative) the convex polygon `poly` (pixels, either winding)?
fn signed_inset(poly: &[(f64, f64)], p: (f64, f64)) -> f64 {
    let n = poly.len();
    let area: f64 = (0..n)
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            a.0 * b.1 - b.0 * a.1
        })
        .sum();
    let sign = area.signum();
    (0..n)
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            let (ex, ey) = (b.0 - a.0, b.1 - a.1);
            sign * (ex * (p.1 - a.1) - ey * (p.0 - a.0)) / ex.hypot(ey)
        })
        .fold(f64::INFINITY, f64::min)
}

/// HFW's animated foliage: with a still camera, the quad's pixels sit where the CPU
/// reference of the wind (`Wind::displacement`) puts its four corners at this frame's
/// time, and their motion vectors are the displacement between the previous frame's time
/// and this one's, reprojected (f64) from each pixel's depth; every path agrees (deferred, baseline, pixel pull) and their
/// depths are bit-identical. Without wind the quad does not move.
#[test]
fn animated_foliage_moves_as_the_cpu_reference_and_has_motion_vectors() {
    let wind = Wind {
        direction: Vec2::new(1.0, 0.5),
        amplitude: 0.6,
        frequency: 0.2,
        height: 1.0,
    };
    let camera = Camera::look_at(Vec3::new(0.0, 7.0, 6.0), Vec3::new(0.0, 0.5, 0.0));
    let (t0, t1) = (0.4_f32, 1.5_f32);
    let mut depths = Vec::new();
    for path in [
        RenderPath::Deferred,
        RenderPath::Baseline,
        RenderPath::PixelPull,
    ] {
        let (scene, instance) = swaying_quad(Some(wind));
        let mut r = common::renderer(W, H, true);
        let prepared = r.prepare(&scene).unwrap();
        let origin = prepared.summary().origin;
        let t = Vec3::from(instance.translation) - origin;
        let top = Vec3::new(0.0, 1.0, 0.0);
        let (d0, d1) = (
            wind.displacement(t, top, t0).as_dvec3(),
            wind.displacement(t, top, t1).as_dvec3(),
        );
        assert!((d1 - d0).length() > 0.2, "the test needs motion: {d0} {d1}");
        let mut frame = FrameInput::new(camera);
        frame.time = t0;
        r.render(&prepared, &frame, path).unwrap();
        frame.time = t1;
        r.render(&prepared, &frame, path).unwrap();
        let surfaces = r.inspect().read_gbuffer().unwrap();
        let depth = r.inspect().read_depth().unwrap();

        // Coverage: the corners displaced by the reference, projected.
        let poly: Vec<(f64, f64)> = swaying_quad(None).0.meshes[0]
            .positions
            .iter()
            .map(|&c| {
                let world = instance.transform_point3(c).as_dvec3() + d1;
                pixels(clip(&camera, world))
            })
            .collect();
        let (mut inside, mut outside, mut wrong) = (0, 0, 0);
        let (mut checked, mut off, mut worst) = (0, 0, 0.0_f64);
        for y in 0..H {
            for x in 0..W {
                let i = (y * W + x) as usize;
                let s = signed_inset(&poly, (f64::from(x) + 0.5, f64::from(y) + 0.5));
                let covered = depth[i] > 0.0;
                if s > 0.75 {
                    inside += 1;
                    wrong += usize::from(!covered);
                } else if s < -0.75 {
                    outside += 1;
                    wrong += usize::from(covered);
                }
                if !covered || s < 1.0 {
                    continue;
                }
                // The pixel's point now, and where it was at t0 (the quad translates
                // rigidly: every corner has bend weight 1).
                let now = unproject(&camera, x, y, depth[i]);
                let before = now - d1 + d0;
                let (nx, ny) = pixels(clip(&camera, now));
                let (px, py) = pixels(clip(&camera, before));
                let want = (nx - px, ny - py);
                let got = surfaces[i].motion.as_dvec2();
                let err = (got.x - want.0).hypot(got.y - want.1);
                checked += 1;
                if err > 0.05 + 0.01 * want.0.hypot(want.1) {
                    off += 1;
                    worst = worst.max(err);
                }
            }
        }
        eprintln!(
            "{path:?}: {inside} pixels inside, {outside} outside, {wrong} wrong; motion: {checked} checked, {off} off (worst {worst:.3} px)"
        );
        assert!(inside > 1000 && outside > 1000, "{inside} / {outside}");
        assert_eq!(wrong, 0, "{path:?}: coverage differs from the reference");
        assert!(checked > 1000 && off == 0, "{path:?}: {off} of {checked}");
        depths.push(depth);

        // Without wind: no motion at all.
        let (still, _) = swaying_quad(None);
        let mut r = common::renderer(W, H, true);
        let prepared = r.prepare(&still).unwrap();
        frame.time = t0;
        r.render(&prepared, &frame, path).unwrap();
        frame.time = t1;
        r.render(&prepared, &frame, path).unwrap();
        let surfaces = r.inspect().read_gbuffer().unwrap();
        assert!(surfaces.iter().all(|s| s.motion == Vec2::ZERO));
    }
    assert!(
        depths.windows(2).all(|d| d[0] == d[1]),
        "the paths' depths differ"
    );
}

/// The CPU reference itself: no sway at the root, the full amplitude's bend at the bend
/// height and above, horizontal only, periodic in the main frequency's period when the
/// second term's is commensurate (10 periods of 2.3 f = 23 of f).
#[test]
fn wind_reference_bends_with_height() {
    let w = Wind {
        direction: Vec2::new(3.0, 4.0),
        amplitude: 0.5,
        frequency: 1.0,
        height: 2.0,
    };
    let t = Vec3::new(1.0, 0.0, 2.0);
    for time in [0.0_f32, 0.3, 1.7] {
        assert_eq!(
            w.displacement(t, Vec3::new(0.1, 0.0, 0.2), time),
            Vec3::ZERO
        );
        let top = w.displacement(t, Vec3::new(0.0, 2.0, 0.0), time);
        let above = w.displacement(t, Vec3::new(0.0, 5.0, 0.0), time);
        let half = w.displacement(t, Vec3::new(0.0, 1.0, 0.0), time);
        assert_eq!(top, above);
        assert_eq!(top.y, 0.0);
        assert!((half - top * 0.25).length() < 1e-6);
        // Along (3, 4)/5, at most 1.3 amplitudes.
        assert!((top.x * 4.0 - top.z * 3.0).abs() < 1e-6);
        assert!(top.length() <= 0.5 * 1.3 + 1e-6);
    }
    let a = w.displacement(t, Vec3::Y * 2.0, 0.25);
    let b = w.displacement(t, Vec3::Y * 2.0, 10.25);
    assert!((a - b).length() < 1e-4, "{a} {b}");
    // A sway the shaders would turn into infinite positions is an error naming the field.
    assert!(w.validate().is_ok());
    for bad in [
        Wind {
            frequency: f32::MAX,
            ..w
        },
        Wind {
            amplitude: 1e30,
            ..w
        },
    ] {
        let e = bad.validate().unwrap_err().to_string();
        assert!(e.contains("wind."), "{e}");
    }
}
