//! Multi-threaded quantise+encode and key sorting (rayon), behind the `parallel` feature.
//! Every function gives exactly the sequential result (tested), including which NaN point
//! an error names and the order of equal keys.
//!
//! ```
//! use morton::glam::Vec3;
//! use morton::Quantizer3;
//!
//! let points: Vec<Vec3> = (0..10_000).map(|i| Vec3::splat(i as f32)).collect();
//! let q = Quantizer3::from_points(&points, 10).unwrap();
//! let mut keys = vec![0u32; points.len()];
//! q.par_morton_u32_slice(&points, &mut keys).unwrap();
//! let order = morton::parallel::par_sort_permutation(&keys).unwrap();
//! assert_eq!(order, morton::sort_permutation(&keys).unwrap());
//! ```

use alloc::vec::Vec;

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use crate::sort::{Pair, check_len, histograms, offsets, sort_range, top_digit};
use crate::{Error, Path, Quantizer2, Quantizer3, SortKey, Sorter};

/// Points per rayon task in the quantise+encode functions: large enough that a task costs
/// far more than its scheduling, small enough to balance two to a few dozen threads.
pub const QUANTIZE_CHUNK: usize = 1 << 15;

/// Runs `f` over matching chunks of `points` and `out`, then reports the first error in
/// input order with its index made global, as the sequential function would.
fn par_chunks<P: Sync, C: Send>(
    points: &[P],
    out: &mut [C],
    f: impl Fn(&[P], &mut [C]) -> Result<(), Error> + Sync,
) -> Result<(), Error> {
    if points.len() != out.len() {
        return Err(Error::LengthMismatch {
            what: "out",
            expected: points.len(),
            got: out.len(),
        });
    }
    let errors: Vec<Error> = points
        .par_chunks(QUANTIZE_CHUNK)
        .zip(out.par_chunks_mut(QUANTIZE_CHUNK))
        .enumerate()
        .filter_map(|(c, (p, o))| match f(p, o) {
            Ok(()) => None,
            Err(Error::NanPosition { index }) => Some(Error::NanPosition {
                index: c * QUANTIZE_CHUNK + index,
            }),
            Err(e) => Some(e),
        })
        .collect();
    // `collect` keeps chunk order, so the first error is the lowest index.
    match errors.first() {
        Some(&e) => Err(e),
        None => Ok(()),
    }
}

impl Quantizer3 {
    /// [`Quantizer3::morton_u32_slice`] on all rayon threads.
    pub fn par_morton_u32_slice(&self, points: &[Vec3], out: &mut [u32]) -> Result<(), Error> {
        let path = Path::best();
        par_chunks(points, out, |p, o| self.morton_u32_slice_with(path, p, o))
    }

    /// [`Quantizer3::morton_u64_slice`] on all rayon threads.
    pub fn par_morton_u64_slice(&self, points: &[Vec3], out: &mut [u64]) -> Result<(), Error> {
        let path = Path::best();
        par_chunks(points, out, |p, o| self.morton_u64_slice_with(path, p, o))
    }
}

impl Quantizer2 {
    /// [`Quantizer2::morton_u32_slice`] on all rayon threads.
    pub fn par_morton_u32_slice(&self, points: &[Vec2], out: &mut [u32]) -> Result<(), Error> {
        let path = Path::best();
        par_chunks(points, out, |p, o| self.morton_u32_slice_with(path, p, o))
    }

    /// [`Quantizer2::morton_u64_slice`] on all rayon threads.
    pub fn par_morton_u64_slice(&self, points: &[Vec2], out: &mut [u64]) -> Result<(), Error> {
        let path = Path::best();
        par_chunks(points, out, |p, o| self.morton_u64_slice_with(path, p, o))
    }
}

/// Below this many keys [`par_sort_permutation`] sorts on the calling thread.
pub const PAR_SORT_MIN: usize = 1 << 16;

/// [`crate::sort_permutation`] on all rayon threads: the first split on the most
/// significant varying digit is counted and scattered by chunks in parallel (each chunk into
/// its own slots), then the 256 buckets are sorted in parallel. A stable sort's result is
/// unique, so it equals the sequential one (tested).
pub fn par_sort_permutation<K: SortKey>(keys: &[K]) -> Result<Vec<u32>, Error> {
    let mut out = Vec::new();
    Sorter::new().par_sort_permutation_into(keys, &mut out)?;
    Ok(out)
}

