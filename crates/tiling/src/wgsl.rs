//! The GPU twins: one WGSL module per pass, described once here ([`LAYDOWN_FINALIZE`],
//! [`MID_CLASSIFY`], [`CLASSIFY_OUTPUT`], [`VERTEX_WAVES`]: bindings by name and kind,
//! entry points in order with their workgroup sizes and dispatch geometry over
//! [`TilingParams`], the buffers zeroed first). The `gpu` crate builds its layouts,
//! pipelines and dispatches from these descriptions, the device tests run the passes
//! through them, and a unit test proves each matches its composed module with naga. Every
//! output can be compared with the CPU twin bit for bit (the pixel commands after
//! [`canonical_sort`](crate::canonical_sort)).
//!
//! The modules ([`MODULES`]) import what they use: `visbuf::id` (every bit of the vis word
//! is decoded by its functions), `wave::append` where a pass appends (one atomic per
//! subgroup with the `subgroups` feature, per workgroup without; needs
//! `wgpu::Features::SUBGROUP` with it), `tiling::common` (constants, structs, the
//! workgroup scan, the block sizes of the entry scans), `tiling::decode` (bindings 0, 2, 3
//! and the pixel decode), `tiling::pixel` (adds the vis words at binding 1: the quads, the
//! per-pixel records and stats), `tiling::finalize` (laydown finalise's workgroup marks and
//! the masks at binding 4, imported by `laydown_finalize` and by any pass that has the
//! words in hand: [`finalize_bindings`]) and `tiling::keyed` (bindings 4-5 and the keyed
//! workgroup histogram). The pixel phases run an invocation per 2x2 quad (a
//! 32x32 block per workgroup, the quad's pixels spelled out: loop-indexed vectors live in
//! local memory on some GPUs). `count_pixels` and `write_commands` aggregate through the
//! histogram: a block lies in one tile whose counters are contiguous, so one LDS atomic per
//! pixel and one global atomic per counter of the block replace the wave-append loop over
//! keys; tiles with more than `TILING_HIST_LIMIT` (an `override`, 256) counters take that
//! loop. Both give the same counts and, after [`canonical_sort`](crate::canonical_sort),
//! the same commands. `count_pixels` records each pixel's slot, and without a validity
//! mask classify output's `scatter_write_waves` places the commands from those records
//! (and, in the same dispatch, writes the wave commands). The pixel phases count only the
//! rare stats per pixel; valid and empty pixels follow from the others at the flush.
//! `count_pixels` reads a triangle's indices and marks its vertex chunks only with
//! [`FLAG_VERTEX_CULL`](crate::classify::FLAG_VERTEX_CULL).
//!
//! Units: every length and offset is in elements of the named buffer; a buffer's `size`
//! in the descriptions is the bytes of one element (the least a binding may hold). "Zeroed"
//! buffers must hold zeros when the pass's first entry point starts.
//!
//! The `override`s: `TILING_HIST_LIMIT` (tests set 0 to force the loop everywhere) and mid
//! classify's `TILING_VERTEX_CULL_CODE` (false: `count_pixels` without the vertex-cull
//! code, which ignores [`FLAG_VERTEX_CULL`](crate::classify::FLAG_VERTEX_CULL); its
//! registers alone cost 7-9 µs of the pass on the H200, so frames without the flag should
//! take such a pipeline). Features
//! besides `subgroups`: the timing experiments of `gpu`'s `classify_variants`
//! (`timing_omit_stats`, `timing_omit_cull_marks`, `timing_omit_index_reads`,
//! `timing_omit_append_loop`,
//! `timing_omit_records`, `timing_store_commands`, and laydown finalize's `timing_load_only`
//! and `timing_no_table`; each drops work and most make the output wrong, and the shipped
//! build has none of their code).
//!
//! The prefix sums over (tile, pass) entries (`counter_offsets_pass`, `entry_waves`) run
//! a workgroup per [`ENTRY_BLOCK`] entries; the last workgroup to finish (a counter in the
//! zeroed scratch buffer, `storageBarrier`'s device-scope fences, every value another
//! workgroup wrote read with an atomic load) scans the block sums. No workgroup waits on
//! another, so this needs no forward-progress guarantee. Entry points past 65 535 workgroups continue in rows
//! ([`shader::Dispatch::Items`]).
//!
//! [`TilingParams`]: crate::TilingParams

use shader::{Binding, Entry, Group, Kind, Module, Pass, join};

use crate::TilingParams;
use crate::classify::{PassDispatch, PixelStats, TILE_SIZE, Totals, WaveCommand};
use crate::plan::{MAX_BATCH_GROUPS_PER_PASS, MAX_PASSES, MicroBatchInfo, PassInfo};
use crate::vertex::{DELTA_BLOCK, UberChunk, VertexWaveCommand};

