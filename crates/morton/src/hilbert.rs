//! Hilbert curve keys in 2D and 3D: like Morton codes a map from grid cells to one integer,
//! but consecutive keys are always face-adjacent cells (the Morton curve jumps at every
//! octant boundary), so ranges of keys make tighter clusters. The price is a longer
//! computation; [`crate::locality`] measures the gain and BENCHMARKS.md the price.
//!
//! Algorithm: John Skilling, "Programming the Hilbert curve" (AIP Conf. Proc. 707, 2004):
//! the "inverse undo" pass over the coordinates from the top bit down turns them into the
//! transposed Hilbert index, which is then interleaved (a Morton code, with axis 0 most
//! significant in each group) and Gray-decoded. Written without branches (each
//! exchange-or-invert is a mask select), so the batch functions vectorise like the Morton
//! ones.
//!
//! Conventions: coordinates are unsigned grid cells; bits above the key's bits per axis
//! are ignored. The curve starts at the origin (key 0 is cell 0) and, within each group of
//! 2 or 3 key bits, **x is the most significant** (Skilling's and the `lindel` crate's
//! order, the reverse of this crate's Morton layout). Order 1 in 2D visits
//! (0,0), (0,1), (1,1), (1,0); at higher orders the first 2x2 block's orientation depends
//! on the parity of the order (16 bits per axis: (0,0), (1,0), (1,1), (0,1)).
//!
//! ```
//! use morton::hilbert;
//! assert_eq!(hilbert::encode_generic([0, 1], 1).unwrap(), 1);
//! assert_eq!(hilbert::encode_generic([1, 1], 1).unwrap(), 2);
//! assert_eq!(hilbert::encode2_u32(1, 0), 1);
//! assert_eq!(hilbert::encode2_u32(1, 1), 2);
//! let key = hilbert::encode3_u32(300, 20, 1000);
//! assert_eq!(hilbert::decode3_u32(key), [300, 20, 1000]);
//! // Neighbouring keys are neighbouring cells.
//! let [a, b] = [hilbert::decode3_u32(key), hilbert::decode3_u32(key + 1)];
//! let steps: u32 = (0..3).map(|i| a[i].abs_diff(b[i])).sum();
//! assert_eq!(steps, 1);
//! ```

use crate::{BITS2_U32, BITS3_U32, BITS3_U64, Error, Path, magic};

/// All ones where bit `q` of `v` is set, else zero.
#[inline(always)]
fn bit_mask(v: u32, q: u32) -> u32 {
    ((v & q) != 0) as u32 * u32::MAX
}

/// Skilling's "inverse undo" from the top bit (`1 << (bits - 1)`) down to bit 1: the
/// coordinates become the transposed Hilbert index, still to be Gray-decoded.
#[inline(always)]
fn undo_down<const N: usize>(mut x: [u32; N], bits: u32) -> [u32; N] {
    let mut level = bits - 1;
    while level > 0 {
        undo_level(&mut x, level);
        level -= 1;
    }
    x
}

/// One level of [`undo_down`]: bit `level` of each axis against axis 0.
#[inline(always)]
fn undo_level<const N: usize>(x: &mut [u32; N], level: u32) {
    let q = 1u32 << level;
    let p = q - 1;
    // Axis 0 against itself: invert the low bits when its bit is set.
    x[0] ^= p & bit_mask(x[0], q);
    let mut i = 1;
    while i < N {
        let set = bit_mask(x[i], q);
        let t = (x[0] ^ x[i]) & p & !set; // exchange when the bit is clear
        x[0] ^= (p & set) | t; // invert when set
        x[i] ^= t;
        i += 1;
    }
}

/// The inverse of [`undo_down`]: from bit 1 up to the top bit, axes in reverse order.
#[inline(always)]
fn undo_up<const N: usize>(mut x: [u32; N], bits: u32) -> [u32; N] {
    let mut level = 1;
    while level < bits {
        let q = 1u32 << level;
        let p = q - 1;
        let mut i = N - 1;
        while i > 0 {
            let set = bit_mask(x[i], q);
            let t = (x[0] ^ x[i]) & p & !set;
            x[0] ^= (p & set) | t;
            x[i] ^= t;
            i -= 1;
        }
        x[0] ^= p & bit_mask(x[0], q);
        level += 1;
    }
    x
}

