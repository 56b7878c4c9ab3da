//! The laydown writes the right vis-buffer word in every pixel, on every primitive-ID path
//! the device has: compared with an independent f64 CPU rasteriser of the same scene.

mod common;

use common::laydown::{H, W, compute_device, front_camera, test_scene};
use common::material;
use gpu::config::{LaydownTarget, PrimitiveIdPath};
use gpu::glam::{Affine3A, DVec2, DVec3, DVec4, Vec3};
use gpu::scene::{MaterialId, MeshId, ShaderKind};
use gpu::{Batch, Camera, FrameInput, Laydown, Mesh, Renderer, RendererConfig, Scene};
use testkit::device::ctx;
use tiling::MicroBatchInfo;
use visbuf::{PrimitiveBits, ShadingRate, VisFields, VisId, VisLayout};

/// What an f64 rasteriser sees at one pixel centre.
#[derive(Clone, Copy)]
struct Hit {
    word: u32,
    depth: f64,
    margin: f64,
}

fn cpu_raster(
    scene: &Scene,
    camera: &Camera,
    prepared: &gpu::PreparedScene,
) -> Vec<(Option<Hit>, f64, bool)> {
    let mbs: &[MicroBatchInfo] = &prepared.tiling_plan().micro_batches;
    let aspect = f64::from(W) / f64::from(H);
    let vp = camera.view_projection(aspect as f32).as_dmat4();
    // Per pixel: best hit, the depth of the runner-up, and whether an edge passes within a
    // hundredth of a pixel of the centre without covering it (ambiguous coverage).
    let mut out: Vec<(Option<Hit>, f64, bool)> =
        vec![(None, f64::NEG_INFINITY, false); (W * H) as usize];
    for mb in mbs {
        let batch = &scene.batches[mb.batch as usize];
        let mesh = &scene.meshes[batch.mesh.0];
        let bits = PrimitiveBits::for_count(mesh.primitive_count() as u32).unwrap();
        // The plan's position i holds the batch's instance order[i].
        let order = prepared.instance_order(mb.batch as usize).unwrap();
        for (i, &k) in order.iter().enumerate() {
            let t = &batch.instances[k as usize];
            let (micro_batch, field) = visbuf::split_instance(mb.first_id, i as u32, bits);
            let m = glam::DAffine3::from_mat4(glam::Mat4::from(*t).as_dmat4());
            for (tri, c) in mesh.indices.chunks_exact(3).enumerate() {
                let clip: Vec<DVec4> = c
                    .iter()
                    .map(|&k| {
                        vp * m
                            .transform_point3(mesh.positions[k as usize].as_dvec3())
                            .extend(1.0)
                    })
                    .collect();
                assert!(
                    clip.iter().all(|p| p.w > 0.1),
                    "test scene must stay in front of the camera"
                );
                let s: Vec<DVec2> = clip
                    .iter()
                    .map(|p| {
                        DVec2::new(
                            (p.x / p.w + 1.0) * 0.5 * f64::from(W),
                            (1.0 - p.y / p.w) * 0.5 * f64::from(H),
                        )
                    })
                    .collect();
                let z: Vec<f64> = clip.iter().map(|p| p.z / p.w).collect();
                // Screen-space area; front faces are counter-clockwise in NDC, so clockwise
                // in y-down pixels (negative area here).
                let area = (s[1] - s[0]).perp_dot(s[2] - s[0]);
                if area >= 0.0 {
                    continue; // back face or degenerate: culled
                }
                let word = VisId::pack(
                    VisLayout::Standard,
                    bits,
                    VisFields {
                        micro_batch,
                        instance: field,
                        primitive: tri as u32,
                        rate: ShadingRate::Rate1x1,
                    },
                )
                .unwrap()
                .0;
                let lo = s
                    .iter()
                    .fold(DVec2::splat(f64::INFINITY), |a, &b| a.min(b))
                    .max(DVec2::ZERO);
                let hi = s
                    .iter()
                    .fold(DVec2::splat(f64::NEG_INFINITY), |a, &b| a.max(b))
                    .min(DVec2::new(f64::from(W), f64::from(H)));
                for py in lo.y.floor() as u32..(hi.y.ceil() as u32).min(H) {
                    for px in lo.x.floor() as u32..(hi.x.ceil() as u32).min(W) {
                        let q = DVec2::new(f64::from(px) + 0.5, f64::from(py) + 0.5);
                        let e = DVec3::new(
                            (s[2] - s[1]).perp_dot(q - s[1]),
                            (s[0] - s[2]).perp_dot(q - s[2]),
                            (s[1] - s[0]).perp_dot(q - s[0]),
                        ) / area;
                        // Signed distance to the nearest edge in pixels (negative: outside).
                        let margin = (0..3)
                            .map(|k| {
                                let (a, b) = (s[(k + 1) % 3], s[(k + 2) % 3]);
                                e[k] * area.abs() / (b - a).length()
                            })
                            .fold(f64::INFINITY, f64::min);
                        if margin < 0.0 {
                            if margin > -0.01 {
                                out[(py * W + px) as usize].2 = true;
                            }
                            continue;
                        }
                        let depth = e.x * z[0] + e.y * z[1] + e.z * z[2];
                        let cell = &mut out[(py * W + px) as usize];
                        match cell.0 {
                            Some(best) if best.depth >= depth => cell.1 = cell.1.max(depth),
                            Some(best) => {
                                cell.1 = cell.1.max(best.depth);
                                cell.0 = Some(Hit {
                                    word,
                                    depth,
                                    margin,
                                });
                            }
                            None => {
                                cell.0 = Some(Hit {
                                    word,
                                    depth,
                                    margin,
                                })
                            }
                        }
                    }
                }
            }
        }
    }
    out
}

