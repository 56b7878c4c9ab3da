//! The permutation that sorts keys: a stable radix sort of (key, index) pairs with 8-bit
//! digits.
//!
//! Small inputs (up to [`LSD_MAX`] keys) take a least-significant-digit sort: one
//! histogram pass for all digits, then one scatter pass per digit, skipping digits where
//! every key is the same (Morton keys of few bits leave the top bytes zero). Larger inputs
//! first scatter on their most significant varying digit into 256 buckets, then sort each
//! bucket the same way while it is small enough to stay in cache (or split it again):
//! scattering a large array over 256 destinations once is cheap, but doing it once per digit
//! is what makes a plain LSD sort memory-bound. Both steps are stable, so equal keys keep
//! their input order.
//!
//! Callers sort instances or batches by key without moving them: `perm[i]` is the index of
//! the `i`-th smallest key.
//!
//! ```
//! let keys: [u32; 5] = [30, 10, 20, 10, 0];
//! let perm = morton::sort_permutation(&keys).unwrap();
//! assert_eq!(perm, [4, 1, 3, 2, 0]); // the two 10s keep their order
//! let sorted: Vec<u32> = perm.iter().map(|&i| keys[i as usize]).collect();
//! assert_eq!(sorted, [0, 10, 10, 20, 30]);
//! ```

use alloc::vec::Vec;

use crate::Error;

/// The most keys [`sort_permutation`] takes: indices are u32.
pub const MAX_SORT_KEYS: usize = u32::MAX as usize;

/// Ranges up to this many keys are sorted digit by digit from the least significant;
/// larger ones are first split on their most significant varying digit.
pub const LSD_MAX: usize = 1 << 15;

/// Key types [`sort_permutation`] sorts: `u32` and `u64`. Sealed.
pub trait SortKey: Copy + Send + Sync + sealed::Sealed + 'static {
    /// Bytes in the key (the number of 8-bit digits).
    const BYTES: usize;
    /// The (key, index) pair the sort moves.
    #[doc(hidden)]
    type Pair: Pair;
    /// The key widened to u64.
    fn to_u64(self) -> u64;
    #[doc(hidden)]
    fn pair(self, index: u32) -> Self::Pair;
}

/// A (key, index) pair as the sort moves it. Sealed.
#[doc(hidden)]
pub trait Pair: Copy + Send + Sync + Default + sealed::Sealed + 'static {
    /// Digit `d` (0 = least significant byte) of the key.
    fn digit(self, d: u32) -> usize;
    /// The index.
    fn index(self) -> u32;
}

mod sealed {
    pub trait Sealed {}
    impl Sealed for u32 {}
    impl Sealed for u64 {}
    impl Sealed for super::Pair64 {}
}

/// A u32 key and its index packed in one u64 (key in the high half): 8 bytes a move.
impl Pair for u64 {
    #[inline(always)]
    fn digit(self, d: u32) -> usize {
        ((self >> (32 + 8 * d)) & 0xff) as usize
    }
    #[inline(always)]
    fn index(self) -> u32 {
        self as u32
    }
}

/// A u64 key and its index.
#[doc(hidden)]
#[derive(Clone, Copy, Default, Debug)]
pub struct Pair64 {
    key: u64,
    index: u32,
}

impl Pair for Pair64 {
    #[inline(always)]
    fn digit(self, d: u32) -> usize {
        ((self.key >> (8 * d)) & 0xff) as usize
    }
    #[inline(always)]
    fn index(self) -> u32 {
        self.index
    }
}

impl SortKey for u32 {
    const BYTES: usize = 4;
    type Pair = u64;
    #[inline(always)]
    fn to_u64(self) -> u64 {
        self as u64
    }
    #[inline(always)]
    fn pair(self, index: u32) -> u64 {
        ((self as u64) << 32) | index as u64
    }
}

impl SortKey for u64 {
    const BYTES: usize = 8;
    type Pair = Pair64;
    #[inline(always)]
    fn to_u64(self) -> u64 {
        self
    }
    #[inline(always)]
    fn pair(self, index: u32) -> Pair64 {
        Pair64 { key: self, index }
    }
}

