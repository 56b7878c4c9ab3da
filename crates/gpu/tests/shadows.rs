//! The sun's stable cascaded shadow maps on the GPU (KZ2's stability): rotating the camera
//! in place, moving it by a fraction of a texel, or by several texels shifts each rendered
//! map by whole texels (or not at all) and leaves the texels of the same world place equal
//! (depth offset by the snapped light-space depth), up to f32 rounding at a few edges; a
//! slice at half resolution (KZ2's per-slice resolution) keeps its own texel grid.

mod common;

use demo::{DemoOptions, DemoScene};
use glam::{DVec3, DVec4, Quat, Vec3};
use gpu::config::ShadowConfig;
use gpu::{Camera, FrameInput, RenderPath, Renderer, RendererConfig};

const RES: u32 = 512;
/// KZ2's per-slice resolution in the stability test: slice 1 at half.
const DIVISOR: [u32; 8] = [1, 2, 1, 1, 1, 1, 1, 1];

struct Maps {
    texels: Vec<Vec<f32>>,
    /// Per cascade: clip x, y, z of the world origin (the maps' offsets).
    origin_clip: Vec<DVec3>,
    texel_size: Vec<f64>,
}

fn render(r: &mut Renderer, prepared: &gpu::PreparedScene, frame: &FrameInput) -> Maps {
    r.render(prepared, frame, RenderPath::Deferred).unwrap();
    let c = r.inspect().shadow_cascades().unwrap();
    Maps {
        texels: r.inspect().read_shadow_maps().unwrap(),
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
    // Slice i's map is its resolution's corner of a RES-wide layer.
    let texels = RES / DIVISOR[i];
    let half = f64::from(texels) * 0.5;
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
    let n = i64::from(texels);
    let stride = i64::from(RES);
    for y in 0..n {
        for x in 0..n {
            // Texel (x, y) of `a` is texel (x + sx, y + sy) of `b`.
            let (bx, by) = (x + sx, y + sy);
            if !(0..n).contains(&bx) || !(0..n).contains(&by) {
                continue;
            }
            let da = f64::from(a.texels[i][(y * stride + x) as usize]);
            let db = f64::from(b.texels[i][(by * stride + bx) as usize]);
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
    let config = ShadowConfig {
        cascades: 2,
        resolution: RES,
        resolution_divisor: DIVISOR,
        far: 40.0,
        ..ShadowConfig::default()
    };
    let mut r = common::renderer_with({
        let mut rc = RendererConfig::sized(160, 90);
        rc.lighting.shadows = Some(config);
        rc
    });
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
        for (i, divisor) in DIVISOR.iter().enumerate().take(base.texels.len()) {
            let (shift, compared, differ) = compare(&base, &maps, i);
            eprintln!(
                "{what}, cascade {i}: shifted by {shift:?} texels, {differ} of {compared} texels differ"
            );
            shifted += usize::from(shift != (0, 0));
            let texels = (RES / divisor) as usize;
            assert!(compared * 2 > texels * texels, "{what}: overlap {compared}");
            // Coverage is shift-invariant up to f32 rounding of the vertices at edges.
            assert!(
                differ * 1000 <= compared,
                "{what}, cascade {i}: {differ} of {compared} differ"
            );
        }
    }
    assert!(shifted >= 2, "the maps never moved: {shifted}");
}

/// KZ2's pre-rendered sun shadow: the G-buffer's sun term is 0 on a good part of the forest
/// floor, and where it is 0 the real-time slices agree (an f64 evaluation of lighting's
/// PCF on the read-back maps gives at most a third lit for nearly all of those pixels);
/// with the bake off the term is 1 everywhere.
#[test]
fn the_baked_sun_term_agrees_with_the_real_time_slices() {
    use glam::DMat4;
    let (scene, frame) = demo::build(&DemoOptions {
        scene: DemoScene::Forest,
        seed: 7,
        density: 0.25,
    });
    let (w, h) = (240u32, 136u32);
    let make = |baked_sun: bool| {
        common::renderer_with({
            let mut rc = RendererConfig::sized(w, h);
            rc.lighting.shadows = common::test_shadows();
            rc.lighting.baked_sun = baked_sun;
            rc
        })
    };
    let mut off = make(false);
    let p = off.prepare(&scene).unwrap();
    off.render(&p, &frame, RenderPath::Deferred).unwrap();
    let depth_off = off.inspect().read_depth().unwrap();
    let surfaces_off = off.inspect().read_gbuffer().unwrap();
    assert!(
        surfaces_off
            .iter()
            .zip(&depth_off)
            .all(|(s, &d)| d <= 0.0 || s.sun_shadow == 1.0)
    );

    let mut r = make(true);
    let prepared = r.prepare(&scene).unwrap();
    r.render(&prepared, &frame, RenderPath::Deferred).unwrap();
    let surfaces = r.inspect().read_gbuffer().unwrap();
    let depth = r.inspect().read_depth().unwrap();
    let maps = r.inspect().read_shadow_maps().unwrap();
    let cascades = r.inspect().shadow_cascades().unwrap().cascades().to_vec();
    let config = common::test_shadows().unwrap();
    let stride = i64::from(config.resolution);
    let cam = frame.camera;
    let aspect = f64::from(w) / f64::from(h);
    let view = DMat4::look_at_rh(
        cam.position.as_dvec3(),
        cam.target.as_dvec3(),
        cam.up.as_dvec3(),
    );
    let proj =
        DMat4::perspective_infinite_reverse_rh(f64::from(cam.fov_y), aspect, f64::from(cam.near));
    let inv = (proj * view).inverse();
    let forward = (cam.target - cam.position).as_dvec3().normalize();
    let (mut geometry, mut baked_dark, mut agree) = (0, 0, 0);
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            if depth[i] <= 0.0 {
                continue;
            }
            geometry += 1;
            let s = &surfaces[i];
            if s.sun_shadow > 0.0 || s.normal.dot(frame.lighting.sun_direction.normalize()) <= 0.0 {
                continue;
            }
            baked_dark += 1;
            let ndc = DVec4::new(
                (f64::from(x) + 0.5) / f64::from(w) * 2.0 - 1.0,
                1.0 - (f64::from(y) + 0.5) / f64::from(h) * 2.0,
                f64::from(depth[i]),
                1.0,
            );
            let q = inv * ndc;
            let world = q.truncate() / q.w;
            let dist = (world - cam.position.as_dvec3()).dot(forward);
            let Some(k) = cascades.iter().position(|c| dist <= c.split[1]) else {
                agree += 1; // beyond the slices: nothing real-time to compare
                continue;
            };
            let c = &cascades[k];
            let pushed = world + s.normal.as_dvec3() * (1.5 * c.texel_size);
            let clip = c.world_to_clip * pushed.extend(1.0);
            let (u, v) = (clip.x * 0.5 + 0.5, 0.5 - clip.y * 0.5);
            // The slice's own resolution, in the corner of its layer.
            let res = f64::from(config.slice_resolution(k));
            let (cx, cy) = ((u * res).floor() as i64, (v * res).floor() as i64);
            let n = res as i64;
            let mut lit = 0;
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let (tx, ty) = ((cx + dx).clamp(0, n - 1), (cy + dy).clamp(0, n - 1));
                    lit += usize::from(clip.z <= f64::from(maps[k][(ty * stride + tx) as usize]));
                }
            }
            agree += usize::from(lit <= 3);
        }
    }
    eprintln!(
        "{geometry} geometry pixels, {baked_dark} facing the sun in full baked shadow, {agree} of them at most a third lit in the slices"
    );
    assert!(baked_dark * 10 > geometry, "{baked_dark} of {geometry}");
    assert!(agree * 100 >= baked_dark * 90, "{agree} of {baked_dark}");
}