/// Renders the laydown of the test scene with `config` and compares every unambiguous
/// pixel with the f64 rasteriser; `name` labels failures.
fn check_against_f64(config: RendererConfig, name: &str) -> Renderer {
    let (scene, frame) = test_scene();
    check_scene_against_f64(config, name, &scene, &frame).0
}

/// The same for any `scene` seen from `frame` (every vertex in front of the camera).
fn check_scene_against_f64(
    config: RendererConfig,
    name: &str,
    scene: &Scene,
    frame: &FrameInput,
) -> (Renderer, Option<gpu::inspect::LaydownStats>) {
    let probe = ctx();
    let mut renderer = Renderer::new(&probe.device, &probe.queue, config).unwrap();
    let prepared = renderer.prepare(scene).unwrap();
    let reference = cpu_raster(scene, &frame.camera, &prepared);
    let (vis, _depth) = renderer.hooks().render_laydown(&prepared, frame).unwrap();
    let (mut checked, mut covered) = (0, 0);
    for (i, (&got, &(hit, runner_up, near_miss))) in vis.iter().zip(&reference).enumerate() {
        match hit {
            Some(h) if h.margin > 0.01 && h.depth - runner_up > 1e-6 && !near_miss => {
                assert_eq!(
                    got,
                    h.word,
                    "{name}: pixel {i} ({}, {})",
                    i as u32 % W,
                    i as u32 / W
                );
                checked += 1;
                covered += 1;
            }
            None if !near_miss => {
                assert_eq!(got, visbuf::VIS_NONE, "{name}: pixel {i} should be empty");
                checked += 1;
            }
            _ => {}
        }
    }
    assert!(
        covered > (W * H) as usize / 4,
        "{name}: the scene should cover the image ({covered})"
    );
    assert!(
        checked > (W * H) as usize * 9 / 10,
        "{name}: only {checked} unambiguous pixels"
    );
    let stats = renderer.inspect().read_laydown_stats(&prepared).unwrap();
    if let Some(s) = &stats {
        eprintln!(
            "{name}: {} triangles, {} a workgroup each, {} to the hardware part, {checked} \
             pixels checked",
            s.triangles, s.large, s.hybrid
        );
        assert_eq!(s.dropped, 0);
    }
    (renderer, stats)
}

