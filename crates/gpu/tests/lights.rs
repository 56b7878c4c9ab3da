//! Tiled local lights on testkit's device: the per-tile depth ranges equal
//! `deferred::lights::tile_depth_ranges` of the read-back depth target, the tile lists
//! equal `cull_tiles` on them (up to a tangent light flipping with the device's rounding),
//! lighting from the lists gives the same image as every light at every pixel, and the lit
//! image equals an f64 evaluation of the lighting on the read-back G-buffer.

mod common;

use deferred::lights::{MAX_LIGHTS_PER_TILE, cull_tiles, tile_depth_ranges};
use deferred::{DepthMode, Perspective};
use demo::{DemoOptions, DemoScene};
use gpu::config::LightPaths;
use gpu::inspect::local_light_rows;
use gpu::{FrameInput, PointLight, RenderPath, Renderer, RendererConfig, Scene};

const W: u32 = 333;
const H: u32 = 190;

/// The forest, lighter, with 300 point and spot lights around the camera's target.
fn lit_forest() -> (Scene, FrameInput) {
    let (scene, mut frame) = demo::build(&DemoOptions {
        scene: DemoScene::Forest,
        seed: 7,
        density: 0.25,
    });
    frame.lighting.sun_color *= 0.2;
    let target = frame.camera.target;
    demo::scatter_lights(&mut frame.lighting, target, 25.0, 300, 3);
    (scene, frame)
}

fn renderer(light_paths: LightPaths, subgroups: bool) -> Renderer {
    common::renderer_with({
        let mut rc = RendererConfig::sized(W, H);
        rc.geometry.subgroups = subgroups;
        rc.lighting.light_paths = light_paths;
        rc.lighting.shadows = common::test_shadows();
        rc
    })
}

#[test]
fn light_tiles_equal_the_cpu_twin_on_the_depth_target() {
    let (scene, frame) = lit_forest();
    // Pass 1 with subgroups (where the device has them) and with workgroup atomics alone.
    for subgroups in testkit::device::subgroup_variants()
        .iter()
        .map(|f| f.contains(&"subgroups"))
    {
        light_tiles_equal_the_twin(&scene, &frame, subgroups);
    }
}

