//! KZ2's frame structure: passes allocate out of order, each block frees at the point of
//! the frame where the GPU is done with it, and early allocations for late passes (KZ2's
//! skinning) live until their last reader.

use framealloc::sim::{GpuCommand, SimulatedGpu};
use framealloc::{AllocId, BlockPool, FramePlan, PoolConfig, Stream};

#[test]
fn blocks_free_at_the_end_of_their_pass_whatever_the_allocation_order() {
    let pool = BlockPool::new(PoolConfig::new(16 * 1024, 1024)).unwrap();
    // Geometry, lighting (split among 3 shadow tasks), forward.
    let plan = FramePlan::new(&[10, 30, 10]).unwrap();
    let frame = plan.frame(pool.free_id().next());
    let (geometry, lighting, forward) = (
        frame.pass(0).unwrap(),
        frame.pass(1).unwrap(),
        frame.pass(2).unwrap(),
    );

    // Allocation order: forward, shadow task 2, geometry, shadow task 0, shadow task 1.
    let mut fwd = Stream::new(&pool, forward);
    let f = fwd.push_data(1000, 4).unwrap();
    let shadow: Vec<_> = (0..3).map(|t| lighting.split(t, 3).unwrap()).collect();
    let mut s2 = Stream::new(&pool, shadow[2]);
    let l2 = s2.push_command(600, 4).unwrap();
    let l2b = s2.push_command(600, 4).unwrap(); // second block, next ID of task 2
    let mut geo = Stream::new(&pool, geometry);
    let g = geo.push_data(1000, 4).unwrap();
    // KZ2's early skinning: made now, read by the forward pass, so tagged with forward's
    // last ID even though geometry allocates it.
    let skin = pool.try_allocate(forward.last()).unwrap();
    let mut s0 = Stream::new(&pool, shadow[0]);
    let l0 = s0.push_command(10, 4).unwrap();
    let mut s1 = Stream::new(&pool, shadow[1]);
    let l1 = s1.push_command(10, 4).unwrap();
    assert_eq!(pool.free_blocks(), 16 - 7);

    // The GPU runs the frame in pass order, with a free marker at the end of each pass and
    // after each shadow task.
    let mut gpu = SimulatedGpu::new();
    let read = |s: &framealloc::Span| GpuCommand::Read {
        block: s.block,
        id: s.id,
    };
    gpu.submit(read(&g));
    gpu.submit(GpuCommand::Free(geometry.last()));
    gpu.run(&pool, 2).unwrap();
    // Only geometry's block is free: the shadow, forward and skinning blocks stay.
    assert_eq!(pool.free_blocks(), 16 - 6);
    assert!(!pool.is_live(g.block).unwrap());
    for s in [&l0, &l1, &l2, &l2b, &f] {
        assert!(pool.is_live(s.block).unwrap());
    }

    for (task, spans) in [(0, vec![l0]), (1, vec![l1]), (2, vec![l2, l2b])] {
        for s in &spans {
            gpu.submit(read(s));
        }
        gpu.submit(GpuCommand::Free(shadow[task].last()));
        gpu.run(&pool, spans.len() + 1).unwrap();
        assert!(spans.iter().all(|s| !pool.is_live(s.block).unwrap()));
    }
    assert_eq!(pool.free_blocks(), 16 - 2);
    assert!(pool.holds(&skin));

    gpu.submit(read(&f));
    gpu.submit(GpuCommand::Read {
        block: skin.index(),
        id: skin.id(),
    });
    gpu.submit(GpuCommand::Free(frame.last()));
    gpu.run(&pool, usize::MAX).unwrap();
    assert_eq!(pool.free_blocks(), 16);
    assert_eq!(pool.free_id(), frame.last());
}

#[test]
fn a_block_freed_too_early_is_caught_by_the_simulated_gpu() {
    // The rule the plan exists for: a block tagged with an earlier pass's ID than the pass
    // that reads it frees too early, and the GPU's read finds it reused.
    let pool = BlockPool::new(PoolConfig::new(1024, 1024)).unwrap();
    let plan = FramePlan::new(&[1, 1]).unwrap();
    let frame = plan.frame(AllocId(1));
    let wrong = pool.try_allocate(frame.pass(0).unwrap().first()).unwrap(); // read in pass 1
    let mut gpu = SimulatedGpu::new();
    gpu.submit(GpuCommand::Free(frame.pass(0).unwrap().last()));
    gpu.run(&pool, 1).unwrap();
    let thief = pool.try_allocate(frame.next().first()).unwrap();
    assert_eq!(thief.index(), wrong.index());
    gpu.submit(GpuCommand::Read {
        block: wrong.index(),
        id: wrong.id(),
    });
    assert!(matches!(
        gpu.run(&pool, 1),
        Err(framealloc::Error::NotLive { .. })
    ));
}
