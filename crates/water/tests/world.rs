//! The water query against independent references: an f64 even-odd test over every lake
//! edge, and an f64 Catmull–Rom centre line sampled densely for rivers.

mod common;

use testkit::Rng;
use water::glam::{DVec2, DVec3, Vec2, Vec3};
use water::world::{
    BodyId, BodyKind, Lake, Ocean, River, RiverPoint, WaterWorld, WaterWorldBuilder,
};

fn inside_f64(poly: &[Vec2], p: DVec2) -> bool {
    let mut inside = false;
    for i in 0..poly.len() {
        let (a, b) = (poly[i].as_dvec2(), poly[(i + 1) % poly.len()].as_dvec2());
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y) {
            inside = !inside;
        }
    }
    inside
}

fn dist_to_polygon(poly: &[Vec2], p: DVec2) -> f64 {
    (0..poly.len())
        .map(|i| {
            let (a, b) = (poly[i].as_dvec2(), poly[(i + 1) % poly.len()].as_dvec2());
            let t = ((p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
            (a + (b - a) * t - p).length()
        })
        .fold(f64::INFINITY, f64::min)
}

/// A star-shaped lake with `n` jagged points around `c`.
fn star(c: Vec2, r: f32, n: usize, rng: &mut Rng) -> Vec<Vec2> {
    (0..n)
        .map(|i| {
            let a = i as f64 / n as f64 * std::f64::consts::TAU;
            let rr = r as f64 * (0.5 + 0.5 * f64::from(rng.f32()));
            c + Vec2::new((a.cos() * rr) as f32, (a.sin() * rr) as f32)
        })
        .collect()
}

#[test]
fn lakes_match_an_f64_even_odd_test_with_the_ocean_below() {
    let mut rng = Rng::new(1);
    let mut b = WaterWorldBuilder::new();
    b.ocean = Some(Ocean {
        level: 0.0,
        material: 7,
    });
    for k in 0..6 {
        let c = Vec2::new(rng.f32() * 900.0, rng.f32() * 900.0);
        b.lakes.push(Lake {
            polygon: star(c, 120.0, 50 + 100 * k as usize, &mut rng),
            height: 5.0 + k as f32,
            material: k,
        });
    }
    let world = b.build(&mut water::no_progress).unwrap();
    assert!(world.depth() > 2, "the jagged lakes must split the tree");
    let mut checked = 0;
    for _ in 0..20_000 {
        let p = DVec2::new(
            f64::from(rng.f32()) * 1200.0 - 100.0,
            f64::from(rng.f32()) * 1200.0 - 100.0,
        );
        // The reference: highest lake containing p, else the ocean.
        let mut expect: (f32, BodyId) = (0.0, BodyId::OCEAN);
        let mut near_edge = false;
        for (i, l) in b.lakes.iter().enumerate() {
            if dist_to_polygon(&l.polygon, p) < 1e-3 {
                near_edge = true;
            }
            if inside_f64(&l.polygon, p) && l.height > expect.0 {
                expect = (l.height, BodyId::lake(i as u32));
            }
        }
        if near_edge {
            continue;
        }
        let got = world.query(p.as_vec2()).expect("the ocean is everywhere");
        assert_eq!((got.height, got.body), expect, "at {p}");
        assert_eq!(got.flow, Vec2::ZERO);
        if got.body == BodyId::OCEAN {
            assert_eq!(got.material, 7);
        }
        checked += 1;
    }
    eprintln!(
        "{checked} of 20000 points away from lake edges, tree depth {}",
        world.depth()
    );
    assert!(checked > 19_000);
}

fn catmull_rom(p0: DVec3, p1: DVec3, p2: DVec3, p3: DVec3, t: f64) -> DVec3 {
    let (t2, t3) = (t * t, t * t * t);
    ((2.0 * p1)
        + (p2 - p0) * t
        + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t2
        + (3.0 * p1 - p0 - 3.0 * p2 + p3) * t3)
        * 0.5
}

/// Dense f64 centre line: (position, half width) samples.
fn centre_line(points: &[RiverPoint]) -> Vec<(DVec3, f64)> {
    let n = points.len();
    let at = |i: isize| {
        points[i.clamp(0, n as isize - 1) as usize]
            .position
            .as_dvec3()
    };
    let mut out = Vec::new();
    for i in 0..n - 1 {
        for s in 0..2000 {
            let t = s as f64 / 2000.0;
            let mut p = catmull_rom(
                at(i as isize - 1),
                at(i as isize),
                at(i as isize + 1),
                at(i as isize + 2),
                t,
            );
            // Height is linear between points (no overshoot at the waterfall).
            p.z = at(i as isize).z * (1.0 - t) + at(i as isize + 1).z * t;
            let w = points[i].width as f64 * (1.0 - t) + points[i + 1].width as f64 * t;
            out.push((p, w * 0.5));
        }
    }
    out
}

#[test]
fn rivers_follow_the_spline_with_slopes_and_a_waterfall() {
    let pt = |x: f32, y: f32, z: f32, w: f32| common::river_point(Vec3::new(x, y, z), w, 2.0, 3.0);
    // A bending river that drops 1 m over its first 100 m, then falls 15 m in 2 m
    // horizontally (a waterfall), then flows on.
    let points = vec![
        pt(0.0, 0.0, 30.0, 12.0),
        pt(60.0, 10.0, 29.5, 14.0),
        pt(100.0, 40.0, 29.0, 10.0),
        pt(102.0, 41.5, 14.0, 10.0),
        pt(160.0, 60.0, 13.5, 16.0),
    ];
    let mut b = WaterWorldBuilder::new();
    b.settings.texel_size = 0.5;
    b.settings.tile_texels = 32;
    b.rivers.push(River {
        points: points.clone(),
        material: 3,
    });
    let world = b.build(&mut water::no_progress).unwrap();
    assert!(world.tile_count() > 4);
    let line = centre_line(&points);
    let mut rng = Rng::new(42);
    let (mut wet, mut dry) = (0, 0);
    for _ in 0..20_000 {
        let p = DVec2::new(
            f64::from(rng.f32()) * 200.0 - 20.0,
            f64::from(rng.f32()) * 110.0 - 30.0,
        );
        let (c, hw) = line
            .iter()
            .min_by(|a, b| {
                let da = (a.0.truncate() - p).length() - a.1;
                let db = (b.0.truncate() - p).length() - b.1;
                da.total_cmp(&db)
            })
            .copied()
            .unwrap();
        let margin = (c.truncate() - p).length() - hw; // < 0 inside the river
        let got = world.query(p.as_vec2());
        // Away from the banks (one texel diagonal) water and dry land must agree.
        if margin < -0.75 {
            let got = got.unwrap_or_else(|| panic!("no water at {p}, {margin} m inside"));
            assert_eq!(got.body.kind(), Some(BodyKind::River(0)));
            assert_eq!(got.material, 3);
            // Height: a corner of p's cell (within a texel diagonal, 0.71 m) carries the
            // height of its nearest centre point, which is within 1.5 m more than p's
            // nearest; the answer lies in the range of those heights. On the slopes the
            // range is a few cm; across the waterfall it spans the drop.
            let d_min = line
                .iter()
                .map(|q| (q.0.truncate() - p).length())
                .fold(f64::INFINITY, f64::min);
            let (lo, hi) = line
                .iter()
                .filter(|q| (q.0.truncate() - p).length() <= d_min + 1.5)
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), q| {
                    (lo.min(q.0.z), hi.max(q.0.z))
                });
            let h = f64::from(got.height);
            assert!(
                h >= lo - 0.01 && h <= hi + 0.01,
                "height at {p}: {h} outside [{lo}, {hi}]"
            );
            if hi - lo < 0.1 {
                assert!((h - c.z).abs() < 0.1, "height at {p}: {h} vs {}", c.z);
                wet += 1;
            }
            assert!(got.depth >= 0.0 && got.depth <= 2.0);
            assert!(got.flow.length() <= 3.0 + 0.01);
        } else if margin > 0.75 {
            assert!(got.is_none(), "water at {p}, {margin} m outside: {got:?}");
            dry += 1;
        }
    }
    eprintln!("river: {wet} wet points on slopes, {dry} dry");
    assert!(wet > 500 && dry > 5000, "{wet} {dry}");
    // Flow runs downstream along the centre line, fastest in the middle.
    let mid = world.query(Vec2::new(30.0, 3.0)).unwrap();
    let (dir, speed) = mid.flow_direction_and_speed();
    assert!(dir.x > 0.9, "{dir}");
    assert!(speed > 2.0, "{speed}");
}