/// Gray decode of a whole key: bit `j` becomes the XOR of bits `j` and above.
#[inline(always)]
fn gray_decode_u32(k: u32) -> u32 {
    // The bits above 31 are zero, so the 64-bit decode's top shift adds nothing.
    gray_decode_u64(u64::from(k)) as u32
}

#[inline(always)]
fn gray_decode_u64(mut k: u64) -> u64 {
    k ^= k >> 1;
    k ^= k >> 2;
    k ^= k >> 4;
    k ^= k >> 8;
    k ^= k >> 16;
    k ^= k >> 32;
    k
}

#[inline(always)]
fn mask(v: u32, bits: u32) -> u32 {
    if bits >= 32 { v } else { v & ((1 << bits) - 1) }
}

/// The state of Skilling's "inverse undo" between levels: it has exchanged and inverted
/// the lower bits of the coordinates so far, always the same way at every lower level, so
/// the current lower bits are a signed permutation of the original ones: current bit of
/// axis `a` = original bit of axis `perm[a]` XOR bit `a` of `flip`.
#[derive(Clone, Copy)]
struct Sigma<const N: usize> {
    perm: [usize; N],
    flip: u32,
}

impl<const N: usize> Sigma<N> {
    const IDENTITY: Self = {
        let mut perm = [0; N];
        let mut a = 0;
        while a < N {
            perm[a] = a;
            a += 1;
        }
        Sigma { perm, flip: 0 }
    };

    /// Index in `0..N! * 2^N`: the Lehmer code of `perm`, then `flip`. Identity is 0.
    const fn index(&self) -> usize {
        let mut code = 0;
        let mut a = 0;
        while a < N {
            let mut smaller = 0;
            let mut b = a + 1;
            while b < N {
                if self.perm[b] < self.perm[a] {
                    smaller += 1;
                }
                b += 1;
            }
            code = code * (N - a) + smaller;
            a += 1;
        }
        (code << N) | self.flip as usize
    }

    /// The current bits (bit `a` = axis `a`) of an original octant `o` (bit `a` = axis `a`).
    const fn apply(&self, o: u32) -> u32 {
        let mut c = 0;
        let mut a = 0;
        while a < N {
            c |= (((o >> self.perm[a]) & 1) ^ ((self.flip >> a) & 1)) << a;
            a += 1;
        }
        c
    }

    /// The original octant whose current bits are `c`.
    const fn unapply(&self, c: u32) -> u32 {
        let mut o = 0;
        let mut a = 0;
        while a < N {
            o |= (((c >> a) & 1) ^ ((self.flip >> a) & 1)) << self.perm[a];
            a += 1;
        }
        o
    }

    /// Skilling's operations of one level, given that level's current bits `c`: for axis
    /// 0 and then each other axis `i`, invert axis 0's lower bits when `c_i` is set, else
    /// exchange the lower bits of axes 0 and `i`.
    const fn step(mut self, c: u32) -> Self {
        if c & 1 != 0 {
            self.flip ^= 1;
        }
        let mut i = 1;
        while i < N {
            if (c >> i) & 1 != 0 {
                self.flip ^= 1;
            } else {
                let p = self.perm[0];
                self.perm[0] = self.perm[i];
                self.perm[i] = p;
                let f0 = self.flip & 1;
                let fi = (self.flip >> i) & 1;
                self.flip = (self.flip & !(1 | (1 << i))) | fi | (f0 << i);
            }
            i += 1;
        }
        self
    }

    /// The key digit of current bits `c`: axis 0 most significant (Skilling's order).
    const fn key_digit(c: u32) -> u32 {
        let mut d = 0;
        let mut a = 0;
        while a < N {
            d |= ((c >> a) & 1) << (N - 1 - a);
            a += 1;
        }
        d
    }

    /// The current bits of key digit `d`.
    const fn from_key_digit(d: u32) -> u32 {
        Self::key_digit(d) // reversing the bit order is its own inverse
    }

    /// Rebuilds a state from its index.
    const fn from_index(index: usize) -> Self {
        let flip = (index & ((1 << N) - 1)) as u32;
        let mut code = index >> N;
        // Decode the Lehmer code: digits from the last position up.
        let mut digits = [0usize; N];
        let mut a = N;
        while a > 0 {
            a -= 1;
            let radix = N - a;
            digits[a] = code % radix;
            code /= radix;
        }
        let mut used = [false; N];
        let mut perm = [0usize; N];
        let mut a = 0;
        while a < N {
            let mut k = digits[a];
            let mut v = 0;
            loop {
                if !used[v] {
                    if k == 0 {
                        break;
                    }
                    k -= 1;
                }
                v += 1;
            }
            used[v] = true;
            perm[a] = v;
            a += 1;
        }
        Sigma { perm, flip }
    }
}

