//! Quantisation of float positions inside an axis-aligned box onto the integer grid of a
//! Morton (or Hilbert) code.
//!
//! For `bits` per axis the box `[min, max]` is cut into `2^bits` equal cells per axis, and
//! a position `p` lands in cell
//!
//! ```text
//! cell = clamp(floor((p - min) * 2^bits / (max - min)), 0, 2^bits - 1)     (per axis)
//! ```
//!
//! so `min` is the low corner of cell 0 and `max` falls into the last cell. Units are the
//! caller's (world units in, cells out); the grid's axes are the input axes, x lowest in the
//! key. The arithmetic is f32, as on the GPU: `(p - min)` is rounded once and multiplied by
//! a scale rounded once, so a point within a few ulps of a cell boundary may land in either
//! neighbour (tested against an f64 reference).
//!
//! Edge cases, all tested:
//! - positions outside the box, including ±infinity, clamp to the nearest cell;
//! - an axis with `min == max` (a flat scene) maps every position to cell 0 on that axis,
//!   and so does one thinner than `2^bits / f32::MAX` world units (about 6e-33 at 21
//!   bits), whose cells would be too small for f32 arithmetic;
//! - a NaN component is an error, [`Error::NanPosition`]. The batch functions still
//!   write every key, with each NaN component mapped to cell 0, and return the index of the
//!   first NaN point: the fast loop has no branch, the check is an OR across the batch;
//! - bounds must be finite with `min <= max` ([`Error::BadBounds`]); the bits per
//!   axis must fit the key ([`Error::BadBits`]).
//!
//! ```
//! use morton::glam::{UVec3, Vec3};
//! use morton::Quantizer3;
//!
//! let q = Quantizer3::new(Vec3::splat(-100.0), Vec3::splat(100.0), 10).unwrap();
//! assert_eq!(q.quantize(Vec3::new(-100.0, 0.0, 100.0)).unwrap(), UVec3::new(0, 512, 1023));
//! assert_eq!(q.quantize(Vec3::splat(1e9)).unwrap(), UVec3::splat(1023)); // clamped
//! assert!(q.quantize(Vec3::new(0.0, f32::NAN, 0.0)).is_err());
//!
//! let points = [Vec3::new(-100.0, -100.0, -100.0), Vec3::new(100.0, 100.0, 100.0)];
//! let mut keys = [0u32; 2];
//! q.morton_u32_slice(&points, &mut keys).unwrap();
//! assert_eq!(keys, [0, 0x3fff_ffff]);
//! ```

use glam::{UVec2, UVec3, Vec2, Vec3};

use crate::kernels::available;
use crate::{BITS2_U32, BITS2_U64, BITS3_U32, BITS3_U64, Error, Path, magic};

/// One axis's scale: cells per world unit, `2^bits / (max - min)`, computed in f64 and
/// rounded once to f32; 0 for a flat axis, and for one so thin that the scale would not fit
/// an f32 (extent below `2^bits / f32::MAX`, about 6e-33 at 21 bits).
fn axis_scale(min: f32, max: f32, bits: u32) -> f32 {
    let extent = max as f64 - min as f64;
    if extent <= 0.0 {
        return 0.0;
    }
    let s = (1u64 << bits) as f64 / extent;
    if s > f32::MAX as f64 { 0.0 } else { s as f32 }
}

/// One coordinate onto the grid: `t = (p - min) * scale`, clamped to `[0, top]` with
/// compare-selects (a NaN `t` fails `t >= 0` and becomes 0), then truncated.
#[inline(always)]
fn cell(p: f32, min: f32, scale: f32, top: f32) -> u32 {
    let t = (p - min) * scale;
    let t = if t >= 0.0 { t } else { 0.0 };
    let t = if t <= top { t } else { top };
    // SAFETY: `t` is not NaN and lies in [0, top] with top <= 2^21 - 1 (checked in `new`),
    // so truncation fits an i32.
    let i: i32 = unsafe { t.to_int_unchecked() };
    i as u32
}

fn check_bits(bits: u32, max: u32) -> Result<(), Error> {
    if (1..=max).contains(&bits) {
        Ok(())
    } else {
        Err(Error::BadBits { bits, max })
    }
}

fn check_axis(axis: u8, min: f32, max: f32) -> Result<(), Error> {
    if min.is_finite() && max.is_finite() && min <= max {
        Ok(())
    } else {
        Err(Error::BadBounds { axis, min, max })
    }
}

/// Maps 3D positions inside an axis-aligned box onto a `2^bits`-per-axis grid, and on to
/// Morton keys. See the [module docs](self) for the mapping and its edge cases.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quantizer3 {
    min: Vec3,
    max: Vec3,
    scale: Vec3,
    bits: u32,
    top: f32,
}

