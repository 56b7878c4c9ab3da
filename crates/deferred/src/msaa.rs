//! MSAA lighting tricks from Killzone 2: the shadow filter split across samples, and the
//! edge classifier that keeps per-sample work to the pixels that need it.
//!
//! **Tap split.** KZ2 lit both samples of a 2x MSAA pixel in one shader run and split the
//! percentage-closer-filtering kernel's taps into disjoint per-sample sets: each sample
//! filters with half the taps. On interior pixels the samples' G-buffer values are equal,
//! so the pixel (the samples' average) gets the full kernel for the price of one sample's
//! share: "MSAA is almost as fast as non-MSAA". [`split_taps`] does this for 2x and 4x
//! (the counts wgpu can give: 4 is guaranteed, 2 is adapter-dependent).
//!
//! **Edge classifier.** Interior pixels have equal samples; [`classify_edges`] finds the
//! pixels whose samples differ (any G-buffer word, or depth beyond a relative tolerance,
//! since one triangle's samples have different depths), so per-sample lighting runs only
//! there; [`unique_samples`] says which samples of an edge pixel need their own lighting.

use bytemuck::{Pod, Zeroable};
use glam::Vec2;

use crate::Error;

/// Most taps a kernel may have.
pub const MAX_PCF_TAPS: usize = 64;

/// MSAA sample counts the split supports.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SampleCount {
    /// 2x (KZ2's quincunx); not guaranteed by wgpu.
    X2,
    /// 4x, guaranteed by wgpu for the G-buffer formats.
    X4,
}

impl SampleCount {
    /// Samples per pixel.
    pub const fn get(self) -> u32 {
        match self {
            SampleCount::X2 => 2,
            SampleCount::X4 => 4,
        }
    }
}

/// One tap of a split kernel, as the WGSL struct `DeferredPcfTap` (16 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct DeferredPcfTap {
    /// Offset in shadow-map texels.
    pub offset: [f32; 2],
    /// Weight within its sample's subset (a subset's weights sum to 1).
    pub weight: f32,
    /// The sample index that takes this tap.
    pub sample: u32,
}
const _: () = assert!(size_of::<DeferredPcfTap>() == 16);

/// A kernel split into per-sample subsets: taps sorted by sample, each sample's taps
/// contiguous ([`TapSplit::sample_taps`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TapSplit {
    taps: [DeferredPcfTap; MAX_PCF_TAPS],
    len: usize,
    /// `(first, count)` of each sample's taps.
    ranges: [(u32, u32); 4],
    /// Each sample's share of the kernel's total weight.
    shares: [f32; 4],
    samples: SampleCount,
}

impl TapSplit {
    /// All taps, sorted by sample (upload this as `array<DeferredPcfTap>`).
    pub fn taps(&self) -> &[DeferredPcfTap] {
        &self.taps[..self.len]
    }

    /// The taps of sample `s`.
    pub fn sample_taps(&self, s: u32) -> &[DeferredPcfTap] {
        match self.ranges.get(s as usize) {
            Some(&(first, count)) if s < self.samples.get() => {
                &self.taps[first as usize..(first + count) as usize]
            }
            _ => &[],
        }
    }

    /// `(first, count)` per sample, for a uniform buffer.
    pub fn ranges(&self) -> &[(u32, u32)] {
        &self.ranges[..self.samples.get() as usize]
    }

    /// Each sample's share of the kernel's total weight (ideally `1 / samples` each).
    pub fn shares(&self) -> &[f32] {
        &self.shares[..self.samples.get() as usize]
    }

    /// The largest deviation of a share from `1 / samples`: the pixel average of an
    /// interior pixel is the full kernel's result up to this much of the shadow's range.
    pub fn imbalance(&self) -> f32 {
        let ideal = 1.0 / self.samples.get() as f32;
        self.shares()
            .iter()
            .map(|s| (s - ideal).abs())
            .fold(0.0, f32::max)
    }
}

