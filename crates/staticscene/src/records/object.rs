//! The object's records: the 48-byte [`Transform4x3`], the 64-byte [`QueryObject`] on
//! the snapped 1 m grid, the 32-byte [`QuerySetup`], and the floating-origin helpers.

use bytemuck::{Pod, Zeroable};
use glam::{Affine3A, DVec3, IVec3, Mat3, Vec3};
use half::f16;

use super::half_box::half_to_f32_branchless;
use crate::{Error, Field};

/// A 4x3 affine transform, 48 bytes: three rows `[a, b, c, t]`, so that
/// `p' = (row0 · (p, 1), row1 · (p, 1), row2 · (p, 1))`. WGSL: `array<vec4<f32>, 3>`
/// (`StaticsceneTransform`), the rows of HLSL's `float3x4`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Transform4x3 {
    /// The rows: linear part in `[0..3]`, translation in `[3]`.
    pub rows: [[f32; 4]; 3],
}

const _: () = assert!(size_of::<Transform4x3>() == 48);

impl Default for Transform4x3 {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Transform4x3 {
    /// The identity.
    pub const IDENTITY: Transform4x3 = Transform4x3 {
        rows: [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
        ],
    };

    /// From a linear part and a translation.
    #[must_use]
    pub fn from_mat3_translation(m: Mat3, t: Vec3) -> Transform4x3 {
        Transform4x3 {
            rows: [
                [m.x_axis.x, m.y_axis.x, m.z_axis.x, t.x],
                [m.x_axis.y, m.y_axis.y, m.z_axis.y, t.y],
                [m.x_axis.z, m.y_axis.z, m.z_axis.z, t.z],
            ],
        }
    }

    /// From a glam affine transform.
    #[must_use]
    pub fn from_affine(a: &Affine3A) -> Transform4x3 {
        Self::from_mat3_translation(Mat3::from(a.matrix3), Vec3::from(a.translation))
    }

    /// To a glam affine transform.
    #[must_use]
    pub fn to_affine(&self) -> Affine3A {
        Affine3A::from_mat3_translation(self.linear(), self.translation())
    }

    /// The linear part.
    #[must_use]
    pub fn linear(&self) -> Mat3 {
        let r = &self.rows;
        Mat3::from_cols(
            Vec3::new(r[0][0], r[1][0], r[2][0]),
            Vec3::new(r[0][1], r[1][1], r[2][1]),
            Vec3::new(r[0][2], r[1][2], r[2][2]),
        )
    }

    /// The translation column.
    #[must_use]
    #[inline]
    pub fn translation(&self) -> Vec3 {
        Vec3::new(self.rows[0][3], self.rows[1][3], self.rows[2][3])
    }

    /// This transform with its translation replaced.
    #[must_use]
    #[inline]
    pub fn with_translation(mut self, t: Vec3) -> Transform4x3 {
        self.rows[0][3] = t.x;
        self.rows[1][3] = t.y;
        self.rows[2][3] = t.z;
        self
    }

    /// Whether all twelve entries are finite.
    #[must_use]
    pub fn is_finite(&self) -> bool {
        self.rows.iter().flatten().all(|x| x.is_finite())
    }

    /// Transforms a point.
    #[must_use]
    #[inline]
    pub fn transform_point(&self, p: Vec3) -> Vec3 {
        let r = &self.rows;
        Vec3::new(
            r[0][0] * p.x + r[0][1] * p.y + r[0][2] * p.z + r[0][3],
            r[1][0] * p.x + r[1][1] * p.y + r[1][2] * p.z + r[1][3],
            r[2][0] * p.x + r[2][1] * p.y + r[2][2] * p.z + r[2][3],
        )
    }

    /// `self ∘ rhs`: applies `rhs` first, then `self`.
    #[must_use]
    #[inline]
    pub fn mul(&self, rhs: &Transform4x3) -> Transform4x3 {
        let a = &self.rows;
        let b = &rhs.rows;
        let mut out = [[0.0f32; 4]; 3];
        for i in 0..3 {
            for j in 0..4 {
                let mut s = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
                if j == 3 {
                    s += a[i][3];
                }
                out[i][j] = s;
            }
        }
        Transform4x3 { rows: out }
    }

