//! The block pool: KZ2's table of AllocationIDs and the global FreeID.
//!
//! A fixed pool of memory (KZ2: 22 MiB) is split into equal blocks (KZ2: 256 KiB). The
//! table holds one 32-bit slot per block: the [`AllocId`] its last client gave. A single
//! global FreeID says which blocks are free: block `i` is free iff
//! `table[i] <= FreeID` (wrap-around-safe, see [`AllocId::is_at_or_before`]).
//!
//! - **Allocation** reads FreeID, walks the table from a rotating start and claims the
//!   first free slot with one compare-and-swap that writes the client's ID (walking again
//!   if FreeID moved during the walk, so a preempted thread never reports exhaustion while
//!   blocks are free). No lock, and allocations from many threads may come in any order:
//!   only the IDs encode when each block frees.
//! - **Freeing** is implicit. A client's "free(id)" is a marker in the GPU's command stream;
//!   when the GPU passes it, the consumer calls [`BlockPool::advance_free_id`] and every
//!   block tagged with an ID at or before it becomes free at once.
//!
//! # Wrap-around
//!
//! IDs are `u32` and wrap. Serial-number comparison is exact while the compared IDs are
//! less than 2^31 apart, and the pool keeps it so:
//!
//! - an allocation's ID may be at most [`MAX_ID_LEAD`] (2^30) ahead of FreeID, else
//!   [`Error::IdTooFarAhead`]; at or before FreeID it is [`Error::IdRetired`];
//! - one advance moves FreeID by at most [`MAX_FREE_STEP`] (2^30), else
//!   [`Error::FreeStepTooLarge`];
//! - a free block left untouched would drift more than 2^31 behind FreeID and then compare
//!   as *ahead* of it, i.e. live forever. So whenever FreeID enters a new quarter of the
//!   32-bit range (its top two bits change), the advancing call sweeps the table and
//!   rewrites every free slot to the new FreeID (with a compare-and-swap, so a concurrent
//!   claim wins). Free slots then never lag FreeID by more than 2^31 - 1. The sweep is one
//!   pass over the table every 2^30 IDs.
//!
//! The one window this leaves: a thread suspended *inside* a single allocation while FreeID
//! advances by 2^30 or more could misjudge a slot with its stale FreeID. At 10,000 IDs per
//! frame and 60 frames per second that is a 30-minute stall inside one call.
//!
//! # The contract
//!
//! FreeID may only pass an ID after the GPU has finished every block tagged with it, and
//! clients only allocate with IDs of work the GPU has not yet been given (so FreeID cannot
//! pass them while they fill the block). Under that contract a block is never handed to two
//! clients at once, which `tests/stress.rs` checks with many threads.

use alloc::boxed::Box;
use alloc::vec::Vec;
use core::ops::Range;
use core::sync::atomic::{AtomicU32, Ordering};

use crate::{AllocId, Error, MAX_FREE_STEP, MAX_ID_LEAD};

#[cfg(feature = "std")]
use std::sync::{Condvar, Mutex, PoisonError};
#[cfg(feature = "std")]
use std::time::{Duration, Instant};

/// Killzone 2's pool size: 22 MiB.
pub const KZ2_POOL_BYTES: u64 = 22 * 1024 * 1024;

/// Killzone 2's block size: 256 KiB.
pub const KZ2_BLOCK_BYTES: u32 = 256 * 1024;

/// Block sizes must be a multiple of this many bytes (256: wgpu's default
/// `min_uniform_buffer_offset_alignment` and `min_storage_buffer_offset_alignment`, and a
/// multiple of `COPY_BUFFER_ALIGNMENT`), so block offsets can be bound directly.
pub const BLOCK_ALIGNMENT: u32 = 256;

/// The most blocks a pool may have (65,536). Allocation walks the table linearly, so pools
/// are meant to have tens to a few thousand blocks (KZ2: 88).
pub const MAX_BLOCKS: u32 = 1 << 16;

/// How a pool is laid out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PoolConfig {
    /// Total bytes in the pool; a whole multiple of `block_bytes`.
    pub pool_bytes: u64,
    /// Bytes per block; a non-zero multiple of [`BLOCK_ALIGNMENT`].
    pub block_bytes: u32,
    /// The first ID clients will allocate with. FreeID starts one before it, so every block
    /// starts free.
    pub first_id: AllocId,
}