impl Quantizer3 {
    /// A quantiser for the box `[min, max]` (world units) with `bits` per axis, `1..=21`
    /// ([`BITS3_U64`]); 32-bit keys need `bits <= 10` ([`BITS3_U32`]).
    pub fn new(min: Vec3, max: Vec3, bits: u32) -> Result<Self, Error> {
        check_bits(bits, BITS3_U64)?;
        for axis in 0..3 {
            check_axis(axis as u8, min[axis], max[axis])?;
        }
        Ok(Self {
            min,
            max,
            scale: Vec3::new(
                axis_scale(min.x, max.x, bits),
                axis_scale(min.y, max.y, bits),
                axis_scale(min.z, max.z, bits),
            ),
            bits,
            top: ((1u32 << bits) - 1) as f32,
        })
    }

    /// A quantiser over the bounding box of `points` (NaN components are skipped). Without
    /// any finite point the box is the origin.
    pub fn from_points(points: &[Vec3], bits: u32) -> Result<Self, Error> {
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for p in points {
            for axis in 0..3 {
                let v = p[axis];
                if v.is_finite() {
                    lo[axis] = lo[axis].min(v);
                    hi[axis] = hi[axis].max(v);
                }
            }
        }
        for axis in 0..3 {
            if lo[axis] > hi[axis] {
                lo[axis] = 0.0;
                hi[axis] = 0.0;
            }
        }
        Self::new(lo, hi, bits)
    }

    /// Bits per axis.
    pub fn bits(&self) -> u32 {
        self.bits
    }

    /// The box's low corner, the low corner of cell 0.
    pub fn min(&self) -> Vec3 {
        self.min
    }

    /// The box's high corner, inside the last cell.
    pub fn max(&self) -> Vec3 {
        self.max
    }

    /// Cells per world unit on each axis (0 on a flat axis), as used by the f32 arithmetic.
    pub fn scale(&self) -> Vec3 {
        self.scale
    }

    /// The size of one cell in world units, `(max - min) / 2^bits`.
    pub fn cell_size(&self) -> Vec3 {
        (self.max - self.min) / (1u64 << self.bits) as f32
    }

    /// The grid cell of `p`; [`Error::NanPosition`] (index 0) if a component is NaN.
    #[inline]
    pub fn quantize(&self, p: Vec3) -> Result<UVec3, Error> {
        if p.is_nan() {
            return Err(Error::NanPosition { index: 0 });
        }
        Ok(self.quantize_unchecked_nan(p))
    }

    /// The grid cell of `p` with NaN components mapped to cell 0 (never fails).
    #[inline]
    pub fn quantize_unchecked_nan(&self, p: Vec3) -> UVec3 {
        UVec3::new(
            cell(p.x, self.min.x, self.scale.x, self.top),
            cell(p.y, self.min.y, self.scale.y, self.top),
            cell(p.z, self.min.z, self.scale.z, self.top),
        )
    }

    /// The centre of grid cell `c` in world units (the inverse of [`Self::quantize`] up
    /// to half a cell). Coordinates above `2^bits - 1` are not clamped.
    pub fn cell_center(&self, c: UVec3) -> Vec3 {
        self.min + (c.as_vec3() + 0.5) * self.cell_size()
    }

    /// The 32-bit Morton key of `p` (`bits <= 10`, else [`Error::BadBits`]).
    #[inline]
    pub fn morton_u32(&self, p: Vec3) -> Result<u32, Error> {
        check_bits(self.bits, BITS3_U32)?;
        let c = self.quantize(p)?;
        Ok(crate::encode3_u32(c.x, c.y, c.z))
    }

    /// The 64-bit Morton key of `p`.
    #[inline]
    pub fn morton_u64(&self, p: Vec3) -> Result<u64, Error> {
        let c = self.quantize(p)?;
        Ok(crate::encode3_u64(c.x, c.y, c.z))
    }

    /// Grid cells of many points. On a NaN every cell is still written (NaN components in
    /// cell 0) and the first NaN's index is returned in the error.
    pub fn quantize_slice(&self, points: &[Vec3], out: &mut [UVec3]) -> Result<(), Error> {
        same_len(points.len(), out.len())?;
        let mut nan = false;
        for (o, &p) in out.iter_mut().zip(points) {
            nan |= p.is_nan();
            *o = self.quantize_unchecked_nan(p);
        }
        nan_result(nan, points)
    }

    /// 32-bit Morton keys of many points (`bits <= 10`), on [`Path::best`]. On a NaN every
    /// key is still written (NaN components in cell 0) and the first NaN's index is
    /// returned in the error.
    pub fn morton_u32_slice(&self, points: &[Vec3], out: &mut [u32]) -> Result<(), Error> {
        self.morton_u32_slice_with(Path::best(), points, out)
    }

