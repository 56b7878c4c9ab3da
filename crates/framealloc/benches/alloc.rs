//! Allocate + free of one 256 KiB block out of KZ2's 22 MiB pool (88 blocks), against
//! `offset-allocator` (Bevy's slab allocator, a TLSF-style O(1) allocator) and a
//! `Mutex<Vec<u32>>` free list, in the same groups:
//!
//! - `block_pair/*`: one thread, one allocate + free per iteration. framealloc's "free" is
//!   the FreeID advance past the block's ID (what the consumer does when the GPU passes the
//!   marker). `empty` starts from an empty pool; `quarter_free` keeps 66 of the 88 blocks
//!   live, scattered, so allocation has to search. `ring64` keeps 64 blocks in flight and
//!   frees the oldest each time (a streaming pipeline a few frames deep).
//! - `block_pair_2t/*`: two threads, each doing `iters` allocate + free pairs on the same
//!   pool at once; the time is the wall time of the slower thread, so time / 2 is the
//!   aggregate cost per pair. framealloc takes IDs from one shared counter and each thread
//!   advances FreeID to its own ID (FreeID is monotonic, so the larger wins); an
//!   allocation whose ID the other thread has already retired is retried with a new ID and
//!   counted as extra work, not as a pair. Baselines share one `Mutex`.
//! - `suballoc/*`: suballocations inside one 256 KiB block: per iteration a 64-byte
//!   command at the front and 1 KiB of its data at the back, plus their share of releasing
//!   them (the bump allocator resets when the block is full; offset-allocator managing the
//!   same block frees every allocation then).
//!
//! Reproduce: `cargo bench -p framealloc --bench alloc`.

use std::collections::VecDeque;
use std::hint::black_box;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Barrier, Mutex};
use std::time::{Duration, Instant};

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use framealloc::{
    AllocId, BlockBump, BlockPool, Error, KZ2_BLOCK_BYTES, KZ2_POOL_BYTES, PoolConfig,
};
use offset_allocator::Allocator;

const BLOCKS: u32 = (KZ2_POOL_BYTES / KZ2_BLOCK_BYTES as u64) as u32;
/// Blocks kept live in the `quarter_free` variants.
const LIVE: u32 = BLOCKS * 3 / 4;

/// Indices of the blocks kept live: 3 of every 4, so free ones are scattered.
fn live_pattern() -> impl Iterator<Item = u32> {
    (0..BLOCKS).filter(|i| i % 4 != 3)
}

/// A KZ2 pool with `live` blocks (those of `live_pattern`) tagged far ahead of FreeID.
fn framealloc_pool(live: bool) -> BlockPool {
    let pool = BlockPool::new(PoolConfig::KZ2).unwrap();
    if live {
        // Claim everything, then give back every fourth block (tagged at FreeID + 1).
        let far = pool.free_id().add(1 << 29);
        let near = pool.free_id().next();
        let mut blocks: Vec<_> = (0..BLOCKS)
            .map(|i| {
                pool.try_allocate(if i % 4 == 3 { near } else { far })
                    .unwrap()
            })
            .collect();
        pool.advance_free_id(near).unwrap();
        blocks.retain(|b| pool.holds(b));
        assert_eq!(blocks.len() as u32, LIVE);
        assert!(blocks.iter().map(|b| b.index()).eq(live_pattern()));
    }
    pool
}

fn offset_pool(live: bool) -> Allocator {
    let mut a: Allocator = Allocator::with_max_allocs(KZ2_POOL_BYTES as u32, 1024);
    if live {
        let all: Vec<_> = (0..BLOCKS)
            .map(|_| a.allocate(KZ2_BLOCK_BYTES).unwrap())
            .collect();
        for (i, x) in all.into_iter().enumerate() {
            if i % 4 == 3 {
                a.free(x);
            }
        }
    }
    a
}

fn free_list(live: bool) -> Vec<u32> {
    if live {
        (0..BLOCKS).filter(|i| i % 4 == 3).collect()
    } else {
        (0..BLOCKS).rev().collect()
    }
}