/// States: `N! * 2^N` (48 in 3D, 8 in 2D), most unreachable but indexable.
const fn states(n: usize) -> usize {
    let mut f = 1;
    let mut i = 2;
    while i <= n {
        f *= i;
        i += 1;
    }
    f << n
}

/// The lookup table for `L` levels per lookup, index `state << (N*L) | chunk`, entry
/// `next_state << (N*L) | digits`. The encode table (`DECODE = false`) takes octants (the
/// higher level's octant in the higher bits, each octant in Morton order, x lowest) to key
/// digits; the decode table takes transposed key digits (Gray-coded key) to Morton octants.
const fn table<const N: usize, const L: usize, const SIZE: usize, const DECODE: bool>()
-> [u16; SIZE] {
    let bits = N * L;
    let mut t = [0u16; SIZE];
    let mut s = 0;
    while s < states(N) {
        let mut chunk = 0u32;
        while chunk < (1 << bits) {
            let mut sigma = Sigma::<N>::from_index(s);
            let mut digits = 0u32;
            let mut l = 0;
            while l < L {
                let d = (chunk >> (N * (L - 1 - l))) & ((1 << N) - 1);
                let (c, out) = if DECODE {
                    let c = Sigma::<N>::from_key_digit(d);
                    (c, sigma.unapply(c))
                } else {
                    let c = sigma.apply(d);
                    (c, Sigma::<N>::key_digit(c))
                };
                digits = (digits << N) | out;
                sigma = sigma.step(c);
                l += 1;
            }
            t[(s << bits) | chunk as usize] = ((sigma.index() << bits) as u32 | digits) as u16;
            chunk += 1;
        }
        s += 1;
    }
    t
}

/// 3D, two levels (6 bits) per lookup: 48 states x 64 = 6 KiB.
static ENC3: [u16; 48 * 64] = table::<3, 2, { 48 * 64 }, false>();
static DEC3: [u16; 48 * 64] = table::<3, 2, { 48 * 64 }, true>();
/// 3D, one level per lookup (for the odd 21st level of u64 keys).
static ENC3_1: [u16; 48 * 8] = table::<3, 1, { 48 * 8 }, false>();
static DEC3_1: [u16; 48 * 8] = table::<3, 1, { 48 * 8 }, true>();
/// 2D, four levels (8 bits) per lookup: 8 states x 256 = 4 KiB.
static ENC2: [u16; 8 * 256] = table::<2, 4, { 8 * 256 }, false>();
static DEC2: [u16; 8 * 256] = table::<2, 4, { 8 * 256 }, true>();

// The walks start in state 0: it must be the identity.
const _: () = assert!(states(3) == 48 && states(2) == 8);
const _: () = assert!(Sigma::<3>::IDENTITY.index() == 0 && Sigma::<2>::IDENTITY.index() == 0);

/// Runs `steps` lookups of `bits` bits each over `code` from the top, starting in `entry`'s
/// state; returns the concatenated digits and the last entry.
#[inline(always)]
fn walk<const BITS: u32>(
    table: &[u16],
    code: u64,
    steps: u32,
    mut entry: u32,
    mut out: u64,
) -> (u64, u32) {
    let low = (1u32 << BITS) - 1;
    let mut step = steps;
    while step > 0 {
        step -= 1;
        let chunk = ((code >> (BITS * step)) as u32) & low;
        // The index is below `table.len()`: states < 48 (or 8) and chunk < 2^BITS.
        entry = table[((entry & !low) | chunk) as usize] as u32;
        out = (out << BITS) | (entry & low) as u64;
    }
    (out, entry)
}

/// 2D Hilbert key in a u32, 16 bits per axis (higher bits ignored).
#[inline]
#[must_use]
pub fn encode2_u32(x: u32, y: u32) -> u32 {
    let m = crate::encode2_u32(x, y) as u64;
    let (pre, _) = walk::<8>(&ENC2, m, 4, 0, 0);
    gray_decode_u32(pre as u32)
}

