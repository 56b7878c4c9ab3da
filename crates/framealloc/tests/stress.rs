//! Many allocator threads and one consumer thread on a small pool.
//!
//! Each frame, every worker thread allocates 1-3 blocks with IDs from its own pass range,
//! in whatever order the scheduler runs them, stamps each block's owner word (which must
//! have been empty: a block handed out twice fails here) and fills the block's memory with
//! its token. At the end of the frame one worker submits the frame, sorted by ID as a GPU
//! would consume it, to the consumer thread. The consumer, standing in for the GPU, checks
//! each block is still live under its ID (the simulated GPU's read check) and still holds
//! its writer's token, clears it, and advances FreeID past it; now and then it stalls, so
//! the workers exhaust the pool and must wait. IDs start just below `u32::MAX`, so the run
//! crosses the wrap. At the end every block has come back.

use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::mpsc;
use std::sync::{Condvar, Mutex, PoisonError};
use std::time::{Duration, Instant};

use framealloc::sim::{GpuCommand, SimulatedGpu};
use framealloc::{AllocId, BlockPool, Blocking, FramePlan, PoolConfig, Stall, Wait};

const WORKERS: u32 = 4;
const BLOCKS: u32 = 12;
const WORDS: usize = 8;
const FRAMES: u32 = 1200;
const FIRST_ID: u32 = u32::MAX - 3000;
/// How long anything may stall before the test fails rather than hangs.
const TIMEOUT: Duration = Duration::from_secs(10);

/// One allocated block as submitted to the consumer.
#[derive(Clone, Copy, Debug)]
struct Item {
    id: AllocId,
    block: u32,
    token: u64,
}

struct Shared {
    pool: BlockPool,
    /// Per block: the token of the client that owns it, 0 when free.
    owner: Vec<AtomicU64>,
    /// Per block: its "memory".
    memory: Vec<[AtomicU64; WORDS]>,
    /// Per block: how often it was handed out.
    uses: Vec<AtomicU64>,
    allocated: AtomicU64,
    waits: AtomicU64,
}

/// A barrier that fails instead of hanging when a thread it waits for has panicked.
struct FrameBarrier {
    /// (threads arrived, generation)
    state: Mutex<(u32, u64)>,
    cv: Condvar,
    threads: u32,
}

impl FrameBarrier {
    fn new(threads: u32) -> Self {
        FrameBarrier {
            state: Mutex::new((0, 0)),
            cv: Condvar::new(),
            threads,
        }
    }

    /// Returns true on exactly one thread per round (the last to arrive).
    fn wait(&self) -> bool {
        let mut g = self.state.lock().unwrap_or_else(PoisonError::into_inner);
        let generation = g.1;
        g.0 += 1;
        if g.0 == self.threads {
            *g = (0, generation + 1);
            self.cv.notify_all();
            return true;
        }
        let deadline = Instant::now() + TIMEOUT;
        while g.1 == generation {
            let now = Instant::now();
            assert!(
                now < deadline,
                "frame barrier timed out: another worker failed"
            );
            g = self
                .cv
                .wait_timeout(g, deadline - now)
                .unwrap_or_else(PoisonError::into_inner)
                .0;
        }
        false
    }
}

fn worker(
    w: u32,
    s: &Shared,
    plan: &FramePlan,
    barrier: &FrameBarrier,
    collect: &[Mutex<Vec<Item>>; 2],
    to_gpu: &mpsc::Sender<(Vec<Item>, AllocId)>,
) {
    let mut rng = testkit::Rng::new(u64::from(w) + 1);
    let mut frame = plan.frame(AllocId(FIRST_ID));
    for f in 0..FRAMES {
        let mut ids = frame.pass(w).unwrap().cursor();
        let count = 1 + rng.below(3);
        for _ in 0..count {
            let id = ids.next().unwrap();
            // Wait for the consumer when the pool is exhausted, counting the stalls.
            let mut blocking = Blocking::with_timeout(TIMEOUT);
            let mut wait = |st: &Stall| {
                s.waits.fetch_add(1, Ordering::Relaxed);
                blocking.wait(&s.pool, st)
            };
            let b = s.pool.allocate_with(id, &mut wait).expect("allocation");
            let i = b.index() as usize;
            let token = ((w as u64 + 1) << 48) | ((f as u64) << 8) | (i as u64);
            let prev = s.owner[i].swap(token, Ordering::AcqRel);
            assert_eq!(prev, 0, "block {i} handed out while owned by {prev:#x}");
            for word in &s.memory[i] {
                word.store(token, Ordering::Relaxed);
            }
            s.uses[i].fetch_add(1, Ordering::Relaxed);
            s.allocated.fetch_add(1, Ordering::Relaxed);
            collect[(f % 2) as usize].lock().unwrap().push(Item {
                id,
                block: b.index(),
                token,
            });
        }
        if barrier.wait() {
            let mut items = std::mem::take(&mut *collect[(f % 2) as usize].lock().unwrap());
            items.sort_by_key(|it| it.id.distance_from(frame.first()));
            to_gpu.send((items, frame.last())).unwrap();
        }
        frame = frame.next();
    }
}

