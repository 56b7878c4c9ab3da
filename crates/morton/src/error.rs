//! The crate's one error type.

use core::fmt;

/// Everything that can go wrong in `morton`. No function panics on bad input; each failure
/// names the limit, the value and the item involved.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// A coordinate does not fit the bits per axis of the chosen code (only the `try_`
    /// encoders check; the plain ones ignore the excess bits).
    CoordinateTooLarge {
        /// Axis: 0 = x, 1 = y, 2 = z.
        axis: u8,
        /// The coordinate given.
        value: u32,
        /// The largest coordinate the code holds, `2^bits - 1`.
        max: u32,
    },
    /// Slices that must have the same length do not.
    LengthMismatch {
        /// Which argument (`"ys"`, `"out"`, ...).
        what: &'static str,
        /// The length of the first input.
        expected: usize,
        /// The length of `what`.
        got: usize,
    },
    /// A quantiser's bits per axis is zero or above what the key holds
    /// ([`crate::BITS3_U64`] for 3D, [`crate::BITS2_U64`] for 2D; [`crate::BITS3_U32`] /
    /// [`crate::BITS2_U32`] for 32-bit keys).
    BadBits {
        /// The bits per axis asked for.
        bits: u32,
        /// The largest allowed for this use.
        max: u32,
    },
    /// A quantiser's bounds have a NaN or infinite component, or `min > max` on an axis.
    BadBounds {
        /// The axis at fault: 0 = x, 1 = y, 2 = z.
        axis: u8,
        /// The bound's minimum on that axis.
        min: f32,
        /// The bound's maximum on that axis.
        max: f32,
    },
    /// A position had a NaN component. Batch functions still write a key for every point
    /// (NaN components map to cell 0) and report the first offending index.
    NanPosition {
        /// Index of the first point with a NaN, 0 for single-point calls.
        index: usize,
    },
    /// More keys than a u32 index can address ([`crate::MAX_SORT_KEYS`]).
    TooManyKeys {
        /// The number of keys given.
        len: usize,
        /// [`crate::MAX_SORT_KEYS`].
        max: usize,
    },
    /// A batch path was requested that this CPU (or this build) does not have.
    PathUnavailable {
        /// The path asked for.
        path: crate::Path,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::CoordinateTooLarge { axis, value, max } => write!(
                f,
                "coordinate {value} on axis {} exceeds the code's limit {max}",
                ["x", "y", "z"][axis as usize % 3]
            ),
            Self::LengthMismatch {
                what,
                expected,
                got,
            } => write!(
                f,
                "slice `{what}` has length {got}, expected {expected} (the first input's length)"
            ),
            Self::BadBits { bits, max } => {
                write!(f, "{bits} bits per axis is outside 1..={max}")
            }
            Self::BadBounds { axis, min, max } => write!(
                f,
                "quantiser bounds on axis {} are not finite with min <= max: min {min}, max {max}",
                ["x", "y", "z"][axis as usize % 3]
            ),
            Self::NanPosition { index } => write!(f, "position {index} has a NaN component"),
            Self::TooManyKeys { len, max } => write!(
                f,
                "{len} keys exceed the sort limit of {max} (indices are u32)"
            ),
            Self::PathUnavailable { path } => {
                write!(
                    f,
                    "batch path {path:?} is not available on this CPU or build"
                )
            }
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for Error {}
