//! The synthetic masks the examples and `benches/water.rs` share (`mod common;` in the
//! examples; the bench reaches it through `bake.rs`, which it includes), so every timing
//! measures the same inputs.

use water::glam::Vec2;
use water::noise::{Fbm, FbmParams, NoiseTexture};

/// A `size x size` row-major mask, 1 where the FBM height (a 256^2 noise texture of 16
/// cells from `seed`, six octaves at `frequency` cycles per world unit, gain 0.5) is above
/// `threshold` and 0 elsewhere; texel `(x, y)` samples the height at
/// `to_world(Vec2(x, y))`.
pub fn fbm_mask(
    size: u32,
    seed: u32,
    frequency: f32,
    threshold: f32,
    to_world: impl Fn(Vec2) -> Vec2,
) -> Vec<u8> {
    let tex = NoiseTexture::generate(256, 16, seed).unwrap();
    let f = Fbm::new(
        &tex,
        FbmParams {
            frequency,
            amplitude: 1.0,
            gain: 0.5,
            octaves_near: 6,
            octaves_far: 1,
            lod_distance: 1.0,
        },
    )
    .unwrap();
    (0..size * size)
        .map(|i| {
            let p = to_world(Vec2::new((i % size) as f32, (i / size) as f32));
            u8::from(f.height(p) > threshold)
        })
        .collect()
}

/// A shoreline-and-rocks mask, one texel per world unit: FBM thresholded (about 40% solid
/// at 2048^2), the distance transform's timing input.
#[allow(dead_code)] // bake.rs includes this module for `fbm_mask` alone
pub fn shore_mask(size: u32) -> Vec<u8> {
    fbm_mask(size, 11, 1.0 / 1024.0, 0.15, |p| p)
}
