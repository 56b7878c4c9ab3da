//! The "river" demo: Far Cry 5's water (seed 003) over a terrain. A river with rapids runs
//! down a plateau between rocks, falls over a cliff into a lake, and the lake's outflow
//! runs down to the ocean's edge. Everything is built with `water::WaterWorldBuilder`
//! (lakes, rivers, the ocean), the terrain is carved to the water (channels under the
//! rivers, a basin under the lake, banks rising from the shores), the flow is baked by the
//! SDF-guided flood fill over the shore distance field (rocks are islands in it, so the
//! flow parts around them) into the flow atlas, and the same distance field gives the
//! shore foam. Trees, bushes, grass and rocks stand on the banks, so the opaque frame still
//! exercises deferred texturing.
//!
//! Coordinates: the water crate's +Z up `(x, y, z)` is the renderer's `(x, z, -y)`.

use std::ops::ControlFlow;

use glam::{Affine3A, Quat, Vec2, Vec3};
use water::atlas::{FlowAtlas, FlowAtlasSettings};
use water::decal::DecalTexture;
use water::flowbake::{FlowBakeInput, FlowBakeSettings, FlowSource};
use water::material::WaterMaterial;
use water::optics::WaterType;
use water::world::{Lake, Ocean, River as WaterRiver, RiverPoint, WaterWorldBuilder};

use super::{
    MeshBuilder, Rng, bush_mesh, canopy_mesh, count, forest_layers, material, rock_mesh,
    trunk_mesh, tuft_mesh,
};
use scene::{
    Batch, MaterialId, Mesh, MeshId, Scene, ShaderKind, ShoreField, WaterDecal, WaterScene,
};
use scene::{Camera, FrameInput, Lighting, PointLight};

/// Half the side of the square the scene covers, metres.
pub const HALF_EXTENT: f32 = 192.0;
/// The lake's surface height, metres.
pub const LAKE_HEIGHT: f32 = 12.0;
/// Metres per texel of the flow bake and the shore field.
pub const FLOW_TEXEL: f32 = 1.0;

/// The river demo: the opaque scene, its water, and a view over the rapids towards the
/// waterfall, the lake and the sea.
pub struct RiverDemo {
    /// Terrain, rocks and foliage.
    pub scene: Scene,
    /// The baked world, materials, flow atlas, shore field and a splash decal texture.
    pub water: WaterScene,
    /// The sources the world was built from (rivers, lake, ocean; water coordinates).
    pub builder: WaterWorldBuilder,
    /// Splashes at the waterfall's foot (water coordinates).
    pub decals: Vec<WaterDecal>,
    /// The view.
    pub frame: FrameInput,
}

/// Water-space control points of the upper river: the plateau, the rapids between the
/// rocks, the cliff's edge and the waterfall's foot in the lake.
fn upper_river() -> Vec<RiverPoint> {
    let p = |x: f32, y: f32, z: f32, width: f32, speed: f32| RiverPoint {
        position: Vec3::new(x, y, z),
        width,
        depth: 1.6,
        speed,
    };
    vec![
        p(150.0, 185.0, 42.0, 14.0, 1.5),
        p(130.0, 150.0, 40.0, 15.0, 1.8),
        p(118.0, 118.0, 38.0, 14.0, 2.0),
        // Rapids: the bed steepens, the river narrows and speeds up between the rocks.
        p(100.0, 92.0, 34.0, 12.0, 3.5),
        p(80.0, 70.0, 30.0, 11.0, 4.5),
        p(62.0, 52.0, 27.0, 12.0, 4.5),
        p(42.0, 36.0, 24.5, 13.0, 3.0),
        p(22.0, 20.0, 23.0, 14.0, 2.5),
        // The cliff's edge, then a short steep drop: the waterfall.
        p(6.0, 7.0, 22.0, 14.0, 3.0),
        p(1.0, 2.0, 21.6, 14.0, 4.0),
        p(-3.0, -3.0, 12.6, 12.0, 6.0),
        p(-8.0, -9.0, 12.2, 12.0, 2.0),
    ]
}

/// The lake's outflow down to the sea.
fn outflow() -> Vec<RiverPoint> {
    let p = |x: f32, y: f32, z: f32, width: f32| RiverPoint {
        position: Vec3::new(x, y, z),
        width,
        depth: 1.2,
        speed: 1.6,
    };
    vec![
        p(-52.0, -70.0, 12.0, 10.0),
        p(-62.0, -95.0, 9.0, 10.0),
        p(-68.0, -120.0, 5.5, 11.0),
        p(-70.0, -145.0, 2.0, 13.0),
        p(-72.0, -172.0, 0.3, 16.0),
    ]
}

