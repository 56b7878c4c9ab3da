//! Barycentrics, derivatives and mip selection against independent references: an f64
//! rasteriser (screen-space edge functions, then perspective correction), the DAIS
//! formulas in f64, finite differences of the rasteriser, and edge cases.

use glam::{DMat4, DVec2, DVec3, DVec4, Mat4, Vec2, Vec3, Vec4};
use proptest::prelude::*;
use testkit::Rng;
use visbuf::bary::{Barycentrics, barycentrics, barycentrics_quad, bias_gradients, mip_level};

const VIEWPORT: DVec2 = DVec2::new(1920.0, 1080.0);

/// The reference rasteriser's perspective-correct weights at a framebuffer position, f64.
fn raster_lambda(clip: [DVec4; 3], p: DVec2, vp: DVec2) -> DVec3 {
    let sp = clip.map(|c| {
        DVec2::new(
            (c.x / c.w + 1.0) * 0.5 * vp.x,
            (1.0 - c.y / c.w) * 0.5 * vp.y,
        )
    });
    let cross = |a: DVec2, b: DVec2| a.x * b.y - a.y * b.x;
    let area = cross(sp[1] - sp[0], sp[2] - sp[0]);
    let b = DVec3::new(
        cross(sp[1] - p, sp[2] - p) / area,
        cross(sp[2] - p, sp[0] - p) / area,
        cross(sp[0] - p, sp[1] - p) / area,
    );
    let bw = b / DVec3::new(clip[0].w, clip[1].w, clip[2].w);
    bw / bw.element_sum()
}

/// The DAIS appendix formulas (REFERENCES.md), f64: weights and exact per-pixel gradients.
fn dais(clip: [DVec4; 3], p: DVec2, vp: DVec2) -> (DVec3, DVec3, DVec3) {
    let q = DVec2::new(2.0 * p.x / vp.x - 1.0, 1.0 - 2.0 * p.y / vp.y);
    let n = clip.map(|c| DVec2::new(c.x / c.w, c.y / c.w));
    let om = DVec3::new(1.0 / clip[0].w, 1.0 / clip[1].w, 1.0 / clip[2].w);
    let d = (n[2] - n[1]).perp_dot(n[0] - n[1]);
    let gx = DVec3::new(n[1].y - n[2].y, n[2].y - n[0].y, n[0].y - n[1].y) * om / d;
    let gy = DVec3::new(n[2].x - n[1].x, n[0].x - n[2].x, n[1].x - n[0].x) * om / d;
    let dlt = q - n[0];
    let inv_w = om.x + dlt.x * gx.element_sum() + dlt.y * gy.element_sum();
    let w = 1.0 / inv_w;
    let l = w * (DVec3::new(om.x, 0.0, 0.0) + dlt.x * gx + dlt.y * gy);
    let dx = w * (gx - l * gx.element_sum());
    let dy = w * (gy - l * gy.element_sum());
    (l, dx * (2.0 / vp.x), dy * (-2.0 / vp.y))
}

fn f32s(c: [DVec4; 3]) -> [Vec4; 3] {
    c.map(|v| v.as_vec4())
}