/// The permutation that sorts `keys` ascending, stable: `keys[perm[0]] <= keys[perm[1]] <=
/// ...`, equal keys in input order. [`Error::TooManyKeys`] above [`MAX_SORT_KEYS`].
pub fn sort_permutation<K: SortKey>(keys: &[K]) -> Result<Vec<u32>, Error> {
    let mut out = Vec::new();
    sort_permutation_into(keys, &mut out)?;
    Ok(out)
}

/// [`sort_permutation`] into `out` (cleared first), reusing its allocation. For repeated
/// sorts (every frame) keep a [`Sorter`], which also reuses the scratch buffers.
pub fn sort_permutation_into<K: SortKey>(keys: &[K], out: &mut Vec<u32>) -> Result<(), Error> {
    Sorter::new().sort_permutation_into(keys, out)
}

/// A radix sorter that keeps its two scratch buffers (12 to 16 bytes per key) between
/// calls, so sorting every frame allocates nothing once warm and pays no page faults.
///
/// ```
/// let mut sorter = morton::Sorter::<u64>::new();
/// let mut perm = Vec::new();
/// for frame in 0..3u64 {
///     let keys = [frame + 3, 1, frame];
///     sorter.sort_permutation_into(&keys, &mut perm).unwrap();
///     assert_eq!(perm, if frame == 0 { [2, 1, 0] } else { [1, 2, 0] });
/// }
/// ```
pub struct Sorter<K: SortKey> {
    pub(crate) a: Vec<K::Pair>,
    pub(crate) b: Vec<K::Pair>,
}

impl<K: SortKey> Default for Sorter<K> {
    fn default() -> Self {
        Self::new()
    }
}

impl<K: SortKey> core::fmt::Debug for Sorter<K> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Sorter")
            .field("capacity", &self.a.capacity())
            .finish()
    }
}

impl<K: SortKey> Sorter<K> {
    /// A sorter with no buffers yet.
    pub const fn new() -> Self {
        Self {
            a: Vec::new(),
            b: Vec::new(),
        }
    }

    /// [`sort_permutation`] into `out` (cleared first) with this sorter's buffers.
    pub fn sort_permutation_into(&mut self, keys: &[K], out: &mut Vec<u32>) -> Result<(), Error> {
        check_len(keys.len())?;
        out.clear();
        let n = keys.len();
        let h = histograms(keys);
        let Some(top) = top_digit::<K>(&h, n) else {
            out.extend(0..n as u32);
            return Ok(());
        };
        self.a.resize(n, K::Pair::default());
        self.b.resize(n, K::Pair::default());
        let (a, b) = (&mut self.a[..n], &mut self.b[..n]);
        out.reserve(n);
        if n <= LSD_MAX {
            // Pair up in order, then the LSD passes.
            for (i, (p, &k)) in a.iter_mut().zip(keys).enumerate() {
                *p = k.pair(i as u32);
            }
            let digits = varying_digits::<K>(&h, n, top + 1);
            let src = if lsd(a, b, &digits, &h) { b } else { a };
            out.extend(src.iter().map(|p| p.index()));
            return Ok(());
        }
        // One scatter on the top varying digit straight from the keys, then each bucket.
        let mut o = offsets(&h[top as usize]);
        for (i, &k) in keys.iter().enumerate() {
            let p = k.pair(i as u32);
            let d = p.digit(top);
            a[o[d] as usize] = p;
            o[d] += 1;
        }
        // Each bucket's result lands in `a` or `b`; read the indices from where it is.
        let starts = offsets(&h[top as usize]);
        for d in 0..256 {
            let (s, len) = (starts[d] as usize, h[top as usize][d] as usize);
            let in_b =
                len > 1 && top > 0 && sort_range(&mut a[s..s + len], &mut b[s..s + len], top - 1);
            let src = if in_b { &b[s..s + len] } else { &a[s..s + len] };
            out.extend(src.iter().map(|p| p.index()));
        }
        Ok(())
    }
}

