//! The 12-bit [`LodDistance`] minifloat and the [`LodRange`] bracket (format in the
//! [parent module's docs](super)).

use super::{LOD_CODE_INFINITY, LOD_DISTANCE_MAX};
use crate::{Error, Field};

/// A 12-bit LOD distance code (see the [module docs](super) for the format).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
// The code is read and written by the instance packing beside this file.
pub struct LodDistance(pub(super) u16);

impl LodDistance {
    /// 0 m.
    pub const ZERO: LodDistance = LodDistance(0);
    /// +infinity: a range ending here never switches out.
    pub const INFINITY: LodDistance = LodDistance(LOD_CODE_INFINITY);

    /// The code for `metres`, rounded to nearest. `f32::INFINITY` gives
    /// [`INFINITY`](Self::INFINITY). Negative, NaN, or finite above
    /// [`LOD_DISTANCE_MAX`] (after rounding) is an error naming `field`.
    pub fn encode(metres: f32, field: Field) -> Result<LodDistance, Error> {
        if metres == f32::INFINITY {
            return Ok(Self::INFINITY);
        }
        let err = Error::FloatOutOfRange {
            field,
            value: f64::from(metres),
            max: f64::from(LOD_DISTANCE_MAX),
        };
        // `!(x >= 0)` also catches NaN.
        if metres.is_nan() || metres < 0.0 {
            return Err(err);
        }
        if metres < 4.0 {
            // Exact multiples of 1/64 below 4 m; 255.5 and up rounds to code 256 = 4.0 m.
            let m = crate::math::floor(metres * 64.0 + 0.5) as u16;
            return Ok(LodDistance(m));
        }
        // metres >= 4: the f32's biased exponent is >= 129. Round the 23-bit mantissa to 8
        // bits (half up); a carry rolls into the exponent, which is what we want.
        let bits = metres.to_bits().wrapping_add(1 << 14) >> 15;
        let e = (bits >> 8) as i32 - 128;
        let m = bits & 0xff;
        if !(1..=15).contains(&e) || (e == 15 && m == 0xff) {
            return Err(err);
        }
        Ok(LodDistance(((e as u16) << 8) | m as u16))
    }

    /// The code for `metres` with the generic field name ([`Field::LodDistance`]).
    pub fn from_metres(metres: f32) -> Result<LodDistance, Error> {
        Self::encode(metres, Field::LodDistance)
    }

    /// A raw 12-bit code; `None` above `0xfff`.
    #[must_use]
    pub const fn from_code(code: u16) -> Option<LodDistance> {
        if code <= LOD_CODE_INFINITY {
            Some(LodDistance(code))
        } else {
            None
        }
    }

    /// The raw 12-bit code.
    #[must_use]
    pub const fn code(self) -> u16 {
        self.0
    }

    /// The distance in metres (exact; +infinity for [`INFINITY`](Self::INFINITY)).
    #[must_use]
    #[inline]
    pub fn metres(self) -> f32 {
        decode_lod(u32::from(self.0))
    }
}

/// Decodes a 12-bit LOD code to metres: exact, and bit-identical to the WGSL twin.
#[inline]
pub(crate) fn decode_lod(code: u32) -> f32 {
    let e = code >> 8;
    let m = code & 0xff;
    // Both forms, then selects (no branch in the query's inner loop).
    let normal = f32::from_bits(((e + 128) << 23) | (m << 15));
    let sub = m as f32 * (1.0 / 64.0);
    let v = if e == 0 { sub } else { normal };
    if code == u32::from(LOD_CODE_INFINITY) {
        f32::INFINITY
    } else {
        v
    }
}

/// A LOD level's distance bracket `[min, max)` in metres, before the object's and the
/// view's LOD scales. A level is selected when the distance from the view's LOD point to
/// the level's world-space bounds lies in `[min * s, max * s)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct LodRange {
    /// Start of the bracket (inclusive).
    pub min: LodDistance,
    /// End of the bracket (exclusive).
    pub max: LodDistance,
}

impl LodRange {
    /// `[0, infinity)`: the padding level, always selected.
    pub const ALWAYS: LodRange = LodRange {
        min: LodDistance::ZERO,
        max: LodDistance::INFINITY,
    };

