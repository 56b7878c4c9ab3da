//! Shading inputs against closed forms and analytic geometry: Beer–Lambert transmittance
//! and single scattering against f64 formulas and numerical integration, normals from depth
//! against analytic planes and spheres (and central differences as the baseline that fails
//! at edges), specular AA against the paper's formula.

use glam::{DVec3, UVec2, Vec2, Vec3};
use water::normals::{DepthCamera, DepthView, RadiusRule, Taps};
use water::optics::{Medium, PURE_WATER_ABSORPTION, WaterType, transmittance};

#[test]
fn transmittance_is_beer_lambert_per_channel() {
    for t in WaterType::TABLE {
        let m = t.medium();
        let e = m.extinction().as_dvec3();
        for d in [0.0f32, 0.1, 1.0, 3.7, 25.0, 200.0] {
            let got = m.transmittance(d).as_dvec3();
            let want = DVec3::new(
                (-e.x * d as f64).exp(),
                (-e.y * d as f64).exp(),
                (-e.z * d as f64).exp(),
            );
            assert!(
                (got - want).abs().max_element() < 1e-6,
                "{} at {d} m",
                t.name
            );
            // T(a + b) = T(a) T(b).
            let split = m.transmittance(d * 0.3) * m.transmittance(d * 0.7);
            assert!((split.as_dvec3() - got).abs().max_element() < 1e-6);
        }
    }
    // Pure water: the Pope and Fry coefficients.
    let e = WaterType::PURE.medium().extinction() - water::optics::PURE_WATER_SCATTERING;
    assert!((e - PURE_WATER_ABSORPTION).length() < 1e-7);
    assert_eq!(transmittance(Vec3::ONE, -1.0), Vec3::ONE);
    assert_eq!(transmittance(Vec3::ONE, f32::NAN), Vec3::ONE);
}

#[test]
fn single_scattering_matches_numerical_integration() {
    // L(d) = bed T(d) + integral_0^d sigma_s L_in exp(-sigma_t s) ds, midpoint rule in f64.
    let light = Vec3::new(1.0, 0.9, 0.7);
    let bed = Vec3::new(0.3, 0.2, 0.1);
    for t in WaterType::TABLE {
        let m = t.medium();
        for d in [0.5f32, 4.0, 30.0] {
            let steps = 20_000;
            let ds = d as f64 / steps as f64;
            let (st, ss) = (m.extinction().as_dvec3(), m.scattering.as_dvec3());
            let mut acc = DVec3::ZERO;
            for k in 0..steps {
                let s = (k as f64 + 0.5) * ds;
                acc += ss
                    * light.as_dvec3()
                    * DVec3::new((-st.x * s).exp(), (-st.y * s).exp(), (-st.z * s).exp())
                    * ds;
            }
            let want = bed.as_dvec3()
                * DVec3::new(
                    (-st.x * d as f64).exp(),
                    (-st.y * d as f64).exp(),
                    (-st.z * d as f64).exp(),
                )
                + acc;
            let got = m.light_transport(bed, light, d).as_dvec3();
            assert!(
                (got - want).abs().max_element() < 1e-5,
                "{} at {d} m: {got} vs {want}",
                t.name
            );
        }
        // Deep water converges to light * albedo.
        let deep = m.light_transport(bed, light, 1e5);
        assert!((deep - m.deep_color(light)).length() < 1e-5);
    }
    // A medium that only absorbs scatters nothing in.
    let m = Medium::new(Vec3::splat(0.5), Vec3::ZERO);
    assert_eq!(m.in_scatter(light, 10.0), Vec3::ZERO);
}

#[test]
fn water_types_order_as_expected() {
    // Clear ocean is the clearest of the table (after pure water), mud the murkiest;
    // the sulfur pond scatters the most blue-green for what it absorbs.
    let t1 = |t: WaterType| t.medium().transmittance(1.0);
    assert!(t1(WaterType::CLEAR_OCEAN).z > t1(WaterType::RIVER).z);
    assert!(t1(WaterType::RIVER).y > t1(WaterType::MUDDY).y);
    let sulfur = WaterType::SULFUR_POND.medium().albedo();
    assert!(sulfur.y > sulfur.x && sulfur.z > sulfur.x);
    // Turbidity scales the particles only.
    let twice = WaterType::RIVER.with_turbidity(2.0).medium();
    let once = WaterType::RIVER.medium();
    assert!(
        ((twice.scattering - once.scattering) - WaterType::RIVER.particle_scattering).length()
            < 1e-6
    );
}

fn camera() -> DepthCamera {
    DepthCamera {
        size: UVec2::new(96, 64),
        tan_half_fov: Vec2::new(0.9, 0.6),
    }
}

/// The view ray through pixel `p` (un-normalised, z = -1).
fn ray(cam: &DepthCamera, p: UVec2) -> DVec3 {
    let v = cam.view_position(p, 1.0);
    DVec3::new(v.x as f64, v.y as f64, -1.0)
}

/// Depth of the plane n . X = c seen through each pixel (view depth = the ray's t).
fn plane_depth(cam: &DepthCamera, n: DVec3, c: f64) -> Vec<f32> {
    (0..cam.size.x * cam.size.y)
        .map(|i| {
            let d = ray(cam, UVec2::new(i % cam.size.x, i / cam.size.x));
            let t = c / n.dot(d);
            if t > 0.0 { t as f32 } else { f32::INFINITY }
        })
        .collect()
}

fn angle(a: Vec3, b: DVec3) -> f64 {
    a.as_dvec3()
        .normalize()
        .dot(b.normalize())
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees()
}