    /// [`Self::morton_u32_slice`] on a given [`Path`].
    pub fn morton_u32_slice_with(
        &self,
        path: Path,
        points: &[Vec3],
        out: &mut [u32],
    ) -> Result<(), Error> {
        check_bits(self.bits, BITS3_U32)?;
        available(path)?;
        same_len(points.len(), out.len())?;
        let nan = q3_32::run(path, self, points, out);
        nan_result(nan, points)
    }

    /// 64-bit Morton keys of many points, on [`Path::best`]. NaN handling as
    /// [`Self::morton_u32_slice`].
    pub fn morton_u64_slice(&self, points: &[Vec3], out: &mut [u64]) -> Result<(), Error> {
        self.morton_u64_slice_with(Path::best(), points, out)
    }

    /// [`Self::morton_u64_slice`] on a given [`Path`].
    pub fn morton_u64_slice_with(
        &self,
        path: Path,
        points: &[Vec3],
        out: &mut [u64],
    ) -> Result<(), Error> {
        available(path)?;
        same_len(points.len(), out.len())?;
        let nan = q3_64::run(path, self, points, out);
        nan_result(nan, points)
    }
}

fn same_len(expected: usize, got: usize) -> Result<(), Error> {
    if expected == got {
        Ok(())
    } else {
        Err(Error::LengthMismatch {
            what: "out",
            expected,
            got,
        })
    }
}

/// Turns the batch's NaN flag into the error naming the first NaN point.
fn nan_result<P: NanCheck>(nan: bool, points: &[P]) -> Result<(), Error> {
    if !nan {
        return Ok(());
    }
    let index = points.iter().position(|p| p.has_nan()).unwrap_or(0);
    Err(Error::NanPosition { index })
}

trait NanCheck {
    fn has_nan(&self) -> bool;
}
impl NanCheck for Vec3 {
    fn has_nan(&self) -> bool {
        self.is_nan()
    }
}
impl NanCheck for Vec2 {
    fn has_nan(&self) -> bool {
        self.is_nan()
    }
}

/// The quantise+encode loop: one pass, no branches; evaluates to whether any input was NaN.
macro_rules! q3_loop {
    ($q:expr, $points:expr, $out:expr, $enc:expr) => {{
        let (min, scale, top) = ($q.min, $q.scale, $q.top);
        let mut nan = false;
        for (o, p) in $out.iter_mut().zip($points) {
            nan |= p.x.is_nan() | p.y.is_nan() | p.z.is_nan();
            *o = ($enc)(
                cell(p.x, min.x, scale.x, top),
                cell(p.y, min.y, scale.y, top),
                cell(p.z, min.z, scale.z, top),
            );
        }
        nan
    }};
}

macro_rules! q2_loop {
    ($q:expr, $points:expr, $out:expr, $enc:expr) => {{
        let (min, scale, top) = ($q.min, $q.scale, $q.top);
        let mut nan = false;
        for (o, p) in $out.iter_mut().zip($points) {
            nan |= p.x.is_nan() | p.y.is_nan();
            *o = ($enc)(
                cell(p.x, min.x, scale.x, top),
                cell(p.y, min.y, scale.y, top),
            );
        }
        nan
    }};
}

#[cfg(target_arch = "x86_64")]
use crate::bmi2 as pd;

kernels!(q3_32, q3_loop, (q: &Quantizer3, points: &[Vec3], out: &mut [u32]) -> bool,
    magic: magic::encode3_u32, bmi2: |x, y, z| pd::encode3_u32(x, y, z));
kernels!(q3_64, q3_loop, (q: &Quantizer3, points: &[Vec3], out: &mut [u64]) -> bool,
    magic: magic::encode3_u64, bmi2: |x, y, z| pd::encode3_u64(x, y, z));
kernels!(q2_32, q2_loop, (q: &Quantizer2, points: &[Vec2], out: &mut [u32]) -> bool,
    magic: magic::encode2_u32, bmi2: |x, y| pd::encode2_u32(x, y));
kernels!(q2_64, q2_loop, (q: &Quantizer2, points: &[Vec2], out: &mut [u64]) -> bool,
    magic: magic::encode2_u64, bmi2: |x, y| pd::encode2_u64(x, y));

/// Maps 2D positions inside an axis-aligned rectangle onto a `2^bits`-per-axis grid, and on
/// to Morton keys. The same mapping and edge cases as [`Quantizer3`] (see the
/// [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quantizer2 {
    min: Vec2,
    max: Vec2,
    scale: Vec2,
    bits: u32,
    top: f32,
}

