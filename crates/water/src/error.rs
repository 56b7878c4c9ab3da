//! The crate's one error type.

use core::fmt;

/// Everything that can go wrong in `water`. A variant that comes from a limit names the
/// limit (a `pub const` of this crate), the offending value and the item. User input never
/// panics: builders, bakers and decoders return this instead.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// A float input is NaN or infinite where a finite value is needed.
    NonFinite {
        /// Which input.
        field: &'static str,
    },
    /// A float input lies outside its allowed range.
    OutOfRange {
        /// Which input.
        field: &'static str,
        /// The value given.
        value: f32,
        /// Smallest allowed value.
        min: f32,
        /// Largest allowed value.
        max: f32,
    },
    /// A size or count breaks a structural rule (power of two, divisibility, ...).
    InvalidSize {
        /// Which input.
        field: &'static str,
        /// The value given.
        value: u32,
        /// The rule it breaks.
        rule: &'static str,
    },
    /// A slice does not have the length its dimensions call for.
    LengthMismatch {
        /// Which input.
        field: &'static str,
        /// Its length.
        len: usize,
        /// The length needed.
        expected: usize,
    },
    /// A count or size exceeds one of the crate's named limits.
    LimitExceeded {
        /// What exceeded it.
        what: &'static str,
        /// The value.
        value: u64,
        /// The limit.
        limit: u64,
        /// The limit's name (a `pub const` of this crate).
        limit_name: &'static str,
    },
    /// A packed field does not fit its bits.
    FieldTooWide {
        /// The field.
        field: &'static str,
        /// The value given.
        value: u32,
        /// Bits available.
        bits: u32,
    },
    /// A water body's geometry is unusable.
    DegenerateBody {
        /// Which kind of body: "lake" or "river".
        kind: &'static str,
        /// Its index in the builder.
        index: u32,
        /// What is wrong.
        reason: &'static str,
    },
    /// A baked blob (world data, flow atlas) is malformed.
    InvalidData {
        /// Which blob.
        what: &'static str,
        /// What is wrong.
        reason: &'static str,
    },
    /// An atlas has no free slot left.
    AtlasFull {
        /// Slots in the atlas.
        capacity: u32,
    },
    /// A progress callback asked to stop.
    Cancelled,
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Error::NonFinite { field } => write!(f, "{field} is not finite"),
            Error::OutOfRange {
                field,
                value,
                min,
                max,
            } => write!(f, "{field} = {value} is outside [{min}, {max}]"),
            Error::InvalidSize { field, value, rule } => {
                write!(f, "{field} = {value} is invalid: must be {rule}")
            }
            Error::LengthMismatch {
                field,
                len,
                expected,
            } => write!(f, "{field} has {len} entries, {expected} expected"),
            Error::LimitExceeded {
                what,
                value,
                limit,
                limit_name,
            } => write!(f, "{what} = {value} exceeds {limit_name} = {limit}"),
            Error::FieldTooWide { field, value, bits } => {
                write!(f, "{field} = {value} does not fit in {bits} bits")
            }
            Error::DegenerateBody {
                kind,
                index,
                reason,
            } => write!(f, "{kind} {index}: {reason}"),
            Error::InvalidData { what, reason } => write!(f, "invalid {what}: {reason}"),
            Error::AtlasFull { capacity } => {
                write!(f, "flow atlas full: all {capacity} tile slots are in use")
            }
            Error::Cancelled => f.write_str("cancelled by the progress callback"),
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for Error {}