/// The lake's outline: a wobbly ellipse around (-22, -38).
fn lake_outline() -> Vec<Vec2> {
    (0..40)
        .map(|i| {
            let a = i as f32 / 40.0 * std::f32::consts::TAU;
            let r = 1.0 + 0.08 * (3.0 * a).sin() + 0.05 * (5.0 * a + 1.0).cos();
            Vec2::new(-22.0, -38.0) + Vec2::new(a.cos() * 46.0, a.sin() * 40.0) * r
        })
        .collect()
}

/// The nearest point of the polyline through `points` to `p`: (distance, surface height,
/// half width, depth, speed).
fn nearest_on_river(points: &[RiverPoint], p: Vec2) -> (f32, f32, f32, f32) {
    let mut best = (f32::INFINITY, 0.0, 0.0, 0.0);
    for w in points.windows(2) {
        let (a, b) = (w[0].position.truncate(), w[1].position.truncate());
        let ab = b - a;
        let t = ((p - a).dot(ab) / ab.length_squared().max(1e-6)).clamp(0.0, 1.0);
        let d = (a + ab * t - p).length();
        if d < best.0 {
            let lerp = |x: f32, y: f32| x + (y - x) * t;
            best = (
                d,
                lerp(w[0].position.z, w[1].position.z),
                lerp(w[0].width, w[1].width) * 0.5,
                lerp(w[0].depth, w[1].depth),
            );
        }
    }
    best
}

/// Distance from `p` to the closed polygon `poly`, negative inside.
fn signed_distance(poly: &[Vec2], p: Vec2) -> f32 {
    let mut d = f32::INFINITY;
    let mut inside = false;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        let ab = b - a;
        let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
        d = d.min((a + ab * t - p).length());
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y) {
            inside = !inside;
        }
    }
    if inside { -d } else { d }
}

fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The terrain's height at water-space `p`: a plateau north of a cliff line through the
/// waterfall, lowlands around the lake sloping to the sea, hills, the channels, the lake's
/// basin.
pub fn terrain_height(p: Vec2, seed: u32) -> f32 {
    let s = p.y + 0.25 * p.x;
    let lowland = 14.5 - 22.0 * smoothstep(-95.0, -185.0, p.y);
    let plateau = 24.5 + 0.09 * s.max(0.0);
    let hills = (super::fbm(p / 40.0, seed, 4, 0) - 0.5) * 7.0;
    let cliff = smoothstep(-7.0, 1.0, s);
    let mut h = lowland + cliff * (plateau - lowland) + hills * (0.4 + 0.6 * cliff);
    for river in [upper_river(), outflow()] {
        let (d, surface, half, depth) = nearest_on_river(&river, p);
        if d < half {
            let s = d / half;
            h = h.min(surface - 0.25 - depth * (1.0 - s * s));
        } else {
            h = h.min(surface - 0.25 + (d - half) * 0.55);
        }
    }
    let sd = signed_distance(&lake_outline(), p);
    if sd < 0.0 {
        h = h.min(LAKE_HEIGHT - 0.3 - (-sd * 0.22).min(7.0));
    } else {
        h = h.min(LAKE_HEIGHT - 0.3 + sd * 0.3);
    }
    h
}

/// Where the rocks in the stream stand (water space, their scale).
fn stream_rocks(rng: &mut Rng) -> Vec<(Vec2, f32)> {
    let river = upper_river();
    let mut out = Vec::new();
    for k in 0..18 {
        // Along the rapids (points 2..7), across most of the width.
        let t = 2.0 + 4.8 * (k as f32 + rng.f32()) / 18.0;
        let i = t.floor() as usize;
        let f = t - i as f32;
        let (a, b) = (
            river[i].position.truncate(),
            river[i + 1].position.truncate(),
        );
        let c = a + (b - a) * f;
        let side = (b - a).perp().normalize_or_zero();
        let half = (river[i].width + (river[i + 1].width - river[i].width) * f) * 0.5;
        out.push((c + side * rng.range(-0.7, 0.7) * half, rng.range(0.6, 1.4)));
    }
    out
}