/// The slice cache: a still camera re-renders no slice, a camera moving within texels
/// re-renders only slices whose snapped matrix moved, and every frame's image equals the
/// image of a renderer that renders every slice every frame.
#[test]
fn cached_slices_give_the_images_of_slices_rendered_every_frame() {
    let (scene, frame) = demo::build(&DemoOptions {
        scene: DemoScene::Forest,
        seed: 7,
        density: 0.25,
    });
    let make = |cache: bool| {
        common::renderer_with({
            let mut rc = RendererConfig::sized(160, 90);
            rc.lighting.shadows = Some(ShadowConfig {
                cache,
                ..common::test_shadows().unwrap()
            });
            rc
        })
    };
    let (mut cached, mut every) = (make(true), make(false));
    let (pc, pe) = (
        cached.prepare(&scene).unwrap(),
        every.prepare(&scene).unwrap(),
    );
    let slices_drawn = |out: &gpu::FrameOutput| {
        out.gpu
            .iter()
            .filter(|t| t.label.starts_with("sun shadow"))
            .count()
    };
    let timestamps = !cached
        .render(&pc, &frame, RenderPath::Deferred)
        .unwrap()
        .gpu
        .is_empty();
    let mut path = vec![frame.camera, frame.camera];
    for k in 1..6 {
        let d = Vec3::new(0.02 * k as f32, 0.0, -0.05 * k as f32);
        path.push(Camera {
            position: frame.camera.position + d,
            target: frame.camera.target + d,
            ..frame.camera
        });
    }
    let mut skipped = 0;
    for (k, camera) in path.iter().enumerate() {
        let mut f = frame.clone();
        f.camera = *camera;
        let out = cached.render(&pc, &f, RenderPath::Deferred).unwrap();
        every.render(&pe, &f, RenderPath::Deferred).unwrap();
        let (a, b) = (cached.read_output().unwrap(), every.read_output().unwrap());
        let differ = common::differing_pixels(&a, &b);
        assert_eq!(differ, 0, "frame {k}: {differ} pixels differ");
        if timestamps {
            let drawn = slices_drawn(&out);
            skipped += 4 - drawn;
            if k < 2 {
                assert_eq!(
                    drawn, 0,
                    "frame {k}: a still camera re-rendered {drawn} slices"
                );
            }
        }
    }
    if timestamps {
        eprintln!("{skipped} of {} slice passes skipped", 4 * path.len());
        assert!(skipped > 8, "{skipped}");
    }
}

