//! Hilbert keys: roundtrips, the defining property (consecutive keys are face-adjacent
//! cells, key 0 at the origin), the lindel crate as an independent reference, batch paths.

use morton::{Path, hilbert};
use proptest::prelude::*;

fn manhattan<const N: usize>(a: [u32; N], b: [u32; N]) -> u32 {
    (0..N).map(|i| a[i].abs_diff(b[i])).sum()
}

#[test]
fn order_one_2d_and_start() {
    assert_eq!(hilbert::encode2_u32(0, 0), 0);
    assert_eq!(hilbert::encode3_u32(0, 0, 0), 0);
    assert_eq!(hilbert::encode3_u64(0, 0, 0), 0);
    assert_eq!(hilbert::encode2_u64(0, 0), 0);
    assert_eq!(hilbert::encode_generic([0, 0], 1).unwrap(), 0);
    assert_eq!(hilbert::encode_generic([0, 1], 1).unwrap(), 1);
    assert_eq!(hilbert::encode_generic([1, 1], 1).unwrap(), 2);
    assert_eq!(hilbert::encode_generic([1, 0], 1).unwrap(), 3);
}

/// Walk the whole curve of small grids: every key is a distinct cell one step from the
/// previous one.
#[test]
fn full_walks_are_face_adjacent() {
    for bits in 1..=5u32 {
        let n = 1u64 << (3 * bits);
        let mut seen = vec![false; n as usize];
        let mut prev = [0u32; 3];
        for key in 0..n {
            let c: [u32; 3] = hilbert::decode_generic(key, bits).unwrap();
            assert_eq!(hilbert::encode_generic(c, bits).unwrap(), key);
            let idx = (c[0] | c[1] << bits | c[2] << (2 * bits)) as usize;
            assert!(!seen[idx]);
            seen[idx] = true;
            if key > 0 {
                assert_eq!(manhattan(prev, c), 1, "bits {bits} key {key}");
            }
            prev = c;
        }
    }
    for bits in 1..=7u32 {
        let mut prev = [0u32; 2];
        for key in 0..(1u64 << (2 * bits)) {
            let c: [u32; 2] = hilbert::decode_generic(key, bits).unwrap();
            assert_eq!(hilbert::encode_generic(c, bits).unwrap(), key);
            if key > 0 {
                assert_eq!(manhattan(prev, c), 1);
            }
            prev = c;
        }
    }
}

/// The fixed-width functions are the generic form at their widths.
#[test]
fn fixed_widths_walk_adjacent_at_the_top_too() {
    for start in [0u32, 12_345, (1 << 30) - 5_000] {
        assert_walk_adjacent(start..(start + 5_000).min(1 << 30), |key| {
            let c = hilbert::decode3_u32(key);
            assert_eq!(hilbert::encode3_u32(c[0], c[1], c[2]), key);
            c
        });
    }
    for start in [0u64, 1 << 40, (1 << 63) - 3_000] {
        assert_walk_adjacent(start..start + 2_999, hilbert::decode3_u64);
    }
    for start in [0u32, u32::MAX - 3_000] {
        assert_walk_adjacent(start..start + 2_999, hilbert::decode2_u32);
    }
    for start in [0u64, u64::MAX - 3_000] {
        assert_walk_adjacent(start..start + 2_999, hilbert::decode2_u64);
    }
}

/// Asserts that each of `keys` after the first decodes to a cell one step from the
/// previous key's.
fn assert_walk_adjacent<K, const N: usize>(
    mut keys: impl Iterator<Item = K>,
    decode: impl Fn(K) -> [u32; N],
) where
    K: Copy + std::fmt::Display,
{
    let mut prev = decode(keys.next().unwrap());
    for key in keys {
        let c = decode(key);
        assert_eq!(manhattan(prev, c), 1, "key {key}");
        prev = c;
    }
}

