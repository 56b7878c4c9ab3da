//! HZD's static query in front of the frame (lavapipe in CI): the city drawn from the GPU
//! query's output through reserved slots and indirect draws equals the CPU twin's visible
//! set drawn as planned batches; the deferred image matches the depth-equal baseline on
//! it; occlusion against a HiZ of the previous frame's depth (read back, or reduced on the
//! GPU, which equals `HiZ::build`) leaves the image unchanged (conservative) while it culls;
//! two-pass occlusion leaves it unchanged while the camera moves; bad input to
//! `render_static` is an error.

mod common;

use demo::city::{City, city};
use gpu::glam::{self, Affine3A, Vec3};
use gpu::inspect::diff_metrics;
use gpu::statics::{
    QueryReadback, StaticFrameStats, StaticOcclusion, StaticQuery, StaticView, scene_from_query,
    static_view_desc,
};
use gpu::staticscene;
use gpu::staticscene::ViewDesc;
use gpu::staticscene::{DrawableSetupInstance, HiZ, QueryOptions, QueryOutput, QueryParams};
use gpu::{Batch, Camera, FrameInput, PreparedScene, RenderPath, Renderer, Rgba8Image, Scene};
use testkit::device::ctx;

const W: u32 = 320;
const H: u32 = 180;

fn renderer() -> Renderer {
    renderer_sized(W, H)
}

/// The static frames' renderer: without the baked sun term, which takes a scene's batches
/// only (the city's static instances are placed per frame), so it would differ between a
/// GPU-driven city and the same instances planned as batches, which these tests compare.
fn renderer_sized(width: u32, height: u32) -> Renderer {
    common::renderer_with({
        let mut rc = gpu::RendererConfig::sized(width, height);
        rc.lighting.shadows = common::test_shadows();
        rc.lighting.baked_sun = false;
        rc
    })
}

fn small_city() -> City {
    city(30_000)
}

/// The small city streamed into a query and prepared on a 320x180 renderer.
struct Rig {
    city: City,
    query: StaticQuery,
    cpu: staticscene::Scene,
    r: Renderer,
    prepared: PreparedScene,
}

impl Rig {
    fn new() -> Rig {
        Rig::sized(W, H)
    }

    /// A rig whose renderer draws no sun shadow maps: for the tests that compare what the
    /// camera view draws with a twin of the camera's visible set (the slices' static
    /// casters come from their own shadow views, which see the buildings beside the street
    /// that the camera's set lacks; tests/static_shadows.rs compares those), and for the
    /// occlusion tests, which compare what occlusion draws.
    fn without_sun_shadows(width: u32, height: u32) -> Rig {
        let mut rig = Rig::sized(width, height);
        rig.r = common::renderer_with({
            let mut rc = gpu::RendererConfig::sized(width, height);
            rc.lighting.shadows = None;
            rc.lighting.baked_sun = false;
            rc
        });
        rig.prepared = rig.r.prepare(&rig.city.scene).unwrap();
        rig
    }

    fn sized(width: u32, height: u32) -> Rig {
        let c = ctx();
        let city = small_city();
        let mut query = StaticQuery::new(&c.device, &c.queue).unwrap();
        let cpu = gpu::statics::stream_static_world(
            &c.device,
            &c.queue,
            &mut query,
            &city.world.resources,
            &city.world.groups,
        )
        .unwrap();
        let r = renderer_sized(width, height);
        let prepared = r.prepare(&city.scene).unwrap();
        Rig {
            city,
            query,
            cpu,
            r,
            prepared,
        }
    }

    /// One static frame of `view` from `camera` by `path`: its image and statistics.
    fn frame(
        &mut self,
        view: ViewDesc,
        camera: Camera,
        path: RenderPath,
    ) -> (Rgba8Image, StaticFrameStats) {
        self.frame_with(view, camera, path, StaticOcclusion::Given)
    }

    /// [`Rig::frame`] with the HiZ from `occlusion`.
    fn frame_with(
        &mut self,
        view: ViewDesc,
        camera: Camera,
        path: RenderPath,
        occlusion: StaticOcclusion,
    ) -> (Rgba8Image, StaticFrameStats) {
        let mut view = StaticView {
            query: &mut self.query,
            scene: &mut self.cpu,
            view,
            options: QueryOptions::default(),
            occlusion,
        };
        let input = FrameInput {
            camera,
            ..self.city.frame.clone()
        };
        let out = self
            .r
            .render_static(&self.prepared, &input, path, &mut view)
            .unwrap_or_else(|e| panic!("{e}"));
        let stats = out.statics.expect("a static frame reports its statistics");
        (self.r.read_output().unwrap(), stats)
    }
}