impl PoolConfig {
    /// Killzone 2's layout: 22 MiB in 256 KiB blocks (88 blocks), first ID 1.
    pub const KZ2: PoolConfig = PoolConfig::new(KZ2_POOL_BYTES, KZ2_BLOCK_BYTES);

    /// A layout of `pool_bytes` in blocks of `block_bytes`, first ID 1.
    #[must_use]
    pub const fn new(pool_bytes: u64, block_bytes: u32) -> Self {
        PoolConfig {
            pool_bytes,
            block_bytes,
            first_id: AllocId(1),
        }
    }

    /// The same layout with another first ID (tests start near `u32::MAX` to cross the
    /// wrap early).
    #[must_use]
    pub const fn with_first_id(mut self, first_id: AllocId) -> Self {
        self.first_id = first_id;
        self
    }

    /// The number of blocks this layout makes, or why it is invalid.
    pub const fn block_count(&self) -> Result<u32, Error> {
        if self.block_bytes == 0 || !self.block_bytes.is_multiple_of(BLOCK_ALIGNMENT) {
            return Err(Error::BadConfig {
                what: "block_bytes must be a non-zero multiple of BLOCK_ALIGNMENT (256)",
                value: self.block_bytes as u64,
            });
        }
        if !self.pool_bytes.is_multiple_of(self.block_bytes as u64) {
            return Err(Error::BadConfig {
                what: "pool_bytes must be a whole number of blocks",
                value: self.pool_bytes,
            });
        }
        let blocks = self.pool_bytes / self.block_bytes as u64;
        if blocks == 0 || blocks > MAX_BLOCKS as u64 {
            return Err(Error::BadConfig {
                what: "the block count must be 1 ..= MAX_BLOCKS (65536)",
                value: blocks,
            });
        }
        Ok(blocks as u32)
    }
}

/// One table slot. Slots are packed, 16 to a cache line: a walk reads few lines, and with
/// two threads hammering the pool this measured 2-3x faster than one slot per line (the
/// walks touched more lines the other thread had just written). See BENCHMARKS.md.
#[derive(Debug)]
struct Slot(AtomicU32);

/// A word on its own cache line: FreeID (written by the consumer) and the walk hint
/// (written by allocators) stay off each other's line and off the read-only fields.
#[repr(align(64))]
#[derive(Debug)]
struct Padded(AtomicU32);

/// A block handed to one client: the right to write `offset .. offset + bytes` of the pool
/// until FreeID reaches `id`.
///
/// Not `Clone`: holding a `Block` means being its one writer. Dropping it frees nothing;
/// the block frees when FreeID passes its ID.
#[derive(Debug, PartialEq, Eq, Hash)]
pub struct Block {
    index: u32,
    id: AllocId,
    offset: u64,
    bytes: u32,
}

impl Block {
    /// The block's index in the pool's table, `0 .. block_count`.
    #[inline]
    #[must_use]
    pub fn index(&self) -> u32 {
        self.index
    }

    /// The AllocationID this block was claimed with; it frees when FreeID reaches it.
    #[inline]
    #[must_use]
    pub fn id(&self) -> AllocId {
        self.id
    }

    /// Byte offset of the block's first byte from the start of the pool (in wgpu: the
    /// offset into the pool's `Buffer`). A multiple of the block size.
    #[inline]
    #[must_use]
    pub fn offset(&self) -> u64 {
        self.offset
    }

    /// Bytes in the block.
    #[inline]
    #[must_use]
    pub fn bytes(&self) -> u32 {
        self.bytes
    }

    /// The block's byte range in the pool.
    #[inline]
    #[must_use]
    pub fn range(&self) -> Range<u64> {
        self.offset..self.offset + self.bytes as u64
    }
}

/// What a [`Wait`] is told when a table walk found every block live.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct Stall {
    /// The ID being allocated.
    pub id: AllocId,
    /// The FreeID the failed walk used. The next walk can only succeed once FreeID has
    /// moved past it.
    pub free_id: AllocId,
    /// Rounds of walking made so far, from 1.
    pub attempt: u32,
}

