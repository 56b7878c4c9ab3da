//! The scalar codecs of the vertex's fields, each the Rust twin of a WGSL pack or unpack
//! built-in or of a `visbuf::vertex` function: half floats, 16:16 UV fixed point, unorm8,
//! snorm 10:10:10:2 and square-rooted unorm8 (error bounds in the [parent module's
//! docs](super)).

use glam::{Vec2, Vec4};
use half::f16;

use super::{SNORM_10_10_10_2_W_SHIFT, UV_SCALE};
use crate::{Error, math};

/// `floor(v)` as an integer, exactly, for `abs(v) < 2^31` (NaN gives 0): a truncation and a
/// compare, much cheaper than `floorf` on x86-64 without SSE4.1.
#[inline]
fn floor_i32(v: f32) -> i32 {
    let t = v as i32;
    t - i32::from((t as f32) > v)
}

#[inline]
pub(super) fn finite(field: &'static str, x: f32) -> Result<f32, Error> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(Error::NonFinite { field })
    }
}

#[inline]
fn in_range(field: &'static str, x: f32, min: f32, max: f32) -> Result<f32, Error> {
    finite(field, x)?;
    if x < min || x > max {
        return Err(Error::ValueOutOfRange {
            field,
            value: x,
            min,
            max,
        });
    }
    Ok(x)
}

/// `x` as an [`f16`] (round to nearest even); `None` if `x` is not finite or
/// `abs(x) > f16::MAX` (65504).
#[inline]
fn checked_half(x: f32) -> Option<f16> {
    (x.is_finite() && x.abs() <= f16::MAX.to_f32()).then(|| f16::from_f32(x))
}

#[inline]
pub(super) fn half_field(field: &'static str, x: f32) -> Result<u32, Error> {
    let max = f16::MAX.to_f32();
    in_range(field, x, -max, max)?;
    Ok(u32::from(f16::from_f32(x).to_bits()))
}

/// Two half floats in one word, `x` low: WGSL `pack2x16float`. `None` if either is out of
/// the half range or not finite.
#[must_use]
#[inline]
pub fn try_pack_half2(v: Vec2) -> Option<u32> {
    let (x, y) = (checked_half(v.x)?, checked_half(v.y)?);
    Some(u32::from(x.to_bits()) | (u32::from(y.to_bits()) << 16))
}

/// WGSL `unpack2x16float`: exact (`f16::to_f32`).
#[must_use]
#[inline]
pub fn unpack_half2(word: u32) -> Vec2 {
    Vec2::new(
        f16::from_bits(word as u16).to_f32(),
        f16::from_bits((word >> 16) as u16).to_f32(),
    )
}

/// One UV component to its 16-bit code `floor(uv * 8192 + 0.5)`; errors outside
/// `[-2^-14, UV_MAX)`, i.e. what does not round into `0..=65535`.
#[inline]
pub fn pack_uv_component(field: &'static str, uv: f32) -> Result<u16, Error> {
    finite(field, uv)?;
    let v = uv * UV_SCALE + 0.5;
    let q = if (0.0..65536.0).contains(&v) {
        floor_i32(v)
    } else {
        -1
    };
    if !(0..=65535).contains(&q) {
        return Err(Error::ValueOutOfRange {
            field,
            value: uv,
            min: 0.0,
            max: 65535.0 / UV_SCALE,
        });
    }
    Ok(q as u16)
}

/// UV as 16:16 fixed point scaled down by 8 (u low): range `[0, 8)`, step `1 / 8192`.
#[inline]
pub fn pack_uv_16_16(uv: Vec2) -> Result<u32, Error> {
    Ok(u32::from(pack_uv_component("uv.x", uv.x)?)
        | (u32::from(pack_uv_component("uv.y", uv.y)?) << 16))
}

/// The inverse of [`pack_uv_16_16`]: `code / 8192` per component.
#[must_use]
#[inline]
pub fn unpack_uv_16_16(word: u32) -> Vec2 {
    Vec2::new((word & 0xffff) as f32, (word >> 16) as f32) / UV_SCALE
}

