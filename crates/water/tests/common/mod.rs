//! Fixtures shared by the integration tests (each test file includes this as a module).

use water::glam::{Vec2, Vec3};
use water::world::{Lake, Ocean, River, RiverPoint, WaterWorld, WaterWorldBuilder};

/// An ocean at 0 m (material 0), a 60 x 40 m lake at 10 m (material 1), and a river
/// (material 2) running from (30, 120) at 20 m down into the lake, its last point at
/// height `river_end` over the lake's middle.
pub fn lake_and_river(river_end: f32) -> WaterWorld {
    let mut b = WaterWorldBuilder::new();
    b.ocean = Some(Ocean {
        level: 0.0,
        material: 0,
    });
    b.lakes.push(Lake {
        polygon: vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(60.0, 0.0),
            Vec2::new(60.0, 40.0),
            Vec2::new(0.0, 40.0),
        ],
        height: 10.0,
        material: 1,
    });
    let p = |x: f32, y: f32, z: f32| river_point(Vec3::new(x, y, z), 8.0, 1.5, 2.0);
    b.rivers.push(River {
        points: vec![
            p(30.0, 120.0, 20.0),
            p(30.0, 60.0, 14.0),
            p(30.0, 20.0, river_end),
        ],
        material: 2,
    });
    b.build(&mut water::no_progress).unwrap()
}

/// A river control point.
pub fn river_point(position: Vec3, width: f32, depth: f32, speed: f32) -> RiverPoint {
    RiverPoint {
        position,
        width,
        depth,
        speed,
    }
}
