//! Normals from depth without derivatives.
//!
//! Far Cry 5's compute passes have no `ddx`/`ddy`, so the water normal comes from the
//! mini G-buffer's depth: "position from depth", with a sampling radius that grows as the
//! camera nears the surface (first-person cameras get close), blended with the low-res
//! mesh normal "to remove any of the discontinuities" (seed 003).
//!
//! Central differences smear normals across depth edges. The accurate reconstructions pick,
//! per axis, the neighbour that continues the centre's surface:
//!
//! - [`Taps::Five`] (Turánszki): of the left and right neighbours take the one with the
//!   smaller depth jump; same for up and down.
//! - [`Taps::Nine`] (atyuwen): two neighbours per side; take the side whose linear
//!   extrapolation predicts the centre best. With a perspective camera a plane's `1 / z`,
//!   not `z`, is linear in screen space, so the extrapolation is done in `1 / z`.
//!
//! A one-sided difference is the tangent half a sample away, off by the curvature over
//! that half step (1.7 degrees on a 1 m sphere 3 m away at 96 pixels across). So where
//! both sides continue the surface about equally well (the worse error within
//! [`SMOOTH_RATIO`] times the better plus [`SMOOTH_EPSILON`]), the central difference is
//! used instead; the one-sided choice only acts at discontinuities.
//!
//! # Conventions
//!
//! The depth buffer holds *linear view depth*: metres along the view axis, positive, `+inf`
//! or `<= 0` for "no water". View space is right-handed: +x right, +y up, the camera looks
//! down -z. Pixel `(x, y)` has its centre at `(x + 0.5, y + 0.5)` with +y down the image.
//! Normals are view-space unit vectors facing the camera.

use glam::{UVec2, Vec2, Vec3};

use crate::math;

/// Both sides of an axis count as continuing the surface (and the central difference is
/// used) when the worse side's error is at most this times the better side's ...
pub const SMOOTH_RATIO: f32 = 2.0;
/// ... plus this fraction of the depth (5 taps; of 1/depth for 9 taps).
pub const SMOOTH_EPSILON: f32 = 1e-4;

/// A pinhole camera for view-space positions from depth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DepthCamera {
    /// Image size in pixels.
    pub size: UVec2,
    /// `tan(fov / 2)` horizontally and vertically (the mini G-buffer's wider FOV).
    pub tan_half_fov: Vec2,
}

impl DepthCamera {
    /// View-space position of pixel `p` (integer pixel, centre sampled) at linear depth
    /// `depth`.
    #[must_use]
    pub fn view_position(&self, p: UVec2, depth: f32) -> Vec3 {
        self.view_position_at(p.as_vec2() + 0.5, depth)
    }

    /// View-space position of the image point `pixel` (pixel units, +y down) at `depth`.
    #[must_use]
    pub fn view_position_at(&self, pixel: Vec2, depth: f32) -> Vec3 {
        let ndc = Vec2::new(
            pixel.x / self.size.x as f32 * 2.0 - 1.0,
            1.0 - pixel.y / self.size.y as f32 * 2.0,
        );
        Vec3::new(
            ndc.x * self.tan_half_fov.x * depth,
            ndc.y * self.tan_half_fov.y * depth,
            -depth,
        )
    }
}

/// Which reconstruction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Taps {
    /// Centre plus one neighbour per side (smaller depth jump wins).
    Five,
    /// Centre plus two neighbours per side (better `1/z` extrapolation wins).
    Nine,
}

/// The sampling radius rule: `radius = clamp(round(radius_at_1m / depth), 1, max_radius)`
/// pixels, so it grows as the camera nears the water.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RadiusRule {
    /// Radius in pixels at 1 m depth.
    pub radius_at_1m: f32,
    /// Largest radius in pixels.
    pub max_radius: u32,
}

impl Default for RadiusRule {
    /// 2 pixels at 1 m (1 pixel beyond 2 m... 4 pixels at 0.5 m), at most 4.
    fn default() -> Self {
        Self {
            radius_at_1m: 2.0,
            max_radius: 4,
        }
    }
}

impl RadiusRule {
    /// The radius for a pixel at `depth` metres.
    #[must_use]
    pub fn radius(&self, depth: f32) -> u32 {
        let r = self.radius_at_1m / depth;
        let max = self.max_radius.max(1);
        if !(r > 1.0) {
            return 1;
        }
        let r = math::floor(r + 0.5);
        if r >= max as f32 { max } else { r as u32 }
    }
}

/// A depth buffer to reconstruct from.
#[derive(Clone, Copy, Debug)]
pub struct DepthView<'a> {
    /// Linear view depth, row-major, `camera.size.x * camera.size.y` values.
    pub depth: &'a [f32],
    /// The camera that rendered it.
    pub camera: DepthCamera,
}

fn valid(d: f32) -> bool {
    d > 0.0 && d.is_finite()
}

