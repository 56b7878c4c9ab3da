//! The crate's one error type.

use core::fmt;

use crate::id::VisLayout;

/// Everything that can go wrong in `visbuf`. Every variant that comes from a limit of the
/// talk names the limit (a `pub const` of this crate), the offending value and the item.
///
/// User input never panics: encoders and decoders return this instead.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// A geometry has more primitives than a vis ID can name
    /// ([`MAX_PRIMITIVES_PER_GEOMETRY`](crate::MAX_PRIMITIVES_PER_GEOMETRY)).
    TooManyPrimitives {
        /// Primitives in the geometry.
        count: u64,
        /// The limit, [`MAX_PRIMITIVES_PER_GEOMETRY`](crate::MAX_PRIMITIVES_PER_GEOMETRY).
        limit: u32,
    },
    /// A geometry with zero primitives was given where one is needed.
    EmptyGeometry,
    /// A primitive-bit count above [`MAX_PRIMITIVE_BITS`](crate::MAX_PRIMITIVE_BITS).
    PrimitiveBitsTooLarge {
        /// The bit count given.
        bits: u32,
        /// The limit, [`MAX_PRIMITIVE_BITS`](crate::MAX_PRIMITIVE_BITS).
        limit: u32,
    },
    /// A primitive index does not fit the geometry's primitive bits.
    PrimitiveOutOfRange {
        /// The primitive index given.
        primitive: u32,
        /// The geometry's primitive bits.
        bits: u32,
    },
    /// An instance field does not fit the instance bits (`16 - primitive bits`).
    InstanceFieldOutOfRange {
        /// The instance field given.
        instance: u32,
        /// The instance bits available.
        bits: u32,
    },
    /// A micro-batch ID outside the usable range of the layout (the last ID is reserved
    /// for [`VIS_NONE`](crate::VIS_NONE)).
    MicroBatchIdOutOfRange {
        /// The ID given.
        id: u32,
        /// How many IDs the layout has: [`MICRO_BATCH_IDS`](crate::MICRO_BATCH_IDS) or
        /// [`MICRO_BATCH_IDS_VRS`](crate::MICRO_BATCH_IDS_VRS).
        limit: u32,
        /// The layout.
        layout: VisLayout,
    },
    /// A batch's instance count is outside 1..=
    /// [`MAX_INSTANCES_PER_MICRO_BATCH`](crate::MAX_INSTANCES_PER_MICRO_BATCH).
    InstanceCountOutOfRange {
        /// The instance count given.
        count: u32,
        /// The limit.
        limit: u32,
    },
    /// Allocating a batch's micro-batch-ID range would run past the layout's IDs.
    MicroBatchIdsExhausted {
        /// Index of the batch that did not fit (its order of allocation).
        batch: u32,
        /// IDs the batch needs.
        needed: u32,
        /// IDs still free.
        available: u32,
        /// The layout.
        layout: VisLayout,
    },
    /// A batch index past the batches allocated.
    UnknownBatch {
        /// The batch given.
        batch: u32,
        /// Batches allocated.
        batches: u32,
    },
    /// An instance index past its batch's instance count.
    InstanceOutOfRange {
        /// The instance given.
        instance: u32,
        /// Instances in the batch.
        count: u32,
    },
    /// An index buffer whose length is not a multiple of 3 (triangle lists only).
    IndexCountNotMultipleOf3 {
        /// The index count given.
        len: usize,
    },
    /// A triangle refers to a vertex that does not exist.
    IndexOutOfRange {
        /// The triangle.
        triangle: u32,
        /// The index it holds.
        index: u32,
        /// Vertices in the mesh.
        vertex_count: u32,
    },
    /// A geometry has more vertices than 16-bit indices reach
    /// ([`MAX_VERTICES_PER_GEOMETRY`](crate::MAX_VERTICES_PER_GEOMETRY)).
    TooManyVertices {
        /// Vertices in the mesh.
        count: u32,
        /// The limit.
        limit: u32,
    },
    /// Vertex data shorter than the mesh's vertex count.
    VertexDataTooShort {
        /// Entries given.
        len: usize,
        /// Entries needed.
        needed: u32,
    },
    /// A float input is NaN or infinite where a finite value is needed.
    NonFinite {
        /// Which input.
        field: &'static str,
    },
    /// A float input lies outside the range its packed format can hold.
    ValueOutOfRange {
        /// Which input.
        field: &'static str,
        /// The value given.
        value: f32,
        /// Smallest value the format holds.
        min: f32,
        /// Largest value the format holds.
        max: f32,
    },
    /// Clip-space z cannot be recovered from w for this projection (w does not depend on
    /// view depth, as in an orthographic projection).
    DepthNotRecoverableFromW,
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Error::TooManyPrimitives { count, limit } => write!(
                f,
                "geometry has {count} primitives, more than MAX_PRIMITIVES_PER_GEOMETRY = {limit}"
            ),
            Error::EmptyGeometry => f.write_str("geometry has no primitives"),
            Error::PrimitiveBitsTooLarge { bits, limit } => write!(
                f,
                "primitive bit count {bits} exceeds MAX_PRIMITIVE_BITS = {limit}"
            ),
            Error::PrimitiveOutOfRange { primitive, bits } => write!(
                f,
                "primitive {primitive} does not fit in {bits} primitive bits"
            ),
            Error::InstanceFieldOutOfRange { instance, bits } => write!(
                f,
                "instance field {instance} does not fit in {bits} instance bits"
            ),
            Error::MicroBatchIdOutOfRange { id, limit, layout } => write!(
                f,
                "micro-batch ID {id} out of range for the {layout:?} layout \
                 (IDs 0..{} usable, {} reserved for VIS_NONE; limit {limit})",
                limit - 1,
                limit - 1
            ),
            Error::InstanceCountOutOfRange { count, limit } => write!(
                f,
                "instance count {count} outside 1..=MAX_INSTANCES_PER_MICRO_BATCH = {limit}"
            ),
            Error::MicroBatchIdsExhausted {
                batch,
                needed,
                available,
                layout,
            } => write!(
                f,
                "batch {batch} needs {needed} micro-batch IDs but only {available} remain \
                 in the {layout:?} layout"
            ),
            Error::UnknownBatch { batch, batches } => {
                write!(f, "batch {batch} does not exist ({batches} batches allocated)")
            }
            Error::InstanceOutOfRange { instance, count } => {
                write!(f, "instance {instance} past the batch's {count} instances")
            }
            Error::IndexCountNotMultipleOf3 { len } => {
                write!(f, "index count {len} is not a multiple of 3")
            }
            Error::IndexOutOfRange {
                triangle,
                index,
                vertex_count,
            } => write!(
                f,
                "triangle {triangle} refers to vertex {index}, but the mesh has {vertex_count} vertices"
            ),
            Error::TooManyVertices { count, limit } => write!(
                f,
                "geometry has {count} vertices, more than MAX_VERTICES_PER_GEOMETRY = {limit} (16-bit indices)"
            ),
            Error::VertexDataTooShort { len, needed } => write!(
                f,
                "vertex data has {len} entries, the mesh needs {needed}"
            ),
            Error::NonFinite { field } => write!(f, "{field} is not finite"),
            Error::ValueOutOfRange {
                field,
                value,
                min,
                max,
            } => write!(f, "{field} = {value} outside the packable range [{min}, {max}]"),
            Error::DepthNotRecoverableFromW => f.write_str(
                "clip-space z cannot be recovered from w: the projection's w does not depend on depth",
            ),
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for Error {}
