//! The three classification phases of seed 000 over a vis buffer, pass-shaped: each
//! function takes what its compute pass binds and returns what it writes.
//!
//! 1. [`laydown_finalize`]: per 128x128 tile and pass, a 32-bit mask of the batch groups
//!    used.
//! 2. [`mid_classify`]: the popcount of each mask and its prefix sum into **compact counter
//!    offsets** (one counter per used (tile, pass, group) instead of a full table), the
//!    pixel count of each counter, the **vertex cull buffer** (one byte per 64-vertex
//!    chunk, set when a visible primitive uses a vertex of the chunk) and the prefix sum of
//!    the counts into **pixel-command offsets**.
//! 3. [`classify_output`]: the 16-bit pixel commands, the final counts, each counter
//!    rounded up to whole waves, the wave commands and one indirect-dispatch argument set
//!    per pass.
//!
//! # Indexing (all tile-major except the wave commands)
//!
//! Tiles are 128x128 pixels, `tiles_x = ceil(width / 128)`, tile `t` is at
//! `(t % tiles_x, t / tiles_x)`; the last column and row of tiles may be partial. With
//! `P` passes and `T` tiles:
//!
//! | buffer | length | index |
//! | --- | --- | --- |
//! | masks, counter offsets | `T * P` | `t * P + p` |
//! | counts, pixel offsets, final counts, wave offsets | counters (`sum popcount(masks)`) | `counter_offsets[t * P + p] + rank of g in masks[t * P + p]` |
//! | pixel commands | `sum counts` | `pixel_offsets[c] + k` (the tile's commands are together) |
//! | wave commands | `sum ceil(final count / wave width)` | pass-major: pass, then tile, then group, then wave |
//! | pass dispatches | `P` | `p` |
//!
//! **Memory.** The compact counters replace a full table of `T * P * 32` counters: at 4K
//! (30 x 17 = 510 tiles) with 256 passes that would be 510 * 256 * 32 * 4 bytes = 16.7 MB
//! (the talk's "16mb"); the compact one takes 4 bytes per (tile, pass, group) actually
//! used, plus the `T * P` masks and offsets (1 MB at 256 passes).
//!
//! # Which pixels are shaded
//!
//! A pixel is *valid* when its word is not [`visbuf::VIS_NONE`], its bit in the optional
//! validity bitmask is set (the talk's stencil bit), its micro-batch ID names a row of the
//! table that is in range (ID within the row's `first_id..first_id + id_count`, pass below
//! the pass count, group below 32, at most 16 primitive bits), and its instance and
//! primitive lie below the row's counts. Every other pixel is skipped and counted in
//! [`PixelStats`]; nothing is read out of bounds.
//!
//! # Commands and their canonical order
//!
//! With [`VisLayout::Standard`](visbuf::VisLayout::Standard) every valid pixel is one 16-bit **pixel command**:
//!
//! | bits | 15..14 | 13..7 | 6..0 |
//! | --- | --- | --- | --- |
//! | field | 0 | y within the tile | x within the tile |
//!
//! With [`VisLayout::Vrs`](visbuf::VisLayout::Vrs) the commands are **quad commands** (see [`crate::vrs`]): one per
//! shading sample,
//!
//! | bits | 15..12 | 11..6 | 5..0 |
//! | --- | --- | --- | --- |
//! | field | pixels of the quad that receive the result (bit `2 * dy + dx`) | quad y (0..64) | quad x (0..64) |
//!
//! Within a counter the CPU twin writes commands in row-major order of the pixel that
//! carries the sample (for pixel commands: ascending command value). The GPU appends with
//! atomics, so its order within a counter is arbitrary: sort each counter's commands by
//! [`command_sort_key`] ([`canonical_sort`] does it) before comparing. Everything else
//! (offsets, counts, wave commands, dispatches, the cull buffer) is deterministic and
//! compares bit for bit.
//!
//! # Files
//!
//! One file per phase, each the CPU twin of one WGSL module, over shared pieces:
//!
//! | file | what |
//! | --- | --- |
//! | `types.rs` | the public settings, uniform, stats, wave commands and phase outputs |
//! | `frame.rs` | what every tile kernel reads and how a phase runs its tiles (serially here, on threads in [`crate::parallel`]) |
//! | `finalize.rs` | phase 1, [`laydown_finalize`] |
//! | `marks.rs` | the vertex cull buffer's marking, shared by phase 2 and the fused scan |
//! | `mid.rs` | phase 2, [`mid_classify`] |
//! | `output.rs` | phase 3, [`classify_output`], and the commands' canonical order |
//! | `fused.rs` | the three phases in one scan per tile, [`classify()`] |
//!
//! The tile, command-word and vis-buffer definitions come from the crate's lowest module
//! and are re-exported here.

