//! The parallel functions equal the sequential ones exactly.

use glam::Vec3;
use morton::{Error, Quantizer3, SortKey, parallel, sort_permutation};

fn points(n: usize, seed: u64) -> Vec<Vec3> {
    let mut rng = testkit::Rng::new(seed);
    let mut next = || rng.range(-100.0, 100.0);
    (0..n).map(|_| Vec3::new(next(), next(), next())).collect()
}

#[test]
fn quantize_encode_equals_sequential() {
    let pts = points(200_003, 7);
    let q = Quantizer3::new(Vec3::splat(-90.0), Vec3::splat(90.0), 10).unwrap();
    let (mut a, mut b) = (vec![0u32; pts.len()], vec![0u32; pts.len()]);
    q.morton_u32_slice(&pts, &mut a).unwrap();
    q.par_morton_u32_slice(&pts, &mut b).unwrap();
    assert_eq!(a, b);
    let q = Quantizer3::new(Vec3::splat(-90.0), Vec3::splat(90.0), 21).unwrap();
    let (mut a, mut b) = (vec![0u64; pts.len()], vec![0u64; pts.len()]);
    q.morton_u64_slice(&pts, &mut a).unwrap();
    q.par_morton_u64_slice(&pts, &mut b).unwrap();
    assert_eq!(a, b);
}

#[test]
fn nan_error_names_the_same_point() {
    let mut pts = points(150_000, 9);
    pts[140_001].y = f32::NAN;
    pts[70_000].x = f32::NAN;
    let q = Quantizer3::new(Vec3::splat(-100.0), Vec3::splat(100.0), 10).unwrap();
    let (mut a, mut b) = (vec![0u32; pts.len()], vec![0u32; pts.len()]);
    let ea = q.morton_u32_slice(&pts, &mut a).unwrap_err();
    let eb = q.par_morton_u32_slice(&pts, &mut b).unwrap_err();
    assert_eq!(ea, Error::NanPosition { index: 70_000 });
    assert_eq!(ea, eb);
    assert_eq!(a, b);
    let mut short = vec![0u32; 3];
    assert!(q.par_morton_u32_slice(&pts, &mut short).is_err());
}

/// Asserts that the parallel sort permutation of `keys` equals the sequential one.
fn assert_par_sort_equal<K: SortKey>(keys: &[K]) {
    assert_eq!(
        parallel::par_sort_permutation(keys).unwrap(),
        sort_permutation(keys).unwrap()
    );
}

#[test]
fn sort_equals_sequential() {
    let pts = points(300_000, 11);
    let q = Quantizer3::new(Vec3::splat(-100.0), Vec3::splat(100.0), 10).unwrap();
    let mut k32 = vec![0u32; pts.len()];
    q.morton_u32_slice(&pts, &mut k32).unwrap();
    // Coarse keys have many ties: stability matters.
    let coarse: Vec<u32> = k32.iter().map(|k| k >> 12).collect();
    for keys in [&k32, &coarse] {
        assert_par_sort_equal(keys);
    }
    let q = Quantizer3::new(Vec3::splat(-100.0), Vec3::splat(100.0), 21).unwrap();
    let mut k64 = vec![0u64; pts.len()];
    q.morton_u64_slice(&pts, &mut k64).unwrap();
    let coarse: Vec<u64> = k64.iter().map(|k| k >> 40).collect();
    for keys in [&k64, &coarse] {
        assert_par_sort_equal(keys);
    }
    assert_par_sort_equal(&vec![5u64; 100_000]);
    let small = [3u32, 1, 2];
    assert_eq!(parallel::par_sort_permutation(&small).unwrap(), [1, 2, 0]);
}

#[test]
fn sorter_parallel_reuse_equals_sequential() {
    let pts = points(120_000, 5);
    let q = Quantizer3::new(Vec3::splat(-100.0), Vec3::splat(100.0), 21).unwrap();
    let mut keys = vec![0u64; pts.len()];
    q.morton_u64_slice(&pts, &mut keys).unwrap();
    let mut sorter = morton::Sorter::new();
    let mut perm = vec![7u32; 3];
    for len in [120_000, 70_000, 100, 120_000] {
        sorter
            .par_sort_permutation_into(&keys[..len], &mut perm)
            .unwrap();
        assert_eq!(perm, sort_permutation(&keys[..len]).unwrap(), "len {len}");
    }
}