impl DepthView<'_> {
    fn at(&self, x: i64, y: i64) -> f32 {
        let s = self.camera.size;
        if x < 0 || y < 0 || x >= i64::from(s.x) || y >= i64::from(s.y) {
            return f32::INFINITY;
        }
        self.depth
            .get(y as usize * s.x as usize + x as usize)
            .copied()
            .unwrap_or(f32::INFINITY)
    }

    fn pos(&self, x: i64, y: i64, d: f32) -> Vec3 {
        self.camera
            .view_position_at(Vec2::new(x as f32 + 0.5, y as f32 + 0.5), d)
    }

    /// The view-space tangent along one axis at pixel `(x, y)` with step `(sx, sy)`:
    /// `centre - before` or `after - centre`, whichever side continues the surface.
    fn tangent(&self, x: i64, y: i64, c: f32, sx: i64, sy: i64, taps: Taps) -> Option<Vec3> {
        let pc = self.pos(x, y, c);
        let (b1, a1) = (self.at(x - sx, y - sy), self.at(x + sx, y + sy));
        // How badly each side continues the centre's surface (infinite: no depth there).
        let (eb, ea) = match taps {
            Taps::Five => {
                let jump = |n: f32| {
                    if valid(n) {
                        (n - c).abs()
                    } else {
                        f32::INFINITY
                    }
                };
                (jump(b1), jump(a1))
            }
            Taps::Nine => {
                let (b2, a2) = (
                    self.at(x - 2 * sx, y - 2 * sy),
                    self.at(x + 2 * sx, y + 2 * sy),
                );
                // Error of predicting 1/c from each side's two taps, linearly in 1/z.
                let err = |n1: f32, n2: f32| {
                    if valid(n1) && valid(n2) {
                        (2.0 / n1 - 1.0 / n2 - 1.0 / c).abs()
                    } else if valid(n1) {
                        // One tap only: fall back to the jump, in 1/z.
                        (1.0 / n1 - 1.0 / c).abs() * 2.0
                    } else {
                        f32::INFINITY
                    }
                };
                (err(b1, b2), err(a1, a2))
            }
        };
        if eb.is_infinite() && ea.is_infinite() {
            return None;
        }
        let before = || self.pos(x - sx, y - sy, b1);
        let after = || self.pos(x + sx, y + sy, a1);
        // Both sides continue the surface about equally well (a smooth surface): the
        // central difference, which is exact to second order. Otherwise the better side.
        let (lo, hi) = if eb < ea { (eb, ea) } else { (ea, eb) };
        let tol = match taps {
            Taps::Five => SMOOTH_EPSILON * c,
            Taps::Nine => SMOOTH_EPSILON / c,
        };
        if hi <= SMOOTH_RATIO * lo + tol {
            return Some((after() - before()) * 0.5);
        }
        Some(if eb < ea { pc - before() } else { after() - pc })
    }

    /// The reconstructed view-space normal at pixel `p`, sampling `radius` pixels away, or
    /// `None` where the pixel or both neighbours of an axis have no depth.
    #[must_use]
    pub fn normal(&self, p: UVec2, radius: u32, taps: Taps) -> Option<Vec3> {
        let (x, y) = (i64::from(p.x), i64::from(p.y));
        let c = self.at(x, y);
        if !valid(c) {
            return None;
        }
        let r = i64::from(radius.max(1));
        let tx = self.tangent(x, y, c, r, 0, taps)?;
        // +y in pixels is down the image; the tangent along it points down in view space.
        let ty = self.tangent(x, y, c, 0, r, taps)?;
        let n = ty.cross(tx);
        let n = n.normalize_or_zero();
        if n == Vec3::ZERO {
            return None;
        }
        // Face the camera: the view vector to the camera is -position.
        let to_camera = -self.pos(x, y, c);
        Some(if n.dot(to_camera) < 0.0 { -n } else { n })
    }

    /// [`DepthView::normal`] with the radius from `rule` at this pixel's depth.
    #[must_use]
    pub fn normal_auto(&self, p: UVec2, rule: &RadiusRule, taps: Taps) -> Option<Vec3> {
        let d = self.at(i64::from(p.x), i64::from(p.y));
        self.normal(p, rule.radius(d), taps)
    }

    /// Plain central differences (the baseline that smears across edges).
    #[must_use]
    pub fn normal_central(&self, p: UVec2) -> Option<Vec3> {
        let (x, y) = (i64::from(p.x), i64::from(p.y));
        let (l, r, u, d) = (
            self.at(x - 1, y),
            self.at(x + 1, y),
            self.at(x, y - 1),
            self.at(x, y + 1),
        );
        if !(valid(l) && valid(r) && valid(u) && valid(d)) {
            return None;
        }
        let tx = self.pos(x + 1, y, r) - self.pos(x - 1, y, l);
        let ty = self.pos(x, y + 1, d) - self.pos(x, y - 1, u);
        let n = ty.cross(tx).normalize_or_zero();
        let to_camera = -self.pos(x, y, self.at(x, y));
        (n != Vec3::ZERO).then(|| if n.dot(to_camera) < 0.0 { -n } else { n })
    }
}

/// Blends the high-frequency normal from depth with the mesh normal: `normalize(mix(mesh,
/// detail, detail_weight))`, the mesh normal where the result would vanish.
#[must_use]
pub fn blend_with_mesh(mesh: Vec3, detail: Vec3, detail_weight: f32) -> Vec3 {
    let w = math::saturate(detail_weight);
    let n = (mesh * (1.0 - w) + detail * w).normalize_or_zero();
    if n == Vec3::ZERO {
        mesh.normalize_or_zero()
    } else {
        n
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radius_grows_near_the_camera() {
        let r = RadiusRule::default();
        assert_eq!(r.radius(10.0), 1);
        assert_eq!(r.radius(1.0), 2);
        assert_eq!(r.radius(0.5), 4);
        assert_eq!(r.radius(0.01), 4);
        assert_eq!(r.radius(f32::NAN), 1);
        assert_eq!(r.radius(-1.0), 1);
    }

    #[test]
    fn blend_falls_back_to_the_mesh_normal() {
        assert_eq!(blend_with_mesh(Vec3::Z, -Vec3::Z, 0.5), Vec3::Z);
        assert_eq!(blend_with_mesh(Vec3::Z, Vec3::X, 0.0), Vec3::Z);
    }
}
