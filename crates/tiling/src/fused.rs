//! [`classify`](crate::classify) as one pass per tile: the three phases' outputs computed
//! from a single scan of each tile (its words stay in cache), then the prefix sums and the
//! wave commands. The outputs are those of running [`laydown_finalize`],
//! [`mid_classify`] and [`classify_output`] in turn with one validity (the tests check it);
//! the phase functions remain the pass-shaped twins of the GPU passes.
//!
//! Per tile: the scan ORs the batch-group masks, counts commands per `pass * 32 + group`,
//! marks the vertex cull buffer and records each command with its (pass, group); the
//! tile's counters are the set bits of its masks in (pass, group) order, so a counting sort
//! by counter puts the tile's commands in their final order, and because the layout is
//! tile-major the tiles' counts and commands concatenate into the frame's.
//!
//! [`laydown_finalize`]: crate::laydown_finalize
//! [`mid_classify`]: crate::mid_classify
//! [`classify_output`]: crate::classify_output

use alloc::vec;
use alloc::vec::Vec;
use core::sync::atomic::{AtomicU8, Ordering};

use visbuf::VisLayout;

use crate::classify::{
    Classification, ClassifyConfig, ClassifyOutput, Frame, MidClassify, PixelStats, TileMarks,
    pixel_command, write_waves,
};
use crate::plan::{MAX_BATCH_GROUPS_PER_PASS, MAX_PASSES, MicroBatchInfo};
use crate::vrs;

/// Per-thread scratch, reused from tile to tile.
pub(crate) struct Scratch {
    /// Per `pass * 32 + group`: commands counted in this tile (reset after each tile; a
    /// tile has at most 16 384).
    pg_count: Vec<u16>,
    /// Per `pass * 32 + group`: the tile-local counter (valid for the tile's mask bits).
    lut: Vec<u16>,
    /// The tile's triangles, marked in the cull buffer after the scan.
    marks: TileMarks,
    /// The tile's runs of commands in scan order.
    runs: Vec<Run>,
}

impl Scratch {
    pub fn new() -> Self {
        let n = MAX_PASSES as usize * MAX_BATCH_GROUPS_PER_PASS as usize;
        Self {
            pg_count: vec![0; n],
            lut: vec![0; n],
            marks: TileMarks::new(),
            runs: Vec::with_capacity(128 * 128),
        }
    }
}

/// `n` consecutive commands `cmd, cmd + 1, ..` of one (pass, group): a run of pixels of
/// one word (always `n = 1` with VRS).
#[derive(Clone, Copy)]
pub(crate) struct Run {
    pg: u16,
    cmd: u16,
    n: u16,
}

/// One tile's share of the frame's outputs.
pub(crate) struct TileOut {
    counts: Vec<u32>,
    commands: Vec<u16>,
    stats: PixelStats,
}

/// Scans tile `t`: fills its mask row `masks_t`, marks `cull`, returns its counters'
/// counts and its commands in final order.
pub(crate) fn tile(
    f: &Frame<'_>,
    t: usize,
    table: &[MicroBatchInfo],
    indices: &[u32],
    cull: &[AtomicU8],
    chunk_count: u32,
    masks_t: &mut [u32],
    s: &mut Scratch,
) -> TileOut {
    s.runs.clear();
    let (x0, y0, _, _) = f.tile_rect(t);
    let mut stats = PixelStats::default();
    let vrs = f.vis.layout() == VisLayout::Vrs;
    s.marks.begin();
    let Scratch {
        pg_count,
        runs,
        marks,
        ..
    } = s;
    f.for_each_run(t, &mut stats, |x, y, n, word, d| {
        masks_t[usize::from(d.pg >> 5)] |= 1 << (d.pg & 31);
        marks.add(word, &d);
        if vrs {
            for xx in x..x + n {
                if let Some(mask) = vrs::sample_mask(&f.vis, xx, y, word) {
                    pg_count[usize::from(d.pg)] += 1;
                    runs.push(Run {
                        pg: d.pg,
                        cmd: vrs::quad_command((xx - x0) >> 1, (y - y0) >> 1, mask),
                        n: 1,
                    });
                }
            }
        } else {
            pg_count[usize::from(d.pg)] += n as u16;
            runs.push(Run {
                pg: d.pg,
                cmd: pixel_command(x - x0, y - y0),
                n: n as u16,
            });
        }
    });
    // The tile's counters: its mask bits in (pass, group) order.
    let mut counts = Vec::new();
    for (p, &m) in masks_t.iter().enumerate() {
        let mut bits = m;
        while bits != 0 {
            let g = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            let k = p * 32 + g;
            s.lut[k] = counts.len() as u16;
            counts.push(u32::from(s.pg_count[k]));
            s.pg_count[k] = 0;
        }
    }
    // Counting sort of the runs by counter (stable: scan order within a counter); a run's
    // pixel commands are consecutive (x in the low bits, never past the row).
    let mut next: Vec<u32> = Vec::with_capacity(counts.len());
    let mut sum = 0;
    for &n in &counts {
        next.push(sum);
        sum += n;
    }
    let mut commands = vec![0u16; sum as usize];
    for r in &s.runs {
        let slot = &mut next[usize::from(s.lut[usize::from(r.pg)])];
        let at = *slot as usize;
        for (k, c) in commands[at..at + usize::from(r.n)].iter_mut().enumerate() {
            *c = r.cmd + k as u16;
        }
        *slot += u32::from(r.n);
    }
    stats.commands = sum;
    stats.bad_indices = s.marks.finish(f, t, table, indices, cull, chunk_count);
    TileOut {
        counts,
        commands,
        stats,
    }
}

/// The frame's outputs from the tiles' (in tile order) and the mask rows.
pub(crate) fn assemble(
    f: &Frame<'_>,
    config: &ClassifyConfig,
    masks: Vec<u32>,
    tiles: Vec<TileOut>,
    cull: Vec<AtomicU8>,
) -> Classification {
    let mut mid = MidClassify::default();
    mid.counter_count = crate::classify::exclusive_scan(
        masks.iter().map(|m| m.count_ones()),
        &mut mid.counter_offsets,
    );
    let counters: usize = tiles.iter().map(|t| t.counts.len()).sum();
    let total: usize = tiles.iter().map(|t| t.commands.len()).sum();
    let mut counts = Vec::with_capacity(counters);
    let mut commands = Vec::with_capacity(total);
    let mut stats = PixelStats::default();
    for t in &tiles {
        counts.extend_from_slice(&t.counts);
        commands.extend_from_slice(&t.commands);
        stats = stats.merge(t.stats);
    }
    drop(tiles);
    mid.command_count =
        crate::classify::exclusive_scan(counts.iter().copied(), &mut mid.pixel_offsets);
    mid.vertex_cull = cull
        .into_iter()
        .map(|c| c.load(Ordering::Relaxed))
        .collect();
    mid.stats = stats;
    let mut output = ClassifyOutput {
        commands,
        final_counts: counts.clone(),
        stats: PixelStats {
            bad_indices: 0,
            ..stats
        },
        ..ClassifyOutput::default()
    };
    mid.counts = counts;
    write_waves(
        f,
        &masks,
        &mid.counter_offsets,
        &mid.pixel_offsets,
        config.wave_width,
        &mut output,
    );
    Classification { masks, mid, output }
}
