//! Tiled local lights on testkit's device: the per-tile depth ranges equal
//! `deferred::lights::tile_depth_ranges` of the read-back depth target, the tile lists
//! equal `cull_tiles` on them (up to a tangent light flipping with the device's rounding),
//! and lighting from the lists gives the same image as every light at every pixel.

mod common;

use deferred::lights::{MAX_LIGHTS_PER_TILE, cull_tiles, tile_depth_ranges};
use deferred::{DepthMode, Perspective};
use gpu::demo::{self, DemoOptions, DemoScene};
use gpu::{FrameInput, RenderPath, Renderer, RendererConfig, Scene, local_light_rows};
use testkit::device::ctx;

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

fn renderer(tiled_lights: bool, subgroups: bool) -> Renderer {
    let c = ctx();
    Renderer::new(
        &c.device,
        &c.queue,
        RendererConfig {
            width: W,
            height: H,
            tiled_lights,
            subgroups,
            ..RendererConfig::default()
        },
    )
    .unwrap_or_else(|e| panic!("{e}"))
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
    let mut r = renderer(true, subgroups);
    let prepared = r.prepare(scene).unwrap();
    for path in [RenderPath::Deferred, RenderPath::Baseline] {
        r.render(&prepared, frame, path).unwrap();
        let tiles = r.read_light_tiles().unwrap();
        let depth = r.read_depth().unwrap();
        // Pass 1: exactly the CPU's reduction.
        let mut cpu_depths = vec![deferred::DeferredTileDepth::default(); tiles.depths.len()];
        tile_depth_ranges(&depth, W, H, DepthMode::Reversed, &mut cpu_depths).unwrap();
        assert_eq!(tiles.depths, cpu_depths, "{path:?}: tile depth ranges");
        // Pass 2: the CPU twin on the same tiles and lights.
        let lights = local_light_rows(&frame.lighting, &frame.camera);
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
            "{path:?}, subgroups {subgroups}: {n} tiles, {} with geometry, {} lights, {} pairs, {differ} decisions differ",
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
    let mut tiled = renderer(true, true);
    let mut all = renderer(false, true);
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
        let differ = a
            .pixels
            .iter()
            .zip(&b.pixels)
            .filter(|(x, y)| x != y)
            .count();
        assert_eq!(differ, 0, "{path:?}: {differ} pixels differ");
        // The lights do light the frame.
        tiled.render(&pt, &dark, path).unwrap();
        let unlit = tiled.read_output().unwrap();
        let lit = a
            .pixels
            .iter()
            .zip(&unlit.pixels)
            .filter(|(x, y)| x != y)
            .count();
        eprintln!(
            "{path:?}: {lit} of {} pixels lit by local lights",
            a.pixels.len()
        );
        assert!(lit * 10 > a.pixels.len(), "{lit}");
    }
}
