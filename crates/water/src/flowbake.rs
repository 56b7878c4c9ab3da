//! Flow baking by an SDF-guided flood fill.
//!
//! Far Cry 5 bakes the whole world's flow offline: "we run a flood fill algorithm. But
//! flood fill is kind of tricky because some pixels will arrive at the destination sooner
//! than others. So we actually use a signed distance field to guide the flood fill around
//! corners, which also works for rocks" (seed 003).
//!
//! [`bake_flow`] takes a grid (the water mask's signed distance field, from
//! [`crate::edt`]), river splines and point sources, and:
//!
//! 1. **Seeds** every water texel under a river (the river's horizontal downstream
//!    direction times its speed, parabolic across the width, as the world bake does) or
//!    inside a source's radius.
//! 2. **Floods** outward in order of a travel cost, Dijkstra's algorithm on the 8-connected
//!    water texels with a bucket queue. A step costs its length (10 straight, 14 diagonal)
//!    times `1 + bank_penalty * closeness`, where `closeness = 1 - sdf / bank_width`
//!    (clamped) is 1 on the shore and 0 from `bank_width` out: the front runs ahead down
//!    the middle of a channel and reaches the banks from the middle, so flow turns corners
//!    with the channel instead of arriving wherever the grid distance is shortest. A texel
//!    takes the mean of its already-flooded neighbours' flows (weighted by 1 / step cost),
//!    then the SDF guide below.
//! 3. **Smooths** with Jacobi iterations: each water texel becomes the mean of its 3 x 3
//!    water neighbourhood, then the guide. This removes what is left of the
//!    order-of-arrival pattern (seeds are held fixed).
//!
//! The **SDF guide**: the SDF's isolines run parallel to the nearest shore or rock, so the
//! flow is turned onto the isoline through the texel (perpendicular to the SDF gradient),
//! keeping its speed and the orientation the flood brought (the sign that agrees with the
//! propagated flow). The turn is total up to half of `guide_distance` from the shore,
//! fades out at `guide_distance` (open water far from shore keeps the propagated flow),
//! and fades where the gradient is unreliable: on the medial axis of a channel, where the
//! central difference of the distance field collapses (`|grad| < 0.8`), the flow is the
//! neighbours' mean. So flow follows banks and bends and goes around rocks.
//!
//! Water texels no seed can reach keep zero flow. The flood is sequential (a priority
//! order); the smoothing runs on rayon in [`crate::parallel::bake_flow`] with the same
//! result, bit for bit.
//!
//! # Units and conventions
//!
//! The grid is `width x height` texels of `texel_size` metres; texel `(i, j)`'s centre is
//! at world `origin + (i + 0.5, j + 0.5) * texel_size` (z up, so `(x, y)` is horizontal).
//! Flow is in m/s along +x and +y.

use alloc::vec;
use alloc::vec::Vec;
use core::ops::ControlFlow;

use glam::Vec2;

use crate::Error;
use crate::edt::DistanceField;
use crate::grid::{clamped_index, size_getters};
use crate::math;
use crate::progress::{Progress, Stage, report};
use crate::world::{River, spline};

/// A point source of flow (a spring, an outlet, the foot of a waterfall).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlowSource {
    /// World position, metres.
    pub position: Vec2,
    /// Flow velocity it imposes, m/s.
    pub velocity: Vec2,
    /// Radius it covers, metres.
    pub radius: f32,
}

/// Flow bake settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlowBakeSettings {
    /// Distance from a bank (metres) over which the flood is slowed.
    pub bank_width: f32,
    /// Distance from a bank (metres) out to which the SDF guides the flow direction.
    pub guide_distance: f32,
    /// Extra travel cost on the shore (0 = plain Dijkstra distance).
    pub bank_penalty: f32,
    /// Jacobi smoothing iterations after the flood.
    pub smoothing_iterations: u32,
}

impl Default for FlowBakeSettings {
    /// 4 m banks, penalty 3, guided out to 40 m, 8 smoothing iterations.
    fn default() -> Self {
        Self {
            bank_width: 4.0,
            guide_distance: 40.0,
            bank_penalty: 3.0,
            smoothing_iterations: 8,
        }
    }
}