fn light_tiles_equal_the_twin(scene: &Scene, frame: &FrameInput, subgroups: bool) {
    let mut r = renderer(LightPaths::Tiled, subgroups);
    let prepared = r.prepare(scene).unwrap();
    // The compute laydown's frame too: its depth comes from the laydown's unpack.
    let mut compute = common::renderer_with({
        let mut rc = RendererConfig::sized(W, H);
        rc.geometry.subgroups = subgroups;
        rc.geometry.laydown = gpu::Laydown::Compute;
        rc.lighting.light_paths = LightPaths::Tiled;
        rc.lighting.shadows = common::test_shadows();
        rc
    });
    assert_eq!(compute.laydown(), gpu::Laydown::Compute);
    let compute_prepared = compute.prepare(scene).unwrap();
    for (in_compute, path) in [
        (false, RenderPath::Deferred),
        (true, RenderPath::Deferred),
        (false, RenderPath::Baseline),
    ] {
        let (r, prepared) = if in_compute {
            (&mut compute, &compute_prepared)
        } else {
            (&mut r, &prepared)
        };
        r.render(prepared, frame, path).unwrap();
        let tiles = r.inspect().read_light_tiles().unwrap();
        let depth = r.inspect().read_depth().unwrap();
        // Pass 1: exactly the CPU's reduction.
        let mut cpu_depths = vec![deferred::DeferredTileDepth::default(); tiles.depths.len()];
        tile_depth_ranges(&depth, W, H, DepthMode::Reversed, &mut cpu_depths).unwrap();
        assert_eq!(tiles.depths, cpu_depths, "{path:?}: tile depth ranges");
        // Pass 2: the CPU twin on the same tiles and lights.
        let lights = local_light_rows(&frame.lighting, &frame.camera);
        // Every light is tiled, in order (the renderer keeps a spot's shadow-map slot in
        // the flags' bits 8-15).
        let strip = |l: &deferred::DeferredLight| deferred::DeferredLight {
            flags: l.flags & 0xff,
            ..*l
        };
        assert_eq!(tiles.lights.iter().map(strip).collect::<Vec<_>>(), lights);
        let proj = Perspective::try_new(
            frame.camera.fov_y,
            W as f32 / H as f32,
            frame.camera.near,
            None,
            DepthMode::Reversed,
        )
        .unwrap()
        .gpu(glam::Vec2::new(W as f32, H as f32));
        let n = cpu_depths.len();
        let m = MAX_LIGHTS_PER_TILE as usize;
        let mut counts = vec![0; n];
        let mut indices = vec![0; n * m];
        let stats = cull_tiles(&proj, &cpu_depths, &lights, &mut counts, &mut indices).unwrap();
        let mut differ = 0;
        for t in 0..n {
            let cpu: std::collections::BTreeSet<u32> = indices[t * m..t * m + counts[t] as usize]
                .iter()
                .copied()
                .collect();
            let gpu: Vec<u32> = tiles.indices[t * m..t * m + tiles.counts[t] as usize].to_vec();
            assert!(
                gpu.windows(2).all(|w| w[0] < w[1]),
                "tile {t}: not ascending"
            );
            let gpu: std::collections::BTreeSet<u32> = gpu.into_iter().collect();
            differ += cpu.symmetric_difference(&gpu).count();
        }
        eprintln!(
            "{path:?} ({:?} laydown), subgroups {subgroups}: {n} tiles, {} with geometry, {} lights, {} pairs, {differ} decisions differ",
            r.laydown(),
            stats.tiles_with_geometry,
            lights.len(),
            stats.pairs
        );
        assert!(stats.pairs > 500, "{stats:?}");
        assert!(differ * 10_000 <= n * lights.len(), "{differ}");
        assert_eq!(tiles.stats.tiles_with_geometry, stats.tiles_with_geometry);
        assert_eq!(tiles.stats.overflowed_tiles, stats.overflowed_tiles);
    }
}

/// Culling drops only lights that light no pixel of the tile: the image from the tile lists
/// equals the image with every light tested at every pixel, on both paths.
#[test]
fn tiled_lighting_equals_every_light_at_every_pixel() {
    let (scene, frame) = lit_forest();
    let mut tiled = renderer(LightPaths::Tiled, true);
    let mut all = renderer(LightPaths::EveryPixel, true);
    let pt = tiled.prepare(&scene).unwrap();
    let pa = all.prepare(&scene).unwrap();
    let mut dark = frame.clone();
    dark.lighting.point_lights.clear();
    dark.lighting.spot_lights.clear();
    for path in [RenderPath::Deferred, RenderPath::Baseline] {
        tiled.render(&pt, &frame, path).unwrap();
        let a = tiled.read_output().unwrap();
        all.render(&pa, &frame, path).unwrap();
        let b = all.read_output().unwrap();
        let differ = common::differing_pixels(&a, &b);
        assert_eq!(differ, 0, "{path:?}: {differ} pixels differ");
        // The lights do light the frame.
        tiled.render(&pt, &dark, path).unwrap();
        let unlit = tiled.read_output().unwrap();
        let lit = common::differing_pixels(&a, &unlit);
        eprintln!(
            "{path:?}: {lit} of {} pixels lit by local lights",
            a.pixels.len()
        );
        assert!(lit * 10 > a.pixels.len(), "{lit}");
    }
}

