//! The material scene: glTF 2.0's metallic-roughness model feature by feature. Spheres over
//! metallic (left to right, 0 to 1) × roughness (front row to back, 0.1 to 0.9); a brick
//! wall with a normal and occlusion map whose left half reads its texture mirrored (u runs
//! right to left, handedness −1); an emissive panel under an emissive map; a plate with a
//! metallic-roughness map (metal tiles in rough stone); alpha-masked leaf cards that show
//! both faces; all on a ground plane.

use super::*;
use scene::{DataLayer, MaterialMaps, NormalMap, OcclusionMap};

/// Bricks per row and rows of the wall's texture (one texture repeat).
const BRICKS: (f32, f32) = (4.0, 8.0);
/// The mortar's half width, in brick heights.
const MORTAR: f32 = 0.08;
/// The bevel at a brick's edge: how far (in brick heights) its face slopes to the mortar.
const BEVEL: f32 = 0.12;

/// The brick relief's height at `uv` (1 on a brick's face, 0 in the mortar, a linear bevel
/// between), as the wall's normal and occlusion maps encode it.
pub fn brick_height(uv: Vec2) -> f32 {
    let row = (uv.y * BRICKS.1).floor();
    let shift = if row as i32 % 2 == 0 { 0.0 } else { 0.5 };
    let fx = (uv.x * BRICKS.0 + shift).fract();
    let fy = (uv.y * BRICKS.1).fract();
    // Distance to the nearest joint, in brick heights (a brick is 2 heights wide).
    let aspect = BRICKS.1 / BRICKS.0;
    let d = (fx.min(1.0 - fx) * aspect).min(fy.min(1.0 - fy));
    ((d - MORTAR) / BEVEL).clamp(0.0, 1.0)
}

fn data_layer(f: impl Fn(Vec2) -> [u8; 4]) -> DataLayer {
    let n = LAYER_SIZE;
    let texels = (0..n * n)
        .map(|i| {
            f(Vec2::new(
                ((i % n) as f32 + 0.5) / n as f32,
                ((i / n) as f32 + 0.5) / n as f32,
            ))
        })
        .collect();
    DataLayer { size: n, texels }
}

/// The bricks' tangent-space normal map (glTF's convention: +X along +u, +Y along −v, the
/// image's up), from central differences of [`brick_height`] at a relief depth of 2 cm per
/// wall metre of texture.
fn brick_normals() -> DataLayer {
    let e = 0.5 / LAYER_SIZE as f32;
    let depth = 0.04;
    data_layer(|uv| {
        let dx = brick_height(uv + Vec2::new(e, 0.0)) - brick_height(uv - Vec2::new(e, 0.0));
        let dy = brick_height(uv + Vec2::new(0.0, e)) - brick_height(uv - Vec2::new(0.0, e));
        // +Y is −v: the height's slope along +Y is −dy.
        let n = Vec3::new(-dx / (2.0 * e) * depth, dy / (2.0 * e) * depth, 1.0).normalize();
        let c = |x: f32| ((x * 0.5 + 0.5) * 255.0).round() as u8;
        [c(n.x), c(n.y), c(n.z), 255]
    })
}

/// The bricks' occlusion (R: the mortar lies in shade), rough everywhere (G 1, B 0).
fn brick_occlusion() -> DataLayer {
    data_layer(|uv| {
        let o = 0.35 + 0.65 * brick_height(uv);
        [(o * 255.0).round() as u8, 255, 0, 255]
    })
}

/// Metal tiles in rough stone: G roughness, B metallic (glTF's packing), R unused.
fn tile_metal_roughness() -> DataLayer {
    data_layer(|uv| {
        let t = ((uv * 4.0).fract() - 0.5).abs().max_element();
        let metal = t < 0.38;
        let noise = tile_noise(uv, 32, 9);
        if metal {
            [255, (40.0 + 40.0 * noise) as u8, 255, 255]
        } else {
            [255, (200.0 + 55.0 * noise) as u8, 0, 255]
        }
    })
}

