//! River splines: Catmull–Rom through the control points, flattened into a fine polyline
//! that the bake rasterises.

use alloc::vec::Vec;

use glam::{Vec2, Vec3};

use super::MAX_RIVER_TEXELS;
use crate::{Error, math};

/// One control point of a river.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RiverPoint {
    /// The centre of the water surface here, metres (z up).
    pub position: Vec3,
    /// Full width of the water surface, metres.
    pub width: f32,
    /// Depth of the bed below the surface at the centre, metres.
    pub depth: f32,
    /// Flow speed at the centre, m/s, downstream (towards the next point).
    pub speed: f32,
}

/// A sample of the flattened spline.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SplineSample {
    pub position: Vec3,
    pub width: f32,
    pub depth: f32,
    pub speed: f32,
}

fn catmull_rom(p0: Vec3, p1: Vec3, p2: Vec3, p3: Vec3, t: f32) -> Vec3 {
    let t2 = t * t;
    let t3 = t2 * t;
    ((2.0 * p1)
        + (p2 - p0) * t
        + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t2
        + (3.0 * p1 - p0 - 3.0 * p2 + p3) * t3)
        * 0.5
}

/// Samples the river's centre line so that consecutive samples are at most `max_step`
/// metres apart horizontally: the uniform Catmull–Rom spline through the points (end points
/// duplicated) in x and y; height, width, depth and speed linearly between control points,
/// so a waterfall (a steep drop between two close points) never overshoots above its top
/// or below its foot.
#[cfg(test)]
pub(crate) fn flatten(points: &[RiverPoint], max_step: f32) -> Vec<SplineSample> {
    flatten_bounded(points, max_step, usize::MAX).unwrap_or_default()
}

/// Steps for the segment from point `i` to `i + 1`.
fn segment_steps(points: &[RiverPoint], i: usize, max_step: f32) -> usize {
    let n = points.len();
    let at = |i: isize| points[i.clamp(0, n as isize - 1) as usize].position;
    let (a, b) = (points[i].position, points[i + 1].position);
    let (p0, p3) = (at(i as isize - 1), at(i as isize + 2));
    // The curve segment is no longer than the control polygon around it.
    let len = (a.truncate() - p0.truncate()).length()
        + (b.truncate() - a.truncate()).length()
        + (p3.truncate() - b.truncate()).length();
    (math::ceil(len / max_step.max(1e-3)) as usize).clamp(1, 1 << 16)
}

/// [`flatten`], or `None` if it would take more than `max_samples` samples.
pub(crate) fn flatten_bounded(
    points: &[RiverPoint],
    max_step: f32,
    max_samples: usize,
) -> Option<Vec<SplineSample>> {
    let n = points.len();
    let total: usize = (0..n.saturating_sub(1))
        .map(|i| segment_steps(points, i, max_step))
        .sum::<usize>()
        + 1;
    if total > max_samples {
        return None;
    }
    let mut out = Vec::with_capacity(total);
    if n == 0 {
        return Some(out);
    }
    if n == 1 {
        let p = points[0];
        out.push(SplineSample {
            position: p.position,
            width: p.width,
            depth: p.depth,
            speed: p.speed,
        });
        return Some(out);
    }
    let at = |i: isize| points[i.clamp(0, n as isize - 1) as usize].position;
    for i in 0..n - 1 {
        let (a, b) = (points[i], points[i + 1]);
        let p0 = at(i as isize - 1);
        let p3 = at(i as isize + 2);
        let steps = segment_steps(points, i, max_step);
        for s in 0..steps {
            let t = s as f32 / steps as f32;
            let xy = catmull_rom(p0, a.position, b.position, p3, t);
            out.push(SplineSample {
                position: Vec3::new(xy.x, xy.y, math::mix(a.position.z, b.position.z, t)),
                width: math::mix(a.width, b.width, t),
                depth: math::mix(a.depth, b.depth, t),
                speed: math::mix(a.speed, b.speed, t),
            });
        }
    }
    let last = points[n - 1];
    out.push(SplineSample {
        position: last.position,
        width: last.width,
        depth: last.depth,
        speed: last.speed,
    });
    Some(out)
}

