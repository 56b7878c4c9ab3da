//! The crate's one error type.

use core::fmt;

use crate::AllocId;

/// Everything that can go wrong in `framealloc`. No operation panics on bad input; each
/// failure names the limit, the value and the item involved.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Error {
    /// Every block is live: no block's AllocationID is at or before FreeID. Nothing was
    /// allocated; retry after the GPU has advanced FreeID, or allocate with a [`crate::Wait`].
    Exhausted {
        /// The ID the allocation asked for.
        id: AllocId,
        /// Blocks in the pool, all live.
        blocks: u32,
        /// Rounds of walking the table before giving up: 1 when not waiting, else 1 +
        /// the number of waits. (A round repeats its walk while FreeID moves under it.)
        attempts: u32,
    },
    /// The ID is at or before FreeID: the GPU has already passed it, so a block tagged with
    /// it would be free the moment it was handed out.
    IdRetired {
        /// The ID asked for.
        id: AllocId,
        /// FreeID when the allocation was tried.
        free_id: AllocId,
    },
    /// The ID is more than [`crate::MAX_ID_LEAD`] IDs ahead of FreeID, outside the window
    /// where wrap-around comparison is safe.
    IdTooFarAhead {
        /// The ID asked for.
        id: AllocId,
        /// FreeID when the allocation was tried.
        free_id: AllocId,
        /// [`crate::MAX_ID_LEAD`].
        limit: u32,
    },
    /// An [`crate::BlockPool::advance_free_id`] would move FreeID by more than
    /// [`crate::MAX_FREE_STEP`] at once (or the target lies 2^31 or more away, which is
    /// ambiguous with wrap-around). FreeID is unchanged.
    FreeStepTooLarge {
        /// FreeID before the call.
        free_id: AllocId,
        /// The requested new FreeID.
        to: AllocId,
        /// [`crate::MAX_FREE_STEP`].
        limit: u32,
    },
    /// A pool configuration was rejected.
    BadConfig {
        /// What was wrong, naming the limit.
        what: &'static str,
        /// The offending value.
        value: u64,
    },
    /// A suballocation is larger than a whole block.
    TooLarge {
        /// Bytes asked for.
        bytes: u32,
        /// Bytes in one block.
        block_bytes: u32,
    },
    /// An alignment is zero, not a power of two, or does not divide the block size (so it
    /// could not hold for offsets in the pool).
    BadAlignment {
        /// The alignment asked for, in bytes.
        align: u32,
        /// Bytes in one block.
        block_bytes: u32,
    },
    /// A block's front (commands) and back (data) would cross: the block is full.
    BlockFull {
        /// Bytes asked for.
        bytes: u32,
        /// Alignment asked for, in bytes.
        align: u32,
        /// Bytes still free between front and back.
        free: u32,
    },
    /// A pass's ID range has no IDs left.
    RangeExhausted {
        /// First ID of the range.
        first: AllocId,
        /// IDs in the range, all handed out.
        len: u32,
    },
    /// A frame plan was rejected.
    BadPlan {
        /// What was wrong, naming the limit.
        what: &'static str,
        /// The offending value.
        value: u64,
    },
    /// A pass or part index is out of range.
    NoSuchPass {
        /// The index asked for.
        index: u32,
        /// How many there are.
        count: u32,
    },
    /// A block index is out of range for the pool.
    NoSuchBlock {
        /// The index asked for.
        index: u32,
        /// Blocks in the pool.
        blocks: u32,
    },
    /// The simulated GPU read a block that is no longer live under the ID it was written
    /// with: its memory may have been handed to someone else (a use-after-free).
    NotLive {
        /// The block read.
        block: u32,
        /// The ID it was written under.
        id: AllocId,
        /// The AllocationID the pool's table holds for it now.
        found: AllocId,
        /// FreeID at the time of the read.
        free_id: AllocId,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Error::Exhausted {
                id,
                blocks,
                attempts,
            } => write!(
                f,
                "no free block for allocation {id}: all {blocks} blocks are live \
                 (walk rounds: {attempts})"
            ),
            Error::IdRetired { id, free_id } => write!(
                f,
                "allocation ID {id} is at or before FreeID {free_id}: the GPU already passed it"
            ),
            Error::IdTooFarAhead { id, free_id, limit } => write!(
                f,
                "allocation ID {id} is more than MAX_ID_LEAD ({limit}) IDs ahead of FreeID {free_id}"
            ),
            Error::FreeStepTooLarge { free_id, to, limit } => write!(
                f,
                "advancing FreeID from {free_id} to {to} exceeds MAX_FREE_STEP ({limit} IDs)"
            ),
            Error::BadConfig { what, value } => {
                write!(f, "bad pool configuration: {what} ({value})")
            }
            Error::TooLarge { bytes, block_bytes } => write!(
                f,
                "suballocation of {bytes} bytes is larger than a block ({block_bytes} bytes)"
            ),
            Error::BadAlignment { align, block_bytes } => write!(
                f,
                "alignment {align} must be a power of two dividing the block size ({block_bytes} bytes)"
            ),
            Error::BlockFull { bytes, align, free } => write!(
                f,
                "block full: {bytes} bytes aligned to {align} do not fit in the {free} free bytes"
            ),
            Error::RangeExhausted { first, len } => write!(
                f,
                "ID range starting at {first} is used up (all {len} IDs handed out)"
            ),
            Error::BadPlan { what, value } => write!(f, "bad frame plan: {what} ({value})"),
            Error::NoSuchPass { index, count } => {
                write!(f, "pass or part {index} out of range (there are {count})")
            }
            Error::NoSuchBlock { index, blocks } => {
                write!(f, "block {index} out of range (the pool has {blocks})")
            }
            Error::NotLive {
                block,
                id,
                found,
                free_id,
            } => write!(
                f,
                "block {block} read under ID {id} is not live: the table holds {found}, FreeID is {free_id}"
            ),
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for Error {}