/// A UV sphere of `radius` about the origin (u around, v from the top).
fn sphere_mesh(radius: f32) -> Mesh {
    let (around, down) = (32u32, 16u32);
    let mut b = MeshBuilder::new("sphere");
    for j in 0..=down {
        let v = j as f32 / down as f32;
        let (st, ct) = (v * std::f32::consts::PI).sin_cos();
        for i in 0..=around {
            let u = i as f32 / around as f32;
            let (sp, cp) = (u * std::f32::consts::TAU).sin_cos();
            let n = Vec3::new(st * cp, ct, -st * sp);
            b.vertex(n * radius, n, Vec2::new(u, v));
        }
    }
    let w = (around + 1) as u16;
    for j in 0..down as u16 {
        for i in 0..around as u16 {
            let (a, c) = (j * w + i, (j + 1) * w + i);
            b.quad(a, c, c + 1, a + 1);
        }
    }
    b.finish()
}

/// A quad in the plane through `o` spanned by half-extents `r` (right) and `u` (up),
/// facing `r × u`, its texture `uv0` at the top-left and `uv1` at the bottom-right (a
/// `uv0.x > uv1.x` mirrors it).
fn panel(b: &mut MeshBuilder, o: Vec3, r: Vec3, u: Vec3, uv0: Vec2, uv1: Vec2) {
    let n = r.cross(u).normalize_or(Vec3::Z);
    let a = b.vertex(o - r - u, n, Vec2::new(uv0.x, uv1.y));
    let c = b.vertex(o + r - u, n, Vec2::new(uv1.x, uv1.y));
    let d = b.vertex(o + r + u, n, Vec2::new(uv1.x, uv0.y));
    let e = b.vertex(o - r + u, n, Vec2::new(uv0.x, uv0.y));
    b.quad(a, c, d, e);
}

