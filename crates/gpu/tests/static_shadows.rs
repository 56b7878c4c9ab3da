//! The static query's shadow views (KZ2's shadow query with size threshold, HZD's sun
//! query) on lavapipe: each sun slice draws the static casters of its own view, so a
//! caster outside the camera's frustum shadows what the camera sees, and the maps equal
//! those of the same instances drawn as planned batches (an independent path: no query,
//! no placement); a caster below the size threshold of a slice's texels is absent from
//! that slice only, and present with the threshold off; the camera view's rows and image
//! are untouched by the shadow views (its vis IDs and G-buffer equal a frame without sun
//! shadows); the baked sun map holds the static casters.

mod common;

use demo::city::box_mesh;
use gpu::config::ShadowConfig;
use gpu::glam::{Affine3A, DVec3, Vec3};
use gpu::scene::{AlbedoLayer, MaterialId, MeshId, ShaderKind, StaticSetup};
use gpu::statics::{StaticFrameStats, StaticOcclusion, StaticQuery, StaticView, static_view_desc};
use gpu::staticscene::{
    self, BuildConfig, MeshNode, PlacedObject, QueryOptions, ResourceLibrary, StaticMesh,
    StreamingGroup, TileStreamer,
};
use gpu::{Batch, Camera, FrameInput, Material, RenderPath, Renderer, RendererConfig, Scene};
use testkit::device::ctx;

const W: u32 = 160;
const H: u32 = 90;

/// Setup 0: a 2 x 6 x 2 m tower; setup 1: a 3 m cube. Local origin at the base centre.
const TOWER: (Vec3, Vec3) = (Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 6.0, 1.0));
const CUBE: (Vec3, Vec3) = (Vec3::new(-1.5, 0.0, -1.5), Vec3::new(1.5, 3.0, 1.5));

/// The camera at 2 m looking down -Z; towers beside the view (outside its frustum, their
/// shadows falling into it: the sun is to the right), one tower in view, and the cube
/// 12 m ahead.
fn camera() -> Camera {
    Camera::look_at(Vec3::new(0.0, 2.0, 0.0), Vec3::new(0.0, 1.0, -10.0))
}

fn frame() -> FrameInput {
    let mut f = FrameInput::new(camera());
    f.lighting.sun_direction = Vec3::new(1.0, 0.7, 0.2).normalize();
    f
}

/// Where the static instances stand: `(setup, base position)`. The towers at x >= 9 are
/// at least 48° off the view axis (the horizontal half field of view is 46°); one tower of the
/// same setup stands in view, so the camera's and the shadow views' ranks of setup 0
/// name different instances.
fn placements(layout: Layout) -> Vec<(usize, Vec3)> {
    let mut p = vec![
        (0, Vec3::new(9.0, 0.0, -6.0)),
        (0, Vec3::new(10.0, 0.0, -4.0)),
        (0, Vec3::new(12.0, 0.0, -8.0)),
        (0, layout.in_view),
    ];
    if layout.cube {
        p.push((1, Vec3::new(0.5, 0.0, -12.0)));
    }
    p
}

/// Which instances the world holds: the cube or not, and where the tower in view stands.
#[derive(Clone, Copy, Debug)]
struct Layout {
    cube: bool,
    in_view: Vec3,
}

const WITH_CUBE: Layout = Layout {
    cube: true,
    in_view: Vec3::new(-3.0, 0.0, -16.0),
};
const NO_CUBE: Layout = Layout {
    cube: false,
    ..WITH_CUBE
};

