//! `water::draw` against the query it draws: every point the query finds a body at lies
//! under that body's mesh, the sector tree's nodes hold their children, and the material
//! map sees the other material across a boundary.

mod common;

use water::Error;
use water::axes::y_up_from_z_up;
use water::draw::{NODE_OCEAN, material_map, near_meshes, sector_tree};
use water::glam::{Vec2, Vec3};

#[test]
fn near_meshes_cover_every_point_of_their_bodies() {
    let w = common::lake_and_river(10.0);
    let bodies = w.bodies();
    let m = near_meshes(&w, &bodies, 2.0).unwrap();
    assert_eq!(m.bodies.len(), 2);
    // Every point a query finds a body at lies under one of that body's triangles
    // (seen from above), at the body's height there.
    for (k, b) in bodies.iter().enumerate() {
        let (lo, hi, first, count, body, _) = m.bodies[k];
        assert_eq!(body, b.body.0);
        let tris = &m.indices[first as usize..(first + count) as usize];
        for y in (0..160).map(|v| v as f32 * 0.83) {
            for x in (0..80).map(|v| v as f32 * 0.91) {
                let p = Vec2::new(x, y);
                let Some(q) = w.query(p).filter(|q| q.body == b.body) else {
                    continue;
                };
                let g = y_up_from_z_up(p.extend(q.height));
                assert!(
                    g.cmpge(lo - 1e-3).all() && g.cmple(hi + 1e-3).all(),
                    "{g} {lo} {hi} {:?}",
                    b.body
                );
                let covered = tris.chunks_exact(3).any(|t| {
                    let v = |i: u32| {
                        let r = m.vertices[i as usize];
                        Vec2::new(r[0], r[2])
                    };
                    let (a, bb, c) = (v(t[0]), v(t[1]), v(t[2]));
                    let g2 = Vec2::new(g.x, g.z);
                    let e = |p0: Vec2, p1: Vec2| (p1 - p0).perp_dot(g2 - p0);
                    let (e0, e1, e2) = (e(a, bb), e(bb, c), e(c, a));
                    (e0 >= -1e-4 && e1 >= -1e-4 && e2 >= -1e-4)
                        || (e0 <= 1e-4 && e1 <= 1e-4 && e2 <= 1e-4)
                });
                assert!(covered, "{p} of {:?} is not under its mesh", b.body);
            }
        }
        // Counter-clockwise seen from above (+Y): the face normal points up.
        for t in tris.chunks_exact(3) {
            let v = |i: u32| {
                let r = m.vertices[i as usize];
                Vec3::new(r[0], r[1], r[2])
            };
            let n = (v(t[1]) - v(t[0])).cross(v(t[2]) - v(t[0]));
            assert!(n.y > 0.0, "{n}");
        }
    }
}

#[test]
fn sector_tree_nodes_hold_their_children_and_the_ocean() {
    let w = common::lake_and_river(10.0);
    let bodies = w.bodies();
    let t = sector_tree(&w, &bodies, 64.0, 4096.0).unwrap();
    assert_eq!(t.sectors_per_side, 64);
    assert_eq!(t.levels, 7);
    assert_eq!(t.nodes.len(), (4usize.pow(7) - 1) / 3);
    // Every leaf has the ocean; the root's box holds every leaf's.
    let leaves = &t.nodes[(4usize.pow(6) - 1) / 3..];
    assert!(leaves.iter().all(|l| l[3].to_bits() & NODE_OCEAN != 0));
    let root = t.nodes[0];
    for l in leaves {
        for k in 0..3 {
            assert!(root[k] <= l[k] && root[4 + k] >= l[4 + k]);
        }
    }
    // Over the talk's 64 x 64 sectors: an error naming the limit.
    match sector_tree(&w, &bodies, 64.0, 64.0 * 65.0) {
        Err(Error::LimitExceeded { limit_name, .. }) => {
            assert_eq!(limit_name, "MAX_WATER_SECTORS_PER_SIDE")
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn material_map_blends_over_the_boundary() {
    let w = common::lake_and_river(10.0);
    let bodies = w.bodies();
    let m = material_map(&w, &bodies, 6.0);
    assert!(m.width > 10 && m.height > 10);
    let at = |p: Vec2| {
        let t = ((p - m.origin) / m.texel).floor();
        m.words[(t.y as u32 * m.width + t.x as u32) as usize]
    };
    // Deep in the lake, away from the river: no other material.
    let w0 = at(Vec2::new(8.0, 8.0));
    assert_eq!(w0 & 0x7ff, 1);
    assert_eq!(w0 >> 22, 1023);
    // Along the river's banks inside the lake, each side sees the other within reach.
    let sees = |own: u32, other: u32| {
        m.words
            .iter()
            .filter(|&&w| w & 0x7ff == own && (w >> 11) & 0x7ff == other && w >> 22 < 300)
            .count()
    };
    assert!(
        sees(1, 2) > 10 && sees(2, 1) > 10,
        "{} {}",
        sees(1, 2),
        sees(2, 1)
    );
}