impl<K: SortKey> Sorter<K> {
    /// [`par_sort_permutation`] into `out` (cleared first) with this sorter's buffers.
    pub fn par_sort_permutation_into(
        &mut self,
        keys: &[K],
        out: &mut Vec<u32>,
    ) -> Result<(), Error> {
        check_len(keys.len())?;
        if keys.len() < PAR_SORT_MIN {
            return self.sort_permutation_into(keys, out);
        }
        par_sort(keys, &mut self.a, &mut self.b, out);
        Ok(())
    }
}

fn par_sort<K: SortKey>(
    keys: &[K],
    a: &mut Vec<K::Pair>,
    b: &mut Vec<K::Pair>,
    out: &mut Vec<u32>,
) {
    let n = keys.len();
    let threads = rayon::current_num_threads().max(1);
    // A few chunks per thread so an uneven machine still balances.
    let chunk = n.div_ceil(threads * 4).max(4096);

    // Which digits vary: one parallel pass of full histograms.
    let total = keys.par_chunks(chunk).map(histograms).reduce(
        || [[0u32; 256]; 8],
        |mut a, b| {
            for (ad, bd) in a.iter_mut().zip(&b) {
                for (x, y) in ad.iter_mut().zip(bd) {
                    *x += y;
                }
            }
            a
        },
    );
    out.clear();
    let Some(top) = top_digit::<K>(&total, n) else {
        out.extend(0..n as u32);
        return;
    };

    // Per-chunk counts of the top digit, then each chunk scatters its pairs into its own
    // slots (chunk `c`'s slots for digit `v` follow every earlier chunk's).
    let counts: Vec<[u32; 256]> = keys
        .par_chunks(chunk)
        .map(|c| {
            let mut h = [0u32; 256];
            for &k in c {
                h[k.pair(0).digit(top)] += 1;
            }
            h
        })
        .collect();
    let mut starts: Vec<[u32; 256]> = Vec::with_capacity(counts.len());
    let mut running = offsets(&total[top as usize]);
    for h in &counts {
        starts.push(running);
        for (r, &c) in running.iter_mut().zip(h) {
            *r += c;
        }
    }
    a.resize(n, K::Pair::default());
    b.resize(n, K::Pair::default());
    out.resize(n, 0);
    let dst = Out(a.as_mut_ptr());
    keys.par_chunks(chunk)
        .zip(starts.into_par_iter())
        .enumerate()
        .for_each(|(c, (ks, mut o))| {
            let base = c * chunk;
            for (i, &k) in ks.iter().enumerate() {
                let p = k.pair((base + i) as u32);
                let digit = p.digit(top);
                let slot = o[digit] as usize;
                debug_assert!(slot < n);
                // SAFETY: `slot` lies in this chunk's own range for `digit` (the exclusive
                // prefix over all smaller digits and over earlier chunks' counts of this
                // digit, plus this chunk's running count), which is inside `a` (the counts
                // sum to `n`) and written by no other task.
                unsafe { dst.get().add(slot).write(p) };
                o[digit] += 1;
            }
        });

    // Sort the buckets below the top digit, in parallel over disjoint ranges, each writing
    // its indices into its own range of the output.
    let mut ranges = Vec::with_capacity(256);
    let (mut ra, mut rb, mut rp) = (&mut a[..n], &mut b[..n], &mut out[..n]);
    for &len in total[top as usize].iter() {
        let (ha, ta) = core::mem::take(&mut ra).split_at_mut(len as usize);
        let (hb, tb) = core::mem::take(&mut rb).split_at_mut(len as usize);
        let (hp, tp) = core::mem::take(&mut rp).split_at_mut(len as usize);
        if len > 0 {
            ranges.push((ha, hb, hp));
        }
        (ra, rb, rp) = (ta, tb, tp);
    }
    // Largest buckets first, for balance.
    ranges.sort_by_key(|(x, _, _)| core::cmp::Reverse(x.len()));
    ranges.into_par_iter().for_each(|(x, y, out)| {
        let in_b = x.len() > 1 && top > 0 && sort_range(x, y, top - 1);
        let src: &[K::Pair] = if in_b { y } else { x };
        for (o, p) in out.iter_mut().zip(src) {
            *o = p.index();
        }
    });
}

/// A raw output pointer shared by the scatter tasks, each writing only its own slots.
struct Out<P>(*mut P);

impl<P> Clone for Out<P> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<P> Copy for Out<P> {}

// SAFETY: the tasks write disjoint slots (per-chunk, per-digit ranges computed from exact
// counts), and the buffer outlives the parallel loop; `P` is `Send`.
unsafe impl<P: Send> Send for Out<P> {}
// SAFETY: as above.
unsafe impl<P: Send> Sync for Out<P> {}

impl<P> Out<P> {
    /// The pointer (a method, so closures capture the whole `Sync` wrapper).
    fn get(self) -> *mut P {
        self.0
    }
}