/// What an allocation does when every block is live: wait somehow and retry, or give up.
///
/// Implemented for closures `FnMut(&Stall) -> bool` (write the argument's type,
/// `|s: &Stall|`, so the closure takes any borrow). That is how a wgpu user polls the device
/// while waiting, `|_: &Stall| device.poll(wgpu::PollType::Poll).is_ok()`: on native wgpu,
/// FreeID only advances inside a poll or submit, so a thread that blocks without polling
/// could wait forever.
///
/// ```
/// use framealloc::{AllocId, BlockPool, PoolConfig, Stall};
/// let pool = BlockPool::new(PoolConfig::new(256, 256))?;
/// let _live = pool.try_allocate(AllocId(1))?;
/// // Stand-in for `device.poll(..)`, whose callbacks would advance FreeID.
/// let mut poll = |s: &Stall| s.attempt < 3 && pool.advance_free_id(AllocId(1)).is_ok();
/// let b = pool.allocate_with(AllocId(2), &mut poll)?;
/// assert_eq!(b.id(), AllocId(2));
/// # Ok::<(), framealloc::Error>(())
/// ```
pub trait Wait {
    /// Called after a walk found no free block. Return `true` to walk again, `false` to
    /// give up with [`Error::Exhausted`].
    fn wait(&mut self, pool: &BlockPool, stall: &Stall) -> bool;
}

impl<F: FnMut(&Stall) -> bool> Wait for F {
    fn wait(&mut self, _pool: &BlockPool, stall: &Stall) -> bool {
        self(stall)
    }
}

/// Never wait: exhaustion is an immediate [`Error::Exhausted`].
#[derive(Clone, Copy, Debug, Default)]
pub struct NoWait;

impl Wait for NoWait {
    #[inline]
    fn wait(&mut self, _pool: &BlockPool, _stall: &Stall) -> bool {
        false
    }
}

/// Busy-wait with exponential back-off (`core::hint::spin_loop`), up to `max_attempts`
/// rounds of walking. For no_std consumers that advance FreeID from another core or an interrupt.
#[derive(Clone, Copy, Debug)]
pub struct Spin {
    /// Rounds of walking before giving up.
    pub max_attempts: u32,
}

impl Wait for Spin {
    fn wait(&mut self, pool: &BlockPool, stall: &Stall) -> bool {
        if stall.attempt >= self.max_attempts {
            return false;
        }
        let spins = 1u32 << stall.attempt.min(12);
        for _ in 0..spins {
            if pool.free_id() != stall.free_id {
                break;
            }
            core::hint::spin_loop();
        }
        true
    }
}

/// Block the thread until FreeID advances (on a condition variable the pool signals from
/// [`BlockPool::advance_free_id`]), up to a deadline. Needs another thread to advance
/// FreeID: with wgpu, another thread must be polling the device.
#[cfg(feature = "std")]
#[derive(Clone, Copy, Debug)]
pub struct Blocking {
    deadline: Option<Instant>,
}

#[cfg(feature = "std")]
impl Blocking {
    /// Wait at most `timeout` in total, across all retries.
    #[must_use]
    pub fn with_timeout(timeout: Duration) -> Self {
        Blocking {
            deadline: Instant::now().checked_add(timeout),
        }
    }

    /// Wait as long as it takes.
    #[must_use]
    pub fn forever() -> Self {
        Blocking { deadline: None }
    }
}

#[cfg(feature = "std")]
impl Wait for Blocking {
    fn wait(&mut self, pool: &BlockPool, stall: &Stall) -> bool {
        pool.wait_for_advance(stall.free_id, self.deadline)
    }
}

/// The pool's blocking-wait machinery: used only when a thread actually waits, so the
/// lock-free paths never touch the mutex.
#[cfg(feature = "std")]
#[derive(Debug, Default)]
struct Waiters {
    count: AtomicU32,
    gate: Mutex<()>,
    cv: Condvar,
}

