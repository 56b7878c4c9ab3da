//! Seed 004's path on a device (lavapipe in CI, which has no hardware barycentrics: the
//! fragment stage traces the pixel's camera ray against its triangle, `visbuf::ray`):
//! its image matches HZD's depth-equal baseline within the bounds the deferred-vs-baseline
//! comparison uses, on the adapter's primitive-ID path and on the provoking-vertex one
//! (payloads), and corrupt primitive IDs never reach past an array: an ID past its mesh
//! writes nothing, random ones render without a device error. (The hardware-barycentric
//! variant is composed and naga-validated down to SPIR-V in the crate's unit tests.)

mod common;

use demo::{DemoOptions, DemoScene};
use gpu::config::PrimitiveIdPath;
use gpu::inspect::diff_metrics;
use gpu::{RenderPath, RendererConfig, Scene};
use testkit::device::ctx;

const W: u32 = 256;
const H: u32 = 144;

fn scene(kind: DemoScene) -> (Scene, gpu::FrameInput) {
    demo::build(&DemoOptions {
        scene: kind,
        seed: 7,
        density: 0.25,
    })
}

fn renderer(primitive_id: Option<PrimitiveIdPath>) -> gpu::Renderer {
    common::renderer_with({
        let mut rc = RendererConfig::sized(W, H);
        rc.geometry.primitive_id = primitive_id;
        rc.lighting.shadows = common::test_shadows();
        rc
    })
}

/// The bounds of `tests/frame.rs`'s deferred-vs-baseline comparison (set on llvmpipe,
/// LLVM 15, Mesa 22.3.6). Measured there at 256x144: mean 0.021 (forest), 0.032 (grass),
/// p99 1-2, on both primitive-ID paths (the ray fallback's gradients are visbuf's analytic
/// ones; with quad differences of the pulled UVs instead, 0.75 and 0.93, p99 13 and 18:
/// llvmpipe gives the baseline's varyings their plane's exact gradient).
const MAX_MEAN_ERROR: f64 = 1.0;
const MAX_P99_ERROR: u8 = 24;

#[test]
fn the_pixel_pull_image_matches_the_baseline() {
    let paths = [None, Some(PrimitiveIdPath::ProvokingVertex)];
    for kind in DemoScene::ALL {
        let (scene, frame) = scene(kind);
        for path in paths {
            let mut r = renderer(path);
            assert!(
                !r.paths().barycentrics || !ctx().info.name.contains("llvmpipe"),
                "lavapipe has no hardware barycentrics: the ray fallback is what runs"
            );
            let prepared = r.prepare(&scene).unwrap();
            r.render(&prepared, &frame, RenderPath::Baseline).unwrap();
            let baseline = r.read_output().unwrap();
            let baseline_gbuffer = r.inspect().read_gbuffer().unwrap();
            r.render(&prepared, &frame, RenderPath::PixelPull).unwrap();
            let pull = r.read_output().unwrap();
            let pull_gbuffer = r.inspect().read_gbuffer().unwrap();
            if path.is_none() {
                pull.write_png(&std::env::temp_dir().join(format!("pull_{}.png", kind.name())))
                    .unwrap();
            }
            let (mean, _) = diff_metrics(&pull, &baseline, 0.5).unwrap();
            let (_, p99) = diff_metrics(&pull, &baseline, 0.99).unwrap();
            // The G-buffer's albedo, texel for texel: what the pulled UVs sampled.
            let albedo_worst = pull_gbuffer
                .iter()
                .zip(&baseline_gbuffer)
                .map(|(a, b)| (a.albedo - b.albedo).abs().max_element())
                .fold(0.0f32, f32::max);
            eprintln!(
                "{} {}: pixel pull ({}) vs baseline mean {mean:.3} / 255, p99 {p99} / 255, worst albedo {albedo_worst:.3}, on {}",
                kind.name(),
                r.paths().primitive_id.name(),
                if r.paths().barycentrics {
                    "hardware barycentrics"
                } else {
                    "ray fallback"
                },
                ctx().adapter_line()
            );
            assert!(
                mean <= MAX_MEAN_ERROR && p99 <= MAX_P99_ERROR,
                "{}: pixel pull vs baseline mean {mean:.3}, p99 {p99}",
                kind.name()
            );
            let distinct: std::collections::BTreeSet<[u8; 4]> =
                pull.pixels.iter().copied().collect();
            assert!(distinct.len() > 500, "{}: a blank image", kind.name());
        }
    }
}

#[test]
fn corrupt_primitive_ids_never_read_out_of_bounds() {
    let (scene, frame) = scene(DemoScene::Forest);
    // The provoking-vertex path: the primitive ID is a payload, which the test corrupts.
    let mut r = renderer(Some(PrimitiveIdPath::ProvokingVertex));
    let prepared = r.prepare(&scene).unwrap();
    let n = prepared.payload_count();
    r.render(&prepared, &frame, RenderPath::Deferred).unwrap();
    let deferred = r.read_output().unwrap();
    // Every ID past every mesh: each fragment discards, the G-buffer keeps the deferred
    // frame's texels, and lighting (over the same depth) gives the deferred image.
    r.hooks()
        .write_payloads(&prepared, &vec![u32::MAX; n])
        .unwrap();
    r.render(&prepared, &frame, RenderPath::PixelPull).unwrap();
    assert_eq!(
        r.read_output().unwrap().pixels,
        deferred.pixels,
        "an out-of-range primitive ID wrote something"
    );
    // Random IDs, in range and not: wrong triangles, but every read clamped (the frame
    // runs under validation; a device error fails `render`).
    let mut rng = testkit::Rng::new(3);
    let words: Vec<u32> = (0..n)
        .map(|_| match rng.next_u32() % 3 {
            0 => rng.next_u32(),
            1 => rng.next_u32() % 64,
            _ => 0xffff - rng.next_u32() % 4,
        })
        .collect();
    r.hooks().write_payloads(&prepared, &words).unwrap();
    r.render(&prepared, &frame, RenderPath::PixelPull).unwrap();
    r.read_output().unwrap();
    assert!(r.hooks().write_payloads(&prepared, &words[1..]).is_err());
}
