//! Operation sequences against simple models.
//!
//! The pool model keeps IDs as unwrapped `u64`s (no wrap-around, no serial arithmetic, no
//! sweeps) and a plain `Vec` of per-block IDs: a block is free iff its ID <= FreeID. The
//! real pool, with 32-bit wrapping IDs started anywhere (near `u32::MAX` included) and
//! FreeID jumps of up to 2^30, must agree with it after every operation.
//!
//! The stream model is a byte map of the whole pool: every span handed out is stamped with
//! its owner and must not overlap any live span; stamps are cleared when the simulated GPU
//! frees their block.

use framealloc::sim::{GpuCommand, SimulatedGpu};
use framealloc::{
    AllocId, Block, BlockPool, Error, FramePlan, MAX_FREE_STEP, MAX_ID_LEAD, PoolConfig, Stream,
};
use proptest::prelude::*;

#[derive(Clone, Debug)]
enum Op {
    /// Allocate with ID FreeID + lead.
    Alloc(u32),
    /// Allocate with ID FreeID - back (always retired).
    AllocBehind(u32),
    /// Advance FreeID by `step`.
    Advance(u32),
    /// Advance FreeID to FreeID - back (a stale marker).
    Retreat(u32),
}

fn op() -> impl Strategy<Value = Op> {
    let lead = prop_oneof![
        Just(0u32),
        1..8u32,
        MAX_ID_LEAD - 2..=MAX_ID_LEAD + 2,
        any::<u32>(),
    ];
    let step = prop_oneof![
        0..6u32,
        1..=MAX_FREE_STEP,
        MAX_FREE_STEP - 1..=MAX_FREE_STEP + 1,
        any::<u32>(),
    ];
    prop_oneof![
        4 => lead.prop_map(Op::Alloc),
        1 => (1..=u32::MAX / 2).prop_map(Op::AllocBehind),
        3 => step.prop_map(Op::Advance),
        1 => (1..u32::MAX / 2).prop_map(Op::Retreat),
    ]
}

fn first_id() -> impl Strategy<Value = u32> {
    prop_oneof![Just(0u32), Just(1), u32::MAX - 8..=u32::MAX, any::<u32>()]
}

struct Model {
    /// FreeID, unwrapped; starts far from 0 so stale markers never underflow.
    free: u64,
    /// Per block: its ID, unwrapped.
    slots: Vec<u64>,
}

impl Model {
    fn new(blocks: u32, first: u32) -> Self {
        let free = (4u64 << 32) + first as u64 - 1;
        Model {
            free,
            slots: vec![free; blocks as usize],
        }
    }
    fn live(&self, i: usize) -> bool {
        self.slots[i] > self.free
    }
}

fn wrap(x: u64) -> AllocId {
    AllocId(x as u32)
}

fn run_pool(blocks: u32, first: u32, ops: &[Op]) -> Result<(), TestCaseError> {
    let pool =
        BlockPool::new(PoolConfig::new(blocks as u64 * 512, 512).with_first_id(AllocId(first)))
            .map_err(|e| TestCaseError::fail(e.to_string()))?;
    let mut m = Model::new(blocks, first);
    let mut held: Vec<(Block, u64)> = Vec::new();
    for op in ops {
        match *op {
            Op::Alloc(lead) | Op::AllocBehind(lead) => {
                let id64 = match *op {
                    Op::Alloc(_) => m.free + lead as u64,
                    _ => m.free - lead as u64,
                };
                let (id, free_id) = (wrap(id64), wrap(m.free));
                let got = pool.try_allocate(id);
                // 2^31 or more ahead is, in 32 bits, the same ID as one up to 2^31 behind.
                if id64 <= m.free || id64 - m.free >= 1 << 31 {
                    prop_assert_eq!(got, Err(Error::IdRetired { id, free_id }));
                } else if id64 - m.free > MAX_ID_LEAD as u64 {
                    prop_assert_eq!(
                        got,
                        Err(Error::IdTooFarAhead {
                            id,
                            free_id,
                            limit: MAX_ID_LEAD
                        })
                    );
                } else if (0..m.slots.len()).all(|i| m.live(i)) {
                    prop_assert_eq!(
                        got,
                        Err(Error::Exhausted {
                            id,
                            blocks,
                            attempts: 1
                        })
                    );
                } else {
                    let b = got.map_err(|e| TestCaseError::fail(format!("{op:?}: {e}")))?;
                    let i = b.index() as usize;
                    prop_assert!(!m.live(i), "{:?} handed out live block {}", op, i);
                    prop_assert_eq!(b.id(), id);
                    prop_assert_eq!(b.offset(), i as u64 * 512);
                    prop_assert_eq!(b.bytes(), 512);
                    m.slots[i] = id64;
                    held.push((b, id64));
                }
            }
            Op::Advance(step) => {
                let got = pool.advance_free_id(wrap(m.free + step as u64));
                if step == 0 || step > u32::MAX / 2 {
                    // Not ahead: a stale marker, no change.
                    prop_assert_eq!(got, Ok(wrap(m.free)));
                } else if step > MAX_FREE_STEP {
                    prop_assert_eq!(
                        got,
                        Err(Error::FreeStepTooLarge {
                            free_id: wrap(m.free),
                            to: wrap(m.free + step as u64),
                            limit: MAX_FREE_STEP
                        })
                    );
                } else {
                    m.free += step as u64;
                    prop_assert_eq!(got, Ok(wrap(m.free)));
                }
            }
            Op::Retreat(back) => {
                prop_assert_eq!(
                    pool.advance_free_id(wrap(m.free - back as u64)),
                    Ok(wrap(m.free))
                );
            }
        }
        // The whole observable state agrees with the model.
        prop_assert_eq!(pool.free_id(), wrap(m.free));
        let live = (0..m.slots.len()).filter(|&i| m.live(i)).count() as u32;
        prop_assert_eq!(pool.free_blocks(), blocks - live);
        for i in 0..m.slots.len() {
            prop_assert_eq!(
                pool.is_live(i as u32),
                Ok(m.live(i)),
                "block {} after {:?}",
                i,
                op
            );
            if m.live(i) {
                prop_assert_eq!(pool.block_id(i as u32), Ok(wrap(m.slots[i])));
            }
        }
        for (b, id64) in &held {
            let holds = m.slots[b.index() as usize] == *id64 && *id64 > m.free;
            prop_assert_eq!(pool.holds(b), holds);
        }
        held.retain(|(b, _)| pool.holds(b));
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 192, ..ProptestConfig::default() })]

    #[test]
    fn pool_matches_the_unwrapped_model(
        blocks in 1..7u32,
        first in first_id(),
        ops in prop::collection::vec(op(), 1..160),
    ) {
        run_pool(blocks, first, &ops)?;
    }
}

