//! Scalar Morton encode/decode by "magic bits": spread (or compact) one coordinate with a
//! fixed ladder of shift-or-mask steps, then OR the shifted lanes together. Branch-free,
//! table-free, `const`, and written with literal masks so that Cargo's default release
//! profile (no LTO) inlines and vectorises it inside loops.
//!
//! Source: the well-known "interleave bits by binary magic numbers" from Sean Eron Anderson's
//! *Bit Twiddling Hacks* and Fabian Giesen's "Decoding Morton codes" (2009), whose
//! `Part1By1` / `Part1By2` / `Compact1By1` / `Compact1By2` names are used here.

/// Spreads the low 16 bits of `x` to the even bits of a u32 (bit `i` moves to bit `2i`).
#[inline(always)]
pub(crate) const fn part1by1_u32(x: u32) -> u32 {
    let mut x = x & 0x0000_ffff;
    x = (x | (x << 8)) & 0x00ff_00ff;
    x = (x | (x << 4)) & 0x0f0f_0f0f;
    x = (x | (x << 2)) & 0x3333_3333;
    x = (x | (x << 1)) & 0x5555_5555;
    x
}

/// Gathers the even bits of `x` into its low 16 bits (inverse of [`part1by1_u32`]).
#[inline(always)]
pub(crate) const fn compact1by1_u32(x: u32) -> u32 {
    let mut x = x & 0x5555_5555;
    x = (x | (x >> 1)) & 0x3333_3333;
    x = (x | (x >> 2)) & 0x0f0f_0f0f;
    x = (x | (x >> 4)) & 0x00ff_00ff;
    x = (x | (x >> 8)) & 0x0000_ffff;
    x
}

/// Spreads the low 10 bits of `x` to every third bit of a u32 (bit `i` moves to bit `3i`).
#[inline(always)]
pub(crate) const fn part1by2_u32(x: u32) -> u32 {
    let mut x = x & 0x0000_03ff;
    x = (x | (x << 16)) & 0x0300_00ff;
    x = (x | (x << 8)) & 0x0300_f00f;
    x = (x | (x << 4)) & 0x030c_30c3;
    x = (x | (x << 2)) & 0x0924_9249;
    x
}

/// Gathers every third bit of `x` (bits 0, 3, 6, ..., 27) into its low 10 bits.
#[inline(always)]
pub(crate) const fn compact1by2_u32(x: u32) -> u32 {
    let mut x = x & 0x0924_9249;
    x = (x | (x >> 2)) & 0x030c_30c3;
    x = (x | (x >> 4)) & 0x0300_f00f;
    x = (x | (x >> 8)) & 0x0300_00ff;
    x = (x | (x >> 16)) & 0x0000_03ff;
    x
}

/// Spreads the low 32 bits of `x` to the even bits of a u64.
#[inline(always)]
pub(crate) const fn part1by1_u64(x: u64) -> u64 {
    let mut x = x & 0x0000_0000_ffff_ffff;
    x = (x | (x << 16)) & 0x0000_ffff_0000_ffff;
    x = (x | (x << 8)) & 0x00ff_00ff_00ff_00ff;
    x = (x | (x << 4)) & 0x0f0f_0f0f_0f0f_0f0f;
    x = (x | (x << 2)) & 0x3333_3333_3333_3333;
    x = (x | (x << 1)) & 0x5555_5555_5555_5555;
    x
}

/// Gathers the even bits of a u64 into its low 32 bits.
#[inline(always)]
pub(crate) const fn compact1by1_u64(x: u64) -> u64 {
    let mut x = x & 0x5555_5555_5555_5555;
    x = (x | (x >> 1)) & 0x3333_3333_3333_3333;
    x = (x | (x >> 2)) & 0x0f0f_0f0f_0f0f_0f0f;
    x = (x | (x >> 4)) & 0x00ff_00ff_00ff_00ff;
    x = (x | (x >> 8)) & 0x0000_ffff_0000_ffff;
    x = (x | (x >> 16)) & 0x0000_0000_ffff_ffff;
    x
}