/// `tiling::common`: constants, buffer structs and helpers of every pass (no bindings).
pub const COMMON: Module = Module::new("tiling::common", include_str!("wgsl/common.wgsl"));
/// `tiling::decode`: the pixel decode and its bindings (0, 2, 3: params, validity, table).
pub const DECODE: Module = Module::new("tiling::decode", include_str!("wgsl/decode.wgsl"));
/// `tiling::pixel`: the classification passes' bindings 0-3 (`tiling::decode`'s and the vis
/// words), the quads and the per-pixel records.
pub const PIXEL: Module = Module::new("tiling::pixel", include_str!("wgsl/pixel.wgsl"));
/// `tiling::finalize`: laydown finalise's per-pixel marks and their binding (4, the
/// masks), for any pass whose workgroups lie in one tile ([`finalize_bindings`]).
pub const FINALIZE: Module = Module::new("tiling::finalize", include_str!("wgsl/finalize.wgsl"));
/// `tiling::keyed`: bindings 4-5 of the pixel phases and the keyed workgroup histogram.
pub const KEYED: Module = Module::new("tiling::keyed", include_str!("wgsl/keyed.wgsl"));
/// `tiling::laydown_finalize`: phase 1.
pub const LAYDOWN_FINALIZE_MODULE: Module = Module::new(
    "tiling::laydown_finalize",
    include_str!("wgsl/laydown_finalize.wgsl"),
);
/// `tiling::mid_classify`: phase 2.
pub const MID_CLASSIFY_MODULE: Module = Module::new(
    "tiling::mid_classify",
    include_str!("wgsl/mid_classify.wgsl"),
);
/// `tiling::classify_output`: phase 3.
pub const CLASSIFY_OUTPUT_MODULE: Module = Module::new(
    "tiling::classify_output",
    include_str!("wgsl/classify_output.wgsl"),
);
/// `tiling::vertex_waves`: the vertex wave commands.
pub const VERTEX_WAVES_MODULE: Module = Module::new(
    "tiling::vertex_waves",
    include_str!("wgsl/vertex_waves.wgsl"),
);

/// This crate's modules.
pub const MODULES: &[Module] = &[
    COMMON,
    DECODE,
    PIXEL,
    FINALIZE,
    KEYED,
    LAYDOWN_FINALIZE_MODULE,
    MID_CLASSIFY_MODULE,
    CLASSIFY_OUTPUT_MODULE,
    VERTEX_WAVES_MODULE,
];

/// Every module list a tiling pass may import from.
pub const LIBRARY: &[&[Module]] = &[visbuf::wgsl::MODULES, wave::wgsl::MODULES, MODULES];

/// Bindings 0-3 of every classification phase: `tiling::pixel`'s.
const PIXEL_BINDINGS: [Binding; 4] = [
    Binding::new("params", Kind::uniform(size_of::<TilingParams>())),
    // width * height vis words, row-major.
    Binding::new("vis", Kind::read(4)),
    // The validity bitmask of FLAG_VALIDITY: bit i % 32 of word i / 32 for pixel i, read
    // only with the flag (bind any non-empty buffer without it).
    Binding::new("valid", Kind::read(4)),
    Binding::new("table", Kind::read(size_of::<MicroBatchInfo>())),
];

/// Group 0 of a pass that imports `tiling::finalize` ([`FINALIZE`]) and declares binding 1
/// itself (`binding1`: `gpu`'s compute laydown unpack, the vis words it writes): `params`,
/// `binding1`, `valid`, `table` and `masks` (`tiles * P` `atomic<u32>`, zeroed before the
/// pass; [`LAYDOWN_FINALIZE`]'s output).
#[must_use]
pub const fn finalize_bindings(binding1: Binding) -> [Binding; 5] {
    [
        PIXEL_BINDINGS[0],
        binding1,
        PIXEL_BINDINGS[2],
        PIXEL_BINDINGS[3],
        Binding::new("masks", Kind::read_write(4)),
    ]
}

/// Bindings 0-5 of both pixel phases: `tiling::pixel`'s and `tiling::keyed`'s.
const KEYED_BINDINGS: [Binding; 6] = join(
    PIXEL_BINDINGS,
    [
        Binding::new("masks", Kind::read(4)),
        Binding::new("counter_offsets", Kind::read_write(4)),
    ],
);

/// Invocations per workgroup of every [`Entry::items`] entry point (WGSL
/// `TILING_ITEMS_WORKGROUP_SIZE`, which those entry points' `@workgroup_size` and item
/// index `tiling_item_index` use).
const ITEMS_WORKGROUP_SIZE: u32 = 64;

/// Dispatch over the vis buffer, one invocation per 2x2 quad of pixels.
fn quads(p: &TilingParams) -> [u32; 2] {
    [p.width.div_ceil(2), p.height.div_ceil(2)]
}

/// Pixels across the square block of one 16x16 workgroup of the pixel phases and of laydown
/// finalise, four an invocation (WGSL `TILING_BLOCK_SIZE`, `tiling_block_tile`): a block
/// lies in one tile. A pass that finalises the laydown itself (`gpu`'s unpack) dispatches
/// one workgroup per block.
pub const BLOCK_SIZE: u32 = 32;

