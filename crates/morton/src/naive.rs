//! Test-only references: Morton codes bit by bit, independent of every method the crate
//! ships.

/// The code of `c`: bit `i` of axis `a` at bit `D * i + a`, for the low `bits` bits.
pub(crate) fn naive_encode<const D: usize>(c: [u32; D], bits: u32) -> u64 {
    let mut key = 0u64;
    for i in 0..bits {
        for (axis, &v) in c.iter().enumerate() {
            key |= (((v >> i) & 1) as u64) << (D as u32 * i + axis as u32);
        }
    }
    key
}

/// The inverse of [`naive_encode`].
pub(crate) fn naive_decode<const D: usize>(key: u64, bits: u32) -> [u32; D] {
    let mut c = [0u32; D];
    for i in 0..bits {
        for (axis, v) in c.iter_mut().enumerate() {
            *v |= (((key >> (D as u32 * i + axis as u32)) & 1) as u32) << i;
        }
    }
    c
}
