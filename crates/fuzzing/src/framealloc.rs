//! `framealloc`: operation sequences on the block pool and on per-pass streams, checked
//! against simple models.

use framealloc::sim::{GpuCommand, SimulatedGpu};
use framealloc::{
    AllocId, Block, BlockPool, Error, FramePlan, MAX_FREE_STEP, MAX_ID_LEAD, PoolConfig, Span,
    Spin, Stream,
};

use crate::Input;

/// Pool operations (allocate with any ID, advance FreeID by any step, spin-waits, simulated
/// GPU reads of held blocks) from arbitrary bytes, against a model with unwrapped `u64` IDs
/// and a plain per-block table. Every answer, error or block, must match the model, and no
/// live block is ever handed out again.
pub fn framealloc_pool_ops(data: &[u8]) {
    let mut inp = Input::new(data);
    let blocks = 1 + u32::from(inp.u8() % 8);
    let first = inp.u32();
    let pool =
        BlockPool::new(PoolConfig::new(blocks as u64 * 256, 256).with_first_id(AllocId(first)))
            .expect("a valid layout");
    // The model: FreeID and block IDs unwrapped, far from 0 so "behind" never underflows.
    let mut free: u64 = (4u64 << 32) + first as u64 - 1;
    let mut slots = vec![free; blocks as usize];
    let mut held: Vec<(Block, u64)> = Vec::new();
    let mut gpu = SimulatedGpu::new();
    let wrap = |x: u64| AllocId(x as u32);
    while inp.remaining() > 0 {
        let kind = inp.u8() % 8;
        match kind {
            0..=3 | 7 => {
                let lead = match kind {
                    3 => inp.u32(),
                    _ => u32::from(inp.u8() % 8),
                };
                let id64 = free + lead as u64;
                let (id, free_id) = (wrap(id64), wrap(free));
                let spins = 1 + u32::from(inp.u8() % 3);
                let got = if kind == 7 {
                    pool.allocate_with(
                        id,
                        &mut Spin {
                            max_attempts: spins,
                        },
                    )
                } else {
                    pool.try_allocate(id)
                };
                let any_free = slots.iter().any(|&s| s <= free);
                let attempts = if kind == 7 { spins } else { 1 };
                match got {
                    Ok(b) => {
                        assert!(lead != 0 && lead <= MAX_ID_LEAD && any_free, "{id}: {b:?}");
                        let i = b.index() as usize;
                        assert!(slots[i] <= free, "live block {i} handed out again");
                        assert_eq!((b.id(), b.offset()), (id, i as u64 * 256));
                        slots[i] = id64;
                        held.push((b, id64));
                    }
                    Err(e) => {
                        let want = if lead == 0 || lead > u32::MAX / 2 {
                            Error::IdRetired { id, free_id }
                        } else if lead > MAX_ID_LEAD {
                            Error::IdTooFarAhead {
                                id,
                                free_id,
                                limit: MAX_ID_LEAD,
                            }
                        } else {
                            assert!(!any_free, "{e} with a free block");
                            Error::Exhausted {
                                id,
                                blocks,
                                attempts,
                            }
                        };
                        assert_eq!(e, want);
                    }
                }
            }
            4 | 5 => {
                let step = if kind == 4 {
                    u32::from(inp.u8() % 8)
                } else {
                    inp.u32()
                };
                let got = pool.advance_free_id(wrap(free + step as u64));
                if step == 0 || step > u32::MAX / 2 {
                    assert_eq!(got, Ok(wrap(free)));
                } else if step > MAX_FREE_STEP {
                    assert!(matches!(got, Err(Error::FreeStepTooLarge { .. })));
                } else {
                    free += step as u64;
                    assert_eq!(got, Ok(wrap(free)));
                }
            }
            _ => {
                // The simulated GPU reads a held block: fine iff the model says it is live.
                if held.is_empty() {
                    continue;
                }
                let k = inp.u8() as usize % held.len();
                let (b, id64) = (&held[k].0, held[k].1);
                gpu.submit(GpuCommand::Read {
                    block: b.index(),
                    id: b.id(),
                });
                let live = slots[b.index() as usize] == id64 && id64 > free;
                assert_eq!(gpu.step(&pool).is_ok(), live);
                assert_eq!(pool.holds(b), live);
                if !live {
                    held.swap_remove(k);
                }
            }
        }
        assert_eq!(pool.free_id(), wrap(free));
        let free_count = slots.iter().filter(|&&s| s <= free).count() as u32;
        assert_eq!(pool.free_blocks(), free_count);
        for (i, &s) in slots.iter().enumerate() {
            assert_eq!(pool.is_live(i as u32), Ok(s > free));
        }
    }
}

