//! The few transcendental functions the crate needs, routed through one place: `std` when
//! it is on, `libm` otherwise (no_std targets), so every build computes the same values.

#[cfg(feature = "std")]
mod imp {
    pub(crate) fn sqrt(x: f32) -> f32 {
        x.sqrt()
    }
    pub(crate) fn powf(x: f32, y: f32) -> f32 {
        x.powf(y)
    }
    pub(crate) fn log2(x: f32) -> f32 {
        x.log2()
    }
    pub(crate) fn exp2(x: f32) -> f32 {
        x.exp2()
    }
    pub(crate) fn cos(x: f32) -> f32 {
        x.cos()
    }
    pub(crate) fn sqrt64(x: f64) -> f64 {
        x.sqrt()
    }
    pub(crate) fn tan64(x: f64) -> f64 {
        x.tan()
    }
    pub(crate) fn floor64(x: f64) -> f64 {
        x.floor()
    }
    pub(crate) fn ceil64(x: f64) -> f64 {
        x.ceil()
    }
    pub(crate) fn powf64(x: f64, y: f64) -> f64 {
        x.powf(y)
    }
}

#[cfg(not(feature = "std"))]
mod imp {
    pub(crate) fn sqrt(x: f32) -> f32 {
        libm::sqrtf(x)
    }
    pub(crate) fn powf(x: f32, y: f32) -> f32 {
        libm::powf(x, y)
    }
    pub(crate) fn log2(x: f32) -> f32 {
        libm::log2f(x)
    }
    pub(crate) fn exp2(x: f32) -> f32 {
        libm::exp2f(x)
    }
    pub(crate) fn cos(x: f32) -> f32 {
        libm::cosf(x)
    }
    pub(crate) fn sqrt64(x: f64) -> f64 {
        libm::sqrt(x)
    }
    pub(crate) fn tan64(x: f64) -> f64 {
        libm::tan(x)
    }
    pub(crate) fn floor64(x: f64) -> f64 {
        libm::floor(x)
    }
    pub(crate) fn ceil64(x: f64) -> f64 {
        libm::ceil(x)
    }
    pub(crate) fn powf64(x: f64, y: f64) -> f64 {
        libm::pow(x, y)
    }
}

pub(crate) use imp::*;

/// `floor` for f32 without std: exact for every finite value (values of magnitude 2^23
/// and above are integers already).
#[inline]
pub(crate) fn floor(x: f32) -> f32 {
    // NaN, infinities and magnitudes of 2^23 and above are returned as they are.
    if x.is_nan() || x.abs() >= 8_388_608.0 {
        return x;
    }
    let t = x as i32 as f32;
    if t > x { t - 1.0 } else { t }
}

/// Round to nearest, ties to even: what WGSL's `round` does, so quantisers agree with
/// their WGSL twins bit for bit.
#[inline]
pub(crate) fn round_half_even(x: f32) -> f32 {
    let f = floor(x);
    let d = x - f;
    let even = (f * 0.5) == floor(f * 0.5);
    if d > 0.5 || (d == 0.5 && !even) {
        f + 1.0
    } else {
        f
    }
}

/// Saturate with NaN mapped to 0 (WGSL `saturate` of NaN is indeterminate; the encoders
/// sanitise first so both sides agree).
#[inline]
pub(crate) fn saturate(x: f32) -> f32 {
    if x > 0.0 {
        if x < 1.0 { x } else { 1.0 }
    } else {
        0.0
    }
}