/// KZ2's stencil light volumes light what the tiles light: every light as a volume, and
/// KZ2's classification (here with a light holding the eye, drawn from inside, and one
/// large enough for the volume path), give the tiled image on both frame paths, within
/// 1 / 255 per channel on at most 0.5% of the pixels (the volumes' sum is added in another
/// order; their f32 accumulation rounds once more). Some lights have no specular term, so
/// the volumes draw every permutation: with and without specular, with and without a spot
/// shadow map.
#[test]
fn stencil_volumes_give_the_tiled_image() {
    use glam::Vec3;
    let (scene, mut frame) = lit_forest();
    for (i, p) in frame.lighting.point_lights.iter_mut().enumerate() {
        p.specular = i % 2 == 1;
    }
    // Shadowed spots are every other one: both kinds with and without specular.
    for (i, s) in frame.lighting.spot_lights.iter_mut().enumerate() {
        s.specular = i % 4 >= 2;
    }
    let eye = frame.camera.position;
    let target = frame.camera.target;
    frame.lighting.point_lights.push(PointLight {
        position: eye + Vec3::new(0.4, -0.3, 0.0),
        color: Vec3::new(0.9, 0.6, 0.3),
        radius: 8.0,
        specular: true,
    });
    frame.lighting.point_lights.push(PointLight {
        position: eye.lerp(target, 0.5) + Vec3::Y,
        color: Vec3::new(0.3, 0.5, 0.9),
        radius: 14.0,
        specular: true,
    });
    let total = (frame.lighting.point_lights.len() + frame.lighting.spot_lights.len()) as u32;
    let mut tiled = renderer(LightPaths::Tiled, true);
    let pt = tiled.prepare(&scene).unwrap();
    for paths in [LightPaths::Volumes, LightPaths::Classified] {
        let mut r = renderer(paths, true);
        let pr = r.prepare(&scene).unwrap();
        for path in [RenderPath::Deferred, RenderPath::Baseline] {
            tiled.render(&pt, &frame, path).unwrap();
            let a = tiled.read_output().unwrap();
            r.render(&pr, &frame, path).unwrap();
            let b = r.read_output().unwrap();
            let counts = r.inspect().light_path_counts();
            match paths {
                LightPaths::Volumes => {
                    assert_eq!(counts.tiled, 0);
                    // Lights wholly behind the near plane are not drawn.
                    assert!(counts.volumes <= total && counts.volumes > total / 2);
                    assert!(counts.volumes_from_inside >= 1, "{counts:?}");
                    assert!(counts.volumes_from_inside < total, "{counts:?}");
                }
                _ => {
                    assert!(counts.volumes >= 2, "{counts:?}");
                    assert!(counts.volumes_from_inside >= 1, "{counts:?}");
                    assert!(counts.tiled >= total / 2, "{counts:?}");
                }
            }
            let worst = a
                .pixels
                .iter()
                .zip(&b.pixels)
                .map(|(p, q)| (0..3).map(|k| p[k].abs_diff(q[k])).max().unwrap_or(0))
                .max()
                .unwrap_or(0);
            let differ = common::differing_pixels(&a, &b);
            eprintln!(
                "{paths:?} {path:?}: {counts:?}; {differ} of {} pixels differ, worst {worst}",
                a.pixels.len()
            );
            assert!(
                worst <= 1,
                "{paths:?} {path:?}: worst channel difference {worst}"
            );
            assert!(
                differ * 200 <= a.pixels.len(),
                "{paths:?} {path:?}: {differ}"
            );
        }
    }
}

/// The lit image against an f64 CPU evaluation of the same lighting (sun, ambient, every
/// point and spot light, ACES, sRGB) on the G-buffer and depth read back: every channel
/// within 2 / 255, all but 0.1% within 1 / 255 (lavapipe: worst 1, none over 1).
#[test]
fn lit_image_equals_an_f64_reference() {
    let (scene, frame) = reference_forest();
    let (worst, over1, pixels) = against_f64_reference(&scene, &frame, LightPaths::Tiled);
    assert!(worst <= 2, "worst {worst}");
    assert!(over1 * 1000 <= pixels * 3, "{over1}");
}

