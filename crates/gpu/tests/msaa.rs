//! KZ2's MSAA on the baseline path: the edge pixels are exactly the pixels a brute-force
//! coverage test at the standard 4x sample positions finds partly covered, they resolve to
//! the coverage-weighted average of their surfaces, KZ2's tricks give the image of
//! lighting every sample, and the configurations MSAA cannot serve are refused.

mod common;

use demo::{DemoOptions, DemoScene};
use glam::{Affine3A, Mat4, Vec2, Vec3, Vec4};
use gpu::config::{LightPaths, MsaaLighting};
use gpu::scene::{AlbedoLayer, MaterialId, MeshId, ShaderKind};
use gpu::{
    Batch, Camera, FrameInput, Material, Mesh, RenderPath, RendererConfig, Rgba8Image, Scene,
};

const W: u32 = 96;
const H: u32 = 64;

/// Vulkan's (and D3D's) standard 4x sample positions within a pixel.
const SAMPLES: [Vec2; 4] = [
    Vec2::new(0.375, 0.125),
    Vec2::new(0.875, 0.375),
    Vec2::new(0.125, 0.625),
    Vec2::new(0.625, 0.875),
];

/// One flat, matte, single-coloured quad facing the camera, turned 17° in its plane, the
/// sky behind it: its lit colour is the same at every covered sample.
fn quad_scene() -> (Scene, FrameInput, [Vec3; 4]) {
    let (s, c) = 17f32.to_radians().sin_cos();
    let corners = [(-1.3, -0.9), (1.3, -0.9), (1.3, 0.9), (-1.3, 0.9)]
        .map(|(x, y): (f32, f32)| Vec3::new(x * c - y * s, x * s + y * c, 0.0));
    let mesh = Mesh {
        name: "quad".into(),
        positions: corners.to_vec(),
        normals: vec![Vec3::Z; 4],
        uvs: vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y],
        tangents: vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 4],
        // Counter-clockwise seen from +Z (the camera).
        indices: vec![0, 1, 2, 0, 2, 3],
    };
    let scene = Scene {
        data_layers: Vec::new(),
        meshes: vec![mesh],
        materials: vec![Material {
            name: "matte".into(),
            shader: ShaderKind::Opaque,
            albedo_layer: 0,
            tint: Vec3::ONE,
            alpha_cutoff: 0.5,
            roughness: 1.0,
            specular: 0.0,
            regular: false,
            ..Default::default()
        }],
        albedo_layers: vec![AlbedoLayer {
            size: 4,
            texels: vec![[200, 90, 40, 255]; 16],
        }],
        batches: vec![Batch {
            mesh: MeshId(0),
            material: MaterialId(0),
            instances: vec![Affine3A::IDENTITY],
        }],
        static_setups: Vec::new(),
        wind: None,
    };
    let mut frame = FrameInput::new(Camera::look_at(Vec3::new(0.0, 0.0, 2.6), Vec3::ZERO));
    frame.lighting.sun_direction = Vec3::new(0.3, 0.4, 0.9);
    (scene, frame, corners)
}

fn config(msaa: Option<MsaaLighting>) -> RendererConfig {
    {
        let mut rc = RendererConfig::sized(W, H);
        rc.image.msaa = msaa;
        rc.lighting.shadows = None;
        rc.lighting.spot_shadows = None;
        rc.lighting.baked_sun = false;
        rc
    }
}

