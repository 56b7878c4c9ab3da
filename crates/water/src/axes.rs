//! The one place where `water`'s world axes meet the rest of the workspace.
//!
//! `water` works in metres, right-handed, **+Z up**: a horizontal position is `(x, y)` (what
//! [`crate::world::WaterWorld::query`] takes), a height is `z`, flow is along +x and +y. The
//! renderer (`gpu`, and `deferred`'s cascades, `staticscene`'s demo city) works in metres,
//! right-handed, **+Y up**. The conversion is a rotation of -90° about +x:
//!
//! | water (+Z up) | +Y up |
//! | --- | --- |
//! | `+x` (east) | `+x` |
//! | `+y` (north, horizontal) | `-z` |
//! | `+z` (up) | `+y` |
//!
//! so `(x, y, z)` in water is `(x, z, -y)` in +Y up, and `(x, y, z)` in +Y up is
//! `(x, -z, y)` in water. Being a rotation (determinant +1) it keeps right-handed frames
//! right-handed and cross products (normals, winding) meaningful on both sides; the
//! components only move and change sign, so the conversion is exact in f32.
//!
//! Convert at the boundary, once: positions and directions going from the renderer into a
//! water query or bake with [`z_up_from_y_up`] (or [`horizontal_from_y_up`] for the 2D
//! query position), results coming back with [`y_up_from_z_up`]. Matrices:
//! [`Y_UP_FROM_Z_UP`], [`Z_UP_FROM_Y_UP`] (for a transform `T` in water's axes, the +Y-up
//! transform is `Y_UP_FROM_Z_UP * T * Z_UP_FROM_Y_UP`).
//!
//! ```
//! use water::axes::{horizontal_from_y_up, y_up_from_z_up, z_up_from_y_up};
//! use water::glam::{Vec2, Vec3};
//!
//! // A river point 30 m up at water's (10, 20) is (10, 30, -20) for the renderer.
//! assert_eq!(y_up_from_z_up(Vec3::new(10.0, 20.0, 30.0)), Vec3::new(10.0, 30.0, -20.0));
//! assert_eq!(z_up_from_y_up(Vec3::new(10.0, 30.0, -20.0)), Vec3::new(10.0, 20.0, 30.0));
//! // A camera at (10, 5, -20) in +Y up queries the water at (10, 20).
//! assert_eq!(horizontal_from_y_up(Vec3::new(10.0, 5.0, -20.0)), Vec2::new(10.0, 20.0));
//! ```

use glam::{Mat3, Vec2, Vec3};

/// Water's +Z-up axes to +Y-up axes: columns are the images of water's `x`, `y`, `z`.
pub const Y_UP_FROM_Z_UP: Mat3 = Mat3::from_cols(Vec3::X, Vec3::NEG_Z, Vec3::Y);

/// +Y-up axes to water's +Z-up axes, the inverse (and transpose) of [`Y_UP_FROM_Z_UP`].
pub const Z_UP_FROM_Y_UP: Mat3 = Mat3::from_cols(Vec3::X, Vec3::Z, Vec3::NEG_Y);

/// A water (+Z up) position or direction in +Y-up axes: `(x, y, z) -> (x, z, -y)`.
#[must_use]
#[inline]
pub fn y_up_from_z_up(v: Vec3) -> Vec3 {
    Vec3::new(v.x, v.z, -v.y)
}

/// A +Y-up position or direction in water's +Z-up axes: `(x, y, z) -> (x, -z, y)`.
#[must_use]
#[inline]
pub fn z_up_from_y_up(v: Vec3) -> Vec3 {
    Vec3::new(v.x, -v.z, v.y)
}

/// The horizontal water position (what [`crate::world::WaterWorld::query`] takes) of a +Y-up
/// point: `(x, y, z) -> (x, -z)`; the height is dropped.
#[must_use]
#[inline]
pub fn horizontal_from_y_up(v: Vec3) -> Vec2 {
    Vec2::new(v.x, -v.z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The reference: the table in the module docs, written out axis by axis.
    fn table_y_up(v: Vec3) -> Vec3 {
        let east = Vec3::X;
        let up = Vec3::Y;
        let north = -Vec3::Z;
        east * v.x + north * v.y + up * v.z
    }

    #[test]
    fn axes_map_as_the_table_says() {
        assert_eq!(y_up_from_z_up(Vec3::X), Vec3::X);
        assert_eq!(y_up_from_z_up(Vec3::Y), Vec3::NEG_Z);
        assert_eq!(y_up_from_z_up(Vec3::Z), Vec3::Y);
        assert_eq!(Y_UP_FROM_Z_UP * Vec3::Z, Vec3::Y);
        assert_eq!(Z_UP_FROM_Y_UP * Vec3::Y, Vec3::Z);
    }

    #[test]
    fn matrices_are_rotations_and_inverses() {
        assert_eq!(Y_UP_FROM_Z_UP.determinant(), 1.0);
        assert_eq!(Z_UP_FROM_Y_UP.determinant(), 1.0);
        assert_eq!(Y_UP_FROM_Z_UP * Z_UP_FROM_Y_UP, Mat3::IDENTITY);
        assert_eq!(Z_UP_FROM_Y_UP * Y_UP_FROM_Z_UP, Mat3::IDENTITY);
        assert_eq!(Y_UP_FROM_Z_UP.transpose(), Z_UP_FROM_Y_UP);
        // A rotation of -90 degrees about +x.
        let r = Mat3::from_rotation_x(-core::f32::consts::FRAC_PI_2);
        assert!(r.abs_diff_eq(Y_UP_FROM_Z_UP, 1e-7));
    }

    fn finite() -> impl Strategy<Value = f32> {
        -1e30f32..1e30
    }

    proptest! {
        #[test]
        fn conversions_are_exact_inverses(x in finite(), y in finite(), z in finite()) {
            let v = Vec3::new(x, y, z);
            prop_assert_eq!(z_up_from_y_up(y_up_from_z_up(v)), v);
            prop_assert_eq!(y_up_from_z_up(z_up_from_y_up(v)), v);
            prop_assert_eq!(y_up_from_z_up(v), table_y_up(v));
            prop_assert_eq!(Y_UP_FROM_Z_UP * v, y_up_from_z_up(v));
            prop_assert_eq!(Z_UP_FROM_Y_UP * v, z_up_from_y_up(v));
            let h = horizontal_from_y_up(y_up_from_z_up(v));
            prop_assert_eq!(h, Vec2::new(x, y));
        }

        #[test]
        fn handedness_is_kept(
            a in (-1e3f32..1e3, -1e3f32..1e3, -1e3f32..1e3),
            b in (-1e3f32..1e3, -1e3f32..1e3, -1e3f32..1e3),
        ) {
            // A rotation commutes with the cross product; a reflection would flip its sign.
            let (a, b) = (Vec3::new(a.0, a.1, a.2), Vec3::new(b.0, b.1, b.2));
            let lhs = y_up_from_z_up(a.cross(b));
            let rhs = y_up_from_z_up(a).cross(y_up_from_z_up(b));
            prop_assert!((lhs - rhs).abs().max_element() <= 1e-6 * (1.0 + lhs.abs().max_element()));
            let lhs = z_up_from_y_up(a.cross(b));
            let rhs = z_up_from_y_up(a).cross(z_up_from_y_up(b));
            prop_assert!((lhs - rhs).abs().max_element() <= 1e-6 * (1.0 + lhs.abs().max_element()));
        }
    }
}
