//! A pass's stream of blocks: the double-ended bump allocator chained across blocks.
//!
//! KZ2 built its push buffer this way: commands at the front of block N, their data at the
//! back, and when the two meet, a new block N+1 is allocated (anywhere in the pool) and the
//! stream carries on there. [`Stream`] does the bookkeeping: it takes blocks from a
//! [`BlockPool`] with consecutive IDs from its pass's range, so each block frees as soon as
//! the GPU is past it. Once the range runs out, further blocks reuse its last ID (they then
//! free together at the end of the range, which is later but never too early).

use crate::{AllocId, Block, BlockBump, BlockPool, Error, IdCursor, NoWait, PassIds, Wait};

/// Where a suballocation landed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Span {
    /// Index of the block in the pool.
    pub block: u32,
    /// The block's AllocationID.
    pub id: AllocId,
    /// Byte offset from the start of the pool (in wgpu: the offset into the pool's
    /// `Buffer`), aligned as asked.
    pub offset: u64,
    /// Bytes allocated.
    pub bytes: u32,
    /// True for the first allocation in a block the stream has just taken: a push-buffer
    /// writer links the previous block to this one here (KZ2: a jump, and a "free N" marker
    /// as the new block's first command).
    pub new_block: bool,
}

/// One writer's chain of blocks for one pass (or one task of a pass). Single-threaded:
/// give each thread its own stream with its own part of the pass's range
/// ([`PassIds::split`]).
///
/// ```
/// use framealloc::{BlockPool, FramePlan, PoolConfig, Stream};
/// let pool = BlockPool::new(PoolConfig::new(4 * 1024, 1024))?;
/// let plan = FramePlan::new(&[16, 16])?;
/// let frame = plan.frame(pool.free_id().next());
/// let mut geometry = Stream::new(&pool, frame.pass(0)?);
/// let cmd = geometry.push_command(64, 16)?;    // e.g. indirect draw arguments
/// let verts = geometry.push_data(900, 4)?;     // the vertices they draw
/// assert_eq!(cmd.block, verts.block);
/// let more = geometry.push_data(512, 256)?;    // does not fit: a new block
/// assert!(more.new_block && more.block != cmd.block);
/// assert_eq!(more.id, cmd.id.next());
/// # Ok::<(), framealloc::Error>(())
/// ```
#[derive(Debug)]
pub struct Stream<'p> {
    pool: &'p BlockPool,
    ids: IdCursor,
    last_id: Option<AllocId>,
    current: Option<Block>,
    bump: BlockBump,
    blocks: u32,
}

#[derive(Clone, Copy)]
enum End {
    Front,
    Back,
}

impl<'p> Stream<'p> {
    /// A stream taking blocks from `pool` with the IDs of `ids`, in order.
    #[must_use]
    pub fn new(pool: &'p BlockPool, ids: PassIds) -> Self {
        Stream {
            pool,
            ids: ids.cursor(),
            last_id: None,
            current: None,
            bump: BlockBump::new(pool.block_bytes()),
            blocks: 0,
        }
    }

    /// Allocates `bytes` for commands (front of the block), aligned to `align`; takes a new
    /// block when the current one is full, failing with [`Error::Exhausted`] when the pool
    /// has none free (the stream is unchanged then: retry later).
    pub fn push_command(&mut self, bytes: u32, align: u32) -> Result<Span, Error> {
        self.push(End::Front, bytes, align, &mut NoWait)
    }

    /// Allocates `bytes` for data (back of the block), aligned to `align`; otherwise as
    /// [`Stream::push_command`].
    pub fn push_data(&mut self, bytes: u32, align: u32) -> Result<Span, Error> {
        self.push(End::Back, bytes, align, &mut NoWait)
    }

    /// [`Stream::push_command`], waiting with `wait` when the pool is exhausted.
    pub fn push_command_with<W: Wait + ?Sized>(
        &mut self,
        bytes: u32,
        align: u32,
        wait: &mut W,
    ) -> Result<Span, Error> {
        self.push(End::Front, bytes, align, wait)
    }

    /// [`Stream::push_data`], waiting with `wait` when the pool is exhausted.
    pub fn push_data_with<W: Wait + ?Sized>(
        &mut self,
        bytes: u32,
        align: u32,
        wait: &mut W,
    ) -> Result<Span, Error> {
        self.push(End::Back, bytes, align, wait)
    }

    /// The block being filled, if any.
    #[must_use]
    pub fn block(&self) -> Option<&Block> {
        self.current.as_ref()
    }

    /// The current block's fill state (empty before the first block).
    #[must_use]
    pub fn bump(&self) -> &BlockBump {
        &self.bump
    }