/// framealloc: allocate with the next ID, then the consumer passes its marker.
#[inline]
fn framealloc_pair(pool: &BlockPool, id: &mut AllocId) {
    *id = id.next();
    let b = pool.try_allocate(*id).unwrap();
    black_box(b.offset());
    pool.advance_free_id(*id).unwrap();
}

/// Blocks in flight in the `ring` variant: the GPU frees each block `RING` allocations
/// after it was made, as a streaming pipeline a few frames deep does.
const RING: u32 = 64;

/// `ring`: allocate a block, free the one allocated `RING` allocations ago.
fn block_ring(c: &mut Criterion) {
    let mut g = c.benchmark_group(format!("block_pair/ring{RING}"));
    g.throughput(Throughput::Elements(1));
    g.bench_function("framealloc", |b| {
        b.iter_custom(|iters| {
            let pool = BlockPool::new(PoolConfig::KZ2).unwrap();
            let mut id = pool.free_id();
            for _ in 0..RING {
                id = id.next();
                pool.try_allocate(id).unwrap();
            }
            let t = Instant::now();
            for _ in 0..iters {
                id = id.next();
                let b = pool.try_allocate(id).unwrap();
                black_box(b.offset());
                pool.advance_free_id(id.sub(RING)).unwrap();
            }
            t.elapsed()
        })
    });
    g.bench_function("offset_allocator", |b| {
        b.iter_custom(|iters| {
            let mut a = offset_pool(false);
            let mut ring: VecDeque<_> = (0..RING)
                .map(|_| a.allocate(KZ2_BLOCK_BYTES).unwrap())
                .collect();
            let t = Instant::now();
            for _ in 0..iters {
                let x = a.allocate(black_box(KZ2_BLOCK_BYTES)).unwrap();
                black_box(x.offset);
                ring.push_back(x);
                a.free(ring.pop_front().unwrap());
            }
            t.elapsed()
        })
    });
    g.bench_function("mutex_vec", |b| {
        b.iter_custom(|iters| {
            let list = Mutex::new(free_list(false));
            let mut ring: VecDeque<u32> = (0..RING)
                .map(|_| list.lock().unwrap().pop().unwrap())
                .collect();
            let t = Instant::now();
            for _ in 0..iters {
                let i = list.lock().unwrap().pop().unwrap();
                black_box(i as u64 * KZ2_BLOCK_BYTES as u64);
                ring.push_back(i);
                list.lock().unwrap().push(ring.pop_front().unwrap());
            }
            t.elapsed()
        })
    });
    g.finish();
}

fn block_pair(c: &mut Criterion) {
    for (name, live) in [("empty", false), ("quarter_free", true)] {
        let mut g = c.benchmark_group(format!("block_pair/{name}"));
        g.throughput(Throughput::Elements(1));
        g.bench_function("framealloc", |b| {
            b.iter_custom(|iters| {
                let pool = framealloc_pool(live);
                let mut id = pool.free_id();
                let t = Instant::now();
                for _ in 0..iters {
                    framealloc_pair(&pool, &mut id);
                }
                t.elapsed()
            })
        });
        g.bench_function("offset_allocator", |b| {
            b.iter_custom(|iters| {
                let mut a = offset_pool(live);
                let t = Instant::now();
                for _ in 0..iters {
                    let x = a.allocate(black_box(KZ2_BLOCK_BYTES)).unwrap();
                    black_box(x.offset);
                    a.free(x);
                }
                t.elapsed()
            })
        });
        g.bench_function("mutex_vec", |b| {
            b.iter_custom(|iters| {
                let list = Mutex::new(free_list(live));
                let t = Instant::now();
                for _ in 0..iters {
                    let i = list.lock().unwrap().pop().unwrap();
                    black_box(i as u64 * KZ2_BLOCK_BYTES as u64);
                    list.lock().unwrap().push(i);
                }
                t.elapsed()
            })
        });
        g.finish();
    }
}

