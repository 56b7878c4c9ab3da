//! Killzone 2's lock-free render-memory allocator, for per-frame GPU uploads.
//!
//! Source: Michal Valient, "The Rendering Technology of Killzone 2", GDC 2009, the "KZ2
//! render memory allocator" slides (`shared/seeds/002_*`). Many threads (SPUs there, worker
//! threads here) build commands and data for the GPU at the same time and out of order;
//! ring buffers cannot take out-of-order allocations and double buffering costs too much
//! memory. KZ2's answer, implemented here:
//!
//! - a fixed pool (KZ2: 22 MiB) split into equal blocks (KZ2: 256 KiB), [`BlockPool`];
//! - each block records the [`AllocId`] its client gave when allocating it;
//! - one global FreeID, advanced when the GPU passes a "free" marker
//!   ([`BlockPool::advance_free_id`]); a block is free iff its AllocationID ≤ FreeID;
//! - allocation walks the table lock-free and claims a block with one compare-and-swap,
//!   from any thread and in any order ([`BlockPool::try_allocate`]);
//! - each pass of a frame uses its own range of IDs, so its blocks free at the right point
//!   of the frame ([`FramePlan`], [`PassIds`]);
//! - IDs are `u32` and wrap; they are compared with serial-number arithmetic and the pool
//!   keeps every compared pair within the safe window ([`id`], [`pool`]);
//! - inside a block, a double-ended bump allocator puts commands at the front and their
//!   data at the back, full when they meet ([`BlockBump`], chained across blocks by
//!   [`Stream`]).
//!
//! Exhaustion is [`Error::Exhausted`], or a wait if the caller passes a [`Wait`]
//! ([`Spin`], a polling closure, or under `std` [`Blocking`]); never a panic, never a block
//! handed out while live. The crate owns no memory: it hands out byte offsets into a pool
//! the caller owns. It is `no_std` (atomics from `core`, `alloc` for the table); the `std`
//! feature (default) adds the blocking wait.
//!
//! # Example
//!
//! A frame of two passes, written out of order by two "threads", consumed by the
//! [`sim::SimulatedGpu`] that stands in for the GPU:
//!
//! ```
//! use framealloc::{BlockPool, FramePlan, PoolConfig, Stream};
//! use framealloc::sim::{GpuCommand, SimulatedGpu};
//!
//! let pool = BlockPool::new(PoolConfig::KZ2)?; // 88 blocks of 256 KiB
//! let plan = FramePlan::new(&[100, 800])?;     // geometry, lighting
//! let mut gpu = SimulatedGpu::new();
//! let mut frame = plan.frame(pool.free_id().next());
//! for _ in 0..3 {
//!     // Lighting's writer may well run before geometry's: only the IDs matter.
//!     let mut lighting = Stream::new(&pool, frame.pass(1)?);
//!     let mut geometry = Stream::new(&pool, frame.pass(0)?);
//!     let l = lighting.push_data(200_000, 256)?;
//!     let g = geometry.push_command(4096, 16)?;
//!     // The GPU runs geometry, then lighting, then passes the frame's free marker.
//!     gpu.submit(GpuCommand::Read { block: g.block, id: g.id });
//!     gpu.submit(GpuCommand::Read { block: l.block, id: l.id });
//!     gpu.submit(GpuCommand::Free(frame.last()));
//!     frame = frame.next();
//! }
//! gpu.run(&pool, usize::MAX)?; // errors if a read found its block reused
//! assert_eq!(pool.free_blocks(), 88);
//! # Ok::<(), framealloc::Error>(())
//! ```
//!
//! # Driving it from wgpu
//!
//! The `gpu` crate's per-frame uploads run through it (`gpu`'s `resources/uploads.rs`: every
//! frame's writes sub-allocated from one pool buffer and copied ahead of the frame's
//! commands). Any wgpu user can drive it like this:
//!
//! 1. Create one `wgpu::Buffer` of [`BlockPool::pool_bytes`] (usages as needed, e.g.
//!    `COPY_DST | VERTEX | INDEX | UNIFORM | STORAGE | INDIRECT`) and one `BlockPool` in an
//!    `Arc`. Block and suballocation offsets ([`Block::offset`], [`Span::offset`]) are byte
//!    offsets into that buffer; blocks are multiples of [`BLOCK_ALIGNMENT`] (256) so a
//!    256-aligned span can be bound as a uniform or storage buffer directly.
//! 2. Make a [`FramePlan`] with one ID budget per pass, in the order the passes are
//!    submitted (a budget is how many blocks, or block groups that free together, a pass
//!    may tag separately). Keep a frame counter: frame `n` uses
//!    `plan.nth_frame(first, n)` (or `frame.next()` each frame), starting at
//!    `pool.free_id().next()`.
//! 3. Each pass's writers allocate with IDs from that pass's range only, in the order the
//!    GPU will consume their blocks: one [`Stream`] per writer thread, each on its own
//!    [`PassIds::split`] part when a pass has several. Data that must live until a later
//!    pass is tagged with an ID of that later pass. Write the bytes with
//!    `queue.write_buffer(&buffer, span.offset, bytes)` (or through a mapped staging
//!    buffer copied to `span.offset`).
//! 4. After `queue.submit(...)` of the frame's command buffers, register
//!    `queue.on_submitted_work_done(move || { let _ = pool.advance_free_id(last); })`
//!    where `last` is the last ID of the passes in that submission ([`FrameIds::last`] for
//!    a one-submission frame; per submission when a frame submits pass by pass). The
//!    callback runs once the GPU has finished that submission, during a later
//!    `device.poll(..)` or `queue.submit(..)`, on whichever thread calls it. FreeID then
//!    frees every block of the submitted passes at once. Never advance FreeID to an ID of
//!    work not yet submitted: that frees blocks still being written.
//! 5. When allocation fails with [`Error::Exhausted`], the GPU is behind: either drop or
//!    defer the upload, or wait with [`BlockPool::allocate_with`] and a closure that polls,
//!    `|_: &Stall| device.poll(wgpu::PollType::Poll).is_ok()` (or
//!    `PollType::wait_indefinitely()` to sleep until the oldest submission completes).
//!    [`Blocking`] only suits a thread that is not itself the one polling the device.
//!
//! With `queue.write_buffer` wgpu already orders the copy after earlier submissions; the
//! allocator's job is that two uploads in flight never share bytes, so no frame's data is
//! clobbered before the GPU has read it, and that memory is reused as soon as the GPU is
//! done, without a ring's in-order constraint.
//!
//! # Limits
//!
//! | constant | value | what |
//! | --- | --- | --- |
//! | [`MAX_ID_LEAD`] | 2^30 | an allocation's ID is at most this far ahead of FreeID |
//! | [`MAX_FREE_STEP`] | 2^30 | one FreeID advance moves it at most this far |
//! | [`MAX_BLOCKS`] | 65,536 | blocks per pool (allocation walks the table) |
//! | [`BLOCK_ALIGNMENT`] | 256 bytes | block sizes are multiples of it |
//! | [`MAX_PASSES`] | 64 | passes per [`FramePlan`] |
//! | [`MAX_FRAME_SPAN`] | 2^24 | IDs per frame |

#![no_std]
#![cfg_attr(docsrs, feature(doc_cfg))]

extern crate alloc;
#[cfg(feature = "std")]
extern crate std;

pub mod bump;
mod error;
pub mod id;
pub mod plan;
pub mod pool;
pub mod sim;
pub mod stream;

pub use bump::BlockBump;
pub use error::Error;
pub use id::{AllocId, MAX_FREE_STEP, MAX_ID_LEAD};
pub use plan::{FrameIds, FramePlan, IdCursor, MAX_FRAME_SPAN, MAX_PASSES, PassIds};
#[cfg(feature = "std")]
pub use pool::Blocking;
pub use pool::{
    BLOCK_ALIGNMENT, Block, BlockPool, KZ2_BLOCK_BYTES, KZ2_POOL_BYTES, MAX_BLOCKS, NoWait,
    PoolConfig, Spin, Stall, Wait,
};
pub use stream::{Span, Stream};
