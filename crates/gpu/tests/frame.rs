//! The whole frame on a device (lavapipe in CI): the GPU classification equals `tiling`'s
//! CPU twin on both demo scenes (subgroup appends and the workgroup fallback) and on random
//! vis buffers; the deferred-texturing image matches HZD's depth-equal baseline; each
//! scene matches a small golden image.
//!
//! Golden images live in `tests/golden/`; `GPU_BLESS=1 cargo test -p gpu --test frame`
//! rewrites them from this machine's device (commit them with the adapter named in the
//! message). Every test runs on testkit's device (lavapipe in CI).

mod common;

use std::path::PathBuf;

use gpu::demo::{self, DemoOptions, DemoScene};
use gpu::{FrameInput, RenderPath, Rgba8Image, Scene, diff_metrics};
use testkit::device::{GoldenBounds, check_golden, ctx};
use visbuf::{ShadingRate, VisFields, VisId, VisLayout};

/// A lighter demo scene for lavapipe: same generator, fewer instances.
fn scene(kind: DemoScene) -> (Scene, FrameInput) {
    demo::build(&DemoOptions {
        scene: kind,
        seed: 7,
        density: 0.25,
    })
}

/// Both append paths where the device has subgroups, the fallback alone otherwise.
fn subgroup_settings() -> Vec<bool> {
    testkit::device::subgroup_variants()
        .into_iter()
        .map(|f| !f.is_empty())
        .collect()
}

#[test]
fn gpu_classification_equals_the_cpu_twin_on_both_demo_scenes() {
    for kind in DemoScene::ALL {
        let (scene, frame) = scene(kind);
        for subgroups in subgroup_settings() {
            // 300x200: partial tiles on the right and bottom edges.
            let mut r = common::renderer(300, 200, subgroups);
            let prepared = r.prepare(&scene).unwrap();
            r.render(&prepared, &frame, RenderPath::Deferred).unwrap();
            let gpu = r.read_classification(&prepared).unwrap();
            let (stats, mismatch) = r.classification_statistics(&prepared, &gpu).unwrap();
            assert_eq!(
                mismatch,
                None,
                "{} subgroups {subgroups}: GPU classification differs from the CPU twin",
                kind.name()
            );
            assert!(
                stats.vis_pixels > 300 * 200 / 2,
                "{}: the scene should cover most of the image ({} pixels)",
                kind.name(),
                stats.vis_pixels
            );
            assert_eq!(stats.pixel_commands, stats.vis_pixels);
            assert!(stats.wave_commands > 0 && stats.passes >= 1);
            eprintln!(
                "{} subgroups {subgroups}: {} pixels, {} waves, {} passes: equal",
                kind.name(),
                stats.vis_pixels,
                stats.wave_commands,
                stats.passes
            );
        }
    }
}

#[test]
fn gpu_classification_equals_the_cpu_twin_on_random_vis_buffers() {
    let (scene, _) = scene(DemoScene::Forest);
    for subgroups in subgroup_settings() {
        let (w, h) = (257, 131);
        let mut r = common::renderer(w, h, subgroups);
        let prepared = r.prepare(&scene).unwrap();
        let mbs = &prepared.tiling_plan().micro_batches;
        for seed in 1..=3u64 {
            let mut rng = testkit::Rng::new(seed);
            // Runs of one valid ID (as triangles make), sky, IDs past the table, primitives
            // past the geometry, and raw garbage.
            let mut words = Vec::with_capacity((w * h) as usize);
            let mut current = visbuf::VIS_NONE;
            for _ in 0..w * h {
                if rng.next_u32().is_multiple_of(16) {
                    current = match rng.next_u32() % 10 {
                        0 => visbuf::VIS_NONE,
                        1 => rng.next_u32(),
                        2 => 0xfff0_0000 | (rng.next_u32() & 0xffff),
                        _ => {
                            let mb = &mbs[(rng.next_u32() as usize) % mbs.len()];
                            let i = rng.next_u32() % mb.instance_count;
                            let (id, field) = mb.instance_id(i);
                            let over = rng.next_u32().is_multiple_of(8);
                            let primitive = if over {
                                (mb.primitive_count + rng.next_u32() % 4)
                                    .min((1 << mb.primitive_bits) - 1)
                            } else {
                                rng.next_u32() % mb.primitive_count
                            };
                            VisId::pack(
                                VisLayout::Standard,
                                mb.bits(),
                                VisFields {
                                    micro_batch: id,
                                    instance: field,
                                    primitive,
                                    rate: ShadingRate::Rate1x1,
                                },
                            )
                            .unwrap()
                            .0
                        }
                    };
                }
                words.push(current);
            }
            let gpu = r.classify_words(&prepared, &words).unwrap();
            assert_eq!(gpu.vis, words);
            let (stats, mismatch) = r.classification_statistics(&prepared, &gpu).unwrap();
            assert_eq!(
                mismatch, None,
                "seed {seed} subgroups {subgroups}: GPU classification differs from the CPU twin"
            );
            assert!(stats.vis_pixels > 0);
        }
    }
}