/// A 16x16, 4-frame splash: a ring of upward displacement that spreads and falls.
fn splash_texture() -> DecalTexture {
    let (n, frames) = (16u32, 4u32);
    let mut texels = Vec::with_capacity((n * n * frames) as usize);
    for f in 0..frames {
        let ring = 0.25 + 0.15 * f as f32;
        let height = 0.9 - 0.2 * f as f32;
        for y in 0..n {
            for x in 0..n {
                let p = (Vec2::new(x as f32, y as f32) + 0.5) / n as f32 * 2.0 - 1.0;
                let r = p.length();
                let bump = (-((r - ring) * 8.0).powi(2)).exp() * height;
                // Up (box z), and a little outwards.
                let out = p.normalize_or_zero() * bump * 0.2;
                texels.push(Vec3::new(out.x, out.y, bump));
            }
        }
    }
    DecalTexture::new(n, n, frames, texels).expect("a valid splash")
}

/// Builds the river demo (`density` scales the foliage; the water does not change with
/// it), reporting the world bake's, the distance field's, the flow bake's and the atlas's
/// progress.
///
/// # Errors
/// What the water crate's bakes return (cancelled by `progress`).
pub fn river(
    seed: u64,
    density: f32,
    progress: &mut impl FnMut(water::Progress) -> ControlFlow<()>,
) -> Result<RiverDemo, water::Error> {
    let density = if density.is_finite() {
        density.max(0.0)
    } else {
        0.0
    };
    let mut rng = Rng::new(seed ^ 0x0072_6976_6572);
    let tseed = seed as u32;
    let mut builder = WaterWorldBuilder::new();
    builder.ocean = Some(Ocean {
        level: 0.0,
        material: 0,
    });
    builder.lakes.push(Lake {
        polygon: lake_outline(),
        height: LAKE_HEIGHT,
        material: 2,
    });
    builder.rivers.push(WaterRiver {
        points: upper_river(),
        material: 1,
    });
    builder.rivers.push(WaterRiver {
        points: outflow(),
        material: 3,
    });
    let world = builder.build(progress)?;
    let rocks = stream_rocks(&mut rng);
    // The water mask (terrain under the surface, rocks excepted), its distance field, the
    // flow bake around the rocks, the atlas.
    let side = (2.0 * HALF_EXTENT / FLOW_TEXEL) as u32;
    let origin = Vec2::splat(-HALF_EXTENT);
    let mask: Vec<u8> = (0..side * side)
        .map(|k| {
            let p = origin + (Vec2::new((k % side) as f32, (k / side) as f32) + 0.5) * FLOW_TEXEL;
            let wet = world
                .query(p)
                .is_some_and(|q| q.height > terrain_height(p, tseed) + 0.02);
            let rock = rocks.iter().any(|(c, s)| (p - *c).length() < 0.9 * s);
            u8::from(!wet || rock)
        })
        .collect();
    let sdf = water::edt::signed_edt(&mask, side, side, progress)?;
    let foot = upper_river()
        .last()
        .map_or(Vec2::ZERO, |p| p.position.truncate());
    let sources = [FlowSource {
        position: foot,
        velocity: (Vec2::new(-22.0, -38.0) - foot).normalize_or_zero() * 2.0,
        radius: 6.0,
    }];
    let field = water::flowbake::bake_flow(
        &FlowBakeInput {
            sdf: &sdf,
            texel_size: FLOW_TEXEL,
            origin,
            rivers: &builder.rivers,
            sources: &sources,
        },
        &FlowBakeSettings::default(),
        progress,
    )?;
    let atlas = FlowAtlas::build(
        &field,
        &FlowAtlasSettings {
            sector_size: 64.0,
            tile_res: 64,
            width: 2048,
            max_speed: 8.0,
            slots: 64,
            ..FlowAtlasSettings::default()
        },
        |_| true,
        progress,
    )?;
    let mut materials = vec![
        WaterMaterial::from_type(&WaterType::CLEAR_OCEAN),
        WaterMaterial::from_type(&WaterType::RIVER),
        WaterMaterial::from_type(&WaterType::RIVER.with_turbidity(0.35)),
        WaterMaterial::from_type(&WaterType::MUDDY.with_turbidity(0.25)),
    ];
    for (m, amp, foam) in [
        (0, 0.45, 0.8),
        (1, 0.22, 1.0),
        (2, 0.07, 0.7),
        (3, 0.12, 0.9),
    ] {
        materials[m].displacement_amplitude = amp;
        materials[m].foam_intensity = foam;
    }
    materials[0].roughness = 0.06;
    materials[2].roughness = 0.04;
    let mut water = WaterScene::new(world, materials);
    water.fbm.frequency = 1.0 / 24.0;
    water.flow = Some(atlas);
    water.shore = Some(ShoreField {
        field: sdf,
        origin,
        texel_size: FLOW_TEXEL,
    });
    water.decal_textures.push(splash_texture());
    let decals = (0..3)
        .map(|k| {
            let c = foot + Vec2::new(k as f32 * 4.0 - 4.0, -2.0 - 2.0 * k as f32);
            WaterDecal {
                box_to_world: Affine3A::from_scale_rotation_translation(
                    Vec3::new(5.0, 5.0, 1.0),
                    Quat::from_rotation_z(k as f32),
                    c.extend(LAKE_HEIGHT),
                ),
                texture: 0,
                strength: 0.6,
                frame: k as f32 * 1.3,
                fade: 0.3,
            }
        })
        .collect();
    let scene = opaque(seed, density, &rocks, &water.world);
    // From the plateau east of the rapids: the rocks in the stream, the waterfall's edge,
    // the lake below and the sea beyond the lowlands.
    let camera = Camera::look_at(Vec3::new(60.0, 40.0, -40.0), Vec3::new(-10.0, 10.0, 20.0));
    let lamp = |x: f32, y: f32, color: Vec3| PointLight {
        position: Vec3::new(x, LAKE_HEIGHT + 2.5, -y),
        color,
        radius: 14.0,
        specular: true,
    };
    let lighting = Lighting {
        point_lights: vec![
            lamp(14.0, -30.0, Vec3::new(6.0, 3.5, 1.2)),
            lamp(-8.0, 2.0, Vec3::new(1.5, 3.0, 6.0)),
        ],
        ..Lighting::default()
    };
    Ok(RiverDemo {
        scene,
        water,
        builder,
        decals,
        frame: FrameInput {
            camera,
            time: 0.0,
            lighting,
        },
    })
}