mod finalize;
mod frame;
mod fused;
mod marks;
mod mid;
mod output;
mod types;

pub use output::{canonical_sort, command_sort_key};
pub use types::{
    Classification, ClassifyConfig, ClassifyOutput, FLAG_VALIDITY, FLAG_VERTEX_CULL, FLAG_VRS,
    MidClassify, PixelStats, TilingParams, Totals, WAVE_GROUP_SHIFT, WAVE_TILE_Y_SHIFT,
    WaveCommand,
};

pub use crate::layout::{
    MAX_DIMENSION, MAX_DISPATCH_X, PIXEL_COORD_MASK, PIXEL_Y_SHIFT, PassDispatch, QUAD_COORD_MASK,
    QUAD_INDEX_MASK, QUAD_PIXELS_SHIFT, QUAD_Y_SHIFT, TILE_SHIFT, TILE_SIZE, VisBuffer,
    first_of_run, pixel_command, unpack_pixel_command,
};

pub(crate) use finalize::laydown_finalize_on;
pub(crate) use frame::{Frame, Schedule};
pub(crate) use fused::classify_on;
pub(crate) use mid::mid_classify_on;
pub(crate) use output::classify_output_on;

/// The classification's five public functions on one [`Schedule`], each with the docs
/// given before its name: the sequential ones below, the parallel ones in
/// [`crate::parallel`]. One signature and one body per function serve both.
macro_rules! phase_functions {
    (
        $schedule:expr;
        $(#[$finalize:meta])* fn laydown_finalize;
        $(#[$mid:meta])* fn mid_classify;
        $(#[$output:meta])* fn classify_output;
        $(#[$fused:meta])* fn classify;
        $(#[$phases:meta])* fn classify_phases;
    ) => {
        $(#[$finalize])*
        pub fn laydown_finalize(
            vis: &$crate::VisBuffer<'_>,
            table: &[$crate::MicroBatchInfo],
            config: &$crate::ClassifyConfig,
        ) -> Result<(::alloc::vec::Vec<u32>, $crate::PixelStats), $crate::Error> {
            $crate::classify::laydown_finalize_on($schedule, vis, table, config)
        }

        $(#[$mid])*
        pub fn mid_classify(
            vis: &$crate::VisBuffer<'_>,
            table: &[$crate::MicroBatchInfo],
            indices: &[u32],
            config: &$crate::ClassifyConfig,
            masks: &[u32],
        ) -> Result<$crate::MidClassify, $crate::Error> {
            $crate::classify::mid_classify_on($schedule, vis, table, indices, config, masks)
        }

        $(#[$output])*
        pub fn classify_output(
            vis: &$crate::VisBuffer<'_>,
            table: &[$crate::MicroBatchInfo],
            config: &$crate::ClassifyConfig,
            masks: &[u32],
            mid: &$crate::MidClassify,
        ) -> Result<$crate::ClassifyOutput, $crate::Error> {
            $crate::classify::classify_output_on($schedule, vis, table, config, masks, mid)
        }

        $(#[$fused])*
        pub fn classify(
            vis: &$crate::VisBuffer<'_>,
            table: &[$crate::MicroBatchInfo],
            indices: &[u32],
            config: &$crate::ClassifyConfig,
        ) -> Result<$crate::Classification, $crate::Error> {
            $crate::classify::classify_on($schedule, vis, table, indices, config)
        }

        $(#[$phases])*
        pub fn classify_phases(
            vis: &$crate::VisBuffer<'_>,
            table: &[$crate::MicroBatchInfo],
            indices: &[u32],
            config: &$crate::ClassifyConfig,
        ) -> Result<$crate::Classification, $crate::Error> {
            let (masks, _) = laydown_finalize(vis, table, config)?;
            let mid = mid_classify(vis, table, indices, config, &masks)?;
            let output = classify_output(vis, table, config, &masks, &mid)?;
            Ok($crate::Classification { masks, mid, output })
        }
    };
}

#[cfg(feature = "parallel")]
pub(crate) use phase_functions;

phase_functions! {
    Schedule::Serial;

    /// Phase 1: per (tile, pass) the mask of batch groups used by valid pixels,
    /// `masks[t * P + p]`, bit `g` for group `g`.
    ///
    /// GPU twin: [`wgsl::LAYDOWN_FINALIZE`](crate::wgsl::LAYDOWN_FINALIZE).
    fn laydown_finalize;

    /// Phase 2: compact counter offsets, counts, the vertex cull buffer and pixel-command
    /// offsets. `masks` comes from [`laydown_finalize`]; `indices` is the shared index
    /// buffer the table's `first_index` points into (three local indices per triangle).
    ///
    /// GPU twin: [`wgsl::MID_CLASSIFY`](crate::wgsl::MID_CLASSIFY).
    fn mid_classify;

    /// Phase 3: pixel (or quad) commands, final counts, wave commands and per-pass
    /// dispatches. `masks` from [`laydown_finalize`], `mid` from [`mid_classify`]
    /// (possibly run with an earlier validity mask: the talk's mid classify overlaps the
    /// geometry pass, so its counts may only overestimate). `vis` carries the final
    /// validity.
    ///
    /// GPU twin: [`wgsl::CLASSIFY_OUTPUT`](crate::wgsl::CLASSIFY_OUTPUT).
    fn classify_output;

    /// All three phases with one validity (the vis buffer's), fused into one scan per
    /// tile: the same outputs as [`classify_phases`] (running [`laydown_finalize`],
    /// [`mid_classify`] and [`classify_output`] in turn), faster on the CPU because each
    /// tile is read once while it is in cache.
    ///
    /// ```
    /// use tiling::{classify, ClassifyConfig, MicroBatchInfo};
    /// use visbuf::{VisLayout, VIS_NONE};
    /// use wave::WaveWidth;
    ///
    /// // One micro batch (ID 0) of one 2-triangle instance, pass 0, group 3.
    /// let row = MicroBatchInfo { id_count: 1, batch_group: 3, primitive_bits: 1,
    ///     primitive_count: 2, vertex_count: 4, instance_count: 1, ..Default::default() };
    /// let indices = [0, 1, 2, 2, 1, 3];
    /// let mut words = vec![VIS_NONE; 4 * 4];
    /// words[5] = 1; // pixel (1, 1): micro batch 0, instance 0, primitive 1
    /// let vis = tiling::VisBuffer::new(&words, 4, 4, VisLayout::Standard)?;
    /// let config = ClassifyConfig { pass_count: 1, wave_width: WaveWidth::W8, chunk_count: 1, vertex_cull: true };
    /// let c = classify(&vis, &[row], &indices, &config)?;
    /// assert_eq!(c.masks, [1 << 3]);
    /// assert_eq!(c.output.commands, [tiling::pixel_command(1, 1)]);
    /// assert_eq!(c.output.waves.len(), 1);
    /// assert_eq!(c.mid.vertex_cull, [1, 0, 0, 0]);
    /// # Ok::<(), tiling::Error>(())
    /// ```
    fn classify;

    /// All three phases run as the GPU runs them: [`laydown_finalize`], [`mid_classify`],
    /// [`classify_output`], each over the whole frame. Equal to [`classify()`].
    fn classify_phases;
}
