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
//! With [`VisLayout::Standard`] every valid pixel is one 16-bit **pixel command**:
//!
//! | bits | 15..14 | 13..7 | 6..0 |
//! | --- | --- | --- | --- |
//! | field | 0 | y within the tile | x within the tile |
//!
//! With [`VisLayout::Vrs`] the commands are **quad commands** (see [`crate::vrs`]): one per
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

use alloc::vec;
use alloc::vec::Vec;
use core::sync::atomic::{AtomicU8, Ordering};

use visbuf::{VIS_NONE, VisLayout};
use wave::WaveWidth;

use crate::Error;
use crate::decode::{Decoded, Decoder, KIND_VALID};
use crate::plan::{MAX_BATCH_GROUPS_PER_PASS, MAX_PASSES, MicroBatchInfo, VERTEX_CHUNK_SIZE};
use crate::{fused, vrs};

/// Side of a loose tile in pixels.
pub const TILE_SIZE: u32 = 128;
/// `log2(TILE_SIZE)`.
pub const TILE_SHIFT: u32 = 7;
/// Bit position of y in a pixel command (x is in the bits below).
pub const PIXEL_Y_SHIFT: u32 = 7;
/// Mask of one coordinate in a pixel command.
pub const PIXEL_COORD_MASK: u32 = TILE_SIZE - 1;
/// Bit position of the quad's y in a quad command.
pub const QUAD_Y_SHIFT: u32 = 6;
/// Mask of one quad coordinate in a quad command (64 quads per tile side).
pub const QUAD_COORD_MASK: u32 = TILE_SIZE / 2 - 1;
/// Mask of the 12-bit quad index in a quad command.
pub const QUAD_INDEX_MASK: u32 = 0xfff;
/// Bit position of the 4-bit pixel mask in a quad command.
pub const QUAD_PIXELS_SHIFT: u32 = 12;
/// Most workgroups in one dimension of a dispatch (WebGPU's default
/// `max_compute_workgroups_per_dimension`, [`shader::MAX_WORKGROUPS_X`]): larger wave
/// counts spill into `y`.
pub const MAX_DISPATCH_X: u32 = shader::MAX_WORKGROUPS_X;
/// Largest vis-buffer width or height.
pub const MAX_DIMENSION: u32 = 32_768;

/// Bit of [`TilingParams::flags`]: the validity bitmask is bound and applies.
pub const FLAG_VALIDITY: u32 = 1;
/// Bit of [`TilingParams::flags`]: the words use [`VisLayout::Vrs`] (quad commands).
pub const FLAG_VRS: u32 = 2;
/// Bit of [`TilingParams::flags`]: mid classify marks the vertex chunks of visible
/// triangles ([`ClassifyConfig::vertex_cull`]).
pub const FLAG_VERTEX_CULL: u32 = 4;

/// Whether pixel `(x, y)`, holding `word`, starts a triangle run: neither its left nor its
/// upper neighbour (in the whole buffer, across tile edges) holds the same word with its
/// validity bit set. Every valid pixel's word is also held by a run start at or above-left
/// of it, so marking a triangle's vertex chunks only at run starts marks every visible
/// triangle. Out-of-range coordinates are run starts.
#[must_use]
pub fn first_of_run(vis: &VisBuffer<'_>, x: u32, y: u32, word: u32) -> bool {
    let w = vis.width as usize;
    let same = |i: usize| {
        vis.words.get(i) == Some(&word)
            && vis
                .valid
                .is_none_or(|m| m.get(i >> 5).is_some_and(|b| (b >> (i & 31)) & 1 == 1))
    };
    let i = y as usize * w + x as usize;
    !((x > 0 && x < vis.width && same(i - 1)) || (y > 0 && x < vis.width && same(i - w)))
}

/// The standard-layout pixel command of pixel `(x, y)` within its tile (each `0..128`,
/// masked).
#[must_use]
#[inline]
pub const fn pixel_command(x: u32, y: u32) -> u16 {
    ((x & PIXEL_COORD_MASK) | ((y & PIXEL_COORD_MASK) << PIXEL_Y_SHIFT)) as u16
}

/// The `(x, y)` within its tile of a pixel command.
#[must_use]
#[inline]
pub const fn unpack_pixel_command(cmd: u16) -> (u32, u32) {
    let c = cmd as u32;
    (
        c & PIXEL_COORD_MASK,
        (c >> PIXEL_Y_SHIFT) & PIXEL_COORD_MASK,
    )
}

/// The key that orders commands within a counter canonically: the index `y * 128 + x`
/// within the tile of the pixel that carries the sample (for a pixel command, the command
/// itself; for a quad command, its quad's top-left plus the offset of its lowest pixel).
#[must_use]
#[inline]
pub const fn command_sort_key(cmd: u16, layout: VisLayout) -> u16 {
    match layout {
        VisLayout::Standard => cmd,
        VisLayout::Vrs => {
            let (x, y) = vrs::sample_pixel(cmd);
            pixel_command(x, y)
        }
    }
}

/// A vis buffer with its validity rule: `width * height` words, row-major from the
/// top-left, and an optional bitmask (bit `i % 32` of word `i / 32` for pixel
/// `i = y * width + x`) that must also be set for a pixel to count (the talk's stencil
/// bit).
#[derive(Clone, Copy, Debug)]
pub struct VisBuffer<'a> {
    words: &'a [u32],
    valid: Option<&'a [u32]>,
    width: u32,
    height: u32,
    layout: VisLayout,
}

impl<'a> VisBuffer<'a> {
    /// Checks the size: `words.len() == width * height`, both sides in
    /// `1..=`[`MAX_DIMENSION`].
    pub fn new(
        words: &'a [u32],
        width: u32,
        height: u32,
        layout: VisLayout,
    ) -> Result<Self, Error> {
        for (what, v) in [("width", width), ("height", height)] {
            if v == 0 || v > MAX_DIMENSION {
                return Err(Error::InvalidConfig {
                    what,
                    value: v.into(),
                    min: 1,
                    max: MAX_DIMENSION.into(),
                });
            }
        }
        let n = u64::from(width) * u64::from(height);
        if words.len() as u64 != n {
            return Err(Error::BufferSize {
                what: "vis buffer",
                expected: n,
                got: words.len() as u64,
            });
        }
        Ok(Self {
            words,
            valid: None,
            width,
            height,
            layout,
        })
    }