/// The renderer's scene: meshes, one material, the ground as a planned batch, and either
/// the static setups (the instances come from the query) or, for the reference, the same
/// instances as planned batches.
fn scene(statics: bool, layout: Layout) -> Scene {
    let mut scene = Scene {
        data_layers: Vec::new(),
        meshes: vec![
            box_mesh("tower", TOWER.0, TOWER.1),
            box_mesh("cube", CUBE.0, CUBE.1),
            box_mesh(
                "ground",
                Vec3::new(-100.0, -0.2, -100.0),
                Vec3::new(100.0, 0.0, 100.0),
            ),
        ],
        materials: vec![Material {
            name: "plaster".into(),
            shader: ShaderKind::Opaque,
            albedo_layer: 0,
            tint: Vec3::ONE,
            alpha_cutoff: 0.5,
            roughness: 0.8,
            specular: 0.3,
            regular: false,
            ..Default::default()
        }],
        albedo_layers: vec![AlbedoLayer {
            size: 4,
            texels: vec![[180, 170, 160, 255]; 16],
        }],
        batches: vec![Batch {
            mesh: MeshId(2),
            material: MaterialId(0),
            instances: vec![Affine3A::IDENTITY],
        }],
        static_setups: Vec::new(),
        wind: None,
    };
    if statics {
        scene.static_setups = (0..2)
            .map(|mesh| StaticSetup {
                mesh: MeshId(mesh),
                material: MaterialId(0),
                capacity: 8,
            })
            .collect();
    } else {
        for (setup, at) in placements(layout) {
            scene.batches.push(Batch {
                mesh: MeshId(setup),
                material: MaterialId(0),
                instances: vec![Affine3A::from_translation(at)],
            });
        }
    }
    scene
}

/// The static world of `placements`, its tiles built and activated on a new query.
fn static_world(layout: Layout) -> (StaticQuery, staticscene::Scene) {
    let c = ctx();
    let leaf = |setup: u64, (min, max): (Vec3, Vec3)| {
        MeshNode::Static(StaticMesh {
            setup,
            bounds: staticscene::Aabb { min, max },
            filter: staticscene::FILTER_VISUAL | staticscene::FILTER_SUN_SHADOW,
            flags: 0,
        })
    };
    let resources = vec![leaf(0, TOWER), leaf(1, CUBE)];
    let group = StreamingGroup {
        id: 1,
        objects: placements(layout)
            .into_iter()
            .map(|(r, at)| PlacedObject::new(r, at.as_dvec3()))
            .collect(),
    };
    let mut streamer = TileStreamer::new(ResourceLibrary::new(&resources), BuildConfig::default());
    let mut query = StaticQuery::new(&c.device, &c.queue).unwrap();
    let mut cpu = staticscene::Scene::new();
    let update = streamer.add_group(&group).unwrap();
    assert!(update.dynamic.is_empty());
    for t in &update.add {
        query.activate(&c.device, &c.queue, t.tile()).unwrap();
    }
    cpu.apply(update);
    (query, cpu)
}

fn shadows(threshold: f32) -> ShadowConfig {
    ShadowConfig {
        static_size_threshold: threshold,
        ..common::test_shadows().unwrap()
    }
}

fn renderer(shadows: Option<ShadowConfig>, baked_sun: bool) -> Renderer {
    common::renderer_with({
        let mut rc = RendererConfig::sized(W, H);
        rc.lighting.shadows = shadows;
        rc.lighting.baked_sun = baked_sun;
        rc
    })
}

/// One static frame of the world: the renderer's statistics (its maps, image and buffers
/// are left to read).
fn static_frame(r: &mut Renderer, layout: Layout) -> StaticFrameStats {
    let (mut query, mut cpu) = static_world(layout);
    let prepared = r.prepare(&scene(true, layout)).unwrap();
    let mut desc = static_view_desc(&camera(), W, H);
    desc.fade_frames = 0;
    let mut view = StaticView {
        query: &mut query,
        scene: &mut cpu,
        view: desc,
        options: QueryOptions::default(),
        occlusion: StaticOcclusion::Given,
    };
    r.render_static(&prepared, &frame(), RenderPath::Deferred, &mut view)
        .unwrap_or_else(|e| panic!("{e}"))
        .statics
        .expect("a static frame reports its statistics")
}

/// The same instances as planned batches, rendered without a query.
fn planned_frame(r: &mut Renderer, layout: Layout) {
    let prepared = r.prepare(&scene(false, layout)).unwrap();
    r.render(&prepared, &frame(), RenderPath::Deferred).unwrap();
}