/// KZ2's render-memory allocator: a table of per-block AllocationIDs and a global FreeID.
///
/// `BlockPool` is `Sync`: share it (`&BlockPool`, `Arc<BlockPool>`) between every thread
/// that allocates and the one that advances FreeID. It owns no memory: it hands out byte
/// ranges of a pool the caller owns (a wgpu `Buffer`, a mapped staging area, a `Vec<u8>`).
///
/// ```
/// use framealloc::{AllocId, BlockPool, Error, PoolConfig};
/// let pool = BlockPool::new(PoolConfig::new(4 * 1024, 1024))?; // 4 blocks
/// let a = pool.try_allocate(AllocId(1))?;
/// let b = pool.try_allocate(AllocId(2))?;
/// assert_ne!(a.index(), b.index());
/// assert_eq!(pool.free_blocks(), 2);
/// pool.advance_free_id(AllocId(1))?; // the GPU passed block a's "free" marker
/// assert_eq!(pool.free_blocks(), 3);
/// assert!(pool.is_live(b.index())?);
/// # Ok::<(), Error>(())
/// ```
#[derive(Debug)]
pub struct BlockPool {
    free_id: Padded,
    hint: Padded,
    slots: Box<[Slot]>,
    block_bytes: u32,
    #[cfg(feature = "std")]
    waiters: Waiters,
}

impl BlockPool {
    /// A pool with every block free and FreeID at `config.first_id - 1`.
    pub fn new(config: PoolConfig) -> Result<Self, Error> {
        let blocks = config.block_count()?;
        let free = config.first_id.sub(1).0;
        let slots: Vec<Slot> = (0..blocks).map(|_| Slot(AtomicU32::new(free))).collect();
        Ok(BlockPool {
            free_id: Padded(AtomicU32::new(free)),
            hint: Padded(AtomicU32::new(0)),
            slots: slots.into_boxed_slice(),
            block_bytes: config.block_bytes,
            #[cfg(feature = "std")]
            waiters: Waiters::default(),
        })
    }

    /// Blocks in the pool.
    #[inline]
    #[must_use]
    pub fn block_count(&self) -> u32 {
        self.slots.len() as u32
    }

    /// Bytes per block.
    #[inline]
    #[must_use]
    pub fn block_bytes(&self) -> u32 {
        self.block_bytes
    }

    /// Bytes in the whole pool (size the backing buffer to this).
    #[inline]
    #[must_use]
    pub fn pool_bytes(&self) -> u64 {
        self.slots.len() as u64 * self.block_bytes as u64
    }

    /// Byte offset of block `index` from the start of the pool.
    pub fn block_offset(&self, index: u32) -> Result<u64, Error> {
        self.check_index(index)?;
        Ok(index as u64 * self.block_bytes as u64)
    }

    /// The current FreeID: every block tagged at or before it is free.
    #[inline]
    #[must_use]
    pub fn free_id(&self) -> AllocId {
        AllocId(self.free_id.0.load(Ordering::Acquire))
    }

    /// The AllocationID block `index` was last claimed with (or, for a block free since a
    /// sweep, a recent FreeID). A snapshot: other threads may change it at any time.
    pub fn block_id(&self, index: u32) -> Result<AllocId, Error> {
        self.check_index(index)?;
        Ok(AllocId(
            self.slots[index as usize].0.load(Ordering::Acquire),
        ))
    }

    /// Whether block `index` is live (its ID is after FreeID). A snapshot.
    pub fn is_live(&self, index: u32) -> Result<bool, Error> {
        let id = self.block_id(index)?;
        Ok(!id.is_at_or_before(self.free_id()))
    }

    /// Whether `block` is still live under its own ID: no FreeID advance has passed it and
    /// nobody has claimed it since. False means its memory may belong to someone else.
    #[must_use]
    pub fn holds(&self, block: &Block) -> bool {
        let Some(slot) = self.slots.get(block.index as usize) else {
            return false;
        };
        slot.0.load(Ordering::Acquire) == block.id.0 && !block.id.is_at_or_before(self.free_id())
    }

    /// How many blocks are free now. A snapshot: one walk of the table.
    #[must_use]
    pub fn free_blocks(&self) -> u32 {
        let free = self.free_id();
        self.slots
            .iter()
            .filter(|s| AllocId(s.0.load(Ordering::Relaxed)).is_at_or_before(free))
            .count() as u32
    }

    fn check_index(&self, index: u32) -> Result<(), Error> {
        if (index as usize) < self.slots.len() {
            Ok(())
        } else {
            Err(Error::NoSuchBlock {
                index,
                blocks: self.block_count(),
            })
        }
    }