    /// Adds the validity bitmask: `ceil(width * height / 32)` words.
    pub fn with_validity(self, mask: &'a [u32]) -> Result<Self, Error> {
        let n = (u64::from(self.width) * u64::from(self.height)).div_ceil(32);
        if mask.len() as u64 != n {
            return Err(Error::BufferSize {
                what: "validity mask",
                expected: n,
                got: mask.len() as u64,
            });
        }
        Ok(Self {
            valid: Some(mask),
            ..self
        })
    }

    /// The words.
    #[must_use]
    pub fn words(&self) -> &'a [u32] {
        self.words
    }

    /// The validity bitmask, if any.
    #[must_use]
    pub fn validity(&self) -> Option<&'a [u32]> {
        self.valid
    }

    /// Width in pixels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The word layout.
    #[must_use]
    pub fn layout(&self) -> VisLayout {
        self.layout
    }

    /// Tiles across.
    #[must_use]
    pub fn tiles_x(&self) -> u32 {
        self.width.div_ceil(TILE_SIZE)
    }

    /// Tiles down.
    #[must_use]
    pub fn tiles_y(&self) -> u32 {
        self.height.div_ceil(TILE_SIZE)
    }

    /// Tiles in all.
    #[must_use]
    pub fn tile_count(&self) -> u32 {
        self.tiles_x() * self.tiles_y()
    }

    /// Whether pixel `i` passes the validity bitmask (true without one).
    #[inline(always)]
    pub(crate) fn mask_bit(&self, i: usize) -> bool {
        match self.valid {
            None => true,
            Some(m) => (m[i >> 5] >> (i & 31)) & 1 == 1,
        }
    }
}

/// The frame-wide settings of the classification.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ClassifyConfig {
    /// Passes in the plan, 1..=[`MAX_PASSES`]: the length of the per-tile mask row.
    pub pass_count: u32,
    /// Lanes per shading wave: counters are rounded up to whole waves.
    pub wave_width: WaveWidth,
    /// Entries of the vertex cull buffer ([`Plan::chunk_count`](crate::Plan::chunk_count)).
    pub chunk_count: u32,
    /// Whether mid classify marks the 64-vertex chunks of every visible triangle in the
    /// vertex cull buffer (HFW's vertex culling: a triangle's indices are read at its run
    /// starts, [`first_of_run`]). Without it the cull buffer stays zero, no index is read
    /// and [`PixelStats::bad_indices`] is 0: for frames whose vertex work reads no cull
    /// buffer (the GPU pass is a third faster without the index reads).
    pub vertex_cull: bool,
}

impl ClassifyConfig {
    /// The configuration for a plan.
    #[must_use]
    pub fn for_plan(plan: &crate::Plan, wave_width: WaveWidth) -> Self {
        Self {
            pass_count: (plan.passes.len() as u32).max(1),
            wave_width,
            chunk_count: plan.chunk_count,
            vertex_cull: true,
        }
    }

    fn validate(&self) -> Result<(), Error> {
        if self.pass_count == 0 || self.pass_count > MAX_PASSES {
            return Err(Error::InvalidConfig {
                what: "pass_count",
                value: self.pass_count.into(),
                min: 1,
                max: MAX_PASSES.into(),
            });
        }
        Ok(())
    }
}

/// The uniform every WGSL pass of this crate reads (WGSL `TilingParams`), 48 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, bytemuck::Pod, bytemuck::Zeroable)]
pub struct TilingParams {
    /// Vis-buffer width in pixels.
    pub width: u32,
    /// Vis-buffer height in pixels.
    pub height: u32,
    /// Tiles across, `ceil(width / 128)`.
    pub tiles_x: u32,
    /// Tiles down, `ceil(height / 128)`.
    pub tiles_y: u32,
    /// Passes (`P`).
    pub pass_count: u32,
    /// Lanes per shading wave (8, 16, 32 or 64).
    pub wave_width: u32,
    /// [`FLAG_VALIDITY`] | [`FLAG_VRS`] | [`FLAG_VERTEX_CULL`].
    pub flags: u32,
    /// Rows of the MicroBatchInfoTable (micro-batch IDs at or past it name nothing).
    pub table_len: u32,
    /// Entries of the micro-batch order buffer.
    pub micro_batch_count: u32,
    /// Entries of the vertex cull buffer (64-vertex chunks).
    pub chunk_count: u32,
    /// Uber chunks, `ceil(chunk_count / 64)`.
    pub uber_count: u32,
    /// Padding (zero).
    pub pad: u32,
}

const _: () = assert!(size_of::<TilingParams>() == 48);

impl TilingParams {
    /// The uniform for a frame, its table and order buffer lengths.
    #[must_use]
    pub fn new(
        vis: &VisBuffer<'_>,
        config: &ClassifyConfig,
        table_len: u32,
        micro_batch_count: u32,
    ) -> Self {
        Self::for_frame(
            (vis.width, vis.height),
            vis.layout,
            vis.valid.is_some(),
            config,
            table_len,
            micro_batch_count,
        )
    }

    /// [`new`](Self::new) for a vis buffer not in hand (it lives on the GPU): its `size`
    /// (width, height in pixels), its word `layout`, whether a validity bitmask applies.
    #[must_use]
    pub fn for_frame(
        size: (u32, u32),
        layout: VisLayout,
        validity: bool,
        config: &ClassifyConfig,
        table_len: u32,
        micro_batch_count: u32,
    ) -> Self {
        let mut flags = 0;
        if validity {
            flags |= FLAG_VALIDITY;
        }
        if layout == VisLayout::Vrs {
            flags |= FLAG_VRS;
        }
        if config.vertex_cull {
            flags |= FLAG_VERTEX_CULL;
        }
        Self {
            width: size.0,
            height: size.1,
            tiles_x: size.0.div_ceil(TILE_SIZE),
            tiles_y: size.1.div_ceil(TILE_SIZE),
            pass_count: config.pass_count,
            wave_width: config.wave_width.lanes(),
            flags,
            table_len,
            micro_batch_count,
            chunk_count: config.chunk_count,
            uber_count: config
                .chunk_count
                .div_ceil(crate::vertex::UBER_CHUNK_CHUNKS),
            pad: 0,
        }
    }
}