#[test]
fn laydown_matches_an_f64_rasteriser_on_every_available_path() {
    let probe = ctx();
    let mut tested = 0;
    for path in PrimitiveIdPath::ALL {
        if !probe.device.features().contains(path.required_features()) {
            eprintln!(
                "path {} not on this adapter ({}): not tested here",
                path.name(),
                probe.adapter_line()
            );
            continue;
        }
        tested += 1;
        let mut config = RendererConfig::sized(W, H);
        config.geometry.primitive_id = Some(path);
        check_against_f64(config, path.name());
    }
    assert!(tested >= 1);
}

/// The compute laydown at the test size with split `extent` and target `target`.
fn compute_config(extent: f32, target: LaydownTarget) -> RendererConfig {
    {
        let mut rc = RendererConfig::sized(W, H);
        rc.geometry.laydown = Laydown::Compute;
        rc.geometry.compute_laydown_max_extent = extent;
        rc.geometry.compute_laydown_target = Some(target);
        rc
    }
}

#[test]
fn compute_laydown_matches_the_f64_rasteriser() {
    assert!(compute_device());
    let probe = ctx();
    // Both targets where the device has them (lavapipe: the buffer; the H200: both).
    for target in [LaydownTarget::Buffer, LaydownTarget::Texture] {
        if !probe.device.features().contains(target.required_features()) {
            eprintln!(
                "the {} target is not on this adapter ({}): not tested here",
                target.name(),
                probe.adapter_line()
            );
            // Forcing it is an error naming the feature, not a panic.
            let forced = Renderer::new(&probe.device, &probe.queue, {
                let mut rc = RendererConfig::sized(W, H);
                rc.geometry.laydown = Laydown::Compute;
                rc.geometry.compute_laydown_target = Some(target);
                rc
            });
            let message = forced.err().map(|e| e.to_string()).unwrap_or_default();
            assert!(message.contains("INT64"), "{message}");
            continue;
        }
        // The default split, every triangle an invocation (the largest extent), every
        // triangle a workgroup of the large-triangle pass (extent 0: its 64-bit edge
        // functions), and a split at 1 pixel that sends part of the scene's (small)
        // triangles there.
        for (extent, name) in [
            (gpu::config::COMPUTE_LAYDOWN_MAX_EXTENT, "compute"),
            (
                gpu::config::COMPUTE_LAYDOWN_EXTENT_LIMIT,
                "an invocation each",
            ),
            (0.0, "a workgroup each"),
            (1.0, "split at 1 pixel"),
        ] {
            let r = check_against_f64(
                compute_config(extent, target),
                &format!("{name}, {} target", target.name()),
            );
            assert_eq!(r.laydown(), Laydown::Compute);
            assert_eq!(r.laydown_target(), Some(target));
        }
    }
}

/// `mesh` with an opaque material (the demo's first albedo layer), one batch of `instances`.
fn plain_scene(mesh: Mesh, instances: Vec<Affine3A>) -> Scene {
    let (demo, _) = demo::build(&demo::DemoOptions {
        density: 0.01,
        ..Default::default()
    });
    Scene {
        data_layers: Vec::new(),
        meshes: vec![mesh],
        materials: vec![material("plain", ShaderKind::Opaque)],
        albedo_layers: vec![demo.albedo_layers[0].clone()],
        batches: vec![Batch {
            mesh: MeshId(0),
            material: MaterialId(0),
            instances,
        }],
        static_setups: Vec::new(),
        wind: None,
    }
}