/// Per slice, the texels (of the slice's own corner of its layer) whose depths differ by
/// more than 1e-5: the planned path stores transforms relative to another origin, so
/// depths may differ by f32 rounding, never by a caster.
fn differing_texels(a: &[Vec<f32>], b: &[Vec<f32>], config: &ShadowConfig) -> Vec<usize> {
    let stride = config.resolution as usize;
    a.iter()
        .zip(b)
        .enumerate()
        .map(|(k, (x, y))| {
            let n = config.slice_resolution(k) as usize;
            (0..n * n)
                .filter(|&i| {
                    let at = (i / n) * stride + i % n;
                    (x[at] - y[at]).abs() > 1e-5
                })
                .count()
        })
        .collect()
}

/// (a) The towers outside the camera's frustum cast into the slices (their own shadow
/// views find them; the camera's query does not), and every slice's map equals the map of
/// the same instances drawn as planned batches; the image too, and it is darker than the
/// image without the towers' shadows.
#[test]
fn casters_outside_the_view_shadow_it_as_planned_batches_do() {
    let config = shadows(0.0);
    let mut r = renderer(Some(config), false);
    let stats = static_frame(&mut r, WITH_CUBE);
    let maps = r.inspect().read_shadow_maps().unwrap();
    let image = r.read_output().unwrap();
    eprintln!(
        "camera: {} instances; slices: {:?}",
        stats.instances,
        stats
            .shadow_slices
            .iter()
            .map(|s| (s.slice, s.instances, s.placed, s.query.rejected_frustum))
            .collect::<Vec<_>>()
    );
    // The camera sees the tower in view and the cube; the slices see more.
    assert_eq!(stats.instances, 2, "the camera's query");
    assert_eq!(stats.shadow_slices.len(), config.cascades as usize);
    for s in &stats.shadow_slices {
        assert_eq!((s.over_capacity, s.bad_batches), (0, 0));
        assert_eq!(s.placed, u64::from(s.instances));
        assert_eq!(s.query.rejected_size, 0, "threshold 0 drops nothing");
        assert_eq!(s.texels, config.slice_resolution(s.slice as usize));
    }
    assert!(
        stats.shadow_slices.iter().any(|s| s.instances >= 4),
        "a slice holds the towers beside the view"
    );

    let mut reference = renderer(Some(config), false);
    planned_frame(&mut reference, WITH_CUBE);
    let want = reference.inspect().read_shadow_maps().unwrap();
    let differ = differing_texels(&maps, &want, &config);
    eprintln!("texels differing from the planned batches' maps: {differ:?}");
    assert!(differ.iter().all(|&d| d == 0), "{differ:?}");
    let planned_image = reference.read_output().unwrap();
    let (_, max) = gpu::inspect::diff_metrics(&image, &planned_image, 1.0).unwrap();
    assert!(max <= 2, "image vs planned batches: max {max}");

    // Without the towers beside the view (the camera query's casters alone, as before),
    // their shadows are missing: the static frame is darker in many pixels.
    let mut without = renderer(Some(config), false);
    let prepared = without
        .prepare(&Scene {
            batches: scene(false, WITH_CUBE)
                .batches
                .into_iter()
                .enumerate()
                .filter(|(i, _)| !matches!(i, 1..=3))
                .map(|(_, b)| b)
                .collect(),
            ..scene(false, WITH_CUBE)
        })
        .unwrap();
    without
        .render(&prepared, &frame(), RenderPath::Deferred)
        .unwrap();
    let lit = without.read_output().unwrap();
    let luma = |p: &[u8; 4]| u32::from(p[0]) + u32::from(p[1]) + u32::from(p[2]);
    let darker = image
        .pixels
        .iter()
        .zip(&lit.pixels)
        .filter(|(a, b)| luma(a) + 30 < luma(b))
        .count();
    eprintln!("pixels the towers beside the view darken: {darker}");
    assert!(darker > 200, "{darker}");
}