/// What to bake.
#[derive(Clone, Copy, Debug)]
pub struct FlowBakeInput<'a> {
    /// Signed distance to the shore in texels (positive in water) over the whole grid.
    pub sdf: &'a DistanceField,
    /// Metres per texel.
    pub texel_size: f32,
    /// World position of the grid's corner (texel (0, 0)'s outer corner).
    pub origin: Vec2,
    /// Rivers to seed from (world coordinates).
    pub rivers: &'a [River],
    /// Point sources.
    pub sources: &'a [FlowSource],
}

/// A baked flow field.
#[derive(Clone, Debug, PartialEq)]
pub struct FlowField {
    width: u32,
    height: u32,
    texel_size: f32,
    origin: Vec2,
    flow: Vec<Vec2>,
}

impl FlowField {
    /// A field from existing velocities (`width * height`, row-major, m/s).
    pub fn from_flow(
        width: u32,
        height: u32,
        texel_size: f32,
        origin: Vec2,
        flow: Vec<Vec2>,
    ) -> Result<Self, Error> {
        if width == 0 || height == 0 {
            return Err(Error::InvalidSize {
                field: "flow field size",
                value: 0,
                rule: "at least 1 x 1",
            });
        }
        let expected = width as usize * height as usize;
        if flow.len() != expected {
            return Err(Error::LengthMismatch {
                field: "flow texels",
                len: flow.len(),
                expected,
            });
        }
        check_geometry(texel_size, origin)?;
        if !flow.iter().all(|v| v.is_finite()) {
            return Err(Error::NonFinite {
                field: "flow texel",
            });
        }
        Ok(Self {
            width,
            height,
            texel_size,
            origin,
            flow,
        })
    }

    size_getters!("Width in texels.", "Height in texels.");
    /// Metres per texel.
    #[must_use]
    pub fn texel_size(&self) -> f32 {
        self.texel_size
    }
    /// World position of the grid's corner.
    #[must_use]
    pub fn origin(&self) -> Vec2 {
        self.origin
    }
    /// Velocities, row-major, m/s.
    #[must_use]
    pub fn flow(&self) -> &[Vec2] {
        &self.flow
    }
    /// Velocity of texel `(x, y)` (clamped to the grid).
    #[must_use]
    pub fn texel(&self, x: i64, y: i64) -> Vec2 {
        self.flow[clamped_index(self.width, self.height, x, y)]
    }
    /// Bilinear velocity at world position `p` (clamped at the edges; zero for NaN).
    #[must_use]
    pub fn sample(&self, p: Vec2) -> Vec2 {
        let t = (p - self.origin) / self.texel_size - 0.5;
        if !t.is_finite() {
            return Vec2::ZERO;
        }
        let (fx, fy) = (math::floor(t.x), math::floor(t.y));
        let (ax, ay) = (t.x - fx, t.y - fy);
        let (x, y) = (fx as i64, fy as i64);
        let a = self.texel(x, y).lerp(self.texel(x + 1, y), ax);
        let b = self.texel(x, y + 1).lerp(self.texel(x + 1, y + 1), ax);
        a.lerp(b, ay)
    }
}

pub(crate) fn check_geometry(texel_size: f32, origin: Vec2) -> Result<(), Error> {
    if !(texel_size > 0.0) || !texel_size.is_finite() {
        return Err(Error::OutOfRange {
            field: "texel size",
            value: texel_size,
            min: f32::MIN_POSITIVE,
            max: f32::MAX,
        });
    }
    if !origin.is_finite() {
        return Err(Error::NonFinite {
            field: "grid origin",
        });
    }
    Ok(())
}

/// Step costs in tenths of a texel.
const STRAIGHT: u32 = 10;
const DIAGONAL: u32 = 14;
const NEIGHBOURS: [(i32, i32, u32); 8] = [
    (1, 0, STRAIGHT),
    (-1, 0, STRAIGHT),
    (0, 1, STRAIGHT),
    (0, -1, STRAIGHT),
    (1, 1, DIAGONAL),
    (-1, 1, DIAGONAL),
    (1, -1, DIAGONAL),
    (-1, -1, DIAGONAL),
];
/// Most extra cost factor (keeps step costs small for the bucket queue).
pub const MAX_BANK_PENALTY: f32 = 15.0;

