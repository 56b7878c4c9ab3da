//! The crate's one error type.

use core::fmt;

/// Everything that can go wrong in `deferred`. Variants that come from a limit name the
/// limit (a `pub const` of this crate), the offending value and the item.
///
/// User input never panics: the fallible entry points return this instead.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// A float parameter is NaN, infinite or outside its valid range.
    InvalidParameter {
        /// Which parameter.
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// A light with a bad field (non-finite, `range <= 0`, a spot's direction not unit or
    /// `cos_outer` outside `(0, 1)`).
    InvalidLight {
        /// Index of the light in the slice given.
        index: u32,
        /// Which field.
        field: &'static str,
    },
    /// More lights than one pass takes ([`MAX_LIGHTS`](crate::lights::MAX_LIGHTS)).
    TooManyLights {
        /// Lights given.
        count: usize,
        /// The limit.
        limit: u32,
    },
    /// A viewport edge of 0 or above [`MAX_VIEWPORT`](crate::lights::MAX_VIEWPORT).
    ViewportOutOfRange {
        /// Which edge.
        name: &'static str,
        /// Its value in pixels.
        value: u32,
        /// The limit.
        limit: u32,
    },
    /// A cascade count of 0 or above [`MAX_CASCADES`](crate::cascades::MAX_CASCADES).
    TooManyCascades {
        /// The count given.
        count: u32,
        /// The limit.
        limit: u32,
    },
    /// A PCF kernel with fewer taps than samples or more than
    /// [`MAX_PCF_TAPS`](crate::msaa::MAX_PCF_TAPS).
    KernelSize {
        /// Taps given.
        taps: usize,
        /// Fewest taps (one per sample).
        min: u32,
        /// The limit.
        max: u32,
    },
    /// A PCF tap with a non-finite offset or a weight that is not positive and finite.
    InvalidTap {
        /// Index of the tap in the kernel given.
        index: u32,
    },
    /// An output or input buffer shorter than the pass needs.
    BufferTooSmall {
        /// Which buffer.
        buffer: &'static str,
        /// Its length in elements.
        len: usize,
        /// Elements needed.
        needed: usize,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Error::InvalidParameter { name, value } => {
                write!(f, "invalid parameter `{name}`: {value}")
            }
            Error::InvalidLight { index, field } => {
                write!(f, "light {index}: invalid `{field}`")
            }
            Error::TooManyLights { count, limit } => {
                write!(f, "{count} lights exceed MAX_LIGHTS ({limit})")
            }
            Error::ViewportOutOfRange { name, value, limit } => {
                write!(
                    f,
                    "viewport {name} {value} is outside 1..=MAX_VIEWPORT ({limit})"
                )
            }
            Error::TooManyCascades { count, limit } => {
                write!(
                    f,
                    "cascade count {count} is outside 1..=MAX_CASCADES ({limit})"
                )
            }
            Error::KernelSize { taps, min, max } => {
                write!(
                    f,
                    "PCF kernel of {taps} taps is outside {min}..=MAX_PCF_TAPS ({max})"
                )
            }
            Error::InvalidTap { index } => write!(f, "PCF tap {index}: bad offset or weight"),
            Error::BufferTooSmall {
                buffer,
                len,
                needed,
            } => write!(f, "buffer `{buffer}` holds {len} elements, {needed} needed"),
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for Error {}
