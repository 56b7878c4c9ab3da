//! The few transcendental functions the crate needs, routed through one place: `std` when
//! it is on, `libm` otherwise (no_std targets).

#[cfg(feature = "std")]
mod imp {
    pub(crate) fn log2(x: f32) -> f32 {
        x.log2()
    }
    pub(crate) fn exp2(x: f32) -> f32 {
        x.exp2()
    }
    pub(crate) fn sqrt(x: f32) -> f32 {
        x.sqrt()
    }
}

#[cfg(not(feature = "std"))]
mod imp {
    pub(crate) fn log2(x: f32) -> f32 {
        libm::log2f(x)
    }
    pub(crate) fn exp2(x: f32) -> f32 {
        libm::exp2f(x)
    }
    pub(crate) fn sqrt(x: f32) -> f32 {
        libm::sqrtf(x)
    }
}

pub(crate) use imp::*;
