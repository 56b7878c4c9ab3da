//! Phase 3, classify output: the 16-bit pixel (or quad) commands in each counter's
//! range, the final counts, the wave commands (each counter rounded up to whole waves)
//! and one indirect dispatch per pass; and the canonical order that makes the GPU's
//! atomically appended commands comparable. GPU twin:
//! [`wgsl::CLASSIFY_OUTPUT`](crate::wgsl::CLASSIFY_OUTPUT).

use alloc::vec;
use alloc::vec::Vec;

use visbuf::VisLayout;
use wave::WaveWidth;

use super::frame::{
    CounterLut, Frame, Ranges, Schedule, TileCounters, split_at_starts, sum_stats,
    tile_counter_ranges,
};
use super::types::{
    ClassifyConfig, ClassifyOutput, MidClassify, PixelStats, WAVE_GROUP_SHIFT, WAVE_TILE_Y_SHIFT,
    WaveCommand,
};
use crate::Error;
use crate::layout::{PassDispatch, VisBuffer, pixel_command};
use crate::plan::MicroBatchInfo;
use crate::vrs;

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

/// Checks that `mid` belongs to `masks` and returns each tile's counter range and command
/// range.
fn check_mid(f: &Frame<'_>, masks: &[u32], mid: &MidClassify) -> Result<(Ranges, Ranges), Error> {
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
/// first command) and final counts (`finals_t`), its counters looked up in `counters`.
fn output_tile(
    f: &Frame<'_>,
    t: usize,
    counters: TileCounters<'_>,
    counts_t: &[u32],
    pixel_offsets_t: &[u32],
    commands_t: &mut [u16],
    finals_t: &mut [u32],
) -> PixelStats {
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
        let Some(c) = counters.get(d.pg) else {
            dropped += 1;
            return;
        };
        let k = finals_t[c];
        if k >= counts_t[c] {
            dropped += 1;
            return;
        }
        let cmd = match f.vis.layout() {
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

/// The wave commands and pass dispatches from `out`'s final counts and `mid`'s offsets (sequential: one entry per
/// (tile, pass), cheap next to the pixels).
pub(crate) fn write_waves(
    f: &Frame<'_>,
    masks: &[u32],
    mid: &MidClassify,
    wave_width: WaveWidth,
    out: &mut ClassifyOutput,
) {
    let (counter_offsets, pixel_offsets) = (&mid.counter_offsets, &mid.pixel_offsets);
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

/// [`classify_output`](crate::classify_output) with its tiles run by `schedule`.
pub(crate) fn classify_output_on(
    schedule: Schedule,
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
    let pieces = split_at_starts(&mut commands, &cmd_ranges)
        .into_iter()
        .zip(split_at_starts(&mut finals, &ranges))
        .collect();
    let stats =
        sum_stats(
            schedule.map(pieces, CounterLut::new, |lut, t, (commands_t, finals_t)| {
                let (a, b) = ranges[t];
                let counters = lut.fill(&masks[f.row(t)], &mid.counter_offsets[f.row(t)]);
                output_tile(
                    &f,
                    t,
                    counters,
                    &mid.counts[a..b],
                    &mid.pixel_offsets[a..b],
                    commands_t,
                    finals_t,
                )
            }),
        );
    let mut out = ClassifyOutput {
        commands,
        final_counts: finals,
        stats,
        ..ClassifyOutput::default()
    };
    write_waves(&f, masks, mid, config.wave_width, &mut out);
    Ok(out)
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