/// Sorts `a` (whose keys agree on every digit above `hi`) by digits `hi..=0`, stable,
/// with `b` as scratch of the same length. Returns whether the result is in `b` (else in
/// `a`): LSD passes alternate between the two, and copying back would cost a pass.
pub(crate) fn sort_range<P: Pair>(a: &mut [P], b: &mut [P], hi: u32) -> bool {
    let n = a.len();
    let mut h = [[0u32; 256]; 8];
    for &p in a.iter() {
        for d in 0..=hi {
            h[d as usize][p.digit(d)] += 1;
        }
    }
    let Some(top) = (0..=hi).rev().find(|&d| !trivial(&h[d as usize], n)) else {
        return false;
    };
    if n <= LSD_MAX || top == 0 {
        let mut digits = [0u32; 8];
        let mut count = 0;
        for d in 0..=top {
            if !trivial(&h[d as usize], n) {
                digits[count] = d;
                count += 1;
            }
        }
        return lsd(a, b, &digits[..count], &h);
    }
    // Still large: split on `top` into `b`, then sort each bucket there (bringing back any
    // whose result landed in `a`).
    scatter(a, b, top, &h[top as usize]);
    let starts = offsets(&h[top as usize]);
    for d in 0..256 {
        let (s, len) = (starts[d] as usize, h[top as usize][d] as usize);
        if len > 1 && sort_range(&mut b[s..s + len], &mut a[s..s + len], top - 1) {
            b[s..s + len].copy_from_slice(&a[s..s + len]);
        }
    }
    true
}

/// LSD passes over `digits` (ascending), ping-ponging between `a` and `b`. `h[d]` is the
/// histogram of digit `d` over `a`. Returns whether the result is in `b`.
fn lsd<P: Pair>(a: &mut [P], b: &mut [P], digits: &[u32], h: &[[u32; 256]; 8]) -> bool {
    let mut in_b = false;
    for &d in digits {
        if in_b {
            scatter(b, a, d, &h[d as usize]);
        } else {
            scatter(a, b, d, &h[d as usize]);
        }
        in_b = !in_b;
    }
    in_b
}

/// One stable counting-sort pass of `src` into `dst` on digit `d`.
#[inline]
fn scatter<P: Pair>(src: &[P], dst: &mut [P], d: u32, h: &[u32; 256]) {
    let mut o = offsets(h);
    for &p in src {
        let digit = p.digit(d);
        dst[o[digit] as usize] = p;
        o[digit] += 1;
    }
}

pub(crate) fn check_len(len: usize) -> Result<(), Error> {
    if len > MAX_SORT_KEYS {
        Err(Error::TooManyKeys {
            len,
            max: MAX_SORT_KEYS,
        })
    } else {
        Ok(())
    }
}

/// Per-digit histograms of all keys, in one pass (digits past `K::BYTES` stay empty).
pub(crate) fn histograms<K: SortKey>(keys: &[K]) -> [[u32; 256]; 8] {
    let mut h = [[0u32; 256]; 8];
    for &k in keys {
        let k = k.to_u64();
        for (d, hd) in h.iter_mut().enumerate().take(K::BYTES) {
            hd[((k >> (8 * d)) & 0xff) as usize] += 1;
        }
    }
    h
}

/// The most significant digit on which keys differ, if any.
pub(crate) fn top_digit<K: SortKey>(h: &[[u32; 256]; 8], n: usize) -> Option<u32> {
    (0..K::BYTES as u32)
        .rev()
        .find(|&d| !trivial(&h[d as usize], n))
}

/// The digits below `end` on which keys differ, ascending.
fn varying_digits<K: SortKey>(h: &[[u32; 256]; 8], n: usize, end: u32) -> Vec<u32> {
    (0..end.min(K::BYTES as u32))
        .filter(|&d| !trivial(&h[d as usize], n))
        .collect()
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