/// What happened to the pixels of one phase (WGSL `TilingStats`), 32 bytes. Every pixel
/// lands in exactly one of `empty`, `unknown`, `out_of_range`, `valid`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PixelStats {
    /// Pixels shaded.
    pub valid: u32,
    /// [`visbuf::VIS_NONE`] or cleared in the validity bitmask.
    pub empty: u32,
    /// Micro-batch ID naming no row (or an invalid one).
    pub unknown: u32,
    /// Instance or primitive past the row's counts.
    pub out_of_range: u32,
    /// Commands counted (mid classify) or written (output): one per valid pixel, or one
    /// per shading sample with VRS.
    pub commands: u32,
    /// Commands with no room: a (pass, group) missing from the tile's mask (mid classify),
    /// or past the counter's count from mid classify (output). Zero when every phase sees
    /// the same validity.
    pub dropped: u32,
    /// Mid classify: valid pixels that start a triangle run, see [`first_of_run`], and
    /// whose triangle has an index past the index buffer, an index at or past the
    /// geometry's vertex count, or a chunk past the cull buffer (their vertices are not
    /// marked). Counted per run start rather than per pixel: the GPU reads a triangle's
    /// indices only at run starts, one set of index loads and chunk marks per run.
    pub bad_indices: u32,
    /// Padding (zero).
    pub pad: u32,
}

const _: () = assert!(size_of::<PixelStats>() == 32);

impl PixelStats {
    /// Field-wise sum.
    #[must_use]
    pub fn merge(self, o: PixelStats) -> PixelStats {
        PixelStats {
            valid: self.valid + o.valid,
            empty: self.empty + o.empty,
            unknown: self.unknown + o.unknown,
            out_of_range: self.out_of_range + o.out_of_range,
            commands: self.commands + o.commands,
            dropped: self.dropped + o.dropped,
            bad_indices: self.bad_indices + o.bad_indices,
            pad: 0,
        }
    }

    /// Pixels seen: `valid + empty + unknown + out_of_range`.
    #[must_use]
    pub fn pixels(&self) -> u64 {
        u64::from(self.valid)
            + u64::from(self.empty)
            + u64::from(self.unknown)
            + u64::from(self.out_of_range)
    }
}

/// One wave of pixel shading (WGSL `TilingWaveCommand`), 16 bytes: which tile, pass and
/// batch group it shades and which pixel commands.
///
/// | word | bits | field |
/// | --- | --- | --- |
/// | `tile` | 15..0 / 31..16 | tile x / tile y (in tiles) |
/// | `pass_group` | 7..0 / 12..8 | pass / batch group (bits 31..13 zero) |
/// | `first_command` | 31..0 | index of its first pixel command |
/// | `command_count` | 31..0 | its commands, 1..=wave width |
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, bytemuck::Pod, bytemuck::Zeroable)]
pub struct WaveCommand {
    /// `tile_x | tile_y << 16`.
    pub tile: u32,
    /// `pass | batch_group << 8`.
    pub pass_group: u32,
    /// Index of the wave's first pixel command.
    pub first_command: u32,
    /// Commands in the wave (the last wave of a counter may be partial).
    pub command_count: u32,
}

const _: () = assert!(size_of::<WaveCommand>() == 16);

/// Bit position of the tile's y in [`WaveCommand::tile`].
pub const WAVE_TILE_Y_SHIFT: u32 = 16;
/// Bit position of the batch group in [`WaveCommand::pass_group`].
pub const WAVE_GROUP_SHIFT: u32 = 8;

impl WaveCommand {
    /// Tile x and y, in tiles.
    #[must_use]
    pub const fn tile_xy(&self) -> (u32, u32) {
        (self.tile & 0xffff, self.tile >> WAVE_TILE_Y_SHIFT)
    }

    /// The pass.
    #[must_use]
    pub const fn pass(&self) -> u32 {
        self.pass_group & 0xff
    }

    /// The batch group.
    #[must_use]
    pub const fn batch_group(&self) -> u32 {
        self.pass_group >> WAVE_GROUP_SHIFT
    }
}

/// One pass's indirect dispatch (WGSL `TilingPassDispatch`), 24 bytes. The first three
/// words are `dispatch_workgroups_indirect`'s arguments (at byte offset `24 * p`): one
/// workgroup per command, `x = min(count, 65535)`, `y = ceil(count / 65535)`, `z = 1`
/// (zero workgroups when the pass has no work). A shader finds its command as
/// `first + workgroup_id.y * 65535 + workgroup_id.x` and returns when that passes
/// `first + count`.
///
/// For pixel shading a command is a [`WaveCommand`] and `items` counts pixel commands;
/// for the vertex transform a command is a [`VertexWaveCommand`](crate::VertexWaveCommand)
/// and `items` counts vertices in its chunks.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PassDispatch {
    /// Workgroups in x.
    pub x: u32,
    /// Workgroups in y.
    pub y: u32,
    /// Workgroups in z (1, or 0 with no work).
    pub z: u32,
    /// Index of the pass's first command.
    pub first: u32,
    /// Commands of the pass.
    pub count: u32,
    /// Work items of the pass (pixel commands or vertices).
    pub items: u32,
}

const _: () = assert!(size_of::<PassDispatch>() == 24);

impl PassDispatch {
    /// The arguments for `count` commands starting at `first`.
    #[must_use]
    pub const fn new(first: u32, count: u32, items: u32) -> Self {
        let x = if count < MAX_DISPATCH_X {
            count
        } else {
            MAX_DISPATCH_X
        };
        let y = count.div_ceil(MAX_DISPATCH_X);
        Self {
            x,
            y,
            z: if count == 0 { 0 } else { 1 },
            first,
            count,
            items,
        }
    }
}

