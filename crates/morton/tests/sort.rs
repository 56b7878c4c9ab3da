//! Sorting: the permutation against std's stable sort, stability, skipped digit passes.

use morton::{Error, sort_permutation, sort_permutation_into};
use proptest::prelude::*;

fn reference<K: Ord + Copy>(keys: &[K]) -> Vec<u32> {
    let mut idx: Vec<u32> = (0..keys.len() as u32).collect();
    idx.sort_by_key(|&i| keys[i as usize]); // stable
    idx
}

#[test]
fn small_cases() {
    assert_eq!(sort_permutation::<u32>(&[]).unwrap(), Vec::<u32>::new());
    assert_eq!(sort_permutation(&[5u32]).unwrap(), [0]);
    assert_eq!(sort_permutation(&[7u64, 7, 7]).unwrap(), [0, 1, 2]);
    assert_eq!(
        sort_permutation(&[u32::MAX, 0, 1 << 31]).unwrap(),
        [1, 2, 0]
    );
    assert_eq!(
        sort_permutation(&[u64::MAX, 0, 1 << 63, 1 << 32]).unwrap(),
        [1, 3, 2, 0]
    );
    let mut out = vec![99, 98];
    sort_permutation_into(&[3u32, 1, 2], &mut out).unwrap();
    assert_eq!(out, [1, 2, 0]);
}

#[test]
fn too_many_keys_is_an_error_value() {
    let e = Error::TooManyKeys {
        len: usize::MAX,
        max: morton::MAX_SORT_KEYS,
    };
    assert!(e.to_string().contains("sort limit"));
}

#[test]
fn stable_for_equal_keys() {
    // 1000 keys in 3 values: equal keys keep their input order.
    let keys: Vec<u64> = (0..1000u64).map(|i| ((i * 7919) % 3) << 40).collect();
    let perm = sort_permutation(&keys).unwrap();
    assert_eq!(perm, reference(&keys));
    for w in perm.windows(2) {
        let (a, b) = (w[0] as usize, w[1] as usize);
        assert!(keys[a] < keys[b] || (keys[a] == keys[b] && a < b));
    }
}

#[test]
fn morton_keys_of_a_grid_sort_to_the_curve() {
    // Every cell of a 16^3 grid in raster order: sorted by Morton key they decode to the
    // Z-order curve, key i at position i.
    let cells: Vec<[u32; 3]> = (0..4096u32)
        .map(|i| [i & 15, (i >> 4) & 15, i >> 8])
        .collect();
    let keys: Vec<u32> = cells
        .iter()
        .map(|c| morton::encode3_u32(c[0], c[1], c[2]))
        .collect();
    let perm = sort_permutation(&keys).unwrap();
    for (rank, &i) in perm.iter().enumerate() {
        assert_eq!(keys[i as usize], rank as u32);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn u32_matches_std(keys in proptest::collection::vec(any::<u32>(), 0..600), shift in 0u32..32) {
        let keys: Vec<u32> = keys.into_iter().map(|k| k >> shift).collect();
        prop_assert_eq!(sort_permutation(&keys).unwrap(), reference(&keys));
    }

    #[test]
    fn u64_matches_std(keys in proptest::collection::vec(any::<u64>(), 0..600), shift in 0u32..64) {
        let keys: Vec<u64> = keys.into_iter().map(|k| k >> shift).collect();
        prop_assert_eq!(sort_permutation(&keys).unwrap(), reference(&keys));
    }

    #[test]
    fn few_distinct_values(keys in proptest::collection::vec(0u32..4, 0..300), hi in any::<u32>()) {
        // Few values, in one byte or spread over two: many passes skipped or not.
        let keys: Vec<u32> = keys.into_iter().map(|k| if k == 3 { hi } else { k << 16 }).collect();
        prop_assert_eq!(sort_permutation(&keys).unwrap(), reference(&keys));
    }
}

/// Inputs above `LSD_MAX` take the split-then-sort path, and skewed ones split twice.
#[test]
fn large_inputs_match_std() {
    let mut rng = testkit::Rng::new(0x0123_4567_89ab_cdef);
    let n = 150_000;
    let uniform: Vec<u32> = rng.words(n);
    let morton30: Vec<u32> = (0..n).map(|_| rng.next_u32() >> 2).collect();
    // Most keys share the top two bytes: one bucket far above LSD_MAX, split again.
    let skewed: Vec<u32> = (0..n)
        .map(|i| {
            if i % 10 == 0 {
                rng.next_u32()
            } else {
                0x1234_0000 | (rng.next_u32() & 0xffff)
            }
        })
        .collect();
    let few: Vec<u32> = (0..n).map(|_| rng.below(5) as u32 * 0x0101_0101).collect();
    for keys in [&uniform, &morton30, &skewed, &few] {
        assert_eq!(sort_permutation(keys).unwrap(), reference(keys));
    }
    let u64s: Vec<u64> = (0..n).map(|_| rng.next_u64() >> 1).collect();
    let skewed64: Vec<u64> = (0..n)
        .map(|i| {
            if i % 7 == 0 {
                rng.next_u64()
            } else {
                0xabcd_ef00_0000_0000 | (rng.next_u64() & 0xff_ffff)
            }
        })
        .collect();
    let low_only: Vec<u64> = (0..n).map(|_| rng.next_u64() & 0xff).collect();
    for keys in [&u64s, &skewed64, &low_only] {
        assert_eq!(sort_permutation(keys).unwrap(), reference(keys));
    }
    assert!(n > morton::sort::LSD_MAX * 4);
}

#[test]
fn sorter_reuses_buffers_across_sizes() {
    let mut sorter = morton::Sorter::<u32>::new();
    let mut perm = Vec::new();
    let mut rng = testkit::Rng::new(99);
    for n in [50_000usize, 10, 0, 40_000, 1] {
        let keys: Vec<u32> = (0..n).map(|_| rng.next_u32() >> 3).collect();
        sorter.sort_permutation_into(&keys, &mut perm).unwrap();
        assert_eq!(perm, reference(&keys), "n = {n}");
    }
    let mut sorter64 = morton::Sorter::<u64>::default();
    let keys: Vec<u64> = (0..1000).map(|_| rng.next_u64() >> 3).collect();
    sorter64.sort_permutation_into(&keys, &mut perm).unwrap();
    assert_eq!(perm, reference(&keys));
}
