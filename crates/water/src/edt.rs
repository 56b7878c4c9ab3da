//! The exact signed Euclidean distance transform of a shoreline / rock mask.
//!
//! Far Cry 5 drives foam and guides its flow bake with a signed distance field "based on
//! the shorelines and the rocks" (seed 003). This is the separable linear-time algorithm of
//! Felzenszwalb and Huttenlocher, "Distance Transforms of Sampled Functions" (Theory of
//! Computing 8, 2012): a 1D transform down every column, then the lower envelope of
//! parabolas along every row. It is exact: squared distances are integers, and every
//! comparison in the envelope is done in integer arithmetic (the intersection of two
//! parabolas is compared as a fraction, never rounded), so the result equals a brute-force
//! search bit for bit.
//!
//! # Conventions
//!
//! - The mask is `width x height` bytes, row-major; non-zero is *solid* (land, rock), zero
//!   is *water*.
//! - Distances are in texels between pixel centres. A water pixel gets `+d`, `d` the
//!   distance to the nearest solid pixel; a solid pixel gets `-d`, `d` the distance to the
//!   nearest water pixel. So `|value| >= 1` everywhere and the shoreline lies between the
//!   `+1` and `-1` pixels (subtract `0.5 * signum` for a field whose zero crossing is at the
//!   shoreline under bilinear filtering). Multiply by metres per texel for metres.
//! - Where the other class does not exist at all, the value is `+inf` (all water) or
//!   `-inf` (all solid).
//! - f32 values are `sqrt` of the exact squared distance converted to f32 (exact below
//!   4096 texels, within one f32 rounding above).
//!
//! One signed transform costs about as much as one unsigned one: the column pass computes,
//! for each pixel, the vertical distance to the nearest pixel of the *other* class (one
//! array for both signs), and in the row pass the interior pixels of a run of one class
//! are left out of that class's envelope (a run's two ends are always nearer to any pixel
//! outside it).

use alloc::vec;
use alloc::vec::Vec;
use core::ops::ControlFlow;

use glam::Vec2;

use crate::Error;
use crate::math;
use crate::progress::{Progress, Stage, report};

/// Largest mask side: keeps squared distances and the envelope arithmetic in `i32`.
pub const MAX_EDT_SIDE: u32 = 16384;

/// "No pixel of the other class in this column".
pub(crate) const INF: u32 = u32::MAX;

/// A signed distance field in texels (see the module docs for the sign and units).
#[derive(Clone, Debug, PartialEq)]
pub struct DistanceField {
    width: u32,
    height: u32,
    values: Vec<f32>,
}

impl DistanceField {
    /// Wraps values computed elsewhere (`width * height`, row-major).
    pub fn from_values(width: u32, height: u32, values: Vec<f32>) -> Result<Self, Error> {
        check_dims(width, height, values.len())?;
        Ok(Self {
            width,
            height,
            values,
        })
    }

    /// Width in texels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in texels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The values, row-major.
    #[must_use]
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// The value at texel `(x, y)`, clamped to the field.
    #[inline]
    #[must_use]
    pub fn at(&self, x: i64, y: i64) -> f32 {
        let x = x.clamp(0, i64::from(self.width) - 1) as usize;
        let y = y.clamp(0, i64::from(self.height) - 1) as usize;
        self.values[y * self.width as usize + x]
    }

    /// Whether texel `(x, y)` is water (non-negative).
    #[must_use]
    pub fn is_water(&self, x: u32, y: u32) -> bool {
        self.at(i64::from(x), i64::from(y)) > 0.0
    }

    /// Bilinear sample at `p` in texel units (texel centres at integers), clamped at the
    /// edges; infinite values are clamped to `+-1e6` first.
    #[must_use]
    pub fn sample(&self, p: Vec2) -> f32 {
        let (fx, fy) = (math::floor(p.x), math::floor(p.y));
        let (tx, ty) = (p.x - fx, p.y - fy);
        let (x, y) = (fx as i64, fy as i64);
        let v = |dx, dy| self.at(x + dx, y + dy).clamp(-1e6, 1e6);
        let a = math::mix(v(0, 0), v(1, 0), tx);
        let b = math::mix(v(0, 1), v(1, 1), tx);
        math::mix(a, b, ty)
    }

