//! The classification's public types: its settings ([`ClassifyConfig`]), the uniform its
//! WGSL passes read ([`TilingParams`]), the pixel bookkeeping ([`PixelStats`]), the wave
//! commands and what each phase returns.

use alloc::vec::Vec;

use visbuf::VisLayout;
use wave::WaveWidth;

use crate::Error;
use crate::layout::{PassDispatch, TILE_SIZE, VisBuffer};
use crate::plan::MAX_PASSES;
use crate::vertex::UBER_CHUNK_CHUNKS;

/// Bit of [`TilingParams::flags`]: the validity bitmask is bound and applies.
pub const FLAG_VALIDITY: u32 = 1;
/// Bit of [`TilingParams::flags`]: the words use [`VisLayout::Vrs`] (quad commands).
pub const FLAG_VRS: u32 = 2;
/// Bit of [`TilingParams::flags`]: mid classify marks the vertex chunks of visible
/// triangles ([`ClassifyConfig::vertex_cull`]).
pub const FLAG_VERTEX_CULL: u32 = 4;

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
    /// starts, [`first_of_run`](crate::first_of_run)). Without it the cull buffer stays zero, no index is read
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

    /// Errors unless `pass_count` is in `1..=MAX_PASSES`.
    pub(crate) fn validate(&self) -> Result<(), Error> {
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
            (vis.width(), vis.height()),
            vis.layout(),
            vis.validity().is_some(),
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
            uber_count: config.chunk_count.div_ceil(UBER_CHUNK_CHUNKS),
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
    /// Mid classify: valid pixels that start a triangle run, see [`first_of_run`](crate::first_of_run), and
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