/// The material scene and its view.
pub(crate) fn materials(paint: bool) -> (Scene, FrameInput) {
    // Albedo layers: white, ground, leaf, bricks' colour, stone, the emissive stripes.
    let albedo_layers = if paint {
        vec![
            AlbedoLayer {
                size: LAYER_SIZE,
                texels: vec![[255; 4]; (LAYER_SIZE * LAYER_SIZE) as usize],
            },
            ground_layer(),
            leaf_layer(),
            layers::paint(|uv| {
                let h = brick_height(uv);
                let n = tile_noise(uv, 48, 3);
                let brick = Vec3::new(0.55, 0.22, 0.14) * (0.8 + 0.4 * n);
                (Vec3::splat(0.6).lerp(brick, h), 1.0)
            }),
            layers::paint(|uv| (Vec3::splat(0.45 + 0.2 * tile_noise(uv, 24, 5)), 1.0)),
            layers::paint(|uv| {
                let on = (uv.x * 6.0).fract() < 0.5;
                (if on { Vec3::ONE } else { Vec3::splat(0.1) }, 1.0)
            }),
        ]
    } else {
        Vec::new()
    };
    let data_layers = if paint {
        vec![brick_normals(), brick_occlusion(), tile_metal_roughness()]
    } else {
        Vec::new()
    };
    let gold = Vec3::new(1.0, 0.78, 0.34);
    let mut materials = vec![
        material("ground", ShaderKind::Opaque, 1, 0.9),
        Material {
            maps: MaterialMaps {
                normal: Some(NormalMap {
                    layer: 0,
                    scale: 1.0,
                }),
                occlusion: Some(OcclusionMap {
                    layer: 1,
                    strength: 1.0,
                }),
                ..MaterialMaps::default()
            },
            specular: 0.5,
            ..material("bricks", ShaderKind::Opaque, 3, 0.85)
        },
        Material {
            emissive: Vec3::new(3.0, 1.6, 0.5),
            maps: MaterialMaps {
                emissive: Some(5),
                ..MaterialMaps::default()
            },
            tint: Vec3::splat(0.1),
            ..material("emissive panel", ShaderKind::Opaque, 0, 0.5)
        },
        Material {
            metallic: 1.0,
            maps: MaterialMaps {
                metallic_roughness: Some(2),
                ..MaterialMaps::default()
            },
            ..material("metal tiles", ShaderKind::Opaque, 4, 1.0)
        },
        material("leaves", ShaderKind::AlphaTested, 2, 0.6),
    ];
    let first_sphere = materials.len();
    let (columns, rows) = (5, 4);
    for row in 0..rows {
        for column in 0..columns {
            let roughness = 0.1 + 0.8 * row as f32 / (rows - 1) as f32;
            let metallic = column as f32 / (columns - 1) as f32;
            materials.push(Material {
                metallic,
                tint: gold,
                ..material(
                    &format!("sphere metallic {metallic} roughness {roughness}"),
                    ShaderKind::Opaque,
                    0,
                    roughness,
                )
            });
        }
    }
    for m in &mut materials {
        m.specular = 1.0;
    }
    let mut ground = MeshBuilder::new("ground");
    panel(
        &mut ground,
        Vec3::ZERO,
        Vec3::new(12.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, -12.0),
        Vec2::ZERO,
        Vec2::splat(6.0),
    );
    // The wall, 6 m x 3 m: its right half reads the texture as it is, its left half mirrored.
    let mut wall = MeshBuilder::new("brick wall");
    let (half, up) = (Vec3::new(1.5, 0.0, 0.0), Vec3::new(0.0, 1.5, 0.0));
    panel(
        &mut wall,
        Vec3::new(1.5, 1.5, -3.0),
        half,
        up,
        Vec2::ZERO,
        Vec2::new(1.0, 1.0),
    );
    panel(
        &mut wall,
        Vec3::new(-1.5, 1.5, -3.0),
        half,
        up,
        Vec2::new(1.0, 0.0),
        Vec2::new(0.0, 1.0),
    );
    let mut glow = MeshBuilder::new("emissive panel");
    panel(
        &mut glow,
        Vec3::new(-4.2, 1.2, -2.0),
        Vec3::new(0.6, 0.0, 0.5),
        Vec3::new(0.0, 0.8, 0.0),
        Vec2::ZERO,
        Vec2::ONE,
    );
    let mut plate = MeshBuilder::new("metal tiles");
    panel(
        &mut plate,
        Vec3::new(4.2, 0.01, 0.5),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, -1.0),
        Vec2::ZERO,
        Vec2::ONE,
    );
    let mut cards = MeshBuilder::new("leaf cards");
    for k in 0..3 {
        let x = 4.0 + 0.5 * k as f32;
        let turn = Vec3::new((0.6 * k as f32).cos(), 0.0, (0.6 * k as f32).sin()) * 0.4;
        cards.card(
            Vec3::new(x, 0.6, -1.5),
            turn,
            Vec3::new(0.0, 0.5, 0.0),
            Vec2::ZERO,
            Vec2::ONE,
            Vec3::ZERO,
        );
    }
    let meshes = vec![
        ground.finish(),
        wall.finish(),
        glow.finish(),
        plate.finish(),
        cards.finish(),
        sphere_mesh(0.4),
    ];
    let mut batches: Vec<Batch> = (0..5)
        .map(|i| Batch {
            mesh: MeshId(i),
            material: MaterialId(i),
            instances: vec![Affine3A::IDENTITY],
        })
        .collect();
    for row in 0..rows {
        for column in 0..columns {
            batches.push(Batch {
                mesh: MeshId(5),
                material: MaterialId(first_sphere + row * columns + column),
                instances: vec![Affine3A::from_translation(Vec3::new(
                    (column as f32 - 2.0) * 1.0,
                    0.4,
                    1.2 - row as f32 * 1.0,
                ))],
            });
        }
    }
    let camera = Camera::look_at(Vec3::new(0.0, 2.6, 6.5), Vec3::new(0.0, 0.9, -0.5));
    let lighting = Lighting {
        sun_direction: Vec3::new(-0.45, 0.6, 0.65).normalize(),
        point_lights: vec![PointLight {
            position: Vec3::new(1.5, 1.8, 2.0),
            color: Vec3::new(3.0, 2.6, 2.2),
            radius: 6.0,
            specular: true,
        }],
        ..Lighting::default()
    };
    (
        Scene {
            meshes,
            materials,
            albedo_layers,
            data_layers,
            batches,
            static_setups: Vec::new(),
            wind: None,
        },
        FrameInput {
            camera,
            time: 0.0,
            lighting,
        },
    )
}