/// Spreads the low 21 bits of `x` to every third bit of a u64 (bits 0, 3, ..., 60).
#[inline(always)]
pub(crate) const fn part1by2_u64(x: u64) -> u64 {
    let mut x = x & 0x0000_0000_001f_ffff;
    x = (x | (x << 32)) & 0x001f_0000_0000_ffff;
    x = (x | (x << 16)) & 0x001f_0000_ff00_00ff;
    x = (x | (x << 8)) & 0x100f_00f0_0f00_f00f;
    x = (x | (x << 4)) & 0x10c3_0c30_c30c_30c3;
    x = (x | (x << 2)) & 0x1249_2492_4924_9249;
    x
}

/// Gathers every third bit of a u64 (bits 0, 3, ..., 60) into its low 21 bits.
#[inline(always)]
pub(crate) const fn compact1by2_u64(x: u64) -> u64 {
    let mut x = x & 0x1249_2492_4924_9249;
    x = (x | (x >> 2)) & 0x10c3_0c30_c30c_30c3;
    x = (x | (x >> 4)) & 0x100f_00f0_0f00_f00f;
    x = (x | (x >> 8)) & 0x001f_0000_ff00_00ff;
    x = (x | (x >> 16)) & 0x001f_0000_0000_ffff;
    x = (x | (x >> 32)) & 0x0000_0000_001f_ffff;
    x
}

/// 2D, 16 bits per axis into a u32, by magic bits. See [`crate::encode2_u32`].
#[inline(always)]
pub const fn encode2_u32(x: u32, y: u32) -> u32 {
    part1by1_u32(x) | (part1by1_u32(y) << 1)
}

/// Inverse of [`encode2_u32`].
#[inline(always)]
pub const fn decode2_u32(code: u32) -> [u32; 2] {
    [compact1by1_u32(code), compact1by1_u32(code >> 1)]
}

/// 3D, 10 bits per axis into a u32 (bits 30 and 31 zero), by magic bits.
#[inline(always)]
pub const fn encode3_u32(x: u32, y: u32, z: u32) -> u32 {
    part1by2_u32(x) | (part1by2_u32(y) << 1) | (part1by2_u32(z) << 2)
}

/// Inverse of [`encode3_u32`]; bits 30 and 31 of `code` are ignored.
#[inline(always)]
pub const fn decode3_u32(code: u32) -> [u32; 3] {
    [
        compact1by2_u32(code),
        compact1by2_u32(code >> 1),
        compact1by2_u32(code >> 2),
    ]
}

/// 2D, 32 bits per axis into a u64, by magic bits.
#[inline(always)]
pub const fn encode2_u64(x: u32, y: u32) -> u64 {
    part1by1_u64(x as u64) | (part1by1_u64(y as u64) << 1)
}

/// Inverse of [`encode2_u64`].
#[inline(always)]
pub const fn decode2_u64(code: u64) -> [u32; 2] {
    [
        compact1by1_u64(code) as u32,
        compact1by1_u64(code >> 1) as u32,
    ]
}

/// 3D, 21 bits per axis into a u64 (bit 63 zero), by magic bits.
#[inline(always)]
pub const fn encode3_u64(x: u32, y: u32, z: u32) -> u64 {
    part1by2_u64(x as u64) | (part1by2_u64(y as u64) << 1) | (part1by2_u64(z as u64) << 2)
}

/// Inverse of [`encode3_u64`]; bit 63 of `code` is ignored.
#[inline(always)]
pub const fn decode3_u64(code: u64) -> [u32; 3] {
    [
        compact1by2_u64(code) as u32,
        compact1by2_u64(code >> 1) as u32,
        compact1by2_u64(code >> 2) as u32,
    ]
}