#[test]
fn generic_rejects_bad_bits() {
    assert!(hilbert::encode_generic([1u32, 2, 3], 0).is_err());
    assert!(hilbert::encode_generic([1u32, 2, 3], 22).is_err());
    assert!(hilbert::encode_generic([1u32, 2], 32).is_ok());
    assert!(hilbert::decode_generic::<2>(5, 33).is_err());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn roundtrips(x: u32, y: u32, z: u32, k32: u32, k64: u64) {
        let m = |v: u32, b: u32| if b == 32 { v } else { v & ((1 << b) - 1) };
        prop_assert_eq!(hilbert::decode2_u32(hilbert::encode2_u32(x, y)), [m(x, 16), m(y, 16)]);
        prop_assert_eq!(hilbert::decode2_u64(hilbert::encode2_u64(x, y)), [x, y]);
        prop_assert_eq!(hilbert::decode3_u32(hilbert::encode3_u32(x, y, z)), [m(x, 10), m(y, 10), m(z, 10)]);
        prop_assert_eq!(hilbert::decode3_u64(hilbert::encode3_u64(x, y, z)), [m(x, 21), m(y, 21), m(z, 21)]);
        let [a, b] = hilbert::decode2_u32(k32);
        prop_assert_eq!(hilbert::encode2_u32(a, b), k32);
        let [a, b, c] = hilbert::decode3_u32(k32);
        prop_assert_eq!(hilbert::encode3_u32(a, b, c), k32 & 0x3fff_ffff);
        let [a, b, c] = hilbert::decode3_u64(k64);
        prop_assert_eq!(hilbert::encode3_u64(a, b, c), k64 & !(1 << 63));
        let [a, b] = hilbert::decode2_u64(k64);
        prop_assert_eq!(hilbert::encode2_u64(a, b), k64);
    }

    #[test]
    fn fixed_widths_equal_generic(x: u32, y: u32, z: u32) {
        prop_assert_eq!(hilbert::encode3_u32(x, y, z) as u64, hilbert::encode_generic([x, y, z], 10).unwrap());
        prop_assert_eq!(hilbert::encode3_u64(x, y, z), hilbert::encode_generic([x, y, z], 21).unwrap());
        prop_assert_eq!(hilbert::encode2_u32(x, y) as u64, hilbert::encode_generic([x, y], 16).unwrap());
        prop_assert_eq!(hilbert::encode2_u64(x, y), hilbert::encode_generic([x, y], 32).unwrap());
    }

    /// lindel (an independent implementation of Skilling's method) at the widths it has.
    #[test]
    fn matches_lindel(x: u8, y: u8, z: u8, a: u16, b: u16) {
        let ours = hilbert::encode_generic([x as u32, y as u32, z as u32], 8).unwrap();
        let theirs: u32 = lindel::hilbert_encode([x, y, z]);
        prop_assert_eq!(ours, theirs as u64);
        let ours = hilbert::encode_generic([a as u32, b as u32], 16).unwrap();
        let theirs: u32 = lindel::hilbert_encode([a, b]);
        prop_assert_eq!(ours, theirs as u64);
        prop_assert_eq!(ours, hilbert::encode2_u32(a as u32, b as u32) as u64);
        let back: [u16; 2] = lindel::hilbert_decode(theirs);
        prop_assert_eq!(hilbert::decode2_u32(theirs), [back[0] as u32, back[1] as u32]);
    }

    #[test]
    fn batch_paths_equal_scalar(coords in proptest::collection::vec(any::<[u32; 3]>(), 0..70)) {
        let xs: Vec<u32> = coords.iter().map(|c| c[0]).collect();
        let ys: Vec<u32> = coords.iter().map(|c| c[1]).collect();
        let zs: Vec<u32> = coords.iter().map(|c| c[2]).collect();
        let n = coords.len();
        for path in Path::available() {
            let (mut o32, mut o64) = (vec![0u32; n], vec![0u64; n]);
            hilbert::encode3_u32_soa_with(path, &xs, &ys, &zs, &mut o32).unwrap();
            hilbert::encode3_u64_soa_with(path, &xs, &ys, &zs, &mut o64).unwrap();
            for i in 0..n {
                prop_assert_eq!(o32[i], hilbert::encode3_u32(xs[i], ys[i], zs[i]));
                prop_assert_eq!(o64[i], hilbert::encode3_u64(xs[i], ys[i], zs[i]));
            }
            hilbert::encode2_u32_soa_with(path, &xs, &ys, &mut o32).unwrap();
            hilbert::encode2_u64_soa_with(path, &xs, &ys, &mut o64).unwrap();
            for i in 0..n {
                prop_assert_eq!(o32[i], hilbert::encode2_u32(xs[i], ys[i]));
                prop_assert_eq!(o64[i], hilbert::encode2_u64(xs[i], ys[i]));
            }
        }
    }
}

#[test]
fn batch_rejects_mismatched_lengths() {
    let mut out = [0u32; 2];
    assert!(hilbert::encode3_u32_soa(&[1, 2], &[1, 2], &[1], &mut out).is_err());
    assert!(hilbert::encode2_u32_soa(&[1, 2], &[1, 2], &mut out[..1]).is_err());
}