/// Per-texel data shared by the flood and the smoothing.
pub(crate) struct Grid<'a> {
    pub(crate) w: usize,
    pub(crate) h: usize,
    pub(crate) sdf: &'a [f32],
    /// Closeness to a bank, 0..1 (the flood's penalty).
    pub(crate) closeness: Vec<f32>,
    /// Strength of the guide, 0..1.
    pub(crate) guide: Vec<f32>,
    /// Unit SDF gradient (away from land).
    pub(crate) normal: Vec<Vec2>,
}

impl Grid<'_> {
    pub(crate) fn water(&self, i: usize) -> bool {
        self.sdf[i] > 0.0
    }

    /// The SDF guide at texel `i`: turn `v` onto the isoline, keeping speed and
    /// orientation.
    pub(crate) fn constrain(&self, i: usize, v: Vec2) -> Vec2 {
        let c = self.guide[i];
        let n = self.normal[i];
        let speed = v.length();
        if c <= 0.0 || speed == 0.0 {
            return v;
        }
        let mut t = n.perp();
        if t.dot(v) < 0.0 {
            t = -t;
        }
        let out = v.lerp(t * speed, c);
        let l = out.length();
        if l > 0.0 {
            out * (speed / l)
        } else {
            t * speed
        }
    }
}

pub(crate) fn grid<'a>(sdf: &'a DistanceField, texel_size: f32, s: &FlowBakeSettings) -> Grid<'a> {
    let (w, h) = (sdf.width() as usize, sdf.height() as usize);
    let bank = (s.bank_width / texel_size).max(1e-6);
    let guide_d = (s.guide_distance / texel_size).max(1e-6);
    let mut closeness = vec![0.0; w * h];
    let mut guide = vec![0.0; w * h];
    let mut normal = vec![Vec2::ZERO; w * h];
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            let d = sdf.values()[i];
            if !(d > 0.0) {
                continue; // land: no flow, no guide
            }
            closeness[i] = math::saturate(1.0 - d / bank);
            let gr = sdf.gradient(x as u32, y as u32);
            let reliable = math::smoothstep(0.5, 0.8, gr.length());
            guide[i] = reliable * math::saturate(2.0 - 2.0 * d / guide_d);
            normal[i] = gr.normalize_or_zero();
        }
    }
    Grid {
        w,
        h,
        sdf: sdf.values(),
        closeness,
        guide,
        normal,
    }
}

fn check(input: &FlowBakeInput<'_>, s: &FlowBakeSettings) -> Result<(), Error> {
    check_geometry(input.texel_size, input.origin)?;
    for (field, v) in [
        ("bank width", s.bank_width),
        ("bank penalty", s.bank_penalty),
        ("guide distance", s.guide_distance),
    ] {
        if !v.is_finite() {
            return Err(Error::NonFinite { field });
        }
    }
    if !(0.0..=MAX_BANK_PENALTY).contains(&s.bank_penalty) {
        return Err(Error::OutOfRange {
            field: "bank penalty",
            value: s.bank_penalty,
            min: 0.0,
            max: MAX_BANK_PENALTY,
        });
    }
    for src in input.sources {
        if !(src.position.is_finite() && src.velocity.is_finite() && src.radius.is_finite()) {
            return Err(Error::NonFinite {
                field: "flow source",
            });
        }
    }
    Ok(())
}