/// `[x, y]` of a 2D u32 Hilbert key, the inverse of [`encode2_u32`].
#[inline]
#[must_use]
pub fn decode2_u32(key: u32) -> [u32; 2] {
    let (m, _) = walk::<8>(&DEC2, (key ^ (key >> 1)) as u64, 4, 0, 0);
    crate::decode2_u32(m as u32)
}

/// 2D Hilbert key in a u64, 32 bits per axis.
#[inline]
#[must_use]
pub fn encode2_u64(x: u32, y: u32) -> u64 {
    let m = crate::encode2_u64(x, y);
    let (pre, _) = walk::<8>(&ENC2, m, 8, 0, 0);
    gray_decode_u64(pre)
}

/// `[x, y]` of a 2D u64 Hilbert key, the inverse of [`encode2_u64`].
#[inline]
#[must_use]
pub fn decode2_u64(key: u64) -> [u32; 2] {
    let (m, _) = walk::<8>(&DEC2, key ^ (key >> 1), 8, 0, 0);
    crate::decode2_u64(m)
}

/// 3D Hilbert key in a u32, 10 bits per axis (higher bits ignored; key bits 30 and 31 are
/// zero).
#[inline]
#[must_use]
pub fn encode3_u32(x: u32, y: u32, z: u32) -> u32 {
    let m = crate::encode3_u32(x, y, z) as u64;
    let (pre, _) = walk::<6>(&ENC3, m, 5, 0, 0);
    gray_decode_u32(pre as u32)
}

/// `[x, y, z]` of a 3D u32 Hilbert key, the inverse of [`encode3_u32`] (bits 30 and 31
/// are ignored).
#[inline]
#[must_use]
pub fn decode3_u32(key: u32) -> [u32; 3] {
    let key = key & 0x3fff_ffff;
    let (m, _) = walk::<6>(&DEC3, (key ^ (key >> 1)) as u64, 5, 0, 0);
    crate::decode3_u32(m as u32)
}

/// 3D Hilbert key in a u64, 21 bits per axis (bit 63 zero).
#[inline]
#[must_use]
pub fn encode3_u64(x: u32, y: u32, z: u32) -> u64 {
    let m = crate::encode3_u64(x, y, z);
    // The top level alone, then ten double levels.
    let first = ENC3_1[((m >> 60) & 7) as usize] as u32;
    let (pre, _) = walk::<6>(&ENC3, m, 10, (first >> 3) << 6, (first & 7) as u64);
    gray_decode_u64(pre)
}

/// `[x, y, z]` of a 3D u64 Hilbert key, the inverse of [`encode3_u64`] (bit 63 ignored).
#[inline]
#[must_use]
pub fn decode3_u64(key: u64) -> [u32; 3] {
    let key = key & 0x7fff_ffff_ffff_ffff;
    let g = key ^ (key >> 1);
    let first = DEC3_1[((g >> 60) & 7) as usize] as u32;
    let (m, _) = walk::<6>(&DEC3, g, 10, (first >> 3) << 6, (first & 7) as u64);
    crate::decode3_u64(m)
}

/// Skilling's form of the fixed widths, branch-free bit operations only: what the SIMD
/// batch paths run (the table walk above does not vectorise). The levels are unrolled by
/// hand: LLVM vectorises only innermost loops, so the per-key body must be straight-line.
mod skilling {
    use super::*;

    macro_rules! levels {
        ($x:ident; $($l:literal)*) => { $( undo_level(&mut $x, $l); )* };
    }

    #[inline(always)]
    pub(super) fn encode3_u32(x: u32, y: u32, z: u32) -> u32 {
        let b = BITS3_U32;
        let mut t = [mask(x, b), mask(y, b), mask(z, b)];
        levels!(t; 9 8 7 6 5 4 3 2 1);
        gray_decode_u32(magic::encode3_u32(t[2], t[1], t[0]))
    }

    #[inline(always)]
    pub(super) fn encode3_u64(x: u32, y: u32, z: u32) -> u64 {
        let b = BITS3_U64;
        let mut t = [mask(x, b), mask(y, b), mask(z, b)];
        levels!(t; 20 19 18 17 16 15 14 13 12 11 10 9 8 7 6 5 4 3 2 1);
        gray_decode_u64(magic::encode3_u64(t[2], t[1], t[0]))
    }

    #[inline(always)]
    pub(super) fn encode2_u32(x: u32, y: u32) -> u32 {
        let mut t = [mask(x, BITS2_U32), mask(y, BITS2_U32)];
        levels!(t; 15 14 13 12 11 10 9 8 7 6 5 4 3 2 1);
        gray_decode_u32(magic::encode2_u32(t[1], t[0]))
    }

