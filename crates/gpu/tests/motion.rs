//! Motion vectors: the G-buffer's motion (pixels, current minus previous, `+y` down) of a
//! still scene under a moving camera equals an f64 reprojection of each pixel's depth
//! through the two cameras, on both paths; a scene's first frame has none.

mod common;

use glam::{DMat4, DVec3, DVec4, Vec3};
use gpu::demo::{self, DemoOptions, DemoScene};
use gpu::{Camera, RenderPath};

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
        let still = first.read_gbuffer().unwrap();
        assert!(
            still.iter().all(|s| s.motion == glam::Vec2::ZERO),
            "{path:?}: first frame"
        );

        // Frame 1, then frame 2 with the camera moved sideways, forwards and turned.
        let before = frame.camera;
        r.render(&prepared, &frame, path).unwrap();
        let mut moved = frame.clone();
        moved.camera.position += Vec3::new(0.6, 0.1, -0.4);
        moved.camera.target += Vec3::new(-1.5, 0.3, 0.0);
        r.render(&prepared, &moved, path).unwrap();
        let surfaces = r.read_gbuffer().unwrap();
        let depth = r.read_depth().unwrap();
        let (mut checked, mut off, mut moving) = (0, 0, 0);
        let mut worst: f64 = 0.0;
        for y in 0..H {
            for x in 0..W {
                let i = (y * W + x) as usize;
                if depth[i] <= 0.0 {
                    continue;
                }
                let world = unproject(&moved.camera, x, y, depth[i]);
                let (nx, ny) = pixels(clip(&moved.camera, world));
                let (px, py) = pixels(clip(&before, world));
                let want = (nx - px, ny - py);
                let got = surfaces[i].motion.as_dvec2();
                let err = (got.x - want.0).hypot(got.y - want.1);
                let tolerance = 0.05 + 0.01 * want.0.hypot(want.1);
                checked += 1;
                moving += usize::from(want.0.hypot(want.1) > 1.0);
                if err > tolerance {
                    off += 1;
                    worst = worst.max(err);
                }
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
