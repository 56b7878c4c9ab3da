//! Order-preserving `f32` words for atomics: [`ordered_f32`] maps a float to a `u32` whose
//! unsigned order is the float's order (`-0.0` just below `+0.0`), so `atomicMax` /
//! `atomicMin` on the words keep the largest / smallest float; [`unordered_f32`] maps back.
//! Zero-initialised memory holds the smallest word (below every float's), so a minimum kept
//! as the maximum of the complemented words (`!ordered_f32(x)`) starts from a neutral 0 too.
//! WGSL twins: `wave_ordered_f32` / `wave_unordered_f32` in `wave::common`. NaNs map
//! beyond the infinities (positive NaNs above `+inf`, negative ones below `-inf`).

/// The word of `f` (see the module docs).
#[inline]
pub const fn ordered_f32(f: f32) -> u32 {
    let b = f.to_bits();
    if b & 0x8000_0000 != 0 {
        !b
    } else {
        b | 0x8000_0000
    }
}

/// The float of a word [`ordered_f32`] made (exact inverse on every bit pattern).
#[inline]
pub const fn unordered_f32(u: u32) -> f32 {
    f32::from_bits(if u & 0x8000_0000 != 0 {
        u & 0x7fff_ffff
    } else {
        !u
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Fixed vectors across the sign boundary and the ends.
    #[test]
    fn fixed_words() {
        assert_eq!(ordered_f32(0.0), 0x8000_0000);
        assert_eq!(ordered_f32(-0.0), 0x7fff_ffff);
        assert_eq!(ordered_f32(1.0), 0xbf80_0000);
        assert_eq!(ordered_f32(-1.0), 0x407f_ffff);
        assert_eq!(ordered_f32(f32::INFINITY), 0xff80_0000);
        assert_eq!(ordered_f32(f32::NEG_INFINITY), 0x007f_ffff);
        assert!(ordered_f32(f32::MIN_POSITIVE) > ordered_f32(0.0));
        assert!(ordered_f32(-f32::MIN_POSITIVE) < ordered_f32(-0.0));
    }

    proptest! {
        /// Every bit pattern comes back; non-NaN floats keep their order.
        #[test]
        fn roundtrip_and_order(a in any::<u32>(), b in any::<u32>()) {
            let (x, y) = (f32::from_bits(a), f32::from_bits(b));
            prop_assert_eq!(unordered_f32(ordered_f32(x)).to_bits(), a);
            if !x.is_nan() && !y.is_nan() && x < y {
                prop_assert!(ordered_f32(x) < ordered_f32(y));
            }
        }
    }
}