/// Mid classify's per-pixel record (its `slots` buffer, four per 2x2 quad), which classify
/// output's scatter turns into the pixel's command: with a command, this bit, the command's
/// slot within its counter (bits `0..RECORD_COUNTER_SHIFT`, [`RECORD_SLOT_MASK`]), the
/// counter's index among its tile's ([`RECORD_COUNTER_MASK`] at [`RECORD_COUNTER_SHIFT`])
/// and the sample mask (4 bits at [`RECORD_MASK_SHIFT`]); without one, the pixel's kind
/// (bits 0-1: empty, unknown, out of range, valid) and perhaps [`RECORD_DROPPED`]. WGSL
/// `TILING_RECORD_*` in `tiling::pixel`.
pub const RECORD_COMMAND: u32 = 1 << 31;
/// A record without a command whose valid pixel was dropped (its key is not in its tile's
/// masks).
pub const RECORD_DROPPED: u32 = 4;
/// Where a record's counter index starts; the slot below it.
pub const RECORD_COUNTER_SHIFT: u32 = 14;
/// A record's slot: a counter holds at most one tile's pixels, 128 * 128.
pub const RECORD_SLOT_MASK: u32 = (1 << RECORD_COUNTER_SHIFT) - 1;
/// Where a record's 4-bit sample mask starts.
pub const RECORD_MASK_SHIFT: u32 = 27;
/// A record's counter index within its tile's counters (after the shift).
pub const RECORD_COUNTER_MASK: u32 = (1 << (RECORD_MASK_SHIFT - RECORD_COUNTER_SHIFT)) - 1;

// The record's fields fit: a tile's pixels as slots, every counter a tile may have as an
// index, the sample mask below the command bit, the dropped flag above the kind's two bits.
const _: () = assert!(RECORD_SLOT_MASK + 1 >= TILE_SIZE * TILE_SIZE);
const _: () = assert!(RECORD_COUNTER_MASK + 1 >= MAX_PASSES * MAX_BATCH_GROUPS_PER_PASS);
const _: () = assert!(RECORD_MASK_SHIFT + 4 <= 31 && RECORD_DROPPED > 3);

/// A 16x16 workgroup per [`BLOCK_SIZE`] block of the vis buffer, an invocation per 2x2
/// quad (WGSL `tiling_quad_pixel`).
const fn per_quad(name: &'static str) -> Entry<TilingParams> {
    Entry::grid(name, 16, 16, quads)
}

/// [`quads`] with a validity mask (`write_commands` classifies the final mask), none
/// without.
fn quads_with_validity(p: &TilingParams) -> [u32; 2] {
    if has_validity(p) { quads(p) } else { [0, 0] }
}

/// Whether the frame has a validity mask (classify output's four dispatches run, else its
/// two).
fn has_validity(p: &TilingParams) -> bool {
    p.flags & crate::classify::FLAG_VALIDITY != 0
}

/// Words of mid classify's `offset_scratch` for `tiles` tiles and `passes` passes: a
/// workgroup counter and three pad words, each (tile, pass) entry's offset within its
/// block of [`ENTRY_BLOCK`], one sum per block (WGSL `tiling_offset_*`).
#[must_use]
pub const fn offset_scratch_words(tiles: u32, passes: u32) -> u32 {
    let n = tiles * passes;
    SCRATCH_HEADER_WORDS + n + n.div_ceil(ENTRY_BLOCK)
}

/// 2x2 quads of a `width x height` vis buffer (`slots` elements): `ceil(width / 2) *
/// ceil(height / 2)`.
#[must_use]
pub const fn record_quads(width: u32, height: u32) -> u32 {
    width.div_ceil(2) * height.div_ceil(2)
}

/// (tile, pass) entries of a frame: `tiles * passes`.
fn entries(p: &TilingParams) -> u32 {
    p.tiles_x * p.tiles_y * p.pass_count
}

/// Invocations of classify output's `write_waves` per (tile, pass) entry, which stride over
/// its counters' waves (WGSL `TILING_WAVE_ENTRY_LANES`).
pub const WAVE_ENTRY_LANES: u32 = 16;

/// (tile, pass) entries a workgroup of the block scans sums (`counter_offsets_pass`,
/// `entry_waves`; WGSL `TILING_ENTRY_BLOCK`).
pub const ENTRY_BLOCK: u32 = 256;

/// Workgroups of classify output's write_waves: one per `256 / WAVE_ENTRY_LANES` entries.
fn write_waves_groups(p: &TilingParams) -> u32 {
    entries(p).div_ceil(256 / WAVE_ENTRY_LANES)
}

/// Words before the entries in `offset_scratch` and `wave_scratch`: a workgroup counter and
/// pad (WGSL `TILING_SCRATCH_ENTRIES`).
pub const SCRATCH_HEADER_WORDS: u32 = 4;

/// Words of classify output's `wave_scratch` for `tiles` tiles and `passes` passes: a
/// workgroup counter and three pad words, each (tile, pass) entry's first wave within its
/// block of [`ENTRY_BLOCK`] entries, one sum per block, the waves and the commands of every
/// pass (WGSL `tiling_scratch_*`).
#[must_use]
pub const fn wave_scratch_words(tiles: u32, passes: u32) -> u32 {
    let n = tiles * passes;
    SCRATCH_HEADER_WORDS + n + n.div_ceil(ENTRY_BLOCK) + 2 * passes
}