/// An inclusive grid range `(x0, y0, x1, y1)`.
pub(crate) type GridRange = (i64, i64, i64, i64);

/// The inclusive range `(x0, y0, x1, y1)` of grid points inside the box `[lo, hi]`, grid
/// point `(x, y)` lying at `origin + ((x, y) + shift) * texel`; with `size = (w, h)`
/// clamped to the grid.
pub(crate) fn grid_range(
    lo: Vec2,
    hi: Vec2,
    texel: f32,
    origin: Vec2,
    shift: f32,
    size: Option<(i64, i64)>,
) -> GridRange {
    let lo = (lo - origin) / texel - shift;
    let hi = (hi - origin) / texel - shift;
    let (x0, y0) = (math::ceil(lo.x) as i64, math::ceil(lo.y) as i64);
    let (x1, y1) = (math::floor(hi.x) as i64, math::floor(hi.y) as i64);
    match size {
        Some((w, h)) => (x0.max(0), y0.max(0), x1.min(w - 1), y1.min(h - 1)),
        None => (x0, y0, x1, y1),
    }
}

/// A river flattened for a grid of `texel` metres, and the inclusive grid range
/// `(x0, y0, x1, y1)` under each segment's capsule's bounding box, where grid point
/// `(x, y)` lies at `origin + ((x, y) + shift) * texel`; with `size = (w, h)` the ranges
/// are clamped to the grid. The world bake and the flow bake rasterise rivers through
/// this, so both refuse the same rivers, before any rasterising: more than
/// [`MAX_RIVER_TEXELS`] texels over all ranges is an error.
pub(crate) fn river_ranges(
    points: &[RiverPoint],
    texel: f32,
    origin: Vec2,
    shift: f32,
    size: Option<(i64, i64)>,
) -> Result<(Vec<SplineSample>, Vec<GridRange>), Error> {
    let too_big = |value: u64| Error::LimitExceeded {
        what: "texels a river's segments cover",
        value,
        limit: MAX_RIVER_TEXELS,
        limit_name: "MAX_RIVER_TEXELS",
    };
    let samples = flatten_bounded(points, texel * 0.5, MAX_RIVER_TEXELS as usize)
        .ok_or(too_big(MAX_RIVER_TEXELS + 1))?;
    let ranges: Vec<GridRange> = samples
        .windows(2)
        .map(|seg| {
            let (a2, b2) = (seg[0].position.truncate(), seg[1].position.truncate());
            let r = seg[0].width.max(seg[1].width) * 0.5;
            grid_range(a2.min(b2) - r, a2.max(b2) + r, texel, origin, shift, size)
        })
        .collect();
    let total = ranges
        .iter()
        .map(|&(x0, y0, x1, y1)| {
            ((x1 - x0 + 1).max(0) as u64).saturating_mul((y1 - y0 + 1).max(0) as u64)
        })
        .fold(0u64, u64::saturating_add);
    if total > MAX_RIVER_TEXELS {
        return Err(too_big(total));
    }
    Ok((samples, ranges))
}

/// Closest point on segment `a -> b` to `p` (2D): parameter in `[0, 1]` and distance.
pub(crate) fn closest_on_segment(a: Vec2, b: Vec2, p: Vec2) -> (f32, f32) {
    let ab = b - a;
    let l2 = ab.length_squared();
    let t = if l2 > 0.0 {
        ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (t, (a + ab * t - p).length())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passes_through_the_control_points() {
        let pts: Vec<RiverPoint> = [
            Vec3::ZERO,
            Vec3::new(10.0, 0.0, -1.0),
            Vec3::new(20.0, 5.0, -2.0),
        ]
        .into_iter()
        .map(|p| RiverPoint {
            position: p,
            width: 4.0,
            depth: 1.0,
            speed: 1.0,
        })
        .collect();
        let s = flatten(&pts, 0.5);
        assert_eq!(s[0].position, Vec3::ZERO);
        assert_eq!(s.last().unwrap().position, pts[2].position);
        assert!(
            s.iter()
                .any(|x| (x.position - pts[1].position).length() < 1e-5)
        );
        for w in s.windows(2) {
            assert!((w[1].position.truncate() - w[0].position.truncate()).length() <= 0.5 + 1e-4);
        }
    }
}
