//! Scalar Morton encode/decode with BMI2 `pdep` / `pext` (x86-64 only): one deposit per
//! coordinate, one extract per axis. Each function carries
//! `#[target_feature(enable = "bmi2")]`, so it is safe to call from code compiled with BMI2
//! and inlines into the batch loops of [`crate::batch`], which carry the same feature: the
//! fast loop sits inside one BMI2 function, never one call per key from ordinary code.
//!
//! On AMD Zen 1 and Zen 2 `pdep`/`pext` are microcoded (18 to ~300 cycles depending on the
//! mask): [`crate::Path::best`] never picks this path there (see [`crate::Path`]).

use core::arch::x86_64::{_pdep_u32, _pdep_u64, _pext_u32, _pext_u64};

/// Bits of x in a 2D code: the even bits.
pub(crate) const M2_X: u64 = 0x5555_5555_5555_5555;
/// Bits of y in a 2D code: the odd bits.
pub(crate) const M2_Y: u64 = 0xaaaa_aaaa_aaaa_aaaa;
/// Bits of x in a 3D code: 0, 3, 6, ...
pub(crate) const M3_X: u64 = 0x1249_2492_4924_9249;
/// Bits of y in a 3D code: 1, 4, 7, ...
pub(crate) const M3_Y: u64 = 0x2492_4924_9249_2492;
/// Bits of z in a 3D code: 2, 5, 8, ...
pub(crate) const M3_Z: u64 = 0x4924_9249_2492_4924;

/// 2D-32 encode with `pdep`.
#[inline]
#[target_feature(enable = "bmi2")]
pub(crate) fn encode2_u32(x: u32, y: u32) -> u32 {
    _pdep_u32(x, M2_X as u32) | _pdep_u32(y, M2_Y as u32)
}

/// 2D-32 decode with `pext`.
#[inline]
#[target_feature(enable = "bmi2")]
pub(crate) fn decode2_u32(code: u32) -> [u32; 2] {
    [_pext_u32(code, M2_X as u32), _pext_u32(code, M2_Y as u32)]
}

/// 3D-32 encode with `pdep` (10 bits per axis; `pdep` drops the excess bits itself).
#[inline]
#[target_feature(enable = "bmi2")]
pub(crate) fn encode3_u32(x: u32, y: u32, z: u32) -> u32 {
    _pdep_u32(x, M3_X as u32 & 0x3fff_ffff)
        | _pdep_u32(y, M3_Y as u32 & 0x3fff_ffff)
        | _pdep_u32(z, M3_Z as u32 & 0x3fff_ffff)
}

/// 3D-32 decode with `pext`.
#[inline]
#[target_feature(enable = "bmi2")]
#[cfg_attr(any(not(feature = "std"), target_feature = "bmi2"), allow(dead_code))]
pub(crate) fn decode3_u32(code: u32) -> [u32; 3] {
    [
        _pext_u32(code, M3_X as u32 & 0x3fff_ffff),
        _pext_u32(code, M3_Y as u32 & 0x3fff_ffff),
        _pext_u32(code, M3_Z as u32 & 0x3fff_ffff),
    ]
}

/// 2D-64 encode with `pdep`.
#[inline]
#[target_feature(enable = "bmi2")]
pub(crate) fn encode2_u64(x: u32, y: u32) -> u64 {
    _pdep_u64(x as u64, M2_X) | _pdep_u64(y as u64, M2_Y)
}

/// 2D-64 decode with `pext`.
#[inline]
#[target_feature(enable = "bmi2")]
#[cfg_attr(any(not(feature = "std"), target_feature = "bmi2"), allow(dead_code))]
pub(crate) fn decode2_u64(code: u64) -> [u32; 2] {
    [_pext_u64(code, M2_X) as u32, _pext_u64(code, M2_Y) as u32]
}

/// 3D-64 encode with `pdep` (21 bits per axis).
#[inline]
#[target_feature(enable = "bmi2")]
pub(crate) fn encode3_u64(x: u32, y: u32, z: u32) -> u64 {
    _pdep_u64(x as u64, M3_X) | _pdep_u64(y as u64, M3_Y) | _pdep_u64(z as u64, M3_Z)
}

/// 3D-64 decode with `pext`.
#[inline]
#[target_feature(enable = "bmi2")]
#[cfg_attr(any(not(feature = "std"), target_feature = "bmi2"), allow(dead_code))]
pub(crate) fn decode3_u64(code: u64) -> [u32; 3] {
    [
        _pext_u64(code, M3_X) as u32,
        _pext_u64(code, M3_Y) as u32,
        _pext_u64(code, M3_Z) as u32,
    ]
}

// The packed forms serve the run-time dispatch of the scalar decoders (`std` only).

/// [`decode2_u64`] packed as `x | y << 32`: returned in one register, so a call from code
/// without BMI2 (run-time dispatch) does not go through memory.
#[inline]
#[target_feature(enable = "bmi2")]
#[cfg_attr(any(not(feature = "std"), target_feature = "bmi2"), allow(dead_code))]
pub(crate) fn decode2_u64_packed(code: u64) -> u64 {
    let [x, y] = decode2_u64(code);
    x as u64 | (y as u64) << 32
}

/// [`decode3_u64`] packed as `x | y << 21 | z << 42`.
#[inline]
#[target_feature(enable = "bmi2")]
#[cfg_attr(any(not(feature = "std"), target_feature = "bmi2"), allow(dead_code))]
pub(crate) fn decode3_u64_packed(code: u64) -> u64 {
    let [x, y, z] = decode3_u64(code);
    x as u64 | (y as u64) << 21 | (z as u64) << 42
}

/// Unpacks `x | y << 32`.
#[inline(always)]
#[cfg_attr(any(not(feature = "std"), target_feature = "bmi2"), allow(dead_code))]
pub(crate) fn unpack2(p: u64) -> [u32; 2] {
    [p as u32, (p >> 32) as u32]
}

/// Unpacks `x | y << 21 | z << 42`.
#[inline(always)]
#[cfg_attr(any(not(feature = "std"), target_feature = "bmi2"), allow(dead_code))]
pub(crate) fn unpack3(p: u64) -> [u32; 3] {
    [
        (p & 0x1f_ffff) as u32,
        ((p >> 21) & 0x1f_ffff) as u32,
        (p >> 42) as u32,
    ]
}