/// Overlapping triangles from a few pixels to several times the image across, slivers
/// among them, over a background of two triangles far past every side of the view
/// (`front_camera`): most boxes hold many 8x8 blocks, and thin slanted ones mostly empty
/// ones, which is what the large-triangle pass's block rejection is for.
fn large_triangles_scene() -> (Scene, FrameInput) {
    let mut rng = testkit::Rng::new(17);
    let v = Vec3::new;
    let mut tris = vec![
        [
            v(-30.0, -30.0, -3.0),
            v(30.0, -30.0, -3.0),
            v(30.0, 30.0, -3.0),
        ],
        [
            v(-30.0, -30.0, -3.0),
            v(30.0, 30.0, -3.0),
            v(-30.0, 30.0, -3.0),
        ],
    ];
    for i in 0..120 {
        let centre = v(
            rng.range(-5.0, 5.0),
            rng.range(-3.0, 3.0),
            rng.range(-2.5, 1.0),
        );
        // Sizes in world units; 2.7 is the view's half-height at z = 0.
        let size = match i % 4 {
            0 => rng.range(0.05, 0.4),
            1 | 2 => rng.range(0.4, 2.5),
            _ => rng.range(2.5, 8.0),
        };
        let mut corner = || {
            centre
                + v(
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                    rng.range(-0.3, 0.3),
                ) * size
        };
        let (a, mut b, mut c) = (corner(), corner(), corner());
        if i % 5 == 0 {
            // A sliver: the third vertex close to the first edge.
            c = a.lerp(b, rng.range(0.2, 0.8)) + v(0.0, 0.02 * size, 0.0);
        }
        // Counter-clockwise seen from +z (the camera): front faces.
        if (b - a).truncate().perp_dot((c - a).truncate()) < 0.0 {
            std::mem::swap(&mut b, &mut c);
        }
        tris.push([a, b, c]);
    }
    let scene = plain_scene(triangles_mesh("large", &tris), vec![Affine3A::IDENTITY]);
    (scene, FrameInput::new(front_camera()))
}

#[test]
fn large_triangles_match_the_f64_rasteriser() {
    assert!(compute_device());
    let probe = ctx();
    let (scene, frame) = large_triangles_scene();
    for target in [LaydownTarget::Buffer, LaydownTarget::Texture] {
        if !probe.device.features().contains(target.required_features()) {
            continue; // compute_laydown_matches_the_f64_rasteriser says so
        }
        // Every triangle through the large-triangle pass, the default split, and a split
        // low enough that only slivers and specks stay with an invocation each.
        for extent in [0.0, gpu::config::COMPUTE_LAYDOWN_MAX_EXTENT, 4.0] {
            let config = compute_config(extent, target);
            let name = format!(
                "large triangles, split at {extent} px, {} target",
                target.name()
            );
            let (_, stats) = check_scene_against_f64(config, &name, &scene, &frame);
            let stats = stats.unwrap();
            assert!(stats.large >= 40, "{name}: {stats:?}");
        }
    }
}

/// A fan of huge triangles around a vertex `apex_x` m to the right of the view's centre,
/// its rim far to the left, `px_per_m` pixels a metre at z = 0. The rim vertices lie
/// alternately 2^18 px - 3000 and 2^18 + 3000 from the apex, two and two, so of two
/// triangles sharing an edge one box may reach past 2^18 px (2^26 subpixels) and the
/// other not (the large-triangle pass). Returns the fan and its two outer edges.
fn huge_fan(apex_x: f32, px_per_m: f32) -> (Mesh, [[Vec3; 2]; 2]) {
    let apex = Vec3::new(apex_x, 0.0, 0.0);
    let rim: Vec<Vec3> = (0..=40)
        .map(|i| {
            let px = if (i / 2) % 2 == 0 {
                262_144.0 - 3000.0
            } else {
                262_144.0 + 3000.0
            };
            Vec3::new(apex_x - px / px_per_m, -8.0 + 0.4 * i as f32, 0.0)
        })
        .collect();
    let tris: Vec<[Vec3; 3]> = rim
        .windows(2)
        .map(|r| {
            // Counter-clockwise seen from +z (the camera): front faces.
            if (r[0] - apex).truncate().perp_dot((r[1] - apex).truncate()) > 0.0 {
                [apex, r[0], r[1]]
            } else {
                [apex, r[1], r[0]]
            }
        })
        .collect();
    (
        triangles_mesh("huge fan", &tris),
        [[apex, rim[0]], [apex, rim[40]]],
    )
}