/// Totals the GPU passes write for the CPU to read back (WGSL `TilingTotals`), 16 bytes.
/// The CPU twins return them as lengths instead.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Totals {
    /// Counters (mid classify's `counter_offsets` pass): [`MidClassify::counter_count`].
    pub counter_count: u32,
    /// Commands ([`MidClassify::command_count`]; on the GPU the counts' prefix sum, classify
    /// output's first dispatch).
    pub command_count: u32,
    /// Wave commands (on the GPU written by classify output's `write_waves` work).
    pub wave_count: u32,
    /// Visible chunks, the vertex wave commands (the vertex pass's `build_pyramid`).
    pub visible_chunks: u32,
}

const _: () = assert!(size_of::<Totals>() == 16);

/// Phase 2's outputs.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct MidClassify {
    /// Per (tile, pass), `t * P + p`: the exclusive prefix sum of the masks' popcounts.
    pub counter_offsets: Vec<u32>,
    /// Counters in all: `sum popcount(masks)`.
    pub counter_count: u32,
    /// Per counter: commands counted (pixels; shading samples with VRS).
    pub counts: Vec<u32>,
    /// Per counter: the exclusive prefix sum of `counts`, where its commands start.
    pub pixel_offsets: Vec<u32>,
    /// Commands in all: `sum counts`, the pixel-command buffer's length.
    pub command_count: u32,
    /// One byte per 64-vertex chunk, 1 where a visible triangle uses a vertex of the chunk;
    /// padded with zeros to a multiple of 4 bytes (it casts to the GPU's `array<u32>`).
    pub vertex_cull: Vec<u8>,
    /// What happened to the pixels.
    pub stats: PixelStats,
}

/// Phase 3's outputs.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ClassifyOutput {
    /// The 16-bit commands, `command_count` of them (the GPU packs two per `u32`, low half
    /// first); counter `c` owns `pixel_offsets[c]..pixel_offsets[c] + counts[c]` and fills
    /// its first `final_counts[c]`, the rest stay 0.
    pub commands: Vec<u16>,
    /// Per counter: commands written.
    pub final_counts: Vec<u32>,
    /// Per counter: index of its first wave command.
    pub wave_offsets: Vec<u32>,
    /// The wave commands, pass-major.
    pub waves: Vec<WaveCommand>,
    /// Per pass: the shading dispatch over its wave commands.
    pub passes: Vec<PassDispatch>,
    /// What happened to the pixels.
    pub stats: PixelStats,
}

/// All three phases' outputs.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Classification {
    /// Phase 1: per (tile, pass), the batch groups used.
    pub masks: Vec<u32>,
    /// Phase 2.
    pub mid: MidClassify,
    /// Phase 3.
    pub output: ClassifyOutput,
}

impl Classification {
    /// Bytes of the command buffers the shading reads: 2 per pixel command, 16 per wave
    /// command, 24 per pass dispatch.
    #[must_use]
    pub fn command_bytes(&self) -> u64 {
        2 * self.output.commands.len() as u64
            + size_of::<WaveCommand>() as u64 * self.output.waves.len() as u64
            + size_of::<PassDispatch>() as u64 * self.output.passes.len() as u64
    }
}

/// Everything a tile kernel reads.
pub(crate) struct Frame<'a> {
    pub vis: VisBuffer<'a>,
    pub dec: Decoder,
    pub passes: usize,
    /// [`ClassifyConfig::vertex_cull`].
    pub vertex_cull: bool,
}

impl<'a> Frame<'a> {
    pub fn new(
        vis: &VisBuffer<'a>,
        table: &[MicroBatchInfo],
        config: &ClassifyConfig,
    ) -> Result<Self, Error> {
        config.validate()?;
        Ok(Self {
            vis: *vis,
            dec: Decoder::new(table, config.pass_count, vis.layout),
            passes: config.pass_count as usize,
            vertex_cull: config.vertex_cull,
        })
    }

    /// Pixel rectangle of tile `t`: `(x0, y0, x1, y1)`.
    #[inline]
    pub fn tile_rect(&self, t: usize) -> (u32, u32, u32, u32) {
        let tx = t as u32 % self.vis.tiles_x();
        let ty = t as u32 / self.vis.tiles_x();
        let (x0, y0) = (tx * TILE_SIZE, ty * TILE_SIZE);
        (
            x0,
            y0,
            (x0 + TILE_SIZE).min(self.vis.width),
            (y0 + TILE_SIZE).min(self.vis.height),
        )
    }

    /// Calls `f(x, y, word, valid, decoded)` for every pixel of tile `t`, row-major,
    /// counting every pixel in `stats`. The decode has no branches; pixels that are not
    /// valid come with the (pass, group) [`TRASH_PG`], so a caller may also do its
    /// bookkeeping without one.
    #[inline(always)]
    pub fn for_each_pixel(
        &self,
        t: usize,
        stats: &mut PixelStats,
        mut f: impl FnMut(u32, u32, u32, bool, Decoded),
    ) {
        let (x0, y0, x1, y1) = self.tile_rect(t);
        let w = self.vis.width as usize;
        let mut kinds = [0u32; 4];
        for y in y0..y1 {
            let row = y as usize * w + x0 as usize;
            let words = &self.vis.words[row..row + (x1 - x0) as usize];
            match self.vis.valid {
                None => {
                    for (i, &word) in words.iter().enumerate() {
                        let (k, d) = self.dec.classify(word, true);
                        kinds[(k & 3) as usize] += 1;
                        f(x0 + i as u32, y, word, k == KIND_VALID, d);
                    }
                }
                Some(m) => {
                    for (i, &word) in words.iter().enumerate() {
                        let p = row + i;
                        let bit = (m[p >> 5] >> (p & 31)) & 1 == 1;
                        let (k, d) = self.dec.classify(word, bit);
                        kinds[(k & 3) as usize] += 1;
                        f(x0 + i as u32, y, word, k == KIND_VALID, d);
                    }
                }
            }
        }
        stats.empty += kinds[0];
        stats.unknown += kinds[1];
        stats.out_of_range += kinds[2];
        stats.valid += kinds[3];
    }

