//! How well an ordering keeps neighbours together, to choose between the Morton and
//! Hilbert curves (or judge any other order) on your own data.
//!
//! Two measures over grid cells visited in a given order:
//! - the **step**: the Manhattan distance in cells between consecutive points (a curve that
//!   jumps has long steps);
//! - the **chunk bounds**: cut the order into runs of `chunk` points, as a cluster builder
//!   does, and take the half surface area of each run's bounding box in cells
//!   (`dx*dy + dy*dz + dz*dx`, with `d` = extent + 1): smaller boxes cull better.
//!
//! ```
//! use morton::glam::UVec3;
//! use morton::locality::{Curve, curve_order3, measure3};
//!
//! // Every cell of an 8x8x8 grid: the Hilbert curve steps one cell at a time.
//! let cells: Vec<UVec3> = (0..512).map(|i| UVec3::new(i & 7, (i >> 3) & 7, i >> 6)).collect();
//! let hilbert = measure3(&cells, &curve_order3(Curve::Hilbert, &cells).unwrap(), 64);
//! let morton = measure3(&cells, &curve_order3(Curve::Morton, &cells).unwrap(), 64);
//! assert_eq!(hilbert.mean_step, 1.0);
//! assert!(morton.mean_step > 1.0);
//! ```

use alloc::vec::Vec;
use glam::{UVec2, UVec3};

use crate::{Error, hilbert, sort_permutation};

/// A space-filling curve to order cells by.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Curve {
    /// Z-order ([`crate::encode3_u64`], [`crate::encode2_u64`]).
    Morton,
    /// Hilbert ([`hilbert::encode3_u64`], [`hilbert::encode2_u64`]).
    Hilbert,
}

/// The two locality measures of an ordering (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Locality {
    /// Mean Manhattan distance in cells between consecutive points (0 with fewer than 2).
    pub mean_step: f64,
    /// Largest Manhattan distance between consecutive points.
    pub max_step: u64,
    /// Mean half surface area, in cells², of the bounding boxes of consecutive runs of
    /// `chunk` points (the last run may be shorter); in 2D the mean box area.
    pub mean_chunk_bounds: f64,
}

/// The permutation that orders 3D cells along `curve` (21 bits per axis; higher bits are
/// ignored). Ties (equal cells) keep input order.
pub fn curve_order3(curve: Curve, cells: &[UVec3]) -> Result<Vec<u32>, Error> {
    let keys: Vec<u64> = cells
        .iter()
        .map(|c| match curve {
            Curve::Morton => crate::encode3_u64(c.x, c.y, c.z),
            Curve::Hilbert => hilbert::encode3_u64(c.x, c.y, c.z),
        })
        .collect();
    sort_permutation(&keys)
}

/// The permutation that orders 2D cells along `curve` (32 bits per axis).
pub fn curve_order2(curve: Curve, cells: &[UVec2]) -> Result<Vec<u32>, Error> {
    let keys: Vec<u64> = cells
        .iter()
        .map(|c| match curve {
            Curve::Morton => crate::encode2_u64(c.x, c.y),
            Curve::Hilbert => hilbert::encode2_u64(c.x, c.y),
        })
        .collect();
    sort_permutation(&keys)
}

/// Locality of visiting `cells` in `order` (indices into `cells`; out-of-range indices are
/// skipped), with chunk bounds over runs of `chunk` points (`chunk` 0 is taken as 1).
pub fn measure3(cells: &[UVec3], order: &[u32], chunk: usize) -> Locality {
    let seq = order.iter().filter_map(|&i| cells.get(i as usize).copied());
    let dist = |a: UVec3, b: UVec3| {
        a.x.abs_diff(b.x) as u64 + a.y.abs_diff(b.y) as u64 + a.z.abs_diff(b.z) as u64
    };
    let area = |lo: UVec3, hi: UVec3| {
        let d = (hi - lo).as_dvec3() + 1.0;
        d.x * d.y + d.y * d.z + d.z * d.x
    };
    measure(seq, chunk, dist, |a, b| (a.min(b), a.max(b)), area)
}

/// [`measure3`] in 2D; the chunk bounds are box areas.
pub fn measure2(cells: &[UVec2], order: &[u32], chunk: usize) -> Locality {
    let seq = order.iter().filter_map(|&i| cells.get(i as usize).copied());
    let dist = |a: UVec2, b: UVec2| a.x.abs_diff(b.x) as u64 + a.y.abs_diff(b.y) as u64;
    let area = |lo: UVec2, hi: UVec2| {
        let d = (hi - lo).as_dvec2() + 1.0;
        d.x * d.y
    };
    measure(seq, chunk, dist, |a, b| (a.min(b), a.max(b)), area)
}

fn measure<T: Copy>(
    seq: impl Iterator<Item = T>,
    chunk: usize,
    dist: impl Fn(T, T) -> u64,
    grow: impl Fn(T, T) -> (T, T),
    area: impl Fn(T, T) -> f64,
) -> Locality {
    let chunk = chunk.max(1);
    let (mut prev, mut steps, mut sum, mut max) = (None, 0u64, 0u64, 0u64);
    let (mut boxes, mut area_sum, mut run, mut bounds) = (0u64, 0.0f64, 0usize, None);
    for c in seq {
        if let Some(p) = prev {
            let d = dist(p, c);
            sum += d;
            max = max.max(d);
            steps += 1;
        }
        prev = Some(c);
        bounds = Some(match bounds {
            None => (c, c),
            Some((lo, hi)) => {
                let (lo, _) = grow(lo, c);
                let (_, hi) = grow(hi, c);
                (lo, hi)
            }
        });
        run += 1;
        if run == chunk {
            if let Some((lo, hi)) = bounds.take() {
                area_sum += area(lo, hi);
                boxes += 1;
            }
            run = 0;
        }
    }
    if let Some((lo, hi)) = bounds {
        area_sum += area(lo, hi);
        boxes += 1;
    }
    Locality {
        mean_step: if steps == 0 {
            0.0
        } else {
            sum as f64 / steps as f64
        },
        max_step: max,
        mean_chunk_bounds: if boxes == 0 {
            0.0
        } else {
            area_sum / boxes as f64
        },
    }
}