    /// Checks `id` against a FreeID snapshot: after it, and at most `MAX_ID_LEAD` ahead.
    #[inline]
    fn check_id(id: AllocId, free: u32) -> Result<(), Error> {
        let lead = id.0.wrapping_sub(free);
        if lead == 0 || lead > u32::MAX / 2 {
            Err(Error::IdRetired {
                id,
                free_id: AllocId(free),
            })
        } else if lead > MAX_ID_LEAD {
            Err(Error::IdTooFarAhead {
                id,
                free_id: AllocId(free),
                limit: MAX_ID_LEAD,
            })
        } else {
            Ok(())
        }
    }

    /// One walk of the table from the rotating start: claims the first free slot for `id`.
    #[inline]
    fn walk(&self, id: AllocId, free: u32) -> Option<Block> {
        let n = self.slots.len();
        let mut i = self.hint.0.load(Ordering::Relaxed) as usize;
        if i >= n {
            i = 0;
        }
        for _ in 0..n {
            let slot = &self.slots[i].0;
            let v = slot.load(Ordering::Relaxed);
            // Free iff table[i] <= FreeID, wrap-around-safe.
            if (free.wrapping_sub(v) as i32) >= 0
                && slot
                    .compare_exchange(v, id.0, Ordering::Acquire, Ordering::Relaxed)
                    .is_ok()
            {
                let next = if i + 1 == n { 0 } else { i + 1 };
                self.hint.0.store(next as u32, Ordering::Relaxed);
                return Some(Block {
                    index: i as u32,
                    id,
                    offset: i as u64 * self.block_bytes as u64,
                    bytes: self.block_bytes,
                });
            }
            i += 1;
            if i == n {
                i = 0;
            }
        }
        None
    }

    /// Claims a free block for `id`, or fails at once with [`Error::Exhausted`] when every
    /// block is live. Lock-free; callable from any number of threads.
    ///
    /// `id` must be after FreeID ([`Error::IdRetired`]) and at most [`MAX_ID_LEAD`] ahead
    /// ([`Error::IdTooFarAhead`]). Many blocks may share one ID.
    #[inline]
    pub fn try_allocate(&self, id: AllocId) -> Result<Block, Error> {
        self.allocate_with(id, &mut NoWait)
    }

    /// Claims a free block for `id`; when every block is live, asks `wait` whether to wait
    /// and walk again. A round of walking ends only after a full walk under an unchanged
    /// FreeID found nothing, so exhaustion is never reported merely because FreeID advanced
    /// during a walk. Gives up with [`Error::Exhausted`] when `wait` returns false, and
    /// with [`Error::IdRetired`] if FreeID passes `id` while waiting.
    pub fn allocate_with<W: Wait + ?Sized>(
        &self,
        id: AllocId,
        wait: &mut W,
    ) -> Result<Block, Error> {
        let mut attempt = 0u32;
        loop {
            attempt = attempt.saturating_add(1);
            let mut free = self.free_id.0.load(Ordering::Acquire);
            Self::check_id(id, free)?;
            loop {
                if let Some(block) = self.walk(id, free) {
                    return Ok(block);
                }
                // A walk judges slots by its FreeID snapshot. If FreeID moved meanwhile
                // (the walking thread was preempted while others allocated and freed
                // round the table), blocks may have freed behind it: walk again before
                // calling the pool exhausted. Each repeat means the consumer progressed.
                let now = self.free_id.0.load(Ordering::Acquire);
                if now == free {
                    break;
                }
                free = now;
                Self::check_id(id, free)?;
            }
            let stall = Stall {
                id,
                free_id: AllocId(free),
                attempt,
            };
            if !wait.wait(self, &stall) {
                return Err(Error::Exhausted {
                    id,
                    blocks: self.block_count(),
                    attempts: attempt,
                });
            }
        }
    }

    /// Claims a free block for `id`, blocking up to `timeout` for another thread to advance
    /// FreeID when every block is live. [`Error::Exhausted`] after the timeout.
    #[cfg(feature = "std")]
    pub fn allocate_wait(&self, id: AllocId, timeout: Duration) -> Result<Block, Error> {
        self.allocate_with(id, &mut Blocking::with_timeout(timeout))
    }