    /// The bracket `[min, max)` in metres, each rounded to its 12-bit code; `fields`
    /// names the two ends in errors. Fails if either end is out of range or `min > max`.
    pub fn new(min: f32, max: f32, fields: (Field, Field)) -> Result<LodRange, Error> {
        let lo = LodDistance::encode(min, fields.0)?;
        let hi = LodDistance::encode(max, fields.1)?;
        if lo > hi {
            return Err(Error::Inverted {
                field: fields.0,
                min: f64::from(min),
                max: f64::from(max),
            });
        }
        Ok(LodRange { min: lo, max: hi })
    }

    /// `[min, max)` with the generic field name.
    pub fn from_metres(min: f32, max: f32) -> Result<LodRange, Error> {
        Self::new(min, max, (Field::LodDistance, Field::LodDistance))
    }

    /// Whether this is the always-on padding bracket.
    #[must_use]
    pub fn is_always(self) -> bool {
        self == Self::ALWAYS
    }

    /// The LOD test: `min² s² <= d² < max² s²` (`d2` the squared distance, `scale2` the
    /// squared combined LOD scale), as the query evaluates it in f32.
    #[must_use]
    #[inline]
    pub fn selects(self, d2: f32, scale2: f32) -> bool {
        lod_selects(u32::from(self.min.0), u32::from(self.max.0), d2, scale2)
    }
}

/// The LOD test on raw codes (the query's inner loop).
#[inline]
pub(crate) fn lod_selects(min_code: u32, max_code: u32, d2: f32, scale2: f32) -> bool {
    let lo = decode_lod(min_code);
    let hi = decode_lod(max_code);
    d2 >= lo * lo * scale2 && d2 < hi * hi * scale2
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::records::LOD_DISTANCE_MAX;

    #[test]
    fn lod_code_vectors() {
        let m = |d: f32| LodDistance::from_metres(d).unwrap().code();
        assert_eq!(m(0.0), 0);
        assert_eq!(m(1.0 / 64.0), 1);
        assert_eq!(m(3.984375), 255);
        assert_eq!(m(4.0), 0x100);
        assert_eq!(m(8.0), 0x200);
        assert_eq!(m(5.0), 0x140); // 5 = 4 * (1 + 64/256)
        assert_eq!(m(LOD_DISTANCE_MAX), 0xffe);
        assert_eq!(m(f32::INFINITY), 0xfff);
        assert_eq!(LodDistance(0x140).metres(), 5.0);
        assert_eq!(LodDistance(0xffe).metres(), LOD_DISTANCE_MAX);
        assert_eq!(LodDistance(0xfff).metres(), f32::INFINITY);
        assert_eq!(LodDistance(0x0ff).metres(), 255.0 / 64.0);
        assert!(LodDistance::from_metres(-1.0).is_err());
        assert!(LodDistance::from_metres(f32::NAN).is_err());
        assert!(LodDistance::from_metres(131_000.0).is_err());
        assert_eq!(
            LodDistance::encode(-0.5, Field::ChildLodMax),
            Err(Error::FloatOutOfRange {
                field: Field::ChildLodMax,
                value: -0.5,
                max: 130560.0
            })
        );
    }

    #[test]
    fn lod_codes_monotonic_and_decode_exact() {
        let mut prev = -1.0f32;
        for c in 0..0xfffu16 {
            let v = LodDistance(c).metres();
            assert!(v > prev, "code {c:#x}");
            // Decoding against the definition in f64.
            let e = u32::from(c >> 8);
            let mm = f64::from(c & 0xff);
            let want = if e == 0 {
                mm / 64.0
            } else {
                (1.0 + mm / 256.0) * 2f64.powi(e as i32 + 1)
            };
            assert_eq!(f64::from(v), want, "code {c:#x}");
            assert_eq!(LodDistance::from_metres(v).unwrap().code(), c);
            prev = v;
        }
    }

    #[test]
    fn lod_error_bound() {
        // Dense sweep: error at most half a step (1/128 m below 4 m, 2^-9 relative above).
        let mut d = 0.0f32;
        while d < 130_000.0 {
            let q = LodDistance::from_metres(d).unwrap().metres();
            let err = (f64::from(q) - f64::from(d)).abs();
            let bound = if d < 4.0 {
                1.0 / 128.0
            } else {
                f64::from(d) / 512.0
            };
            assert!(err <= bound + 1e-12, "d {d} q {q}");
            d = d * 1.0007 + 0.0013;
        }
    }
}