    /// The axis-aligned box enclosing the transformed box `[min, max]` (centre and
    /// extent through the absolute linear part, Arvo's method). Returns `(min, max)`.
    #[must_use]
    #[inline]
    pub fn transform_aabb(&self, min: Vec3, max: Vec3) -> (Vec3, Vec3) {
        let c = (min + max) * 0.5;
        let e = (max - min) * 0.5;
        let r = &self.rows;
        let tc = self.transform_point(c);
        let te = Vec3::new(
            r[0][0].abs() * e.x + r[0][1].abs() * e.y + r[0][2].abs() * e.z,
            r[1][0].abs() * e.x + r[1][1].abs() * e.y + r[1][2].abs() * e.z,
            r[2][0].abs() * e.x + r[2][1].abs() * e.y + r[2][2].abs() * e.z,
        );
        (tc - te, tc + te)
    }
}

/// The object flag: ignore the view's global LOD scale (bit 16 of [`QueryObject::lod`]).
pub const OBJECT_FLAG_IGNORE_GLOBAL_LOD_SCALE: u32 = 1 << 16;

/// One placed object (the talk's DrawableObject), 64 bytes, stored once per tile.
/// WGSL: `StaticsceneQueryObject`.
///
/// | bytes | field | meaning |
/// | --- | --- | --- |
/// | 0-47 | `object_to_snapped` | object space to the object's snapped frame: rotation and scale, and the sub-metre remainder of the position |
/// | 48-59 | `snapped` | the object's position on the 1 m integer grid, `i32` x, y, z |
/// | 60-61 | `lod` bits 0-15 | LOD scale, f16 (> 0): multiplies every LOD distance of the object |
/// | 62-63 | `lod` bits 16-31 | flags: bit 16 [`OBJECT_FLAG_IGNORE_GLOBAL_LOD_SCALE`], others zero |
///
/// World position of an object-space point `p`: `snapped + object_to_snapped(p)`, so with
/// the view's snapped origin `o` the renderer's floating-space position is
/// `(snapped - o) + object_to_snapped(p)`: the integer difference is exact in f32 up to
/// 2^24 m, and the f32 remainder stays small, so precision does not depend on the
/// distance from the world origin.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct QueryObject {
    /// Object to snapped frame.
    pub object_to_snapped: Transform4x3,
    /// Snapped integer position, metres.
    pub snapped: [i32; 3],
    /// LOD scale (f16, bits 0-15) and flags (bits 16-31).
    pub lod: u32,
}

const _: () = assert!(size_of::<QueryObject>() == 64);

/// The largest |coordinate| of an object position, metres (the snapped grid is `i32`).
pub const WORLD_MAX: f64 = 2_000_000_000.0;

impl QueryObject {
    /// An object at world `position` (metres, f64) with linear part `linear` (rotation and
    /// scale, object to world). The position is snapped to the nearest integer metre and
    /// the remainder goes into the matrix. `lod_scale` (> 0, finite, at most
    /// [`f16::MAX`]) is stored as f16 rounded to nearest.
    pub fn from_world(
        position: DVec3,
        linear: Mat3,
        lod_scale: f32,
        ignore_global_lod_scale: bool,
    ) -> Result<QueryObject, Error> {
        for c in position.to_array() {
            if !c.is_finite() || c.abs() > WORLD_MAX {
                return Err(Error::FloatOutOfRange {
                    field: Field::Position,
                    value: c,
                    max: WORLD_MAX,
                });
            }
        }
        let snapped = snap(position);
        let rem = (position - snapped.as_dvec3()).as_vec3();
        let m = Transform4x3::from_mat3_translation(linear, rem);
        if !m.is_finite() {
            return Err(Error::FloatOutOfRange {
                field: Field::Transform,
                value: f64::NAN,
                max: f64::from(f32::MAX),
            });
        }
        Self::new(m, snapped, lod_scale, ignore_global_lod_scale)
    }

    /// From its parts; fails on a non-finite matrix or a LOD scale that is not a positive
    /// finite f16.
    pub fn new(
        object_to_snapped: Transform4x3,
        snapped: IVec3,
        lod_scale: f32,
        ignore_global_lod_scale: bool,
    ) -> Result<QueryObject, Error> {
        if !object_to_snapped.is_finite() {
            return Err(Error::FloatOutOfRange {
                field: Field::Transform,
                value: f64::NAN,
                max: f64::from(f32::MAX),
            });
        }
        let h = f16::from_f32(lod_scale);
        if lod_scale.is_nan() || lod_scale <= 0.0 || !h.is_finite() || h.to_f32() <= 0.0 {
            return Err(Error::FloatOutOfRange {
                field: Field::LodScale,
                value: f64::from(lod_scale),
                max: f16::MAX.to_f64(),
            });
        }
        let flags = if ignore_global_lod_scale {
            OBJECT_FLAG_IGNORE_GLOBAL_LOD_SCALE
        } else {
            0
        };
        Ok(QueryObject {
            object_to_snapped,
            snapped: snapped.to_array(),
            lod: u32::from(h.to_bits()) | flags,
        })
    }

    /// The object's LOD scale.
    #[must_use]
    #[inline]
    pub fn lod_scale(&self) -> f32 {
        half_to_f32_branchless(self.lod as u16)
    }

    /// Whether the object ignores the view's global LOD scale.
    #[must_use]
    #[inline]
    pub fn ignores_global_lod_scale(&self) -> bool {
        self.lod & OBJECT_FLAG_IGNORE_GLOBAL_LOD_SCALE != 0
    }

    /// The snapped position.
    #[must_use]
    #[inline]
    pub fn snapped(&self) -> IVec3 {
        IVec3::from_array(self.snapped)
    }

