//! Which laydown runs: the compute laydown's fallback without 64-bit atomics, alpha-tested
//! cards through both laydowns against a trilinear reference, and `Laydown::Auto`'s trial.

mod common;

use common::laydown::{H, W, compute_device, front_camera, test_scene};
use common::material;
use gpu::glam::{Affine3A, DVec2, DVec3, Quat, Vec3};
use gpu::scene::{AlbedoLayer, MaterialId, MeshId, ShaderKind};
use gpu::{Batch, FrameInput, Laydown, Mesh, Renderer, RendererConfig, Scene};
use testkit::device::ctx;

#[test]
fn the_compute_laydown_falls_back_to_the_hardware_one_without_64_bit_atomics() {
    let c = gpu::headless(&gpu::HeadlessOptions {
        disable_features: wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX,
        ..Default::default()
    })
    .unwrap();
    assert!(!c.paths.int64_atomics);
    let mut config = RendererConfig::sized(W, H);
    config.geometry.laydown = Laydown::Compute;
    let mut r = Renderer::new(&c.device, &c.queue, config).unwrap();
    assert_eq!(r.laydown(), Laydown::Hardware);
    let (scene, frame) = test_scene();
    let prepared = r.prepare(&scene).unwrap();
    let (vis, _) = r.hooks().render_laydown(&prepared, &frame).unwrap();
    assert!(vis.iter().any(|&w| w != visbuf::VIS_NONE));
    assert_eq!(r.inspect().read_laydown_stats(&prepared).unwrap(), None);
}

/// Trilinear alpha of `chain` (level 0 first, `size` texels square at level 0) at `uv` and
/// level `lod`, repeat addressing: what the albedo sampler returns, in f64.
fn trilinear_alpha(chain: &[Vec<[u8; 4]>], size: u32, uv: DVec2, lod: f64) -> f64 {
    let bilinear = |level: usize| {
        let s = (size >> level).max(1) as i64;
        let x = uv.x * s as f64 - 0.5;
        let y = uv.y * s as f64 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let texel = |i: i64, j: i64| {
            let (i, j) = (i.rem_euclid(s), j.rem_euclid(s));
            f64::from(chain[level][(j * s + i) as usize][3]) / 255.0
        };
        let (i, j) = (x0 as i64, y0 as i64);
        let top = texel(i, j) * (1.0 - fx) + texel(i + 1, j) * fx;
        let bottom = texel(i, j + 1) * (1.0 - fx) + texel(i + 1, j + 1) * fx;
        top * (1.0 - fy) + bottom * fy
    };
    let lod = lod.clamp(0.0, (chain.len() - 1) as f64);
    let l0 = lod.floor() as usize;
    let l1 = (l0 + 1).min(chain.len() - 1);
    let t = lod - l0 as f64;
    bilinear(l0) * (1.0 - t) + bilinear(l1) * t
}

