//! The sun's stable cascaded shadow maps on the GPU (KZ2's stability): rotating the camera
//! in place, moving it by a fraction of a texel, or by several texels shifts each rendered
//! map by whole texels (or not at all) and leaves the texels of the same world place equal
//! (depth offset by the snapped light-space depth), up to f32 rounding at a few edges.

mod common;

use glam::{DVec3, DVec4, Quat, Vec3};
use gpu::demo::{self, DemoOptions, DemoScene};
use gpu::{Camera, FrameInput, RenderPath, Renderer, RendererConfig, ShadowConfig};
use testkit::device::ctx;

const RES: u32 = 512;

struct Maps {
    texels: Vec<Vec<f32>>,
    /// Per cascade: clip x, y, z of the world origin (the maps' offsets).
    origin_clip: Vec<DVec3>,
    texel_size: Vec<f64>,
}

fn render(r: &mut Renderer, prepared: &gpu::PreparedScene, frame: &FrameInput) -> Maps {
    r.render(prepared, frame, RenderPath::Deferred).unwrap();
    let c = r.shadow_cascades().unwrap();
    Maps {
        texels: r.read_shadow_maps().unwrap(),
        origin_clip: c
            .cascades()
            .iter()
            .map(|k| (k.world_to_clip * DVec4::new(0.0, 0.0, 0.0, 1.0)).truncate())
            .collect(),
        texel_size: c.cascades().iter().map(|k| k.texel_size).collect(),
    }
}

/// Compares cascade `i` of `b` against `a` over their overlap: returns (whole-texel shift,
/// texels compared, texels that differ).
fn compare(a: &Maps, b: &Maps, i: usize) -> ((i64, i64), usize, usize) {
    let half = f64::from(RES) * 0.5;
    let dx = (b.origin_clip[i].x - a.origin_clip[i].x) * half;
    let dy = -(b.origin_clip[i].y - a.origin_clip[i].y) * half;
    let dz = b.origin_clip[i].z - a.origin_clip[i].z;
    // Whole texels (up to the f64 matrices' rounding).
    assert!(
        (dx - dx.round()).abs() < 1e-6 && (dy - dy.round()).abs() < 1e-6,
        "cascade {i}: shift ({dx}, {dy})"
    );
    assert!(
        (a.texel_size[i] - b.texel_size[i]).abs() < 1e-12,
        "cascade {i}: texel size changed"
    );
    let (sx, sy) = (dx.round() as i64, dy.round() as i64);
    let (mut compared, mut differ) = (0, 0);
    let n = i64::from(RES);
    for y in 0..n {
        for x in 0..n {
            // Texel (x, y) of `a` is texel (x + sx, y + sy) of `b`.
            let (bx, by) = (x + sx, y + sy);
            if !(0..n).contains(&bx) || !(0..n).contains(&by) {
                continue;
            }
            let da = f64::from(a.texels[i][(y * n + x) as usize]);
            let db = f64::from(b.texels[i][(by * n + bx) as usize]);
            compared += 1;
            let same = if da >= 1.0 || db >= 1.0 {
                da == db
            } else {
                (db - (da + dz)).abs() <= 1e-5
            };
            differ += usize::from(!same);
        }
    }
    ((sx, sy), compared, differ)
}

#[test]
fn shadow_maps_move_by_whole_texels_and_keep_their_texels() {
    let (scene, frame) = demo::build(&DemoOptions {
        scene: DemoScene::Forest,
        seed: 7,
        density: 0.25,
    });
    let c = ctx();
    let config = ShadowConfig {
        cascades: 2,
        resolution: RES,
        far: 40.0,
        ..ShadowConfig::default()
    };
    let mut r = Renderer::new(
        &c.device,
        &c.queue,
        RendererConfig {
            width: 160,
            height: 90,
            shadows: Some(config),
            ..RendererConfig::default()
        },
    )
    .unwrap();
    let prepared = r.prepare(&scene).unwrap();
    let base = render(&mut r, &prepared, &frame);
    // Something casts into every cascade.
    for (i, t) in base.texels.iter().enumerate() {
        let cast = t.iter().filter(|&&d| d < 1.0).count();
        assert!(cast * 20 > t.len(), "cascade {i}: {cast} texels cast");
    }
    let texel0 = base.texel_size[0] as f32;
    let turned = |deg: f32| {
        let cam = frame.camera;
        let q = Quat::from_rotation_y(deg.to_radians());
        Camera {
            target: cam.position + q * (cam.target - cam.position),
            ..cam
        }
    };
    let moved = |d: Vec3| Camera {
        position: frame.camera.position + d,
        target: frame.camera.target + d,
        ..frame.camera
    };
    let cases = [
        ("turned 25° in place", turned(25.0)),
        ("moved 0.3 texel", moved(Vec3::new(0.3 * texel0, 0.0, 0.0))),
        (
            "moved 7.6 texels",
            moved(Vec3::new(5.3 * texel0, 0.0, -5.4 * texel0)),
        ),
    ];
    let mut shifted = 0;
    for (what, camera) in cases {
        let mut f = frame.clone();
        f.camera = camera;
        let maps = render(&mut r, &prepared, &f);
        for i in 0..base.texels.len() {
            let (shift, compared, differ) = compare(&base, &maps, i);
            eprintln!(
                "{what}, cascade {i}: shifted by {shift:?} texels, {differ} of {compared} texels differ"
            );
            shifted += usize::from(shift != (0, 0));
            assert!(
                compared * 2 > (RES * RES) as usize,
                "{what}: overlap {compared}"
            );
            // Coverage is shift-invariant up to f32 rounding of the vertices at edges.
            assert!(
                differ * 1000 <= compared,
                "{what}, cascade {i}: {differ} of {compared} differ"
            );
        }
    }
    assert!(shifted >= 2, "the maps never moved: {shifted}");
}
