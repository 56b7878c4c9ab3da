//! Horizon Forbidden West's analysis of the visibility buffer (GDC 2022, seed 000), as CPU
//! twins of its GPU passes: which pixels and which vertices each material pass shades, and
//! the command buffers that drive the shading.
//!
//! - [`plan`]: the CPU setup. Batches sorted by shader, per-batch data and a quantised
//!   Morton code, split into **micro batches** (at most 64k triangles, 192k vertices, 64k
//!   instances, instance overflow into consecutive micro-batch IDs) and packed into
//!   **passes** (one shader, at most half the vertex ring, 32 batch groups; at most 256
//!   passes). Output: the MicroBatchInfoTable ([`MicroBatchInfo`], indexed by micro-batch
//!   ID), the micro-batch order buffer, [`PassInfo`] and the per-instance
//!   ([`InstanceRef`]) mapping the laydown writes.
//! - [`classify`](mod@classify): the three classification phases over a `width x height` vis buffer:
//!   [`laydown_finalize`] (per 128x128 tile and pass, a mask of batch groups),
//!   [`mid_classify`] (compact counter offsets, pixel counts, the vertex cull buffer,
//!   pixel-command offsets) and [`classify_output`] (16-bit pixel commands, final counts,
//!   [`WaveCommand`]s, one [`PassDispatch`] per pass). [`classify_phases`] runs the
//!   three in turn, as the GPU does; [`classify()`] computes the same outputs in one scan
//!   per tile (the fast CPU path).
//! - [`vrs`]: with the VRS word layout, quad commands (12-bit quad index, 4-bit pixel
//!   mask) and the wave's work expansion into its per-pixel broadcast list.
//! - [`vertex`]: uber chunks, the histogram pyramid and the micro-batch-ID deltas that
//!   turn the vertex cull buffer into [`VertexWaveCommand`]s and per-pass dispatches.
//! - [`measure`](mod@measure): the talk's closing tables (pixel-shading waves with depth equal against
//!   deferred texturing, unfilled lanes, vertices before and after chunk culling).
//! - [`wgsl`]: the GPU twins, complete WGSL compute modules (`visbuf`'s ID decoding and
//!   `wave`'s appends built in) with the same buffer layouts, their bindings and dispatch
//!   sizes tabled there. `tests/device.rs` runs them against these CPU twins bit for bit.
//! - `parallel` (feature `parallel`): the classification over tiles on many threads
//!   (rayon), equal to the sequential result.
//!
//! Vis-buffer words are decoded only through `visbuf` ([`visbuf::VisId`],
//! [`visbuf::PrimitiveBits`], [`visbuf::instance_index`]); wave widths and the expansion's
//! prefix sums come from `wave`.
//!
//! # Coordinates and units
//!
//! Pixels are `(x, y)` from the top-left, `x` right and `y` down; the vis buffer is
//! row-major, `width * height` words. Tiles are 128x128 from the top-left (the last row
//! and column may be partial); tile `t` is `(t % tiles_x, t / tiles_x)`. Counts and
//! offsets are elements of the named buffer, never bytes, unless a name says bytes.
//!
//! # Example
//!
//! ```
//! use tiling::{build_plan, classify, Batch, ClassifyConfig, Geometry, PlanConfig, VisBuffer};
//! use visbuf::{VisFields, VisId, VisLayout, VIS_NONE, ShadingRate};
//! use wave::WaveWidth;
//!
//! // Two batches of a 2-triangle card with different textures: two batch groups.
//! let card = Geometry { vertex_count: 4, primitive_count: 2, first_index: 0, base_vertex: 0 };
//! let at = vec![[0.0f32, 0.0, 0.0]; 10];
//! let batches = [
//!     Batch { shader: 0, batch_data: 1, geometry: card, instances: &at },
//!     Batch { shader: 0, batch_data: 2, geometry: card, instances: &at },
//! ];
//! let plan = build_plan(&batches, &PlanConfig::default())?;
//! assert_eq!((plan.passes.len(), plan.pass_groups[0].len()), (1, 2));
//!
//! // A 256x128 vis buffer: the left tile covered by instance 3 of batch 0, triangle 1.
//! let mb = &plan.micro_batches[0];
//! let (id, field) = mb.instance_id(3);
//! let word = VisId::pack(VisLayout::Standard, mb.bits(),
//!     VisFields { micro_batch: id, instance: field, primitive: 1, rate: ShadingRate::Rate1x1 })?;
//! let words: Vec<u32> = (0..256 * 128).map(|i| if i % 256 < 128 { word.0 } else { VIS_NONE }).collect();
//! let vis = VisBuffer::new(&words, 256, 128, VisLayout::Standard)?;
//! let config = ClassifyConfig::for_plan(&plan, WaveWidth::W32);
//! let c = classify(&vis, &plan.table, &[0, 1, 2, 2, 1, 3], &config)?;
//! assert_eq!(c.output.waves.len(), 128 * 128 / 32); // one tile, one group, full waves
//! assert_eq!(c.output.passes[0].count, 512);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Features: `std` (default), `libm` (for `visbuf`'s float math without std; build the
//! crate alone with `--no-default-features --features libm`), `parallel` (rayon).

#![no_std]
#![cfg_attr(docsrs, feature(doc_cfg))]

extern crate alloc;
#[cfg(feature = "std")]
extern crate std;

#[cfg(not(any(feature = "std", feature = "libm")))]
compile_error!("tiling needs visbuf's float math: enable the `std` (default) or `libm` feature");

pub mod classify;
mod decode;
mod error;
mod layout;
pub mod measure;
#[cfg(feature = "parallel")]
pub mod parallel;
pub mod plan;
pub mod vertex;
pub mod vrs;
pub mod wgsl;

pub use classify::{
    Classification, ClassifyConfig, ClassifyOutput, MidClassify, PassDispatch, PixelStats,
    TILE_SIZE, TilingParams, Totals, VisBuffer, WaveCommand, canonical_sort, classify,
    classify_output, classify_phases, command_sort_key, first_of_run, laydown_finalize,
    mid_classify, pixel_command, unpack_pixel_command,
};
pub use error::Error;
pub use measure::{TalkMeasurements, depth_equal_waves, measure};
pub use plan::{
    Batch, Geometry, InstanceRef, MAX_BATCH_GROUPS_PER_PASS, MAX_MICRO_BATCH_INSTANCES,
    MAX_MICRO_BATCH_PRIMITIVES, MAX_MICRO_BATCH_VERTICES, MAX_PASSES, MAX_PRIMITIVES_PER_GEOMETRY,
    MicroBatchInfo, PassInfo, Plan, PlanConfig, RING_BYTES_PS4, RING_BYTES_PS5, RING_VERTEX_BYTES,
    Reservation, ReservedRange, VERTEX_CHUNK_SIZE, build_plan,
};
pub use vertex::{UberChunk, VertexWaveCommand, VertexWaves, vertex_wave_commands};
pub use vrs::{BroadcastList, expand_wave, quad_command, unpack_quad_command};