    /// Central-difference gradient at texel `(x, y)` (texels per texel), pointing away
    /// from solid ground; zero where the field is flat or infinite.
    #[must_use]
    pub fn gradient(&self, x: u32, y: u32) -> Vec2 {
        let (x, y) = (i64::from(x), i64::from(y));
        let v = |dx, dy| self.at(x + dx, y + dy).clamp(-1e6, 1e6);
        let g = Vec2::new(v(1, 0) - v(-1, 0), v(0, 1) - v(0, -1)) * 0.5;
        if g.is_finite() { g } else { Vec2::ZERO }
    }
}

pub(crate) fn check_dims(width: u32, height: u32, len: usize) -> Result<(), Error> {
    for (field, v) in [("mask width", width), ("mask height", height)] {
        if v == 0 || v > MAX_EDT_SIDE {
            return Err(Error::InvalidSize {
                field,
                value: v,
                rule: "in 1..=MAX_EDT_SIDE (16384)",
            });
        }
    }
    let expected = width as usize * height as usize;
    if len != expected {
        return Err(Error::LengthMismatch {
            field: "mask",
            len,
            expected,
        });
    }
    Ok(())
}

/// The column pass for one row, given the previous row's classes and distances: the
/// downward sweep (distance to the nearest pixel of the other class above).
#[inline]
pub(crate) fn column_down(prev_class: &[u8], prev_g: &[u32], class: &[u8], g: &mut [u32]) {
    for x in 0..g.len() {
        g[x] = if class[x] != prev_class[x] {
            1
        } else {
            prev_g[x].saturating_add(1)
        };
    }
}

/// The upward sweep for one row, given the row below.
#[inline]
pub(crate) fn column_up(next_class: &[u8], next_g: &[u32], class: &[u8], g: &mut [u32]) {
    for x in 0..g.len() {
        let d = if class[x] != next_class[x] {
            1
        } else {
            next_g[x].saturating_add(1)
        };
        g[x] = g[x].min(d);
    }
}

/// Classes as 0 (water) / 1 (solid).
pub(crate) fn classes(mask: &[u8]) -> Vec<u8> {
    mask.iter().map(|&m| u8::from(m != 0)).collect()
}

/// Sequential column pass over all rows: `g[y * w + x]` = vertical distance from `(x, y)`
/// to the nearest pixel of the other class in column `x`, or [`INF`].
pub(crate) fn column_pass(class: &[u8], width: usize, g: &mut [u32]) {
    let h = class.len() / width;
    g[..width].fill(INF);
    for y in 1..h {
        let (done, rest) = g.split_at_mut(y * width);
        column_down(
            &class[(y - 1) * width..y * width],
            &done[(y - 1) * width..],
            &class[y * width..(y + 1) * width],
            &mut rest[..width],
        );
    }
    for y in (0..h.saturating_sub(1)).rev() {
        let (head, below) = g.split_at_mut((y + 1) * width);
        column_up(
            &class[(y + 1) * width..(y + 2) * width],
            &below[..width],
            &class[y * width..(y + 1) * width],
            &mut head[y * width..],
        );
    }
}

/// Scratch space for one row's two envelopes.
#[derive(Default)]
pub(crate) struct RowScratch {
    site: Vec<i32>,
    f: Vec<i32>,
    v: Vec<i32>,
    fv: Vec<i32>,
    z: Vec<i32>,
    /// The last row's signed squared distances.
    pub(crate) d2: Vec<i32>,
}

impl RowScratch {
    pub(crate) fn new(width: usize) -> Self {
        Self {
            site: Vec::with_capacity(width),
            f: Vec::with_capacity(width),
            v: vec![0; width + 1],
            fv: vec![0; width + 1],
            z: vec![0; width + 2],
            d2: vec![0; width],
        }
    }
}