fn srgb_decode(c: u8) -> f64 {
    let c = f64::from(c) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

fn srgb_encode(c: f64) -> f64 {
    if c <= 0.0031308 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// Per pixel, how many of its four samples the quad covers (brute force, in f64), or
/// `None` where a sample lies within 1e-3 pixels of the quad's outline (the rasteriser's
/// tie-breaking decides those).
fn coverage(frame: &FrameInput, corners: &[Vec3; 4]) -> Vec<Option<u32>> {
    let cam = &frame.camera;
    let view_proj: Mat4 = cam.projection(W as f32 / H as f32) * cam.view();
    let screen: Vec<(f64, f64)> = corners
        .iter()
        .map(|&p| {
            let c = view_proj * p.extend(1.0);
            let (x, y) = (f64::from(c.x / c.w), f64::from(c.y / c.w));
            (
                (x * 0.5 + 0.5) * f64::from(W),
                (0.5 - y * 0.5) * f64::from(H),
            )
        })
        .collect();
    // Signed distance in pixels to each outline edge (positive inside: the outline is
    // convex and wound the same way throughout).
    let side = |px: f64, py: f64, i: usize| {
        let (ax, ay) = screen[i];
        let (bx, by) = screen[(i + 1) % 4];
        let (ex, ey) = (bx - ax, by - ay);
        (ex * (py - ay) - ey * (px - ax)) / (ex * ex + ey * ey).sqrt()
    };
    let sign = side(screen[2].0, screen[2].1, 0).signum();
    (0..W * H)
        .map(|i| {
            let (x, y) = (f64::from(i % W), f64::from(i / W));
            let mut n = 0;
            for s in SAMPLES {
                let (px, py) = (x + f64::from(s.x), y + f64::from(s.y));
                let d = (0..4)
                    .map(|e| sign * side(px, py, e))
                    .fold(f64::MAX, f64::min);
                if d.abs() < 1e-3 {
                    return None;
                }
                n += u32::from(d > 0.0);
            }
            Some(n)
        })
        .collect()
}

/// The edge list is the brute-force set of partly covered pixels, and every pixel is the
/// coverage-weighted average of the quad's and the sky's tone-mapped colours (within
/// 2 / 255), both with KZ2's tricks and with every sample lit; fully covered and empty
/// pixels equal the single-sample image.
#[test]
fn edges_are_the_partly_covered_pixels_and_resolve_to_their_coverage() {
    let (scene, frame, corners) = quad_scene();
    let cover = coverage(&frame, &corners);
    let partly: Vec<u32> = (0..W * H)
        .filter(|&i| matches!(cover[i as usize], Some(1..=3)))
        .collect();
    let ambiguous = cover.iter().filter(|c| c.is_none()).count();
    assert!(partly.len() > 100, "{} partly covered", partly.len());

    let mut single = common::renderer_with(config(None));
    let prepared = single.prepare(&scene).unwrap();
    single
        .render(&prepared, &frame, RenderPath::Baseline)
        .unwrap();
    let single = single.read_output().unwrap();

    for mode in [MsaaLighting::Kz2, MsaaLighting::EverySample] {
        let mut r = common::renderer_with(config(Some(mode)));
        let prepared = r.prepare(&scene).unwrap();
        r.render(&prepared, &frame, RenderPath::Baseline).unwrap();
        let image = r.read_output().unwrap();
        let edges = r.inspect().read_msaa_edges().unwrap();
        if mode == MsaaLighting::Kz2 {
            let missing = partly.iter().filter(|p| edges.binary_search(p).is_err());
            let extra = edges
                .iter()
                .filter(|&&p| cover[p as usize].is_some() && partly.binary_search(&p).is_err());
            let (missing, extra) = (missing.count(), extra.count());
            eprintln!(
                "{} edges, {} partly covered, {ambiguous} ambiguous: {missing} missing, {extra} extra",
                edges.len(),
                partly.len()
            );
            assert_eq!((missing, extra), (0, 0));
        } else {
            assert!(edges.is_empty(), "every sample lit: no edge list");
        }
        check_resolve(&image, &single, &cover);
    }
}

/// Pixels of `image` against the coverage-weighted average of `single`'s quad and sky.
fn check_resolve(image: &Rgba8Image, single: &Rgba8Image, cover: &[Option<u32>]) {
    let px = |i: usize| image.pixels[i];
    // The quad's and the sky's tone-mapped colours, from the single-sample image.
    let inside = cover.iter().position(|&c| c == Some(4)).unwrap();
    let outside = cover.iter().position(|&c| c == Some(0)).unwrap();
    let (q, s) = (single.pixels[inside], single.pixels[outside]);
    let mut worst = 0i32;
    for (i, c) in cover.iter().enumerate() {
        let Some(k) = *c else { continue };
        let want: [i32; 3] = std::array::from_fn(|ch| {
            if k == 0 || k == 4 {
                return i32::from(single.pixels[i][ch]);
            }
            let (a, b) = (srgb_decode(q[ch]), srgb_decode(s[ch]));
            let mix = (f64::from(k) * a + f64::from(4 - k) * b) / 4.0;
            (srgb_encode(mix) * 255.0).round() as i32
        });
        for (ch, &w) in want.iter().enumerate() {
            let e = (i32::from(px(i)[ch]) - w).abs();
            worst = worst.max(e);
            assert!(
                e <= 2,
                "pixel {} {} (coverage {k}/4) channel {ch}: {} vs {w}",
                i % W as usize,
                i / W as usize,
                px(i)[ch],
            );
        }
    }
    eprintln!("resolve vs coverage: worst {worst} / 255");
}

/// On the lit forest (local lights, shadowed spots, alpha-tested foliage), KZ2's tricks
/// give the image of lighting every sample. An interior pixel is lit once at its centre,
/// every sample at four points of the same plane: without shadow maps the edge pixels are
/// equal (within 1 / 255) and the interior ones differ by the lighting's curvature across
/// the pixel (near a light: over 4 / 255 at fewer than 0.1% of the pixels); with the sun's
/// and the spots' maps, also where the PCF changes within a pixel (the test's 512-texel
/// sun maps put about a texel under each pixel) and by the split taps on the edges: less
/// than 1 / 255 on average, over 4 / 255 at fewer than 3% of the pixels.
#[test]
fn kz2_tricks_give_the_every_sample_image() {
    let (scene, mut frame) = demo::build(&DemoOptions {
        scene: DemoScene::Forest,
        seed: 3,
        density: 0.25,
    });
    let target = frame.camera.target;
    demo::scatter_lights(&mut frame.lighting, target, 12.0, 40, 5);
    let render = |mode, shadows| {
        let mut r = common::renderer_with({
            let mut rc = RendererConfig::sized(320, 192);
            rc.image.msaa = Some(mode);
            rc.lighting.shadows = shadows;
            rc.lighting.spot_shadows = shadows.map(|_| gpu::config::SpotShadowConfig::default());
            rc
        });
        let prepared = r.prepare(&scene).unwrap();
        r.render(&prepared, &frame, RenderPath::Baseline).unwrap();
        (
            r.read_output().unwrap(),
            r.inspect().read_msaa_edges().unwrap(),
        )
    };
    for shadows in [None, common::test_shadows()] {
        let (kz2, edges) = render(MsaaLighting::Kz2, shadows);
        let (every, _) = render(MsaaLighting::EverySample, shadows);
        let n = kz2.pixels.len();
        let diff: Vec<i32> = (0..n)
            .map(|i| {
                (0..3)
                    .map(|c| (i32::from(kz2.pixels[i][c]) - i32::from(every.pixels[i][c])).abs())
                    .max()
                    .unwrap()
            })
            .collect();
        let worst = diff.iter().copied().max().unwrap();
        let over4 = diff.iter().filter(|&&d| d > 4).count();
        let mean = diff.iter().map(|&d| f64::from(d)).sum::<f64>() / n as f64;
        let edge_worst = edges.iter().map(|&p| diff[p as usize]).max().unwrap_or(0);
        eprintln!(
            "shadow maps {}: {} edge pixels of {n}; worst {worst} / 255 (edges {edge_worst}), mean {mean:.3}, {over4} over 4",
            shadows.is_some(),
            edges.len()
        );
        assert!(
            edges.len() > n / 50 && edges.len() < n / 4,
            "{}",
            edges.len()
        );
        if shadows.is_none() {
            // The edges are lit the same way; interior pixels differ by the lights'
            // curvature across the pixel (near a light's centre).
            assert!(edge_worst <= 1, "edges: worst {edge_worst}");
            assert!(mean < 0.1, "mean {mean}");
            assert!(over4 * 1000 < n, "{over4} over 4 / 255");
        } else {
            assert!(mean < 1.0, "mean {mean}");
            assert!(over4 * 100 < n * 3, "{over4} over 4 / 255");
        }
    }
}

/// MSAA with stencil volumes is refused naming the field; the deferred path of an MSAA
/// renderer renders single-sample, the image of a renderer without MSAA.
#[test]
fn msaa_refuses_what_it_cannot_serve() {
    let bad = RendererConfig {
        lighting: gpu::config::LightingConfig {
            light_paths: LightPaths::Volumes,
            ..config(Some(MsaaLighting::Kz2)).lighting
        },
        ..config(Some(MsaaLighting::Kz2))
    };
    let e = bad.validate().unwrap_err().to_string();
    assert!(e.contains("RendererConfig::image.msaa"), "{e}");

    let (scene, frame, _) = quad_scene();
    let mut r = common::renderer_with(config(Some(MsaaLighting::Kz2)));
    let prepared = r.prepare(&scene).unwrap();
    r.render(&prepared, &frame, RenderPath::Deferred).unwrap();
    let mut plain = common::renderer_with(config(None));
    let p = plain.prepare(&scene).unwrap();
    plain.render(&p, &frame, RenderPath::Deferred).unwrap();
    assert_eq!(
        common::differing_pixels(&r.read_output().unwrap(), &plain.read_output().unwrap()),
        0
    );
}