/// A random visible triangle of about `px` pixels and a framebuffer point inside it.
fn random_triangle(rng: &mut Rng, px: f64) -> ([DVec4; 3], DVec2) {
    let mut r = || f64::from(rng.f32());
    let proj = DMat4::perspective_rh(1.0, VIEWPORT.x / VIEWPORT.y, 0.1, 1000.0);
    let depth = 2.0 + 60.0 * r();
    let half_h = depth * (0.5f64).tan();
    let centre = DVec3::new(
        (r() - 0.5) * half_h * 2.5,
        (r() - 0.5) * half_h * 1.6,
        -depth,
    );
    let world_per_px = 2.0 * half_h / VIEWPORT.y;
    let size = px * world_per_px;
    // Reject slivers: the screen-space triangle must not be thinner than 1/10 of its
    // longest edge (the errors of every f32 method grow without bound as shapes degenerate).
    let clip = loop {
        let mut dir = || DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5).normalize() * size;
        let v = [centre + dir(), centre + dir(), centre + dir()];
        let clip = v.map(|p| proj * p.extend(1.0));
        let sp = clip.map(|c| DVec2::new(c.x / c.w * VIEWPORT.x, c.y / c.w * VIEWPORT.y) * 0.5);
        let area2 = (sp[1] - sp[0]).perp_dot(sp[2] - sp[0]).abs();
        let longest = (sp[1] - sp[0])
            .length()
            .max((sp[2] - sp[1]).length())
            .max((sp[0] - sp[2]).length());
        if area2 >= 0.1 * longest * longest {
            break clip;
        }
    };
    // A point inside: random weights, projected.
    let (a, b) = (r(), r());
    let (a, b) = if a + b > 1.0 {
        (1.0 - a, 1.0 - b)
    } else {
        (a, b)
    };
    let x = clip[0] * (1.0 - a - b) + clip[1] * a + clip[2] * b;
    let p = DVec2::new(
        (x.x / x.w + 1.0) * 0.5 * VIEWPORT.x,
        (1.0 - x.y / x.w) * 0.5 * VIEWPORT.y,
    );
    (clip, p)
}

#[test]
fn weights_and_derivatives_match_f64_references_on_1_to_100_px_triangles() {
    let mut rng = Rng::new(0x5eed);
    let (mut sum, mut max, mut n) = (0.0f64, 0.0f64, 0);
    let mut worst_rel_d = 0.0f64;
    for i in 0..20_000 {
        let px = 1.0 + 99.0 * (i % 100) as f64 / 99.0;
        let (clip, p) = random_triangle(&mut rng, px);
        // Reference weights at the f32-rounded inputs the code sees.
        let clip = clip.map(|c| c.as_vec4().as_dvec4());
        let p = p.as_vec2().as_dvec2();
        let got = barycentrics(f32s(clip), p.as_vec2(), VIEWPORT.as_vec2());
        let want = raster_lambda(clip, p, VIEWPORT);
        let (dl, dx, dy) = dais(clip, p, VIEWPORT);
        assert!(
            (want - dl).abs().max_element() < 1e-9,
            "the two references agree"
        );
        let err = (got.lambda.as_dvec3() - want).abs().max_element();
        sum += err;
        max = max.max(err);
        n += 1;
        // Derivatives: relative to the size of the gradient (about 1 / triangle size).
        let scale = dx.abs().max_element().max(dy.abs().max_element());
        let rel = (got.ddx.as_dvec3() - dx)
            .abs()
            .max_element()
            .max((got.ddy.as_dvec3() - dy).abs().max_element())
            / scale;
        worst_rel_d = worst_rel_d.max(rel);
    }
    let mean = sum / n as f64;
    eprintln!(
        "f32 weights vs f64: mean {mean:.2e}, max {max:.2e}; derivative max relative {worst_rel_d:.2e}"
    );
    assert!(mean < 1e-5, "mean {mean}");
    assert!(max < 2e-3, "max {max}");
    assert!(worst_rel_d < 1e-2, "derivatives {worst_rel_d}");
}

