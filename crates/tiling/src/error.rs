//! The crate's one error type.

use core::fmt;

use visbuf::VisLayout;

/// Everything that can go wrong in `tiling`. A variant that comes from one of the talk's
/// limits names the limit (a `pub const` of this crate or of `visbuf`), the offending
/// value and the item (the batch, by its index in the caller's slice).
///
/// User input never panics: the builder and the passes return this instead. Inside the
/// passes, bad *data* (vis words that name no micro batch, primitives past a geometry's
/// count, indices past the index buffer) is not an error: it is skipped and counted in
/// [`PixelStats`](crate::PixelStats), as the GPU twin does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Error {
    /// A batch's geometry has more primitives than a vis ID can name (16-bit indices,
    /// [`MAX_PRIMITIVES_PER_GEOMETRY`](crate::MAX_PRIMITIVES_PER_GEOMETRY)); it cannot be
    /// split.
    GeometryTooLarge {
        /// Index of the batch in the caller's slice.
        batch: u32,
        /// Primitives in its geometry.
        primitives: u32,
        /// The limit, [`MAX_PRIMITIVES_PER_GEOMETRY`](crate::MAX_PRIMITIVES_PER_GEOMETRY).
        limit: u32,
    },
    /// A batch's geometry has no primitives or no vertices.
    EmptyGeometry {
        /// Index of the batch in the caller's slice.
        batch: u32,
    },
    /// One instance of a batch has more vertices than a micro batch may hold (the
    /// smaller of [`PlanConfig::max_micro_batch_vertices`](crate::PlanConfig) and half
    /// the vertex ring), so no split can make it fit.
    InstanceTooLarge {
        /// Index of the batch in the caller's slice.
        batch: u32,
        /// Vertices of one instance.
        vertices: u32,
        /// The micro-batch vertex limit in force.
        limit: u32,
    },
    /// The work needs more passes than the limit
    /// ([`MAX_PASSES`](crate::MAX_PASSES) or the configured one).
    TooManyPasses {
        /// Index of the batch that needed the pass past the limit.
        batch: u32,
        /// The pass limit in force.
        limit: u32,
    },
    /// The layout's micro-batch IDs ran out (65 535 usable, 16 383 with VRS).
    MicroBatchIdsExhausted {
        /// Index of the batch whose micro batch did not get its IDs.
        batch: u32,
        /// IDs the micro batch needed.
        needed: u32,
        /// IDs left.
        available: u32,
        /// The layout.
        layout: VisLayout,
    },
    /// A configuration value outside its allowed range.
    InvalidConfig {
        /// Which setting.
        what: &'static str,
        /// The value given.
        value: u64,
        /// The smallest allowed value.
        min: u64,
        /// The largest allowed value.
        max: u64,
    },
    /// A buffer whose length does not match the frame (vis buffer, validity mask, a
    /// previous phase's output).
    BufferSize {
        /// Which buffer.
        what: &'static str,
        /// The length needed (elements).
        expected: u64,
        /// The length given.
        got: u64,
    },
    /// A previous phase's output that does not belong to these inputs (its offsets are
    /// not the prefix sums of its counts, or it was made for another frame size or pass
    /// count).
    MismatchedPhase {
        /// Which input.
        what: &'static str,
    },
}

impl Error {
    /// `Ok` when buffer `what` holds `got` elements, the `expected` length; else
    /// [`Error::BufferSize`].
    pub(crate) fn check_len(what: &'static str, expected: u64, got: usize) -> Result<(), Self> {
        if got as u64 == expected {
            Ok(())
        } else {
            Err(Self::BufferSize {
                what,
                expected,
                got: got as u64,
            })
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Error::GeometryTooLarge {
                batch,
                primitives,
                limit,
            } => write!(
                f,
                "batch {batch}: geometry has {primitives} primitives, over \
                 MAX_PRIMITIVES_PER_GEOMETRY = {limit} (16-bit indices); it cannot be split"
            ),
            Error::EmptyGeometry { batch } => {
                write!(
                    f,
                    "batch {batch}: geometry has no primitives or no vertices"
                )
            }
            Error::InstanceTooLarge {
                batch,
                vertices,
                limit,
            } => write!(
                f,
                "batch {batch}: one instance has {vertices} vertices, over the micro-batch \
                 vertex limit {limit} (MAX_MICRO_BATCH_VERTICES or half the vertex ring)"
            ),
            Error::TooManyPasses { batch, limit } => write!(
                f,
                "batch {batch}: needs a pass past the limit of {limit} passes (MAX_PASSES)"
            ),
            Error::MicroBatchIdsExhausted {
                batch,
                needed,
                available,
                layout,
            } => write!(
                f,
                "batch {batch}: a micro batch needs {needed} micro-batch IDs but only \
                 {available} are left in the {layout:?} layout"
            ),
            Error::InvalidConfig {
                what,
                value,
                min,
                max,
            } => write!(f, "{what} = {value} is outside {min}..={max}"),
            Error::BufferSize {
                what,
                expected,
                got,
            } => write!(f, "{what}: {got} elements given, {expected} needed"),
            Error::MismatchedPhase { what } => {
                write!(f, "{what} does not belong to these inputs")
            }
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for Error {}
