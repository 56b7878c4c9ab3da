//! Foam: where it appears and what it looks like.
//!
//! Far Cry 5: "It's just a noise texture modulated by a noise texture", sampled through the
//! two-phase flow map, and "driven using a signed distance field based on the shorelines
//! and the rocks"; "we also blend in the displacement foam with the shoreline foam"; rivers'
//! foam follows their depth and width and goes "around any rocks" (seed 003).
//!
//! [`foam`] computes, per pixel:
//!
//! 1. the *amount* of foam wanted, the largest of
//!    - shoreline: `1 - smoothstep(0, shore_width, sdf)` for the signed distance `sdf`
//!      (metres, positive in water, as [`crate::edt`] gives it times the texel size), so 1
//!      at and inside the shore or a rock, 0 from `shore_width` out;
//!    - speed: `smoothstep(speed_start, speed_full, flow speed)` (rapids);
//!    - shallowness: `1 - smoothstep(0, shallow_depth, depth)` where a depth is known;
//! 2. the *pattern*: a detail noise modulated by a mask noise,
//!    `saturate(0.5 + 0.5 detail) * saturate(0.5 + 0.5 mask + mask_bias)`;
//! 3. coverage: foam shows where the pattern exceeds `1 - amount`, with a soft edge,
//!    `smoothstep(1 - amount, 1 - amount + softness, pattern)`, so more amount means more
//!    of the pattern, never a uniform white;
//! 4. the displacement foam (splashes, from the decals) is added and the sum clamped.
//!
//! Noise values come in as inputs (sample them with [`crate::flow::flow_layers`] from the
//! noise texture) so the same function serves the CPU and the GPU (`water_foam`).

use crate::math;

/// Foam parameters (a water material's foam controls).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FoamParams {
    /// Shoreline foam reaches this far into the water, metres.
    pub shore_width: f32,
    /// Flow speed (m/s) where speed foam starts.
    pub speed_start: f32,
    /// Flow speed (m/s) of full speed foam.
    pub speed_full: f32,
    /// Depth (metres) below which shallow water foams.
    pub shallow_depth: f32,
    /// Width of the coverage edge in pattern units.
    pub softness: f32,
    /// Added to the mask noise (more = fewer holes in the pattern).
    pub mask_bias: f32,
    /// Scales the final foam (the material's foam intensity).
    pub intensity: f32,
}

impl Default for FoamParams {
    /// 3 m of shore foam, rapids foam from 1.5 m/s (full at 4 m/s), 0.3 m shallows.
    fn default() -> Self {
        Self {
            shore_width: 3.0,
            speed_start: 1.5,
            speed_full: 4.0,
            shallow_depth: 0.3,
            softness: 0.15,
            mask_bias: 0.2,
            intensity: 1.0,
        }
    }
}

/// What a pixel knows when shading foam.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FoamInputs {
    /// Signed distance to the shore or a rock, metres (positive in water).
    pub signed_distance: f32,
    /// Flow speed, m/s.
    pub flow_speed: f32,
    /// Water depth in metres (`f32::INFINITY` when unknown).
    pub depth: f32,
    /// Detail noise in `[-1, 1]` (already flow-blended).
    pub detail_noise: f32,
    /// Mask noise in `[-1, 1]`, lower frequency (already flow-blended).
    pub mask_noise: f32,
    /// Foam from displacement decals, `[0, 1]`.
    pub displacement_foam: f32,
}

/// The foam amount before the pattern (step 1 of the module docs), in `[0, 1]`.
#[must_use]
pub fn foam_amount(i: &FoamInputs, p: &FoamParams) -> f32 {
    let shore = 1.0 - math::smoothstep(0.0, p.shore_width.max(1e-6), i.signed_distance);
    let speed = math::smoothstep(
        p.speed_start,
        p.speed_full.max(p.speed_start + 1e-6),
        i.flow_speed,
    );
    let shallow = 1.0 - math::smoothstep(0.0, p.shallow_depth.max(1e-6), i.depth);
    math::saturate(shore.max(speed).max(shallow))
}

/// Foam coverage in `[0, 1]`; NaN inputs never give a NaN result.
#[must_use]
pub fn foam(i: &FoamInputs, p: &FoamParams) -> f32 {
    let amount = foam_amount(i, p);
    let pattern = math::saturate(0.5 + 0.5 * i.detail_noise)
        * math::saturate(0.5 + 0.5 * i.mask_noise + p.mask_bias);
    let edge = 1.0 - amount;
    let covered = if amount > 0.0 {
        math::smoothstep(edge, edge + p.softness.max(1e-6), pattern)
    } else {
        0.0
    };
    math::saturate(math::saturate(covered * p.intensity) + math::saturate(i.displacement_foam))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inputs(sdf: f32, speed: f32) -> FoamInputs {
        FoamInputs {
            signed_distance: sdf,
            flow_speed: speed,
            depth: f32::INFINITY,
            detail_noise: 0.3,
            mask_noise: 0.1,
            displacement_foam: 0.0,
        }
    }

    #[test]
    fn open_slow_water_has_no_foam_and_shores_do() {
        let p = FoamParams::default();
        assert_eq!(foam(&inputs(50.0, 0.2), &p), 0.0);
        assert!(foam(&inputs(0.0, 0.2), &p) > 0.5);
        assert!(foam(&inputs(0.0, 0.2), &p) >= foam(&inputs(1.5, 0.2), &p));
        assert!(foam(&inputs(50.0, 5.0), &p) > 0.5, "rapids foam");
    }

    #[test]
    fn displacement_foam_adds_and_clamps() {
        let p = FoamParams::default();
        let mut i = inputs(50.0, 0.0);
        i.displacement_foam = 0.4;
        assert_eq!(foam(&i, &p), 0.4);
        i.signed_distance = 0.0;
        i.displacement_foam = 0.9;
        assert_eq!(foam(&i, &p), 1.0);
        i.signed_distance = f32::NAN;
        i.detail_noise = f32::NAN;
        assert!(foam(&i, &p).is_finite());
    }
}