/// Phase 1, laydown finalise: per (tile, pass) the batch groups used.
///
/// | binding | buffer | element |
/// | --- | --- | --- |
/// | `params` | the uniform | [`TilingParams`] |
/// | `vis` | `width * height` vis words | `u32` |
/// | `valid` | validity bitmask, `ceil(width * height / 32)` | `u32` |
/// | `table` | the MicroBatchInfoTable | [`MicroBatchInfo`] |
/// | `masks` | `tiles * P`, zeroed | `atomic<u32>` |
pub const LAYDOWN_FINALIZE: Pass<TilingParams> = Pass {
    name: "classify 1: laydown finalize",
    module: "tiling::laydown_finalize",
    library: LIBRARY,
    features: &["timing_omit_stats", "timing_load_only", "timing_no_table"],
    groups: &[Group {
        name: "classification",
        bindings: &finalize_bindings(PIXEL_BINDINGS[1]),
    }],
    entries: &[per_quad("laydown_finalize")],
    zeroed: &["masks"],
};

/// Phase 2, mid classify (`subgroups`: `wave`'s subgroup appends).
///
/// | binding | buffer | element |
/// | --- | --- | --- |
/// | `params`, `vis`, `valid`, `table` | as phase 1 | |
/// | `masks` | phase 1's | `u32` |
/// | `counter_offsets` | `tiles * P`: first counter per (tile, pass) | `u32` |
/// | `counts` | per counter (at most `tiles * P * 32`), zeroed | `atomic<u32>` |
/// | `vertex_cull` | `ceil(chunk_count / 4)`, four bytes per word, zeroed | `atomic<u32>` |
/// | `indices` | the index buffer the table's `first_index` points into | `u32` |
/// | `totals` | `counter_count` | [`Totals`] |
/// | `stats` | zeroed | [`PixelStats`] as `array<atomic<u32>, 8>` |
/// | `slots` | [`record_quads`]: each 2x2 quad's pixel records (WGSL `TILING_RECORD_*`: a command's slot and counter, or the pixel's kind) | `vec4<u32>` |
///
/// | `offset_scratch` | [`offset_scratch_words`], zeroed | `atomic<u32>` |
///
/// `counter_offsets_pass` (per (tile, pass) entry, [`ENTRY_BLOCK`] a workgroup) writes the
/// entries' offsets within their blocks and the blocks' first counters into
/// `offset_scratch`, and `totals.counter_count`; `count_pixels` (per quad) `counts`,
/// `vertex_cull`, `stats`, `slots` and, from the tile's first block, `counter_offsets`.
/// The counts' prefix sum, `pixel_offsets`, is [`CLASSIFY_OUTPUT`]'s first entry point.
pub const MID_CLASSIFY: Pass<TilingParams> = Pass {
    name: "classify 2: mid classify",
    module: "tiling::mid_classify",
    library: LIBRARY,
    features: &[
        "subgroups",
        "timing_omit_stats",
        "timing_omit_cull_marks",
        "timing_omit_index_reads",
        "timing_omit_append_loop",
        "timing_omit_records",
    ],
    groups: &[Group {
        name: "classification",
        bindings: &join::<6, 7, 13>(
            KEYED_BINDINGS,
            [
                Binding::new("counts", Kind::read_write(4)),
                Binding::new("vertex_cull", Kind::read_write(4)),
                Binding::new("indices", Kind::read(4)),
                Binding::new("totals", Kind::read_write(size_of::<Totals>())),
                Binding::new("stats", Kind::read_write(size_of::<PixelStats>())),
                Binding::new("slots", Kind::read_write(16)),
                Binding::new("offset_scratch", Kind::read_write(4)),
            ],
        ),
    }],
    entries: &[
        Entry::items("counter_offsets_pass", ENTRY_BLOCK, entries),
        per_quad("count_pixels"),
    ],
    zeroed: &["counts", "vertex_cull", "stats", "offset_scratch"],
};