#[test]
fn huge_triangles_sharing_edges_leave_no_crack() {
    assert!(compute_device());
    let probe = ctx();
    let camera = front_camera();
    let vp = camera.view_projection(W as f32 / H as f32).as_dmat4();
    let screen = |p: Vec3| {
        let c = vp * p.as_dvec3().extend(1.0);
        DVec2::new(
            (c.x / c.w + 1.0) * 0.5 * f64::from(W),
            (1.0 - c.y / c.w) * 0.5 * f64::from(H),
        )
    };
    let px_per_m = (screen(Vec3::X) - screen(Vec3::ZERO)).x as f32;
    // Several apexes: whether a box-relative f32 difference rounds depends on the apex's
    // last bits, so one fan might happen to be exact.
    for apex_x in [5_000.0, 5_000.37, 5_001.1, 4_999.6, 5_002.9, 4_998.3] {
        let (mesh, outer) = huge_fan(apex_x, px_per_m);
        let scene = plain_scene(mesh, vec![Affine3A::IDENTITY]);
        for target in [LaydownTarget::Buffer, LaydownTarget::Texture] {
            if !probe.device.features().contains(target.required_features()) {
                continue; // compute_laydown_matches_the_f64_rasteriser says so
            }
            let name = format!("fan at {apex_x} m, {} target", target.name());
            let config = compute_config(gpu::config::COMPUTE_LAYDOWN_MAX_EXTENT, target);
            let mut r = Renderer::new(&probe.device, &probe.queue, config).unwrap();
            let prepared = r.prepare(&scene).unwrap();
            let (vis, _) = r
                .hooks()
                .render_laydown(&prepared, &FrameInput::new(camera))
                .unwrap();
            let stats = r.inspect().read_laydown_stats(&prepared).unwrap().unwrap();
            assert_eq!((stats.large, stats.hybrid), (40, 0), "{name}: {stats:?}");
            // Signed distance (pixels) of a pixel centre to each outer edge, positive on
            // the fan's side.
            let lines = outer.map(|[a, b]| (screen(a), screen(b)));
            let inside = |q: DVec2| {
                let d = lines.map(|(a, b)| (b - a).perp_dot(q - a) / (b - a).length());
                d[0] * d[1] < 0.0 && d[0].abs().min(d[1].abs()) > 1.0
            };
            let mut inner = 0;
            for y in 0..H {
                for x in 0..W {
                    let q = DVec2::new(f64::from(x) + 0.5, f64::from(y) + 0.5);
                    if inside(q) {
                        inner += 1;
                        assert_ne!(
                            vis[(y * W + x) as usize],
                            visbuf::VIS_NONE,
                            "{name}: crack at ({x}, {y})"
                        );
                    }
                }
            }
            assert!(
                inner > (W * H) as usize * 3 / 4,
                "{name}: {inner} pixels inside"
            );
        }
    }
}

/// One triangle (counter-clockwise seen from +z) per entry of `tris`, object space.
fn triangles_mesh(name: &str, tris: &[[Vec3; 3]]) -> Mesh {
    let positions: Vec<Vec3> = tris.iter().flatten().copied().collect();
    let n = positions.len();
    Mesh {
        name: name.into(),
        normals: vec![Vec3::Z; n],
        uvs: positions.iter().map(|p| p.truncate()).collect(),
        tangents: vec![glam::Vec4::new(1.0, 0.0, 0.0, 1.0); n],
        indices: (0..n as u16).collect(),
        positions,
    }
}

