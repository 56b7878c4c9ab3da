//! Every transcendental (and rounding) function the crate uses, in one place.
//!
//! All of them go through the `libm` crate, with or without `std`: `libm` is a portable
//! Rust implementation, so `exp`, `sin`, `pow` and friends give the same bits on every
//! platform and with every C library (the platform `libm` that `std` calls does not; glibc,
//! musl and MSVC differ in the last place). `sqrt`, `floor` and `fract` are exact IEEE
//! operations and agree anyway; they are here so that nothing in the crate reaches for
//! `f32` inherent methods, which `core` does not have. `sqrt` uses the compiler intrinsic
//! under `std` (so loops of it vectorise) and `libm` without; both are correctly rounded,
//! so the bits are the same.
//!
//! The WGSL twins use the GPU's built-ins (`exp`, `sin`, ...), which WGSL only requires to
//! be accurate to a few ulp (more for `sin`/`cos` on large arguments); the tolerances the
//! device tests state cover that difference.

/// `e^x`.
#[inline]
pub fn exp(x: f32) -> f32 {
    libm::expf(x)
}

/// `2^x`.
#[inline]
pub fn exp2(x: f32) -> f32 {
    libm::exp2f(x)
}

/// Base-2 logarithm.
#[inline]
pub fn log2(x: f32) -> f32 {
    libm::log2f(x)
}

/// `x^y`.
#[inline]
pub fn pow(x: f32, y: f32) -> f32 {
    libm::powf(x, y)
}

/// Sine of `x` radians.
#[inline]
pub fn sin(x: f32) -> f32 {
    libm::sinf(x)
}

/// Cosine of `x` radians.
#[inline]
pub fn cos(x: f32) -> f32 {
    libm::cosf(x)
}

/// Angle of `(x, y)` in radians, in `[-pi, pi]`.
#[inline]
pub fn atan2(y: f32, x: f32) -> f32 {
    libm::atan2f(y, x)
}

/// Square root (correctly rounded).
#[inline]
pub fn sqrt(x: f32) -> f32 {
    #[cfg(feature = "std")]
    {
        x.sqrt()
    }
    #[cfg(not(feature = "std"))]
    {
        libm::sqrtf(x)
    }
}

/// Square root in f64 (correctly rounded).
#[inline]
pub fn sqrt64(x: f64) -> f64 {
    libm::sqrt(x)
}

/// Largest integer not above `x`.
#[inline]
pub fn floor(x: f32) -> f32 {
    libm::floorf(x)
}

/// Smallest integer not below `x`.
#[inline]
pub fn ceil(x: f32) -> f32 {
    libm::ceilf(x)
}

/// Nearest integer, halves away from zero (`f32::round`).
#[inline]
pub fn round(x: f32) -> f32 {
    libm::roundf(x)
}

/// `x - floor(x)`, in `[0, 1)` for finite `x` (WGSL's `fract`).
#[inline]
pub fn fract(x: f32) -> f32 {
    x - libm::floorf(x)
}

/// `x` clamped to `[0, 1]` (NaN gives 0).
#[inline]
pub fn saturate(x: f32) -> f32 {
    if x > 0.0 {
        if x < 1.0 { x } else { 1.0 }
    } else {
        0.0
    }
}

/// Hermite smoothstep of `x` between `e0` and `e1` (WGSL's `smoothstep`).
#[inline]
pub fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = saturate((x - e0) / (e1 - e0));
    t * t * (3.0 - 2.0 * t)
}

/// Linear interpolation `a + (b - a) t` (WGSL's `mix`).
#[inline]
pub fn mix(a: f32, b: f32, t: f32) -> f32 {
    a + (b - a) * t
}

/// [`mix`] per component of a `Vec2` (`a + (b - a) t`, as WGSL's `mix` is written in the
/// twins; glam's `lerp` rounds differently).
#[inline]
pub fn mix2(a: glam::Vec2, b: glam::Vec2, t: f32) -> glam::Vec2 {
    a + (b - a) * t
}

/// [`mix`] per component of a `Vec3`.
#[inline]
pub fn mix3(a: glam::Vec3, b: glam::Vec3, t: f32) -> glam::Vec3 {
    a + (b - a) * t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounding_matches_wgsl_definitions() {
        assert_eq!(fract(-0.25), 0.75);
        assert_eq!(fract(3.5), 0.5);
        assert_eq!(floor(-1.5), -2.0);
        assert_eq!(ceil(-1.5), -1.0);
        assert_eq!(saturate(f32::NAN), 0.0);
        assert_eq!(saturate(2.0), 1.0);
        assert_eq!(smoothstep(0.0, 1.0, 0.5), 0.5);
        assert_eq!(mix(2.0, 4.0, 0.25), 2.5);
    }

    #[test]
    fn transcendentals_agree_with_f64() {
        for i in -100..100 {
            let x = i as f32 * 0.173;
            assert!(
                (exp(x * 0.1) as f64 - (x as f64 * 0.1).exp()).abs()
                    < 1e-6 * (x as f64 * 0.1).exp()
            );
            assert!((sin(x) as f64 - (x as f64).sin()).abs() < 1e-6);
            assert!((cos(x) as f64 - (x as f64).cos()).abs() < 1e-6);
            assert!((atan2(x, 1.3) as f64 - (x as f64).atan2(1.3)).abs() < 1e-6);
        }
        assert_eq!(exp2(3.0), 8.0);
        assert_eq!(log2(8.0), 3.0);
        assert_eq!(sqrt(16.0), 4.0);
        assert!((pow(2.0, 0.5) - core::f32::consts::SQRT_2).abs() < 1e-7);
    }
}
