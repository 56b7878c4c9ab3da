//! Multi-threaded quantise+encode and key sorting (rayon), behind the `parallel` feature.
//! Every function gives exactly the sequential result (tested), including which NaN point
//! an error names and the order of equal keys.
//!
//! ```
//! use glam::Vec3;
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

use crate::sort::{check_len, offsets, trivial};
use crate::{MortonError, Path, Quantizer2, Quantizer3, SortKey};

/// Points per rayon task in the quantise+encode functions: large enough that a task costs
/// far more than its scheduling, small enough to balance two to a few dozen threads.
pub const QUANTIZE_CHUNK: usize = 1 << 15;

/// Runs `f` over matching chunks of `points` and `out`, then reports the first error in
/// input order with its index made global, as the sequential function would.
fn par_chunks<P: Sync, C: Send>(
    points: &[P],
    out: &mut [C],
    f: impl Fn(&[P], &mut [C]) -> Result<(), MortonError> + Sync,
) -> Result<(), MortonError> {
    if points.len() != out.len() {
        return Err(MortonError::LengthMismatch {
            what: "out",
            expected: points.len(),
            got: out.len(),
        });
    }
    let errors: Vec<MortonError> = points
        .par_chunks(QUANTIZE_CHUNK)
        .zip(out.par_chunks_mut(QUANTIZE_CHUNK))
        .enumerate()
        .filter_map(|(c, (p, o))| match f(p, o) {
            Ok(()) => None,
            Err(MortonError::NanPosition { index }) => Some(MortonError::NanPosition {
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
    pub fn par_morton_u32_slice(
        &self,
        points: &[Vec3],
        out: &mut [u32],
    ) -> Result<(), MortonError> {
        let path = Path::best();
        par_chunks(points, out, |p, o| self.morton_u32_slice_with(path, p, o))
    }

    /// [`Quantizer3::morton_u64_slice`] on all rayon threads.
    pub fn par_morton_u64_slice(
        &self,
        points: &[Vec3],
        out: &mut [u64],
    ) -> Result<(), MortonError> {
        let path = Path::best();
        par_chunks(points, out, |p, o| self.morton_u64_slice_with(path, p, o))
    }
}

impl Quantizer2 {
    /// [`Quantizer2::morton_u32_slice`] on all rayon threads.
    pub fn par_morton_u32_slice(
        &self,
        points: &[Vec2],
        out: &mut [u32],
    ) -> Result<(), MortonError> {
        let path = Path::best();
        par_chunks(points, out, |p, o| self.morton_u32_slice_with(path, p, o))
    }

    /// [`Quantizer2::morton_u64_slice`] on all rayon threads.
    pub fn par_morton_u64_slice(
        &self,
        points: &[Vec2],
        out: &mut [u64],
    ) -> Result<(), MortonError> {
        let path = Path::best();
        par_chunks(points, out, |p, o| self.morton_u64_slice_with(path, p, o))
    }
}

/// Below this many keys [`par_sort_permutation`] sorts on the calling thread.
pub const PAR_SORT_MIN: usize = 1 << 16;

/// [`crate::sort_permutation`] on all rayon threads: the same stable LSD radix sort, with
/// per-thread digit counts and scatters into disjoint ranges, so the result is identical.
pub fn par_sort_permutation<K: SortKey>(keys: &[K]) -> Result<Vec<u32>, MortonError> {
    check_len(keys.len())?;
    if keys.len() < PAR_SORT_MIN {
        return crate::sort_permutation(keys);
    }
    let n = keys.len();
    let threads = rayon::current_num_threads().max(1);
    // A few chunks per thread so an uneven machine still balances.
    let chunk = n.div_ceil(threads * 4).max(4096);

    // Which digits vary at all: one parallel pass of full histograms.
    let total = keys
        .par_chunks(chunk)
        .map(|c| {
            let mut h = [[0u32; 256]; 8];
            for &k in c {
                let k = k.to_u64();
                for (d, hd) in h.iter_mut().enumerate().take(K::BYTES) {
                    hd[((k >> (8 * d)) & 0xff) as usize] += 1;
                }
            }
            h
        })
        .reduce(
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
    let passes: Vec<u32> = (0..K::BYTES as u32)
        .filter(|&d| !trivial(&total[d as usize], n))
        .collect();
    if passes.is_empty() {
        return Ok((0..n as u32).collect());
    }

    // Pairs as (key, index), 16 bytes; the sort moves them between two buffers.
    let mut a: Vec<(u64, u32)> = keys
        .par_iter()
        .enumerate()
        .map(|(i, &k)| (k.to_u64(), i as u32))
        .collect();
    let mut b: Vec<(u64, u32)> = alloc::vec![(0, 0); n];
    for &d in &passes {
        scatter_pass(&a, &mut b, chunk, 8 * d, &total[d as usize]);
        core::mem::swap(&mut a, &mut b);
    }
    Ok(a.par_iter().map(|&(_, i)| i).collect())
}

/// A raw output pointer shared by the scatter tasks, each writing only its own slots.
#[derive(Clone, Copy)]
struct Out(*mut (u64, u32));
// SAFETY: the tasks write disjoint slots (per-chunk, per-digit ranges computed from exact
// counts), and the buffer outlives the parallel scope.
unsafe impl Send for Out {}
// SAFETY: as above.
unsafe impl Sync for Out {}

impl Out {
    /// The pointer (a method, so closures capture the whole `Sync` wrapper).
    fn get(self) -> *mut (u64, u32) {
        self.0
    }
}

/// One stable counting-sort pass on the digit at `shift`: per-chunk counts, then each chunk
/// scatters into its own ranges (chunk `c`'s slots for digit `v` follow those of every
/// earlier chunk's digit `v`).
fn scatter_pass(
    src: &[(u64, u32)],
    dst: &mut [(u64, u32)],
    chunk: usize,
    shift: u32,
    total: &[u32; 256],
) {
    let counts: Vec<[u32; 256]> = src
        .par_chunks(chunk)
        .map(|c| {
            let mut h = [0u32; 256];
            for &(k, _) in c {
                h[((k >> shift) & 0xff) as usize] += 1;
            }
            h
        })
        .collect();
    let mut starts: Vec<[u32; 256]> = Vec::with_capacity(counts.len());
    let mut running = offsets(total);
    for h in &counts {
        starts.push(running);
        for (r, &c) in running.iter_mut().zip(h) {
            *r += c;
        }
    }
    let out = Out(dst.as_mut_ptr());
    let len = dst.len();
    src.par_chunks(chunk)
        .zip(starts.into_par_iter())
        .for_each(|(c, mut o)| {
            for &e in c {
                let digit = ((e.0 >> shift) & 0xff) as usize;
                let slot = o[digit] as usize;
                debug_assert!(slot < len);
                // SAFETY: `slot` lies in this chunk's own range for `digit` (its exclusive
                // prefix over all digits and earlier chunks plus its running count), which
                // is inside `dst` (counts sum to `len`) and written by no other task.
                unsafe { out.get().add(slot).write(e) };
                o[digit] += 1;
            }
        });
}
