//! Stable cascades: the two stability properties (sub-texel camera moves change the
//! matrices only by whole texels; rotations never change a cascade's size), coverage of
//! every slice, and the split scheme against its formula.

use deferred::cascades::*;
use glam::{DQuat, DVec3, DVec4};
use proptest::prelude::*;

fn camera(position: DVec3, forward: DVec3) -> CascadeCamera {
    CascadeCamera {
        position,
        forward,
        fov_y: 1.0,
        aspect: 16.0 / 9.0,
    }
}

fn sun() -> DVec3 {
    DVec3::new(0.3, 0.8, -0.4).normalize()
}

fn params() -> CascadeParams {
    CascadeParams {
        count: 4,
        far: 300.0,
        resolution: 1024,
        // KZ2's per-slice resolutions: the far slices coarser.
        resolution_divisor: [1, 1, 2, 4, 1, 1, 1, 1],
        ..CascadeParams::default()
    }
}

/// Translation of a clip-space matrix row in texel units (x, y) and depth steps (z).
fn translation(c: &Cascade, res: f64) -> DVec3 {
    let t = c.world_to_clip.w_axis;
    DVec3::new(t.x * res / 2.0, t.y * res / 2.0, t.z)
}

fn unit(v: (f64, f64, f64)) -> DVec3 {
    let d = DVec3::new(v.0, v.1, v.2);
    if d.length() < 1e-3 {
        DVec3::NEG_Z
    } else {
        d.normalize()
    }
}

fn vec3() -> impl Strategy<Value = (f64, f64, f64)> {
    (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// Moving the camera by less than a texel: every matrix keeps its linear part exactly
    /// and its x / y translation changes by a whole number of texels (at most one).
    #[test]
    fn sub_texel_moves_change_matrices_by_whole_texels(
        pos in (-5000.0f64..5000.0, -100.0f64..500.0, -5000.0f64..5000.0),
        fwd in vec3(),
        step in vec3(),
        frac in 0.0f64..0.999,
    ) {
        let p = params();
        let a = camera(DVec3::new(pos.0, pos.1, pos.2), unit(fwd));
        let first = StableCascades::fit(&a, sun(), &p).unwrap();
        for (i, c0) in first.cascades().iter().enumerate() {
            // A move shorter than this cascade's texel.
            let mv = unit(step) * c0.texel_size * frac;
            let b = camera(a.position + mv, a.forward);
            let c1 = StableCascades::fit(&b, sun(), &p).unwrap().cascades()[i];
            prop_assert_eq!(c0.radius, c1.radius);
            for k in 0..3 {
                prop_assert_eq!(c0.world_to_clip.col(k), c1.world_to_clip.col(k));
            }
            let res = f64::from(p.slice_resolution(i));
            let d = translation(&c1, res) - translation(c0, res);
            for v in [d.x, d.y] {
                prop_assert!((v - v.round()).abs() < 1e-6 * (1.0 + pos.0.abs().max(pos.2.abs()) / 100.0), "{v}");
                prop_assert!(v.round().abs() <= 1.0, "{v}");
            }
            // Depth moves by whole depth steps: z = (p · fwd - z_near) / (2 R + margin).
            let dz = d.z * (2.0 * c0.radius + p.caster_margin) / p.depth_step;
            prop_assert!((dz - dz.round()).abs() < 1e-6, "{dz}");
        }
    }

    /// Rotating the camera never changes a cascade's size (radius, texel), bit for bit.
    #[test]
    fn rotation_never_changes_cascade_size(
        pos in (-1000.0f64..1000.0, 0.0f64..100.0, -1000.0f64..1000.0),
        fwd in vec3(),
        axis in vec3(),
        angle in -3.2f64..3.2,
    ) {
        let p = params();
        let a = camera(DVec3::new(pos.0, pos.1, pos.2), unit(fwd));
        let rotated = DQuat::from_axis_angle(unit(axis), angle) * a.forward;
        let b = camera(a.position, rotated);
        let ca = StableCascades::fit(&a, sun(), &p).unwrap();
        let cb = StableCascades::fit(&b, sun(), &p).unwrap();
        for (x, y) in ca.cascades().iter().zip(cb.cascades()) {
            prop_assert_eq!(x.radius, y.radius);
            prop_assert_eq!(x.texel_size, y.texel_size);
            prop_assert_eq!(x.split, y.split);
            // The box's width in clip space: the linear part's scale is the same.
            prop_assert_eq!(x.world_to_clip.x_axis.length(), y.world_to_clip.x_axis.length());
        }
    }

    /// Every point of each slice lands inside its cascade's box, after snapping.
    #[test]
    fn cascades_cover_their_slices(
        pos in (-1e6f64..1e6, -100.0f64..500.0, -1e6f64..1e6),
        fwd in vec3(),
        corner in (-1.0f64..=1.0, -1.0f64..=1.0, 0.0f64..=1.0),
    ) {
        let p = params();
        let cam = camera(DVec3::new(pos.0, pos.1, pos.2), unit(fwd));
        let set = StableCascades::fit(&cam, sun(), &p).unwrap();
        let f = cam.forward;
        let right = f.cross(if f.y.abs() < 0.99 { DVec3::Y } else { DVec3::X }).normalize();
        let up = right.cross(f);
        let ty = (cam.fov_y * 0.5).tan();
        let tx = ty * cam.aspect;
        for c in set.cascades() {
            let dist = c.split[0] + (c.split[1] - c.split[0]) * corner.2;
            let q = cam.position + f * dist + right * (corner.0 * tx * dist) + up * (corner.1 * ty * dist);
            // Camera-relative f32 matrix, as the GPU uses it.
            let m = c.relative_matrix(cam.position);
            let rel = (q - cam.position).as_vec3();
            let clip = m * rel.extend(1.0);
            prop_assert!(clip.x.abs() <= 1.0 + 1e-4 && clip.y.abs() <= 1.0 + 1e-4, "{clip}");
            prop_assert!((0.0..=1.0 + 1e-4).contains(&clip.z), "{clip}");
            // And the f64 matrix agrees with the f32 relative one to well under a texel.
            let w = c.world_to_clip * DVec4::new(q.x, q.y, q.z, 1.0);
            let texel = 2.0 / f64::from(p.resolution);
            prop_assert!((w.x - f64::from(clip.x)).abs() < 0.05 * texel, "{} vs {}", w.x, clip.x);
        }
    }
}

#[test]
fn practical_splits_match_the_formula() {
    let mut out = [0.0; 5];
    practical_splits(0.5, 500.0, 4, 0.6, &mut out);
    assert_eq!((out[0], out[4]), (0.5, 500.0));
    for i in 1..4 {
        let t = i as f64 / 4.0;
        let expect = 0.6 * 0.5 * 1000f64.powf(t) + 0.4 * (0.5 + 499.5 * t);
        assert!(
            (out[i] - expect).abs() < 1e-9,
            "{i}: {} vs {expect}",
            out[i]
        );
        assert!(out[i] > out[i - 1]);
    }
    // lambda 0 is uniform, 1 logarithmic.
    practical_splits(1.0, 16.0, 4, 1.0, &mut out);
    for (i, v) in out.iter().enumerate() {
        assert!((v - 2f64.powi(i as i32)).abs() < 1e-9);
    }
}

#[test]
fn bounding_sphere_is_minimal_and_holds_the_slice() {
    for (n, f, tx, ty) in [
        (0.1, 10.0, 1.0, 0.6),
        (10.0, 12.0, 0.3, 0.2),
        (1.0, 100.0, 2.0, 1.2),
    ] {
        let (c, r) = slice_bounding_sphere(n, f, tx, ty);
        let corners: Vec<DVec3> = [n, f]
            .iter()
            .flat_map(|&d| {
                [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)]
                    .map(|(sx, sy)| DVec3::new(sx * tx * d, sy * ty * d, d))
            })
            .collect();
        let centre = DVec3::new(0.0, 0.0, c);
        let far_corner = corners
            .iter()
            .map(|p| (*p - centre).length())
            .fold(0.0, f64::max);
        assert!(far_corner <= r * (1.0 + 1e-12), "{far_corner} > {r}");
        // Minimal: no axis point does better (sampled).
        for i in 0..=1000 {
            let z = n + (f - n) * i as f64 / 1000.0;
            let m = corners
                .iter()
                .map(|p| (*p - DVec3::new(0.0, 0.0, z)).length())
                .fold(0.0, f64::max);
            assert!(m >= r * (1.0 - 1e-9), "{z}: {m} < {r}");
        }
    }
}

