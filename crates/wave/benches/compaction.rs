//! Stream compaction of 16M items at 1/3 density: aggregated atomics (one per wave) against
//! one atomic per kept item, on rayon's threads sharing one real `AtomicU32`, and the same
//! pair sequentially. Criterion reports time per 16M items (divide by 16.78M for ns/item)
//! and elements/s; atomics per item are printed once at the start, from the runs' own
//! counts.
//!
//! `cargo bench -p wave --features parallel --bench compaction`

use std::hint::black_box;
use std::sync::atomic::AtomicU32;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use wave::parallel::{par_compact, par_compact_per_item};
use wave::{CountedAtomicU32, WaveWidth, compact, compact_per_item};

const N: usize = 1 << 24;

/// 16M pseudo-random words; `keep` selects about a third of them at random positions.
fn items() -> Vec<u32> {
    testkit::Rng::new(0x9e37_79b9_7f4a_7c15).words(N)
}

fn keep(x: &u32) -> bool {
    x.is_multiple_of(3)
}

fn bench(c: &mut Criterion) {
    let items = items();
    let mut out = vec![0u32; N];

    // Atomics per item, counted by the runs themselves (not timed).
    for width in [WaveWidth::W32, WaveWidth::W64] {
        let mut counter = AtomicU32::new(0);
        let a = par_compact(width, &items, keep, &mut counter, &mut out).expect("fits");
        let mut counter = AtomicU32::new(0);
        let b = par_compact_per_item(width, &items, keep, &mut counter, &mut out).expect("fits");
        let counted = CountedAtomicU32::new(0);
        let s = compact(width, &items, keep, &counted, &mut out);
        assert_eq!(counted.atomic_ops(), s.atomic_ops);
        println!(
            "wave {width}: density {:.4}, aggregated {:.5} atomics/item ({} atomics), \
             per item {:.5} atomics/item ({} atomics), {} waves",
            a.selected as f64 / N as f64,
            a.atomic_ops as f64 / N as f64,
            a.atomic_ops,
            b.atomic_ops as f64 / N as f64,
            b.atomic_ops,
            a.waves
        );
    }

    let mut g = c.benchmark_group("compaction_16M_density_1_3");
    g.throughput(Throughput::Elements(N as u64));
    g.sample_size(10);
    for width in [WaveWidth::W32, WaveWidth::W64] {
        let w = width.lanes();
        g.bench_function(BenchmarkId::new("par_aggregated", w), |b| {
            b.iter(|| {
                let mut counter = AtomicU32::new(0);
                par_compact(width, black_box(&items), keep, &mut counter, &mut out).expect("fits")
            })
        });
        g.bench_function(BenchmarkId::new("par_per_item_atomic", w), |b| {
            b.iter(|| {
                let mut counter = AtomicU32::new(0);
                par_compact_per_item(width, black_box(&items), keep, &mut counter, &mut out)
                    .expect("fits")
            })
        });
        g.bench_function(BenchmarkId::new("seq_aggregated", w), |b| {
            b.iter(|| {
                let counter = AtomicU32::new(0);
                compact(width, black_box(&items), keep, &counter, &mut out)
            })
        });
        g.bench_function(BenchmarkId::new("seq_per_item_atomic", w), |b| {
            b.iter(|| {
                let counter = AtomicU32::new(0);
                compact_per_item(width, black_box(&items), keep, &counter, &mut out)
            })
        });
    }
    // The floor: a branchless sequential filter into a slice, no atomics and no waves.
    g.bench_function("seq_filter_no_atomics", |b| {
        b.iter(|| {
            let mut n = 0;
            for &x in black_box(&items) {
                out[n] = x;
                n += usize::from(keep(&x));
            }
            n
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
