//! [`classify`](crate::classify()) as one pass per tile: the three phases' outputs computed
//! from a single scan of each tile (its words stay in cache), then the prefix sums and the
//! wave commands. The outputs are those of running [`laydown_finalize`],
//! [`mid_classify`] and [`classify_output`] in turn with one validity (the tests check it);
//! the phase functions remain the pass-shaped twins of the GPU passes.
//!
//! Per tile: the scan decodes every pixel without branches (invalid pixels get a trash
//! (pass, group) and are written but not kept), records each triangle once for the vertex
//! cull buffer, and keeps each command with its (pass, group). The counts per (pass,
//! group) give the masks (every (pass, group) with a valid pixel in the tile has a sample
//! in it); the tile's counters are the set bits of its masks in (pass, group) order, so a
//! counting sort by counter puts the tile's commands in their final order, and because the
//! layout is tile-major the tiles' counts and commands concatenate into the frame's.
//!
//! [`laydown_finalize`]: crate::laydown_finalize
//! [`mid_classify`]: crate::mid_classify
//! [`classify_output`]: crate::classify_output

use alloc::vec;
use alloc::vec::Vec;

use visbuf::VisLayout;

use super::frame::{Frame, Schedule, exclusive_scan, split_at_starts};
use super::marks::{CullBuffer, TileMarks};
use super::output::write_waves;
use super::types::{Classification, ClassifyConfig, ClassifyOutput, MidClassify, PixelStats};
use crate::Error;
use crate::decode::{KIND_VALID, PG_SLOTS};
use crate::layout::{TILE_SIZE, VisBuffer, pixel_command};
use crate::plan::MicroBatchInfo;
use crate::vrs;

/// Per-thread scratch, reused from tile to tile.
struct Scratch {
    /// Per `pass * 32 + group` (and the trash slot): commands counted in this tile (reset
    /// after each tile; a tile has at most 16 384).
    pg_count: Vec<u16>,
    /// Per `pass * 32 + group`: the tile-local counter (valid for the tile's mask bits).
    lut: Vec<u16>,
    /// The tile's commands in scan order and their `pass * 32 + group`: room for one per
    /// pixel, the first `n` are kept.
    cmd: Vec<u16>,
    pg: Vec<u16>,
    /// The tile's triangles, marked in the cull buffer after the scan.
    marks: TileMarks,
}

impl Scratch {
    fn new() -> Self {
        let pixels = (TILE_SIZE * TILE_SIZE) as usize;
        Self {
            pg_count: vec![0; PG_SLOTS],
            lut: vec![0; PG_SLOTS],
            cmd: vec![0; pixels + 1],
            pg: vec![0; pixels + 1],
            marks: TileMarks::new(),
        }
    }
}

/// One tile's share of the frame's outputs.
struct TileOut {
    counts: Vec<u32>,
    commands: Vec<u16>,
    stats: PixelStats,
}

