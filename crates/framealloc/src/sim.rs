//! A simulated GPU consumer: executes a command stream in order and advances FreeID when it
//! passes a "free" marker, as KZ2's RSX did.
//!
//! The allocator itself knows nothing of GPUs; this is what drives FreeID in tests, and it
//! checks the property the allocator exists for: when the GPU reads a block, the block is
//! still live under the ID it was written with (nobody was handed its memory meanwhile).

use alloc::collections::VecDeque;

use crate::{AllocId, BlockPool, Error};

/// One command of the simulated GPU's stream.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum GpuCommand {
    /// Read block `block`, written under AllocationID `id`.
    Read {
        /// Block index in the pool.
        block: u32,
        /// The ID the block was allocated with.
        id: AllocId,
    },
    /// KZ2's "free" marker: when executed, FreeID becomes this ID (if it is ahead).
    Free(AllocId),
}

/// An in-order consumer of [`GpuCommand`]s for one pool.
///
/// ```
/// use framealloc::{AllocId, BlockPool, PoolConfig};
/// use framealloc::sim::{GpuCommand, SimulatedGpu};
/// let pool = BlockPool::new(PoolConfig::new(2 * 256, 256))?;
/// let mut gpu = SimulatedGpu::new();
/// let a = pool.try_allocate(AllocId(1))?;
/// gpu.submit(GpuCommand::Read { block: a.index(), id: a.id() });
/// gpu.submit(GpuCommand::Free(a.id()));
/// assert_eq!(gpu.run(&pool, usize::MAX)?, 2);
/// assert_eq!(pool.free_id(), AllocId(1));
/// assert_eq!(pool.free_blocks(), 2);
/// # Ok::<(), framealloc::Error>(())
/// ```
#[derive(Clone, Debug, Default)]
pub struct SimulatedGpu {
    queue: VecDeque<GpuCommand>,
    executed: u64,
}

impl SimulatedGpu {
    /// An idle GPU with an empty queue.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Appends a command to the end of the queue.
    pub fn submit(&mut self, command: GpuCommand) {
        self.queue.push_back(command);
    }

    /// Commands submitted but not yet executed.
    #[must_use]
    pub fn pending(&self) -> usize {
        self.queue.len()
    }

    /// Commands executed so far.
    #[must_use]
    pub fn executed(&self) -> u64 {
        self.executed
    }

    /// Executes the next command, returning it (`None` when the queue is empty).
    ///
    /// A `Read` of a block that is not live under its ID is [`Error::NotLive`] (the command
    /// is consumed); a `Free` that [`BlockPool::advance_free_id`] rejects returns that error
    /// and stays at the head of the queue.
    pub fn step(&mut self, pool: &BlockPool) -> Result<Option<GpuCommand>, Error> {
        let Some(&command) = self.queue.front() else {
            return Ok(None);
        };
        match command {
            GpuCommand::Read { block, id } => {
                self.queue.pop_front();
                self.executed += 1;
                let found = pool.block_id(block)?;
                let free_id = pool.free_id();
                if found != id || id.is_at_or_before(free_id) {
                    return Err(Error::NotLive {
                        block,
                        id,
                        found,
                        free_id,
                    });
                }
            }
            GpuCommand::Free(id) => {
                pool.advance_free_id(id)?;
                self.queue.pop_front();
                self.executed += 1;
            }
        }
        Ok(Some(command))
    }

    /// Executes up to `max` commands, stopping at the first error; returns how many ran.
    pub fn run(&mut self, pool: &BlockPool, max: usize) -> Result<usize, Error> {
        let mut n = 0;
        while n < max && self.step(pool)?.is_some() {
            n += 1;
        }
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::PoolConfig;

    #[test]
    fn catches_a_read_after_the_block_was_freed() {
        let pool = BlockPool::new(PoolConfig::new(256, 256)).unwrap();
        let mut gpu = SimulatedGpu::new();
        let a = pool.try_allocate(AllocId(1)).unwrap();
        // A broken client: frees before the GPU read the block.
        gpu.submit(GpuCommand::Free(AllocId(1)));
        gpu.submit(GpuCommand::Read {
            block: a.index(),
            id: a.id(),
        });
        assert_eq!(gpu.step(&pool), Ok(Some(GpuCommand::Free(AllocId(1)))));
        let b = pool.try_allocate(AllocId(2)).unwrap();
        assert_eq!(b.index(), a.index());
        assert_eq!(
            gpu.step(&pool),
            Err(Error::NotLive {
                block: 0,
                id: AllocId(1),
                found: AllocId(2),
                free_id: AllocId(1)
            })
        );
        assert_eq!(gpu.pending(), 0);
        assert_eq!(gpu.executed(), 2);
    }

    #[test]
    fn a_rejected_free_stays_queued() {
        let pool = BlockPool::new(PoolConfig::new(256, 256)).unwrap();
        let mut gpu = SimulatedGpu::new();
        gpu.submit(GpuCommand::Free(AllocId(u32::MAX / 2)));
        assert!(matches!(
            gpu.run(&pool, 10),
            Err(Error::FreeStepTooLarge { .. })
        ));
        assert_eq!(gpu.pending(), 1);
        gpu.submit(GpuCommand::Read {
            block: 9,
            id: AllocId(1),
        });
        assert_eq!(gpu.run(&pool, 0), Ok(0));
    }
}