    /// Blocks taken so far.
    #[must_use]
    pub fn blocks_taken(&self) -> u32 {
        self.blocks
    }

    /// The highest ID the stream has tagged a block with: FreeID must reach it before all
    /// of the stream's blocks are free.
    #[must_use]
    pub fn last_id(&self) -> Option<AllocId> {
        self.last_id
    }

    fn push<W: Wait + ?Sized>(
        &mut self,
        end: End,
        bytes: u32,
        align: u32,
        wait: &mut W,
    ) -> Result<Span, Error> {
        // Reject what could never fit before taking a block for it.
        BlockBump::new(self.pool.block_bytes()).check(bytes, align)?;
        let mut new_block = false;
        let fits = match end {
            End::Front => self.bump.fits_front(bytes, align),
            End::Back => self.bump.fits_back(bytes, align),
        };
        if self.current.is_none() || !fits {
            let id = match self.ids.peek() {
                Ok(id) => id,
                // The range is used up: share its last ID (frees at the range's end).
                Err(e) => self.last_id.ok_or(e)?,
            };
            let block = self.pool.allocate_with(id, wait)?;
            if self.ids.remaining() > 0 {
                let _ = self.ids.next();
            }
            self.bump = BlockBump::new(block.bytes());
            self.current = Some(block);
            self.last_id = Some(id);
            self.blocks += 1;
            new_block = true;
        }
        let Some(block) = &self.current else {
            unreachable!("a block was just taken");
        };
        let local = match end {
            End::Front => self.bump.push_front(bytes, align)?,
            End::Back => self.bump.push_back(bytes, align)?,
        };
        Ok(Span {
            block: block.index(),
            id: block.id(),
            offset: block.offset() + local as u64,
            bytes,
            new_block,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::PoolConfig;
    use alloc::vec::Vec;

    #[test]
    fn chains_blocks_with_consecutive_ids_then_reuses_the_last() {
        let pool = BlockPool::new(PoolConfig::new(8 * 256, 256)).unwrap();
        let ids = PassIds::new(AllocId(1), 3).unwrap();
        let mut s = Stream::new(&pool, ids);
        let spans: Vec<Span> = (0..5).map(|_| s.push_data(200, 4).unwrap()).collect();
        assert_eq!(
            spans.iter().map(|p| p.id.0).collect::<Vec<_>>(),
            [1, 2, 3, 3, 3]
        );
        assert!(spans.iter().all(|p| p.new_block));
        let mut blocks: Vec<u32> = spans.iter().map(|p| p.block).collect();
        blocks.sort_unstable();
        blocks.dedup();
        assert_eq!(blocks.len(), 5);
        assert_eq!(s.blocks_taken(), 5);
        assert_eq!(s.last_id(), Some(AllocId(3)));
        // Freeing up to the stream's second ID frees exactly its first two blocks.
        pool.advance_free_id(AllocId(2)).unwrap();
        assert_eq!(pool.free_blocks(), 8 - 3);
    }

    #[test]
    fn exhaustion_leaves_the_stream_usable() {
        let pool = BlockPool::new(PoolConfig::new(256, 256)).unwrap();
        let mut s = Stream::new(&pool, PassIds::new(AllocId(1), 4).unwrap());
        let a = s.push_command(200, 4).unwrap();
        assert!(matches!(
            s.push_command(100, 4),
            Err(Error::Exhausted { .. })
        ));
        assert_eq!(s.block().map(Block::index), Some(a.block));
        // The GPU passes the first block; the stream's next block gets ID 2, not 3.
        pool.advance_free_id(AllocId(1)).unwrap();
        let b = s.push_command(100, 4).unwrap();
        assert_eq!((b.id, b.offset, b.new_block), (AllocId(2), 0, true));
        // Requests that can never fit fail without taking a block.
        assert!(matches!(s.push_data(257, 4), Err(Error::TooLarge { .. })));
        assert!(matches!(s.push_data(1, 3), Err(Error::BadAlignment { .. })));
        assert_eq!(s.blocks_taken(), 2);
    }

    #[test]
    fn offsets_are_pool_offsets_and_aligned() {
        let pool = BlockPool::new(PoolConfig::new(4 * 1024, 1024)).unwrap();
        let _skip = pool.try_allocate(AllocId(1)).unwrap(); // block 0 taken
        let mut s = Stream::new(&pool, PassIds::new(AllocId(2), 8).unwrap());
        let c = s.push_command(10, 4).unwrap();
        let d = s.push_data(10, 256).unwrap();
        assert_eq!(c.offset, 1024);
        assert_eq!(d.offset, 1024 + 768);
        assert!(!d.new_block && c.new_block);
        assert_eq!(s.bump().free(), 758);
    }
}