/// Issue 17: alpha-tested cards give the same vis buffer in the compute laydown (alpha at
/// the level of the analytic UV derivatives, `textureSampleLevel`) and the hardware one
/// (`textureSample`, the level from 2x2-quad differences). The stated bound: every pixel
/// where the two differ lies on a card where the trilinear alpha, over the levels within
/// one of the analytic level, reaches the cutoff (to 1/255, the texels' step); every other
/// pixel holds the same word in both. Six cards from magnified (level < 0) to four texels
/// a pixel and one at 60 degrees, an alpha pattern crossing the cutoff many times.
#[test]
fn alpha_tested_cards_agree_between_the_compute_and_hardware_laydowns_within_one_level() {
    assert!(compute_device());
    // Twice the other tests' image: more pixels on each card.
    const W: u32 = 320;
    const H: u32 = 192;
    const SIZE: u32 = 64;
    let mut texels = Vec::new();
    for j in 0..SIZE {
        for i in 0..SIZE {
            let (u, v) = (
                (f64::from(i) + 0.5) / f64::from(SIZE),
                (f64::from(j) + 0.5) / f64::from(SIZE),
            );
            let a = 0.5
                + 0.5
                    * (std::f64::consts::TAU * (2.0 * u + 0.3)).sin()
                    * (std::f64::consts::TAU * 2.0 * v).sin();
            texels.push([128, 160, 96, (a * 255.0).round() as u8]);
        }
    }
    let layer = AlbedoLayer { size: SIZE, texels };
    let chain = layer.mip_chain();
    // Cards: centre, UV scale, rotation about y (radians); 1.4 m squares in the z = 0 plane
    // facing the camera at z = 5.
    let cards = [
        (Vec3::new(-2.2, 1.1, 0.0), 0.25, 0.0),
        (Vec3::new(0.0, 1.1, 0.0), 0.5, 0.0),
        (Vec3::new(2.2, 1.1, 0.0), 1.0, 0.0),
        (Vec3::new(-2.2, -1.1, 0.0), 2.0, 0.0),
        (Vec3::new(0.0, -1.1, 0.0), 4.0, 0.0),
        (Vec3::new(2.2, -1.1, 0.0), 1.0, 1.05),
    ];
    let half = 0.7f32;
    let mut meshes = Vec::new();
    let mut batches = Vec::new();
    // Per card: its four corners (world) and their UVs.
    let mut quads = Vec::new();
    for (k, &(centre, scale, angle)) in cards.iter().enumerate() {
        let corners = [
            Vec3::new(-half, -half, 0.0),
            Vec3::new(half, -half, 0.0),
            Vec3::new(half, half, 0.0),
            Vec3::new(-half, half, 0.0),
        ];
        let uvs: Vec<glam::Vec2> = [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]]
            .iter()
            .map(|c| glam::Vec2::new(c[0] * scale, c[1] * scale))
            .collect();
        meshes.push(Mesh {
            name: format!("card {k}"),
            positions: corners.to_vec(),
            normals: vec![Vec3::Z; 4],
            uvs: uvs.clone(),
            tangents: vec![glam::Vec4::new(1.0, 0.0, 0.0, 1.0); 4],
            indices: vec![0, 1, 2, 0, 2, 3],
        });
        let t = Affine3A::from_rotation_translation(Quat::from_rotation_y(angle), centre);
        batches.push(Batch {
            mesh: MeshId(k),
            material: MaterialId(0),
            instances: vec![t],
        });
        quads.push((
            corners.map(|c| t.transform_point3(c).as_dvec3()),
            uvs.iter().map(|u| u.as_dvec2()).collect::<Vec<_>>(),
        ));
    }
    let scene = Scene {
        data_layers: Vec::new(),
        meshes,
        materials: vec![material("card", ShaderKind::AlphaTested)],
        albedo_layers: vec![layer],
        batches,
        static_setups: Vec::new(),
        wind: None,
    };
    let camera = front_camera();
    let frame = FrameInput::new(camera);
    let probe = ctx();
    let vis = |laydown| {
        let mut r = Renderer::new(&probe.device, &probe.queue, {
            let mut rc = RendererConfig::sized(W, H);
            rc.geometry.laydown = laydown;
            rc
        })
        .unwrap();
        assert_eq!(r.laydown(), laydown);
        let prepared = r.prepare(&scene).unwrap();
        r.hooks().render_laydown(&prepared, &frame).unwrap().0
    };
    let (hardware, compute) = (vis(Laydown::Hardware), vis(Laydown::Compute));

    // The f64 reference: per pixel, the card under its centre (away from the card's
    // edges), the perspective-correct UV and the analytic level.
    let vp = camera
        .view_projection(f64::from(W) as f32 / H as f32)
        .as_dmat4();
    let screen = |p: DVec3| {
        let c = vp * p.extend(1.0);
        (
            DVec2::new(
                (c.x / c.w + 1.0) * 0.5 * f64::from(W),
                (1.0 - c.y / c.w) * 0.5 * f64::from(H),
            ),
            c.w,
        )
    };
    let (mut both, mut differ, mut straddling) = (0, 0, 0);
    for py in 0..H {
        for px in 0..W {
            let i = (py * W + px) as usize;
            let q = DVec2::new(f64::from(px) + 0.5, f64::from(py) + 0.5);
            // UV at screen point `q` on the card's triangle containing it, and the distance
            // to the nearest card edge (negative outside).
            let mut sample = None;
            for (corners, uvs) in &quads {
                let s: Vec<(DVec2, f64)> = corners.iter().map(|&c| screen(c)).collect();
                for tri in [[0, 1, 2], [0, 2, 3]] {
                    let p = tri.map(|k| s[k].0);
                    let area = (p[1] - p[0]).perp_dot(p[2] - p[0]);
                    let uv_at = |q: DVec2| {
                        let e = DVec3::new(
                            (p[2] - p[1]).perp_dot(q - p[1]),
                            (p[0] - p[2]).perp_dot(q - p[2]),
                            (p[1] - p[0]).perp_dot(q - p[0]),
                        ) / area;
                        let w = DVec3::new(e.x / s[tri[0]].1, e.y / s[tri[1]].1, e.z / s[tri[2]].1);
                        let w = w / (w.x + w.y + w.z);
                        (e, uvs[tri[0]] * w.x + uvs[tri[1]] * w.y + uvs[tri[2]] * w.z)
                    };
                    let (e, uv) = uv_at(q);
                    if e.min_element() < 0.0 {
                        continue;
                    }
                    let d = 1e-3;
                    let dx = (uv_at(q + DVec2::new(d, 0.0)).1 - uv_at(q - DVec2::new(d, 0.0)).1)
                        / (2.0 * d);
                    let dy = (uv_at(q + DVec2::new(0.0, d)).1 - uv_at(q - DVec2::new(0.0, d)).1)
                        / (2.0 * d);
                    let rho = (dx * f64::from(SIZE))
                        .length()
                        .max((dy * f64::from(SIZE)).length());
                    // Distance in pixels to the card's outline (the two edges of this
                    // triangle that are not the diagonal 0-2).
                    let edge_distance =
                        |a: DVec2, b: DVec2| (b - a).perp_dot(q - a).abs() / (b - a).length();
                    let outline_distance = match tri {
                        [0, 1, 2] => edge_distance(p[0], p[1]).min(edge_distance(p[1], p[2])),
                        _ => edge_distance(p[1], p[2]).min(edge_distance(p[2], p[0])),
                    };
                    sample = Some((uv, rho.log2(), outline_distance));
                }
            }
            let (hw, cs) = (hardware[i], compute[i]);
            let Some((uv, lod, outline)) = sample else {
                assert_eq!(
                    (hw, cs),
                    (visbuf::VIS_NONE, visbuf::VIS_NONE),
                    "pixel ({px}, {py}) off the cards"
                );
                continue;
            };
            if outline < 0.01 {
                continue;
            }
            let alphas: Vec<f64> = [lod - 1.0, lod.floor(), lod.ceil(), lod + 1.0, lod]
                .iter()
                .map(|&l| trilinear_alpha(&chain, SIZE, uv, l))
                .collect();
            let lo = alphas.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = alphas.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let reaches = lo - 1.0 / 255.0 <= 0.5 && 0.5 <= hi + 1.0 / 255.0;
            straddling += usize::from(reaches);
            if hw != visbuf::VIS_NONE && cs != visbuf::VIS_NONE {
                both += 1;
            }
            if hw != cs {
                differ += 1;
                assert!(
                    reaches,
                    "pixel ({px}, {py}): hardware {hw:#x}, compute {cs:#x}, but the alpha over \
                     levels {:.2}..{:.2} is {lo:.3}..{hi:.3}, clear of the cutoff 0.5",
                    lod - 1.0,
                    lod + 1.0
                );
            }
        }
    }
    eprintln!(
        "alpha-tested cards: {both} pixels covered by both laydowns, {differ} differ, {straddling} \
         within one level of the cutoff"
    );
    assert!(both > 1000, "the cards should cover the image ({both})");
    assert!(
        straddling > 50,
        "the alpha pattern should cross the cutoff ({straddling})"
    );
    assert!(differ <= straddling);
}