#[test]
fn awkward_triangles_neither_hang_nor_spill_and_near_ones_reach_the_hardware_part() {
    if !compute_device() {
        return;
    }
    let v = Vec3::new;
    // Looking down -z from z = 5 (near 0.5): the scene lies around z = 0.
    let tris = [
        // A plain small triangle.
        [v(-1.0, -1.0, 0.0), v(-0.6, -1.0, 0.0), v(-0.8, -0.6, 0.0)],
        // Degenerate: two equal vertices, and three collinear ones.
        [v(0.2, 0.2, 0.0), v(0.2, 0.2, 0.0), v(0.5, 0.6, 0.0)],
        [v(0.0, 0.0, 0.0), v(0.1, 0.1, 0.0), v(0.2, 0.2, 0.0)],
        // Huge: the left half of the view and far past it (the large-triangle pass).
        [
            v(-60.0, -60.0, -1.0),
            v(-0.1, -60.0, -1.0),
            v(-0.1, 60.0, -1.0),
        ],
        // Off screen on every side.
        [v(40.0, 0.0, 0.0), v(41.0, 0.0, 0.0), v(40.5, 1.0, 0.0)],
        [v(0.0, -40.0, 0.0), v(1.0, -40.0, 0.0), v(0.5, -39.0, 0.0)],
        // Behind the camera, entirely.
        [v(0.0, 0.0, 9.0), v(1.0, 0.0, 9.0), v(0.5, 1.0, 9.0)],
        // Crossing the near plane (z = 4.5) and the eye plane: one vertex behind the eye.
        [v(0.3, -1.2, 0.5), v(1.4, -1.2, 0.5), v(0.8, 2.0, 6.0)],
        // Back-facing (clockwise from the camera).
        [v(0.6, 0.6, 0.0), v(0.8, 1.0, 0.0), v(1.0, 0.6, 0.0)],
    ];
    let scene = plain_scene(
        triangles_mesh("awkward", &tris),
        vec![
            Affine3A::IDENTITY,
            // A finite transform whose clip coordinates overflow to infinity and NaN.
            Affine3A::from_scale(Vec3::splat(3.0e38)),
        ],
    );
    let camera = front_camera();
    let frame = FrameInput::new(camera);
    let probe = ctx();
    let render = |laydown| {
        let mut config = RendererConfig::sized(W, H);
        config.geometry.laydown = laydown;
        let mut r = Renderer::new(&probe.device, &probe.queue, config).unwrap();
        let prepared = r.prepare(&scene).unwrap();
        let (vis, _) = r.hooks().render_laydown(&prepared, &frame).unwrap();
        (vis, r.inspect().read_laydown_stats(&prepared).unwrap())
    };
    let (hardware, _) = render(Laydown::Hardware);
    let (compute, stats) = render(Laydown::Compute);
    let stats = stats.unwrap();
    eprintln!("awkward: {stats:?}");
    // The near-plane triangle of each instance with finite coordinates goes to the
    // hardware part, the huge one to the large-triangle pass.
    assert!(stats.hybrid >= 1 && stats.large >= 1, "{stats:?}");
    assert_eq!(stats.dropped, 0);
    let at = |img: &[u32], x: i64, y: i64| {
        (x >= 0 && y >= 0 && x < i64::from(W) && y < i64::from(H))
            .then(|| img[(y * i64::from(W) + x) as usize])
    };
    // Every word either image writes, the other writes within one pixel: no pixel outside
    // its triangle (but for edge pixels), nothing lost (the near-plane triangle included).
    let mut differ = 0;
    for (a, b, name) in [
        (&compute, &hardware, "compute"),
        (&hardware, &compute, "hardware"),
    ] {
        for y in 0..i64::from(H) {
            for x in 0..i64::from(W) {
                let w = at(a, x, y).unwrap();
                if w == at(b, x, y).unwrap() {
                    continue;
                }
                differ += 1;
                if w == visbuf::VIS_NONE {
                    continue;
                }
                let near = (-1..=1)
                    .flat_map(|dy| (-1..=1).map(move |dx| (dx, dy)))
                    .any(|(dx, dy)| at(b, x + dx, y + dy) == Some(w));
                assert!(
                    near,
                    "{name}: word {w:#x} at ({x}, {y}) is nowhere near the other image's"
                );
            }
        }
    }
    assert!(differ < (W * H) as usize / 50, "{differ} pixels differ");
    // The near-plane triangle (primitive 7 of instance 0) is drawn.
    let words: std::collections::BTreeSet<u32> = compute.iter().copied().collect();
    let bits = PrimitiveBits::for_count(tris.len() as u32).unwrap();
    let primitive = |w: u32| VisId(w).primitive(bits);
    assert!(
        words
            .iter()
            .any(|&w| w != visbuf::VIS_NONE && primitive(w) == 7),
        "the near-plane triangle is missing"
    );
}
