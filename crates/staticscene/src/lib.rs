//! Horizon Zero Dawn's static-scene visibility query (Will Vale, "Decima: Visibility in
//! Horizon Zero Dawn", GDC 2018; seed 001) on the CPU, written as the twin of a planned
//! GPU compute pass: the same packed buffers in, the same batched draw items out. The
//! records and per-thread tests have a WGSL twin ([`wgsl::QUERY`]), and the query runs as
//! a GPU compute pass ([`pass::QUERY_PASS`], with the HiZ reduction [`pass::HIZ_PASS`])
//! that `gpu::statics::StaticQuery` dispatches; the query does not feed `gpu`'s laydown yet. For
//! 0.5-1.5M static instances: immutable tiles built on
//! the streaming thread, clusters pre-culled on the CPU, one compute job per visible
//! cluster, one thread per 16-byte instance.
//!
//! - [`records`]: the tile's GPU records with their bit tables: [`QueryInstance`] (16 B:
//!   filter, flags, setup/object/bounds/matrix indices, parent and child 12-bit LOD
//!   brackets, group-end bit), [`QueryObject`] (64 B: object-to-snapped matrix, snapped
//!   integer position, LOD scale and flags), [`QuerySetup`] (32 B: accurate local bounds,
//!   renderer handle), [`Transform4x3`] (48 B), [`HalfAabb`] (12 B), the [`LodDistance`]
//!   minifloat.
//! - [`resource`]: mesh-resource trees ([`MeshNode`]: LOD switches, multi-meshes, static
//!   leaves) flattened to two LOD levels per leaf ([`flatten`], [`ResourceLibrary`]);
//!   what does not fit goes to a dynamic list with its [`DynamicReason`].
//! - [`tile`]: [`StaticTile`]s from streaming groups (split above 24K instances, the
//!   orphan tile under 1K, split again when an index space would overflow), records
//!   stored once per tile by hashing, the spatial+ partition into [`Cluster`]s.
//! - [`scene`]: [`TileStreamer`] (streaming thread: groups in, [`TileUpdate`]s out,
//!   `Send`) and [`Scene`] (main thread: O(1) activation, the per-view query with the CPU
//!   pre-cull of tiles and clusters).
//! - [`view`]: [`Camera`], [`ViewDesc`] and the query's uniform block [`QueryParams`];
//!   floating origin (the camera snapped to the 1 m grid), clip conventions.
//! - [`query`]: [`query_cluster`], the pass itself: filter, parent LOD, child LOD,
//!   accurate frustum, screen size, HiZ occlusion, LOD fade, batched output through
//!   `wave`'s run-grouped append.
//! - [`hiz`]: the conservative depth pyramid ([`HiZ`]; non-power-of-two sizes, reversed
//!   depth) and the box test against it.
//! - [`output`]: the batched output, [`DrawableSetupInstance`] (64 B, or 112 B with the
//!   previous transform) and [`DrawableSetupBatch`] (48 B).
//! - [`wgsl`]: `staticscene::query` ([`wgsl::QUERY`]), the WGSL twin of the records and
//!   the per-thread tests, and the two pass modules, validated by naga, their constants
//!   and struct layouts tied to the Rust ones.
//! - [`pass`]: the query and HiZ passes' descriptions, the pooled record layout
//!   ([`pass::tile_records`], [`pass::TileSlots`]), the GPU jobs ([`Scene::plan_gpu`]);
//!   `tests/device.rs` runs them against the CPU twin.
//! - [`baseline`]: the benches' flat loop (no tiles, clusters or packing).
//! - [`demo`]: a procedural city (1.5M instances for the benches) and a box rasteriser
//!   for depth buffers.
//!
//! Features: `std` (default), `libm` (float math without std: build with
//! `--no-default-features --features libm`), `parallel` ([`Scene::par_query`] on rayon,
//! equal to [`Scene::query`]).
//!
//! Units and conventions: metres; world positions f64; floating space = world minus the
//! view's snapped origin, f32; wgpu clip space (depth 0..1, or reversed); pixels from the
//! top-left, +y down. Details in [`view`].
//!
//! # Example
//!
//! ```
//! use staticscene::glam::{DVec3, Mat4, Vec3};
//! use staticscene::*;
//!
//! // A resource: a LOD switch between a detailed mesh (0-50 m) and a simple one.
//! let unit = Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0));
//! let leaf = |setup| MeshNode::Static(StaticMesh { setup, bounds: unit, filter: FILTER_ALL, flags: 0 });
//! let tree = MeshNode::Lod {
//!     bounds: unit,
//!     levels: vec![
//!         LodLevel { min: 0.0, max: 50.0, node: leaf(100) },
//!         LodLevel { min: 50.0, max: f32::INFINITY, node: leaf(101) },
//!     ],
//! };
//! // On the streaming thread: a group of 2000 placements a million metres out.
//! let far = DVec3::new(1.0e6, 0.0, 1.0e6);
//! let objects = (0..2000)
//!     .map(|i| PlacedObject::new(0, far + DVec3::new(f64::from(i % 50) * 4.0, 0.0, -f64::from(i / 50) * 4.0)))
//!     .collect();
//! let mut streamer = TileStreamer::new(ResourceLibrary::new(&[tree]), BuildConfig::default());
//! let update = streamer.add_group(&StreamingGroup { id: 7, objects })?;
//!
//! // On the main thread: activate, then query a camera view.
//! let mut scene = Scene::new();
//! scene.apply(update);
//! let camera = Camera::look_at(
//!     far + DVec3::new(100.0, 10.0, 30.0),
//!     far + DVec3::new(100.0, 0.0, -80.0),
//!     DVec3::Y,
//!     Mat4::perspective_rh(1.2, 16.0 / 9.0, 0.1, 2000.0),
//!     false,
//! );
//! let mut view = ViewDesc::camera(camera, [1280, 720]);
//! view.fade_frames = 0; // switch LODs at once (the default fades over 8 frames)
//! let params = QueryParams::new(&view)?;
//! let mut out = QueryOutput::<DrawableSetupInstance>::new();
//! scene.query(&params, None, &QueryOptions::default(), &mut out)?;
//!
//! // Near objects draw setup 100, far ones 101, in batches of up to 64 instances.
//! assert!(out.batches.iter().any(|b| b.setup == 100) && out.batches.iter().any(|b| b.setup == 101));
//! assert!(out.batches.len() * 4 < out.instances.len());
//! for b in &out.batches {
//!     let first = &out.instances[b.first_instance as usize];
//!     // Transforms are relative to the snapped camera: small numbers, full precision.
//!     assert!(first.local_to_floating.translation().length() < 2000.0);
//! }
//! # Ok::<(), staticscene::Error>(())
//! ```
#![no_std]