#[test]
fn non_finite_positions_give_none_and_empty_worlds_work() {
    let mut b = WaterWorldBuilder::new();
    let world = b.build(&mut water::no_progress).unwrap();
    assert_eq!(world.query(Vec2::ZERO), None);
    b.ocean = Some(Ocean {
        level: -2.0,
        material: 0,
    });
    let world = b.build(&mut water::no_progress).unwrap();
    assert_eq!(world.query(Vec2::new(1e30, 5.0)).unwrap().height, -2.0);
    assert_eq!(world.query(Vec2::new(f32::NAN, 0.0)), None);
    assert_eq!(world.query(Vec2::new(0.0, f32::INFINITY)), None);
    let under = Vec3::new(3.0, 4.0, -10.0);
    assert!(world.water_level(under).unwrap().is_submerged(under));
    assert!(
        !world
            .water_level(Vec3::new(3.0, 4.0, 1.0))
            .unwrap()
            .is_submerged(Vec3::new(3.0, 4.0, 1.0))
    );
}

#[test]
fn bad_bodies_are_errors_naming_the_body() {
    let mut b = WaterWorldBuilder::new();
    b.lakes.push(Lake {
        polygon: vec![Vec2::ZERO, Vec2::X],
        height: 0.0,
        material: 0,
    });
    let e = b.build(&mut water::no_progress).unwrap_err();
    assert!(e.to_string().contains("lake 0"), "{e}");
    b.lakes[0].polygon = vec![Vec2::ZERO, Vec2::X, Vec2::new(0.0, f32::NAN)];
    assert!(b.build(&mut water::no_progress).is_err());
    b.lakes.clear();
    b.rivers.push(River {
        points: vec![RiverPoint {
            position: Vec3::ZERO,
            width: 1.0,
            depth: 1.0,
            speed: 1.0,
        }],
        material: 0,
    });
    let e = b.build(&mut water::no_progress).unwrap_err();
    assert!(e.to_string().contains("river 0"), "{e}");
}