#[test]
fn planes_reconstruct_exactly_with_both_tap_counts() {
    let cam = camera();
    for n in [
        DVec3::new(0.0, 1.0, 0.3),
        DVec3::new(0.4, 0.8, 0.5),
        DVec3::new(-0.3, 0.2, 1.0),
    ] {
        let n = n.normalize();
        let depth = plane_depth(&cam, n, -4.0 * n.z.abs().max(0.2));
        let v = DepthView {
            depth: &depth,
            camera: cam,
        };
        let mut worst: f64 = 0.0;
        for y in 2..cam.size.y - 2 {
            for x in 2..cam.size.x - 2 {
                let p = UVec2::new(x, y);
                if !depth[(y * cam.size.x + x) as usize].is_finite() {
                    continue;
                }
                let facing = if n.dot(-ray(&cam, p)) < 0.0 { -n } else { n };
                for taps in [Taps::Five, Taps::Nine] {
                    if let Some(got) = v.normal(p, 1, taps) {
                        worst = worst.max(angle(got, facing));
                    }
                }
            }
        }
        assert!(worst < 0.05, "plane {n}: {worst} degrees");
    }
}

#[test]
fn depth_edges_do_not_bleed_but_central_differences_do() {
    // A plane tilted towards the camera in front of a far wall; the edge runs down x = 40.
    let cam = camera();
    let n = DVec3::new(0.0, 0.6, 0.8);
    let near = plane_depth(&cam, n, -3.0);
    let far = plane_depth(&cam, DVec3::Z, -20.0);
    let depth: Vec<f32> = (0..cam.size.x * cam.size.y)
        .map(|i| {
            if i % cam.size.x < 40 {
                near[i as usize]
            } else {
                far[i as usize]
            }
        })
        .collect();
    let v = DepthView {
        depth: &depth,
        camera: cam,
    };
    let (mut five, mut nine, mut central) = (0.0f64, 0.0f64, 0.0f64);
    for y in 3..cam.size.y - 3 {
        for x in [38u32, 39, 40, 41] {
            let p = UVec2::new(x, y);
            let truth = if x < 40 { n } else { DVec3::Z };
            five = five.max(angle(v.normal(p, 1, Taps::Five).unwrap(), truth));
            nine = nine.max(angle(v.normal(p, 1, Taps::Nine).unwrap(), truth));
            central = central.max(angle(v.normal_central(p).unwrap(), truth));
        }
    }
    eprintln!(
        "at the edge: 5-tap {five:.3} deg, 9-tap {nine:.3} deg, central differences {central:.1} deg"
    );
    assert!(five < 0.05 && nine < 0.05);
    assert!(central > 30.0);
}

#[test]
fn sphere_normals_and_the_near_radius() {
    // A sphere of radius 1 at 3 m: analytic normals, reconstruction error small away from
    // the silhouette; close to the camera the radius rule widens the footprint.
    let cam = camera();
    let c = DVec3::new(0.2, -0.1, -3.0);
    let depth: Vec<f32> = (0..cam.size.x * cam.size.y)
        .map(|i| {
            let d = ray(&cam, UVec2::new(i % cam.size.x, i / cam.size.x));
            let (a, b, cc) = (d.dot(d), -2.0 * d.dot(c), c.dot(c) - 1.0);
            let disc = b * b - 4.0 * a * cc;
            if disc < 0.0 {
                f32::INFINITY
            } else {
                ((-b - disc.sqrt()) / (2.0 * a)) as f32
            }
        })
        .collect();
    let v = DepthView {
        depth: &depth,
        camera: cam,
    };
    let mut errs = Vec::new();
    for y in 0..cam.size.y {
        for x in 0..cam.size.x {
            let p = UVec2::new(x, y);
            let d = ray(&cam, p);
            let t = depth[(y * cam.size.x + x) as usize];
            if !t.is_finite() {
                continue;
            }
            let hit = d * t as f64;
            let truth = hit - c;
            // Skip grazing pixels near the silhouette.
            if truth.normalize().dot(-d.normalize()) < 0.5 {
                continue;
            }
            errs.push(angle(v.normal(p, 1, Taps::Nine).unwrap(), truth));
        }
    }
    errs.sort_by(f64::total_cmp);
    let p95 = errs[errs.len() * 95 / 100];
    eprintln!(
        "sphere: {} pixels, median {:.2} deg, p95 {p95:.2} deg",
        errs.len(),
        errs[errs.len() / 2]
    );
    assert!(errs.len() > 300 && errs[errs.len() / 2] < 0.3 && p95 < 2.5);
    let rule = RadiusRule {
        radius_at_1m: 3.0,
        max_radius: 6,
    };
    assert_eq!(rule.radius(3.0), 1);
    assert_eq!(rule.radius(0.5), 6);
    assert!(
        v.normal_auto(UVec2::new(48, 32), &rule, Taps::Five)
            .is_some()
    );
}

#[test]
fn specular_aa_widens_with_variance_and_stays_clamped() {
    use water::specaa::{DEFAULT_KAPPA, filtered_alpha, filtered_roughness};
    let mut last = 0.0;
    for k in 0..100 {
        let v = k as f32 * 0.002;
        let a = filtered_alpha(0.05, v, DEFAULT_KAPPA, 1.0);
        let want = (0.05f64 * 0.05 + (2.0 * v as f64).min(DEFAULT_KAPPA as f64)).sqrt();
        assert!((a as f64 - want).abs() < 1e-7);
        assert!(a >= last);
        last = a;
    }
    assert!(
        (last as f64 - (0.0025f64 + 0.18).sqrt()).abs() < 1e-7,
        "kappa caps the widening"
    );
    let r = filtered_roughness(0.3, 0.01, DEFAULT_KAPPA, 1.0);
    assert!((r as f64 - ((0.09f64 * 0.09 + 0.02).sqrt()).sqrt()).abs() < 1e-7);
}
