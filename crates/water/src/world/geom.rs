//! The word and plane helpers that the bake and the reader share: floats in words, the
//! WGSL half packing, the 2D box, the even-odd crossing test and segment clipping.

use glam::Vec2;
use half::f16;

use super::MAX_COORDINATE;

pub(super) fn f(w: u32) -> f32 {
    f32::from_bits(w)
}

/// `pack2x16float` as WGSL does it (round to nearest even, low half first).
pub(super) fn pack2x16float(a: f32, b: f32) -> u32 {
    u32::from(f16::from_f32(a).to_bits()) | u32::from(f16::from_f32(b).to_bits()) << 16
}

/// `unpack2x16float`.
pub(super) fn unpack2x16float(w: u32) -> Vec2 {
    Vec2::new(
        f16::from_bits(w as u16).to_f32(),
        f16::from_bits((w >> 16) as u16).to_f32(),
    )
}

pub(super) fn finite2(p: Vec2) -> bool {
    p.x.is_finite() && p.y.is_finite() && p.x.abs() <= MAX_COORDINATE && p.y.abs() <= MAX_COORDINATE
}

/// Axis-aligned box `[min, max]`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Aabb {
    pub(super) min: Vec2,
    pub(super) max: Vec2,
}

impl Aabb {
    pub(super) fn empty() -> Self {
        Self {
            min: Vec2::splat(f32::INFINITY),
            max: Vec2::splat(f32::NEG_INFINITY),
        }
    }
    pub(super) fn add(&mut self, p: Vec2) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }
    pub(super) fn union(&mut self, o: &Aabb) {
        self.min = self.min.min(o.min);
        self.max = self.max.max(o.max);
    }
    pub(super) fn overlaps(&self, o: &Aabb, margin: f32) -> bool {
        self.min.x <= o.max.x + margin
            && o.min.x <= self.max.x + margin
            && self.min.y <= o.max.y + margin
            && o.min.y <= self.max.y + margin
    }
    pub(super) fn is_empty(&self) -> bool {
        !(self.min.x <= self.max.x)
    }
}

/// Even-odd test against a whole polygon (the build's classification; queries use
/// the same [`crosses`] on a leaf's edges).
pub(super) fn point_in_polygon(poly: &[Vec2], p: Vec2) -> bool {
    let mut inside = false;
    let n = poly.len();
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        if crosses(a.x, a.y, b.x, b.y, p) {
            inside = !inside;
        }
    }
    inside
}

/// Whether the ray from `p` towards +x crosses edge `(x0, y0) -> (x1, y1)` (half-open in y).
#[inline]
pub(super) fn crosses(x0: f32, y0: f32, x1: f32, y1: f32, p: Vec2) -> bool {
    if (y0 > p.y) != (y1 > p.y) {
        let xc = x0 + (p.y - y0) * (x1 - x0) / (y1 - y0);
        p.x < xc
    } else {
        false
    }
}

pub(super) fn signed_area(poly: &[Vec2]) -> f64 {
    let n = poly.len();
    let mut a = 0.0f64;
    for i in 0..n {
        let (p, q) = (poly[i], poly[(i + 1) % n]);
        a += f64::from(p.x) * f64::from(q.y) - f64::from(q.x) * f64::from(p.y);
    }
    a * 0.5
}

/// Liang–Barsky along one axis: the sub-range of `t in [t0, t1]` where `a + (b - a) t`
/// lies in `[lo, hi]` (f64), or `None`.
pub(super) fn clip(a: f32, b: f32, lo: f64, hi: f64, t0: f64, t1: f64) -> Option<(f64, f64)> {
    let (a, d) = (f64::from(a), f64::from(b) - f64::from(a));
    let (mut t0, mut t1) = (t0, t1);
    if d == 0.0 {
        return (a >= lo && a <= hi).then_some((t0, t1));
    }
    let (mut ta, mut tb) = ((lo - a) / d, (hi - a) / d);
    if ta > tb {
        core::mem::swap(&mut ta, &mut tb);
    }
    t0 = t0.max(ta);
    t1 = t1.min(tb);
    (t0 <= t1).then_some((t0, t1))
}