/// Gives every material of `scene` every map of glTF's model, derived from its albedo
/// layer (for measuring the resolve with all maps on the demo scenes): a normal map from
/// the layer's luminance as a height field (central differences, wrapping), an
/// occlusion-roughness-metallic layer (R occlusion darkening with depth, G and B 1: the
/// factors unchanged) and the albedo layer itself as an emissive map under a zero factor
/// (sampled, adding nothing). Two data layers are appended per albedo layer.
pub fn add_material_maps(scene: &mut Scene) {
    let first = scene.data_layers.len() as u32;
    for layer in &scene.albedo_layers {
        let n = layer.size as usize;
        let height = |x: usize, y: usize| {
            let p = layer.texels[(y % n) * n + x % n];
            (0.2126 * f32::from(p[0]) + 0.7152 * f32::from(p[1]) + 0.0722 * f32::from(p[2])) / 255.0
        };
        let mut normal = Vec::with_capacity(n * n);
        let mut orm = Vec::with_capacity(n * n);
        for y in 0..n {
            for x in 0..n {
                let dx = height(x + 1, y) - height(x + n - 1, y);
                let dy = height(x, y + n - 1) - height(x, y + 1);
                let v = Vec3::new(-dx * 2.0, -dy * 2.0, 1.0).normalize();
                let c = |x: f32| ((x * 0.5 + 0.5) * 255.0).round() as u8;
                normal.push([c(v.x), c(v.y), c(v.z), 255]);
                let o = (0.5 + 0.5 * height(x, y)).min(1.0);
                orm.push([(o * 255.0).round() as u8, 255, 255, 255]);
            }
        }
        scene.data_layers.push(DataLayer {
            size: layer.size,
            texels: normal,
        });
        scene.data_layers.push(DataLayer {
            size: layer.size,
            texels: orm,
        });
    }
    for m in &mut scene.materials {
        let (normal, orm) = (first + 2 * m.albedo_layer, first + 2 * m.albedo_layer + 1);
        m.maps = MaterialMaps {
            normal: Some(NormalMap {
                layer: normal,
                scale: 1.0,
            }),
            metallic_roughness: Some(orm),
            occlusion: Some(OcclusionMap {
                layer: orm,
                strength: 1.0,
            }),
            emissive: Some(m.albedo_layer),
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bricks_have_faces_bevels_and_mortar() {
        // A brick's middle is its face, a joint is mortar.
        assert_eq!(brick_height(Vec2::new(0.125, 0.0625)), 1.0);
        assert_eq!(brick_height(Vec2::new(0.0, 0.0625)), 0.0);
        assert_eq!(brick_height(Vec2::new(0.125, 0.0)), 0.0);
        // Odd rows are shifted by half a brick: the even rows' joint is an odd row's face.
        assert_eq!(brick_height(Vec2::new(0.0, 0.1875)), 1.0);
    }

    #[test]
    fn the_scene_is_valid_and_every_feature_is_used() {
        let (scene, frame) = materials(true);
        scene.validate().unwrap();
        // Every map on a forest: valid, and each material has every feature but the
        // alpha test it had.
        let (mut forest, _) = build(&DemoOptions {
            density: 0.05,
            ..DemoOptions::default()
        });
        add_material_maps(&mut forest);
        forest.validate().unwrap();
        assert_eq!(forest.data_layers.len(), 2 * forest.albedo_layers.len());
        assert!(
            forest
                .materials
                .iter()
                .all(|m| m.features().0 & 0b1111 == 0b1111)
        );
        frame.validate().unwrap();
        use scene::MaterialFeatures as F;
        let all = scene
            .materials
            .iter()
            .fold(0, |acc, m| acc | m.features().0);
        assert_eq!(
            all,
            F::NORMAL_MAP.0
                | F::METALLIC_ROUGHNESS_MAP.0
                | F::OCCLUSION_MAP.0
                | F::EMISSIVE.0
                | F::ALPHA_TEST.0
        );
        // The wall's left half has mirrored texture coordinates: handedness −1 there.
        let wall = &scene.meshes[1];
        assert!(wall.tangents[..4].iter().all(|t| t.w > 0.0));
        assert!(wall.tangents[4..].iter().all(|t| t.w < 0.0));
    }
}