/// Phase 3, classify output (`subgroups`: `wave`'s subgroup appends).
///
/// | binding | buffer | element |
/// | --- | --- | --- |
/// | `params`, `vis`, `valid`, `table` | as phase 1 | |
/// | `masks`, `counts` | phase 2's (read) | `u32` |
/// | `pixel_offsets` | per counter: first pixel command | `u32` |
/// | `counter_offsets` | phase 2's (bound `read_write`, shared with phase 2 through `tiling::keyed`; only read here) | `u32` |
/// | `final_counts` | per counter: commands written, zeroed | `atomic<u32>` |
/// | `commands` | `ceil(command_count / 2)`, command `i` in bits `16 (i % 2)..` of word `i / 2`, zeroed | `atomic<u32>` |
/// | `wave_offsets` | per counter: first wave command | `u32` |
/// | `waves` | wave commands, pass-major | [`WaveCommand`] |
/// | `passes` | `P`, the shading passes' indirect arguments | [`PassDispatch`] |
/// | `totals` | phase 2's `counter_count` (read); `command_count`, `wave_count` | [`Totals`] |
/// | `stats` | zeroed | [`PixelStats`] as `array<atomic<u32>, 8>` |
///
/// | `wave_scratch` | [`wave_scratch_words`], zeroed | `atomic<u32>` |
/// | `slots` | phase 2's | `vec4<u32>` |
/// | `mid_stats` | phase 2's `stats` | [`PixelStats`] |
///
/// `pixel_offsets_pass` (one workgroup; part of the CPU twin's mid classify, here where
/// the counts are plain loads: the atomic loads waited for each other) writes
/// `pixel_offsets` and `totals.command_count`. `entry_waves` (per (tile, pass) entry,
/// pass-major, [`ENTRY_BLOCK`] a workgroup) clamps `final_counts` to the counts, writes each
/// entry's first wave within its block and the sums per block and pass into
/// `wave_scratch`, and its last workgroup writes the blocks' first waves. `write_waves`
/// ([`WAVE_ENTRY_LANES`] invocations per entry, 256 a workgroup) writes `wave_offsets` and
/// `waves`, and its first workgroup `passes` and `totals.wave_count`.
///
/// With a validity mask (the mixed frame: the mask changed since phase 2) four dispatches:
/// `pixel_offsets_pass`, `write_commands` (per quad: classifies again and writes
/// `final_counts`, `commands`, `stats`; in the standard layout from phase 2's `slots`
/// where the final mask keeps a pixel phase 2 classified, from the word where phase 2 had
/// it empty: the mask may have grown), `entry_waves`, `write_waves`. Without one the
/// final counts are the counts, so two: `pixel_offsets_entry_waves` (`pixel_offsets_pass`'
/// workgroup first, then `entry_waves`'; and `stats`: phase 2's) and `scatter_write_waves`
/// (`write_waves`' workgroups, then one per [`BLOCK_SIZE`] block placing each pixel's
/// command at the slot phase 2 recorded; commands that find no room move from commands to
/// dropped).
pub const CLASSIFY_OUTPUT: Pass<TilingParams> = Pass {
    name: "classify 3: output",
    module: "tiling::classify_output",
    library: LIBRARY,
    features: &["subgroups", "timing_omit_stats", "timing_store_commands"],
    groups: &[Group {
        name: "classification",
        bindings: &join::<6, 12, 18>(
            KEYED_BINDINGS,
            [
                Binding::new("counts", Kind::read(4)),
                Binding::new("pixel_offsets", Kind::read_write(4)),
                Binding::new("final_counts", Kind::read_write(4)),
                Binding::new("commands", Kind::read_write(4)),
                Binding::new("wave_offsets", Kind::read_write(4)),
                Binding::new("waves", Kind::read_write(size_of::<WaveCommand>())),
                Binding::new("passes", Kind::read_write(size_of::<PassDispatch>())),
                Binding::new("totals", Kind::read_write(size_of::<Totals>())),
                Binding::new("stats", Kind::read_write(size_of::<PixelStats>())),
                Binding::new("wave_scratch", Kind::read_write(4)),
                Binding::new("slots", Kind::read(16)),
                Binding::new("mid_stats", Kind::read(size_of::<PixelStats>())),
            ],
        ),
    }],
    entries: &[
        // With a validity mask (the mixed frame) four dispatches:
        Entry::items("pixel_offsets_pass", 256, |p| {
            if has_validity(p) { 256 } else { 0 }
        }),
        Entry::grid("write_commands", 16, 16, quads_with_validity),
        Entry::items("entry_waves", ENTRY_BLOCK, |p| {
            if has_validity(p) { entries(p) } else { 0 }
        }),
        Entry::items("write_waves", 256, |p| {
            if has_validity(p) {
                256 * write_waves_groups(p)
            } else {
                0
            }
        }),
        // Without one two: pixel_offsets_pass' workgroup, then one per ENTRY_BLOCK entries;
        Entry::items("pixel_offsets_entry_waves", 256, |p| {
            if has_validity(p) {
                0
            } else {
                256 * (1 + entries(p).div_ceil(ENTRY_BLOCK))
            }
        }),
        // write_waves' workgroups, then one per BLOCK_SIZE block.
        Entry::items("scatter_write_waves", 256, |p| {
            if has_validity(p) {
                0
            } else {
                let blocks = p.width.div_ceil(BLOCK_SIZE) * p.height.div_ceil(BLOCK_SIZE);
                256 * (write_waves_groups(p) + blocks)
            }
        }),
    ],
    zeroed: &["final_counts", "commands", "stats", "wave_scratch"],
};