/// (b) KZ2's size threshold per slice: the cube is dropped from the slices where its
/// bounding sphere spans fewer texels than the threshold (counted as rejected by size;
/// those maps equal the planned batches' maps without the cube) and kept where it spans
/// more (those maps equal the maps with the cube); with the threshold off it is in every
/// slice.
#[test]
fn the_size_threshold_drops_small_casters_per_slice() {
    let probe = shadows(0.0);
    let mut r = renderer(Some(probe), false);
    static_frame(&mut r, WITH_CUBE);
    let cascades = r.inspect().shadow_cascades().unwrap().cascades().to_vec();
    // The cube's and the towers' bounding sphere diameters (the query's size test: the
    // box's diagonal) in each slice's texels, for the slices whose volume holds the
    // cube's centre.
    let diagonal = |(min, max): (Vec3, Vec3)| f64::from((max - min).length());
    let centre = DVec3::new(0.5, 1.5, -12.0);
    let spans: Vec<(usize, f64)> = cascades
        .iter()
        .enumerate()
        .filter(|(_, c)| {
            let p = c.world_to_clip.project_point3(centre);
            p.x.abs() < 1.0 && p.y.abs() < 1.0 && (0.0..1.0).contains(&p.z)
        })
        .map(|(k, c)| (k, diagonal(CUBE) / c.texel_size))
        .collect();
    let coarsest = spans.iter().map(|s| s.1).fold(f64::INFINITY, f64::min);
    // Between the cube's and the towers' spans in the coarsest slice: the cube dropped
    // there, the towers kept everywhere.
    let towers = coarsest * diagonal(TOWER) / diagonal(CUBE);
    let threshold = (coarsest * towers).sqrt() as f32;
    assert!(
        spans
            .iter()
            .all(|s| (s.1 / f64::from(threshold) - 1.0).abs() > 0.1)
    );
    assert!(
        spans.iter().any(|s| s.1 > f64::from(threshold)),
        "{spans:?}"
    );
    eprintln!("cube spans (slice, texels): {spans:?}; threshold {threshold}");

    let config = shadows(threshold);
    let mut r = renderer(Some(config), false);
    let stats = static_frame(&mut r, WITH_CUBE);
    let maps = r.inspect().read_shadow_maps().unwrap();
    let mut with_cube = renderer(Some(config), false);
    planned_frame(&mut with_cube, WITH_CUBE);
    let mut without_cube = renderer(Some(config), false);
    planned_frame(&mut without_cube, NO_CUBE);
    let with = differing_texels(
        &maps,
        &with_cube.inspect().read_shadow_maps().unwrap(),
        &config,
    );
    let without = differing_texels(
        &maps,
        &without_cube.inspect().read_shadow_maps().unwrap(),
        &config,
    );
    eprintln!("differing from the maps with the cube {with:?}, without {without:?}");
    let (mut kept, mut dropped) = (0, 0);
    for &(k, span) in &spans {
        let s = stats
            .shadow_slices
            .iter()
            .find(|s| s.slice as usize == k)
            .expect("every slice re-rendered");
        if span >= f64::from(threshold) {
            kept += 1;
            assert_eq!(s.query.rejected_size, 0, "slice {k}");
            assert_eq!(with[k], 0, "slice {k} holds the cube");
            assert!(without[k] > 0, "slice {k}: the cube casts something");
        } else {
            dropped += 1;
            assert_eq!(s.query.rejected_size, 1, "slice {k}");
            assert_eq!(without[k], 0, "slice {k} leaves the cube out");
            assert!(with[k] > 0, "slice {k}: the cube would cast something");
        }
    }
    assert!(kept > 0 && dropped > 0, "{kept} {dropped}");
}