/// Builds the lower envelope of the parabolas `(x - site)^2 + f` (sites increasing) and
/// evaluates it at every `x` where `class[x] == target`, writing `d2[x]`. Returns nothing
/// to evaluate against (leaves `d2` untouched) when there are no sites.
fn envelope(s: &mut RowScratch, class: &[u8], target: u8) {
    let n = s.site.len();
    if n == 0 {
        for (x, &c) in class.iter().enumerate() {
            if c == target {
                s.d2[x] = i32::MAX;
            }
        }
        return;
    }
    let (v, fv, z) = (&mut s.v, &mut s.fv, &mut s.z);
    let mut k = 0usize;
    v[0] = s.site[0];
    fv[0] = s.f[0];
    z[0] = i32::MIN;
    z[1] = i32::MAX;
    for i in 1..n {
        let (q, fq) = (s.site[i], s.f[i]);
        let hq = q * q + fq;
        let (num, den) = loop {
            // Parabola q is at most parabola v[k] for x >= num / den.
            let num = hq - (v[k] * v[k] + fv[k]);
            let den = 2 * (q - v[k]);
            // Pop v[k] if q already wins at the first integer of v[k]'s interval:
            // ceil(num / den) <= z[k]  <=>  num <= z[k] * den (den > 0, z[k] an integer).
            if k > 0 && i64::from(num) <= i64::from(z[k]) * i64::from(den) {
                k -= 1;
            } else {
                break (num, den);
            }
        };
        // First integer x where q wins: ceil(num / den), with Rust's truncating division.
        let t = num / den + i32::from(num % den > 0);
        k += 1;
        v[k] = q;
        fv[k] = fq;
        z[k] = t;
        z[k + 1] = i32::MAX;
    }
    let mut k = 0usize;
    for (x, &c) in class.iter().enumerate() {
        if c != target {
            continue;
        }
        let x = x as i32;
        while z[k + 1] <= x {
            k += 1;
        }
        let dx = x - v[k];
        s.d2[x as usize] = dx * dx + fv[k];
    }
}

/// The row pass for one row: signed squared distances into `s.d2` (positive for water,
/// negative for solid, `i32::MAX` / `-i32::MAX` where the other class does not exist).
pub(crate) fn row_pass(s: &mut RowScratch, class: &[u8], g: &[u32]) {
    let w = class.len();
    for target in [0u8, 1u8] {
        // Envelope of distances to the class `1 - target`, evaluated at `target` pixels.
        s.site.clear();
        s.f.clear();
        for x in 0..w {
            if class[x] == target {
                // A pixel of the evaluated class is a site through its column distance.
                if g[x] != INF {
                    s.site.push(x as i32);
                    s.f.push((g[x] * g[x]) as i32);
                }
            } else {
                // A pixel of the other class: distance 0, needed only at a run's ends.
                let left_end = x == 0 || class[x - 1] == target;
                let right_end = x + 1 == w || class[x + 1] == target;
                if left_end || right_end {
                    s.site.push(x as i32);
                    s.f.push(0);
                }
            }
        }
        envelope(s, class, target);
    }
    for x in 0..w {
        if class[x] == 1 {
            s.d2[x] = -s.d2[x];
        }
    }
}

/// Writes one row of f32 distances from signed squared distances.
#[inline]
pub(crate) fn finish_row(d2: &[i32], out: &mut [f32]) {
    for (o, &d) in out.iter_mut().zip(d2) {
        *o = if d == i32::MAX {
            f32::INFINITY
        } else if d == -i32::MAX {
            f32::NEG_INFINITY
        } else if d >= 0 {
            math::sqrt(d as f32)
        } else {
            -math::sqrt((-d) as f32)
        };
    }
}

/// Rows per progress report.
pub(crate) const ROWS_PER_REPORT: usize = 256;

/// The exact signed distance transform of `mask` (non-zero = solid), single-threaded. See
/// the module docs for conventions; [`crate::parallel::signed_edt`] is the rayon version
/// (same result, bit for bit).
pub fn signed_edt(
    mask: &[u8],
    width: u32,
    height: u32,
    progress: &mut impl FnMut(Progress) -> ControlFlow<()>,
) -> Result<DistanceField, Error> {
    check_dims(width, height, mask.len())?;
    let (w, h) = (width as usize, height as usize);
    let class = classes(mask);
    let mut g = vec![0u32; w * h];
    column_pass(&class, w, &mut g);
    report(progress, Stage::DistanceColumns, 1, 1)?;
    let mut values = vec![0.0f32; w * h];
    let mut s = RowScratch::new(w);
    for y in 0..h {
        let r = y * w..(y + 1) * w;
        row_pass(&mut s, &class[r.clone()], &g[r.clone()]);
        finish_row(&s.d2, &mut values[r]);
        if (y + 1) % ROWS_PER_REPORT == 0 || y + 1 == h {
            report(progress, Stage::DistanceRows, (y + 1) as u64, h as u64)?;
        }
    }
    Ok(DistanceField {
        width,
        height,
        values,
    })
}