    /// [`first_of_run`] over this frame's vis buffer.
    #[inline(always)]
    pub fn first_of_run(&self, x: u32, y: u32, word: u32) -> bool {
        first_of_run(&self.vis, x, y, word)
    }

    /// With VRS: the pixel mask of the shading sample pixel `(x, y)` carries, or `None`
    /// when another pixel of its block carries it. Without VRS: always `Some(1)`.
    #[inline(always)]
    pub fn sample(&self, x: u32, y: u32, word: u32) -> Option<u32> {
        if self.vis.layout == VisLayout::Standard {
            return Some(1);
        }
        vrs::sample_mask(&self.vis, x, y, word)
    }
}

/// Phase 1, one tile: `masks` is the tile's row of `P` masks.
pub(crate) fn finalize_tile(f: &Frame<'_>, t: usize, masks: &mut [u32]) -> PixelStats {
    let mut stats = PixelStats::default();
    f.for_each_pixel(t, &mut stats, |_, _, _, valid, d| {
        if valid {
            masks[usize::from(d.pg >> 5)] |= 1 << (d.pg & 31);
        }
    });
    stats
}

/// Checks the masks' length.
pub(crate) fn check_masks(f: &Frame<'_>, masks: &[u32]) -> Result<(), Error> {
    let n = f.vis.tile_count() as u64 * f.passes as u64;
    if masks.len() as u64 != n {
        return Err(Error::BufferSize {
            what: "batch-group masks",
            expected: n,
            got: masks.len() as u64,
        });
    }
    Ok(())
}

/// Phase 1: per (tile, pass) the mask of batch groups used by valid pixels,
/// `masks[t * P + p]`, bit `g` for group `g`.
///
/// GPU twin: [`wgsl::LAYDOWN_FINALIZE`](crate::wgsl::LAYDOWN_FINALIZE).
pub fn laydown_finalize(
    vis: &VisBuffer<'_>,
    table: &[MicroBatchInfo],
    config: &ClassifyConfig,
) -> Result<(Vec<u32>, PixelStats), Error> {
    let f = Frame::new(vis, table, config)?;
    let mut masks = vec![0u32; vis.tile_count() as usize * f.passes];
    let mut stats = PixelStats::default();
    for (t, row) in masks.chunks_mut(f.passes).enumerate() {
        stats = stats.merge(finalize_tile(&f, t, row));
    }
    Ok((masks, stats))
}

/// Exclusive prefix sum; returns the total. Wraps like the GPU's `u32` adds.
pub(crate) fn exclusive_scan(values: impl Iterator<Item = u32>, out: &mut Vec<u32>) -> u32 {
    let mut sum = 0u32;
    out.clear();
    for v in values {
        out.push(sum);
        sum = sum.wrapping_add(v);
    }
    sum
}

/// Per-tile lookup from `pass * 32 + group` to the counter's index relative to the tile's
/// first counter; only entries whose bit is set in the tile's masks are written (and read).
pub(crate) struct CounterLut {
    lut: Vec<u32>,
}

impl CounterLut {
    pub fn new() -> Self {
        Self {
            lut: vec![0; MAX_PASSES as usize * MAX_BATCH_GROUPS_PER_PASS as usize],
        }
    }

    /// Fills the entries of tile `t`; returns the tile's first counter.
    pub fn fill(&mut self, masks_t: &[u32], offsets_t: &[u32]) -> u32 {
        let base = offsets_t.first().copied().unwrap_or(0);
        for (p, (&m, &o)) in masks_t.iter().zip(offsets_t).enumerate() {
            let mut bits = m;
            let mut rank = o.wrapping_sub(base);
            while bits != 0 {
                let g = bits.trailing_zeros() as usize;
                self.lut[p * 32 + g] = rank;
                rank += 1;
                bits &= bits - 1;
            }
        }
        base
    }

    /// The tile-relative counter of `(pass, group)`, or `None` if the mask lacks it.
    #[inline(always)]
    pub fn get(&self, masks_t: &[u32], pg: u16) -> Option<usize> {
        let p = usize::from(pg >> 5);
        if (masks_t[p] >> (pg & 31)) & 1 == 0 {
            return None;
        }
        Some(self.lut[usize::from(pg)] as usize)
    }
}

/// The triangles of one tile's valid pixels, gathered during the pixel scan and marked in
/// the cull buffer after it. A direct-mapped cache of words (per thread, kept from tile to
/// tile) folds most repeats into one request; the marking then runs in two loops whose iterations are independent (load
/// each triangle's indices into chunk numbers, then set the chunks' bytes), so their cache
/// misses overlap. Triangles with bad indices are rare: their pixels are counted by a
/// second look at the tile only when there are any.
pub(crate) struct TileMarks {
    slots: Vec<u32>,
    /// Room for one request per pixel of a tile; the first `n` are the tile's.
    requests: Vec<MarkRequest>,
    n: usize,
    chunks: Vec<u32>,
    bad_words: Vec<u32>,
}

#[derive(Clone, Copy, Default)]
struct MarkRequest {
    word: u32,
    mb: u32,
    instance: u32,
    prim: u32,
}

impl TileMarks {
    const BITS: u32 = 14;

    pub fn new() -> Self {
        Self {
            slots: vec![VIS_NONE; 1 << Self::BITS],
            requests: vec![MarkRequest::default(); (TILE_SIZE * TILE_SIZE) as usize + 1],
            n: 0,
            chunks: Vec::new(),
            bad_words: Vec::new(),
        }
    }

    /// Starts a tile. The cache of words persists from tile to tile (a cached word's
    /// triangle is marked, and words with bad indices are taken out of it).
    pub fn begin(&mut self) {
        self.n = 0;
    }

    #[inline(always)]
    fn hash(word: u32) -> usize {
        (word.wrapping_mul(0x9e37_79b1) >> (32 - Self::BITS)) as usize
    }

