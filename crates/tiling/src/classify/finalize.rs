//! Phase 1, laydown finalize: per (tile, pass) a 32-bit mask of the batch groups that
//! valid pixels use. GPU twin: [`wgsl::LAYDOWN_FINALIZE`](crate::wgsl::LAYDOWN_FINALIZE).

use alloc::vec;
use alloc::vec::Vec;

use super::frame::{Frame, Schedule, sum_stats};
use super::types::{ClassifyConfig, PixelStats};
use crate::Error;
use crate::layout::VisBuffer;
use crate::plan::MicroBatchInfo;

/// Phase 1, one tile: `masks` is the tile's row of `P` masks.
fn finalize_tile(f: &Frame<'_>, t: usize, masks: &mut [u32]) -> PixelStats {
    let mut stats = PixelStats::default();
    f.for_each_pixel(t, &mut stats, |_, _, _, valid, d| {
        if valid {
            masks[usize::from(d.pg >> 5)] |= 1 << (d.pg & 31);
        }
    });
    stats
}

/// [`laydown_finalize`](crate::laydown_finalize) with its tiles run by `schedule`.
pub(crate) fn laydown_finalize_on(
    schedule: Schedule,
    vis: &VisBuffer<'_>,
    table: &[MicroBatchInfo],
    config: &ClassifyConfig,
) -> Result<(Vec<u32>, PixelStats), Error> {
    let f = Frame::new(vis, table, config)?;
    let mut masks = vec![0u32; vis.tile_count() as usize * f.passes];
    let rows = masks.chunks_mut(f.passes).collect();
    let stats = sum_stats(schedule.map(rows, || (), |(), t, row| finalize_tile(&f, t, row)));
    Ok((masks, stats))
}
