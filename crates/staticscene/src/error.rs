//! The crate's one error type.

use core::fmt;

/// A packed field of the query records, named in errors.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Field {
    /// [`QueryInstance`](crate::QueryInstance) filter mask (3 bits).
    Filter,
    /// [`QueryInstance`](crate::QueryInstance) flags (2 bits).
    Flags,
    /// [`QueryInstance`](crate::QueryInstance) setup index (12 bits).
    Setup,
    /// [`QueryInstance`](crate::QueryInstance) object index (17 bits).
    Object,
    /// [`QueryInstance`](crate::QueryInstance) parent bounds index (15 bits).
    ParentBounds,
    /// [`QueryInstance`](crate::QueryInstance) child bounds index (15 bits).
    ChildBounds,
    /// [`QueryInstance`](crate::QueryInstance) matrix index (14 bits).
    Matrix,
    /// Parent LOD range start (12-bit distance code).
    ParentLodMin,
    /// Parent LOD range end (12-bit distance code).
    ParentLodMax,
    /// Child LOD range start (12-bit distance code).
    ChildLodMin,
    /// Child LOD range end (12-bit distance code).
    ChildLodMax,
    /// A LOD distance outside any level (a tree node's range).
    LodDistance,
    /// [`QueryObject`](crate::QueryObject) LOD scale (f16).
    LodScale,
    /// A half-precision bounding box ([`HalfAabb`](crate::HalfAabb)).
    HalfBounds,
    /// A float bounding box (setup bounds, LOD node bounds).
    Bounds,
    /// An object or node transform.
    Transform,
    /// An object's world position.
    Position,
}

impl fmt::Display for Field {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Field::Filter => "filter mask",
            Field::Flags => "flags",
            Field::Setup => "setup index",
            Field::Object => "object index",
            Field::ParentBounds => "parent bounds index",
            Field::ChildBounds => "child bounds index",
            Field::Matrix => "matrix index",
            Field::ParentLodMin => "parent LOD min distance",
            Field::ParentLodMax => "parent LOD max distance",
            Field::ChildLodMin => "child LOD min distance",
            Field::ChildLodMax => "child LOD max distance",
            Field::LodDistance => "LOD distance",
            Field::LodScale => "LOD scale",
            Field::HalfBounds => "half-precision bounds",
            Field::Bounds => "bounds",
            Field::Transform => "transform",
            Field::Position => "position",
        })
    }
}

/// Everything that can go wrong in `staticscene`. Limits from the talk are named `pub
/// const`s of this crate; exceeding one names the field, the value and the limit. User
/// input never panics: builders, decoders and the query return this instead.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// An integer field does not fit its bits.
    FieldOverflow {
        /// The field.
        field: Field,
        /// The value given.
        value: u64,
        /// The largest value the field holds.
        max: u64,
    },
    /// A float that must be finite (and, for distances and scales, non-negative or
    /// positive) is not, or is too large for its encoding.
    FloatOutOfRange {
        /// The field.
        field: Field,
        /// The value given.
        value: f64,
        /// The largest value the encoding holds.
        max: f64,
    },
    /// A range or box whose minimum exceeds its maximum.
    Inverted {
        /// The field.
        field: Field,
        /// The minimum given.
        min: f64,
        /// The maximum given.
        max: f64,
    },
    /// A decoded [`QueryInstance`](crate::QueryInstance) has its spare bit set: not a word
    /// this crate wrote.
    SpareBitSet,
    /// A depth buffer with a zero side, or whose length is not `width * height`.
    DepthSize {
        /// Width given.
        width: u32,
        /// Height given.
        height: u32,
        /// Samples given.
        len: usize,
    },
    /// A viewport with a zero side, or larger than [`MAX_VIEWPORT`](crate::MAX_VIEWPORT).
    Viewport {
        /// Width given.
        width: u32,
        /// Height given.
        height: u32,
    },
    /// A camera or projection with non-finite entries.
    NonFiniteCamera,
    /// A LOD fade length above [`MAX_FADE_FRAMES`](crate::MAX_FADE_FRAMES).
    FadeFrames {
        /// Frames given.
        frames: u32,
    },
    /// A placed object names a resource outside the resource list.
    UnknownResource {
        /// The object's position in its streaming group.
        object: usize,
        /// The resource index given.
        resource: usize,
        /// Resources available.
        resources: usize,
    },
    /// A tile's instance whose record index points outside the tile's table
    /// ([`StaticTile::from_parts`](crate::StaticTile::from_parts)).
    TileRecord {
        /// The tile.
        tile: u32,
        /// The instance's index in the tile.
        instance: usize,
        /// The index field.
        field: Field,
        /// The index given.
        value: u32,
        /// Entries in the table it indexes.
        len: usize,
    },
    /// A tile's clusters that do not cover its instances in order (`cluster`: the first
    /// that does not follow on, or the cluster count when they stop short).
    TileClusters {
        /// The tile.
        tile: u32,
        /// The cluster.
        cluster: usize,
    },
    /// A streaming group id that is already loaded (adds and removes must match).
    DuplicateGroup {
        /// The group id.
        group: u64,
    },
    /// A streaming group id that is not loaded.
    UnknownGroup {
        /// The group id.
        group: u64,
    },
    /// A configuration value outside its documented range.
    Config {
        /// What is wrong.
        what: &'static str,
    },
    /// The wave model refused a run.
    Wave(wave::Error),
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Error::FieldOverflow { field, value, max } => {
                write!(f, "{field} {value} does not fit (max {max})")
            }
            Error::FloatOutOfRange { field, value, max } => {
                write!(f, "{field} {value} out of range (finite, 0..={max})")
            }
            Error::Inverted { field, min, max } => {
                write!(f, "{field} inverted: min {min} > max {max}")
            }
            Error::SpareBitSet => f.write_str("QueryInstance spare bit 127 is set"),
            Error::DepthSize { width, height, len } => write!(
                f,
                "depth buffer of {len} samples for {width} x {height} (sides must be non-zero)"
            ),
            Error::Viewport { width, height } => write!(
                f,
                "viewport {width} x {height} (sides 1..={})",
                crate::MAX_VIEWPORT
            ),
            Error::NonFiniteCamera => f.write_str("camera or projection is not finite"),
            Error::FadeFrames { frames } => write!(
                f,
                "LOD fade of {frames} frames (max {})",
                crate::MAX_FADE_FRAMES
            ),
            Error::UnknownResource {
                object,
                resource,
                resources,
            } => write!(
                f,
                "object {object} names resource {resource} of {resources}"
            ),
            Error::TileRecord {
                tile,
                instance,
                field,
                value,
                len,
            } => write!(
                f,
                "tile {tile}, instance {instance}: {field} {value} outside the tile's {len}"
            ),
            Error::TileClusters { tile, cluster } => write!(
                f,
                "tile {tile}: cluster {cluster} does not follow on (clusters must cover the instances in order)"
            ),
            Error::DuplicateGroup { group } => write!(f, "streaming group {group} already loaded"),
            Error::UnknownGroup { group } => write!(f, "streaming group {group} is not loaded"),
            Error::Config { what } => write!(f, "configuration: {what}"),
            Error::Wave(e) => write!(f, "wave: {e}"),
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for Error {}

impl From<wave::Error> for Error {
    fn from(e: wave::Error) -> Self {
        Error::Wave(e)
    }
}