/// The CPU twin's visible instances of `view` as planned batches (world transforms: the
/// snapped origin plus the floating-space transform), on `city`'s meshes and materials.
fn twin_scene(city: &City, cpu: &mut gpu::staticscene::Scene, params: &QueryParams) -> Scene {
    let mut out = QueryOutput::<DrawableSetupInstance>::new();
    cpu.query(params, None, &QueryOptions::default(), &mut out)
        .unwrap();
    let origin = Vec3::new(
        params.origin[0] as f32,
        params.origin[1] as f32,
        params.origin[2] as f32,
    );
    let mut scene = city.scene.clone();
    scene.static_setups.clear();
    for b in &out.batches {
        let setup = city.scene.static_setups[b.setup as usize];
        let first = b.first_instance as usize;
        let instances = out.instances[first..first + b.count as usize]
            .iter()
            .map(|i| Affine3A::from_translation(origin) * i.local_to_floating.to_affine())
            .collect();
        scene.batches.push(Batch {
            mesh: setup.mesh,
            material: setup.material,
            instances,
        });
    }
    scene
}

#[test]
fn the_city_from_the_gpu_query_equals_the_twins_visible_set_drawn_as_batches() {
    let mut rig = Rig::without_sun_shadows(W, H);
    let mut twin = rig.cpu.clone();
    let camera = rig.city.frame.camera;
    // No fade: the first frame would dither every instance in (the planned twin is opaque).
    let desc = still_lod_desc(&camera);
    let params = QueryParams::new(&desc).unwrap();
    let (gpu_image, stats) = rig.frame(desc, camera, RenderPath::Deferred);
    let (city, r) = (&rig.city, &mut rig.r);
    let reference = twin_scene(city, &mut twin, &params);
    let visible = reference.instance_count() - city.scene.instance_count();
    eprintln!(
        "city: {} static instances, {} visible, {} batches, draws {:?}",
        cpu_instances(city),
        visible,
        stats.batches,
        stats.draws
    );
    assert!(visible > 1000, "the street view sees the city");
    assert_eq!(stats.instances as usize, visible);
    assert_eq!(stats.placed as usize, visible);
    assert_eq!((stats.over_capacity, stats.bad_batches), (0, 0));
    assert!(stats.draws[0] > 0 && stats.draws[1] > 0, "both lists drawn");
    let planned = r.prepare(&reference).unwrap();
    r.render(&planned, &city.frame, RenderPath::Deferred)
        .unwrap();
    let twin_image = r.read_output().unwrap();
    let (mean, _) = diff_metrics(&gpu_image, &twin_image, 0.5).unwrap();
    let (_, p99) = diff_metrics(&gpu_image, &twin_image, 0.99).unwrap();
    eprintln!("GPU-driven vs planned twin: mean {mean:.4} / 255, p99 {p99}");
    // Same instances, same meshes: only the transforms' rounding differs (the planned
    // path re-bases them on the scene origin in f32).
    assert!(mean < 0.05 && p99 <= 2, "mean {mean}, p99 {p99}");
    save("static_city_deferred", &gpu_image);
}

fn cpu_instances(city: &City) -> u64 {
    city.scene
        .static_setups
        .iter()
        .map(|s| u64::from(s.capacity))
        .sum()
}