    /// Records pixel word `word` if `valid` (without a branch: the request is always
    /// written, and kept only when it is valid and new).
    #[inline(always)]
    pub fn add(&mut self, word: u32, d: &Decoded, valid: bool) {
        let slot = &mut self.slots[Self::hash(word)];
        let new = valid & (*slot != word);
        *slot = if valid { word } else { *slot };
        // At most one request per pixel of the tile, so `n` stays within the buffer.
        let at = self.n.min(self.requests.len() - 1);
        self.requests[at] = MarkRequest {
            word,
            mb: d.mb,
            instance: d.instance,
            prim: d.prim,
        };
        self.n += usize::from(new);
    }

    /// Marks every recorded triangle of tile `t`; returns the valid pixels whose triangle
    /// has bad indices.
    pub fn finish(
        &mut self,
        f: &Frame<'_>,
        t: usize,
        table: &[MicroBatchInfo],
        indices: &[u32],
        cull: &[AtomicU8],
        chunk_count: u32,
    ) -> u32 {
        self.chunks.clear();
        self.bad_words.clear();
        for r in &self.requests[..self.n] {
            if !triangle_chunks(
                &table[r.mb as usize],
                r.instance,
                r.prim,
                indices,
                chunk_count,
                &mut self.chunks,
            ) {
                self.bad_words.push(r.word);
            }
        }
        let mut prev = u32::MAX;
        for &c in &self.chunks {
            if c != prev {
                let cell = &cull[c as usize];
                if cell.load(Ordering::Relaxed) == 0 {
                    cell.store(1, Ordering::Relaxed);
                }
                prev = c;
            }
        }
        if self.bad_words.is_empty() {
            return 0;
        }
        self.bad_words.sort_unstable();
        self.bad_words.dedup();
        // Bad triangles are requested again in every tile that has them, so each tile
        // counts its own bad pixels.
        for &w in &self.bad_words {
            let slot = &mut self.slots[Self::hash(w)];
            if *slot == w {
                *slot = VIS_NONE;
            }
        }
        let mut bad = 0;
        let mut ignore = PixelStats::default();
        f.for_each_pixel(t, &mut ignore, |x, y, word, valid, _| {
            if valid && self.bad_words.binary_search(&word).is_ok() && f.first_of_run(x, y, word) {
                bad += 1;
            }
        });
        bad
    }
}

/// Appends the cull-buffer chunks of the triangle of a valid pixel to `out` (those that
/// exist); false if an index was bad (past the index buffer, at or past the vertex count,
/// or a chunk past the buffer).
#[inline(always)]
pub(crate) fn triangle_chunks(
    row: &MicroBatchInfo,
    instance: u32,
    prim: u32,
    indices: &[u32],
    chunk_count: u32,
    out: &mut Vec<u32>,
) -> bool {
    let first = u64::from(row.first_index) + 3 * u64::from(prim);
    let Some(tri) = indices.get(first as usize..first as usize + 3) else {
        return false;
    };
    let base = u64::from(instance) * u64::from(row.vertex_count);
    let mut ok = true;
    for &v in tri {
        if v >= row.vertex_count {
            ok = false;
            continue;
        }
        let chunk =
            u64::from(row.first_chunk) + (base + u64::from(v)) / u64::from(VERTEX_CHUNK_SIZE);
        if chunk >= u64::from(chunk_count) {
            ok = false;
            continue;
        }
        out.push(chunk as u32);
    }
    ok
}

/// Phase 2, one tile: counts into `counts_t` (the tile's counters) and marks `cull`.
#[expect(
    clippy::too_many_arguments,
    reason = "pass-shaped CPU twin: one workgroup of mid classify, taking the pass's per-tile bindings in the shader's order"
)]
pub(crate) fn count_tile(
    f: &Frame<'_>,
    t: usize,
    table: &[MicroBatchInfo],
    indices: &[u32],
    masks_t: &[u32],
    offsets_t: &[u32],
    counts_t: &mut [u32],
    cull: &[AtomicU8],
    chunk_count: u32,
    (lut, marks): &mut (CounterLut, TileMarks),
) -> PixelStats {
    lut.fill(masks_t, offsets_t);
    marks.begin();
    let mut stats = PixelStats::default();
    let mut dropped = 0u32;
    let mut commands = 0u32;
    f.for_each_pixel(t, &mut stats, |x, y, word, valid, d| {
        marks.add(word, &d, valid && f.vertex_cull);
        if !valid || f.sample(x, y, word).is_none() {
            return;
        }
        match lut.get(masks_t, d.pg) {
            Some(c) => {
                counts_t[c] += 1;
                commands += 1;
            }
            None => dropped += 1,
        }
    });
    stats.commands = commands;
    stats.dropped = dropped;
    stats.bad_indices = marks.finish(f, t, table, indices, cull, chunk_count);
    stats
}

/// Half-open element ranges, one per tile.
pub(crate) type Ranges = Vec<(usize, usize)>;

/// Splits `data` into consecutive pieces at the given starts (relative to `data`).
pub(crate) fn split_at_starts<'s, T>(
    mut data: &'s mut [T],
    bounds: &[(usize, usize)],
) -> Vec<&'s mut [T]> {
    let mut out = Vec::with_capacity(bounds.len());
    let mut at = 0usize;
    for &(start, end) in bounds {
        let (_, rest) = data.split_at_mut(start - at);
        let (piece, rest) = rest.split_at_mut(end - start);
        out.push(piece);
        data = rest;
        at = end;
    }
    out
}

/// Checks the counter offsets against the masks and returns each tile's counter range.
pub(crate) fn tile_counter_ranges(
    f: &Frame<'_>,
    masks: &[u32],
    counter_offsets: &[u32],
) -> Result<(Ranges, u32), Error> {
    check_masks(f, masks)?;
    if counter_offsets.len() != masks.len() {
        return Err(Error::MismatchedPhase {
            what: "counter offsets",
        });
    }
    let mut sum = 0u64;
    for (&m, &o) in masks.iter().zip(counter_offsets) {
        if u64::from(o) != sum {
            return Err(Error::MismatchedPhase {
                what: "counter offsets",
            });
        }
        sum += u64::from(m.count_ones());
    }
    let p = f.passes;
    let ranges = (0..f.vis.tile_count() as usize)
        .map(|t| {
            let start = counter_offsets[t * p] as usize;
            let end = counter_offsets
                .get((t + 1) * p)
                .map_or(sum as usize, |&o| o as usize);
            (start, end)
        })
        .collect();
    Ok((ranges, sum as u32))
}