/// KZ2's shadowed spot lights: lamps over the forest floor with `shadow` on get maps
/// (largest on screen first), and their light only ever loses to the maps: no pixel is
/// brighter than with the same lamps unshadowed, and the leaves and trunks under them cast
/// shadows (some pixels darker). Faded out (every lamp below the fade's coverage), no map
/// is drawn and the image is the unshadowed one exactly.
#[test]
fn shadowed_spots_only_darken_and_fade_out() {
    use gpu::SpotLight;
    use gpu::config::SpotShadowConfig;
    let (scene, mut frame) = demo::build(&DemoOptions {
        scene: DemoScene::Forest,
        seed: 7,
        density: 0.25,
    });
    frame.lighting.sun_color *= 0.05;
    frame.lighting.ambient *= 0.3;
    let eye = frame.camera.position;
    let target = frame.camera.target;
    for (k, t) in [0.3f32, 0.5, 0.7].into_iter().enumerate() {
        let at = eye.lerp(target, t) + Vec3::new(k as f32 - 1.0, 4.0, 0.0);
        frame.lighting.spot_lights.push(SpotLight {
            position: at,
            direction: Vec3::new(0.1, -1.0, 0.05),
            color: Vec3::new(30.0, 24.0, 16.0),
            radius: 14.0,
            half_angle: 0.7,
            shadow: true,
            specular: true,
        });
    }
    let mut unshadowed = frame.clone();
    for s in &mut unshadowed.lighting.spot_lights {
        s.shadow = false;
    }
    let make = |spot_shadows| {
        common::renderer_with({
            let mut rc = RendererConfig::sized(240, 136);
            rc.lighting.shadows = common::test_shadows();
            rc.lighting.spot_shadows = spot_shadows;
            rc
        })
    };
    let mut r = make(Some(SpotShadowConfig::default()));
    let p = r.prepare(&scene).unwrap();
    r.render(&p, &unshadowed, RenderPath::Deferred).unwrap();
    let plain = r.read_output().unwrap();
    assert_eq!(r.inspect().light_path_counts().spot_shadow_maps, 0);
    r.render(&p, &frame, RenderPath::Deferred).unwrap();
    let shadowed = r.read_output().unwrap();
    assert_eq!(r.inspect().light_path_counts().spot_shadow_maps, 3);
    let (mut darker, mut brighter) = (0, 0);
    for (a, b) in shadowed.pixels.iter().zip(&plain.pixels) {
        darker += usize::from((0..3).any(|k| a[k] < b[k]));
        brighter += usize::from((0..3).any(|k| a[k] > b[k]));
    }
    eprintln!(
        "{darker} pixels darker, {brighter} brighter of {}",
        plain.pixels.len()
    );
    assert_eq!(brighter, 0);
    assert!(darker * 50 > plain.pixels.len(), "{darker}");
    // KZ2's fade: below the fade's coverage, no map and the unshadowed shader.
    let mut faded = make(Some(SpotShadowConfig {
        // Coverage never passes 1.
        fade: deferred::lights::ShadowFade {
            full: 2.0,
            zero: 1.5,
        },
        ..SpotShadowConfig::default()
    }));
    let pf = faded.prepare(&scene).unwrap();
    faded.render(&pf, &frame, RenderPath::Deferred).unwrap();
    assert_eq!(faded.inspect().light_path_counts().spot_shadow_maps, 0);
    assert_eq!(
        common::differing_pixels(&faded.read_output().unwrap(), &plain),
        0
    );
}