#[test]
fn derivatives_match_finite_differences_of_the_rasteriser() {
    let mut rng = Rng::new(77);
    for _ in 0..2000 {
        let (clip, p) = random_triangle(&mut rng, 30.0);
        let clip = clip.map(|c| c.as_vec4().as_dvec4());
        let p = p.as_vec2().as_dvec2();
        let got = barycentrics(f32s(clip), p.as_vec2(), VIEWPORT.as_vec2());
        let h = 1e-3;
        let cx = (raster_lambda(clip, p + DVec2::X * h, VIEWPORT)
            - raster_lambda(clip, p - DVec2::X * h, VIEWPORT))
            / (2.0 * h);
        let cy = (raster_lambda(clip, p + DVec2::Y * h, VIEWPORT)
            - raster_lambda(clip, p - DVec2::Y * h, VIEWPORT))
            / (2.0 * h);
        let scale = cx.abs().max_element().max(cy.abs().max_element());
        assert!(
            (got.ddx.as_dvec3() - cx).abs().max_element() < 2e-3 * scale,
            "{:?} vs {cx:?}",
            got.ddx
        );
        assert!(
            (got.ddy.as_dvec3() - cy).abs().max_element() < 2e-3 * scale,
            "{:?} vs {cy:?}",
            got.ddy
        );
        // Quad differences: the rasteriser's weights one pixel over, minus here.
        let q = barycentrics_quad(f32s(clip), p.as_vec2(), VIEWPORT.as_vec2());
        let l0 = raster_lambda(clip, p, VIEWPORT);
        let fx = raster_lambda(clip, p + DVec2::X, VIEWPORT) - l0;
        let fy = raster_lambda(clip, p + DVec2::Y, VIEWPORT) - l0;
        assert!(
            (q.ddx.as_dvec3() - fx).abs().max_element() < 2e-3 * scale,
            "{:?} vs {fx:?}",
            q.ddx
        );
        assert!(
            (q.ddy.as_dvec3() - fy).abs().max_element() < 2e-3 * scale,
            "{:?} vs {fy:?}",
            q.ddy
        );
        assert_eq!(q.lambda, got.lambda);
    }
}

#[test]
fn interpolated_attributes_and_their_derivatives_follow_the_rasteriser() {
    let mut rng = Rng::new(99);
    for _ in 0..500 {
        let (clip, p) = random_triangle(&mut rng, 50.0);
        let clip = clip.map(|c| c.as_vec4().as_dvec4());
        let p = p.as_vec2().as_dvec2();
        let uv = [
            Vec2::new(0.0, 0.0),
            Vec2::new(3.0, 0.5),
            Vec2::new(-1.0, 2.0),
        ];
        let b = barycentrics(f32s(clip), p.as_vec2(), VIEWPORT.as_vec2());
        let it = b.interpolate(uv);
        let at = |p: DVec2| {
            let l = raster_lambda(clip, p, VIEWPORT);
            uv[0].as_dvec2() * l.x + uv[1].as_dvec2() * l.y + uv[2].as_dvec2() * l.z
        };
        assert!((it.value.as_dvec2() - at(p)).abs().max_element() < 1e-3);
        let h = 1e-3;
        let dx = (at(p + DVec2::X * h) - at(p - DVec2::X * h)) / (2.0 * h);
        let dy = (at(p + DVec2::Y * h) - at(p - DVec2::Y * h)) / (2.0 * h);
        let scale = dx.abs().max_element().max(dy.abs().max_element());
        assert!((it.ddx.as_dvec2() - dx).abs().max_element() < 2e-3 * scale);
        assert!((it.ddy.as_dvec2() - dy).abs().max_element() < 2e-3 * scale);
        // Scalars interpolate the same way.
        let z = b.interpolate([1.0f32, 2.0, 4.0]);
        assert!((z.value - (b.lambda.x + 2.0 * b.lambda.y + 4.0 * b.lambda.z)).abs() < 1e-5);
    }
}