extern crate alloc;
#[cfg(feature = "std")]
extern crate std;

#[cfg(not(any(feature = "std", feature = "libm")))]
compile_error!("staticscene needs float math: enable the `std` (default) or `libm` feature");

pub mod baseline;
mod dedup;
pub mod demo;
mod error;
pub mod hiz;
mod math;
pub mod output;
#[cfg(feature = "parallel")]
mod parallel;
pub mod pass;
pub mod query;
pub mod records;
pub mod resource;
pub mod scene;
pub mod tile;
pub mod view;
pub mod wgsl;

pub use error::{Error, Field};
/// The glam version this crate's API uses; use `staticscene::glam` to avoid a version mismatch
/// with a `glam` of your own.
pub use glam;
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
    StaticTile, StreamingGroup, TILE_SPLIT_INSTANCES, TileId, TileParts, build_tiles,
    prepare_group,
};
pub use view::{
    CAMERA_STATE_VISIBLE, Camera, FRUSTUM_TOLERANCE, OcclusionPass, QUERY_FLAG_FADE,
    QUERY_FLAG_FIRST_PASS, QUERY_FLAG_OCCLUSION, QUERY_FLAG_REVERSED_DEPTH, QUERY_FLAG_SECOND_PASS,
    QUERY_FLAG_SHADOW, QUERY_FLAG_SIZE, QueryParams, ViewDesc, ViewKind, box_outside_frustum,
    snap_origin,
};
pub use wave::WaveWidth;

/// The largest viewport side the query accepts, pixels.
pub const MAX_VIEWPORT: u32 = 16384;
/// The longest LOD fade, frames.
pub const MAX_FADE_FRAMES: u32 = 127;