/// One pass's writes in a frame: (pass, is_command, bytes, log2 align).
type Push = (u32, bool, u32, u32);

fn run_streams(
    first: u32,
    budgets: &[u32],
    frames: &[Vec<Push>],
    lag: usize,
) -> Result<(), TestCaseError> {
    const BLOCK: u32 = 1024;
    const BLOCKS: u32 = 8;
    let pool = BlockPool::new(
        PoolConfig::new((BLOCKS * BLOCK) as u64, BLOCK).with_first_id(AllocId(first)),
    )
    .unwrap();
    let plan = FramePlan::new(budgets).unwrap();
    let mut gpu = SimulatedGpu::new();
    // Byte map of the pool: 0 = free, else the owning span's tag.
    let mut bytes = vec![0u32; (BLOCKS * BLOCK) as usize];
    let mut frame = plan.frame(pool.free_id().next());
    let mut tag = 0u32;
    let mut submitted_frames = std::collections::VecDeque::new();
    for writes in frames {
        // Streams are created in reverse pass order: allocation order must not matter.
        let mut streams: Vec<Stream> = (0..plan.pass_count())
            .rev()
            .map(|p| Stream::new(&pool, frame.pass(p).unwrap()))
            .collect();
        streams.reverse();
        let mut reads = Vec::new();
        for &(pass, command, size, align_log2) in writes {
            let pass = pass % plan.pass_count();
            let s = &mut streams[pass as usize];
            let align = 1 << align_log2;
            let got = if command {
                s.push_command(size, align)
            } else {
                s.push_data(size, align)
            };
            match got {
                Ok(span) => {
                    tag += 1;
                    prop_assert_eq!(span.offset % align as u64, 0);
                    prop_assert!(span.offset >= span.block as u64 * BLOCK as u64);
                    prop_assert!(
                        (span.offset + size as u64) <= (span.block as u64 + 1) * BLOCK as u64
                    );
                    prop_assert!(frame.pass(pass).unwrap().contains(span.id));
                    for b in &mut bytes[span.offset as usize..(span.offset + size as u64) as usize]
                    {
                        prop_assert_eq!(*b, 0, "byte handed out twice");
                        *b = tag;
                    }
                    reads.push((pass, span));
                }
                // The pool is full of frames the GPU has not finished: drain them.
                Err(Error::Exhausted { .. }) => {}
                Err(e) => return Err(TestCaseError::fail(e.to_string())),
            }
        }
        // The GPU reads the frame pass by pass, then passes its free marker.
        reads.sort_by_key(|&(pass, _)| pass);
        for &(_, span) in &reads {
            gpu.submit(GpuCommand::Read {
                block: span.block,
                id: span.id,
            });
        }
        gpu.submit(GpuCommand::Free(frame.last()));
        submitted_frames.push_back(reads);
        // A lagging GPU: only frames older than `lag` complete now.
        while submitted_frames.len() > lag {
            let done = submitted_frames.pop_front().unwrap();
            let n = done.len() + 1;
            prop_assert_eq!(gpu.run(&pool, n), Ok(n));
            for (_, span) in done {
                bytes[span.offset as usize..(span.offset + span.bytes as u64) as usize].fill(0);
            }
        }
        frame = frame.next();
    }
    prop_assert_eq!(gpu.run(&pool, usize::MAX).map(|_| gpu.pending()), Ok(0));
    prop_assert_eq!(pool.free_blocks(), BLOCKS);
    Ok(())
}

fn push() -> impl Strategy<Value = Push> {
    (
        0..4u32,
        any::<bool>(),
        prop_oneof![0..64u32, 0..=1024u32],
        0..9u32,
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn streams_never_share_live_bytes(
        first in first_id(),
        budgets in prop::collection::vec(1..5u32, 1..4),
        frames in prop::collection::vec(prop::collection::vec(push(), 0..24), 1..12),
        lag in 0..3usize,
    ) {
        run_streams(first, &budgets, &frames, lag)?;
    }
}