/// Seeds: flow per texel and whether it is fixed.
pub(crate) fn seed(
    input: &FlowBakeInput<'_>,
    g: &Grid<'_>,
    flow: &mut [Vec2],
    fixed: &mut [bool],
) -> Result<(), Error> {
    let ts = input.texel_size;
    let (w, h) = (g.w as i64, g.h as i64);
    let mut best = vec![f32::INFINITY; g.w * g.h];
    for (ri, river) in input.rivers.iter().enumerate() {
        if river.points.len() < 2
            || !river
                .points
                .iter()
                .all(|p| p.position.is_finite() && p.width.is_finite() && p.speed.is_finite())
        {
            return Err(Error::DegenerateBody {
                kind: "river",
                index: ri as u32,
                reason: "fewer than 2 points, or a non-finite point",
            });
        }
        // Texel centres sit half a texel in from the grid's corners.
        let (samples, ranges) =
            spline::river_ranges(&river.points, ts, input.origin, 0.5, Some((w, h)))?;
        for (seg, &(x0, y0, x1, y1)) in samples.windows(2).zip(&ranges) {
            let (a, b) = (seg[0], seg[1]);
            let (a2, b2) = (a.position.truncate(), b.position.truncate());
            let dir = (b2 - a2).normalize_or_zero();
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let i = (y * w + x) as usize;
                    if !g.water(i) {
                        continue;
                    }
                    let p = input.origin + (Vec2::new(x as f32, y as f32) + 0.5) * ts;
                    let (t, d) = spline::closest_on_segment(a2, b2, p);
                    let hw = math::mix(a.width, b.width, t) * 0.5;
                    if d <= hw && d < best[i] {
                        best[i] = d;
                        let s = if hw > 0.0 { d / hw } else { 0.0 };
                        flow[i] = dir * (math::mix(a.speed, b.speed, t) * (1.0 - s * s));
                        fixed[i] = true;
                    }
                }
            }
        }
    }
    for src in input.sources {
        let r = src.radius.max(0.0);
        let (x0, y0, x1, y1) = spline::grid_range(
            src.position - r,
            src.position + r,
            ts,
            input.origin,
            0.5,
            Some((w, h)),
        );
        for y in y0..=y1 {
            for x in x0..=x1 {
                let i = (y * w + x) as usize;
                let p = input.origin + (Vec2::new(x as f32, y as f32) + 0.5) * ts;
                if g.water(i) && (p - src.position).length() <= r {
                    flow[i] = src.velocity;
                    fixed[i] = true;
                }
            }
        }
    }
    Ok(())
}

/// The flood: Dijkstra with a bucket queue over integer costs. Returns which texels it
/// reached.
fn flood(
    g: &Grid<'_>,
    s: &FlowBakeSettings,
    flow: &mut [Vec2],
    fixed: &[bool],
    progress: &mut impl FnMut(Progress) -> ControlFlow<()>,
) -> Result<Vec<bool>, Error> {
    let (w, h) = (g.w, g.h);
    let n = w * h;
    // Step cost factor per texel in 1/16 units: 16 * (1 + penalty * closeness).
    let factor: Vec<u32> = g
        .closeness
        .iter()
        .map(|&c| 16 + (16.0 * s.bank_penalty * c) as u32)
        .collect();
    let max_step = DIAGONAL * (16 + (16.0 * MAX_BANK_PENALTY) as u32);
    let buckets = max_step as usize + 1;
    let mut queue: Vec<Vec<u32>> = vec![Vec::new(); buckets];
    let mut dist = vec![u32::MAX; n];
    let mut done = vec![false; n];
    let mut pending = 0usize;
    for i in 0..n {
        if fixed[i] {
            dist[i] = 0;
            queue[0].push(i as u32);
            pending += 1;
        }
    }
    let water_total = (0..n).filter(|&i| g.water(i)).count() as u64;
    let mut finished = 0u64;
    let mut cur: u64 = 0;
    while pending > 0 {
        let b = (cur % buckets as u64) as usize;
        let Some(i) = queue[b].pop() else {
            cur += 1;
            continue;
        };
        pending -= 1;
        let i = i as usize;
        if done[i] || u64::from(dist[i]) != cur {
            continue;
        }
        done[i] = true;
        finished += 1;
        let (x, y) = ((i % w) as i32, (i / w) as i32);
        if !fixed[i] {
            // Mean of the already-flooded neighbours, weighted by 1 / step cost.
            let mut sum = Vec2::ZERO;
            let mut wsum = 0.0;
            for (dx, dy, c) in NEIGHBOURS {
                let (nx, ny) = (x + dx, y + dy);
                if nx < 0 || ny < 0 || nx >= w as i32 || ny >= h as i32 {
                    continue;
                }
                let j = ny as usize * w + nx as usize;
                if done[j] && j != i {
                    let wt = 1.0 / c as f32;
                    sum += flow[j] * wt;
                    wsum += wt;
                }
            }
            if wsum > 0.0 {
                flow[i] = g.constrain(i, sum / wsum);
            }
        }
        for (dx, dy, c) in NEIGHBOURS {
            let (nx, ny) = (x + dx, y + dy);
            if nx < 0 || ny < 0 || nx >= w as i32 || ny >= h as i32 {
                continue;
            }
            let j = ny as usize * w + nx as usize;
            if done[j] || !g.water(j) {
                continue;
            }
            // Cost of the step: its length times the mean factor of its two ends.
            let step = c * (factor[i] + factor[j]) / 2;
            let nd = dist[i] + step;
            if nd < dist[j] {
                dist[j] = nd;
                queue[(u64::from(nd) % buckets as u64) as usize].push(j as u32);
                pending += 1;
            }
        }
        if finished.is_multiple_of(1 << 20) {
            report(progress, Stage::FlowFill, finished, water_total)?;
        }
    }
    report(progress, Stage::FlowFill, water_total, water_total)?;
    Ok(done)
}