/// (c) The shadow views write their own rows: the camera's vis IDs and G-buffer (which
/// the resolve reads through the camera's rows by vis ID) equal those of the same frame
/// without sun shadows, whose slices run no shadow view.
#[test]
fn shadow_views_leave_the_camera_views_rows_alone() {
    // The tower in view at several places, so that in some layout a shadow view's rank 0
    // of its setup is another tower than the camera's (ranks follow the tile's Morton
    // order): rows written into the camera's slots would then show (checked by writing
    // them there: the layout 2.5 m ahead catches it).
    for in_view in [
        Vec3::new(-3.0, 0.0, -16.0),
        Vec3::new(1.5, 0.0, -2.5),
        Vec3::new(14.0, 0.0, -40.0),
    ] {
        let layout = Layout {
            in_view,
            ..WITH_CUBE
        };
        let mut with = renderer(Some(shadows(0.0)), false);
        let stats = static_frame(&mut with, layout);
        assert!(
            stats
                .shadow_slices
                .iter()
                .any(|s| s.instances > stats.instances)
        );
        let mut without = renderer(None, false);
        let plain = static_frame(&mut without, layout);
        assert!(plain.shadow_slices.is_empty());
        assert_eq!(stats.instances, plain.instances);
        let vis = with.inspect().read_vis().unwrap();
        let other = without.inspect().read_vis().unwrap();
        let moved = vis.iter().zip(&other).filter(|(a, b)| a != b).count();
        assert_eq!(moved, 0, "{in_view}: vis IDs differing");
        assert!(vis.iter().any(|&w| w != visbuf::VIS_NONE));
        let (a, b) = (
            with.inspect().read_gbuffer().unwrap(),
            without.inspect().read_gbuffer().unwrap(),
        );
        let differ = a
            .iter()
            .zip(&b)
            .filter(|(x, y)| (x.albedo, x.normal, x.motion) != (y.albedo, y.normal, y.motion))
            .count();
        assert_eq!(differ, 0, "{in_view}: G-buffer pixels differing");
    }
}

/// (d) The baked sun map holds the static casters: with the real-time slices off, the
/// G-buffer's baked sun term of the static frame matches that of the same instances as
/// planned batches (the bake's own box may differ by the tiles' bounds' rounding: a few
/// edge pixels), and the towers beside the view darken pixels of it.
#[test]
fn the_baked_sun_map_holds_the_static_casters() {
    let mut r = renderer(None, true);
    let stats = static_frame(&mut r, WITH_CUBE);
    let baked = stats.baked.expect("the first frame bakes");
    eprintln!(
        "bake: {} casters, {} placed, draws {:?}",
        baked.instances, baked.placed, baked.draws
    );
    assert_eq!(baked.instances, 5, "every static caster");
    assert_eq!(baked.placed, 5);
    let sun = |r: &Renderer| -> Vec<f32> {
        r.inspect()
            .read_gbuffer()
            .unwrap()
            .iter()
            .map(|s| s.sun_shadow)
            .collect()
    };
    let got = sun(&r);
    let mut reference = renderer(None, true);
    planned_frame(&mut reference, WITH_CUBE);
    let want = sun(&reference);
    let differ = got
        .iter()
        .zip(&want)
        .filter(|(a, b)| (*a - *b).abs() > 0.25)
        .count();
    let shadowed = got.iter().filter(|&&s| s < 0.5).count();
    eprintln!("baked: {shadowed} pixels in baked shadow, {differ} differ from the planned");
    assert!(shadowed > 200, "{shadowed}");
    assert!(differ * 100 < got.len(), "{differ}");
    // A second frame keeps the bake (same scene, sun and tiles).
    assert!(static_frame_again(&mut r).baked.is_none());
}

/// Another frame of a fresh world on `r` with its last prepared scene's content: a new
/// prepared scene re-bakes, so this renders the same prepared scene twice.
fn static_frame_again(r: &mut Renderer) -> StaticFrameStats {
    let (mut query, mut cpu) = static_world(WITH_CUBE);
    let prepared = r.prepare(&scene(true, WITH_CUBE)).unwrap();
    let mut desc = static_view_desc(&camera(), W, H);
    desc.fade_frames = 0;
    let mut view = StaticView {
        query: &mut query,
        scene: &mut cpu,
        view: desc,
        options: QueryOptions::default(),
        occlusion: StaticOcclusion::Given,
    };
    let first = r
        .render_static(&prepared, &frame(), RenderPath::Deferred, &mut view)
        .unwrap()
        .statics
        .unwrap();
    assert!(first.baked.is_some(), "a new prepared scene bakes");
    r.render_static(&prepared, &frame(), RenderPath::Deferred, &mut view)
        .unwrap()
        .statics
        .unwrap()
}