#[test]
fn words_roundtrip_and_corruption_is_rejected() {
    let mut b = WaterWorldBuilder::new();
    b.lakes.push(Lake {
        polygon: vec![
            Vec2::ZERO,
            Vec2::new(10.0, 0.0),
            Vec2::new(10.0, 10.0),
            Vec2::new(0.0, 10.0),
        ],
        height: 1.0,
        material: 2,
    });
    let world = b.build(&mut water::no_progress).unwrap();
    let again = WaterWorld::from_words(world.words().to_vec()).unwrap();
    assert_eq!(again, world);
    assert_eq!(
        again.query(Vec2::new(5.0, 5.0)).unwrap().body,
        BodyId::lake(0)
    );
    let mut bad = world.words().to_vec();
    bad[0] ^= 1;
    assert!(WaterWorld::from_words(bad).is_err());
    let mut bad = world.words().to_vec();
    bad.pop();
    assert!(WaterWorld::from_words(bad).is_err());
    let (tex, w, h) = world.to_texture(16);
    assert_eq!(tex.len(), (w * h) as usize);
    assert_eq!(&tex[..world.words().len()], world.words());
}

/// `WaterWorld::bodies` holds every point a query finds a body at: random points over
/// lakes and rivers, each found body's point inside its bounds and height range.
#[test]
fn body_bounds_hold_every_point_the_query_finds() {
    let mut rng = Rng::new(5);
    let mut b = WaterWorldBuilder::new();
    b.ocean = Some(Ocean {
        level: -3.0,
        material: 9,
    });
    for k in 0..3 {
        let c = Vec2::new(100.0 + 250.0 * k as f32, 200.0);
        b.lakes.push(Lake {
            polygon: star(c, 80.0, 40, &mut rng),
            height: 4.0 + k as f32,
            material: k,
        });
    }
    let point = |x: f32, y: f32, z: f32| common::river_point(Vec3::new(x, y, z), 12.0, 2.0, 2.0);
    b.rivers.push(River {
        points: vec![
            point(0.0, 500.0, 30.0),
            point(300.0, 420.0, 20.0),
            point(600.0, 520.0, 8.0),
        ],
        material: 5,
    });
    let world = b.build(&mut water::no_progress).unwrap();
    let bodies = world.bodies();
    assert_eq!(bodies.len(), 4);
    assert_eq!(world.ocean(), b.ocean);
    assert!(world.root().1 > 0.0);
    let mut found = 0;
    for _ in 0..20_000 {
        let p = Vec2::new(rng.f32() * 800.0 - 50.0, rng.f32() * 700.0);
        let Some(l) = world.query(p) else { continue };
        if l.body == BodyId::OCEAN {
            continue;
        }
        let bb = bodies
            .iter()
            .find(|x| x.body == l.body)
            .expect("a body of the list");
        assert!(
            p.cmpge(bb.min).all() && p.cmple(bb.max).all(),
            "{p} outside {bb:?}"
        );
        assert!(l.height >= bb.height.0 - 1e-4 && l.height <= bb.height.1 + 1e-4);
        assert_eq!(l.material, bb.material);
        found += 1;
    }
    assert!(found > 1000, "{found}");
}

/// `WaterWorld::candidates` holds the query's answer and every body covering the point.
#[test]
fn candidates_hold_the_query_and_every_covering_body() {
    let world = common::lake_and_river(9.0);
    let mut both = 0;
    for y in 0..120 {
        for x in 0..60 {
            let q = Vec2::new(x as f32 + 0.3, y as f32 + 0.6);
            let c = world.candidates(q);
            let best = world.query(q);
            assert_eq!(best.is_some(), !c.is_empty());
            if let Some(b) = best {
                assert!(c.contains(&b));
                assert!(c.iter().all(|l| l.height <= b.height));
            }
            if c.iter().any(|l| l.body == BodyId::lake(0))
                && c.iter().any(|l| l.body == BodyId::river(0))
            {
                both += 1;
            }
        }
    }
    // The river runs into the lake: there both cover the point (the lake wins below the
    // river's end, which is lower).
    assert!(both > 50, "{both}");
    assert!(world.candidates(Vec2::NAN).is_empty());
}