/// Exact signed squared distances (`+d^2` water, `-d^2` solid, `i32::MAX` / `-i32::MAX`
/// where the other class does not exist): the integers [`signed_edt`] takes the root of.
pub fn signed_squared_edt(mask: &[u8], width: u32, height: u32) -> Result<Vec<i32>, Error> {
    check_dims(width, height, mask.len())?;
    let (w, h) = (width as usize, height as usize);
    let class = classes(mask);
    let mut g = vec![0u32; w * h];
    column_pass(&class, w, &mut g);
    let mut out = vec![0i32; w * h];
    let mut s = RowScratch::new(w);
    for y in 0..h {
        let r = y * w..(y + 1) * w;
        row_pass(&mut s, &class[r.clone()], &g[r.clone()]);
        out[r].copy_from_slice(&s.d2);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::progress::no_progress;

    fn brute(mask: &[u8], w: usize, h: usize) -> Vec<i32> {
        let mut out = vec![0; w * h];
        for y in 0..h {
            for x in 0..w {
                let solid = mask[y * w + x] != 0;
                let mut best = i64::MAX;
                for yy in 0..h {
                    for xx in 0..w {
                        if (mask[yy * w + xx] != 0) != solid {
                            let d = (x as i64 - xx as i64).pow(2) + (y as i64 - yy as i64).pow(2);
                            best = best.min(d);
                        }
                    }
                }
                let d = if best == i64::MAX {
                    i32::MAX
                } else {
                    best as i32
                };
                out[y * w + x] = if solid { -d } else { d };
            }
        }
        out
    }

    #[test]
    fn matches_brute_force_on_small_masks() {
        let mut s = 0x1234_5678u32;
        for case in 0..60 {
            let (w, h) = (1 + case % 13, 1 + (case * 7) % 11);
            let density = case % 5;
            let mask: Vec<u8> = (0..w * h)
                .map(|_| {
                    s = crate::hash::pcg(s);
                    u8::from(s % 5 < density as u32)
                })
                .collect();
            let got = signed_squared_edt(&mask, w as u32, h as u32).unwrap();
            assert_eq!(got, brute(&mask, w, h), "case {case} {w}x{h}");
        }
    }

    #[test]
    fn single_rock_gives_exact_radial_distances() {
        let (w, h) = (9u32, 7u32);
        let mut mask = vec![0u8; 63];
        mask[3 * 9 + 4] = 1;
        let f = signed_edt(&mask, w, h, &mut no_progress).unwrap();
        assert_eq!(f.at(4, 3), -1.0);
        assert_eq!(f.at(7, 3), 3.0);
        assert_eq!(f.at(8, 6), 5.0);
        assert!((f.at(0, 0) - 5.0).abs() < 1e-6);
        let all_solid = signed_edt(&[1; 6], 3, 2, &mut no_progress).unwrap();
        assert!(all_solid.values().iter().all(|&v| v == f32::NEG_INFINITY));
        let all_water = signed_edt(&[0; 6], 2, 3, &mut no_progress).unwrap();
        assert!(all_water.values().iter().all(|&v| v == f32::INFINITY));
    }

    #[test]
    fn rejects_bad_dimensions() {
        assert!(signed_edt(&[0; 10], 3, 3, &mut no_progress).is_err());
        assert!(signed_edt(&[], 0, 0, &mut no_progress).is_err());
        assert!(signed_squared_edt(&[0; 4], 4, 1).is_ok());
    }

    #[test]
    fn cancels() {
        let r = signed_edt(&[0; 16], 4, 4, &mut |_| ControlFlow::Break(()));
        assert_eq!(r, Err(Error::Cancelled));
    }
}