    /// The GPU passed a "free" marker for `to`: every block tagged at or before `to` becomes
    /// free. Returns the FreeID after the call.
    ///
    /// FreeID only moves forward. A `to` at or before the current FreeID (a late or repeated
    /// marker) changes nothing and is not an error: those blocks are free already. A `to`
    /// more than [`MAX_FREE_STEP`] ahead is [`Error::FreeStepTooLarge`] and changes nothing.
    /// Safe to call from any thread (wgpu runs `on_submitted_work_done` callbacks on
    /// whichever thread polls).
    pub fn advance_free_id(&self, to: AllocId) -> Result<AllocId, Error> {
        let mut cur = self.free_id.0.load(Ordering::Acquire);
        loop {
            let step = to.0.wrapping_sub(cur);
            if step == 0 || step > u32::MAX / 2 {
                return Ok(AllocId(cur));
            }
            if step > MAX_FREE_STEP {
                return Err(Error::FreeStepTooLarge {
                    free_id: AllocId(cur),
                    to,
                    limit: MAX_FREE_STEP,
                });
            }
            match self.free_id.0.compare_exchange_weak(
                cur,
                to.0,
                Ordering::SeqCst,
                Ordering::Acquire,
            ) {
                Ok(_) => break,
                Err(now) => cur = now,
            }
        }
        if (cur >> 30) != (to.0 >> 30) {
            self.sweep(to.0);
        }
        #[cfg(feature = "std")]
        self.wake_waiters();
        Ok(to)
    }

    /// Rewrites every free slot to `free` (a FreeID value, so they stay free) to keep free
    /// slots within 2^31 of FreeID. A concurrent claim of the same slot wins the CAS.
    #[cold]
    fn sweep(&self, free: u32) {
        for slot in self.slots.iter() {
            let v = slot.0.load(Ordering::Relaxed);
            if v != free && (free.wrapping_sub(v) as i32) >= 0 {
                let _ = slot
                    .0
                    .compare_exchange(v, free, Ordering::Relaxed, Ordering::Relaxed);
            }
        }
    }

    #[cfg(feature = "std")]
    #[inline]
    fn wake_waiters(&self) {
        // SeqCst pairs with the waiter's increment and re-check of FreeID: either the waiter
        // sees the new FreeID, or this load sees the waiter and takes the gate to notify.
        if self.waiters.count.load(Ordering::SeqCst) != 0 {
            drop(
                self.waiters
                    .gate
                    .lock()
                    .unwrap_or_else(PoisonError::into_inner),
            );
            self.waiters.cv.notify_all();
        }
    }