#[test]
fn screen_aligned_quad_has_unit_texel_footprint_and_bias_moves_the_level() {
    // A quad at w = 1 covering the viewport exactly, UV 0..1 over a 1920x1080 texture:
    // one texel per pixel, level 0.
    let vp = Vec2::new(1920.0, 1080.0);
    let clip = [
        Vec4::new(-1.0, 1.0, 0.5, 1.0),
        Vec4::new(1.0, 1.0, 0.5, 1.0),
        Vec4::new(-1.0, -1.0, 0.5, 1.0),
    ];
    let uv = [
        Vec2::new(0.0, 0.0),
        Vec2::new(1.0, 0.0),
        Vec2::new(0.0, 1.0),
    ];
    let b = barycentrics(clip, Vec2::new(100.5, 200.5), vp);
    let it = b.interpolate(uv);
    assert!(
        (it.value - Vec2::new(100.5 / 1920.0, 200.5 / 1080.0))
            .abs()
            .max_element()
            < 1e-6
    );
    assert!((it.ddx - Vec2::new(1.0 / 1920.0, 0.0)).abs().max_element() < 1e-9);
    assert!((it.ddy - Vec2::new(0.0, 1.0 / 1080.0)).abs().max_element() < 1e-9);
    assert!(mip_level(it.ddx, it.ddy, vp, 0.0).abs() < 1e-5);
    assert!((mip_level(it.ddx, it.ddy, vp, 1.5) - 1.5).abs() < 1e-5);
    assert!((mip_level(it.ddx, it.ddy, vp / 4.0, 0.0) + 2.0).abs() < 1e-5);
    assert!((mip_level(it.ddx * 8.0, it.ddy, vp, 0.0) - 3.0).abs() < 1e-5);
    let (bx, by) = bias_gradients(it.ddx, it.ddy, 2.0);
    assert!((mip_level(bx, by, vp, 0.0) - mip_level(it.ddx, it.ddy, vp, 2.0)).abs() < 1e-5);
    // Zero and infinite footprints stay finite.
    assert_eq!(mip_level(Vec2::ZERO, Vec2::ZERO, vp, 0.0), -63.0);
    assert_eq!(
        mip_level(Vec2::splat(f32::INFINITY), Vec2::ZERO, vp, 0.0),
        64.0
    );
}

#[test]
fn mip_level_matches_a_finite_difference_footprint() {
    let mut rng = Rng::new(4242);
    for _ in 0..300 {
        let (clip, p) = random_triangle(&mut rng, 40.0);
        let clip = clip.map(|c| c.as_vec4().as_dvec4());
        let uv = [
            DVec2::new(0.1, 0.2),
            DVec2::new(0.9, 0.3),
            DVec2::new(0.4, 0.8),
        ];
        let at = |p: DVec2| {
            let l = raster_lambda(clip, p, VIEWPORT);
            uv[0] * l.x + uv[1] * l.y + uv[2] * l.z
        };
        let h = 1e-3;
        let dx = (at(p + DVec2::X * h) - at(p - DVec2::X * h)) / (2.0 * h) * 256.0;
        let dy = (at(p + DVec2::Y * h) - at(p - DVec2::Y * h)) / (2.0 * h) * 256.0;
        let want = dx.length().max(dy.length()).log2() - 0.5;
        let it = barycentrics(f32s(clip), p.as_vec2(), VIEWPORT.as_vec2())
            .interpolate(uv.map(|u| u.as_vec2()));
        let got = mip_level(it.ddx, it.ddy, Vec2::splat(256.0), -0.5);
        assert!((got as f64 - want).abs() < 1e-3, "{got} vs {want}");
    }
}

