//! What every tile kernel of the classification shares: the frame it reads ([`Frame`]:
//! the vis buffer, the decoder, the per-pixel scan), how a phase runs its tiles
//! ([`Schedule`]: one after another, or on rayon's threads), the per-tile counter lookup
//! and the checks and prefix sums between the phases.

use alloc::vec;
use alloc::vec::Vec;
use core::ops::Range;

use visbuf::VisLayout;

use super::types::{ClassifyConfig, PixelStats};
use crate::Error;
use crate::decode::{Decoded, Decoder, KIND_VALID};
use crate::layout::{TILE_SIZE, VisBuffer, first_of_run};
use crate::plan::{MAX_BATCH_GROUPS_PER_PASS, MAX_PASSES, MicroBatchInfo};
use crate::vrs;

/// How a phase runs its tiles: tile `t` is one call `work(scratch, t, items[t])`, with a
/// scratch made by `init` (one per worker, reused from tile to tile: it never carries a
/// result from one tile to the next); the results come back in tile order. Every phase
/// has one body for both schedules, so the serial and the parallel results are equal by
/// construction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Schedule {
    /// One tile after another on the calling thread, with one scratch.
    Serial,
    /// The tiles on rayon's threads, a scratch per worker.
    #[cfg(feature = "parallel")]
    Threads,
}

impl Schedule {
    /// `work` over `items`, in tile order.
    pub fn map<I: Send, S, R: Send>(
        self,
        items: Vec<I>,
        init: impl Fn() -> S + Sync + Send,
        work: impl Fn(&mut S, usize, I) -> R + Sync + Send,
    ) -> Vec<R> {
        match self {
            Self::Serial => {
                let mut scratch = init();
                items
                    .into_iter()
                    .enumerate()
                    .map(|(t, item)| work(&mut scratch, t, item))
                    .collect()
            }
            #[cfg(feature = "parallel")]
            Self::Threads => {
                use rayon::prelude::*;
                items
                    .into_par_iter()
                    .enumerate()
                    .map_init(init, |scratch, (t, item)| work(scratch, t, item))
                    .collect()
            }
        }
    }
}

/// The field-wise sum of the tiles' stats.
pub(crate) fn sum_stats(stats: impl IntoIterator<Item = PixelStats>) -> PixelStats {
    stats
        .into_iter()
        .fold(PixelStats::default(), PixelStats::merge)
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
            dec: Decoder::new(table, config.pass_count, vis.layout()),
            passes: config.pass_count as usize,
            vertex_cull: config.vertex_cull,
        })
    }

    /// Tile `t`'s row of the per-(tile, pass) buffers (masks, counter offsets):
    /// `t * P..(t + 1) * P`.
    #[inline]
    pub fn row(&self, t: usize) -> Range<usize> {
        t * self.passes..(t + 1) * self.passes
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
            (x0 + TILE_SIZE).min(self.vis.width()),
            (y0 + TILE_SIZE).min(self.vis.height()),
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
        let w = self.vis.width() as usize;
        let mut kinds = [0u32; 4];
        for y in y0..y1 {
            let row = y as usize * w + x0 as usize;
            let words = &self.vis.words()[row..row + (x1 - x0) as usize];
            match self.vis.validity() {
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
        if self.vis.layout() == VisLayout::Standard {
            return Some(1);
        }
        vrs::sample_mask(&self.vis, x, y, word)
    }
}

/// Checks the masks' length.
pub(crate) fn check_masks(f: &Frame<'_>, masks: &[u32]) -> Result<(), Error> {
    let n = u64::from(f.vis.tile_count()) * f.passes as u64;
    Error::check_len("batch-group masks", n, masks.len())
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

    /// Fills the entries of one tile from its row of masks and of counter offsets;
    /// returns the tile's lookup.
    pub fn fill<'s>(&'s mut self, masks_t: &'s [u32], offsets_t: &[u32]) -> TileCounters<'s> {
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
        TileCounters {
            masks_t,
            lut: &self.lut,
        }
    }
}

/// One tile's filled [`CounterLut`] with the tile's row of masks.
#[derive(Clone, Copy)]
pub(crate) struct TileCounters<'s> {
    masks_t: &'s [u32],
    lut: &'s [u32],
}

impl TileCounters<'_> {
    /// The tile-relative counter of `(pass, group)`, or `None` if the mask lacks it.
    #[inline(always)]
    pub fn get(&self, pg: u16) -> Option<usize> {
        let p = usize::from(pg >> 5);
        if (self.masks_t[p] >> (pg & 31)) & 1 == 0 {
            return None;
        }
        Some(self.lut[usize::from(pg)] as usize)
    }
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