/// Scans tile `t`: fills its mask row `masks_t`, marks `cull`, returns its counters'
/// counts and its commands in final order.
fn tile(
    f: &Frame<'_>,
    t: usize,
    cull: &CullBuffer<'_>,
    masks_t: &mut [u32],
    s: &mut Scratch,
) -> TileOut {
    let (x0, y0, _, _) = f.tile_rect(t);
    let mut stats = PixelStats::default();
    s.marks.begin();
    let mut n = 0usize;
    let last = s.cmd.len() - 1;
    let Scratch {
        pg_count,
        cmd,
        pg,
        marks,
        ..
    } = s;
    if f.vis.layout() == VisLayout::Vrs {
        f.for_each_pixel(t, &mut stats, |x, y, word, valid, d| {
            marks.add(word, &d, valid && f.vertex_cull);
            if !valid {
                return;
            }
            if let Some(mask) = vrs::sample_mask(&f.vis, x, y, word) {
                cmd[n] = vrs::quad_command((x - x0) >> 1, (y - y0) >> 1, mask);
                pg[n] = d.pg;
                n += 1;
            }
        });
    } else {
        // Without branches: every pixel's command is written, valid ones are kept. The
        // loop is written out (not through a closure) so it stays one tight body.
        let (_, _, x1, y1) = f.tile_rect(t);
        let w = f.vis.width() as usize;
        let mask = f.vis.validity();
        let mut kinds = [0u32; 4];
        for y in y0..y1 {
            let row = y as usize * w + x0 as usize;
            let words = &f.vis.words()[row..row + (x1 - x0) as usize];
            for (i, &word) in words.iter().enumerate() {
                let bit = match mask {
                    None => true,
                    Some(m) => (m[(row + i) >> 5] >> ((row + i) & 31)) & 1 == 1,
                };
                let (k, d) = f.dec.classify(word, bit);
                kinds[(k & 3) as usize] += 1;
                let valid = k == KIND_VALID;
                marks.add(word, &d, valid && f.vertex_cull);
                let at = n.min(last);
                cmd[at] = pixel_command(i as u32, y - y0);
                pg[at] = d.pg;
                n += usize::from(valid);
            }
        }
        stats.empty += kinds[0];
        stats.unknown += kinds[1];
        stats.out_of_range += kinds[2];
        stats.valid += kinds[3];
    }
    // Counts per (pass, group), then the masks from them (every (pass, group) with a
    // valid pixel in the tile has a sample in it, so these are the laydown-finalise masks
    // too). No branch per command.
    for &k in &pg[..n] {
        pg_count[usize::from(k)] += 1;
    }
    for (p, m) in masks_t.iter_mut().enumerate() {
        let row = &pg_count[p * 32..p * 32 + 32];
        let mut bits = 0u32;
        for (g, &c) in row.iter().enumerate() {
            bits |= u32::from(c != 0) << g;
        }
        *m = bits;
    }
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
        }
    }
    s.pg_count.fill(0);
    // Counting sort of the commands by counter (stable: scan order within a counter).
    let mut next: Vec<u32> = Vec::with_capacity(counts.len());
    let mut sum = 0;
    for &c in &counts {
        next.push(sum);
        sum += c;
    }
    let mut commands = vec![0u16; n];
    for (&c, &k) in s.cmd[..n].iter().zip(&s.pg[..n]) {
        let slot = &mut next[usize::from(s.lut[usize::from(k)])];
        commands[*slot as usize] = c;
        *slot += 1;
    }
    stats.commands = n as u32;
    stats.bad_indices = s.marks.finish(f, t, cull);
    TileOut {
        counts,
        commands,
        stats,
    }
}

/// The frame's outputs from the tiles' (in tile order) and the mask rows, the tiles'
/// commands copied into their places by `schedule`.
fn assemble(
    schedule: Schedule,
    f: &Frame<'_>,
    config: &ClassifyConfig,
    masks: Vec<u32>,
    tiles: Vec<TileOut>,
    cull: CullBuffer<'_>,
) -> Classification {
    let mut mid = MidClassify::default();
    mid.counter_count = exclusive_scan(
        masks.iter().map(|m| m.count_ones()),
        &mut mid.counter_offsets,
    );
    let counters: usize = tiles.iter().map(|t| t.counts.len()).sum();
    let mut counts = Vec::with_capacity(counters);
    let mut stats = PixelStats::default();
    let mut ranges = Vec::with_capacity(tiles.len());
    let mut at = 0;
    for t in &tiles {
        counts.extend_from_slice(&t.counts);
        stats = stats.merge(t.stats);
        ranges.push((at, at + t.commands.len()));
        at += t.commands.len();
    }
    let mut commands = vec![0u16; at];
    let pieces = split_at_starts(&mut commands, &ranges)
        .into_iter()
        .zip(&tiles)
        .collect();
    schedule.map(
        pieces,
        || (),
        |(), _, (out, t)| out.copy_from_slice(&t.commands),
    );
    drop(tiles);
    mid.command_count = exclusive_scan(counts.iter().copied(), &mut mid.pixel_offsets);
    mid.vertex_cull = cull.into_bytes();
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
    write_waves(f, &masks, &mid, config.wave_width, &mut output);
    Classification { masks, mid, output }
}

/// [`classify`](crate::classify()) with its tiles run by `schedule`.
pub(crate) fn classify_on(
    schedule: Schedule,
    vis: &VisBuffer<'_>,
    table: &[MicroBatchInfo],
    indices: &[u32],
    config: &ClassifyConfig,
) -> Result<Classification, Error> {
    let f = Frame::new(vis, table, config)?;
    let mut masks = vec![0u32; vis.tile_count() as usize * f.passes];
    let cull = CullBuffer::new(table, indices, config.chunk_count);
    let rows = masks.chunks_mut(f.passes).collect();
    let tiles = schedule.map(rows, Scratch::new, |s, t, m| tile(&f, t, &cull, m, s));
    Ok(assemble(schedule, &f, config, masks, tiles, cull))
}