/// One Jacobi smoothing row: `out` is row `y` of the new field. Texels the flood did not
/// reach (water cut off from every seed) keep zero flow.
fn smooth_row(
    g: &Grid<'_>,
    flow: &[Vec2],
    fixed: &[bool],
    reached: &[bool],
    y: usize,
    out: &mut [Vec2],
) {
    let (w, h) = (g.w, g.h);
    for (x, o) in out[..w].iter_mut().enumerate() {
        let i = y * w + x;
        if fixed[i] || !reached[i] {
            *o = flow[i];
            continue;
        }
        let mut sum = Vec2::ZERO;
        let mut count = 0.0;
        for dy in -1i32..=1 {
            for dx in -1i32..=1 {
                let (nx, ny) = (x as i32 + dx, y as i32 + dy);
                if nx < 0 || ny < 0 || nx >= w as i32 || ny >= h as i32 {
                    continue;
                }
                let j = ny as usize * w + nx as usize;
                if g.water(j) {
                    sum += flow[j];
                    count += 1.0;
                }
            }
        }
        *o = g.constrain(i, sum / count);
    }
}

/// The bake with its smoothing sweep given, shared by the sequential [`bake_flow`] and the
/// parallel [`crate::parallel::bake_flow`] (the seeds and the flood are sequential by
/// nature: a priority order). Each iteration calls `sweep(w, next, smooth_row)`, which must
/// call `smooth_row(y, row)` once for every row `y` of `next` (rows of `w` texels), in any
/// order and on any thread: every row reads the previous iteration only.
pub(crate) fn bake_flow_with(
    input: &FlowBakeInput<'_>,
    s: &FlowBakeSettings,
    progress: &mut impl FnMut(Progress) -> ControlFlow<()>,
    mut sweep: impl FnMut(usize, &mut [Vec2], &(dyn Fn(usize, &mut [Vec2]) + Sync)),
) -> Result<FlowField, Error> {
    check(input, s)?;
    let g = grid(input.sdf, input.texel_size, s);
    let n = g.w * g.h;
    let mut flow = vec![Vec2::ZERO; n];
    let mut fixed = vec![false; n];
    seed(input, &g, &mut flow, &mut fixed)?;
    report(progress, Stage::FlowSeeds, 1, 1)?;
    let reached = flood(&g, s, &mut flow, &fixed, progress)?;
    let mut next = flow.clone();
    for it in 0..s.smoothing_iterations {
        sweep(g.w, &mut next, &|y, row| {
            smooth_row(&g, &flow, &fixed, &reached, y, row);
        });
        core::mem::swap(&mut flow, &mut next);
        report(
            progress,
            Stage::FlowSmooth,
            u64::from(it + 1),
            u64::from(s.smoothing_iterations),
        )?;
    }
    Ok(FlowField {
        width: g.w as u32,
        height: g.h as u32,
        texel_size: input.texel_size,
        origin: input.origin,
        flow,
    })
}

/// Bakes flow over the grid of `input.sdf` (see the module docs), single-threaded.
pub fn bake_flow(
    input: &FlowBakeInput<'_>,
    s: &FlowBakeSettings,
    progress: &mut impl FnMut(Progress) -> ControlFlow<()>,
) -> Result<FlowField, Error> {
    bake_flow_with(input, s, progress, |w, next, smooth_row| {
        for (y, row) in next.chunks_mut(w).enumerate() {
            smooth_row(y, row);
        }
    })
}