#[test]
fn bad_parameters_are_errors() {
    let cam = camera(DVec3::ZERO, DVec3::NEG_Z);
    let mut p = params();
    p.count = 9;
    assert!(
        StableCascades::fit(&cam, sun(), &p)
            .unwrap_err()
            .to_string()
            .contains("MAX_CASCADES")
    );
    p = params();
    p.far = 0.01;
    assert!(
        StableCascades::fit(&cam, sun(), &p)
            .unwrap_err()
            .to_string()
            .contains("far")
    );
    assert!(StableCascades::fit(&cam, DVec3::ZERO, &params()).is_err());
    assert!(StableCascades::fit(&camera(DVec3::NAN, DVec3::Z), sun(), &params()).is_err());
}

#[test]
fn select_picks_the_first_cascade_beyond_the_distance() {
    let set = StableCascades::fit(&camera(DVec3::ZERO, DVec3::NEG_Z), sun(), &params()).unwrap();
    assert_eq!(set.select(0.2), Some(0));
    let c = set.cascades();
    assert_eq!(set.select(c[1].split[0] + 1e-9), Some(1));
    assert_eq!(set.select(301.0), None);
    let g = c[2].gpu(DVec3::new(5.0, 0.0, 0.0));
    assert_eq!(g.split_far, c[2].split[1] as f32);
}

/// Slice `i` has `resolution / resolution_divisor[i]` texels across its box, and a zero
/// divisor (or one leaving under 2 texels) is refused.
#[test]
fn each_slice_has_its_own_resolution() {
    let p = params();
    let set = StableCascades::fit(&camera(DVec3::ZERO, DVec3::NEG_Z), sun(), &p).unwrap();
    for (i, c) in set.cascades().iter().enumerate() {
        let texels = 2.0 * c.radius / c.texel_size;
        assert!(
            (texels - f64::from(1024 / p.resolution_divisor[i])).abs() < 1e-9,
            "{i}: {texels}"
        );
    }
    for bad in [0, 1024] {
        let mut q = params();
        q.resolution_divisor[3] = bad;
        assert!(StableCascades::fit(&camera(DVec3::ZERO, DVec3::NEG_Z), sun(), &q).is_err());
    }
}