fn consumer(s: &Shared, from_workers: mpsc::Receiver<(Vec<Item>, AllocId)>) -> u64 {
    let mut gpu = SimulatedGpu::new();
    let mut consumed = 0u64;
    let mut frames = 0u32;
    for (items, last) in from_workers {
        frames += 1;
        if frames.is_multiple_of(40) {
            // A slow GPU frame: the workers run ahead and exhaust the pool.
            std::thread::sleep(Duration::from_millis(5));
        }
        for it in items {
            let i = it.block as usize;
            gpu.submit(GpuCommand::Read {
                block: it.block,
                id: it.id,
            });
            gpu.step(&s.pool)
                .expect("GPU read a block that is not live");
            for word in &s.memory[i] {
                assert_eq!(
                    word.swap(0, Ordering::Relaxed),
                    it.token,
                    "block {i} overwritten while live"
                );
            }
            assert_eq!(s.owner[i].swap(0, Ordering::AcqRel), it.token);
            // KZ2: the next block starts with "free previous".
            gpu.submit(GpuCommand::Free(it.id));
            gpu.step(&s.pool).unwrap();
            consumed += 1;
        }
        gpu.submit(GpuCommand::Free(last));
        gpu.step(&s.pool).unwrap();
    }
    consumed
}

#[test]
fn many_allocators_and_a_consumer_never_share_a_block() {
    let plan = FramePlan::new(&[4; WORKERS as usize]).unwrap();
    let s = Shared {
        pool: BlockPool::new(
            PoolConfig::new(BLOCKS as u64 * 256, 256).with_first_id(AllocId(FIRST_ID)),
        )
        .unwrap(),
        owner: (0..BLOCKS).map(|_| AtomicU64::new(0)).collect(),
        memory: (0..BLOCKS)
            .map(|_| std::array::from_fn(|_| AtomicU64::new(0)))
            .collect(),
        uses: (0..BLOCKS).map(|_| AtomicU64::new(0)).collect(),
        allocated: AtomicU64::new(0),
        waits: AtomicU64::new(0),
    };
    let barrier = FrameBarrier::new(WORKERS);
    let collect = [Mutex::new(Vec::new()), Mutex::new(Vec::new())];
    let (tx, rx) = mpsc::channel();
    let finished = AtomicUsize::new(0);
    let consumed = std::thread::scope(|sc| {
        let gpu = sc.spawn(|| consumer(&s, rx));
        for w in 0..WORKERS {
            let (s, plan, barrier, collect, tx, finished) =
                (&s, &plan, &barrier, &collect, tx.clone(), &finished);
            sc.spawn(move || {
                worker(w, s, plan, barrier, collect, &tx);
                finished.fetch_add(1, Ordering::Relaxed);
            });
        }
        drop(tx);
        gpu.join().unwrap()
    });
    assert_eq!(finished.load(Ordering::Relaxed), WORKERS as usize);
    let allocated = s.allocated.load(Ordering::Relaxed);
    assert_eq!(consumed, allocated, "every allocated block was consumed");
    // Every block came back.
    assert_eq!(s.pool.free_blocks(), BLOCKS);
    let span = plan.span();
    assert_eq!(
        s.pool.free_id(),
        AllocId(FIRST_ID).add(FRAMES * span - 1),
        "FreeID is at the last frame's end (past the wrap)"
    );
    assert!(s.owner.iter().all(|o| o.load(Ordering::Relaxed) == 0));
    assert!(
        s.uses.iter().all(|u| u.load(Ordering::Relaxed) > 0),
        "every block was used"
    );
    assert!(
        s.waits.load(Ordering::Relaxed) > 0,
        "the stalling consumer made the workers wait"
    );
    eprintln!(
        "{allocated} blocks through {BLOCKS}, {} waits",
        s.waits.load(Ordering::Relaxed)
    );
}

/// Threads racing allocate + free pairs on a tiny pool: at most one block per thread is
/// ever live, so allocation must never report exhaustion, even for a thread preempted in
/// the middle of a walk while the others cycled through every block.
#[test]
fn racing_pairs_never_see_false_exhaustion() {
    const THREADS: u32 = 3;
    const PAIRS: u32 = 200_000;
    let pool = BlockPool::new(PoolConfig::new(THREADS as u64 * 256, 256)).unwrap();
    let next = std::sync::atomic::AtomicU32::new(pool.free_id().0);
    let retired = AtomicU64::new(0);
    std::thread::scope(|sc| {
        for _ in 0..THREADS {
            sc.spawn(|| {
                let mut done = 0;
                while done < PAIRS {
                    let id = AllocId(next.fetch_add(1, Ordering::Relaxed).wrapping_add(1));
                    match pool.try_allocate(id) {
                        Ok(b) => {
                            assert_eq!(b.id(), id);
                            pool.advance_free_id(id).unwrap();
                            done += 1;
                        }
                        // Another thread already advanced FreeID past this ID.
                        Err(framealloc::Error::IdRetired { .. }) => {
                            retired.fetch_add(1, Ordering::Relaxed);
                        }
                        Err(e) => panic!("{e}"),
                    }
                }
            });
        }
    });
    assert_eq!(pool.free_blocks(), THREADS);
    eprintln!("{} retired IDs skipped", retired.load(Ordering::Relaxed));
}