/// The time `Laydown::Auto` counts for a frame: its GPU passes summed, else its wall time.
fn frame_ms(out: &gpu::FrameOutput) -> f64 {
    if out.gpu.is_empty() {
        out.wall_ms
    } else {
        out.gpu.iter().map(|t| t.ms).sum()
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

#[test]
fn auto_times_both_laydowns_then_keeps_the_faster() {
    assert!(compute_device());
    let c = ctx();
    let mut config = RendererConfig::sized(W, H);
    config.geometry.laydown = Laydown::Auto;
    let mut r = Renderer::new(&c.device, &c.queue, config).unwrap();
    let (scene, frame) = test_scene();
    let prepared = r.prepare(&scene).unwrap();
    let trial = 2 * (1 + gpu::config::AUTO_LAYDOWN_FRAMES);
    // Frames without a laydown leave the trial where it is.
    r.render(&prepared, &frame, gpu::RenderPath::Baseline)
        .unwrap();
    assert_eq!(
        r.laydown_choice().reason,
        gpu::config::LaydownReason::Trial {
            frames_left: trial as u32
        }
    );
    let mut times = [Vec::new(), Vec::new()];
    for k in 0..trial {
        let asked = r.laydown();
        assert!(matches!(
            r.laydown_choice().reason,
            gpu::config::LaydownReason::Trial { .. }
        ));
        // `submit` waits during the trial, so every trial frame is timed.
        let out = r
            .submit(&prepared, &frame, gpu::RenderPath::Deferred)
            .unwrap();
        let expected = if k % 2 == 0 {
            Laydown::Hardware
        } else {
            Laydown::Compute
        };
        assert_eq!(
            (asked, out.laydown),
            (expected, Some(expected)),
            "frame {k}"
        );
        assert!(out.wall_ms > 0.0);
        if k >= 2 {
            times[k % 2].push(frame_ms(&out));
        }
    }
    let (h, c) = (median(times[0].clone()), median(times[1].clone()));
    let choice = r.laydown_choice();
    match choice.reason {
        gpu::config::LaydownReason::Measured {
            hardware_ms,
            compute_ms,
            ..
        } => {
            assert_eq!((hardware_ms, compute_ms), (h, c));
        }
        other => panic!("{other:?}"),
    }
    let faster = if c < h {
        Laydown::Compute
    } else {
        Laydown::Hardware
    };
    assert_eq!(choice.laydown, faster, "hardware {h} ms, compute {c} ms");
    println!(
        "Laydown::Auto on {}: hardware {h:.3} ms, compute {c:.3} ms -> {faster:?}",
        ctx().adapter_line()
    );
    for _ in 0..3 {
        let out = r
            .render(&prepared, &frame, gpu::RenderPath::Deferred)
            .unwrap();
        assert_eq!(out.laydown, Some(faster));
    }
}