/// KZ2's no-specular lights: with every other light (points and spots) diffuse alone, the
/// image equals the f64 reference that leaves out those lights' specular term, on the
/// tiles (the compute lighting's branch) and as stencil volumes (the pipelines compiled
/// without the term), within the tolerances above; and against the image with every
/// light specular, no channel is brighter by more than 1 / 255 (rounding), and the pixels
/// the reference says lose at least 3 / 255 are darker.
#[test]
fn no_specular_lights_equal_the_f64_reference_without_their_specular_term() {
    let (scene, specular) = reference_forest();
    let mut frame = specular.clone();
    let l = &mut frame.lighting;
    for (i, p) in l.point_lights.iter_mut().enumerate() {
        p.specular = i % 2 == 1;
    }
    for (i, s) in l.spot_lights.iter_mut().enumerate() {
        s.specular = i % 2 == 1;
    }
    let off = l.point_lights.iter().filter(|p| !p.specular).count()
        + l.spot_lights.iter().filter(|s| !s.specular).count();
    assert!(off >= 10, "{off}");
    for paths in [LightPaths::Tiled, LightPaths::Volumes] {
        let (worst, over1, pixels) = against_f64_reference(&scene, &frame, paths);
        eprintln!("{paths:?}: no-specular lights vs f64: worst {worst}, {over1} over 1");
        assert!(worst <= 2, "{paths:?}: worst {worst}");
        assert!(over1 * 1000 <= pixels * 3, "{paths:?}: {over1}");
    }
    // Against the image with every light specular: the lost term is non-negative.
    let mut r = reference_renderer(LightPaths::Tiled);
    let prepared = r.prepare(&scene).unwrap();
    r.render(&prepared, &specular, RenderPath::Deferred)
        .unwrap();
    let with = r.read_output().unwrap();
    let want_with = f64_reference(&r, &specular);
    r.render(&prepared, &frame, RenderPath::Deferred).unwrap();
    let without = r.read_output().unwrap();
    let want_without = f64_reference(&r, &frame);
    let (mut brighter, mut expected, mut darker) = (0, 0, 0);
    for (i, (a, b)) in with.pixels.iter().zip(&without.pixels).enumerate() {
        // The reference's own loss at this pixel, in 1 / 255 steps.
        let loss = (0..3)
            .map(|k| want_with[i][k] - want_without[i][k])
            .max()
            .unwrap_or(0);
        assert!(
            (0..3).all(|k| want_with[i][k] >= want_without[i][k]),
            "reference pixel {i}"
        );
        brighter += usize::from((0..3).any(|k| b[k] > a[k].saturating_add(1)));
        if loss >= 3 {
            expected += 1;
            darker += usize::from((0..3).any(|k| b[k] < a[k]));
        }
    }
    eprintln!(
        "no specular: {brighter} pixels brighter by over 1, {darker} of {expected} the reference darkens by 3+ are darker"
    );
    assert_eq!(brighter, 0);
    assert!(expected > 100, "{expected}");
    assert_eq!(darker, expected);
}

/// The forest with 40 lights close to the camera's target.
fn reference_forest() -> (Scene, FrameInput) {
    let (scene, mut frame) = demo::build(&DemoOptions {
        scene: DemoScene::Forest,
        seed: 7,
        density: 0.25,
    });
    let target = frame.camera.target;
    demo::scatter_lights(&mut frame.lighting, target, 12.0, 40, 5);
    (scene, frame)
}

/// Without the sun's and the spots' shadow maps (their tests are tests/shadows.rs): the
/// reference evaluates the lighting terms alone.
fn reference_renderer(light_paths: LightPaths) -> Renderer {
    common::renderer_with({
        let mut rc = RendererConfig::sized(W, H);
        rc.lighting.shadows = None;
        rc.lighting.spot_shadows = None;
        rc.lighting.light_paths = light_paths;
        rc
    })
}