impl Quantizer2 {
    /// A quantiser for the rectangle `[min, max]` with `bits` per axis, `1..=21`: the f32
    /// arithmetic resolves about 2^21 cells, so 2D codes of more bits would only repeat
    /// cells. 32-bit keys take up to [`BITS2_U32`] = 16 bits per axis.
    pub fn new(min: Vec2, max: Vec2, bits: u32) -> Result<Self, Error> {
        check_bits(bits, MAX_BITS_F32)?;
        for axis in 0..2 {
            check_axis(axis as u8, min[axis], max[axis])?;
        }
        Ok(Self {
            min,
            max,
            scale: Vec2::new(
                axis_scale(min.x, max.x, bits),
                axis_scale(min.y, max.y, bits),
            ),
            bits,
            top: ((1u32 << bits) - 1) as f32,
        })
    }

    /// Bits per axis.
    pub fn bits(&self) -> u32 {
        self.bits
    }

    /// The rectangle's low corner.
    pub fn min(&self) -> Vec2 {
        self.min
    }

    /// The rectangle's high corner.
    pub fn max(&self) -> Vec2 {
        self.max
    }

    /// Cells per world unit on each axis (0 on a flat axis).
    pub fn scale(&self) -> Vec2 {
        self.scale
    }

    /// The size of one cell in world units.
    pub fn cell_size(&self) -> Vec2 {
        (self.max - self.min) / (1u64 << self.bits) as f32
    }

    /// The grid cell of `p`; [`Error::NanPosition`] if a component is NaN.
    #[inline]
    pub fn quantize(&self, p: Vec2) -> Result<UVec2, Error> {
        if p.is_nan() {
            return Err(Error::NanPosition { index: 0 });
        }
        Ok(self.quantize_unchecked_nan(p))
    }

    /// The grid cell of `p` with NaN components mapped to cell 0.
    #[inline]
    pub fn quantize_unchecked_nan(&self, p: Vec2) -> UVec2 {
        UVec2::new(
            cell(p.x, self.min.x, self.scale.x, self.top),
            cell(p.y, self.min.y, self.scale.y, self.top),
        )
    }

    /// The centre of grid cell `c` in world units.
    pub fn cell_center(&self, c: UVec2) -> Vec2 {
        self.min + (c.as_vec2() + 0.5) * self.cell_size()
    }

    /// The 32-bit Morton key of `p` (`bits <= 16`).
    #[inline]
    pub fn morton_u32(&self, p: Vec2) -> Result<u32, Error> {
        check_bits(self.bits, BITS2_U32)?;
        let c = self.quantize(p)?;
        Ok(crate::encode2_u32(c.x, c.y))
    }

    /// The 64-bit Morton key of `p`.
    #[inline]
    pub fn morton_u64(&self, p: Vec2) -> Result<u64, Error> {
        let c = self.quantize(p)?;
        Ok(crate::encode2_u64(c.x, c.y))
    }

    /// Grid cells of many points; NaN handling as [`Quantizer3::quantize_slice`].
    pub fn quantize_slice(&self, points: &[Vec2], out: &mut [UVec2]) -> Result<(), Error> {
        same_len(points.len(), out.len())?;
        let mut nan = false;
        for (o, &p) in out.iter_mut().zip(points) {
            nan |= p.is_nan();
            *o = self.quantize_unchecked_nan(p);
        }
        nan_result(nan, points)
    }

    /// 32-bit Morton keys of many points (`bits <= 16`), on [`Path::best`].
    pub fn morton_u32_slice(&self, points: &[Vec2], out: &mut [u32]) -> Result<(), Error> {
        self.morton_u32_slice_with(Path::best(), points, out)
    }

    /// [`Self::morton_u32_slice`] on a given [`Path`].
    pub fn morton_u32_slice_with(
        &self,
        path: Path,
        points: &[Vec2],
        out: &mut [u32],
    ) -> Result<(), Error> {
        check_bits(self.bits, BITS2_U32)?;
        available(path)?;
        same_len(points.len(), out.len())?;
        let nan = q2_32::run(path, self, points, out);
        nan_result(nan, points)
    }

    /// 64-bit Morton keys of many points, on [`Path::best`].
    pub fn morton_u64_slice(&self, points: &[Vec2], out: &mut [u64]) -> Result<(), Error> {
        self.morton_u64_slice_with(Path::best(), points, out)
    }

    /// [`Self::morton_u64_slice`] on a given [`Path`].
    pub fn morton_u64_slice_with(
        &self,
        path: Path,
        points: &[Vec2],
        out: &mut [u64],
    ) -> Result<(), Error> {
        available(path)?;
        same_len(points.len(), out.len())?;
        let nan = q2_64::run(path, self, points, out);
        nan_result(nan, points)
    }
}

/// The most bits per axis a quantiser takes: f32 positions resolve about 2^21 steps
/// across a box, and 3D u64 keys hold 21 bits per axis.
pub const MAX_BITS_F32: u32 = 21;

const _: () = assert!(MAX_BITS_F32 == BITS3_U64 && BITS2_U64 > MAX_BITS_F32);
