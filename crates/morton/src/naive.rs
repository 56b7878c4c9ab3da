//! Test-support references: Morton codes bit by bit, independent of every method the crate
//! ships. The unit tests, `tests/codes.rs` and the `fuzzing` crate all check against these
//! one copies; they are public only for those callers (hidden from the docs) and far too slow
//! for real use.

/// The code of `c`: bit `i` of axis `a` at bit `D * i + a`, for the low `bits` bits.
#[must_use]
pub fn naive_encode<const D: usize>(c: [u32; D], bits: u32) -> u64 {
    let mut key = 0u64;
    for i in 0..bits {
        for (axis, &v) in c.iter().enumerate() {
            key |= (((v >> i) & 1) as u64) << (D as u32 * i + axis as u32);
        }
    }
    key
}

/// The inverse of [`naive_encode`].
#[must_use]
pub fn naive_decode<const D: usize>(key: u64, bits: u32) -> [u32; D] {
    let mut c = [0u32; D];
    for i in 0..bits {
        for (axis, v) in c.iter_mut().enumerate() {
            *v |= (((key >> (D as u32 * i + axis as u32)) & 1) as u32) << i;
        }
    }
    c
}

/// `v`'s low `bits` bits (all of `v` for `bits >= 32`): a coordinate masked to a code's
/// width.
#[must_use]
pub fn low(v: u32, bits: u32) -> u32 {
    if bits >= 32 { v } else { v & ((1 << bits) - 1) }
}
