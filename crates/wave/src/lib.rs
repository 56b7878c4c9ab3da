//! Wave-level patterns for GPU-driven rendering: how every pass of this project appends to
//! a buffer with one atomic per wave instead of one per thread, and how the static-scene
//! query writes its batches. A CPU model (the reference) and WGSL twins.
//!
//! - [`Wave`], [`LaneMask`], [`PerLane`]: a wave of 8, 16, 32 or 64 lanes with an active
//!   mask; `ballot`, popcount, the prefix count of set bits below a lane (the talk's
//!   `MaskBitCnt`), the first active lane, broadcasts, sums.
//! - [`Wave::aggregated_append`] / [`Wave::reserve`]: the aggregated atomic of Horizon Zero
//!   Dawn's query ("Aside: Aggregated atomics", after Adinetz 2014): the first active lane
//!   adds the wave's popcount to a shared [`Counter`], broadcasts the old value, and each
//!   lane writes at old + its prefix count. [`CountedAtomicU32`] counts the atomics.
//! - [`Wave::batch_output`]: HZD's run-grouped batch output ("GPU compute thread:
//!   Batching"): instances append in lane order, the first visible lane of each run writes
//!   one [`WaveBatch`] header.
//! - [`ordered_f32`] / [`unordered_f32`]: floats as order-preserving words, so that
//!   `atomicMax` / `atomicMin` on `u32` keep float extrema (bounds, depth ranges).
//! - [`compact`] / [`batch_compact`]: the same over a whole stream of items, and under the
//!   `parallel` feature `parallel::par_compact` and friends over many threads with a real
//!   shared `AtomicU32`.
//! - [`wgsl`]: the WGSL twins, binding-free library modules prefixed `wave_`: the subgroup
//!   path (`subgroupBallot`, `subgroupExclusiveAdd`, `subgroupBroadcastFirst`), the
//!   fallback for adapters without subgroups (a workgroup ballot from workgroup-shared
//!   atomics, then one global atomic per workgroup), and the run-grouped batch output with
//!   its per-group workgroup-memory accumulation. A pass imports `wave::append` and the
//!   `subgroups` feature picks the path. Validated by naga in unit tests; the workspace's
//!   device tests run them on a device against this model.
//!
//! Features: `std` (default; `std::error::Error`), `parallel` (rayon). Without either the
//! crate is `no_std` and allocation-free.
//!
//! Lane `i` is bit `i` of a [`LaneMask`]; slots are element indices into the output
//! buffer (not bytes). Counters wrap at `u32::MAX` like WGSL's `atomicAdd`; writes whose
//! slot lies outside the output are dropped and reported, as robust buffer access does.
//!
//! Source: Will Vale, "Decima: Visibility in Horizon Zero Dawn" (aggregated atomics,
//! batching during the query); Adinetz, "Optimized filtering with warp-aggregated atomics"
//! (NVIDIA, 2014); Far Cry 5's water tile counts with ballot (one atomic per 8x8 group).
//!
//! # Example: the talk's eight-lane append
//!
//! ```
//! use wave::{CountedAtomicU32, LaneMask, Wave, WaveWidth};
//!
//! // Lanes 1, 2, 4 and 7 want to write (the coloured boxes of the diagram).
//! let wave = Wave::with_active(WaveWidth::W8, LaneMask(0b1001_0110)).unwrap();
//! let counter = CountedAtomicU32::new(5); // other waves already appended 5 items
//! let mut out = [0u32; 16];
//! let append = wave.aggregated_append(&counter, &mut out, |lane| 100 + lane);
//! assert_eq!((append.base, append.count), (5, 4));
//! assert_eq!(out[5..9], [101, 102, 104, 107]); // compact, in lane order
//! assert_eq!(counter.atomic_ops(), 1); // one atomic for the whole wave
//! ```
#![no_std]
#![cfg_attr(docsrs, feature(doc_cfg))]

#[cfg(any(test, feature = "std"))]
extern crate std;

mod append;
mod batch;
mod counter;
mod mask;
mod ordered;
#[cfg(feature = "parallel")]
pub mod parallel;
mod wave;
pub mod wgsl;

pub use append::{Append, Compaction, RangeReservation, Reservation, compact, compact_per_item};
pub use batch::{Batch, BatchCompaction, BatchOutput, WaveBatch, batch_compact};
pub use counter::{CountedAtomicU32, Counter};
pub use mask::{LaneMask, Lanes, WAVE_WIDTH_MAX, WaveWidth};
pub use ordered::{ordered_f32, unordered_f32};
pub use wave::{PerLane, Wave};
pub use wgsl::{NO_SLOT, WG_BALLOT_WORDS, WG_INVOCATIONS_MAX};

use core::fmt;

/// Everything that can go wrong in this crate; each variant names the limit and the value.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Error {
    /// A wave width other than 8, 16, 32 or 64 lanes.
    UnsupportedWidth {
        /// The lane count asked for.
        lanes: u32,
    },
    /// An active mask with lanes at or past the wave's width.
    MaskOutsideWidth {
        /// The wave's width.
        width: WaveWidth,
        /// The offending mask.
        mask: LaneMask,
    },
    /// A per-lane value count that does not match the wave's width.
    LaneCount {
        /// The wave's width.
        width: WaveWidth,
        /// The number of values (or lanes) given.
        values: usize,
    },
    /// A wave's total append does not fit the `u32` counter.
    AppendTooLarge {
        /// The total the wave asked for.
        total: u64,
    },
    /// A run would advance the `u32` counter past `u32::MAX` (slots would repeat).
    CounterOverflow {
        /// The counter's start value.
        start: u32,
        /// The most items the run could append.
        items: usize,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Error::UnsupportedWidth { lanes } => {
                write!(f, "wave width {lanes} unsupported (8, 16, 32 or 64 lanes)")
            }
            Error::MaskOutsideWidth { width, mask } => write!(
                f,
                "active mask {:#x} has lanes outside the wave's {width}",
                mask.0
            ),
            Error::LaneCount { width, values } => {
                write!(f, "{values} per-lane values for a wave of {width}")
            }
            Error::AppendTooLarge { total } => write!(
                f,
                "wave append of {total} items exceeds the u32 counter (max {})",
                u32::MAX
            ),
            Error::CounterOverflow { start, items } => write!(
                f,
                "counter at {start} plus up to {items} items would pass u32::MAX"
            ),
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for Error {}