fn save(name: &str, image: &Rgba8Image) {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"));
    image
        .write_png(&dir.join(format!("{name}.png")))
        .unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn the_static_frame_matches_the_depth_equal_baseline_on_every_path() {
    let mut rig = Rig::new();
    let camera = rig.city.frame.camera;
    let mut images = Vec::new();
    // No fade: the two frames would be different steps of the fade-in dither.
    // Seed 004's path too: its static draws take the pull pass's fade variant. (On
    // llvmpipe its image here equals the deferred one to the bit, both differing from the
    // baseline's in the same 1725 pixels: both compute from the pulled triangle what the
    // baseline interpolates as varyings.)
    for path in [
        RenderPath::Deferred,
        RenderPath::Baseline,
        RenderPath::PixelPull,
    ] {
        images.push(rig.frame(still_lod_desc(&camera), camera, path).0);
    }
    for (name, image) in [("deferred", &images[0]), ("pixel pull", &images[2])] {
        let (mean, _) = diff_metrics(image, &images[1], 0.5).unwrap();
        let (_, p99) = diff_metrics(image, &images[1], 0.99).unwrap();
        eprintln!("static city, {name} vs baseline: mean {mean:.3}, p99 {p99}");
        // The frame test's bounds (tests/frame.rs).
        assert!(mean <= 1.0 && p99 <= 24, "{name}: mean {mean}, p99 {p99}");
    }
}

/// Cameras around the street view: moved along the street, turned, raised.
fn cameras(city: &City) -> Vec<Camera> {
    let base = city.frame.camera;
    let fwd = (base.target - base.position).normalize();
    let turn = |c: Camera, a: f32| Camera {
        target: c.position + glam::Quat::from_rotation_y(a) * (c.target - c.position),
        ..c
    };
    let lift = |c: Camera, y: f32| Camera {
        position: c.position + Vec3::Y * y,
        target: c.target + Vec3::Y * y * 0.5,
        ..c
    };
    let walk = |c: Camera, d: f32| Camera {
        position: c.position + fwd * d,
        target: c.target + fwd * d,
        ..c
    };
    vec![
        base,
        walk(base, 2.0),
        turn(walk(base, -3.0), 0.65),
        lift(turn(base, -0.4), 24.0),
        lift(turn(base, 2.5), 60.0),
    ]
}

/// Occlusion against a HiZ of the previous frame's depth (read back, reduced by
/// `HiZ::build`), the camera held still for a frame: for several cameras the image with
/// occlusion equals the image without, the query culls instances doing it, and the GPU's
/// visible set has the CPU twin's size. (With the camera moving, one-pass occlusion
/// against last frame's depth culls what the motion disoccludes: two-pass occlusion's job.)
#[test]
fn occlusion_against_the_previous_frames_depth_is_conservative() {
    let c = ctx();
    let mut rig = Rig::without_sun_shadows(W, H);
    let desc = |camera: &Camera, occlusion: bool| {
        let mut d = static_view_desc(camera, W, H);
        // LODs switch at once: during a fade both LODs are drawn undithered, and a
        // fading-out block coplanar with its detail parts z-fights with them.
        d.fade_frames = 0;
        d.occlusion_camera = occlusion.then_some(d.camera);
        d
    };
    let mut culled = 0;
    let mut overlaid = false;
    for camera in cameras(&rig.city) {
        let deferred = RenderPath::Deferred;
        rig.query.set_hiz(&c.device, &c.queue, None).unwrap();
        let (off, _) = rig.frame(desc(&camera, false), camera, deferred);
        let hiz = HiZ::build(&rig.r.inspect().read_depth().unwrap(), W, H, true).unwrap();
        rig.query.set_hiz(&c.device, &c.queue, Some(&hiz)).unwrap();
        let mut twin = rig.cpu.clone();
        let (on, stats) = rig.frame(desc(&camera, true), camera, deferred);
        let params = QueryParams::new(&desc(&camera, true)).unwrap();
        let mut out = QueryOutput::<DrawableSetupInstance>::new();
        twin.query(&params, Some(&hiz), &QueryOptions::default(), &mut out)
            .unwrap();
        assert_eq!(stats.instances as usize, out.instances.len());
        culled += stats.query.rejected_occlusion;
        if culled > 0 && !overlaid {
            // The overlay: culled instances outlined in red, drawn ones in green.
            let mut unoccluded = QueryOutput::<DrawableSetupInstance>::new();
            rig.cpu
                .clone()
                .query(
                    &QueryParams::new(&desc(&camera, false)).unwrap(),
                    None,
                    &QueryOptions::default(),
                    &mut unoccluded,
                )
                .unwrap();
            let overlay = gpu::inspect::debug::occlusion_overlay(
                &on,
                &rig.cpu,
                &params,
                &unoccluded.instances,
                &out.instances,
            );
            let count = |c: [u8; 4]| overlay.pixels.iter().filter(|&&p| p == c).count();
            assert!(count([230, 30, 30, 255]) > 0 && count([40, 220, 60, 255]) > 0);
            save("occlusion_overlay", &overlay);
            overlaid = true;
        }
        let (mean, _) = diff_metrics(&on, &off, 0.5).unwrap();
        let (_, max) = diff_metrics(&on, &off, 1.0).unwrap();
        if max != 0 {
            save("occlusion_on", &on);
            save("occlusion_off", &off);
        }
        assert_eq!(
            max, 0,
            "occlusion changed the image (mean {mean}; images in CARGO_TARGET_TMPDIR)"
        );
    }
    eprintln!("occlusion culled {culled} instances over the cameras, image unchanged");
    assert!(
        culled > 1000,
        "the test exercises occlusion ({culled} culled)"
    );
}

/// The view of `camera` with LODs switching at once (see the test above) and no
/// occlusion camera (the modes that build their HiZ set it).
fn still_lod_desc(camera: &Camera) -> ViewDesc {
    let mut d = static_view_desc(camera, W, H);
    d.fade_frames = 0;
    d
}

/// HZD's mode with the pyramid reduced on the GPU: the HiZ the second of two frames from
/// one camera tests against equals `HiZ::build` of the first frame's depth texel for
/// texel, the GPU's visible set has the twin's size on it, and the image equals the one
/// without occlusion.
#[test]
fn the_gpu_hiz_of_the_previous_frame_equals_hiz_build() {
    hiz_of_the_previous_frame(W, H);
}

/// The same at an odd size with more levels: 301x163 has 10 (three dispatches of up to
/// four levels, odd edges at every level).
#[test]
fn the_gpu_hiz_at_an_odd_size_equals_hiz_build() {
    hiz_of_the_previous_frame(301, 163);
}

fn hiz_of_the_previous_frame(w: u32, h: u32) {
    let c = ctx();
    let mut rig = Rig::without_sun_shadows(w, h);
    let deferred = RenderPath::Deferred;
    let mut culled = 0;
    let desc = |camera: &Camera| {
        let mut d = static_view_desc(camera, w, h);
        d.fade_frames = 0;
        d
    };
    for camera in cameras(&rig.city).into_iter().take(3) {
        let previous = StaticOcclusion::PreviousFrame;
        let (off, _) = rig.frame(desc(&camera), camera, deferred);
        // The frame before has no static view of this renderer's depth: no occlusion.
        let depth = rig.r.inspect().read_depth().unwrap();
        let want = HiZ::build(&depth, w, h, true).unwrap();
        let mut twin = rig.cpu.clone();
        let (on, stats) = rig.frame_with(desc(&camera), camera, deferred, previous);
        let (texels, size) = rig.query.read_hiz(&c.device, &c.queue).unwrap();
        assert_eq!(size, (w, h));
        assert_eq!(texels.len(), want.texels().len());
        let differ = texels
            .iter()
            .zip(want.texels())
            .filter(|(a, b)| a.to_bits() != b.to_bits())
            .count();
        assert_eq!(differ, 0, "GPU HiZ texels differing from HiZ::build");
        let mut d = desc(&camera);
        d.occlusion_camera = Some(d.camera);
        let mut out = QueryOutput::<DrawableSetupInstance>::new();
        twin.query(
            &QueryParams::new(&d).unwrap(),
            Some(&want),
            &QueryOptions::default(),
            &mut out,
        )
        .unwrap();
        assert_eq!(stats.instances as usize, out.instances.len());
        culled += stats.query.rejected_occlusion;
        let (_, max) = diff_metrics(&on, &off, 1.0).unwrap();
        assert_eq!(max, 0, "occlusion changed the image");
    }
    assert!(culled > 500, "{culled} culled");
}

/// HZD's previous-frame mode tests against the previous frame of the same prepared scene
/// only: after a frame of another scene, nothing is occluded.
#[test]
fn the_previous_frame_of_another_scene_occludes_nothing() {
    let mut rig = Rig::new();
    let camera = rig.city.frame.camera;
    let previous = StaticOcclusion::PreviousFrame;
    rig.frame(still_lod_desc(&camera), camera, RenderPath::Deferred);
    let (_, same) = rig.frame_with(
        still_lod_desc(&camera),
        camera,
        RenderPath::Deferred,
        previous,
    );
    assert!(
        same.query.rejected_occlusion > 0,
        "the same scene's depth occludes"
    );
    // The same content prepared again is another scene to the renderer.
    rig.frame(still_lod_desc(&camera), camera, RenderPath::Deferred);
    rig.prepared = rig.r.prepare(&rig.city.scene).unwrap();
    let (_, other) = rig.frame_with(
        still_lod_desc(&camera),
        camera,
        RenderPath::Deferred,
        previous,
    );
    assert_eq!(other.query.rejected_occlusion, 0);
}

/// Two-pass occlusion while the camera moves (walks, turns, rises and jumps between
/// frames): every frame's image equals the image without occlusion (same camera), for the
/// deferred path and the baseline, while the second pass hides instances and the first
/// draws last frame's visible set.
#[test]
fn two_pass_occlusion_is_conservative_while_the_camera_moves() {
    let mut rig = Rig::without_sun_shadows(W, H);
    let base = cameras(&rig.city);
    // Small steps between the test cameras, then the jumps between them.
    let mut path = Vec::new();
    for pair in base.windows(2) {
        for k in 0..3 {
            let t = k as f32 / 3.0;
            path.push(Camera {
                position: pair[0].position.lerp(pair[1].position, t),
                target: pair[0].target.lerp(pair[1].target, t),
                ..pair[0]
            });
        }
    }
    let (mut hidden, mut early, mut added) = (0, 0, 0);
    let mut late_pixels = 0;
    for (frame, camera) in path.into_iter().enumerate() {
        let paths: &[RenderPath] = if frame % 4 == 3 {
            &[RenderPath::Deferred, RenderPath::Baseline]
        } else {
            &[RenderPath::Deferred]
        };
        for &path in paths {
            let (on, stats) = rig.frame_with(
                still_lod_desc(&camera),
                camera,
                path,
                StaticOcclusion::TwoPass,
            );
            let second = stats.second_pass.expect("two passes report the second");
            if path == RenderPath::Deferred {
                // The debug words: every static pixel resolves to a placed instance, late
                // pixels exactly when the second pass drew something, no fade (0 frames).
                let vis = rig.r.inspect().read_vis().unwrap();
                let debug = rig.r.inspect().read_static_debug(&rig.prepared).unwrap();
                let (mut statics, mut late) = (0, 0);
                for &w in &vis {
                    if let Some(p) = debug.lookup(w) {
                        statics += 1;
                        late += usize::from(p.late);
                        assert_eq!((p.fade, p.flags), (1.0, 0));
                        assert!((p.setup as usize) < rig.city.scene.static_setups.len());
                    }
                }
                assert!(statics > 0, "frame {frame}: no static pixel");
                assert_eq!(
                    late > 0,
                    second.visible > 0,
                    "frame {frame}: {late} late pixels"
                );
                late_pixels += late;
                if frame == 5 {
                    save(
                        "two_pass_split",
                        &gpu::inspect::debug::static_two_pass(W, H, &vis, &debug),
                    );
                }
            }
            let (off, _) = rig.frame(still_lod_desc(&camera), camera, path);
            assert_eq!((stats.over_capacity, stats.bad_batches), (0, 0));
            assert_eq!(stats.placed, u64::from(stats.instances));
            hidden += second.rejected_occlusion;
            early += second.drawn_early;
            added += second.visible;
            let (mean, _) = diff_metrics(&on, &off, 0.5).unwrap();
            let (_, max) = diff_metrics(&on, &off, 1.0).unwrap();
            if max != 0 {
                save("two_pass_on", &on);
                save("two_pass_off", &off);
            }
            assert_eq!(
                max, 0,
                "frame {frame} {path:?}: two-pass occlusion changed the image (mean {mean}; images in CARGO_TARGET_TMPDIR)"
            );
        }
    }
    eprintln!(
        "two-pass: {early} drawn early, {added} added late ({late_pixels} pixels), {hidden} hidden"
    );
    assert!(
        hidden > 1000 && early > 1000 && added > 100,
        "{hidden} {early} {added}"
    );
}

/// HZD's mode: the query read back (`StaticQuery::run`), its batches planned with
/// `tiling::build_plan` at prepare (`scene_from_query`), rendered as any scene: the image
/// equals the GPU-driven frame's; a batch naming no setup is an error naming it.
#[test]
fn hzds_read_back_mode_draws_what_the_gpu_driven_frame_draws() {
    let c = ctx();
    let mut rig = Rig::without_sun_shadows(W, H);
    let camera = rig.city.frame.camera;
    // No fade: the planned batches are drawn opaque.
    let desc = still_lod_desc(&camera);
    let mut readback_scene = rig.cpu.clone();
    let params = QueryParams::new(&desc).unwrap();
    let out = rig
        .query
        .run(
            &c.device,
            &c.queue,
            &mut readback_scene,
            &params,
            &QueryOptions::default(),
            QueryReadback::Full,
        )
        .unwrap();
    let planned = scene_from_query(&rig.city.scene, &out, &params).unwrap();
    assert_eq!(
        planned.instance_count() - rig.city.scene.instance_count(),
        out.instances.len()
    );
    let (driven, _) = rig.frame(desc, camera, RenderPath::Deferred);
    let prepared = rig.r.prepare(&planned).unwrap();
    rig.r
        .render(&prepared, &rig.city.frame, RenderPath::Deferred)
        .unwrap();
    let hzd = rig.r.read_output().unwrap();
    let (mean, _) = diff_metrics(&driven, &hzd, 0.5).unwrap();
    let (_, p99) = diff_metrics(&driven, &hzd, 0.99).unwrap();
    eprintln!("GPU-driven vs HZD's read-back mode: mean {mean:.4}, p99 {p99}");
    assert!(mean < 0.05 && p99 <= 2, "mean {mean}, p99 {p99}");
    let mut bad = out.clone();
    bad.batches[2].setup = 9_999;
    let e = scene_from_query(&rig.city.scene, &bad, &params).unwrap_err();
    assert!(
        e.to_string().contains("9999") && e.to_string().contains("batch 2"),
        "{e}"
    );
    let mut short = out;
    short.instances.truncate(1);
    assert!(scene_from_query(&rig.city.scene, &short, &params).is_err());
}

/// The LOD / fade debug view's data over a walk with fading on: the placement's debug
/// words give each static pixel its setup and fade state; as LODs switch, some pixels show
/// instances fading in and out with opacities between 0 and 1, and pairs complement.
#[test]
fn the_lod_fade_view_shows_instances_fading() {
    let mut rig = Rig::new();
    let base = rig.city.frame.camera;
    let fwd = (base.target - base.position).normalize();
    let (mut fading_in, mut fading_out) = (0usize, 0usize);
    for frame in 0..12 {
        let d = 6.0 * frame as f32;
        let camera = Camera {
            position: base.position + fwd * d,
            target: base.target + fwd * d,
            ..base
        };
        let mut desc = static_view_desc(&camera, W, H);
        desc.fade_frames = 4;
        rig.frame(desc, camera, RenderPath::Deferred);
        let vis = rig.r.inspect().read_vis().unwrap();
        let debug = rig.r.inspect().read_static_debug(&rig.prepared).unwrap();
        for (i, p) in vis
            .iter()
            .enumerate()
            .filter_map(|(i, &w)| Some((i, debug.lookup(w)?)))
        {
            let out = p.flags & staticscene::STATE_FADING_OUT != 0;
            if p.flags & staticscene::STATE_FADING != 0 {
                assert!(p.fade > 0.0 && p.fade < 1.0, "{p:?}");
                // The laydown's dither: a fading instance shows only where the 4x4 Bayer
                // rank is below its cells of 16 (fading in) or at or above 16 minus them.
                const BAYER: [[u32; 4]; 4] =
                    [[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]];
                let (x, y) = (i as u32 % W, i as u32 / W);
                let rank = BAYER[(y % 4) as usize][(x % 4) as usize];
                let cells = (p.fade * 16.0).round() as u32;
                let kept = if out {
                    rank + cells >= 16
                } else {
                    rank < cells
                };
                assert!(
                    kept,
                    "pixel ({x}, {y}) of a fading instance the dither drops: {p:?}"
                );
                if out {
                    fading_out += 1;
                } else {
                    fading_in += 1;
                }
            } else {
                assert_eq!((p.fade, out), (1.0, false), "{p:?}");
            }
        }
        if frame == 6 {
            save(
                "lod_fade",
                &gpu::inspect::debug::static_lod_fade(W, H, &vis, &debug),
            );
        }
    }
    eprintln!("fading pixels: {fading_in} in, {fading_out} out");
    assert!(fading_in > 0 && fading_out > 0, "{fading_in} {fading_out}");
}

/// Streaming while frames render: streaming groups come and go between frames (a sliding
/// window, one group coming back into freed pool space); each frame's GPU-driven static
/// draws equal the CPU twin's visible set on the same tiles, and every placed instance is
/// drawn.
#[test]
fn tiles_streamed_between_frames_keep_the_frame_equal_to_the_twin() {
    use gpu::staticscene::{BuildConfig, ResourceLibrary, TileStreamer};
    let c = ctx();
    let mut config = staticscene::demo::CityConfig::with_instances(30_000);
    // Small sectors: many streaming groups.
    config.sector_lots = 2;
    let city = demo::city::city_with(config);
    let mut r = renderer();
    let prepared = r.prepare(&city.scene).unwrap();
    let mut query = StaticQuery::new(&c.device, &c.queue).unwrap();
    let mut streamer = TileStreamer::new(
        ResourceLibrary::new(&city.world.resources),
        BuildConfig::default(),
    );
    let mut cpu = staticscene::Scene::new();
    let groups = &city.world.groups;
    let n = groups.len();
    assert!(n >= 4, "{n} groups");
    let mut loaded: Vec<usize> = Vec::new();
    // An update can remove and add (the orphan tile is rebuilt): both sides, both lists.
    let apply =
        |query: &mut StaticQuery, cpu: &mut staticscene::Scene, u: staticscene::TileUpdate| {
            for id in &u.remove {
                assert!(query.deactivate(*id));
            }
            for t in &u.add {
                query.activate(&c.device, &c.queue, t.tile()).unwrap();
            }
            cpu.apply(u);
        };
    let camera = city.frame.camera;
    let mut desc = static_view_desc(&camera, W, H);
    desc.fade_frames = 0;
    let mut seen = 0;
    for frame in 0..8usize {
        let lo = frame * n / 12;
        let mut want: Vec<usize> = (lo..(lo + n / 2).min(n)).collect();
        if frame >= 6 {
            want.push(0);
        }
        for g in loaded.clone() {
            if !want.contains(&g) {
                let u = streamer.remove_group(groups[g].id).unwrap();
                apply(&mut query, &mut cpu, u);
                loaded.retain(|&x| x != g);
            }
        }
        for &g in &want {
            if !loaded.contains(&g) {
                let u = streamer.add_group(&groups[g]).unwrap();
                apply(&mut query, &mut cpu, u);
                loaded.push(g);
            }
        }
        assert_eq!(query.tile_count(), cpu.tiles().len());
        let params = QueryParams::new(&desc).unwrap();
        let mut twin = cpu.clone();
        let mut out = QueryOutput::<DrawableSetupInstance>::new();
        // The twin batches at the query's width (the subgroup size, or 64).
        let twin_options = QueryOptions {
            wave_width: query.wave_width().expect("a fixed subgroup size"),
            ..QueryOptions::default()
        };
        twin.query(&params, None, &twin_options, &mut out).unwrap();
        let mut view = StaticView {
            query: &mut query,
            scene: &mut cpu,
            view: desc,
            options: QueryOptions::default(),
            occlusion: StaticOcclusion::Given,
        };
        let stats = r
            .render_static(&prepared, &city.frame, RenderPath::Deferred, &mut view)
            .unwrap()
            .statics
            .unwrap();
        assert!(stats.skipped_tiles.is_empty());
        assert_eq!(
            stats.instances as usize,
            out.instances.len(),
            "frame {frame}"
        );
        assert_eq!(stats.placed, u64::from(stats.instances), "frame {frame}");
        assert_eq!(stats.batches as usize, out.batches.len(), "frame {frame}");
        seen += out.instances.len();
    }
    assert!(seen > 1000, "{seen}");
}

#[test]
fn render_static_refuses_a_scene_without_static_setups() {
    let c = ctx();
    let city = small_city();
    let mut query = StaticQuery::new(&c.device, &c.queue).unwrap();
    let mut cpu = staticscene::Scene::new();
    let mut r = renderer();
    let mut plain = city.scene.clone();
    plain.static_setups.clear();
    let prepared = r.prepare(&plain).unwrap();
    let mut view = StaticView {
        query: &mut query,
        scene: &mut cpu,
        view: static_view_desc(&city.frame.camera, W, H),
        options: QueryOptions::default(),
        occlusion: StaticOcclusion::Given,
    };
    let e = r
        .render_static(&prepared, &city.frame, RenderPath::Deferred, &mut view)
        .unwrap_err();
    assert!(e.to_string().contains("static setup"), "{e}");
    // A setup naming a missing mesh is refused at prepare, naming it.
    let mut bad = city.scene.clone();
    bad.static_setups[3].mesh = scene::MeshId(10_000);
    let e = r.prepare(&bad).err().expect("a missing mesh is refused");
    assert!(e.to_string().contains("static setup 3"), "{e}");
}

/// KZ2's conditional rendering emulated in a static frame: two shadow-casting spots on the
/// volume path over the street, one lighting it and one buried under it. The buried one's
/// map draws neither its planned casters nor the static query's lists (their counts
/// zeroed on the GPU, where the device has `MULTI_DRAW_INDIRECT_COUNT`), the lit one's
/// draws the lists with the placement's counts, and the image equals the one without
/// the emulation bit for bit.
#[test]
fn conditional_volumes_keep_the_static_frame() {
    let mut rig = Rig::new();
    let camera = rig.city.frame.camera;
    let (eye, target) = (camera.position, camera.target);
    let spot = |position: Vec3, radius: f32| gpu::SpotLight {
        position,
        direction: Vec3::new(0.1, -1.0, 0.05),
        color: Vec3::new(30.0, 24.0, 16.0),
        radius,
        half_angle: 0.7,
        shadow: true,
        specular: true,
    };
    let lighting = &mut rig.city.frame.lighting;
    lighting.sun_color *= 0.05;
    lighting.spot_lights = vec![
        spot(eye.lerp(target, 0.5) + Vec3::new(0.0, 4.0, 0.0), 14.0),
        // 30 m ahead, 14 m below the eye: under the street.
        spot(
            eye + (target - eye).normalize() * 30.0 - Vec3::new(0.0, 14.0, 0.0),
            5.0,
        ),
    ];
    let desc = still_lod_desc(&camera);
    let mut images = Vec::new();
    for conditional_volumes in [true, false] {
        rig.r = common::renderer_with({
            let mut rc = gpu::RendererConfig::sized(W, H);
            rc.lighting.shadows = common::test_shadows();
            rc.lighting.baked_sun = false;
            rc.lighting.light_paths = gpu::config::LightPaths::Volumes;
            rc.lighting.conditional_volumes = conditional_volumes;
            rc
        });
        rig.prepared = rig.r.prepare(&rig.city.scene).unwrap();
        let (image, _) = rig.frame(desc, camera, RenderPath::Deferred);
        let counts = rig.r.inspect().light_path_counts();
        let tested = rig.r.inspect().read_conditional_volumes().unwrap();
        eprintln!("conditional {conditional_volumes}: {counts:?}");
        for t in &tested {
            eprintln!("  {t:?}");
        }
        assert_eq!(counts.spot_shadow_maps, 2, "{counts:?}");
        if conditional_volumes {
            assert_eq!(tested.len(), 2);
            let with_count = ctx()
                .device
                .features()
                .contains(wgpu::Features::MULTI_DRAW_INDIRECT_COUNT);
            // Spots in order: the lit one is nearer the eye (view z closer to 0).
            let (lit, buried) = if tested[0].light.position[1] > tested[1].light.position[1] {
                (tested[0], tested[1])
            } else {
                (tested[1], tested[0])
            };
            assert!(lit.samples > 0 && lit.volume_instances == 1, "{lit:?}");
            assert!(!with_count || lit.static_count > 0, "{lit:?}");
            assert_eq!((buried.samples, buried.volume_instances), (0, 0));
            assert_eq!((buried.caster_count, buried.static_count), (0, 0));
        } else {
            assert!(tested.is_empty());
        }
        images.push(image);
    }
    assert_eq!(common::differing_pixels(&images[0], &images[1]), 0);
}
