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
use crate::grid::{clamped_index, size_getters};
use crate::math;
use crate::progress::{Progress, Stage, report};

/// Largest mask side: keeps squared distances and the envelope arithmetic in `i32`.
pub const MAX_EDT_SIDE: u32 = 16384;

/// "No pixel of the other class in this column".
pub(crate) const INF: u16 = u16::MAX;

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

    size_getters!("Width in texels.", "Height in texels.");

    /// The values, row-major.
    #[must_use]
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// The value at texel `(x, y)`, clamped to the field.
    #[inline]
    #[must_use]
    pub fn at(&self, x: i64, y: i64) -> f32 {
        self.values[clamped_index(self.width, self.height, x, y)]
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

/// The column pass for one row, given the previous row's mask and distances: the
/// downward sweep (distance to the nearest pixel of the other class above).
#[inline]
pub(crate) fn column_down(prev_mask: &[u8], prev_g: &[u16], mask: &[u8], g: &mut [u16]) {
    for (((g, &m), &pm), &pg) in g.iter_mut().zip(mask).zip(prev_mask).zip(prev_g) {
        *g = if (m != 0) != (pm != 0) {
            1
        } else {
            pg.saturating_add(1)
        };
    }
}

/// The upward sweep for one row, given the row below.
#[inline]
pub(crate) fn column_up(next_mask: &[u8], next_g: &[u16], mask: &[u8], g: &mut [u16]) {
    for (((g, &m), &nm), &ng) in g.iter_mut().zip(mask).zip(next_mask).zip(next_g) {
        let d = if (m != 0) != (nm != 0) {
            1
        } else {
            ng.saturating_add(1)
        };
        *g = (*g).min(d);
    }
}

/// Sequential column pass over all rows: `g[y * w + x]` = vertical distance from `(x, y)`
/// to the nearest pixel of the other class in column `x`, or [`INF`] (distances are below
/// [`MAX_EDT_SIDE`], so they fit `u16`).
pub(crate) fn column_pass(mask: &[u8], width: usize, g: &mut [u16]) {
    let h = mask.len() / width;
    g[..width].fill(INF);
    for y in 1..h {
        let (done, rest) = g.split_at_mut(y * width);
        column_down(
            &mask[(y - 1) * width..y * width],
            &done[(y - 1) * width..],
            &mask[y * width..(y + 1) * width],
            &mut rest[..width],
        );
    }
    for y in (0..h.saturating_sub(1)).rev() {
        let (head, below) = g.split_at_mut((y + 1) * width);
        column_up(
            &mask[(y + 1) * width..(y + 2) * width],
            &below[..width],
            &mask[y * width..(y + 1) * width],
            &mut head[y * width..],
        );
    }
}

/// Scratch space for one run's envelope.
pub(crate) struct RowScratch {
    /// Sites (x) and their values (squared column distance).
    site: Vec<i32>,
    f: Vec<i32>,
    /// The envelope: parabola apex x, its value there, `x^2 + f`, and where it starts
    /// (`zn / zd`).
    v: Vec<i32>,
    fv: Vec<i32>,
    hv: Vec<i32>,
    zn: Vec<i64>,
    zd: Vec<i64>,
}

impl RowScratch {
    pub(crate) fn new(width: usize) -> Self {
        Self {
            site: vec![0; width + 2],
            f: vec![0; width + 2],
            v: vec![0; width + 2],
            fv: vec![0; width + 2],
            hv: vec![0; width + 2],
            zn: vec![0; width + 3],
            zd: vec![1; width + 3],
        }
    }
}

/// Builds the lower envelope of the `n` parabolas `(x - site)^2 + f` in the scratch
/// (sites increasing, `n >= 1`) and calls `write(x, d2)` for every `x` in `a..=b`.
///
/// Breakpoints are kept as exact fractions `zn / zd` (`zd > 0`): parabola `q` is below
/// parabola `v` for `x >= (q^2 + f_q - v^2 - f_v) / (2 (q - v))`, and every comparison of
/// two breakpoints, or of a breakpoint with an integer, is a cross-multiplication in `i64`
/// (operands below 2^30 and 2^15, products below 2^46): no rounding and no division.
#[inline]
fn envelope(s: &mut RowScratch, n: usize, a: usize, b: usize, write: &mut impl FnMut(usize, i32)) {
    let (site, f) = (&s.site[..n], &s.f[..n]);
    let (v, fv, hv, zn, zd) = (&mut s.v, &mut s.fv, &mut s.hv, &mut s.zn, &mut s.zd);
    // The top of the stack lives in locals; the arrays hold everything below it too.
    let mut k = 0usize;
    let (mut tv, mut th, mut tzn, mut tzd) = (site[0], site[0] * site[0] + f[0], 0i64, 1i64);
    v[0] = tv;
    fv[0] = f[0];
    hv[0] = th;
    for (&q, &fq) in site[1..].iter().zip(&f[1..]) {
        let hq = q * q + fq;
        loop {
            let num = i64::from(hq - th);
            let den = i64::from(2 * (q - tv));
            // Pop the top when q wins from where it starts: num / den <= tzn / tzd.
            if k > 0 && num * tzd <= tzn * den {
                k -= 1;
                (tv, th, tzn, tzd) = (v[k], hv[k], zn[k], zd[k]);
            } else {
                k += 1;
                (v[k], fv[k], hv[k], zn[k], zd[k]) = (q, fq, hq, num, den);
                (tv, th, tzn, tzd) = (q, hq, num, den);
                break;
            }
        }
    }
    let last = k;
    let (v, fv, zn, zd) = (&v[..=last], &fv[..=last], &zn[..=last], &zd[..=last]);
    let mut k = 0usize;
    for x in a..=b {
        let xi = x as i64;
        // Advance while the next parabola starts at or before x.
        while k < last && zn[k + 1] <= xi * zd[k + 1] {
            k += 1;
        }
        let dx = x as i32 - v[k];
        write(x, dx * dx + fv[k]);
    }
}

/// The row pass for one row: calls `write(x, d2)` once per pixel with its signed squared
/// distance (positive for water, negative for solid, `i32::MAX` / `-i32::MAX` where the
/// other class does not exist).
///
/// The row splits into runs of one class. For a pixel in a run, a site outside the run is
/// never nearer than the other-class pixel just past the run's end on that side (it lies
/// between them, at distance 0), so each run is solved alone: its own pixels as sites
/// through their column distances, plus the two other-class pixels bounding it. A site
/// whose column distance is at least the largest distance the bounding pixels leave,
/// `max_y min(y - (a - 1), (b + 1) - y)`, can never be the nearest and is skipped.
#[inline]
pub(crate) fn row_pass(
    s: &mut RowScratch,
    mask: &[u8],
    g: &[u16],
    mut write: impl FnMut(usize, i32),
) {
    let w = mask.len();
    let mut a = 0usize;
    while a < w {
        let c = mask[a] != 0;
        let mut b = a;
        while b + 1 < w && (mask[b + 1] != 0) == c {
            b += 1;
        }
        let (left, right) = (a > 0, b + 1 < w);
        let len = b - a + 1;
        // Largest squared distance the bounding pixels leave inside the run.
        let reach = match (left, right) {
            (true, true) => len.div_ceil(2),
            (true, false) | (false, true) => len,
            (false, false) => usize::MAX,
        };
        let mut n = 0;
        if left {
            s.site[0] = a as i32 - 1;
            s.f[0] = 0;
            n = 1;
        }
        for (x, &gx) in (a..=b).zip(&g[a..=b]) {
            if gx != INF && usize::from(gx) < reach {
                s.site[n] = x as i32;
                s.f[n] = i32::from(gx) * i32::from(gx);
                n += 1;
            }
        }
        if right {
            s.site[n] = b as i32 + 1;
            s.f[n] = 0;
            n += 1;
        }
        if n == 0 {
            let none = if c { -i32::MAX } else { i32::MAX };
            for x in a..=b {
                write(x, none);
            }
        } else if c {
            envelope(s, n, a, b, &mut |x, d| write(x, -d));
        } else {
            envelope(s, n, a, b, &mut write);
        }
        a = b + 1;
    }
}

/// Turns a row of signed squared distances, stored as f32 (`d2 as f32`), into signed
/// distances, in place: a separate loop so that the square roots vectorise.
#[inline]
pub(crate) fn finish_row(row: &mut [f32]) {
    // `i32::MAX as f32` is 2^31; real squared distances are below 2^29.
    const NONE: f32 = 2_147_483_648.0;
    for v in row.iter_mut() {
        let a = v.abs();
        let r = if a >= NONE {
            f32::INFINITY
        } else {
            math::sqrt(a)
        };
        *v = if *v < 0.0 { -r } else { r };
    }
}

/// Rows per progress report.
pub(crate) const ROWS_PER_REPORT: usize = 256;

/// Row `y` of the signed distance field into `out` (one row, `out.len()` texels wide), from
/// the mask and the column pass's `g`.
pub(crate) fn distance_row(s: &mut RowScratch, mask: &[u8], g: &[u16], y: usize, out: &mut [f32]) {
    let w = out.len();
    let r = y * w..(y + 1) * w;
    row_pass(s, &mask[r.clone()], &g[r], |x, d| out[x] = d as f32);
    finish_row(out);
}

/// The distance transform with its two passes given, shared by the sequential
/// [`signed_edt`] and the parallel [`crate::parallel::signed_edt`]: `column_pass(mask, w, g)`
/// fills `g` like [`column_pass`]; `rows(y0, chunk, g)` fills `chunk`, the whole rows from
/// row `y0` (at most [`ROWS_PER_REPORT`] of them), each like [`distance_row`]. Progress is
/// reported from this thread after the columns and after every chunk of rows.
pub(crate) fn signed_edt_with(
    mask: &[u8],
    width: u32,
    height: u32,
    progress: &mut impl FnMut(Progress) -> ControlFlow<()>,
    column_pass: impl FnOnce(&[u8], usize, &mut [u16]),
    mut rows: impl FnMut(usize, &mut [f32], &[u16]),
) -> Result<DistanceField, Error> {
    check_dims(width, height, mask.len())?;
    let (w, h) = (width as usize, height as usize);
    let mut g = vec![0u16; w * h];
    column_pass(mask, w, &mut g);
    report(progress, Stage::DistanceColumns, 1, 1)?;
    let mut values = vec![0.0f32; w * h];
    for (b, chunk) in values.chunks_mut(ROWS_PER_REPORT * w).enumerate() {
        let y0 = b * ROWS_PER_REPORT;
        rows(y0, chunk, &g);
        let done = (y0 + chunk.len() / w) as u64;
        report(progress, Stage::DistanceRows, done, h as u64)?;
    }
    Ok(DistanceField {
        width,
        height,
        values,
    })
}

/// The exact signed distance transform of `mask` (non-zero = solid), single-threaded. See
/// the module docs for conventions; [`crate::parallel::signed_edt`] is the rayon version
/// (same result, bit for bit).
pub fn signed_edt(
    mask: &[u8],
    width: u32,
    height: u32,
    progress: &mut impl FnMut(Progress) -> ControlFlow<()>,
) -> Result<DistanceField, Error> {
    // Made on the first row, once the dimensions are known to be valid.
    let mut scratch = None;
    signed_edt_with(
        mask,
        width,
        height,
        progress,
        column_pass,
        |y0, chunk, g| {
            let s = scratch.get_or_insert_with(|| RowScratch::new(width as usize));
            for (i, out) in chunk.chunks_mut(width as usize).enumerate() {
                distance_row(s, mask, g, y0 + i, out);
            }
        },
    )
}

/// Exact signed squared distances (`+d^2` water, `-d^2` solid, `i32::MAX` / `-i32::MAX`
/// where the other class does not exist): the integers [`signed_edt`] takes the root of.
pub fn signed_squared_edt(mask: &[u8], width: u32, height: u32) -> Result<Vec<i32>, Error> {
    check_dims(width, height, mask.len())?;
    let (w, h) = (width as usize, height as usize);
    let mut g = vec![0u16; w * h];
    column_pass(mask, w, &mut g);
    let mut out = vec![0i32; w * h];
    let mut s = RowScratch::new(w);
    for y in 0..h {
        let r = y * w..(y + 1) * w;
        let o = &mut out[r.clone()];
        row_pass(&mut s, &mask[r.clone()], &g[r], |x, d| o[x] = d);
    }
    Ok(out)
}

/// The test-support reference for [`signed_squared_edt`]: every texel against every texel of
/// the other class, `O((w h)^2)`, independent of the separable algorithm. `mask` is row-major
/// `w x h` (non-zero = solid); the result follows [`signed_squared_edt`]'s conventions. The
/// unit tests, `tests/edt.rs` and the `fuzzing` crate share this one copy; public only for
/// them (hidden from the docs), far too slow for real masks.
#[doc(hidden)]
#[must_use]
pub fn brute_signed_squared_edt(mask: &[u8], w: usize, h: usize) -> Vec<i32> {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::progress::no_progress;

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
            assert_eq!(
                got,
                brute_signed_squared_edt(&mask, w, h),
                "case {case} {w}x{h}"
            );
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