    /// Blocks until FreeID differs from `seen` (true) or the deadline passes (false).
    #[cfg(feature = "std")]
    fn wait_for_advance(&self, seen: AllocId, deadline: Option<Instant>) -> bool {
        let w = &self.waiters;
        let mut guard = w.gate.lock().unwrap_or_else(PoisonError::into_inner);
        w.count.fetch_add(1, Ordering::SeqCst);
        let advanced = loop {
            if self.free_id.0.load(Ordering::SeqCst) != seen.0 {
                break true;
            }
            match deadline {
                None => guard = w.cv.wait(guard).unwrap_or_else(PoisonError::into_inner),
                Some(d) => {
                    let now = Instant::now();
                    if now >= d {
                        break false;
                    }
                    guard =
                        w.cv.wait_timeout(guard, d - now)
                            .unwrap_or_else(PoisonError::into_inner)
                            .0;
                }
            }
        };
        w.count.fetch_sub(1, Ordering::SeqCst);
        advanced
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn small(blocks: u32, first: u32) -> BlockPool {
        BlockPool::new(PoolConfig::new(blocks as u64 * 1024, 1024).with_first_id(AllocId(first)))
            .unwrap()
    }

    #[test]
    fn kz2_preset_has_88_blocks_of_256_kib() {
        let pool = BlockPool::new(PoolConfig::KZ2).unwrap();
        assert_eq!(pool.block_count(), 88);
        assert_eq!(pool.block_bytes(), 256 * 1024);
        assert_eq!(pool.pool_bytes(), 22 * 1024 * 1024);
        assert_eq!(pool.free_blocks(), 88);
        assert_eq!(pool.free_id(), AllocId(0));
    }

    #[test]
    fn config_rejects_bad_layouts() {
        for (pool, block) in [(1024u64, 0u32), (1024, 100), (1000, 256), (0, 256)] {
            let e = PoolConfig::new(pool, block).block_count().unwrap_err();
            assert!(matches!(e, Error::BadConfig { .. }), "{pool} {block}: {e}");
        }
        let too_many = PoolConfig::new((MAX_BLOCKS as u64 + 1) * 256, 256);
        assert!(matches!(
            BlockPool::new(too_many),
            Err(Error::BadConfig { value, .. }) if value == MAX_BLOCKS as u64 + 1
        ));
        assert_eq!(
            PoolConfig::new(MAX_BLOCKS as u64 * 256, 256).block_count(),
            Ok(MAX_BLOCKS)
        );
    }

    #[test]
    fn exhaustion_is_an_error_and_overwrites_nothing() {
        let pool = small(3, 10);
        let blocks: Vec<Block> = (0..3)
            .map(|k| pool.try_allocate(AllocId(10 + k)).unwrap())
            .collect();
        let e = pool.try_allocate(AllocId(20)).unwrap_err();
        assert_eq!(
            e,
            Error::Exhausted {
                id: AllocId(20),
                blocks: 3,
                attempts: 1
            }
        );
        for b in &blocks {
            assert!(pool.holds(b));
        }
        // Freeing up to 11 frees exactly the blocks tagged 10 and 11.
        pool.advance_free_id(AllocId(11)).unwrap();
        assert!(!pool.holds(&blocks[0]) && !pool.holds(&blocks[1]) && pool.holds(&blocks[2]));
        let c = pool.try_allocate(AllocId(20)).unwrap();
        assert!(c.index() == blocks[0].index() || c.index() == blocks[1].index());
    }

    #[test]
    fn ids_are_checked_against_free_id() {
        let pool = small(2, 100);
        assert_eq!(
            pool.try_allocate(AllocId(99)),
            Err(Error::IdRetired {
                id: AllocId(99),
                free_id: AllocId(99)
            })
        );
        assert!(matches!(
            pool.try_allocate(AllocId(5)),
            Err(Error::IdRetired { .. })
        ));
        assert!(pool.try_allocate(AllocId(99 + MAX_ID_LEAD)).is_ok());
        assert_eq!(
            pool.try_allocate(AllocId(100 + MAX_ID_LEAD)),
            Err(Error::IdTooFarAhead {
                id: AllocId(100 + MAX_ID_LEAD),
                free_id: AllocId(99),
                limit: MAX_ID_LEAD
            })
        );
    }

    #[test]
    fn free_id_only_moves_forward() {
        let pool = small(2, 1);
        assert_eq!(pool.advance_free_id(AllocId(10)), Ok(AllocId(10)));
        assert_eq!(pool.advance_free_id(AllocId(5)), Ok(AllocId(10)));
        assert_eq!(pool.advance_free_id(AllocId(10)), Ok(AllocId(10)));
        assert_eq!(
            pool.advance_free_id(AllocId(11 + MAX_FREE_STEP)),
            Err(Error::FreeStepTooLarge {
                free_id: AllocId(10),
                to: AllocId(11 + MAX_FREE_STEP),
                limit: MAX_FREE_STEP
            })
        );
        assert_eq!(pool.free_id(), AllocId(10));
        assert_eq!(
            pool.advance_free_id(AllocId(10 + MAX_FREE_STEP)),
            Ok(AllocId(10 + MAX_FREE_STEP))
        );
    }

    /// Without the quarter sweep, a block left free while FreeID moves 2^31 ahead would
    /// compare as live forever.
    #[test]
    fn untouched_free_blocks_survive_many_wraps() {
        let pool = small(4, u32::MAX - 5);
        let mut free = pool.free_id();
        // Eight full wraps of the 32-bit space in maximal steps. One block is in use per
        // step while the other three sit untouched (each for 3 * 2^30 IDs).
        for _ in 0..(8 * 4) {
            let b = pool.try_allocate(free.add(1)).unwrap();
            assert_eq!(pool.free_blocks(), 3, "at FreeID {free}");
            free = free.add(MAX_FREE_STEP);
            pool.advance_free_id(free).unwrap();
            assert!(!pool.holds(&b));
            assert_eq!(pool.free_blocks(), 4, "at FreeID {free}");
        }
        for k in 1..=4 {
            pool.try_allocate(free.add(k)).unwrap();
        }
        assert_eq!(pool.free_blocks(), 0);
    }

    #[test]
    fn live_blocks_stay_live_across_the_wrap() {
        let pool = small(4, u32::MAX - 1);
        let a = pool.try_allocate(AllocId(u32::MAX)).unwrap();
        let b = pool.try_allocate(AllocId(3)).unwrap(); // after the wrap
        pool.advance_free_id(AllocId(1)).unwrap(); // passes u32::MAX and 0
        assert!(!pool.holds(&a));
        assert!(pool.holds(&b));
        assert_eq!(pool.free_blocks(), 3);
        pool.advance_free_id(AllocId(3)).unwrap();
        assert_eq!(pool.free_blocks(), 4);
    }

    #[test]
    fn waits_give_up_as_asked() {
        let pool = small(1, 1);
        let _a = pool.try_allocate(AllocId(1)).unwrap();
        let mut calls = 0;
        let e = pool
            .allocate_with(AllocId(2), &mut |s: &Stall| {
                calls += 1;
                assert_eq!(s.attempt, calls);
                calls < 3
            })
            .unwrap_err();
        assert_eq!(
            e,
            Error::Exhausted {
                id: AllocId(2),
                blocks: 1,
                attempts: 3
            }
        );
        assert!(matches!(
            pool.allocate_with(AllocId(2), &mut Spin { max_attempts: 4 }),
            Err(Error::Exhausted { attempts: 4, .. })
        ));
    }

    #[test]
    fn a_polling_wait_succeeds_once_the_consumer_advances() {
        let pool = small(1, 1);
        let _a = pool.try_allocate(AllocId(1)).unwrap();
        // The "poll" is what drives the consumer, as device.poll runs wgpu's callbacks.
        let b = pool
            .allocate_with(AllocId(2), &mut |s: &Stall| {
                assert_eq!(s.free_id, AllocId(0));
                pool.advance_free_id(AllocId(1)).is_ok()
            })
            .unwrap();
        assert_eq!(b.id(), AllocId(2));
    }

    #[test]
    fn retired_while_waiting_is_reported() {
        let pool = small(1, 1);
        let _a = pool.try_allocate(AllocId(5)).unwrap();
        let e = pool
            .allocate_with(AllocId(2), &mut |_: &Stall| {
                // FreeID jumps to 3: past the ID being allocated, but not the live block.
                pool.advance_free_id(AllocId(3)).is_ok()
            })
            .unwrap_err();
        assert_eq!(
            e,
            Error::IdRetired {
                id: AllocId(2),
                free_id: AllocId(3)
            }
        );
    }

    #[cfg(feature = "std")]
    #[test]
    fn blocking_wait_times_out_and_wakes() {
        use std::sync::Arc;
        let pool = Arc::new(small(1, 1));
        let _a = pool.try_allocate(AllocId(1)).unwrap();
        let t0 = Instant::now();
        assert!(matches!(
            pool.allocate_wait(AllocId(2), Duration::from_millis(30)),
            Err(Error::Exhausted { .. })
        ));
        assert!(t0.elapsed() >= Duration::from_millis(30));

        let p2 = Arc::clone(&pool);
        let waiter =
            std::thread::spawn(move || p2.allocate_with(AllocId(2), &mut Blocking::forever()));
        std::thread::sleep(Duration::from_millis(20));
        pool.advance_free_id(AllocId(1)).unwrap();
        let b = waiter.join().unwrap().unwrap();
        assert_eq!((b.index(), b.id()), (0, AllocId(2)));
    }

    #[test]
    fn accessors_reject_bad_indices() {
        let pool = small(2, 1);
        assert_eq!(pool.block_offset(1), Ok(1024));
        assert_eq!(
            pool.block_offset(2),
            Err(Error::NoSuchBlock {
                index: 2,
                blocks: 2
            })
        );
        assert!(pool.block_id(7).is_err());
        assert!(pool.is_live(7).is_err());
        let b = pool.try_allocate(AllocId(1)).unwrap();
        assert_eq!(b.range(), b.offset()..b.offset() + 1024);
    }
}