#[inline]
fn unorm8(x: f32) -> u32 {
    // WGSL pack4x8unorm: floor(0.5 + 255 * clamp(x, 0, 1)); non-negative, so truncation.
    (0.5 + 255.0 * x.clamp(0.0, 1.0)) as u32
}

/// RGBA8 unorm, R in the low byte: WGSL `pack4x8unorm` (clamps to `[0, 1]`; NaN gives 0).
#[must_use]
#[inline]
pub fn pack_unorm8x4(c: Vec4) -> u32 {
    let f = |x: f32| if x.is_nan() { 0 } else { unorm8(x) };
    f(c.x) | (f(c.y) << 8) | (f(c.z) << 16) | (f(c.w) << 24)
}

/// WGSL `unpack4x8unorm`.
#[must_use]
#[inline]
pub fn unpack_unorm8x4(word: u32) -> Vec4 {
    Vec4::new(
        (word & 0xff) as f32,
        ((word >> 8) & 0xff) as f32,
        ((word >> 16) & 0xff) as f32,
        (word >> 24) as f32,
    ) / 255.0
}

#[inline]
fn snorm(x: f32, max: f32, bits: u32) -> u32 {
    let x = if x.is_nan() { 0.0 } else { x.clamp(-1.0, 1.0) };
    (floor_i32(0.5 + max * x) as u32) & ((1 << bits) - 1)
}

#[inline]
fn unsnorm(code: u32, bits: u32, max: f32) -> f32 {
    // Sign-extend `bits` wide, then scale; the most negative code decodes to -1 like -max.
    let shift = 32 - bits;
    let q = ((code << shift) as i32) >> shift;
    (q as f32 / max).max(-1.0)
}

/// Signed normalised 10:10:10:2 (x in bits 9..0): xyz as `floor(0.5 + 511 * c)`, w as
/// `floor(0.5 + w)` in 2 bits, each clamped to `[-1, 1]` first (NaN gives 0).
#[must_use]
#[inline]
pub fn pack_snorm_10_10_10_2(v: Vec4) -> u32 {
    snorm(v.x, 511.0, 10)
        | (snorm(v.y, 511.0, 10) << 10)
        | (snorm(v.z, 511.0, 10) << 20)
        | (snorm(v.w, 1.0, 2) << SNORM_10_10_10_2_W_SHIFT)
}

/// The inverse of [`pack_snorm_10_10_10_2`]: components in `[-1, 1]` (code -512 and the
/// 2-bit code -2 decode to -1).
#[must_use]
#[inline]
pub fn unpack_snorm_10_10_10_2(word: u32) -> Vec4 {
    Vec4::new(
        unsnorm(word & 0x3ff, 10, 511.0),
        unsnorm((word >> 10) & 0x3ff, 10, 511.0),
        unsnorm((word >> 20) & 0x3ff, 10, 511.0),
        unsnorm(word >> SNORM_10_10_10_2_W_SHIFT, 2, 1.0),
    )
}

/// Two colour channels as square-rooted unorm8 in 16 bits (x low): `floor(0.5 + 255 *
/// sqrt(clamp(c, 0, 1)))`. Gives dark values more codes, like sRGB (NaN gives 0).
#[must_use]
#[inline]
pub fn pack_sqrt_unorm8x2(c: Vec2) -> u16 {
    let f = |x: f32| {
        if x.is_nan() {
            0
        } else {
            unorm8(math::sqrt(x.clamp(0.0, 1.0)))
        }
    };
    (f(c.x) | (f(c.y) << 8)) as u16
}