/// Sizes the cull buffer: `chunk_count` rounded up to 4.
pub(crate) fn cull_buffer(chunk_count: u32) -> Vec<AtomicU8> {
    (0..chunk_count.next_multiple_of(4))
        .map(|_| AtomicU8::new(0))
        .collect()
}

/// Phase 2: compact counter offsets, counts, the vertex cull buffer and pixel-command
/// offsets. `masks` comes from [`laydown_finalize`]; `indices` is the shared index buffer
/// the table's `first_index` points into (three local indices per triangle).
///
/// GPU twin: [`wgsl::MID_CLASSIFY`](crate::wgsl::MID_CLASSIFY).
pub fn mid_classify(
    vis: &VisBuffer<'_>,
    table: &[MicroBatchInfo],
    indices: &[u32],
    config: &ClassifyConfig,
    masks: &[u32],
) -> Result<MidClassify, Error> {
    let f = Frame::new(vis, table, config)?;
    check_masks(&f, masks)?;
    let mut mid = MidClassify::default();
    mid.counter_count = exclusive_scan(
        masks.iter().map(|m| m.count_ones()),
        &mut mid.counter_offsets,
    );
    let (ranges, _) = tile_counter_ranges(&f, masks, &mid.counter_offsets)?;
    let mut counts = vec![0u32; mid.counter_count as usize];
    let cull = cull_buffer(config.chunk_count);
    let mut scratch = (CounterLut::new(), TileMarks::new());
    let mut stats = PixelStats::default();
    let p = f.passes;
    for (t, counts_t) in split_at_starts(&mut counts, &ranges)
        .into_iter()
        .enumerate()
    {
        let s = count_tile(
            &f,
            t,
            table,
            indices,
            &masks[t * p..(t + 1) * p],
            &mid.counter_offsets[t * p..(t + 1) * p],
            counts_t,
            &cull,
            config.chunk_count,
            &mut scratch,
        );
        stats = stats.merge(s);
    }
    mid.command_count = exclusive_scan(counts.iter().copied(), &mut mid.pixel_offsets);
    mid.counts = counts;
    mid.vertex_cull = cull.into_iter().map(AtomicU8::into_inner).collect();
    mid.stats = stats;
    Ok(mid)
}

/// Checks that `mid` belongs to `masks` and returns each tile's counter range and command
/// range.
pub(crate) fn check_mid(
    f: &Frame<'_>,
    masks: &[u32],
    mid: &MidClassify,
) -> Result<(Ranges, Ranges), Error> {
    let (ranges, counters) = tile_counter_ranges(f, masks, &mid.counter_offsets)?;
    if counters != mid.counter_count
        || mid.counts.len() != counters as usize
        || mid.pixel_offsets.len() != counters as usize
    {
        return Err(Error::MismatchedPhase { what: "counts" });
    }
    let mut sum = 0u64;
    for (&c, &o) in mid.counts.iter().zip(&mid.pixel_offsets) {
        if u64::from(o) != sum {
            return Err(Error::MismatchedPhase {
                what: "pixel offsets",
            });
        }
        sum += u64::from(c);
    }
    if sum != u64::from(mid.command_count) {
        return Err(Error::MismatchedPhase {
            what: "pixel offsets",
        });
    }
    let cmd_ranges = ranges
        .iter()
        .map(|&(a, b)| {
            let start = mid
                .pixel_offsets
                .get(a)
                .map_or(sum as usize, |&o| o as usize);
            let end = mid
                .pixel_offsets
                .get(b)
                .map_or(sum as usize, |&o| o as usize);
            (start, end.max(start))
        })
        .collect();
    Ok((ranges, cmd_ranges))
}

/// Phase 3, one tile: writes the tile's commands (`commands_t`, starting at the tile's
/// first command) and final counts (`finals_t`).
#[expect(
    clippy::too_many_arguments,
    reason = "pass-shaped CPU twin: one workgroup of classify output, taking the pass's per-tile bindings in the shader's order"
)]
pub(crate) fn output_tile(
    f: &Frame<'_>,
    t: usize,
    masks_t: &[u32],
    offsets_t: &[u32],
    counts_t: &[u32],
    pixel_offsets_t: &[u32],
    commands_t: &mut [u16],
    finals_t: &mut [u32],
    lut: &mut CounterLut,
) -> PixelStats {
    lut.fill(masks_t, offsets_t);
    let cmd_base = pixel_offsets_t.first().copied().unwrap_or(0);
    let (x0, y0, _, _) = f.tile_rect(t);
    let mut stats = PixelStats::default();
    let mut written = 0u32;
    let mut dropped = 0u32;
    f.for_each_pixel(t, &mut stats, |x, y, word, valid, d| {
        if !valid {
            return;
        }
        let Some(mask) = f.sample(x, y, word) else {
            return;
        };
        let Some(c) = lut.get(masks_t, d.pg) else {
            dropped += 1;
            return;
        };
        let k = finals_t[c];
        if k >= counts_t[c] {
            dropped += 1;
            return;
        }
        let cmd = match f.vis.layout {
            VisLayout::Standard => pixel_command(x - x0, y - y0),
            VisLayout::Vrs => vrs::quad_command((x - x0) >> 1, (y - y0) >> 1, mask),
        };
        commands_t[(pixel_offsets_t[c] - cmd_base + k) as usize] = cmd;
        finals_t[c] = k + 1;
        written += 1;
    });
    stats.commands = written;
    stats.dropped = dropped;
    stats
}

