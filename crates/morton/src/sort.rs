//! The permutation that sorts keys: a stable least-significant-digit radix sort of
//! (key, index) pairs, 8-bit digits, one histogram pass for all digits, and digit passes
//! skipped where every key has the same digit (Morton keys of few bits leave the top bytes
//! zero).
//!
//! Callers sort instances or batches by key without moving them: `perm[i]` is the index of
//! the `i`-th smallest key, ties in input order (stable).
//!
//! ```
//! let keys: [u32; 5] = [30, 10, 20, 10, 0];
//! let perm = morton::sort_permutation(&keys).unwrap();
//! assert_eq!(perm, [4, 1, 3, 2, 0]); // the two 10s keep their order
//! let sorted: Vec<u32> = perm.iter().map(|&i| keys[i as usize]).collect();
//! assert_eq!(sorted, [0, 10, 10, 20, 30]);
//! ```

use alloc::vec::Vec;

use crate::MortonError;

/// The most keys [`sort_permutation`] takes: indices are u32.
pub const MAX_SORT_KEYS: usize = u32::MAX as usize;

/// Key types [`sort_permutation`] sorts: `u32` and `u64`. Sealed.
pub trait SortKey: Copy + Send + Sync + sealed::Sealed + 'static {
    /// Bytes in the key (the number of 8-bit digits).
    const BYTES: usize;
    /// The key widened to u64.
    fn to_u64(self) -> u64;
    #[doc(hidden)]
    fn sort_into(keys: &[Self], out: &mut Vec<u32>);
}

mod sealed {
    pub trait Sealed {}
    impl Sealed for u32 {}
    impl Sealed for u64 {}
}

impl SortKey for u32 {
    const BYTES: usize = 4;
    #[inline]
    fn to_u64(self) -> u64 {
        self as u64
    }
    fn sort_into(keys: &[Self], out: &mut Vec<u32>) {
        sort_u32(keys, out);
    }
}

impl SortKey for u64 {
    const BYTES: usize = 8;
    #[inline]
    fn to_u64(self) -> u64 {
        self
    }
    fn sort_into(keys: &[Self], out: &mut Vec<u32>) {
        sort_u64(keys, out);
    }
}

/// The permutation that sorts `keys` ascending, stable: `keys[perm[0]] <= keys[perm[1]] <=
/// ...`, equal keys in input order. [`MortonError::TooManyKeys`] above [`MAX_SORT_KEYS`].
pub fn sort_permutation<K: SortKey>(keys: &[K]) -> Result<Vec<u32>, MortonError> {
    let mut out = Vec::new();
    sort_permutation_into(keys, &mut out)?;
    Ok(out)
}

/// [`sort_permutation`] into `out` (cleared first), reusing its allocation.
pub fn sort_permutation_into<K: SortKey>(
    keys: &[K],
    out: &mut Vec<u32>,
) -> Result<(), MortonError> {
    check_len(keys.len())?;
    K::sort_into(keys, out);
    Ok(())
}

pub(crate) fn check_len(len: usize) -> Result<(), MortonError> {
    if len > MAX_SORT_KEYS {
        Err(MortonError::TooManyKeys {
            len,
            max: MAX_SORT_KEYS,
        })
    } else {
        Ok(())
    }
}

/// Per-digit histograms of all keys, in one pass.
pub(crate) fn histograms<K: SortKey, const D: usize>(keys: &[K]) -> [[u32; 256]; D] {
    let mut h = [[0u32; 256]; D];
    for &k in keys {
        let k = k.to_u64();
        for (d, hd) in h.iter_mut().enumerate() {
            hd[((k >> (8 * d)) & 0xff) as usize] += 1;
        }
    }
    h
}

/// Whether a digit's pass can be skipped: every key has the same digit.
#[inline]
pub(crate) fn trivial(h: &[u32; 256], n: usize) -> bool {
    h.iter().any(|&c| c as usize == n)
}

/// Exclusive prefix sums of a histogram: each digit's first output slot.
#[inline]
pub(crate) fn offsets(h: &[u32; 256]) -> [u32; 256] {
    let mut o = [0u32; 256];
    let mut sum = 0u32;
    for (o, &c) in o.iter_mut().zip(h) {
        *o = sum;
        sum = sum.wrapping_add(c);
    }
    o
}

/// u32 keys: pairs packed as `key << 32 | index` in one u64, sorted on the key's bytes.
fn sort_u32(keys: &[u32], out: &mut Vec<u32>) {
    let n = keys.len();
    out.clear();
    let h: [[u32; 256]; 4] = histograms(keys);
    let passes: Vec<usize> = (0..4).filter(|&d| !trivial(&h[d], n)).collect();
    if passes.is_empty() {
        out.extend(0..n as u32);
        return;
    }
    let mut a: Vec<u64> = Vec::with_capacity(n);
    let mut b: Vec<u64> = alloc::vec![0; n];
    // The first pass scatters straight from the keys.
    let d0 = passes[0];
    let mut o = offsets(&h[d0]);
    for (i, &k) in keys.iter().enumerate() {
        let digit = ((k >> (8 * d0)) & 0xff) as usize;
        b[o[digit] as usize] = ((k as u64) << 32) | i as u64;
        o[digit] += 1;
    }
    a.resize(n, 0);
    for &d in &passes[1..] {
        core::mem::swap(&mut a, &mut b);
        let mut o = offsets(&h[d]);
        let shift = 32 + 8 * d;
        for &p in a.iter() {
            let digit = ((p >> shift) & 0xff) as usize;
            b[o[digit] as usize] = p;
            o[digit] += 1;
        }
    }
    out.extend(b.iter().map(|&p| p as u32));
}

/// u64 keys: keys and indices in two arrays, scattered together.
fn sort_u64(keys: &[u64], out: &mut Vec<u32>) {
    let n = keys.len();
    out.clear();
    let h: [[u32; 256]; 8] = histograms(keys);
    let passes: Vec<usize> = (0..8).filter(|&d| !trivial(&h[d], n)).collect();
    if passes.is_empty() {
        out.extend(0..n as u32);
        return;
    }
    let (mut ka, mut ia) = (alloc::vec![0u64; n], alloc::vec![0u32; n]);
    let (mut kb, mut ib) = (alloc::vec![0u64; n], alloc::vec![0u32; n]);
    let d0 = passes[0];
    let mut o = offsets(&h[d0]);
    for (i, &k) in keys.iter().enumerate() {
        let digit = ((k >> (8 * d0)) & 0xff) as usize;
        let slot = o[digit] as usize;
        kb[slot] = k;
        ib[slot] = i as u32;
        o[digit] += 1;
    }
    for &d in &passes[1..] {
        core::mem::swap(&mut ka, &mut kb);
        core::mem::swap(&mut ia, &mut ib);
        let mut o = offsets(&h[d]);
        let shift = 8 * d;
        for (&k, &i) in ka.iter().zip(&ia) {
            let digit = ((k >> shift) & 0xff) as usize;
            let slot = o[digit] as usize;
            kb[slot] = k;
            ib[slot] = i;
            o[digit] += 1;
        }
    }
    *out = ib;
}
