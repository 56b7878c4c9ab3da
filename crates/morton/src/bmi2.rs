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

/// `pdep`/`pext` as inline assembly, for the scalar functions' run-time dispatch: unlike a
/// `#[target_feature]` function, they inline into code compiled without BMI2, so a
/// dispatched call costs one predictable branch, not a call and return.
#[cfg(all(feature = "std", not(target_feature = "bmi2")))]
pub(crate) mod asm {
    use core::arch::asm;

    use super::{M2_X, M2_Y, M3_X, M3_Y, M3_Z};

    /// `pdep` on u64.
    ///
    /// # Safety
    /// The CPU must have BMI2.
    #[inline(always)]
    unsafe fn pdep(v: u64, mask: u64) -> u64 {
        let r: u64;
        // SAFETY: the caller guarantees BMI2; `pdep` touches no memory or flags.
        unsafe {
            asm!("pdep {r}, {v}, {m}", r = lateout(reg) r, v = in(reg) v, m = in(reg) mask, options(pure, nomem, nostack, preserves_flags))
        };
        r
    }

    /// `pext` on u64.
    ///
    /// # Safety
    /// The CPU must have BMI2.
    #[inline(always)]
    unsafe fn pext(v: u64, mask: u64) -> u64 {
        let r: u64;
        // SAFETY: the caller guarantees BMI2; `pext` touches no memory or flags.
        unsafe {
            asm!("pext {r}, {v}, {m}", r = lateout(reg) r, v = in(reg) v, m = in(reg) mask, options(pure, nomem, nostack, preserves_flags))
        };
        r
    }

    /// `pdep` on u32: no masking of the source, and 32-bit masks are cheap immediates.
    ///
    /// # Safety
    /// The CPU must have BMI2.
    #[inline(always)]
    unsafe fn pdep32(v: u32, mask: u32) -> u32 {
        let r: u32;
        // SAFETY: the caller guarantees BMI2; `pdep` touches no memory or flags.
        unsafe {
            asm!("pdep {r:e}, {v:e}, {m:e}", r = lateout(reg) r, v = in(reg) v, m = in(reg) mask, options(pure, nomem, nostack, preserves_flags))
        };
        r
    }

    /// `pext` on u32.
    ///
    /// # Safety
    /// The CPU must have BMI2.
    #[inline(always)]
    unsafe fn pext32(v: u32, mask: u32) -> u32 {
        let r: u32;
        // SAFETY: the caller guarantees BMI2; `pext` touches no memory or flags.
        unsafe {
            asm!("pext {r:e}, {v:e}, {m:e}", r = lateout(reg) r, v = in(reg) v, m = in(reg) mask, options(pure, nomem, nostack, preserves_flags))
        };
        r
    }

    /// # Safety
    /// The CPU must have BMI2.
    #[inline(always)]
    pub(crate) unsafe fn encode2_u64(x: u32, y: u32) -> u64 {
        // SAFETY: forwarded.
        unsafe { pdep(x as u64, M2_X) | pdep(y as u64, M2_Y) }
    }

    /// # Safety
    /// The CPU must have BMI2.
    #[inline(always)]
    pub(crate) unsafe fn encode3_u64(x: u32, y: u32, z: u32) -> u64 {
        // SAFETY: forwarded.
        unsafe { pdep(x as u64, M3_X) | pdep(y as u64, M3_Y) | pdep(z as u64, M3_Z) }
    }

    /// # Safety
    /// The CPU must have BMI2.
    #[inline(always)]
    pub(crate) unsafe fn decode2_u64(code: u64) -> [u32; 2] {
        // SAFETY: forwarded.
        unsafe { [pext(code, M2_X) as u32, pext(code, M2_Y) as u32] }
    }

    /// # Safety
    /// The CPU must have BMI2.
    #[inline(always)]
    pub(crate) unsafe fn decode3_u64(code: u64) -> [u32; 3] {
        // SAFETY: forwarded.
        unsafe {
            [
                pext(code, M3_X) as u32,
                pext(code, M3_Y) as u32,
                pext(code, M3_Z) as u32,
            ]
        }
    }

    /// # Safety
    /// The CPU must have BMI2.
    #[inline(always)]
    pub(crate) unsafe fn encode2_u32(x: u32, y: u32) -> u32 {
        // SAFETY: forwarded; 16 mask bits take the low 16 bits of each axis.
        unsafe { pdep32(x, M2_X as u32) | pdep32(y, M2_Y as u32) }
    }

    /// # Safety
    /// The CPU must have BMI2.
    #[inline(always)]
    pub(crate) unsafe fn decode2_u32(code: u32) -> [u32; 2] {
        // SAFETY: forwarded.
        unsafe { [pext32(code, M2_X as u32), pext32(code, M2_Y as u32)] }
    }

    /// # Safety
    /// The CPU must have BMI2.
    #[inline(always)]
    pub(crate) unsafe fn decode3_u32(code: u32) -> [u32; 3] {
        // SAFETY: forwarded; the masks stop at bit 29, so bits 30 and 31 are ignored.
        unsafe {
            [
                pext32(code, M3_X as u32 & 0x3fff_ffff),
                pext32(code, M3_Y as u32 & 0x3fff_ffff),
                pext32(code, M3_Z as u32 & 0x3fff_ffff),
            ]
        }
    }
}