/// The wave commands and pass dispatches from the final counts (sequential: one entry per
/// (tile, pass), cheap next to the pixels).
pub(crate) fn write_waves(
    f: &Frame<'_>,
    masks: &[u32],
    counter_offsets: &[u32],
    pixel_offsets: &[u32],
    wave_width: WaveWidth,
    out: &mut ClassifyOutput,
) {
    let finals = &out.final_counts;
    let p_count = f.passes;
    let tiles = f.vis.tile_count() as usize;
    let w = wave_width.lanes();
    let mut wave_offsets = vec![0; finals.len()];
    let mut waves = Vec::new();
    let mut passes = Vec::with_capacity(p_count);
    for p in 0..p_count {
        let first = waves.len() as u32;
        let mut items = 0u32;
        for t in 0..tiles {
            let e = t * p_count + p;
            let mut bits = masks[e];
            let mut c = counter_offsets[e] as usize;
            let tx = t as u32 % f.vis.tiles_x();
            let ty = t as u32 / f.vis.tiles_x();
            while bits != 0 {
                let g = bits.trailing_zeros();
                bits &= bits - 1;
                let n = finals[c];
                wave_offsets[c] = waves.len() as u32;
                let mut k = 0;
                while k < n {
                    waves.push(WaveCommand {
                        tile: tx | (ty << WAVE_TILE_Y_SHIFT),
                        pass_group: p as u32 | (g << WAVE_GROUP_SHIFT),
                        first_command: pixel_offsets[c] + k,
                        command_count: (n - k).min(w),
                    });
                    k += w;
                }
                items += n;
                c += 1;
            }
        }
        let count = waves.len() as u32 - first;
        passes.push(PassDispatch::new(first, count, items));
    }
    out.wave_offsets = wave_offsets;
    out.waves = waves;
    out.passes = passes;
}

/// Phase 3: pixel (or quad) commands, final counts, wave commands and per-pass dispatches.
/// `masks` from [`laydown_finalize`], `mid` from [`mid_classify`] (possibly run with an
/// earlier validity mask: the talk's mid classify overlaps the geometry pass, so its counts
/// may only overestimate). `vis` carries the final validity.
///
/// GPU twin: [`wgsl::CLASSIFY_OUTPUT`](crate::wgsl::CLASSIFY_OUTPUT).
pub fn classify_output(
    vis: &VisBuffer<'_>,
    table: &[MicroBatchInfo],
    config: &ClassifyConfig,
    masks: &[u32],
    mid: &MidClassify,
) -> Result<ClassifyOutput, Error> {
    let f = Frame::new(vis, table, config)?;
    let (ranges, cmd_ranges) = check_mid(&f, masks, mid)?;
    let mut commands = vec![0u16; mid.command_count as usize];
    let mut finals = vec![0u32; mid.counter_count as usize];
    let mut lut = CounterLut::new();
    let mut stats = PixelStats::default();
    let p = f.passes;
    let cmd_pieces = split_at_starts(&mut commands, &cmd_ranges);
    let final_pieces = split_at_starts(&mut finals, &ranges);
    for (t, (commands_t, finals_t)) in cmd_pieces.into_iter().zip(final_pieces).enumerate() {
        let (a, b) = ranges[t];
        let s = output_tile(
            &f,
            t,
            &masks[t * p..(t + 1) * p],
            &mid.counter_offsets[t * p..(t + 1) * p],
            &mid.counts[a..b],
            &mid.pixel_offsets[a..b],
            commands_t,
            finals_t,
            &mut lut,
        );
        stats = stats.merge(s);
    }
    let mut out = ClassifyOutput {
        commands,
        final_counts: finals,
        stats,
        ..ClassifyOutput::default()
    };
    write_waves(
        &f,
        masks,
        &mid.counter_offsets,
        &mid.pixel_offsets,
        config.wave_width,
        &mut out,
    );
    Ok(out)
}

/// All three phases with one validity (the vis buffer's), fused into one scan per tile:
/// the same outputs as [`classify_phases`] (running [`laydown_finalize`],
/// [`mid_classify`] and [`classify_output`] in turn), faster on the CPU because each tile
/// is read once while it is in cache.
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
pub fn classify(
    vis: &VisBuffer<'_>,
    table: &[MicroBatchInfo],
    indices: &[u32],
    config: &ClassifyConfig,
) -> Result<Classification, Error> {
    let f = Frame::new(vis, table, config)?;
    let mut masks = vec![0u32; vis.tile_count() as usize * f.passes];
    let cull = cull_buffer(config.chunk_count);
    let mut scratch = fused::Scratch::new();
    let tiles = masks
        .chunks_mut(f.passes)
        .enumerate()
        .map(|(t, m)| {
            fused::tile(
                &f,
                t,
                table,
                indices,
                &cull,
                config.chunk_count,
                m,
                &mut scratch,
            )
        })
        .collect();
    Ok(fused::assemble(&f, config, masks, tiles, cull))
}

/// All three phases run as the GPU runs them: [`laydown_finalize`], [`mid_classify`],
/// [`classify_output`], each over the whole frame. Equal to [`classify`].
pub fn classify_phases(
    vis: &VisBuffer<'_>,
    table: &[MicroBatchInfo],
    indices: &[u32],
    config: &ClassifyConfig,
) -> Result<Classification, Error> {
    let (masks, _) = laydown_finalize(vis, table, config)?;
    let mid = mid_classify(vis, table, indices, config, &masks)?;
    let output = classify_output(vis, table, config, &masks, &mid)?;
    Ok(Classification { masks, mid, output })
}

/// Sorts each counter's written commands by [`command_sort_key`]: the canonical order in
/// which the CPU twin writes them. Apply it to the GPU's commands before comparing.
/// Ranges past the buffer are skipped.
pub fn canonical_sort(
    commands: &mut [u16],
    pixel_offsets: &[u32],
    final_counts: &[u32],
    layout: VisLayout,
) {
    for (&o, &n) in pixel_offsets.iter().zip(final_counts) {
        let (a, b) = (o as usize, o as usize + n as usize);
        if let Some(seg) = commands.get_mut(a..b) {
            seg.sort_unstable_by_key(|&c| command_sort_key(c, layout));
        }
    }
}
