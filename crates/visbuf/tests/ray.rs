//! The watertight ray-triangle fallback: no cracks on shared edges, barycentrics against
//! f64 and against the analytic clip-space method.

use glam::{DVec3, Mat4, Vec2, Vec3};
use testkit::Rng;
use visbuf::bary::barycentrics;
use visbuf::ray::{intersect_moller_trumbore, intersect_watertight, pixel_ray_direction};

/// f64 reference: ray-plane intersection, then barycentrics by areas (no inside test).
fn reference(o: DVec3, d: DVec3, v: [DVec3; 3]) -> (f64, DVec3) {
    let n = (v[1] - v[0]).cross(v[2] - v[0]);
    let t = (v[0] - o).dot(n) / d.dot(n);
    let p = o + d * t;
    let a = (v[1] - p).cross(v[2] - p).dot(n) / n.length_squared();
    let b = (v[2] - p).cross(v[0] - p).dot(n) / n.length_squared();
    (t, DVec3::new(a, b, 1.0 - a - b))
}

#[test]
fn hits_agree_with_f64() {
    let mut rng = Rng::new(11);
    let mut r = move || f64::from(rng.f32()) * 2.0 - 1.0;
    let mut worst = 0.0f64;
    for _ in 0..20_000 {
        let v = [0, 1, 2].map(|_| DVec3::new(r() * 3.0, r() * 3.0, -5.0 + r()));
        let target = v[0] * 0.3 + v[1] * 0.3 + v[2] * 0.4 + DVec3::new(r(), r(), 0.0) * 0.5;
        let d = target;
        let got = intersect_watertight(Vec3::ZERO, d.as_vec3(), v.map(|p| p.as_vec3()));
        let (t, want) = reference(
            DVec3::ZERO,
            d.as_vec3().as_dvec3(),
            v.map(|p| p.as_vec3().as_dvec3()),
        );
        let inside = want.min_element() > 1e-4;
        let outside = want.min_element() < -1e-4;
        match got {
            Some(h) => {
                assert!(!outside, "hit outside: {want:?}");
                assert!((h.barycentrics.element_sum() - 1.0).abs() < 1e-5);
                assert!(h.barycentrics.min_element() >= 0.0);
                worst = worst.max((h.barycentrics.as_dvec3() - want).abs().max_element());
                assert!((h.t as f64 - t).abs() < 1e-4 * t.abs());
            }
            None => assert!(!inside, "missed inside: {want:?}"),
        }
    }
    assert!(worst < 1e-4, "{worst}");
}

/// Rays aimed exactly at points of an edge shared by two triangles: the watertight test
/// hits at least one every time, Möller–Trumbore misses both on some.
#[test]
fn shared_edges_never_crack() {
    let mut rng = Rng::new(5);
    let mut r = move || rng.f32();
    let (mut mt_cracks, mut rays) = (0, 0);
    for _ in 0..2000 {
        let a = Vec3::new(r() * 4.0 - 2.0, r() * 4.0 - 2.0, -3.0 - r() * 5.0);
        let b = Vec3::new(r() * 4.0 - 2.0, r() * 4.0 - 2.0, -3.0 - r() * 5.0);
        let c = Vec3::new(r() * 4.0 - 2.0, r() * 4.0 - 2.0, -3.0 - r() * 5.0);
        // d on the other side of edge ab from c.
        let d = a + b - c;
        let (t1, t2) = ([a, b, c], [b, a, d]);
        for _ in 0..20 {
            let f = r();
            let dir = a + (b - a) * f;
            rays += 1;
            let w = intersect_watertight(Vec3::ZERO, dir, t1).is_some()
                || intersect_watertight(Vec3::ZERO, dir, t2).is_some();
            assert!(w, "crack at {dir:?}");
            let m = intersect_moller_trumbore(Vec3::ZERO, dir, t1).is_some()
                || intersect_moller_trumbore(Vec3::ZERO, dir, t2).is_some();
            mt_cracks += usize::from(!m);
        }
    }
    eprintln!("Möller–Trumbore missed both triangles on {mt_cracks} of {rays} shared-edge rays");
    assert!(
        mt_cracks > 0,
        "the baseline was expected to crack somewhere"
    );
}

#[test]
fn ray_barycentrics_equal_the_analytic_clip_space_ones() {
    let proj = Mat4::perspective_rh(1.0, 16.0 / 9.0, 0.1, 100.0);
    let view = Mat4::look_at_rh(Vec3::ZERO, Vec3::new(0.2, -0.1, -1.0), Vec3::Y);
    let vp_m = proj * view;
    let inv = vp_m.inverse();
    let vp = Vec2::new(1920.0, 1080.0);
    let tri = [
        Vec3::new(-1.0, -0.5, -4.0),
        Vec3::new(1.5, -0.2, -5.0),
        Vec3::new(0.2, 1.0, -4.5),
    ];
    let clip = tri.map(|p| vp_m * p.extend(1.0));
    let mut hits = 0;
    for py in (0..1080).step_by(37) {
        for px in (0..1920).step_by(41) {
            let pixel = Vec2::new(px as f32 + 0.5, py as f32 + 0.5);
            let dir = pixel_ray_direction(inv, Vec3::ZERO, pixel, vp).unwrap();
            if let Some(h) = intersect_watertight(Vec3::ZERO, dir, tri) {
                let b = barycentrics(clip, pixel, vp);
                assert!(
                    (h.barycentrics - b.lambda).abs().max_element() < 1e-4,
                    "{pixel}"
                );
                hits += 1;
            }
        }
    }
    assert!(hits > 50, "{hits}");
    // Reversed infinite projection: the direction is still finite.
    let rev = (Mat4::perspective_infinite_reverse_rh(1.0, 1.0, 0.1) * view).inverse();
    assert!(
        pixel_ray_direction(rev, Vec3::ZERO, Vec2::new(10.5, 20.5), Vec2::splat(64.0)).is_some()
    );
}