    #[inline(always)]
    pub(super) fn encode2_u64(x: u32, y: u32) -> u64 {
        let mut t = [x, y];
        levels!(t; 31 30 29 28 27 26 25 24 23 22 21 20 19 18 17 16 15 14 13 12 11 10 9 8 7 6 5 4 3 2 1);
        gray_decode_u64(magic::encode2_u64(t[1], t[0]))
    }
}

/// The Hilbert key of an `N`-dimensional point with `bits` per axis (`bits` in 1..=32,
/// `N * bits <= 64`), the general form the fixed-width functions specialise; axis 0 is
/// the most significant in each group. For tests and odd widths; not tuned.
pub fn encode_generic<const N: usize>(point: [u32; N], bits: u32) -> Result<u64, Error> {
    check_generic::<N>(bits)?;
    let mut x = point;
    for v in &mut x {
        *v = mask(*v, bits);
    }
    let t = undo_down(x, bits);
    let mut key = 0u64;
    for level in (0..bits).rev() {
        for v in t {
            key = (key << 1) | ((v >> level) & 1) as u64;
        }
    }
    Ok(gray_decode_u64(key))
}

/// The inverse of [`encode_generic`].
pub fn decode_generic<const N: usize>(key: u64, bits: u32) -> Result<[u32; N], Error> {
    check_generic::<N>(bits)?;
    let g = key ^ (key >> 1);
    let mut x = [0u32; N];
    let total = N as u32 * bits;
    for level in 0..bits {
        for (axis, v) in x.iter_mut().enumerate() {
            // Axis 0 is the most significant of its group.
            let pos = total - 1 - (level * N as u32 + axis as u32);
            *v = (*v << 1) | ((g >> pos) & 1) as u32;
        }
    }
    Ok(undo_up(x, bits))
}

fn check_generic<const N: usize>(bits: u32) -> Result<(), Error> {
    let max = if N == 0 { 0 } else { (64 / N as u32).min(32) };
    if (1..=max).contains(&bits) {
        Ok(())
    } else {
        Err(Error::BadBits { bits, max })
    }
}

// Batch forms over struct-of-arrays lanes, vectorised like the Morton batches.

// Scalar and BMI2 paths walk the tables; the SIMD paths run Skilling's bit operations, which
// the compiler vectorises across lanes.
kernels!(h3_32, map3, (xs: &[u32], ys: &[u32], zs: &[u32], out: &mut [u32]),
    scalar: encode3_u32, bmi2: encode3_u32, simd: skilling::encode3_u32);
kernels!(h3_64, map3, (xs: &[u32], ys: &[u32], zs: &[u32], out: &mut [u64]),
    scalar: encode3_u64, bmi2: encode3_u64, simd: skilling::encode3_u64);
kernels!(h2_32, map2, (xs: &[u32], ys: &[u32], out: &mut [u32]),
    scalar: encode2_u32, bmi2: encode2_u32, simd: skilling::encode2_u32);
kernels!(h2_64, map2, (xs: &[u32], ys: &[u32], out: &mut [u64]),
    scalar: encode2_u64, bmi2: encode2_u64, simd: skilling::encode2_u64);

public!(
    /// 3D Hilbert keys into u32 (10 bits per axis) from struct-of-arrays lanes (BMI2 runs
    /// the scalar code).
    encode3_u32_soa, encode3_u32_soa_with, h3_32,
    (xs: &[u32], ys: &[u32], zs: &[u32], out: &mut [u32]));
public!(
    /// 3D Hilbert keys into u64 (21 bits per axis) from struct-of-arrays lanes.
    encode3_u64_soa, encode3_u64_soa_with, h3_64,
    (xs: &[u32], ys: &[u32], zs: &[u32], out: &mut [u64]));
public!(
    /// 2D Hilbert keys into u32 (16 bits per axis) from struct-of-arrays lanes.
    encode2_u32_soa, encode2_u32_soa_with, h2_32, (xs: &[u32], ys: &[u32], out: &mut [u32]));
public!(
    /// 2D Hilbert keys into u64 (32 bits per axis) from struct-of-arrays lanes.
    encode2_u64_soa, encode2_u64_soa_with, h2_64, (xs: &[u32], ys: &[u32], out: &mut [u64]));