/// Caster culling per shadow view (chunks of 64 Morton-ordered instances tested against
/// each slice's and each spot map's clip volume) leaves every map as drawing every caster
/// does: the sun's maps bit for bit, and the image (which reads the spot maps too).
#[test]
fn culling_casters_per_shadow_view_changes_no_texel() {
    let (scene, mut frame) = demo::build(&DemoOptions {
        scene: DemoScene::Forest,
        seed: 7,
        density: 0.25,
    });
    let target = frame.camera.target;
    demo::scatter_lights(&mut frame.lighting, target, 25.0, 120, 3);
    let make = |cull_shadow_casters| {
        common::renderer_with({
            let mut rc = RendererConfig::sized(200, 112);
            rc.lighting.shadows = common::test_shadows();
            rc.lighting.cull_shadow_casters = cull_shadow_casters;
            rc
        })
    };
    let (mut culled, mut every) = (make(true), make(false));
    let (pc, pe) = (
        culled.prepare(&scene).unwrap(),
        every.prepare(&scene).unwrap(),
    );
    culled.render(&pc, &frame, RenderPath::Deferred).unwrap();
    every.render(&pe, &frame, RenderPath::Deferred).unwrap();
    assert!(culled.inspect().light_path_counts().spot_shadow_maps > 0);
    let (a, b) = (
        culled.inspect().read_shadow_maps().unwrap(),
        every.inspect().read_shadow_maps().unwrap(),
    );
    for (k, (x, y)) in a.iter().zip(&b).enumerate() {
        let differ = x.iter().zip(y).filter(|(p, q)| p != q).count();
        assert_eq!(differ, 0, "slice {k}: {differ} texels differ");
    }
    let (ia, ib) = (culled.read_output().unwrap(), every.read_output().unwrap());
    assert_eq!(common::differing_pixels(&ia, &ib), 0);
}
