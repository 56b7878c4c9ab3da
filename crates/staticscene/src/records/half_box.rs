//! The 12-byte half-precision box [`HalfAabb`] and the branch-free half decoder the
//! query reads halves with.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use half::f16;

use crate::{Error, Field};

/// Half bits to f32, the same value as `f16::from_bits(h).to_f32()` for every pattern
/// (subnormals, infinities, NaN payloads kept in the top mantissa bits; tested against
/// `half` exhaustively), branch-free: the bits shifted into f32 position and rescaled by
/// 2^112, then infinities and NaNs patched.
///
/// Kept beside `half` on purpose: the query decodes up to 13 halves per instance it tests
/// (two half boxes and the LOD scale), and `half`'s `to_f32` (a runtime F16C check and an
/// out-of-line call per value) made `query_street` / `query_aerial` (sequential) 30% / 18%
/// slower, `to_f32_const` 11% / 7% (criterion, 2 cores, 2026-11-24).
#[inline]
pub(super) fn half_to_f32_branchless(h: u16) -> f32 {
    let h = u32::from(h);
    let sign = (h & 0x8000) << 16;
    let mag = h & 0x7fff;
    // 2^112 = 0x7780_0000 as f32.
    let v = f32::from_bits(mag << 13) * f32::from_bits(0x7780_0000);
    let bits = if mag >= 0x7c00 {
        0x7f80_0000 | ((mag & 0x3ff) << 13)
    } else {
        v.to_bits()
    };
    f32::from_bits(bits | sign)
}

/// Three halves' bits as a vector, each through [`half_to_f32_branchless`].
#[inline]
fn half3(h: [u16; 3]) -> Vec3 {
    Vec3::new(
        half_to_f32_branchless(h[0]),
        half_to_f32_branchless(h[1]),
        half_to_f32_branchless(h[2]),
    )
}

/// The f16 at or below `v` (`v` finite).
fn f16_floor(v: f32) -> f16 {
    let h = f16::from_f32(v);
    if h.to_f32() <= v {
        return h;
    }
    f16_step_down(h)
}

/// The f16 at or above `v` (`v` finite).
fn f16_ceil(v: f32) -> f16 {
    let h = f16::from_f32(v);
    if h.to_f32() >= v {
        return h;
    }
    f16_step_up(h)
}

fn f16_step_down(h: f16) -> f16 {
    let b = h.to_bits();
    f16::from_bits(match b {
        0x0000 | 0x8000 => 0x8001,
        b if b & 0x8000 == 0 => b - 1,
        b => b + 1,
    })
}

fn f16_step_up(h: f16) -> f16 {
    let b = h.to_bits();
    f16::from_bits(match b {
        0x0000 | 0x8000 => 0x0001,
        b if b & 0x8000 == 0 => b + 1,
        b => b - 1,
    })
}

/// A half-precision axis-aligned box, 12 bytes: `min` then `max`, three f16 each. Used for
/// the LOD bounds (object space). Encoding is conservative: the half box always contains
/// the f32 box it was made from. WGSL: `array<u32, 3>` (`StaticsceneHalfAabb`), read with
/// `unpack2x16float`.
///
/// | bytes | field |
/// | --- | --- |
/// | 0-5 | min x, y, z (f16) |
/// | 6-11 | max x, y, z (f16) |
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Pod, Zeroable)]
pub struct HalfAabb {
    /// Minimum corner, f16 bits.
    pub min: [u16; 3],
    /// Maximum corner, f16 bits.
    pub max: [u16; 3],
}

const _: () = assert!(size_of::<HalfAabb>() == 12);

impl HalfAabb {
    /// The smallest half box containing `[min, max]`: min rounded down, max rounded up.
    /// Fails if a coordinate is not finite, rounds beyond ±[`f16::MAX`], or `min > max`.
    pub fn from_aabb(min: Vec3, max: Vec3) -> Result<HalfAabb, Error> {
        let mut out = HalfAabb::default();
        for i in 0..3 {
            let (lo, hi) = (min[i], max[i]);
            for v in [lo, hi] {
                if !v.is_finite() || v.abs() > f16::MAX.to_f32_const() {
                    return Err(Error::FloatOutOfRange {
                        field: Field::HalfBounds,
                        value: f64::from(v),
                        max: f16::MAX.to_f64(),
                    });
                }
            }
            if lo > hi {
                return Err(Error::Inverted {
                    field: Field::HalfBounds,
                    min: f64::from(lo),
                    max: f64::from(hi),
                });
            }
            let (l, h) = (f16_floor(lo), f16_ceil(hi));
            if !l.is_finite() || !h.is_finite() {
                return Err(Error::FloatOutOfRange {
                    field: Field::HalfBounds,
                    value: f64::from(if l.is_finite() { hi } else { lo }),
                    max: f16::MAX.to_f64(),
                });
            }
            out.min[i] = l.to_bits();
            out.max[i] = h.to_bits();
        }
        Ok(out)
    }

    /// The minimum corner.
    #[must_use]
    #[inline]
    pub fn min(&self) -> Vec3 {
        half3(self.min)
    }

    /// The maximum corner.
    #[must_use]
    #[inline]
    pub fn max(&self) -> Vec3 {
        half3(self.max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn branchless_half_decode_matches_half_for_every_pattern() {
        for h in 0..=u16::MAX {
            let want = f16::from_bits(h).to_f32();
            let got = half_to_f32_branchless(h);
            if want.is_nan() {
                assert!(got.is_nan(), "{h:#x}");
                assert_eq!(got.to_bits() & 0x8000_0000, want.to_bits() & 0x8000_0000);
            } else {
                assert_eq!(got.to_bits(), want.to_bits(), "{h:#x}");
            }
        }
    }

    #[test]
    fn half_aabb_is_conservative() {
        let min = Vec3::new(0.1, -3.3333, 1000.7);
        let max = Vec3::new(0.2, -1.0001, 2049.3);
        let h = HalfAabb::from_aabb(min, max).unwrap();
        assert!(h.min().cmple(min).all() && h.max().cmpge(max).all());
        assert_eq!(h.min().x, f16::from_bits(h.min[0]).to_f32());
        // Exact values stay exact.
        let h = HalfAabb::from_aabb(Vec3::splat(-2.0), Vec3::splat(0.5)).unwrap();
        assert_eq!((h.min(), h.max()), (Vec3::splat(-2.0), Vec3::splat(0.5)));
        // Zero rounds to itself; a tiny positive max rounds up past zero.
        let h = HalfAabb::from_aabb(Vec3::ZERO, Vec3::splat(1e-9)).unwrap();
        assert!(h.max().x > 0.0 && h.min().x == 0.0);
        assert!(HalfAabb::from_aabb(Vec3::ZERO, Vec3::splat(70_000.0)).is_err());
        assert!(HalfAabb::from_aabb(Vec3::ONE, Vec3::ZERO).is_err());
        assert!(HalfAabb::from_aabb(Vec3::NAN, Vec3::ZERO).is_err());
        // 65504 is representable; just above rounds up to infinity and is refused.
        assert!(HalfAabb::from_aabb(Vec3::ZERO, Vec3::splat(65504.0)).is_ok());
        assert!(HalfAabb::from_aabb(Vec3::ZERO, Vec3::splat(65504.5)).is_err());
    }
}