/// The inverse of [`pack_sqrt_unorm8x2`]: `(code / 255)^2` per channel.
#[must_use]
#[inline]
pub fn unpack_sqrt_unorm8x2(bits: u16) -> Vec2 {
    let s = Vec2::new((bits & 0xff) as f32, (bits >> 8) as f32) / 255.0;
    s * s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vertex::UV_MAX;
    use alloc::vec::Vec;
    use glam::Vec3;

    /// Every finite half value, ascending (independent of `half`'s conversion: built from
    /// the IEEE binary16 definition).
    fn half_values() -> Vec<(f64, u16)> {
        let mut v: Vec<(f64, u16)> = (0u16..=0xffff)
            .filter(|b| (b >> 10) & 0x1f != 0x1f)
            .map(|b| {
                let e = ((b >> 10) & 0x1f) as i32;
                let m = (b & 0x3ff) as f64;
                let mag = if e == 0 {
                    m * 2f64.powi(-24)
                } else {
                    (1.0 + m / 1024.0) * 2f64.powi(e - 15)
                };
                (if b & 0x8000 != 0 { -mag } else { mag }, b)
            })
            .collect();
        v.sort_by(|a, b| a.0.partial_cmp(&b.0).unwrap());
        v
    }

    #[test]
    fn half_decode_matches_the_ieee_definition_for_every_code() {
        for (value, bits) in half_values() {
            // Low half and high half of the word: the same code in either place.
            let word = u32::from(bits) | (u32::from(bits ^ 0x8000) << 16);
            let v = unpack_half2(word);
            assert_eq!(v.x as f64, value, "code {bits:#06x}");
            assert_eq!(v.y as f64, -value, "code {:#06x}", bits ^ 0x8000);
        }
    }

    #[test]
    fn half_encode_is_nearest_and_within_the_documented_bound() {
        let table = half_values();
        let mut rng = testkit::Rng::new(0x1234_5678_9abc_def0);
        for i in 0..200_000 {
            // Spread over magnitudes 2^-26 .. 2^16 and both signs.
            let e = rng.below(42);
            let x = (f64::from(rng.next_u32()) / 4_294_967_296.0 + 1.0) * 2f64.powi(e as i32 - 26);
            let x = if i % 2 == 0 { x } else { -x };
            let x = x as f32;
            let Some(word) = try_pack_half2(Vec2::new(x, -x)) else {
                assert!(x.abs() > 65504.0);
                continue;
            };
            assert_eq!(
                word >> 16,
                (word & 0xffff) ^ 0x8000,
                "x={x}: y = -x in the high half"
            );
            let got = unpack_half2(word).x as f64;
            let err = (got - x as f64).abs();
            // Nearest: no representable value is closer.
            let k = table.partition_point(|(v, _)| *v < x as f64);
            for (v, _) in &table[k.saturating_sub(1)..(k + 1).min(table.len())] {
                assert!(err <= (v - x as f64).abs(), "x={x} got {got}");
            }
            let bound = if (x.abs() as f64) >= 2f64.powi(-14) {
                (x.abs() as f64) * 2f64.powi(-11)
            } else {
                2f64.powi(-25)
            };
            assert!(err <= bound, "x={x} err={err} bound={bound}");
        }
        assert_eq!(try_pack_half2(Vec2::new(65504.0, -1.0)), Some(0xbc00_7bff));
        assert_eq!(try_pack_half2(Vec2::new(65505.0, 0.0)), None);
        assert_eq!(try_pack_half2(Vec2::new(0.0, -65505.0)), None);
        assert_eq!(try_pack_half2(Vec2::new(f32::NAN, 0.0)), None);
        assert_eq!(try_pack_half2(Vec2::new(0.0, f32::INFINITY)), None);
    }

    /// A line-by-line Rust transliteration of `visbuf_pack_half` / `visbuf_unpack_half` in
    /// vertex.wgsl, checked against the `half` crate: the WGSL algorithm is right if the
    /// WGSL text says what this says (no device test runs the text itself yet).
    fn wgsl_pack_half(x: f32) -> u32 {
        let b = x.to_bits();
        let sign = (b >> 16) & 0x8000;
        let a = b & 0x7fff_ffff;
        if a > 0x7f80_0000 {
            return sign | 0x7e00;
        }
        if a >= 0x477f_f000 {
            return sign | 0x7c00;
        }
        if a < 0x3880_0000 {
            return sign | (f32::from_bits(a) * 16_777_216.0).round_ties_even() as u32;
        }
        let m = a - 0x3800_0000;
        sign | ((m + 0xfff + ((m >> 13) & 1)) >> 13)
    }

    fn wgsl_unpack_half(bits: u32) -> f32 {
        let sign = (bits & 0x8000) << 16;
        let e = (bits >> 10) & 0x1f;
        let m = bits & 0x3ff;
        if e == 0 {
            let mag = m as f32 * 2f32.powi(-24);
            return if sign != 0 { -mag } else { mag };
        }
        if e == 31 {
            return f32::from_bits(sign | 0x7f80_0000 | (m << 13));
        }
        f32::from_bits(sign | ((e + 112) << 23) | (m << 13))
    }

    #[test]
    fn wgsl_half_algorithm_matches_the_half_crate() {
        for bits in 0..=0xffffu32 {
            let want = f16::from_bits(bits as u16).to_f32();
            let got = wgsl_unpack_half(bits);
            assert!(
                got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan()),
                "{bits:#x}"
            );
            // Every half value and every midpoint between neighbours (ties) encodes the same.
            if want.is_finite() {
                assert_eq!(
                    wgsl_pack_half(want),
                    u32::from(f16::from_f32(want).to_bits())
                );
                let next = f16::from_bits(bits as u16 + 1).to_f32();
                if next.is_finite() && bits & 0x7fff != 0x7bff {
                    let mid = ((want as f64 + next as f64) / 2.0) as f32;
                    for x in [
                        mid,
                        f32::from_bits(mid.to_bits() + 1),
                        f32::from_bits(mid.to_bits() - 1),
                    ] {
                        assert_eq!(
                            wgsl_pack_half(x),
                            u32::from(f16::from_f32(x).to_bits()),
                            "x={x:e}"
                        );
                    }
                }
            }
        }
        for x in [
            65504.0f32,
            65519.0,
            65520.0,
            1e9,
            f32::INFINITY,
            -f32::INFINITY,
            0.0,
            -0.0,
            1e-30,
        ] {
            assert_eq!(
                wgsl_pack_half(x),
                u32::from(f16::from_f32(x).to_bits()),
                "x={x:e}"
            );
        }
        assert!(f16::from_bits(wgsl_pack_half(f32::NAN) as u16).is_nan());
    }

    #[test]
    fn uv_codes_roundtrip_exhaustively_and_error_is_at_most_2_pow_minus_14() {
        for code in 0..=0xffffu32 {
            let w = code | (code.reverse_bits() >> 16) << 16;
            assert_eq!(pack_uv_16_16(unpack_uv_16_16(w)), Ok(w));
        }
        let mut worst = 0f64;
        for i in 0..=1_000_000u32 {
            let u = i as f32 * (UV_MAX / 1_000_001.0);
            let got = unpack_uv_16_16(pack_uv_16_16(Vec2::splat(u)).unwrap()).x;
            worst = worst.max((got as f64 - u as f64).abs());
        }
        assert!(worst <= 2f64.powi(-14), "{worst}");
        assert!(worst > 2f64.powi(-14) * 0.99, "the bound is tight: {worst}");
        assert!(matches!(
            pack_uv_16_16(Vec2::new(8.0, 0.0)),
            Err(Error::ValueOutOfRange { field: "uv.x", .. })
        ));
        assert!(matches!(
            pack_uv_16_16(Vec2::new(0.0, -0.001)),
            Err(Error::ValueOutOfRange { field: "uv.y", .. })
        ));
        assert_eq!(
            pack_uv_16_16(Vec2::new(f32::NAN, 0.0)),
            Err(Error::NonFinite { field: "uv.x" })
        );
    }

    #[test]
    fn unorm8_codes_roundtrip_and_error_is_half_a_step() {
        for code in 0..=255u32 {
            let w = code * 0x0101_0101;
            assert_eq!(pack_unorm8x4(unpack_unorm8x4(w)), w);
        }
        let mut worst = 0f64;
        for i in 0..=100_000u32 {
            let x = i as f32 / 100_000.0;
            let got = unpack_unorm8x4(pack_unorm8x4(Vec4::splat(x))).x;
            worst = worst.max((got as f64 - x as f64).abs());
        }
        assert!(worst <= 0.5 / 255.0 + 1e-7, "{worst}");
        assert_eq!(
            pack_unorm8x4(Vec4::new(-1.0, 2.0, f32::NAN, 0.5)),
            0x80_00_ff_00
        );
    }

    #[test]
    fn snorm_10_10_10_2_codes_roundtrip_and_error_is_half_a_step() {
        // Every 10-bit code (x), the others fixed; -512 decodes to -1 like -511.
        for code in 0..1024u32 {
            let w = code | (code << 10) | (code << 20) | (code & 3) << 30;
            let v = unpack_snorm_10_10_10_2(w);
            let q = ((code << 22) as i32 >> 22) as f32;
            assert_eq!(v.x, (q / 511.0).max(-1.0));
            let wq = ((code & 3) << 30) as i32 >> 30;
            assert_eq!(v.w, wq.max(-1) as f32);
            if code != 512 && (code & 3) != 2 {
                assert_eq!(pack_snorm_10_10_10_2(v), w, "code {code}");
            }
        }
        let mut worst = 0f64;
        for i in 0..=200_000u32 {
            let x = i as f32 / 100_000.0 - 1.0;
            let got = unpack_snorm_10_10_10_2(pack_snorm_10_10_10_2(Vec4::new(x, -x, x, 1.0)));
            worst = worst
                .max((got.x as f64 - x as f64).abs())
                .max((got.y as f64 + x as f64).abs());
            assert_eq!(got.w, 1.0);
        }
        assert!(worst <= 0.5 / 511.0 + 1e-7, "{worst}");
    }

    #[test]
    fn unit_normals_lose_at_most_a_tenth_of_a_degree() {
        let mut worst = 0f64;
        let n = 400;
        for i in 0..n {
            for j in 0..2 * n {
                let theta = core::f64::consts::PI * (i as f64 + 0.5) / n as f64;
                let phi = core::f64::consts::PI * j as f64 / n as f64;
                let v = Vec3::new(
                    (theta.sin() * phi.cos()) as f32,
                    (theta.sin() * phi.sin()) as f32,
                    theta.cos() as f32,
                );
                let got = unpack_snorm_10_10_10_2(pack_snorm_10_10_10_2(v.extend(0.0))).truncate();
                let c = (got.as_dvec3().normalize().dot(v.as_dvec3().normalize())).min(1.0);
                worst = worst.max(c.acos().to_degrees());
            }
        }
        assert!(worst < 0.1, "{worst} degrees");
    }

    #[test]
    fn sqrt_unorm8_error_is_within_the_documented_bound() {
        for code in 0..=0xffffu32 {
            assert_eq!(
                u32::from(pack_sqrt_unorm8x2(unpack_sqrt_unorm8x2(code as u16))),
                code
            );
        }
        for i in 0..=1_000_000u32 {
            let c = i as f32 / 1_000_000.0;
            let got = unpack_sqrt_unorm8x2(pack_sqrt_unorm8x2(Vec2::new(c, 1.0 - c)));
            for (g, x) in [(got.x, c), (got.y, 1.0 - c)] {
                let bound = (x as f64).sqrt() / 255.0 + 1.0 / (4.0 * 255.0 * 255.0) + 1e-6;
                assert!(((g - x) as f64).abs() <= bound, "c={x} got={g}");
            }
        }
        // Dark values: sqrt coding keeps 1e-4 within 4e-5 where plain unorm8 rounds to 0.
        let dark = unpack_sqrt_unorm8x2(pack_sqrt_unorm8x2(Vec2::splat(1e-4))).x;
        assert!((dark - 1e-4).abs() < 4e-5, "{dark}");
        assert_eq!(unpack_unorm8x4(pack_unorm8x4(Vec4::splat(1e-4))).x, 0.0);
    }
}
