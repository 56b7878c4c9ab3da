//! Progress reporting for the offline bakers (distance transform, flow bake, atlas, world).
//!
//! Every baker takes `progress: &mut impl FnMut(Progress) -> ControlFlow<()>`. It is called
//! from the calling thread only (the parallel bakers report between batches), so a plain
//! closure that updates a progress bar works; returning `ControlFlow::Break(())` stops the
//! bake with [`Error::Cancelled`]. Pass [`no_progress`] to ignore
//! it.
//!
//! ```
//! use core::ops::ControlFlow;
//! let mask = vec![0u8; 64 * 64];
//! let mut calls = 0;
//! water::edt::signed_edt(&mask, 64, 64, &mut |p: water::Progress| {
//!     assert!(p.done <= p.total);
//!     calls += 1;
//!     ControlFlow::Continue(())
//! })?;
//! assert!(calls >= 2);
//! # Ok::<(), water::Error>(())
//! ```

use core::ops::ControlFlow;

use crate::Error;

/// Which step of a bake is running.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Stage {
    /// Distance transform, column pass.
    DistanceColumns,
    /// Distance transform, row pass.
    DistanceRows,
    /// Flow bake: seeding from rivers and sources.
    FlowSeeds,
    /// Flow bake: the SDF-guided flood fill.
    FlowFill,
    /// Flow bake: smoothing iterations.
    FlowSmooth,
    /// Flow atlas: the low-resolution world map.
    AtlasWorldMap,
    /// Flow atlas: the high-resolution tiles.
    AtlasTiles,
    /// Water world: rivers baked to height tiles.
    RiverTiles,
    /// Water world: the quadtree.
    Quadtree,
}

/// One report: `done` of `total` units of `stage` are finished.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Progress {
    /// The step.
    pub stage: Stage,
    /// Units finished (rows, texels, tiles: whatever the stage counts).
    pub done: u64,
    /// Units in the stage.
    pub total: u64,
}

impl Progress {
    /// `done / total` in `[0, 1]` (1 for an empty stage).
    #[must_use]
    pub fn fraction(&self) -> f32 {
        if self.total == 0 {
            1.0
        } else {
            (self.done as f64 / self.total as f64) as f32
        }
    }
}

/// A progress callback that ignores every report.
pub fn no_progress(_: Progress) -> ControlFlow<()> {
    ControlFlow::Continue(())
}

/// Calls the callback and turns a break into [`Error::Cancelled`].
pub(crate) fn report(
    progress: &mut impl FnMut(Progress) -> ControlFlow<()>,
    stage: Stage,
    done: u64,
    total: u64,
) -> Result<(), Error> {
    match progress(Progress { stage, done, total }) {
        ControlFlow::Continue(()) => Ok(()),
        ControlFlow::Break(()) => Err(Error::Cancelled),
    }
}
