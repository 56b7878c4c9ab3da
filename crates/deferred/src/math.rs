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
/// their WGSL twins bit for bit. Branch-free for `|x| < 2^22` (adding and subtracting
/// 1.5 · 2^23 leaves the integer the FPU rounded to, ties to even); larger magnitudes are
/// integers already and NaN passes through.
#[inline]
pub(crate) fn round_half_even(x: f32) -> f32 {
    const MAGIC: f32 = 12_582_912.0;
    if x.abs() < 4_194_304.0 {
        (x + MAGIC) - MAGIC
    } else {
        x
    }
}

/// Saturate with NaN mapped to 0 (WGSL `saturate` of NaN is indeterminate; the encoders
/// sanitise first so both sides agree). `f32::max` returns the non-NaN operand.
#[inline]
#[allow(clippy::manual_clamp)] // reason: `clamp` keeps NaN; this must map it to 0.
pub(crate) fn saturate(x: f32) -> f32 {
    x.max(0.0).min(1.0)
}