/// Splits a PCF kernel (`(offset in texels, weight)` pairs, weights > 0) into disjoint
/// per-sample subsets whose union is the kernel.
///
/// Taps are taken heaviest first (then in the order given); each goes to the sample with
/// the least weight so far, ties broken towards the sample whose taps are farthest from it
/// (an empty sample first). Equal-weight kernels come out balanced to one tap and
/// spatially interleaved (a square grid splits into a checkerboard for 2x), so every
/// sample's subset spans the whole kernel footprint.
pub fn split_taps(kernel: &[(Vec2, f32)], samples: SampleCount) -> Result<TapSplit, Error> {
    let n = kernel.len();
    let k = samples.get() as usize;
    if n < k || n > MAX_PCF_TAPS {
        return Err(Error::KernelSize {
            taps: n,
            min: k as u32,
            max: MAX_PCF_TAPS as u32,
        });
    }
    for (i, (o, w)) in kernel.iter().enumerate() {
        let good_weight = *w > 0.0 && w.is_finite();
        if !o.is_finite() || !good_weight {
            return Err(Error::InvalidTap { index: i as u32 });
        }
    }
    // Order: weight descending, then input order (stable).
    let mut order: [usize; MAX_PCF_TAPS] = core::array::from_fn(|i| i);
    let order = &mut order[..n];
    order.sort_unstable_by(|&a, &b| kernel[b].1.total_cmp(&kernel[a].1).then(a.cmp(&b)));
    let mut assign = [0u8; MAX_PCF_TAPS];
    let mut weight = [0f32; 4];
    let mut members: [[usize; MAX_PCF_TAPS]; 4] = [[0; MAX_PCF_TAPS]; 4];
    let mut count = [0usize; 4];
    // Two weights are "equal" within this (relative to the heaviest tap).
    let eps = kernel[order[0]].1 * 1e-4;
    for &t in order.iter() {
        let p = kernel[t].0;
        let min_w = weight[..k].iter().copied().fold(f32::INFINITY, f32::min);
        let mut best = usize::MAX;
        let mut best_dist = -1.0f32;
        for s in 0..k {
            if weight[s] > min_w + eps {
                continue;
            }
            let dist = members[s][..count[s]]
                .iter()
                .map(|&m| (kernel[m].0 - p).length_squared())
                .fold(f32::INFINITY, f32::min);
            if dist > best_dist {
                best_dist = dist;
                best = s;
            }
        }
        assign[t] = best as u8;
        members[best][count[best]] = t;
        count[best] += 1;
        weight[best] += kernel[t].1;
    }
    let total: f32 = weight[..k].iter().sum();
    let mut out = TapSplit {
        taps: [DeferredPcfTap::default(); MAX_PCF_TAPS],
        len: n,
        ranges: [(0, 0); 4],
        shares: [0.0; 4],
        samples,
    };
    let mut at = 0usize;
    for s in 0..k {
        out.ranges[s] = (at as u32, count[s] as u32);
        out.shares[s] = weight[s] / total;
        // Within a sample, keep the input order.
        for t in 0..n {
            if assign[t] as usize == s {
                out.taps[at] = DeferredPcfTap {
                    offset: kernel[t].0.into(),
                    weight: kernel[t].1 / weight[s],
                    sample: s as u32,
                };
                at += 1;
            }
        }
    }
    Ok(out)
}

/// The taps of a `size` × `size` box kernel (offsets centred on 0, equal weights): the
/// usual PCF footprint.
pub fn box_kernel(size: u32) -> impl Iterator<Item = (Vec2, f32)> {
    let c = (size as f32 - 1.0) * 0.5;
    (0..size * size).map(move |i| (Vec2::new((i % size) as f32 - c, (i / size) as f32 - c), 1.0))
}

/// Whether a pixel is an edge: some sample's G-buffer words differ from sample 0's, or its
/// depth differs from sample 0's by more than `depth_tolerance` relative
/// (`|d - d0| > tolerance · max(|d0|, |d|)`). `words` holds `samples` runs of
/// `words_per_sample`; `depth` one value per sample.
pub fn is_edge(
    words: &[u32],
    words_per_sample: usize,
    depth: &[f32],
    depth_tolerance: f32,
) -> bool {
    let samples = depth.len();
    if samples < 2 {
        return false;
    }
    let first = &words[..words_per_sample.min(words.len())];
    for s in 1..samples {
        let w = words.get(s * words_per_sample..(s + 1) * words_per_sample);
        if w != Some(first) {
            return true;
        }
        let (d0, d) = (depth[0], depth[s]);
        // NaN is an edge too, so it gets per-sample work.
        let diff = (d - d0).abs();
        if diff.is_nan() || diff > depth_tolerance * d0.abs().max(d.abs()) {
            return true;
        }
    }
    false
}

/// Which samples need their own lighting: bit `s` is set when sample `s`'s words differ
/// from every earlier sample's (sample 0 always). An interior pixel gives `0b1`.
pub fn unique_samples(words: &[u32], words_per_sample: usize, samples: u32) -> u32 {
    let mut mask = 0u32;
    let run =
        |s: u32| words.get(s as usize * words_per_sample..(s as usize + 1) * words_per_sample);
    for s in 0..samples.min(32) {
        if (0..s).all(|e| mask & (1 << e) == 0 || run(e) != run(s)) {
            mask |= 1 << s;
        }
    }
    mask
}

/// The edge pass over a whole multisampled G-buffer (the CPU twin of a compute pass that
/// appends edge pixels to a list): `words` holds, per pixel in row-major order, `samples`
/// runs of `words_per_sample` G-buffer words; `depth` per pixel `samples` depths. Edge
/// pixel indices (row-major) go to `edges` in ascending order; returns how many.
pub fn classify_edges(
    words: &[u32],
    words_per_sample: usize,
    depth: &[f32],
    samples: SampleCount,
    pixels: usize,
    depth_tolerance: f32,
    edges: &mut [u32],
) -> Result<usize, Error> {
    let k = samples.get() as usize;
    let need = |buffer, len: usize, needed: usize| {
        if len < needed {
            Err(Error::BufferTooSmall {
                buffer,
                len,
                needed,
            })
        } else {
            Ok(())
        }
    };
    need("words", words.len(), pixels * k * words_per_sample)?;
    need("depth", depth.len(), pixels * k)?;
    let mut n = 0;
    for p in 0..pixels {
        let w = &words[p * k * words_per_sample..(p + 1) * k * words_per_sample];
        if is_edge(
            w,
            words_per_sample,
            &depth[p * k..(p + 1) * k],
            depth_tolerance,
        ) {
            need("edges", edges.len(), n + 1)?;
            edges[n] = p as u32;
            n += 1;
        }
    }
    Ok(n)
}