/// Runs `work(thread, iters)` on two threads released together; returns the slower
/// thread's time.
fn two_threads<F: Fn(usize, u64) + Sync>(iters: u64, work: F) -> Duration {
    let start = Barrier::new(2);
    std::thread::scope(|s| {
        let handles: Vec<_> = (0..2)
            .map(|t| {
                let (start, work) = (&start, &work);
                s.spawn(move || {
                    start.wait();
                    let t0 = Instant::now();
                    work(t, iters);
                    t0.elapsed()
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().unwrap())
            .max()
            .unwrap()
    })
}

fn block_pair_2t(c: &mut Criterion) {
    for (name, live) in [("empty", false), ("quarter_free", true)] {
        let mut g = c.benchmark_group(format!("block_pair_2t/{name}"));
        g.throughput(Throughput::Elements(2));
        g.bench_function("framealloc", |b| {
            b.iter_custom(|iters| {
                let pool = framealloc_pool(live);
                let next = AtomicU32::new(pool.free_id().0);
                two_threads(iters, |_, n| {
                    let mut done = 0;
                    while done < n {
                        let id = AllocId(next.fetch_add(1, Ordering::Relaxed).wrapping_add(1));
                        match pool.try_allocate(id) {
                            Ok(b) => {
                                black_box(b.offset());
                                pool.advance_free_id(id).unwrap();
                                done += 1;
                            }
                            Err(Error::IdRetired { .. }) => {}
                            Err(e) => panic!("{e}"),
                        }
                    }
                })
            })
        });
        g.bench_function("offset_allocator", |b| {
            b.iter_custom(|iters| {
                let a = Mutex::new(offset_pool(live));
                two_threads(iters, |_, n| {
                    for _ in 0..n {
                        let x = a.lock().unwrap().allocate(KZ2_BLOCK_BYTES).unwrap();
                        black_box(x.offset);
                        a.lock().unwrap().free(x);
                    }
                })
            })
        });
        g.bench_function("mutex_vec", |b| {
            b.iter_custom(|iters| {
                let list = Mutex::new(free_list(live));
                two_threads(iters, |_, n| {
                    for _ in 0..n {
                        let i = list.lock().unwrap().pop().unwrap();
                        black_box(i as u64 * KZ2_BLOCK_BYTES as u64);
                        list.lock().unwrap().push(i);
                    }
                })
            })
        });
        g.finish();
    }
}

fn suballoc(c: &mut Criterion) {
    const CMD: u32 = 64;
    const DATA: u32 = 1024;
    let mut g = c.benchmark_group("suballoc");
    // One iteration: a command and its data.
    g.throughput(Throughput::Elements(2));
    g.bench_function("framealloc_bump", |b| {
        let mut bump = BlockBump::new(KZ2_BLOCK_BYTES);
        b.iter(|| {
            // Room for both, alignment padding included; else start the block over.
            if bump.free() < CMD + 16 + DATA + 256 {
                bump.reset();
            }
            black_box(bump.push_front(black_box(CMD), 16).unwrap());
            black_box(bump.push_back(black_box(DATA), 256).unwrap());
        })
    });
    g.bench_function("offset_allocator", |b| {
        let mut a: Allocator = Allocator::with_max_allocs(KZ2_BLOCK_BYTES, 1024);
        let mut held = Vec::with_capacity(1024);
        b.iter(|| {
            let (x, y) = match (a.allocate(black_box(CMD)), a.allocate(black_box(DATA))) {
                (Some(x), Some(y)) => (x, y),
                (x, y) => {
                    x.into_iter().chain(y).for_each(|z| a.free(z));
                    held.drain(..).for_each(|z| a.free(z));
                    (a.allocate(CMD).unwrap(), a.allocate(DATA).unwrap())
                }
            };
            black_box((x.offset, y.offset));
            held.push(x);
            held.push(y);
        })
    });
    g.finish();
}

criterion_group!(benches, block_pair, block_ring, block_pair_2t, suballoc);
criterion_main!(benches);