fn render_both(kind: DemoScene, w: u32, h: u32) -> (Rgba8Image, Rgba8Image) {
    let (scene, frame) = scene(kind);
    let mut r = common::renderer(w, h, true);
    let prepared = r.prepare(&scene).unwrap();
    r.render(&prepared, &frame, RenderPath::Deferred).unwrap();
    let deferred = r.read_output().unwrap();
    r.render(&prepared, &frame, RenderPath::Baseline).unwrap();
    let baseline = r.read_output().unwrap();
    (deferred, baseline)
}

/// Thresholds set on llvmpipe (LLVM 15, Mesa 22.3.6, Vulkan) at 320x180: both paths
/// measured 0.021 (forest) and 0.022 (grass) mean, 2 at the 99th percentile; the bounds leave room for
/// other drivers' texture filtering. The difference comes from the gradients only:
/// analytic (deferred) against the hardware's 2x2 quads (baseline).
const MAX_MEAN_ERROR: f64 = 1.0;
const MAX_P99_ERROR: u8 = 24;

#[test]
fn deferred_texturing_looks_like_the_depth_equal_baseline() {
    for kind in DemoScene::ALL {
        let (deferred, baseline) = render_both(kind, 320, 180);
        let (mean, _) = diff_metrics(&deferred, &baseline, 0.5).unwrap();
        let (_, p99) = diff_metrics(&deferred, &baseline, 0.99).unwrap();
        eprintln!(
            "{} on {}: mean abs error {mean:.3} / 255, 99th percentile {p99} / 255",
            kind.name(),
            ctx().adapter_line()
        );
        assert!(
            mean <= MAX_MEAN_ERROR && p99 <= MAX_P99_ERROR,
            "{}: deferred vs baseline mean {mean:.3} (max {MAX_MEAN_ERROR}), p99 {p99} (max {MAX_P99_ERROR})",
            kind.name()
        );
        // Not a blank image: the scenes have sky and ground and plants.
        let distinct: std::collections::BTreeSet<[u8; 4]> =
            deferred.pixels.iter().copied().collect();
        assert!(
            distinct.len() > 500,
            "{}: {} colours",
            kind.name(),
            distinct.len()
        );
    }
}

/// Bounds against the committed golden images, which were blessed on llvmpipe (the CI
/// driver): tight there. Other drivers rasterise alpha-tested foliage edges and filter
/// textures differently; on the H100 (NVIDIA 580.159.04, Vulkan) forest measured mean
/// 1.456 and p99 53, so other adapters get looser bounds (the strict check on every
/// device is the deferred-vs-baseline comparison above, on one device).
fn golden_bounds() -> GoldenBounds {
    if ctx().info.device_type == wgpu::DeviceType::Cpu {
        GoldenBounds { mean: 0.5, p99: 16 }
    } else {
        GoldenBounds { mean: 3.0, p99: 96 }
    }
}

/// `GPU_BLESS=1 cargo test -p gpu --test frame` rewrites them from this device.
#[test]
fn each_scene_matches_its_golden_image() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden");
    for kind in DemoScene::ALL {
        let (deferred, _) = render_both(kind, 160, 90);
        check_golden(
            &dir.join(format!("{}_160x90.png", kind.name())),
            &deferred,
            golden_bounds(),
        );
    }
}
