//! The few float functions the crate needs, routed through one place: `std` when it is on,
//! `libm` otherwise (no_std targets).

#[cfg(feature = "std")]
mod imp {
    #[inline]
    pub(crate) fn floor(x: f32) -> f32 {
        x.floor()
    }
    #[inline]
    pub(crate) fn round64(x: f64) -> f64 {
        x.round()
    }
}

#[cfg(not(feature = "std"))]
mod imp {
    #[inline]
    pub(crate) fn floor(x: f32) -> f32 {
        libm::floorf(x)
    }
    #[inline]
    pub(crate) fn round64(x: f64) -> f64 {
        libm::round(x)
    }
}

pub(crate) use imp::*;