    /// Object space to the floating space of a view whose snapped origin is `origin`.
    #[must_use]
    #[inline]
    pub fn object_to_floating(&self, origin: IVec3) -> Transform4x3 {
        let d = floating_offset(self.snapped(), origin);
        let t = self.object_to_snapped.translation();
        self.object_to_snapped.with_translation(t + d)
    }
}

/// `snapped - origin` as f32 (exact for differences up to 2^24 m).
#[inline]
pub(crate) fn floating_offset(snapped: IVec3, origin: IVec3) -> Vec3 {
    Vec3::new(
        (i64::from(snapped.x) - i64::from(origin.x)) as f32,
        (i64::from(snapped.y) - i64::from(origin.y)) as f32,
        (i64::from(snapped.z) - i64::from(origin.z)) as f32,
    )
}

/// Rounds a world position to the 1 m grid (`|c| <= WORLD_MAX` assumed).
pub(crate) fn snap(p: DVec3) -> IVec3 {
    IVec3::new(
        crate::math::round64(p.x) as i32,
        crate::math::round64(p.y) as i32,
        crate::math::round64(p.z) as i32,
    )
}

/// One DrawableSetup as the query sees it, 32 bytes, stored once per tile.
/// WGSL: `StaticsceneQuerySetup`.
///
/// | bytes | field | meaning |
/// | --- | --- | --- |
/// | 0-11 | `bounds_min` | accurate vertex bounds of the geometry, minimum, in the setup's local (mesh) space, f32 |
/// | 12-23 | `bounds_max` | maximum |
/// | 24-31 | `handle` | the renderer's handle for the DrawableSetup (the talk's CPU pointer), opaque; WGSL `vec2<u32>` (low, high) |
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct QuerySetup {
    /// Local bounds minimum.
    pub bounds_min: [f32; 3],
    /// Local bounds maximum.
    pub bounds_max: [f32; 3],
    /// Renderer handle.
    pub handle: u64,
}

const _: () = assert!(size_of::<QuerySetup>() == 32);

impl QuerySetup {
    /// A setup with local bounds `[min, max]`; fails if they are not finite or inverted.
    pub fn new(min: Vec3, max: Vec3, handle: u64) -> Result<QuerySetup, Error> {
        check_aabb(min, max, Field::Bounds)?;
        Ok(QuerySetup {
            bounds_min: min.to_array(),
            bounds_max: max.to_array(),
            handle,
        })
    }

    /// Local bounds minimum.
    #[must_use]
    #[inline]
    pub fn min(&self) -> Vec3 {
        Vec3::from_array(self.bounds_min)
    }

    /// Local bounds maximum.
    #[must_use]
    #[inline]
    pub fn max(&self) -> Vec3 {
        Vec3::from_array(self.bounds_max)
    }
}

/// Checks a float box: finite and not inverted.
pub(crate) fn check_aabb(min: Vec3, max: Vec3, field: Field) -> Result<(), Error> {
    for v in min.to_array().into_iter().chain(max.to_array()) {
        if !v.is_finite() {
            return Err(Error::FloatOutOfRange {
                field,
                value: f64::from(v),
                max: f64::from(f32::MAX),
            });
        }
    }
    for i in 0..3 {
        if min[i] > max[i] {
            return Err(Error::Inverted {
                field,
                min: f64::from(min[i]),
                max: f64::from(max[i]),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn object_floating_origin() {
        let p = DVec3::new(1_000_000.3, -5.75, 999_999.49);
        let o = QueryObject::from_world(p, Mat3::IDENTITY, 1.5, true).unwrap();
        assert_eq!(o.snapped, [1_000_000, -6, 999_999]);
        assert!(o.ignores_global_lod_scale());
        assert_eq!(o.lod_scale(), 1.5);
        let f = o.object_to_floating(IVec3::new(1_000_010, 0, 1_000_000));
        let t = f.translation();
        assert!((f64::from(t.x) - (-9.7)).abs() < 1e-6);
        assert!((f64::from(t.y) - (-5.75)).abs() < 1e-6);
        assert!((f64::from(t.z) - (-0.51)).abs() < 1e-6);
        assert!(QueryObject::from_world(p, Mat3::IDENTITY, 0.0, false).is_err());
        assert!(QueryObject::from_world(DVec3::splat(3e9), Mat3::IDENTITY, 1.0, false).is_err());
    }

    #[test]
    fn transform_composition_matches_glam() {
        let a = Affine3A::from_scale_rotation_translation(
            Vec3::new(1.0, 2.0, 0.5),
            glam::Quat::from_rotation_y(0.7),
            Vec3::new(3.0, -1.0, 2.0),
        );
        let b = Affine3A::from_rotation_translation(
            glam::Quat::from_rotation_x(-0.3),
            Vec3::new(0.5, 0.25, -4.0),
        );
        let m = Transform4x3::from_affine(&a).mul(&Transform4x3::from_affine(&b));
        let p = Vec3::new(0.3, -0.7, 1.9);
        let want = (a * b).transform_point3(p);
        assert!((m.transform_point(p) - want).abs().max_element() < 1e-5);
        let back = Transform4x3::from_affine(&m.to_affine());
        assert_eq!(back, m);
    }
}
