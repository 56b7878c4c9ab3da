//! Flow-map sampling with two phase-offset layers (Vlachos, "Water Flow in Portal 2",
//! SIGGRAPH 2010), as Far Cry 5's foam and normals use it: the flow map "is sampled using
//! two different offset phases in order to avoid pulsing" (seed 003).
//!
//! With `t = time / (2 interval) + noise` (per-pixel noise phase in `[0, 1)`):
//!
//! - layer 0 has phase `p0 = frac(t)`, layer 1 `p1 = frac(t + 0.5)`;
//! - each samples its texture at `uv - flow * phase * distance + offset`, where `offset`
//!   jumps once per cycle (`frac(floor(t) * UV_JUMP)`, and for layer 1
//!   `frac(floor(t + 0.5) * UV_JUMP) + 0.5`), hiding the repetition of the reset;
//! - layer 1's weight is `|2 p0 - 1|`, layer 0's the rest, so each layer has weight 0
//!   exactly when its phase wraps.
//!
//! The per-pixel noise phase is what stops the whole surface pulsing in unison; the two
//! layers only hide the reset. `interval` is seconds per half cycle; one full cycle of a
//! layer lasts `2 interval` seconds and scrolls `distance` UV units at unit flow.
//!
//! `flow` is the decoded flow vector (the Vlachos RG8 encoding `rg * 2 - 1` is
//! [`decode_flow_rg8`]) in UV units per cycle at `distance = 1`. Keep `time` bounded (wrap
//! it at a multiple of `2 interval`, e.g. every hour of game time) so f32 keeps its
//! fraction.

use glam::Vec2;

use crate::hash::{hash3, unit};
use crate::math;

/// The per-cycle UV jump (Vlachos uses 0.311 per cycle; a second, different constant for v
/// keeps the jumps off the diagonal).
pub const UV_JUMP: Vec2 = Vec2::new(0.311, 0.243);

/// Flow sampling parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlowParams {
    /// Seconds per half cycle (`t = time / (2 interval)`); positive.
    pub interval: f32,
    /// UV units a layer scrolls over one cycle at unit flow.
    pub distance: f32,
    /// Scale of the per-pixel noise phase (0 makes every pixel pulse together).
    pub noise_strength: f32,
}

impl Default for FlowParams {
    /// One cycle per 2 seconds, 0.25 UV units per cycle, full noise phase.
    fn default() -> Self {
        Self {
            interval: 1.0,
            distance: 0.25,
            noise_strength: 1.0,
        }
    }
}

/// The two layers to sample and blend: `w0 * tex(uv0) + w1 * tex(uv1)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlowLayers {
    /// Layer 0's UV.
    pub uv0: Vec2,
    /// Layer 1's UV.
    pub uv1: Vec2,
    /// Layer 0's weight.
    pub w0: f32,
    /// Layer 1's weight (`1 - w0`).
    pub w1: f32,
    /// Layer 0's phase `frac(t)` (for tests and debugging views).
    pub phase0: f32,
}

/// Decodes a Vlachos RG8 flow texel: `rg / 255 * 2 - 1`.
#[must_use]
pub fn decode_flow_rg8(rg: [u8; 2]) -> Vec2 {
    Vec2::new(f32::from(rg[0]), f32::from(rg[1])) * (2.0 / 255.0) - 1.0
}

/// Encodes a flow vector (each component in `[-1, 1]`, clamped) to RG8, nearest.
#[must_use]
pub fn encode_flow_rg8(flow: Vec2) -> [u8; 2] {
    let e = |v: f32| (math::floor((v.clamp(-1.0, 1.0) + 1.0) * 127.5 + 0.5)) as u8;
    [e(flow.x), e(flow.y)]
}

