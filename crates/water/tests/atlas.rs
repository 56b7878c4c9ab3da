//! The flow atlas against the analytic field it was built from: resident tiles within
//! the tile's bilinear and 16-bit error, the 8 m world map elsewhere, seamless sector
//! borders, streaming in and out, and rejection of corrupt textures.

use water::atlas::{FlowAtlas, FlowAtlasSettings};
use water::flowbake::FlowField;
use water::glam::{UVec2, Vec2};

/// A smooth analytic flow, m/s.
fn analytic(p: Vec2) -> Vec2 {
    Vec2::new((p.y / 50.0).sin() * 2.0, (p.x / 70.0).cos() * 1.5)
}

fn field() -> FlowField {
    let n = 512;
    let ts = 0.5;
    let origin = Vec2::new(-100.0, 300.0);
    let flow = (0..n * n)
        .map(|i| analytic(origin + (Vec2::new((i % n) as f32, (i / n) as f32) + 0.5) * ts))
        .collect();
    FlowField::from_flow(n, n, ts, origin, flow).unwrap()
}

fn settings() -> FlowAtlasSettings {
    FlowAtlasSettings {
        tile_res: 32,
        width: 512,
        slots: 12,
        ..Default::default()
    }
}

#[test]
fn resident_tiles_and_world_map_match_the_field() {
    let f = field();
    let s = settings();
    // Sectors with x + y even are resident.
    let atlas =
        FlowAtlas::build(&f, &s, |c| (c.x + c.y) % 2 == 0, &mut water::no_progress).unwrap();
    assert_eq!(atlas.sectors(), UVec2::new(4, 4));
    assert_eq!(atlas.resident_count(), 8);
    let mut rng = testkit::Rng::new(7);
    let (mut tile_err, mut map_err) = (0.0f32, 0.0f32);
    for _ in 0..20_000 {
        let p = f.origin() + Vec2::new(rng.f32(), rng.f32()) * 256.0;
        let got = atlas.sample(p).unwrap();
        let sector = atlas.sector_of(p).unwrap();
        let e = (got - analytic(p)).length();
        // Away from the field's outer edge, where sampling clamps.
        let inner = |m: f32| {
            (p - f.origin()).min_element() > m && (f.origin() + 256.0 - p).min_element() > m
        };
        if atlas.tile_slot(sector).is_some() {
            if inner(2.0) {
                tile_err = tile_err.max(e);
            }
        } else if inner(8.0) {
            map_err = map_err.max(e);
        }
    }
    eprintln!("max error: tiles {tile_err:.4} m/s, world map {map_err:.4} m/s");
    // Tiles: 2 m texels of a field with curvature ~ 2/50^2, plus 16-bit steps of 16 m/s.
    assert!(tile_err < 0.002, "{tile_err}");
    // The 8 m world map: a box filter and bilinear over 8 m.
    assert!(map_err < 0.03, "{map_err}");
    assert_eq!(atlas.sample(f.origin() - 1.0), None);
    assert_eq!(atlas.sample(Vec2::NAN), None);
}

#[test]
fn tiles_meet_seamlessly_at_sector_borders() {
    let f = field();
    let s = FlowAtlasSettings {
        slots: 16,
        ..settings()
    };
    let atlas = FlowAtlas::build(&f, &s, |_| true, &mut water::no_progress).unwrap();
    for k in 0..200 {
        let y = f.origin().y + 1.0 + k as f32 * 1.27;
        let x = f.origin().x + 64.0;
        let (a, b) = (
            atlas.sample(Vec2::new(x - 1e-3, y)).unwrap(),
            atlas.sample(Vec2::new(x, y)).unwrap(),
        );
        assert!((a - b).length() < 2e-3, "step at the border: {a} {b}");
    }
}

#[test]
fn streaming_tiles_in_and_out() {
    let f = field();
    let s = settings();
    let mut atlas = FlowAtlas::build(&f, &s, |_| false, &mut water::no_progress).unwrap();
    let p = f.origin() + Vec2::new(100.0, 30.0);
    let sector = atlas.sector_of(p).unwrap();
    let from_map = atlas.sample(p).unwrap();
    let slot = atlas
        .insert(sector, &FlowAtlas::tile_texels(&f, &s, sector))
        .unwrap();
    assert_eq!(atlas.tile_slot(sector), Some(slot));
    let from_tile = atlas.sample(p).unwrap();
    assert!((from_tile - analytic(p)).length() < 0.01);
    assert_ne!(from_tile, from_map);
    assert!(atlas.evict(sector));
    assert!(!atlas.evict(sector));
    assert_eq!(atlas.sample(p).unwrap(), from_map);
    // Fill every slot, then one more is an error.
    let mut n = 0;
    for y in 0..4 {
        for x in 0..4 {
            let c = UVec2::new(x, y);
            match atlas.insert(c, &FlowAtlas::tile_texels(&f, &s, c)) {
                Ok(_) => n += 1,
                Err(e) => {
                    assert_eq!(
                        e,
                        water::Error::AtlasFull {
                            capacity: atlas.slot_capacity()
                        }
                    );
                }
            }
        }
    }
    assert_eq!(n, atlas.slot_capacity());
    assert!(atlas.insert(UVec2::new(9, 9), &[]).is_err());
}

#[test]
fn texels_roundtrip_and_corruption_is_rejected() {
    let f = field();
    let atlas = FlowAtlas::build(&f, &settings(), |c| c.x == 1, &mut water::no_progress).unwrap();
    let again = FlowAtlas::from_texels(atlas.texels().to_vec()).unwrap();
    assert_eq!(again, atlas);
    for (word, value) in [(0usize, 0u32), (2, 7), (7, 1000), (12, 100_000), (24, 9999)] {
        let mut t = atlas.texels().to_vec();
        t[word] = value;
        assert!(
            FlowAtlas::from_texels(t).is_err(),
            "word {word} = {value} accepted"
        );
    }
    let mut t = atlas.texels().to_vec();
    t.pop();
    assert!(FlowAtlas::from_texels(t).is_err());
}