/// Per-pass streams over frames from arbitrary bytes: pushes of any size and alignment at
/// either end, frames submitted to a simulated GPU that lags by a chosen number of frames.
/// A byte map of the pool checks that no byte is ever handed to two live spans, and every
/// error is the one the request deserves.
pub fn framealloc_stream_ops(data: &[u8]) {
    let mut inp = Input::new(data);
    let block = 256 * (1 + u32::from(inp.u8() % 8));
    let blocks = 1 + u32::from(inp.u8() % 8);
    let first = inp.u32();
    let passes = 1 + inp.u8() % 4;
    let budgets: Vec<u32> = (0..passes).map(|_| 1 + u32::from(inp.u8() % 4)).collect();
    let lag = usize::from(inp.u8() % 3);
    let pool = BlockPool::new(
        PoolConfig::new(blocks as u64 * block as u64, block).with_first_id(AllocId(first)),
    )
    .expect("a valid layout");
    let plan = FramePlan::new(&budgets).expect("a valid plan");
    let mut owner = vec![0u32; (blocks * block) as usize];
    let mut gpu = SimulatedGpu::new();
    let mut in_flight: std::collections::VecDeque<Vec<Span>> = Default::default();
    let mut frame = plan.frame(pool.free_id().next());
    let mut tag = 0u32;
    while inp.remaining() > 0 {
        let mut streams: Vec<Stream> = (0..plan.pass_count())
            .map(|p| Stream::new(&pool, frame.pass(p).expect("pass in plan")))
            .collect();
        let mut spans: Vec<(u32, Span)> = Vec::new();
        // Pushes until a byte says "end of frame".
        loop {
            let op = inp.u8();
            if op >= 0xf0 || inp.remaining() == 0 {
                break;
            }
            let pass = u32::from(op % passes);
            let size = u32::from(inp.u16()) % (block + 64);
            let align = match inp.u8() {
                a @ 0..=15 => 1u32 << a,
                a => u32::from(a),
            };
            let s = &mut streams[pass as usize];
            let got = if op & 0x10 == 0 {
                s.push_command(size, align)
            } else {
                s.push_data(size, align)
            };
            let bad_align = !align.is_power_of_two() || block % align != 0;
            match got {
                Ok(span) => {
                    assert!(!bad_align && size <= block);
                    assert_eq!(span.offset % align as u64, 0);
                    assert!(span.offset >= span.block as u64 * block as u64);
                    assert!(span.offset + size as u64 <= (span.block as u64 + 1) * block as u64);
                    assert!(frame.pass(pass).expect("pass").contains(span.id));
                    tag += 1;
                    for b in &mut owner[span.offset as usize..(span.offset + size as u64) as usize]
                    {
                        assert_eq!(*b, 0, "byte handed to two live spans");
                        *b = tag;
                    }
                    spans.push((pass, span));
                }
                Err(Error::BadAlignment { .. }) => assert!(bad_align),
                Err(Error::TooLarge { .. }) => assert!(!bad_align && size > block),
                Err(Error::Exhausted { .. }) => assert_eq!(pool.free_blocks(), 0),
                Err(e) => panic!("unexpected error {e}"),
            }
        }
        drop(streams);
        spans.sort_by_key(|&(pass, _)| pass);
        for &(_, s) in &spans {
            gpu.submit(GpuCommand::Read {
                block: s.block,
                id: s.id,
            });
        }
        gpu.submit(GpuCommand::Free(frame.last()));
        in_flight.push_back(spans.into_iter().map(|(_, s)| s).collect());
        while in_flight.len() > lag {
            let done = in_flight.pop_front().expect("non-empty");
            let n = done.len() + 1;
            assert_eq!(gpu.run(&pool, n), Ok(n), "the GPU found a block reused");
            for s in done {
                owner[s.offset as usize..(s.offset + s.bytes as u64) as usize].fill(0);
            }
        }
        frame = frame.next();
    }
    assert_eq!(gpu.run(&pool, usize::MAX).map(|_| gpu.pending()), Ok(0));
    assert_eq!(pool.free_blocks(), blocks);
}
