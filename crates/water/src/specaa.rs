//! Variance-based specular anti-aliasing.
//!
//! Far Cry 5 saw "a lot of specular aliasing" from its high-frequency water normals and
//! widened the roughness from the per-pixel normal variance, then used the per-pixel
//! material to keep the result in the range water should have (seed 003). This is the
//! isotropic deferred form of Tokuyoshi and Kaplanyan, "Improved Geometric Specular
//! Antialiasing" (I3D 2019):
//!
//! - kernel variance from the screen-space derivatives of the normal:
//!   `sigma^2 = 0.25 (|ddx n|^2 + |ddy n|^2)` ([`variance_from_derivatives`]);
//! - GGX `alpha^2 += min(2 sigma^2, kappa)`, with the clamp `kappa = 0.18`
//!   ([`DEFAULT_KAPPA`]; Filament uses 0.15 to 0.2) ([`filtered_alpha`]).
//!
//! Without derivatives (a compute pass), or on top of them, add the slope variance of the
//! FBM octaves the LOD dropped ([`crate::noise::FbmSample::dropped_variance`]): per axis,
//! the slope variance is what a Beckmann or GGX lobe's `alpha^2 / 2` is, so it enters the
//! same `2 sigma^2`.
//!
//! `alpha` is GGX's width (`alpha = perceptual_roughness^2`).

use glam::Vec3;

use crate::math;

/// Tokuyoshi and Kaplanyan's clamp on the added `alpha^2`.
pub const DEFAULT_KAPPA: f32 = 0.18;

/// The kernel variance of a normal field from its screen-space derivatives (per pixel).
#[must_use]
pub fn variance_from_derivatives(dndx: Vec3, dndy: Vec3) -> f32 {
    0.25 * (dndx.length_squared() + dndy.length_squared())
}

/// GGX `alpha` widened by a normal (slope) variance: `sqrt(min(alpha^2 + min(2 variance,
/// kappa), max_alpha^2))`. Negative or NaN variance counts as 0; `max_alpha` (at most 1)
/// is the material's cap, the talk's "scale it back into the range we expect water".
#[must_use]
pub fn filtered_alpha(alpha: f32, variance: f32, kappa: f32, max_alpha: f32) -> f32 {
    let v = if variance > 0.0 { variance } else { 0.0 };
    let added = (2.0 * v).min(kappa.max(0.0));
    let cap = max_alpha.clamp(0.0, 1.0);
    let a2 = (alpha * alpha + added).min(cap * cap);
    math::sqrt(a2.max(0.0))
}

/// [`filtered_alpha`] on perceptual roughness (`alpha = roughness^2`), returning
/// perceptual roughness.
#[must_use]
pub fn filtered_roughness(roughness: f32, variance: f32, kappa: f32, max_roughness: f32) -> f32 {
    let cap = max_roughness.clamp(0.0, 1.0);
    math::sqrt(filtered_alpha(
        roughness * roughness,
        variance,
        kappa,
        cap * cap,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formula_of_the_paper() {
        // alpha 0.1, sigma^2 0.02: alpha^2 = 0.01 + 0.04 = 0.05.
        let a = filtered_alpha(0.1, 0.02, DEFAULT_KAPPA, 1.0);
        assert!((f64::from(a) - 0.05f64.sqrt()).abs() < 1e-7);
        // The clamp: huge variance adds only kappa.
        let a = filtered_alpha(0.1, 10.0, DEFAULT_KAPPA, 1.0);
        assert!((f64::from(a) - 0.19f64.sqrt()).abs() < 1e-7);
        // No variance, no change; NaN variance ignored; the material cap holds.
        assert_eq!(filtered_alpha(0.3, 0.0, DEFAULT_KAPPA, 1.0), 0.3);
        assert_eq!(filtered_alpha(0.3, f32::NAN, DEFAULT_KAPPA, 1.0), 0.3);
        assert_eq!(filtered_alpha(0.3, 1.0, DEFAULT_KAPPA, 0.35), 0.35);
    }

    #[test]
    fn derivative_variance_of_a_bent_normal() {
        // A normal that turns by 0.1 rad per pixel in x: |dn/dx| = 0.1.
        let v = variance_from_derivatives(Vec3::new(0.1, 0.0, 0.0), Vec3::ZERO);
        assert!((v - 0.0025).abs() < 1e-9);
    }
}