/// Renders `frame` with `light_paths` and compares it with [`f64_reference`]: the worst
/// channel difference, the channels off by more than 1, and the pixel count.
fn against_f64_reference(
    scene: &Scene,
    frame: &FrameInput,
    light_paths: LightPaths,
) -> (i32, usize, usize) {
    let mut r = reference_renderer(light_paths);
    let prepared = r.prepare(scene).unwrap();
    r.render(&prepared, frame, RenderPath::Deferred).unwrap();
    let image = r.read_output().unwrap();
    let want = f64_reference(&r, frame);
    let (mut over1, mut worst) = (0usize, 0i32);
    for (got, want) in image.pixels.iter().zip(&want) {
        for (k, w) in want.iter().enumerate() {
            let e = (i32::from(got[k]) - w).abs();
            worst = worst.max(e);
            over1 += usize::from(e > 1);
        }
    }
    eprintln!(
        "{light_paths:?}: lit image vs f64: worst {worst} / 255, {over1} channels off by more than 1"
    );
    (worst, over1, image.pixels.len())
}

/// An f64 CPU evaluation of `frame`'s lighting (sun, the G-buffer's ambient, every point and spot light,
/// each light's specular term only where it has one, ACES, sRGB) on the G-buffer and depth
/// of `r`'s last frame: per pixel, RGB in 1 / 255 steps.
fn f64_reference(r: &Renderer, frame: &FrameInput) -> Vec<[i32; 3]> {
    use glam::{DMat4, DVec3, DVec4};
    let surfaces = r.inspect().read_gbuffer().unwrap();
    let depth = r.inspect().read_depth().unwrap();
    let cam = &frame.camera;
    let aspect = f64::from(W) / f64::from(H);
    let view = DMat4::look_at_rh(
        DVec3::ZERO,
        (cam.target - cam.position).as_dvec3(),
        cam.up.as_dvec3(),
    );
    let proj =
        DMat4::perspective_infinite_reverse_rh(f64::from(cam.fov_y), aspect, f64::from(cam.near));
    let inv = (proj * view).inverse();
    let l = &frame.lighting;
    let sun = l.sun_direction.as_dvec3().normalize();
    // Lights camera-relative (dot products do not care for the view rotation).
    struct Local {
        p: DVec3,
        range: f64,
        dir: Option<(DVec3, f64)>,
        color: DVec3,
        specular: bool,
    }
    let at = |p: glam::Vec3| (p - cam.position).as_dvec3();
    let mut lights: Vec<Local> = l
        .point_lights
        .iter()
        .map(|p| Local {
            p: at(p.position),
            range: f64::from(p.radius),
            dir: None,
            color: p.color.as_dvec3(),
            specular: p.specular,
        })
        .collect();
    lights.extend(l.spot_lights.iter().map(|s| Local {
        p: at(s.position),
        range: f64::from(s.radius),
        dir: Some((
            s.direction.as_dvec3().normalize(),
            f64::from(s.half_angle.cos()),
        )),
        color: s.color.as_dvec3(),
        specular: s.specular,
    }));
    // GGX times Smith times n.l, and Fresnel in the metallic workflow:
    // mix(specular · F(0.04), F(albedo), metallic) with Schlick's F.
    let spec = |n: DVec3, v: DVec3, l: DVec3, rough: f64, fresnel: &dyn Fn(f64) -> DVec3| {
        let h = (v + l).normalize();
        let nh = n.dot(h).max(0.0);
        let nl = n.dot(l).max(0.0);
        let nv = n.dot(v).max(1e-4);
        let a = (rough * rough).max(0.02);
        let a2 = a * a;
        let dd = nh * nh * (a2 - 1.0) + 1.0;
        let ndf = a2 / (std::f64::consts::PI * dd * dd);
        let k = a * 0.5;
        let vis = 1.0 / ((nl * (1.0 - k) + k) * (nv * (1.0 - k) + k) * 4.0);
        fresnel((1.0 - v.dot(h).max(0.0)).powi(5)) * (ndf * vis * nl)
    };
    let smoothstep = |e0: f64, e1: f64, x: f64| {
        let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
        t * t * (3.0 - 2.0 * t)
    };
    let tonemap =
        |x: f64| ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0);
    let srgb = |c: f64| {
        if c <= 0.0031308 {
            c * 12.92
        } else {
            1.055 * c.powf(1.0 / 2.4) - 0.055
        }
    };
    let mut out = Vec::with_capacity((W * H) as usize);
    for y in 0..H {
        for x in 0..W {
            let i = (y * W + x) as usize;
            let d = depth[i];
            let mut color = l.sky.as_dvec3();
            if d > 0.0 {
                let s = &surfaces[i];
                let ndc = DVec4::new(
                    (f64::from(x) + 0.5) / f64::from(W) * 2.0 - 1.0,
                    1.0 - (f64::from(y) + 0.5) / f64::from(H) * 2.0,
                    f64::from(d),
                    1.0,
                );
                let q = inv * ndc;
                let p = q.truncate() / q.w;
                let v = (-p).normalize();
                let n = s.normal.as_dvec3();
                let albedo = s.albedo.as_dvec3();
                let metallic = f64::from(s.metallic);
                let diffuse = albedo * (1.0 - metallic) / std::f64::consts::PI;
                let (rough, specular, shadow) = (
                    f64::from(s.roughness),
                    f64::from(s.specular),
                    f64::from(s.sun_shadow),
                );
                let fresnel = |w: f64| {
                    let dielectric = DVec3::splat(specular * (0.04 + 0.96 * w));
                    let metal = albedo + (DVec3::ONE - albedo) * w;
                    dielectric.lerp(metal, metallic)
                };
                // The geometry pass's ambient and emission are in the G-buffer's lighting.
                color = s.lighting.as_dvec3();
                color += l.sun_color.as_dvec3()
                    * (diffuse * n.dot(sun).max(0.0) * shadow
                        + spec(n, v, sun, rough, &fresnel) * shadow);
                for light in &lights {
                    let to = light.p - p;
                    let dist2 = to.length_squared();
                    if dist2 > light.range * light.range || dist2 == 0.0 {
                        continue;
                    }
                    let dist = dist2.sqrt();
                    let ll = to / dist;
                    let r2 = dist2 / (light.range * light.range);
                    let window = (1.0 - r2 * r2).clamp(0.0, 1.0);
                    let mut falloff = window * window / (dist2 + 1.0);
                    if let Some((dir, cos_outer)) = light.dir {
                        let along = (p - light.p).dot(dir);
                        if along < 0.0 || along * along < dist2 * cos_outer * cos_outer {
                            continue;
                        }
                        falloff *= smoothstep(
                            cos_outer,
                            cos_outer + (1.0 - cos_outer) * 0.25,
                            (-ll).dot(dir),
                        );
                    }
                    let specular_term = if light.specular {
                        spec(n, v, ll, rough, &fresnel)
                    } else {
                        DVec3::ZERO
                    };
                    color += light.color * falloff * (diffuse * n.dot(ll).max(0.0) + specular_term);
                }
            }
            out.push(
                [color.x, color.y, color.z].map(|c| (srgb(tonemap(c)) * 255.0).round() as i32),
            );
        }
    }
    out
}

