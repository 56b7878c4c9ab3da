//! Horizon Zero Dawn's static-scene visibility query (crate docs are completed below).
#![no_std]

extern crate alloc;
#[cfg(feature = "std")]
extern crate std;

#[cfg(not(any(feature = "std", feature = "libm")))]
compile_error!("staticscene needs float math: enable the `std` (default) or `libm` feature");

mod dedup;
pub mod demo;
mod error;
pub mod hiz;
mod math;
pub mod output;
#[cfg(feature = "parallel")]
mod parallel;
pub mod query;
pub mod records;
pub mod resource;
pub mod scene;
pub mod tile;
pub mod view;

pub use error::{Error, Field};
pub use hiz::{HIZ_DEPTH_EPSILON, HiZ, HiZLevel};
pub use output::*;
pub use query::{ClusterJob, ClusterResult, QueryStats, TileBuffers, query_cluster};
pub use records::*;
pub use resource::{
    Aabb, DynamicReason, FlatLeaf, FlatLod, FlatResource, LodLevel, MeshNode, MeshPart,
    ResourceLibrary, StaticMesh, flatten,
};
pub use scene::{BuiltTile, QueryOptions, QueryOutput, Scene, TileStreamer, TileUpdate};
pub use tile::{
    BuildConfig, Cluster, CullInfo, DynamicObject, LodLimits, MIN_CLUSTER_INSTANCES,
    OBJECT_EXTENT_MAX, ORPHAN_INSTANCES, Partition, PlacedObject, PreparedGroup, PreparedObject,
    StaticTile, StreamingGroup, TILE_SPLIT_INSTANCES, TileId, build_tiles, prepare_group,
};
pub use view::{
    Camera, FRUSTUM_TOLERANCE, QUERY_FLAG_FADE, QUERY_FLAG_OCCLUSION, QUERY_FLAG_REVERSED_DEPTH,
    QUERY_FLAG_SIZE, QueryParams, ViewDesc, ViewKind, box_outside_frustum, snap_origin,
};
pub use wave::WaveWidth;

/// The largest viewport side the query accepts, pixels.
pub const MAX_VIEWPORT: u32 = 16384;
/// The longest LOD fade, frames.
pub const MAX_FADE_FRAMES: u32 = 127;