/// Terrain tile `(ti, tj)` of `tiles` x `tiles` over the scene's square, `cells` a side
/// (the vis buffer's 16-bit primitive IDs take at most 65 536 triangles a mesh), +Y up.
fn terrain_tile(ti: u32, tj: u32, tiles: u32, cells: u32, seed: u32) -> Mesh {
    let mut b = MeshBuilder::new("river terrain");
    let h = |x: f32, y: f32| terrain_height(Vec2::new(x, y), seed);
    let size = 2.0 * HALF_EXTENT / tiles as f32;
    let (x0, y0) = (
        -HALF_EXTENT + ti as f32 * size,
        HALF_EXTENT - tj as f32 * size,
    );
    for j in 0..=cells {
        for i in 0..=cells {
            // Water (x, y); the mesh's +Y-up z is -y.
            let x = x0 + i as f32 / cells as f32 * size;
            let y = y0 - j as f32 / cells as f32 * size;
            let e = 0.5;
            let n = Vec3::new(
                h(x - e, y) - h(x + e, y),
                2.0 * e,
                h(x, y + e) - h(x, y - e),
            );
            b.vertex(Vec3::new(x, h(x, y), -y), n, Vec2::new(x, -y) / 4.0);
        }
    }
    b.grid_quads(cells);
    b.finish()
}