#[test]
fn edge_cases_give_defined_finite_results() {
    let vp = Vec2::new(800.0, 600.0);
    let px = Vec2::new(400.5, 300.5);
    let deg = Barycentrics::DEGENERATE;
    // Zero area: collinear, coincident.
    let line = [
        Vec4::new(0.0, 0.0, 0.0, 1.0),
        Vec4::new(0.5, 0.5, 0.0, 1.0),
        Vec4::new(1.0, 1.0, 0.0, 1.0),
    ];
    assert_eq!(barycentrics(line, px, vp), deg);
    let point = [Vec4::new(0.1, 0.1, 0.0, 1.0); 3];
    assert_eq!(barycentrics(point, px, vp), deg);
    assert_eq!(barycentrics_quad(point, px, vp), deg);
    // Edge-on: the triangle's plane contains the eye (all w = 0 is one such case).
    let edge_on = [
        Vec4::new(1.0, 0.0, 0.0, 0.0),
        Vec4::new(0.0, 1.0, 0.0, 0.0),
        Vec4::new(-1.0, -1.0, 0.0, 0.0),
    ];
    assert_eq!(barycentrics(edge_on, px, vp), deg);
    // Non-finite positions, zero viewport, NaN pixel.
    let tri = [
        Vec4::new(-0.5, -0.5, 0.0, 1.0),
        Vec4::new(0.5, -0.5, 0.0, 2.0),
        Vec4::new(0.0, 0.5, 0.0, 3.0),
    ];
    let mut bad = tri;
    bad[1].x = f32::NAN;
    assert_eq!(barycentrics(bad, px, vp), deg);
    bad[1].x = f32::INFINITY;
    assert_eq!(barycentrics(bad, px, vp), deg);
    assert_eq!(barycentrics(tri, px, Vec2::new(0.0, 600.0)), deg);
    assert_eq!(barycentrics(tri, Vec2::NAN, vp), deg);
    // Huge and tiny coordinates: weights do not depend on a common scale of the clip
    // positions, and nothing overflows.
    let base = barycentrics(tri, px, vp);
    for k in [1e-30f32, 1e-20, 1e20, 1e30, 3e38 / 3.0] {
        let b = barycentrics(tri.map(|c| c * k), px, vp);
        assert!(
            (b.lambda - base.lambda).abs().max_element() < 1e-5,
            "scale {k}"
        );
        assert!((b.ddx - base.ddx).abs().max_element() < 1e-6, "scale {k}");
    }
    // Pixels far outside: finite extrapolated weights summing to 1, as in f64.
    for p in [
        Vec2::new(-5000.0, 3.0),
        Vec2::new(1e6, -1e6),
        Vec2::new(799.5, 0.5),
    ] {
        let b = barycentrics(tri, p, vp);
        let want = raster_lambda(tri.map(|c| c.as_dvec4()), p.as_dvec2(), vp.as_dvec2());
        assert!(b.lambda.is_finite() && b.ddx.is_finite() && b.ddy.is_finite());
        assert!(
            (b.lambda.as_dvec3() - want).abs().max_element()
                < 1e-4 * want.abs().max_element().max(1.0),
            "{p}"
        );
    }
}

#[test]
fn vertices_behind_the_eye_interpolate_correctly_where_the_triangle_is_visible() {
    // A big ground triangle reaching behind the camera: one vertex has w < 0, one w = 0.
    let proj = Mat4::perspective_rh(1.2, 800.0 / 600.0, 0.1, 100.0);
    let view = Mat4::look_at_rh(Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 1.0, -1.0), Vec3::Y);
    let world = [
        Vec3::new(-20.0, 0.0, -30.0),
        Vec3::new(20.0, 0.0, -30.0),
        Vec3::new(0.0, 0.0, 5.0),
    ];
    let clip = world.map(|p| proj * view * p.extend(1.0));
    assert!(clip[2].w < 0.0);
    let vp = Vec2::new(800.0, 600.0);
    // Reference: intersect the pixel's view ray with the ground plane in f64 and solve for
    // the weights of that world point.
    let inv = (proj * view).as_dmat4().inverse();
    for py in [350.5f32, 420.5, 590.5] {
        for px in [10.5f32, 400.5, 780.5] {
            let ndc = DVec2::new(2.0 * px as f64 / 800.0 - 1.0, 1.0 - 2.0 * py as f64 / 600.0);
            let near = inv * DVec4::new(ndc.x, ndc.y, 0.0, 1.0);
            let far = inv * DVec4::new(ndc.x, ndc.y, 1.0, 1.0);
            let (o, f) = (near.truncate() / near.w, far.truncate() / far.w);
            let t = -o.y / (f.y - o.y);
            let hit = o + (f - o) * t;
            let w = world.map(|v| v.as_dvec3());
            let a = (w[1] - hit).cross(w[2] - hit).y / (w[1] - w[0]).cross(w[2] - w[0]).y;
            let b = (w[2] - hit).cross(w[0] - hit).y / (w[1] - w[0]).cross(w[2] - w[0]).y;
            let want = DVec3::new(a, b, 1.0 - a - b);
            let got = barycentrics(clip, Vec2::new(px, py), vp);
            assert!(
                (got.lambda.as_dvec3() - want).abs().max_element() < 1e-4,
                "{px},{py}: {:?} vs {want:?}",
                got.lambda
            );
        }
    }
    let mut zero_w = clip;
    zero_w[2] = Vec4::new(0.0, -3.0, 0.5, 0.0);
    let b = barycentrics(zero_w, Vec2::new(400.5, 500.5), vp);
    assert!(b.lambda.is_finite() && (b.lambda.element_sum() - 1.0).abs() < 1e-5);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn any_input_is_finite(bits in proptest::array::uniform12(any::<u32>()), p in proptest::array::uniform2(any::<u32>()), quad: bool) {
        let f = |i: usize| f32::from_bits(bits[i]);
        let clip = [
            Vec4::new(f(0), f(1), f(2), f(3)),
            Vec4::new(f(4), f(5), f(6), f(7)),
            Vec4::new(f(8), f(9), f(10), f(11)),
        ];
        let px = Vec2::new(f32::from_bits(p[0]), f32::from_bits(p[1]));
        for vp in [Vec2::new(1920.0, 1080.0), Vec2::new(1.0, 1.0)] {
            let b = if quad { barycentrics_quad(clip, px, vp) } else { barycentrics(clip, px, vp) };
            prop_assert!(b.lambda.is_finite() && b.ddx.is_finite() && b.ddy.is_finite(), "{:?}", b);
        }
    }
}

