//! The ray-triangle fallback of seed 004: where neither hardware barycentrics nor the clip
//! positions are at hand, trace the pixel's camera ray against the one triangle the vis
//! buffer names and take the hit's barycentrics.
//!
//! Done watertight (Woop, Benthin and Wald, "Watertight Ray/Triangle Intersection", JCGT
//! 2(1), 2013) rather than with the seed's Möller–Trumbore: a ray through an edge shared by
//! two triangles hits at least one of them, so a resolve never finds a crack between
//! neighbours. [`intersect_moller_trumbore`] is kept as the baseline (benches, and a test
//! showing its cracks).
//!
//! Positions should be camera-relative (origin at or near the eye), as for any f32 method.

use glam::{Mat4, Vec2, Vec3};

/// A ray hit: distance along the ray and barycentric weights of the three vertices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    /// Hit distance in units of the ray direction's length (`origin + t * dir`), `t >= 0`.
    pub t: f32,
    /// Weights of vertices 0, 1, 2 at the hit; each in `[0, 1]`, summing to 1.
    pub barycentrics: Vec3,
}

/// Watertight ray-triangle intersection, both faces. `None` for a miss, a hit behind the
/// origin, a degenerate triangle, a zero direction, or non-finite input.
#[must_use]
#[inline]
pub fn intersect_watertight(origin: Vec3, dir: Vec3, v: [Vec3; 3]) -> Option<RayHit> {
    if !(origin.is_finite() && dir.is_finite() && v.iter().all(|p| p.is_finite())) {
        return None;
    }
    // The dimension where the direction is largest becomes z; keep the winding by swapping
    // x and y when that component is negative.
    let a = dir.abs();
    let kz = if a.x > a.y {
        if a.x > a.z { 0 } else { 2 }
    } else if a.y > a.z {
        1
    } else {
        2
    };
    if dir[kz] == 0.0 {
        return None;
    }
    let (mut kx, mut ky) = ((kz + 1) % 3, (kz + 2) % 3);
    if dir[kz] < 0.0 {
        core::mem::swap(&mut kx, &mut ky);
    }
    // Shear so the ray runs along +z.
    let sz = 1.0 / dir[kz];
    let sx = dir[kx] * sz;
    let sy = dir[ky] * sz;
    let rel = v.map(|p| p - origin);
    let sheared = rel.map(|p| Vec2::new(p[kx] - sx * p[kz], p[ky] - sy * p[kz]));
    let (pa, pb, pc) = (sheared[0], sheared[1], sheared[2]);
    // Scaled edge functions; exact zeros (ray through an edge or vertex) are recomputed in
    // f64 so the sign is right and neighbouring triangles agree.
    let mut u = pc.x * pb.y - pc.y * pb.x;
    let mut w_v = pa.x * pc.y - pa.y * pc.x;
    let mut w = pb.x * pa.y - pb.y * pa.x;
    if u == 0.0 || w_v == 0.0 || w == 0.0 {
        let d = |p: Vec2| (p.x as f64, p.y as f64);
        let ((ax, ay), (bx, by), (cx, cy)) = (d(pa), d(pb), d(pc));
        u = (cx * by - cy * bx) as f32;
        w_v = (ax * cy - ay * cx) as f32;
        w = (bx * ay - by * ax) as f32;
    }
    if (u < 0.0 || w_v < 0.0 || w < 0.0) && (u > 0.0 || w_v > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + w_v + w;
    if det == 0.0 {
        return None;
    }
    let z = Vec3::new(sz * rel[0][kz], sz * rel[1][kz], sz * rel[2][kz]);
    let t_scaled = u * z.x + w_v * z.y + w * z.z;
    // t >= 0 without dividing: same sign as det (or zero).
    if (det > 0.0 && t_scaled < 0.0) || (det < 0.0 && t_scaled > 0.0) {
        return None;
    }
    let inv = 1.0 / det;
    let hit = RayHit {
        t: t_scaled * inv,
        barycentrics: Vec3::new(u * inv, w_v * inv, w * inv),
    };
    (hit.t.is_finite() && hit.barycentrics.is_finite()).then_some(hit)
}

/// Möller–Trumbore as printed in seed 004 (`|det| < 1e-6` rejected as parallel), both
/// faces: the baseline. Not watertight: rays through a shared edge can miss both
/// triangles.
#[must_use]
#[inline]
pub fn intersect_moller_trumbore(origin: Vec3, dir: Vec3, v: [Vec3; 3]) -> Option<RayHit> {
    let e1 = v[1] - v[0];
    let e2 = v[2] - v[0];
    let p = dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-6 || det.is_nan() {
        return None;
    }
    let inv = 1.0 / det;
    let tv = origin - v[0];
    let b1 = tv.dot(p) * inv;
    if !(0.0..=1.0).contains(&b1) {
        return None;
    }
    let q = tv.cross(e1);
    let b2 = dir.dot(q) * inv;
    if !(b2 >= 0.0 && b1 + b2 <= 1.0) {
        return None;
    }
    let t = e2.dot(q) * inv;
    (t >= 0.0 && t.is_finite()).then_some(RayHit {
        t,
        barycentrics: Vec3::new(1.0 - b1 - b2, b1, b2),
    })
}

/// The direction of the perspective camera ray from `eye` through a framebuffer position
/// (pixel conventions of [`crate::bary`]): towards the point `inv_view_proj` maps the pixel
/// at NDC depth 0.5 to, which is finite for standard, reversed and infinite WebGPU
/// perspective projections. Unnormalised. With camera-relative positions `eye` is zero.
/// `None` when the result is not finite or zero.
#[must_use]
#[inline]
pub fn pixel_ray_direction(
    inv_view_proj: Mat4,
    eye: Vec3,
    pixel: Vec2,
    viewport: Vec2,
) -> Option<Vec3> {
    let ndc = Vec2::new(
        2.0 * pixel.x / viewport.x - 1.0,
        1.0 - 2.0 * pixel.y / viewport.y,
    );
    let p = inv_view_proj * ndc.extend(0.5).extend(1.0);
    if p.w == 0.0 {
        return None;
    }
    let d = p.truncate() / p.w - eye;
    (d.is_finite() && d != Vec3::ZERO).then_some(d)
}