/// The pixel-pull path's form (gpu's `pixel_pull.wgsl`): the ray from the origin along
/// `(ndc, 1)` against the clip positions' `(x, y, w)`, a linear image of camera-relative
/// space with the eye at its origin, hits with the same barycentrics (a linear map keeps
/// rays through the origin and barycentrics), so no inverse matrix is needed. Reversed-Z
/// infinite projection, as the renderer's.
#[test]
fn a_ray_in_clip_space_xyw_has_the_same_barycentrics() {
    let proj = Mat4::perspective_infinite_reverse_rh(1.0, 16.0 / 9.0, 0.1);
    let view = Mat4::look_at_rh(Vec3::ZERO, Vec3::new(0.2, -0.1, -1.0), Vec3::Y);
    let vp_m = proj * view;
    let inv = vp_m.inverse();
    let vp = Vec2::new(1920.0, 1080.0);
    let mut rng = Rng::new(5);
    let mut hits = 0;
    for _ in 0..200 {
        let c = Vec3::new(
            rng.range(-3.0, 3.0),
            rng.range(-2.0, 2.0),
            rng.range(-40.0, -2.0),
        );
        let tri = [0, 1, 2].map(|_| {
            c + Vec3::new(
                rng.range(-1.5, 1.5),
                rng.range(-1.5, 1.5),
                rng.range(-1.5, 1.5),
            )
        });
        let clip = tri.map(|p| vp_m * p.extend(1.0));
        let xyw = clip.map(|c| Vec3::new(c.x, c.y, c.w));
        for _ in 0..20 {
            // Aimed at a point near the triangle (about nine in ten hit).
            let w = Vec3::new(rng.f32(), rng.f32(), rng.f32()) + 0.05;
            let q = (tri[0] * w.x + tri[1] * w.y + tri[2] * w.z) / (w.x + w.y + w.z);
            let c = vp_m * q.extend(1.0);
            let p = Vec2::new(c.x / c.w * 0.5 + 0.5, 0.5 - c.y / c.w * 0.5) * vp
                + Vec2::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0));
            let pixel = p.floor() + 0.5;
            let ndc = Vec2::new(2.0 * pixel.x / vp.x - 1.0, 1.0 - 2.0 * pixel.y / vp.y);
            let dir = pixel_ray_direction(inv, Vec3::ZERO, pixel, vp).unwrap();
            let world = intersect_watertight(Vec3::ZERO, dir, tri);
            let clip_hit = intersect_watertight(Vec3::ZERO, ndc.extend(1.0), xyw);
            if let (Some(a), Some(b)) = (world, clip_hit) {
                assert!(
                    (a.barycentrics - b.barycentrics).abs().max_element() < 1e-4,
                    "{pixel}: {} vs {}",
                    a.barycentrics,
                    b.barycentrics
                );
                let l = barycentrics(clip, pixel, vp).lambda;
                assert!((b.barycentrics - l).abs().max_element() < 1e-4);
                hits += 1;
            } else {
                // Both miss (outside), or only a ray grazing an edge hits in one space
                // and not the other.
                let l = barycentrics(clip, pixel, vp).lambda;
                assert!(
                    l.min_element().abs() < 1e-3 || l.min_element() < 0.0,
                    "{pixel}: {l}"
                );
            }
        }
    }
    assert!(hits > 100, "{hits}");
}

#[test]
fn degenerate_and_non_finite_input_miss() {
    let t = [
        Vec3::new(-1.0, -1.0, -2.0),
        Vec3::new(1.0, -1.0, -2.0),
        Vec3::new(0.0, 1.0, -2.0),
    ];
    assert!(intersect_watertight(Vec3::ZERO, -Vec3::Z, t).is_some());
    assert!(
        intersect_watertight(Vec3::ZERO, Vec3::Z, t).is_none(),
        "behind the origin"
    );
    assert!(intersect_watertight(Vec3::ZERO, Vec3::ZERO, t).is_none());
    assert!(intersect_watertight(Vec3::ZERO, -Vec3::Z, [t[0]; 3]).is_none());
    assert!(
        intersect_watertight(Vec3::ZERO, -Vec3::Z, [t[0], t[1], (t[0] + t[1]) * 0.5]).is_none()
    );
    assert!(intersect_watertight(Vec3::NAN, -Vec3::Z, t).is_none());
    assert!(
        intersect_watertight(Vec3::ZERO, Vec3::X, t).is_none(),
        "parallel"
    );
    // Back faces hit too (both-sided).
    assert!(intersect_watertight(Vec3::ZERO, -Vec3::Z, [t[0], t[2], t[1]]).is_some());
}