/// The layers at `uv` for `flow`, `time` (seconds) and the pixel's noise phase
/// (`noise` in `[0, 1)`, e.g. [`phase_noise`]). Non-finite inputs give non-finite UVs but
/// never panic.
#[must_use]
pub fn flow_layers(uv: Vec2, flow: Vec2, time: f32, noise: f32, p: &FlowParams) -> FlowLayers {
    let t = time / (2.0 * p.interval) + noise * p.noise_strength;
    let phase0 = math::fract(t);
    let phase1 = math::fract(t + 0.5);
    let cycle0 = math::floor(t);
    let cycle1 = math::floor(t + 0.5);
    let jump = |c: f32| Vec2::new(math::fract(c * UV_JUMP.x), math::fract(c * UV_JUMP.y));
    let uv0 = uv - flow * (phase0 * p.distance) + jump(cycle0);
    let uv1 = uv - flow * (phase1 * p.distance) + jump(cycle1) + 0.5;
    let w1 = (2.0 * phase0 - 1.0).abs();
    FlowLayers {
        uv0,
        uv1,
        w0: 1.0 - w1,
        w1,
        phase0,
    }
}

/// Smooth value noise in `[0, 1)` from the integer hash: bilinear with a smoothstep fade
/// between hashed lattice values at integer `p`. Used as the per-pixel flow phase
/// (`phase_noise(uv * scale)`); WGSL `water_value_noise` gives the same within 1e-6.
#[must_use]
pub fn phase_noise(p: Vec2, seed: u32) -> f32 {
    let (fx, fy) = (math::floor(p.x), math::floor(p.y));
    let (tx, ty) = (p.x - fx, p.y - fy);
    let (ix, iy) = (fx as i64 as u32, fy as i64 as u32);
    let v = |dx: u32, dy: u32| unit(hash3(ix.wrapping_add(dx), iy.wrapping_add(dy), seed));
    let (sx, sy) = (tx * tx * (3.0 - 2.0 * tx), ty * ty * (3.0 - 2.0 * ty));
    let a = math::mix(v(0, 0), v(1, 0), sx);
    let b = math::mix(v(0, 1), v(1, 1), sx);
    math::mix(a, b, sy)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_layer_is_invisible_when_it_resets() {
        let p = FlowParams::default();
        for i in 0..400 {
            let time = i as f32 * 0.01;
            let l = flow_layers(Vec2::ZERO, Vec2::X, time, 0.0, &p);
            assert!((l.w0 + l.w1 - 1.0).abs() < 1e-6);
            // Layer 0 resets when its phase is near 0 (or 1): its weight is near 0.
            if l.phase0 < 0.01 || l.phase0 > 0.99 {
                assert!(l.w0 < 0.03, "{l:?}");
            }
            if (l.phase0 - 0.5).abs() < 0.01 {
                assert!(l.w1 < 0.03, "{l:?}");
            }
        }
    }

    #[test]
    fn layers_scroll_along_the_flow() {
        let p = FlowParams {
            noise_strength: 0.0,
            ..Default::default()
        };
        let a = flow_layers(Vec2::ZERO, Vec2::X, 0.2, 0.0, &p);
        let b = flow_layers(Vec2::ZERO, Vec2::X, 0.4, 0.0, &p);
        // Within a cycle the sample point moves against the flow (texture moves with it):
        // 0.2 s = 0.1 cycles = 0.025 UV at distance 0.25.
        assert!((a.uv0.x - b.uv0.x - 0.025).abs() < 1e-6);
        assert_eq!(a.uv0.y, b.uv0.y);
    }

    #[test]
    fn rg8_roundtrip_and_phase_noise_range() {
        for v in [-1.0, -0.5, 0.0, 0.25, 1.0] {
            let d = decode_flow_rg8(encode_flow_rg8(Vec2::splat(v)));
            assert!((d.x - v).abs() <= 1.0 / 255.0 + 1e-6);
        }
        for i in 0..100 {
            let n = phase_noise(Vec2::new(i as f32 * 0.37, -(i as f32) * 0.11), 3);
            assert!((0.0..1.0).contains(&n));
        }
        let _ = flow_layers(
            Vec2::NAN,
            Vec2::INFINITY,
            f32::NAN,
            f32::NAN,
            &FlowParams::default(),
        );
    }
}