/// KZ2's conditional rendering, emulated: three shadow-casting spots on the volume path,
/// one over the forest floor, one under the ground (its volume wholly behind the terrain:
/// "behind the pillar") and one high in the air pointing up (it lights no surface: "the
/// air in the hallway"). With the emulation, the hidden two's tests count no pixel and
/// the GPU zeroes their maps' caster draws and their volume draws, while the lit one keeps
/// both; the image equals the image without the emulation bit for bit, and the image
/// without the hidden lights at all.
#[test]
fn conditional_volumes_skip_hidden_lights_and_keep_the_image() {
    use glam::Vec3;
    use gpu::SpotLight;
    let (scene, mut frame) = demo::build(&DemoOptions {
        scene: DemoScene::Forest,
        seed: 7,
        density: 0.25,
    });
    frame.lighting.sun_color *= 0.05;
    frame.lighting.ambient *= 0.3;
    let eye = frame.camera.position;
    let target = frame.camera.target;
    let spot = |position: Vec3, direction: Vec3, radius: f32| SpotLight {
        position,
        direction,
        color: Vec3::new(30.0, 24.0, 16.0),
        radius,
        half_angle: 0.7,
        shadow: true,
        specular: true,
    };
    let lit = spot(
        eye.lerp(target, 0.5) + Vec3::new(0.0, 4.0, 0.0),
        Vec3::new(0.1, -1.0, 0.05),
        14.0,
    );
    let buried = spot(target - Vec3::new(0.0, 6.0, 0.0), Vec3::NEG_Y, 5.0);
    let aloft = spot(
        eye.lerp(target, 1.5) + Vec3::new(0.0, 12.0, 0.0),
        Vec3::Y,
        10.0,
    );
    frame.lighting.spot_lights = vec![lit, buried, aloft];
    let make = |conditional_volumes| {
        common::renderer_with({
            let mut rc = RendererConfig::sized(240, 136);
            rc.lighting.shadows = common::test_shadows();
            rc.lighting.light_paths = LightPaths::Volumes;
            rc.lighting.conditional_volumes = conditional_volumes;
            rc
        })
    };
    let mut on = make(true);
    let mut off = make(false);
    let p_on = on.prepare(&scene).unwrap();
    let p_off = off.prepare(&scene).unwrap();
    on.render(&p_on, &frame, RenderPath::Deferred).unwrap();
    let with = on.read_output().unwrap();
    off.render(&p_off, &frame, RenderPath::Deferred).unwrap();
    let without = off.read_output().unwrap();
    let counts = on.inspect().light_path_counts();
    eprintln!(
        "with: {counts:?}; without: {:?}",
        off.inspect().light_path_counts()
    );
    assert_eq!(counts.spot_shadow_maps, 3, "{counts:?}");
    assert_eq!(counts.volumes_tested, 3, "{counts:?}");
    assert_eq!(off.inspect().light_path_counts().volumes_tested, 0);
    let differ = common::differing_pixels(&with, &without);
    assert_eq!(differ, 0, "{differ} pixels differ with the emulation");
    // The GPU's decisions, per spot (matched by their view-space positions).
    let rows = local_light_rows(&frame.lighting, &frame.camera);
    let tested = on.inspect().read_conditional_volumes().unwrap();
    assert_eq!(tested.len(), 3);
    for (i, row) in rows.iter().filter(|r| r.is_spot()).enumerate() {
        let t = tested
            .iter()
            .find(|t| t.light.position == row.position)
            .unwrap_or_else(|| panic!("light {i} not tested"));
        eprintln!("light {i}: {t:?}");
        assert!(t.caster_rows > 0 || i == 2, "light {i}: no casters to skip");
        if i == 0 {
            // Its map, drawn through the indirect arguments, is the directly drawn one (both
            // renderers give the lights the same slots).
            let slot = (t.light.flags >> 8) as usize - 1;
            let map = &on.inspect().read_spot_shadow_maps().unwrap()[slot];
            assert!(map.iter().any(|&d| d < 1.0), "the lit light's map is empty");
            assert!(map == &off.inspect().read_spot_shadow_maps().unwrap()[slot]);
            assert!(t.samples > 0, "lit light {i}: {t:?}");
            assert_eq!(t.volume_instances, 1);
            assert_eq!(t.caster_count, t.caster_rows);
            assert!(t.caster_instances > 0);
        } else {
            assert_eq!(t.samples, 0, "hidden light {i}: {t:?}");
            assert_eq!(t.volume_instances, 0);
            assert_eq!((t.caster_count, t.caster_instances), (0, 0));
        }
    }
    // The hidden lights light nothing: the image without them is the same.
    let mut alone = frame.clone();
    alone.lighting.spot_lights.truncate(1);
    off.render(&p_off, &alone, RenderPath::Deferred).unwrap();
    let only_lit = off.read_output().unwrap();
    assert_eq!(common::differing_pixels(&with, &only_lit), 0);
    // And the lit one does light the frame.
    alone.lighting.spot_lights.clear();
    off.render(&p_off, &alone, RenderPath::Deferred).unwrap();
    let dark = off.read_output().unwrap();
    assert!(common::differing_pixels(&with, &dark) * 50 > with.pixels.len());
}
