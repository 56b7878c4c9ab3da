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
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Error::InvalidParameter { name, value } => {
                write!(f, "invalid parameter `{name}`: {value}")
            }
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for Error {}