/// The vertex wave commands from the vertex cull buffer.
///
/// | binding | buffer | element |
/// | --- | --- | --- |
/// | `params` | `micro_batch_count`, `chunk_count`, `uber_count`, `pass_count`, `table_len` used | [`TilingParams`] |
/// | `table` | the MicroBatchInfoTable | [`MicroBatchInfo`] |
/// | `order` | the micro-batch order buffer | `u32` |
/// | `pass_infos` | the passes | [`PassInfo`] |
/// | `vertex_cull` | phase 2's | `u32` |
/// | `ubers` | `ceil(chunk_count / 64)` | [`UberChunk`] |
/// | `pyramid` | the histogram pyramid ([`pyramid_levels`](crate::vertex::pyramid_levels): the sum of the level lengths) | `u32` |
/// | `deltas` | micro-batch-ID deltas, then the IDs, at least the visible chunks (`chunk_count` is enough), zeroed | `atomic<u32>` |
/// | `micro_batch_waves` | per order entry: its vertex waves | `u32` |
/// | `vertex_commands` | one per visible chunk | [`VertexWaveCommand`] |
/// | `vertex_dispatches` | `P` | [`PassDispatch`] |
/// | `pass_items` | visible vertices per pass, `P`, zeroed | `atomic<u32>` |
/// | `totals` | `visible_chunks` | [`Totals`] |
/// | `delta_blocks` | the deltas' block sums, [`delta_block_count`](crate::vertex::delta_block_count)`(chunk_count)` | `u32` |
pub const VERTEX_WAVES: Pass<TilingParams> = Pass {
    name: "vertex wave commands",
    module: "tiling::vertex_waves",
    library: LIBRARY,
    features: &[],
    groups: &[Group {
        name: "vertex waves",
        bindings: &[
            Binding::new("params", Kind::uniform(size_of::<TilingParams>())),
            Binding::new("table", Kind::read(size_of::<MicroBatchInfo>())),
            Binding::new("order", Kind::read(4)),
            Binding::new("pass_infos", Kind::read(size_of::<PassInfo>())),
            Binding::new("vertex_cull", Kind::read(4)),
            Binding::new("ubers", Kind::read_write(size_of::<UberChunk>())),
            Binding::new("pyramid", Kind::read_write(4)),
            Binding::new("deltas", Kind::read_write(4)),
            Binding::new("micro_batch_waves", Kind::read_write(4)),
            Binding::new(
                "vertex_commands",
                Kind::read_write(size_of::<VertexWaveCommand>()),
            ),
            Binding::new(
                "vertex_dispatches",
                Kind::read_write(size_of::<PassDispatch>()),
            ),
            Binding::new("pass_items", Kind::read_write(4)),
            Binding::new("totals", Kind::read_write(size_of::<Totals>())),
            Binding::new("delta_blocks", Kind::read_write(4)),
        ],
    }],
    entries: &[
        Entry::items("uber_chunks", ITEMS_WORKGROUP_SIZE, |p| p.uber_count),
        Entry::once("build_pyramid", 256),
        Entry::items("micro_batch_deltas", ITEMS_WORKGROUP_SIZE, |p| {
            p.micro_batch_count
        }),
        Entry::items("delta_block_sums", DELTA_SCAN_WORKGROUP, delta_scan_items),
        Entry::once("scan_delta_blocks", DELTA_SCAN_WORKGROUP),
        Entry::items("scan_deltas", DELTA_SCAN_WORKGROUP, delta_scan_items),
        Entry::items("write_vertex_commands", ITEMS_WORKGROUP_SIZE, |p| {
            p.chunk_count
        }),
        Entry::items("pass_args", ITEMS_WORKGROUP_SIZE, |p| p.pass_count),
    ],
    zeroed: &["deltas", "pass_items"],
};

/// Invocations per workgroup of the deltas' prefix sum (`tiling_wg_scan`'s 256), each
/// taking four consecutive deltas of its block.
const DELTA_SCAN_WORKGROUP: u32 = 256;
const _: () = assert!(DELTA_BLOCK == 4 * DELTA_SCAN_WORKGROUP);

/// A workgroup per block of the deltas' prefix sum (the visible chunks, which only the GPU
/// knows, are at most `chunk_count`).
fn delta_scan_items(p: &TilingParams) -> u32 {
    p.chunk_count
        .div_ceil(DELTA_BLOCK)
        .saturating_mul(DELTA_SCAN_WORKGROUP)
}

