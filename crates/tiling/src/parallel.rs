//! The classification on many threads (rayon): tiles are independent in every phase (each
//! owns its masks, its counters and its commands, all contiguous in the tile-major
//! layout), so each phase runs its tiles in parallel and equals the sequential result
//! exactly: each function here is the sequential one's body with its tiles handed to
//! rayon instead of a loop. The vertex cull buffer is shared through relaxed `AtomicU8` stores (setting a
//! byte to 1 commutes); the prefix sums and the wave commands stay sequential (one entry
//! per (tile, pass), negligible next to the pixels).
//!
//! ```
//! # use tiling::{ClassifyConfig, MicroBatchInfo, VisBuffer};
//! # use visbuf::VisLayout;
//! # use wave::WaveWidth;
//! let row = MicroBatchInfo { id_count: 1, primitive_count: 1, vertex_count: 3,
//!     instance_count: 1, ..Default::default() };
//! let words = vec![0u32; 300 * 200]; // every pixel: micro batch 0, instance 0, triangle 0
//! let vis = VisBuffer::new(&words, 300, 200, VisLayout::Standard)?;
//! let config = ClassifyConfig { pass_count: 1, wave_width: WaveWidth::W64, chunk_count: 1, vertex_cull: true };
//! let seq = tiling::classify(&vis, &[row], &[0, 1, 2], &config)?;
//! let par = tiling::parallel::classify(&vis, &[row], &[0, 1, 2], &config)?;
//! assert_eq!(seq, par);
//! # Ok::<(), tiling::Error>(())
//! ```

use crate::classify::{Schedule, phase_functions};

phase_functions! {
    Schedule::Threads;

    /// [`crate::laydown_finalize`] over tiles in parallel.
    fn laydown_finalize;

    /// [`crate::mid_classify`] over tiles in parallel.
    fn mid_classify;

    /// [`crate::classify_output`] over tiles in parallel.
    fn classify_output;

    /// [`crate::classify()`] (all three phases fused per tile) over tiles in parallel.
    fn classify;

    /// [`crate::classify_phases`] with each phase's tiles in parallel.
    fn classify_phases;
}
