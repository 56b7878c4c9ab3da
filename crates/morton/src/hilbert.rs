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

use crate::{BITS2_U32, BITS2_U64, BITS3_U32, BITS3_U64, MortonError, Path, magic};

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
        level -= 1;
    }
    x
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
fn gray_decode_u32(mut k: u32) -> u32 {
    k ^= k >> 1;
    k ^= k >> 2;
    k ^= k >> 4;
    k ^= k >> 8;
    k ^= k >> 16;
    k
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

/// 2D Hilbert key in a u32, 16 bits per axis (higher bits ignored).
#[inline]
#[must_use]
pub fn encode2_u32(x: u32, y: u32) -> u32 {
    let [a, b] = undo_down([mask(x, BITS2_U32), mask(y, BITS2_U32)], BITS2_U32);
    gray_decode_u32(magic::encode2_u32(b, a))
}

/// `[x, y]` of a 2D u32 Hilbert key, the inverse of [`encode2_u32`].
#[inline]
#[must_use]
pub fn decode2_u32(key: u32) -> [u32; 2] {
    let [b, a] = magic::decode2_u32(key ^ (key >> 1));
    undo_up([a, b], BITS2_U32)
}

/// 2D Hilbert key in a u64, 32 bits per axis.
#[inline]
#[must_use]
pub fn encode2_u64(x: u32, y: u32) -> u64 {
    let [a, b] = undo_down([x, y], BITS2_U64);
    gray_decode_u64(magic::encode2_u64(b, a))
}

/// `[x, y]` of a 2D u64 Hilbert key, the inverse of [`encode2_u64`].
#[inline]
#[must_use]
pub fn decode2_u64(key: u64) -> [u32; 2] {
    let [b, a] = magic::decode2_u64(key ^ (key >> 1));
    undo_up([a, b], BITS2_U64)
}

/// 3D Hilbert key in a u32, 10 bits per axis (higher bits ignored; key bits 30 and 31 are
/// zero).
#[inline]
#[must_use]
pub fn encode3_u32(x: u32, y: u32, z: u32) -> u32 {
    let b = BITS3_U32;
    let [a, c, d] = undo_down([mask(x, b), mask(y, b), mask(z, b)], b);
    gray_decode_u32(magic::encode3_u32(d, c, a))
}

/// `[x, y, z]` of a 3D u32 Hilbert key, the inverse of [`encode3_u32`] (bits 30 and 31
/// are ignored).
#[inline]
#[must_use]
pub fn decode3_u32(key: u32) -> [u32; 3] {
    let key = key & 0x3fff_ffff;
    let [d, c, a] = magic::decode3_u32(key ^ (key >> 1));
    undo_up([a, c, d], BITS3_U32)
}

/// 3D Hilbert key in a u64, 21 bits per axis (bit 63 zero).
#[inline]
#[must_use]
pub fn encode3_u64(x: u32, y: u32, z: u32) -> u64 {
    let b = BITS3_U64;
    let [a, c, d] = undo_down([mask(x, b), mask(y, b), mask(z, b)], b);
    gray_decode_u64(magic::encode3_u64(d, c, a))
}

/// `[x, y, z]` of a 3D u64 Hilbert key, the inverse of [`encode3_u64`] (bit 63 ignored).
#[inline]
#[must_use]
pub fn decode3_u64(key: u64) -> [u32; 3] {
    let key = key & 0x7fff_ffff_ffff_ffff;
    let [d, c, a] = magic::decode3_u64(key ^ (key >> 1));
    undo_up([a, c, d], BITS3_U64)
}

/// The Hilbert key of an `N`-dimensional point with `bits` per axis (`bits` in 1..=32,
/// `N * bits <= 64`), the general form the fixed-width functions specialise; axis 0 is
/// the most significant in each group. For tests and odd widths; not tuned.
pub fn encode_generic<const N: usize>(point: [u32; N], bits: u32) -> Result<u64, MortonError> {
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
pub fn decode_generic<const N: usize>(key: u64, bits: u32) -> Result<[u32; N], MortonError> {
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

fn check_generic<const N: usize>(bits: u32) -> Result<(), MortonError> {
    let max = if N == 0 { 0 } else { (64 / N as u32).min(32) };
    if (1..=max).contains(&bits) {
        Ok(())
    } else {
        Err(MortonError::BadBits { bits, max })
    }
}

// Batch forms over struct-of-arrays lanes, vectorised like the Morton batches.

#[inline(always)]
fn map3<C>(xs: &[u32], ys: &[u32], zs: &[u32], out: &mut [C], f: impl Fn(u32, u32, u32) -> C) {
    for (((o, &x), &y), &z) in out.iter_mut().zip(xs).zip(ys).zip(zs) {
        *o = f(x, y, z);
    }
}

#[inline(always)]
fn map2<C>(xs: &[u32], ys: &[u32], out: &mut [C], f: impl Fn(u32, u32) -> C) {
    for ((o, &x), &y) in out.iter_mut().zip(xs).zip(ys) {
        *o = f(x, y);
    }
}

kernels!(h3_32, map3, (xs: &[u32], ys: &[u32], zs: &[u32], out: &mut [u32]),
    magic: encode3_u32, bmi2: encode3_u32);
kernels!(h3_64, map3, (xs: &[u32], ys: &[u32], zs: &[u32], out: &mut [u64]),
    magic: encode3_u64, bmi2: encode3_u64);
kernels!(h2_32, map2, (xs: &[u32], ys: &[u32], out: &mut [u32]),
    magic: encode2_u32, bmi2: encode2_u32);
kernels!(h2_64, map2, (xs: &[u32], ys: &[u32], out: &mut [u64]),
    magic: encode2_u64, bmi2: encode2_u64);

fn prepare(path: Path, n: usize, lens: &[(&'static str, usize)]) -> Result<(), MortonError> {
    if !path.is_available() {
        return Err(MortonError::PathUnavailable { path });
    }
    for &(what, got) in lens {
        if got != n {
            return Err(MortonError::LengthMismatch {
                what,
                expected: n,
                got,
            });
        }
    }
    Ok(())
}

/// 3D Hilbert keys into u32 from struct-of-arrays lanes, on [`Path::best`].
pub fn encode3_u32_soa(
    xs: &[u32],
    ys: &[u32],
    zs: &[u32],
    out: &mut [u32],
) -> Result<(), MortonError> {
    encode3_u32_soa_with(Path::best(), xs, ys, zs, out)
}

/// [`encode3_u32_soa`] on a given [`Path`] (BMI2 runs the scalar code).
pub fn encode3_u32_soa_with(
    path: Path,
    xs: &[u32],
    ys: &[u32],
    zs: &[u32],
    out: &mut [u32],
) -> Result<(), MortonError> {
    prepare(
        path,
        xs.len(),
        &[("ys", ys.len()), ("zs", zs.len()), ("out", out.len())],
    )?;
    h3_32::run(path, xs, ys, zs, out);
    Ok(())
}

/// 3D Hilbert keys into u64 from struct-of-arrays lanes, on [`Path::best`].
pub fn encode3_u64_soa(
    xs: &[u32],
    ys: &[u32],
    zs: &[u32],
    out: &mut [u64],
) -> Result<(), MortonError> {
    encode3_u64_soa_with(Path::best(), xs, ys, zs, out)
}

/// [`encode3_u64_soa`] on a given [`Path`].
pub fn encode3_u64_soa_with(
    path: Path,
    xs: &[u32],
    ys: &[u32],
    zs: &[u32],
    out: &mut [u64],
) -> Result<(), MortonError> {
    prepare(
        path,
        xs.len(),
        &[("ys", ys.len()), ("zs", zs.len()), ("out", out.len())],
    )?;
    h3_64::run(path, xs, ys, zs, out);
    Ok(())
}

/// 2D Hilbert keys into u32 from struct-of-arrays lanes, on [`Path::best`].
pub fn encode2_u32_soa(xs: &[u32], ys: &[u32], out: &mut [u32]) -> Result<(), MortonError> {
    encode2_u32_soa_with(Path::best(), xs, ys, out)
}

/// [`encode2_u32_soa`] on a given [`Path`].
pub fn encode2_u32_soa_with(
    path: Path,
    xs: &[u32],
    ys: &[u32],
    out: &mut [u32],
) -> Result<(), MortonError> {
    prepare(path, xs.len(), &[("ys", ys.len()), ("out", out.len())])?;
    h2_32::run(path, xs, ys, out);
    Ok(())
}

/// 2D Hilbert keys into u64 from struct-of-arrays lanes, on [`Path::best`].
pub fn encode2_u64_soa(xs: &[u32], ys: &[u32], out: &mut [u64]) -> Result<(), MortonError> {
    encode2_u64_soa_with(Path::best(), xs, ys, out)
}

/// [`encode2_u64_soa`] on a given [`Path`].
pub fn encode2_u64_soa_with(
    path: Path,
    xs: &[u32],
    ys: &[u32],
    out: &mut [u64],
) -> Result<(), MortonError> {
    prepare(path, xs.len(), &[("ys", ys.len()), ("out", out.len())])?;
    h2_64::run(path, xs, ys, out);
    Ok(())
}