/// The opaque scene: terrain, the stream's rocks, and on dry banks trees, bushes, grass
/// and rocks (none where the world has water above the terrain).
fn opaque(
    seed: u64,
    density: f32,
    stream: &[(Vec2, f32)],
    world: &water::world::WaterWorld,
) -> Scene {
    let mut rng = Rng::new(seed ^ 0x6261_6e6b);
    let tseed = seed as u32;
    let mut meshes = vec![
        trunk_mesh(),
        canopy_mesh(&mut rng, 200),
        bush_mesh(&mut rng, 9),
        tuft_mesh(&mut rng, 4, 0.7),
        rock_mesh(tseed ^ 0x55),
    ];
    // The terrain in 3 x 3 tiles of 128 cells (1 m).
    let first_tile = meshes.len();
    for t in 0..9 {
        meshes.push(terrain_tile(t % 3, t / 3, 3, 128, tseed));
    }
    let albedo_layers = forest_layers();
    let materials = vec![
        material("ground", ShaderKind::Opaque, 0, 0.9),
        material("bark", ShaderKind::Opaque, 1, 0.8),
        material("leaves", ShaderKind::AlphaTested, 2, 0.6),
        material("fern", ShaderKind::AlphaTested, 3, 0.6),
        material("grass", ShaderKind::AlphaTested, 4, 0.7),
        material("rock", ShaderKind::Opaque, 5, 0.7),
    ];
    let dry = |p: Vec2| {
        let t = terrain_height(p, tseed);
        t > 0.5 && world.candidates(p).iter().all(|q| q.height < t - 0.4)
    };
    let to_y_up = |p: Vec2, h: f32| Vec3::new(p.x, h, -p.y);
    let scatter = |n: usize, scale: (f32, f32), rng: &mut Rng| -> Vec<Affine3A> {
        let mut out = Vec::with_capacity(n);
        let mut tries = 0;
        while out.len() < n && tries < n * 20 {
            tries += 1;
            let p = Vec2::new(
                rng.range(-HALF_EXTENT * 0.95, HALF_EXTENT * 0.95),
                rng.range(-HALF_EXTENT * 0.95, HALF_EXTENT * 0.95),
            );
            if !dry(p) {
                continue;
            }
            let s = rng.range(scale.0, scale.1);
            out.push(Affine3A::from_scale_rotation_translation(
                Vec3::splat(s),
                Quat::from_rotation_y(rng.range(0.0, std::f32::consts::TAU)),
                to_y_up(p, terrain_height(p, tseed) - 0.05),
            ));
        }
        out
    };
    let trees = scatter(count(220.0, density), (0.8, 1.3), &mut rng);
    let bushes = scatter(count(1500.0, density), (0.7, 1.4), &mut rng);
    let grass = scatter(count(6000.0, density), (0.8, 1.3), &mut rng);
    let mut rocks = scatter(count(160.0, density), (0.5, 1.8), &mut rng);
    // The stream's rocks, a third of their height out of the water.
    for &(c, s) in stream {
        let h = world.query(c).map_or(0.0, |q| q.height);
        rocks.push(Affine3A::from_scale_rotation_translation(
            Vec3::new(s * 1.2, s * 1.1, s * 1.2),
            Quat::from_rotation_y(rng.range(0.0, std::f32::consts::TAU)),
            to_y_up(c, h - 0.25 * s),
        ));
    }
    let batch = |mesh: usize, material: usize, instances: Vec<Affine3A>| Batch {
        mesh: MeshId(mesh),
        material: MaterialId(material),
        instances,
    };
    Scene {
        data_layers: Vec::new(),
        meshes,
        materials,
        albedo_layers,
        batches: (first_tile..first_tile + 9)
            .map(|m| batch(m, 0, vec![Affine3A::IDENTITY]))
            .chain([
                batch(0, 1, trees.clone()),
                batch(1, 2, trees),
                batch(2, 3, bushes),
                batch(3, 4, grass),
                batch(4, 5, rocks),
            ])
            .collect(),
        static_setups: Vec::new(),
        wind: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_river_scene_builds_validates_and_has_every_body() {
        let mut stages = std::collections::BTreeSet::new();
        let demo = river(1, 0.1, &mut |p: water::Progress| {
            stages.insert(format!("{:?}", p.stage));
            ControlFlow::Continue(())
        })
        .unwrap();
        demo.scene.validate().unwrap();
        demo.frame.validate().unwrap();
        let w = &demo.water.world;
        assert_eq!((w.lake_count(), w.river_count()), (1, 2));
        assert!(w.ocean().is_some());
        for s in ["RiverTiles", "DistanceRows", "FlowFill", "AtlasTiles"] {
            assert!(stages.contains(s), "{s} not reported: {stages:?}");
        }
        // The rapids flow fast downstream; the lake is still but for the waterfall's foot.
        let rapids = w.query(Vec2::new(80.0, 70.0)).unwrap();
        assert!(rapids.flow.length() > 3.0, "{rapids:?}");
        let atlas = demo.water.flow.as_ref().unwrap();
        let f = atlas.sample(Vec2::new(80.0, 70.0)).unwrap();
        assert!(f.length() > 1.0, "{f}");
        // Water stands over the terrain in the channel and the lake, not on the banks.
        for p in [
            Vec2::new(80.0, 70.0),
            Vec2::new(-22.0, -38.0),
            Vec2::new(-70.0, -145.0),
        ] {
            let q = w.query(p).unwrap();
            assert!(q.height > terrain_height(p, 1) + 0.2, "{p}: {q:?}");
        }
        // The waterfall drops about nine metres.
        let top = w.query(Vec2::new(3.0, 4.5)).unwrap().height;
        let bottom = w.query(Vec2::new(-6.0, -6.5)).unwrap().height;
        assert!(top - bottom > 7.0, "{top} {bottom}");
    }
}