#[test]
fn clamped_weights_match_the_f64_clamp_outside_the_triangle_and_keep_those_inside() {
    let mut rng = Rng::new(0xc1a3);
    let (mut outside, mut worst) = (0, 0.0f64);
    for i in 0..20_000 {
        let (clip, inside) = random_triangle(&mut rng, 1.0 + (i % 50) as f64);
        let clip = clip.map(|c| c.as_vec4().as_dvec4());
        // The point inside, or moved up to 40 px away (mostly outside).
        let p = if i % 4 == 0 {
            inside
        } else {
            inside
                + DVec2::new(
                    f64::from(rng.range(-40.0, 40.0)),
                    f64::from(rng.range(-40.0, 40.0)),
                )
        };
        let p = p.as_vec2().as_dvec2();
        let got = barycentrics(f32s(clip), p.as_vec2(), VIEWPORT.as_vec2());
        let clamped = got.clamped();
        // The derivatives are the plane's, kept.
        assert_eq!((clamped.ddx, clamped.ddy), (got.ddx, got.ddy));
        let l = raster_lambda(clip, p, VIEWPORT);
        let want = l.max(DVec3::ZERO) / l.max(DVec3::ZERO).element_sum();
        if l.min_element() < 0.0 {
            outside += 1;
        } else if l.min_element() > 1e-3 {
            // Well inside: nothing to clamp, the weights as they were but for an ulp.
            assert!((clamped.lambda - got.lambda).abs().max_element() <= 1.2e-7);
        }
        assert!(clamped.lambda.min_element() >= 0.0, "{clamped:?}");
        assert!((clamped.lambda.element_sum() - 1.0).abs() < 1e-6);
        // Relative to the unclamped weights' scale, which grows away from the triangle.
        let err =
            (clamped.lambda.as_dvec3() - want).abs().max_element() / (1.0 + l.abs().max_element());
        worst = worst.max(err);
        assert!(
            err < 2e-3,
            "case {i}: got {:?}, want {want:?}",
            clamped.lambda
        );
    }
    eprintln!("clamped weights vs f64: worst {worst:.2e}, {outside} points outside");
    assert!(outside > 10_000);
    // Not finite: the centroid.
    let nan = Barycentrics {
        lambda: Vec3::new(f32::NAN, 0.5, 0.5),
        ..Barycentrics::DEGENERATE
    };
    assert_eq!(nan.clamped().lambda, Barycentrics::DEGENERATE.lambda);
}
