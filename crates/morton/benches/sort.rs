//! The sort permutation of 1M random Morton keys (u32 of 30 bits, u64 of 63 bits):
//! sequential (fresh buffers, and a reused `Sorter`) and parallel radix sort against
//! std's stable and unstable sorts of
//! (key, index) pairs (what a caller would write without this crate).
//!
//! Run: `cargo bench -p morton --features parallel --bench sort`.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use rayon::prelude::*;

fn keys(n: usize) -> (Vec<u32>, Vec<u64>) {
    let mut rng = testkit::Rng::new(0x243f_6a88_85a3_08d3);
    let k64: Vec<u64> = (0..n).map(|_| rng.next_u64() >> 1).collect();
    let k32: Vec<u32> = (0..n).map(|_| rng.next_u32() >> 2).collect();
    (k32, k64)
}

fn std_stable<K: Ord + Copy>(keys: &[K]) -> Vec<u32> {
    let mut idx: Vec<u32> = (0..keys.len() as u32).collect();
    idx.sort_by_key(|&i| keys[i as usize]);
    idx
}

fn std_unstable_pairs<K: Ord + Copy + Send>(keys: &[K]) -> Vec<u32> {
    let mut pairs: Vec<(K, u32)> = keys
        .iter()
        .enumerate()
        .map(|(i, &k)| (k, i as u32))
        .collect();
    pairs.sort_unstable();
    pairs.into_iter().map(|(_, i)| i).collect()
}

fn par_std_pairs<K: Ord + Copy + Send + Sync>(keys: &[K]) -> Vec<u32> {
    let mut pairs: Vec<(K, u32)> = keys
        .par_iter()
        .enumerate()
        .map(|(i, &k)| (k, i as u32))
        .collect();
    pairs.par_sort_unstable();
    pairs.into_iter().map(|(_, i)| i).collect()
}

fn sort(c: &mut Criterion) {
    for n in [1usize << 16, 1 << 20] {
        let (k32, k64) = keys(n);
        let mut g = c.benchmark_group("sort_permutation");
        g.throughput(Throughput::Elements(n as u64));
        g.sample_size(20);
        g.bench_with_input(BenchmarkId::new("u32/radix_seq", n), &k32, |b, k| {
            b.iter(|| morton::sort_permutation(black_box(k)).unwrap())
        });
        let mut sorter = morton::Sorter::new();
        let mut perm = Vec::new();
        g.bench_with_input(BenchmarkId::new("u32/radix_seq_reused", n), &k32, |b, k| {
            b.iter(|| {
                sorter
                    .sort_permutation_into(black_box(k), &mut perm)
                    .unwrap()
            })
        });
        g.bench_with_input(BenchmarkId::new("u32/radix_par", n), &k32, |b, k| {
            b.iter(|| morton::parallel::par_sort_permutation(black_box(k)).unwrap())
        });
        g.bench_with_input(BenchmarkId::new("u32/radix_par_reused", n), &k32, |b, k| {
            b.iter(|| {
                sorter
                    .par_sort_permutation_into(black_box(k), &mut perm)
                    .unwrap()
            })
        });
        g.bench_with_input(
            BenchmarkId::new("u32/std_stable_indices", n),
            &k32,
            |b, k| b.iter(|| std_stable(black_box(k))),
        );
        g.bench_with_input(
            BenchmarkId::new("u32/std_unstable_pairs", n),
            &k32,
            |b, k| b.iter(|| std_unstable_pairs(black_box(k))),
        );
        g.bench_with_input(
            BenchmarkId::new("u32/rayon_unstable_pairs", n),
            &k32,
            |b, k| b.iter(|| par_std_pairs(black_box(k))),
        );
        g.bench_with_input(BenchmarkId::new("u64/radix_seq", n), &k64, |b, k| {
            b.iter(|| morton::sort_permutation(black_box(k)).unwrap())
        });
        let mut sorter = morton::Sorter::new();
        g.bench_with_input(BenchmarkId::new("u64/radix_seq_reused", n), &k64, |b, k| {
            b.iter(|| {
                sorter
                    .sort_permutation_into(black_box(k), &mut perm)
                    .unwrap()
            })
        });
        g.bench_with_input(BenchmarkId::new("u64/radix_par", n), &k64, |b, k| {
            b.iter(|| morton::parallel::par_sort_permutation(black_box(k)).unwrap())
        });
        g.bench_with_input(BenchmarkId::new("u64/radix_par_reused", n), &k64, |b, k| {
            b.iter(|| {
                sorter
                    .par_sort_permutation_into(black_box(k), &mut perm)
                    .unwrap()
            })
        });
        g.bench_with_input(
            BenchmarkId::new("u64/std_unstable_pairs", n),
            &k64,
            |b, k| b.iter(|| std_unstable_pairs(black_box(k))),
        );
        g.bench_with_input(
            BenchmarkId::new("u64/rayon_unstable_pairs", n),
            &k64,
            |b, k| b.iter(|| par_std_pairs(black_box(k))),
        );
        g.finish();
    }
}

criterion_group!(benches, sort);
criterion_main!(benches);
