//! How tight the tile lists are: on the bench's 1080p scene, the (tile, light) pairs the
//! culling lists against the pairs where the light really lights a pixel of the tile, and
//! the per-pixel light evaluations the lists cause against the exact count. Also how KZ2's
//! classifier splits the lights. Figures for BENCHMARKS.md:
//!
//! `cargo run --release -p deferred --example culling_stats` (no arguments)

use clap::Parser;
use deferred::glam::{Vec2, Vec3};
use deferred::lights::{
    MAX_LIGHTS_PER_TILE, TILE_SIZE, cull_tiles, tile_counts, tile_depth_ranges,
};
use deferred::{
    DeferredLight, DeferredTileDepth, DepthMode, LightClassifier, LightPath, Perspective,
};
use testkit::Rng;

const W: u32 = 1920;
const H: u32 = 1080;

/// How tight the tiled light lists are on the bench's 1080p scene, and how KZ2's classifier
/// splits the lights.
#[derive(Parser)]
#[command(name = "culling_stats")]
struct Args {}

fn main() {
    Args::parse();
    let p = Perspective::try_new(1.0, W as f32 / H as f32, 0.1, None, DepthMode::Reversed).unwrap();
    let proj = p.gpu(Vec2::new(W as f32, H as f32));
    // The bench scene: ground plane, walls every 240 px, sky in the top fifth.
    let mut depth = vec![0.0f32; (W * H) as usize];
    for y in H / 5..H {
        for x in 0..W {
            let ndc_y = 1.0 - (y as f32 + 0.5) / H as f32 * 2.0;
            let ground = if ndc_y < 0.0 {
                1.7 / (-ndc_y * proj.tan_half[1])
            } else {
                1e9
            };
            let wall = 8.0 + (x / 240) as f32 * 6.0 + (x % 240) as f32 * 0.02;
            depth[(y * W + x) as usize] = p.linearize().depth(ground.min(wall).min(150.0));
        }
    }
    let (tx, ty) = tile_counts(W, H);
    let n = (tx * ty) as usize;
    let mut tiles = vec![DeferredTileDepth::default(); n];
    tile_depth_ranges(&depth, W, H, DepthMode::Reversed, &mut tiles).unwrap();
    println!(
        "| lights | listed pairs | needed pairs | listed / needed | light evaluations per pixel, tiled | exact | volume path | depth-bounds path | culled |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    for count in [64usize, 256, 1024] {
        let mut rng = Rng::new(77);
        let lights: Vec<DeferredLight> = (0..count)
            .map(|i| {
                let d = rng.range(2.0, 60.0);
                let pos = Vec3::new(rng.range(-0.9, 0.9) * d, rng.range(-0.5, 0.4) * d, -d);
                let range = rng.range(0.5, 6.0);
                let l = if i % 4 == 0 {
                    DeferredLight::spot(pos, Vec3::new(0.0, -1.0, -0.3), range, 0.6, Vec3::ONE)
                } else {
                    DeferredLight::point(pos, range, Vec3::ONE)
                };
                if i % 10 == 0 { l.with_shadow() } else { l }
            })
            .collect();
        let mut counts = vec![0u32; n];
        let mut indices = vec![0u32; n * MAX_LIGHTS_PER_TILE as usize];
        let stats = cull_tiles(&proj, &tiles, &lights, &mut counts, &mut indices).unwrap();
        let mut needed = 0u64;
        let (mut evals_tiled, mut evals_exact, mut pixels) = (0u64, 0u64, 0u64);
        for t_y in 0..ty {
            for t_x in 0..tx {
                let t = (t_y * tx + t_x) as usize;
                let list = &indices[t * MAX_LIGHTS_PER_TILE as usize..][..counts[t] as usize];
                let mut hit = vec![false; list.len()];
                for y in t_y * TILE_SIZE..((t_y + 1) * TILE_SIZE).min(H) {
                    for x in t_x * TILE_SIZE..((t_x + 1) * TILE_SIZE).min(W) {
                        let d = depth[(y * W + x) as usize];
                        if d == 0.0 {
                            continue;
                        }
                        pixels += 1;
                        let pos = proj.view_position(Vec2::new(x as f32 + 0.5, y as f32 + 0.5), d);
                        evals_tiled += list.len() as u64;
                        for (k, &li) in list.iter().enumerate() {
                            if lights[li as usize].affects(pos) {
                                hit[k] = true;
                                evals_exact += 1;
                            }
                        }
                    }
                }
                needed += hit.iter().filter(|&&h| h).count() as u64;
            }
        }
        let k = LightClassifier::default();
        let mut paths = [0u32; 3];
        for l in &lights {
            paths[match k.classify(&proj, l).path {
                LightPath::Volume => 0,
                LightPath::DepthBounds => 1,
                LightPath::Culled => 2,
            }] += 1;
        }
        println!(
            "| {count} | {} | {needed} | {:.2} | {:.2} | {:.2} | {} | {} | {} |",
            stats.pairs,
            stats.pairs as f64 / needed as f64,
            evals_tiled as f64 / pixels as f64,
            evals_exact as f64 / pixels as f64,
            paths[0],
            paths[1],
            paths[2]
        );
    }
}
