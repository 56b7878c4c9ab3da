//! The talk's closing measurements, computed from a vis buffer (seed 000, the "Pixel Work
//! Reduction" and "Vertex Work Reduction" tables).
//!
//! - **Pixel-shading waves with depth equal** (HZD's method): the hardware shades 2x2
//!   quads per primitive, helper lanes included, and packs a draw's quads into waves. For
//!   each draw (source batch) count the distinct (2x2 quad, primitive instance) pairs over
//!   the valid pixels, times 4 lanes, rounded up to whole waves; sum over draws.
//! - **Pixel-shading waves with deferred texturing**: the wave commands of the
//!   classification, and the fraction of their lanes left unfilled.
//! - **Vertices in the scene** (every micro batch's instances x vertices) against
//!   **vertices after chunk culling** (those in visible 64-vertex chunks).
//!
//! The talk measured 40% / 25% of the depth-equal pixel waves and 32% / 55% of the
//! vertices on its forest and tall-grass scenes at 4K.

use alloc::collections::BTreeMap;
use alloc::vec;

use visbuf::{VIS_RATE_SHIFT, VisLayout};
use wave::WaveWidth;

use crate::classify::{Classification, ClassifyConfig, Frame, VisBuffer};
use crate::decode::Px;
use crate::plan::MicroBatchInfo;
use crate::vertex::{VertexWaves, chunk_vertices};
use crate::{Error, PixelStats};

/// The talk's figures for one frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TalkMeasurements {
    /// Lanes per wave the figures assume.
    pub wave_width: u32,
    /// Pixel-shading waves of the depth-equal geometry pass.
    pub depth_equal_waves: u64,
    /// Distinct (quad, primitive instance) pairs the depth-equal pass shades.
    pub depth_equal_quads: u64,
    /// Pixel-shading waves with deferred texturing (wave commands).
    pub deferred_waves: u64,
    /// Valid pixels (covered by vis-buffer geometry).
    pub covered_pixels: u64,
    /// Shading samples (pixel commands; fewer than pixels with VRS).
    pub shaded_samples: u64,
    /// Vertices of all micro batches.
    pub scene_vertices: u64,
    /// Vertices in visible chunks.
    pub visible_vertices: u64,
}

impl TalkMeasurements {
    /// Deferred-texturing waves over depth-equal waves (the talk: 0.40 forest, 0.25 grass).
    #[must_use]
    pub fn pixel_wave_ratio(&self) -> f64 {
        ratio(self.deferred_waves, self.depth_equal_waves)
    }

    /// Lanes of the deferred-texturing waves that shade nothing.
    #[must_use]
    pub fn unfilled_lane_fraction(&self) -> f64 {
        let lanes = self.deferred_waves * u64::from(self.wave_width);
        if lanes == 0 {
            return 0.0;
        }
        1.0 - self.shaded_samples as f64 / lanes as f64
    }

    /// Visible over scene vertices (the talk: 0.32 forest, 0.55 grass).
    #[must_use]
    pub fn vertex_ratio(&self) -> f64 {
        ratio(self.visible_vertices, self.scene_vertices)
    }

    /// Shaded samples over covered pixels (1 without VRS).
    #[must_use]
    pub fn sample_ratio(&self) -> f64 {
        ratio(self.shaded_samples, self.covered_pixels)
    }
}

fn ratio(a: u64, b: u64) -> f64 {
    if b == 0 { 0.0 } else { a as f64 / b as f64 }
}

/// Depth-equal pixel waves: per draw (source batch of the row), `ceil(4 * quads / width)`
/// where `quads` counts the distinct (2x2 quad, word) pairs of its valid pixels (the word
/// with its shading-rate bits cleared names the primitive instance). Returns
/// `(waves, quads)`.
pub fn depth_equal_waves(
    vis: &VisBuffer<'_>,
    table: &[MicroBatchInfo],
    config: &ClassifyConfig,
) -> Result<(u64, u64), Error> {
    let f = Frame::new(vis, table, config)?;
    let (w, h) = (vis.width(), vis.height());
    let words = vis.words();
    let rate_mask = match vis.layout() {
        VisLayout::Standard => u32::MAX,
        VisLayout::Vrs => (1 << VIS_RATE_SHIFT) - 1,
    };
    // Quads per micro-batch ID, then per batch.
    let mut per_id = vec![0u64; table.len().min(vis.layout().micro_batch_ids() as usize)];
    for qy in 0..h.div_ceil(2) {
        for qx in 0..w.div_ceil(2) {
            let mut seen = [0u32; 4];
            let mut n = 0;
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let (x, y) = (2 * qx + dx, 2 * qy + dy);
                if x >= w || y >= h {
                    continue;
                }
                let i = (y * w + x) as usize;
                let Px::Valid(d) = f.dec.decode(words[i], vis.mask_bit(i)) else {
                    continue;
                };
                let key = words[i] & rate_mask;
                if !seen[..n].contains(&key) {
                    seen[n] = key;
                    n += 1;
                    per_id[d.mb as usize] += 1;
                }
            }
        }
    }
    let mut per_batch: BTreeMap<u32, u64> = BTreeMap::new();
    for (id, &q) in per_id.iter().enumerate() {
        if q > 0 {
            *per_batch.entry(table[id].batch).or_default() += q;
        }
    }
    let lanes = u64::from(config.wave_width.lanes());
    let waves = per_batch.values().map(|&q| (4 * q).div_ceil(lanes)).sum();
    let quads = per_batch.values().sum();
    Ok((waves, quads))
}

/// Every figure of the talk's tables for one frame, from its classification and vertex
/// waves.
pub fn measure(
    vis: &VisBuffer<'_>,
    table: &[MicroBatchInfo],
    config: &ClassifyConfig,
    classification: &Classification,
    vertex: &VertexWaves,
) -> Result<TalkMeasurements, Error> {
    let (depth_equal_waves, depth_equal_quads) = depth_equal_waves(vis, table, config)?;
    let stats: PixelStats = classification.output.stats;
    let scene_vertices = table
        .iter()
        .enumerate()
        .filter(|(id, r)| r.first_id as usize == *id)
        .map(|(_, r)| r.total_vertices())
        .sum();
    let visible_vertices = vertex
        .commands
        .iter()
        .map(|c| {
            table
                .get(c.micro_batch as usize)
                .map_or(0, |r| u64::from(chunk_vertices(r, c.chunk)))
        })
        .sum();
    Ok(TalkMeasurements {
        wave_width: WaveWidth::lanes(config.wave_width),
        depth_equal_waves,
        depth_equal_quads,
        deferred_waves: classification.output.waves.len() as u64,
        covered_pixels: stats.valid.into(),
        shaded_samples: stats.commands.into(),
        scene_vertices,
        visible_vertices,
    })
}
