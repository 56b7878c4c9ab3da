//! Phase 2, mid classify: the compact counter offsets (the masks' popcounts, prefix
//! summed), each counter's command count, the vertex cull buffer and the pixel-command
//! offsets (the counts, prefix summed). GPU twin:
//! [`wgsl::MID_CLASSIFY`](crate::wgsl::MID_CLASSIFY).

use alloc::vec;

use super::frame::{
    CounterLut, Frame, Schedule, TileCounters, check_masks, exclusive_scan, split_at_starts,
    sum_stats, tile_counter_ranges,
};
use super::marks::{CullBuffer, TileMarks};
use super::types::{ClassifyConfig, MidClassify, PixelStats};
use crate::Error;
use crate::layout::VisBuffer;
use crate::plan::MicroBatchInfo;

/// Phase 2, one tile: counts into `counts_t` (the tile's counters, looked up in
/// `counters`) and marks the tile's triangles in `cull`.
fn count_tile(
    f: &Frame<'_>,
    t: usize,
    counters: TileCounters<'_>,
    counts_t: &mut [u32],
    cull: &CullBuffer<'_>,
    marks: &mut TileMarks,
) -> PixelStats {
    marks.begin();
    let mut stats = PixelStats::default();
    let mut dropped = 0u32;
    let mut commands = 0u32;
    f.for_each_pixel(t, &mut stats, |x, y, word, valid, d| {
        marks.add(word, &d, valid && f.vertex_cull);
        if !valid || f.sample(x, y, word).is_none() {
            return;
        }
        match counters.get(d.pg) {
            Some(c) => {
                counts_t[c] += 1;
                commands += 1;
            }
            None => dropped += 1,
        }
    });
    stats.commands = commands;
    stats.dropped = dropped;
    stats.bad_indices = marks.finish(f, t, cull);
    stats
}

/// [`mid_classify`](crate::mid_classify) with its tiles run by `schedule`.
pub(crate) fn mid_classify_on(
    schedule: Schedule,
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
    let cull = CullBuffer::new(table, indices, config.chunk_count);
    let offsets = &mid.counter_offsets;
    let stats = sum_stats(schedule.map(
        split_at_starts(&mut counts, &ranges),
        || (CounterLut::new(), TileMarks::new()),
        |(lut, marks), t, counts_t| {
            let counters = lut.fill(&masks[f.row(t)], &offsets[f.row(t)]);
            count_tile(&f, t, counters, counts_t, &cull, marks)
        },
    ));
    mid.command_count = exclusive_scan(counts.iter().copied(), &mut mid.pixel_offsets);
    mid.counts = counts;
    mid.vertex_cull = cull.into_bytes();
    mid.stats = stats;
    Ok(mid)
}
