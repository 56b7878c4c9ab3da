//! Magic bits written for the loop vectoriser: the crate-root functions in builds with AVX2
//! or AVX-512, where a loop of calls vectorises. The steps that move whole bytes are written
//! as byte moves (each byte masked and shifted into place), which LLVM turns into one byte
//! shuffle (`vpshufb`) per vector instead of two or three shift-or-mask steps; the steps
//! inside bytes stay shift-or-mask. Results are those of [`crate::magic`] bit for bit.
//!
//! 3D codes take 8 bits of a coordinate from 24 code bits, so 3D decode compacts inside
//! 3-byte groups (24-bit masks repeated at bits 0, 24 and 48), then moves the groups'
//! first bytes together.
//!
//! Measured against [`crate::magic`] and `pdep`/`pext` one key at a time in a loop
//! (BENCHMARKS.md): which code uses this depends on the build (see the crate-root
//! functions). The 2D-32 and 3D-32 decodes gain nothing over [`crate::magic`] (the
//! compiler already finds the byte shuffle there), nor 3D-32 encode with byte moves, and
//! 3D-64 encode does not beat `pdep`, so they have none here; 3D-32 encode has another
//! spelling of the magic bits for AVX2-only builds.

// Which are used depends on the build's AVX2 and AVX-512; without AVX2, none.
#![allow(dead_code)]

/// The low 16 bits of `x` to the even bits of a u32: bytes to bytes 0 and 2, then bits.
#[inline(always)]
const fn spread2_u32(x: u32) -> u32 {
    let mut v = (x & 0xff) | ((x & 0xff00) << 8);
    v = (v | (v << 4)) & 0x0f0f_0f0f;
    v = (v | (v << 2)) & 0x3333_3333;
    (v | (v << 1)) & 0x5555_5555
}

/// `x` to the even bits of a u64: bytes to bytes 0, 2, 4 and 6, then bits.
#[inline(always)]
const fn spread2_u64(x: u32) -> u64 {
    let x = x as u64;
    let mut v =
        (x & 0xff) | ((x & 0xff00) << 8) | ((x & 0xff_0000) << 16) | ((x & 0xff00_0000) << 24);
    v = (v | (v << 4)) & 0x0f0f_0f0f_0f0f_0f0f;
    v = (v | (v << 2)) & 0x3333_3333_3333_3333;
    (v | (v << 1)) & 0x5555_5555_5555_5555
}

/// The low 10 bits of `x` to every third bit of a u32, starting at bit `S`, for builds with
/// AVX2 but not AVX-512: [`crate::magic`]'s ladder with the masks shifted by `S`. Measured
/// in a `target-cpu=haswell` build on an AVX-512 Xeon: spreading first and shifting after
/// (`part(y) << 1`) compiled, inlined from this crate, to a loop 1.1-1.2x slower than the
/// same source in the caller's crate; this spelling is 1.04-1.10x.
#[inline(always)]
const fn spread3_u32<const S: u32>(x: u32) -> u32 {
    let mut v = (x & 0x3ff) << S;
    v = (v | (v << 16)) & (0x0300_00ff << S);
    v = (v | (v << 8)) & (0x0300_f00f << S);
    v = (v | (v << 4)) & (0x030c_30c3 << S);
    (v | (v << 2)) & (0x0924_9249 << S)
}

/// The even bits of a u64 into a u32: bits inside bytes, then bytes 0, 2, 4, 6 together.
#[inline(always)]
const fn gather2_u64(code: u64) -> u32 {
    let mut v = code & 0x5555_5555_5555_5555;
    v = (v | (v >> 1)) & 0x3333_3333_3333_3333;
    v = (v | (v >> 2)) & 0x0f0f_0f0f_0f0f_0f0f;
    v = (v | (v >> 4)) & 0x00ff_00ff_00ff_00ff;
    ((v & 0xff) | ((v >> 8) & 0xff00) | ((v >> 16) & 0xff_0000) | ((v >> 24) & 0xff00_0000)) as u32
}

/// Bits 0, 3, ..., 60 of a u64 into 21 bits: inside each 3-byte group, then the groups'
/// first bytes together.
#[inline(always)]
const fn gather3_u64(code: u64) -> u32 {
    let mut v = code & 0x1249_2492_4924_9249;
    v = (v | (v >> 2)) & 0x30c3_0c30_c30c_30c3;
    v = (v | (v >> 4)) & 0xf00f_00f0_0f00_f00f;
    v = (v | (v >> 8)) & 0x00ff_0000_ff00_00ff;
    ((v & 0xff) | ((v >> 16) & 0xff00) | ((v >> 32) & 0xff_0000)) as u32
}

/// [`crate::encode2_u32`].
#[inline(always)]
pub(crate) const fn encode2_u32(x: u32, y: u32) -> u32 {
    spread2_u32(x) | (spread2_u32(y) << 1)
}

/// [`crate::encode2_u64`].
#[inline(always)]
pub(crate) const fn encode2_u64(x: u32, y: u32) -> u64 {
    spread2_u64(x) | (spread2_u64(y) << 1)
}

/// [`crate::encode3_u32`] for builds with AVX2 but not AVX-512.
#[inline(always)]
pub(crate) const fn encode3_u32(x: u32, y: u32, z: u32) -> u32 {
    spread3_u32::<0>(x) | spread3_u32::<1>(y) | spread3_u32::<2>(z)
}

/// [`crate::decode2_u64`].
#[inline(always)]
pub(crate) const fn decode2_u64(code: u64) -> [u32; 2] {
    [gather2_u64(code), gather2_u64(code >> 1)]
}

/// [`crate::decode3_u64`].
#[inline(always)]
pub(crate) const fn decode3_u64(code: u64) -> [u32; 3] {
    [
        gather3_u64(code),
        gather3_u64(code >> 1),
        gather3_u64(code >> 2),
    ]
}

#[cfg(test)]
mod tests {
    use crate::naive::{naive_decode, naive_encode};

    #[test]
    fn matches_naive() {
        let mut s = 0x2545_f491_4f6c_dd1du64;
        let words = (0..4096)
            .map(|_| {
                s ^= s << 13;
                s ^= s >> 7;
                s ^= s << 17;
                s
            })
            .chain([0, u64::MAX, 1 << 63, 0x5555_5555_5555_5555]);
        for w in words {
            let (a, b) = (w as u32, (w >> 32) as u32);
            assert_eq!(super::encode2_u32(a, b) as u64, naive_encode([a, b], 16));
            assert_eq!(super::encode2_u64(a, b), naive_encode([a, b], 32));
            let c = w.rotate_left(23) as u32;
            assert_eq!(
                super::encode3_u32(a, b, c) as u64,
                naive_encode([a, b, c], 10)
            );
            assert_eq!(super::decode2_u64(w), naive_decode::<2>(w, 32));
            assert_eq!(super::decode3_u64(w), naive_decode::<3>(w, 21));
        }
    }
}