/// The three classification phases, in the order a frame runs them.
pub const CLASSIFICATION: [&Pass<TilingParams>; 3] =
    [&LAYDOWN_FINALIZE, &MID_CLASSIFY, &CLASSIFY_OUTPUT];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::classify::*;
    use crate::plan::*;
    use crate::vertex::*;
    use alloc::vec::Vec;
    use shadercheck::{Caps, const_u32, validate};

    fn common() -> naga::Module {
        shadercheck::assert_composed(LIBRARY, "tiling::common", &[], Caps::CORE)
    }

    /// Every `TILING_` constant of the common part, with its Rust value.
    fn expected_constants() -> Vec<(&'static str, u32)> {
        let stat = |field: usize| (field / 4) as u32;
        alloc::vec![
            ("TILING_TILE_SIZE", TILE_SIZE),
            ("TILING_TILE_SHIFT", TILE_SHIFT),
            ("TILING_PIXEL_Y_SHIFT", PIXEL_Y_SHIFT),
            ("TILING_PIXEL_COORD_MASK", PIXEL_COORD_MASK),
            ("TILING_QUAD_Y_SHIFT", QUAD_Y_SHIFT),
            ("TILING_QUAD_COORD_MASK", QUAD_COORD_MASK),
            ("TILING_QUAD_PIXELS_SHIFT", QUAD_PIXELS_SHIFT),
            ("TILING_MAX_PASSES", MAX_PASSES),
            ("TILING_MAX_BATCH_GROUPS", MAX_BATCH_GROUPS_PER_PASS),
            ("TILING_MAX_PRIMITIVE_BITS", visbuf::MAX_PRIMITIVE_BITS),
            ("TILING_CHUNK_SIZE", VERTEX_CHUNK_SIZE),
            ("TILING_UBER_CHUNKS", UBER_CHUNK_CHUNKS),
            ("TILING_PYRAMID_FANOUT", PYRAMID_FANOUT),
            ("TILING_DELTA_BLOCK", DELTA_BLOCK),
            ("TILING_MAX_DISPATCH_X", MAX_DISPATCH_X),
            ("TILING_ITEMS_WORKGROUP_SIZE", ITEMS_WORKGROUP_SIZE),
            ("TILING_FLAG_VALIDITY", FLAG_VALIDITY),
            ("TILING_FLAG_VRS", FLAG_VRS),
            ("TILING_FLAG_VERTEX_CULL", FLAG_VERTEX_CULL),
            ("TILING_WAVE_TILE_Y_SHIFT", WAVE_TILE_Y_SHIFT),
            ("TILING_WAVE_GROUP_SHIFT", WAVE_GROUP_SHIFT),
            ("TILING_COMMAND_BITS", u16::BITS),
            ("TILING_WAVE_ENTRY_LANES", WAVE_ENTRY_LANES),
            ("TILING_BLOCK_SIZE", BLOCK_SIZE),
            ("TILING_NONE", u32::MAX),
            (
                "TILING_STAT_VALID",
                stat(core::mem::offset_of!(PixelStats, valid))
            ),
            (
                "TILING_STAT_EMPTY",
                stat(core::mem::offset_of!(PixelStats, empty))
            ),
            (
                "TILING_STAT_UNKNOWN",
                stat(core::mem::offset_of!(PixelStats, unknown))
            ),
            (
                "TILING_STAT_OUT_OF_RANGE",
                stat(core::mem::offset_of!(PixelStats, out_of_range))
            ),
            (
                "TILING_STAT_COMMANDS",
                stat(core::mem::offset_of!(PixelStats, commands))
            ),
            (
                "TILING_STAT_DROPPED",
                stat(core::mem::offset_of!(PixelStats, dropped))
            ),
            (
                "TILING_STAT_BAD_INDICES",
                stat(core::mem::offset_of!(PixelStats, bad_indices))
            ),
            (
                "TILING_STAT_NO_SAMPLE",
                stat(core::mem::offset_of!(PixelStats, pad))
            ),
            ("TILING_STAT_COUNT", (size_of::<PixelStats>() / 4) as u32),
            ("TILING_ENTRY_BLOCK", ENTRY_BLOCK),
            ("TILING_SCRATCH_ENTRIES", SCRATCH_HEADER_WORDS),
        ]
    }

    #[test]
    fn record_constants_match_rust() {
        let m = shadercheck::assert_composed(LIBRARY, "tiling::pixel", &[], Caps::CORE);
        for (name, value) in [
            ("TILING_RECORD_COMMAND", RECORD_COMMAND),
            ("TILING_RECORD_DROPPED", RECORD_DROPPED),
            ("TILING_RECORD_COUNTER_SHIFT", RECORD_COUNTER_SHIFT),
            ("TILING_RECORD_SLOT_MASK", RECORD_SLOT_MASK),
            ("TILING_RECORD_MASK_SHIFT", RECORD_MASK_SHIFT),
            ("TILING_RECORD_COUNTER_MASK", RECORD_COUNTER_MASK),
        ] {
            assert_eq!(const_u32(&m, name), Some(value), "WGSL const {name}");
        }
    }

    #[test]
    fn common_constants_match_rust() {
        let m = common();
        let expect = expected_constants();
        for (name, value) in &expect {
            assert_eq!(const_u32(&m, name), Some(*value), "WGSL const {name}");
        }
        for name in shadercheck::const_names(&m) {
            assert!(
                expect.iter().any(|(n, _)| *n == name),
                "unchecked WGSL const {name}"
            );
        }
    }

    /// `(WGSL member, byte offset)` of each member of a struct, in WGSL order
    /// (`shadercheck::members!`: the Rust field's offset, its WGSL name after a colon where
    /// they differ).
    type Members = Vec<(&'static str, u32)>;

    /// (WGSL struct, Rust size, WGSL members in WGSL order with the offsets of their Rust
    /// fields) for every shared struct: a Rust field moved, added or removed changes an
    /// offset or the size and fails the layout check.
    fn structs() -> Vec<(&'static str, usize, Members)> {
        alloc::vec![
            (
                "TilingParams",
                size_of::<TilingParams>(),
                shadercheck::members!(TilingParams {
                    width,
                    height,
                    tiles_x,
                    tiles_y,
                    pass_count,
                    wave_width,
                    flags,
                    table_len,
                    micro_batch_count,
                    chunk_count,
                    uber_count,
                    pad
                })
                .to_vec()
            ),
            (
                "TilingMicroBatchInfo",
                size_of::<MicroBatchInfo>(),
                shadercheck::members!(MicroBatchInfo {
                    first_id,
                    id_count,
                    pass: "pass_index",
                    batch_group,
                    primitive_bits,
                    primitive_count,
                    vertex_count,
                    instance_count,
                    first_instance,
                    batch,
                    batch_first_instance,
                    first_index,
                    base_vertex,
                    first_chunk,
                    ring_offset,
                    order
                })
                .to_vec()
            ),
            (
                "TilingPassInfo",
                size_of::<PassInfo>(),
                shadercheck::members!(PassInfo {
                    first_micro_batch,
                    micro_batch_count,
                    vertex_count,
                    first_chunk,
                    chunk_count,
                    batch_group_count,
                    shader,
                    pad
                })
                .to_vec()
            ),
            (
                "TilingWaveCommand",
                size_of::<WaveCommand>(),
                shadercheck::members!(WaveCommand {
                    tile,
                    pass_group,
                    first_command,
                    command_count
                })
                .to_vec()
            ),
            (
                "TilingPassDispatch",
                size_of::<PassDispatch>(),
                shadercheck::members!(PassDispatch {
                    x,
                    y,
                    z,
                    first,
                    count,
                    items
                })
                .to_vec()
            ),
            (
                "TilingUberChunk",
                size_of::<UberChunk>(),
                shadercheck::members!(UberChunk {
                    mask_lo,
                    mask_hi,
                    count,
                    pad
                })
                .to_vec()
            ),
            (
                "TilingVertexWaveCommand",
                size_of::<VertexWaveCommand>(),
                shadercheck::members!(VertexWaveCommand { micro_batch, chunk }).to_vec()
            ),
            (
                "TilingTotals",
                size_of::<Totals>(),
                shadercheck::members!(Totals {
                    counter_count,
                    command_count,
                    wave_count,
                    visible_chunks
                })
                .to_vec()
            ),
        ]
    }

    #[test]
    fn structs_have_the_rust_layouts() {
        // Rust field order, checked against the Pod structs by constructing them with
        // distinct values and reading the words back.
        let p = TilingParams {
            width: 0,
            height: 1,
            tiles_x: 2,
            tiles_y: 3,
            pass_count: 4,
            wave_width: 5,
            flags: 6,
            table_len: 7,
            micro_batch_count: 8,
            chunk_count: 9,
            uber_count: 10,
            pad: 11,
        };
        assert_eq!(
            bytemuck::cast::<_, [u32; 12]>(p),
            core::array::from_fn(|i| i as u32)
        );
        let m = MicroBatchInfo {
            first_id: 0,
            id_count: 1,
            pass: 2,
            batch_group: 3,
            primitive_bits: 4,
            primitive_count: 5,
            vertex_count: 6,
            instance_count: 7,
            first_instance: 8,
            batch: 9,
            batch_first_instance: 10,
            first_index: 11,
            base_vertex: 12,
            first_chunk: 13,
            ring_offset: 14,
            order: 15,
        };
        assert_eq!(
            bytemuck::cast::<_, [u32; 16]>(m),
            core::array::from_fn(|i| i as u32)
        );
        let d = PassDispatch {
            x: 0,
            y: 1,
            z: 2,
            first: 3,
            count: 4,
            items: 5,
        };
        assert_eq!(
            bytemuck::cast::<_, [u32; 6]>(d),
            core::array::from_fn(|i| i as u32)
        );
        let s = PixelStats {
            valid: 0,
            empty: 1,
            unknown: 2,
            out_of_range: 3,
            commands: 4,
            dropped: 5,
            bad_indices: 6,
            pad: 7,
        };
        assert_eq!(
            bytemuck::cast::<_, [u32; 8]>(s),
            core::array::from_fn(|i| i as u32)
        );

        let module = common();
        for (name, size, members) in structs() {
            shadercheck::assert_struct_layout(&module, name, size, &members);
        }
    }

    fn caps(features: &[&str]) -> Caps {
        // The timing experiments need nothing more.
        if features.contains(&"subgroups") {
            Caps::SUBGROUP
        } else {
            Caps::CORE
        }
    }

    #[test]
    fn descriptions_match_their_modules_with_the_narrowest_caps() {
        for pass in [
            &LAYDOWN_FINALIZE,
            &MID_CLASSIFY,
            &CLASSIFY_OUTPUT,
            &VERTEX_WAVES,
        ] {
            shadercheck::check_pass(pass, caps);
        }
        // The subgroup builds really need the capability; the fallback needs none.
        for pass in [&MID_CLASSIFY, &CLASSIFY_OUTPUT] {
            let src = pass.source(&["subgroups"]).unwrap();
            assert!(validate(&src, Caps::CORE).is_err(), "{}", pass.name);
        }
    }

    #[test]
    fn modules_decode_ids_through_visbuf_and_name_everything_tiling() {
        // No re-derived vis-word layout in this crate's sources: no shift by 16 or 30 of a
        // word, no 0xffff / 0x3fff masks.
        for m in MODULES {
            for pattern in ["0xffffu", "0x3fffu", ">> 16u", ">> 30u"] {
                assert!(
                    !m.source.contains(pattern),
                    "{}: re-derives the vis word: `{pattern}`",
                    m.name
                );
            }
        }
        for pass in [&LAYDOWN_FINALIZE, &MID_CLASSIFY, &CLASSIFY_OUTPUT] {
            let m = validate(&pass.source(&[]).unwrap(), Caps::CORE).unwrap();
            assert!(
                m.functions
                    .iter()
                    .any(|(_, f)| f.name.as_deref() == Some("visbuf_micro_batch")),
                "{} decodes through visbuf",
                pass.name
            );
            shadercheck::assert_prefixed(pass.name, &m, "tiling", &["visbuf", "wave"], false);
        }
        let m = common();
        shadercheck::assert_prefixed("tiling::common", &m, "tiling", &[], true);
    }
}
