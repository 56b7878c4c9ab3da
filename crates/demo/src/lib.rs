//! Procedural demo scenes, deterministic from a seed: "forest" (alpha-tested foliage cards,
//! grass tufts, trees and rocks over a terrain: many instances, several foliage materials),
//! "grass" (a tall-grass field of very high vertex density) and "hillside" /
//! "hillside-grass" (HFW-like: a meadow of tall grass, blade by blade, before a forest of
//! dense canopies, seen from 15 m up and from 5 m over the grass; grass triangles under a
//! pixel wide at 4K) and "materials" (glTF 2.0's metallic-roughness model, feature by
//! feature).
//!
//! Everything here is generated, no assets are loaded: a terrain height field, meshes built
//! from primitives, and 256×256 albedo layers painted with integer-hashed value noise.
//! The terrain's and the rocks' materials are [`Material::regular`]: HFW's mixed frame
//! (`gpu::RendererConfig::geometry.mixed_frame`) draws them in its regular geometry pass instead of
//! the vis buffer.
//!
//! Nothing here needs a device: the scenes are `scene` descriptions, which `gpu` prepares.
//! The city's tiles are activated on a GPU static query by `gpu::statics::stream_static_world`.
//!
//! ```
//! let (scene, frame) = demo::build(&demo::DemoOptions { density: 0.05, ..Default::default() });
//! scene.validate()?;
//! frame.validate()?;
//! assert!(scene.instance_count() > 0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use glam::{Affine3A, Quat, Vec2, Vec3, Vec4};

use scene::{
    AlbedoLayer, Batch, Camera, FrameInput, Lighting, Material, MaterialId, Mesh, MeshId,
    PointLight, Scene, ShaderKind, SpotLight,
};
use staticscene::demo::Rng;

pub mod city;
mod hillside;
mod layers;
mod materials;
pub use materials::{add_material_maps, brick_height};
mod mesh;
pub mod river;

use layers::*;
use mesh::*;

/// Which demo scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DemoScene {
    /// Dense alpha-tested foliage over a terrain, with trees and rocks.
    Forest,
    /// A field of tall grass: very high vertex density.
    Grass,
    /// HFW-like foliage seen from 15 m up: a meadow of tall grass, blade by blade, before a
    /// forest of dense canopies; grass triangles under a pixel wide at 4K (the talk's
    /// forest case).
    Hillside,
    /// The hillside's tall grass seen from 5 m above it, grass from the bottom of the image
    /// to the horizon (the talk's tall-grass case). The grass is built in rings of level
    /// of detail around each view's camera, so the two scenes' grass differs.
    HillsideGrass,
    /// glTF 2.0's metallic-roughness model feature by feature: spheres over metallic ×
    /// roughness, a normal- and occlusion-mapped brick wall (half of it with mirrored
    /// texture coordinates), an emissive panel, a metallic-roughness-mapped plate,
    /// alpha-masked leaf cards showing both faces.
    Materials,
}

impl DemoScene {
    /// The two scenes every frame test renders (the hillside's small triangles, in both
    /// its views, are for measurements at 4K).
    pub const ALL: [DemoScene; 2] = [DemoScene::Forest, DemoScene::Grass];

    /// The scene's name, as the CLI spells it.
    pub fn name(self) -> &'static str {
        match self {
            DemoScene::Forest => "forest",
            DemoScene::Grass => "grass",
            DemoScene::Hillside => "hillside",
            DemoScene::HillsideGrass => "hillside-grass",
            DemoScene::Materials => "materials",
        }
    }
}

/// Options for [`build`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DemoOptions {
    /// The scene.
    pub scene: DemoScene,
    /// Seed of every random choice.
    pub seed: u64,
    /// Multiplies instance counts (1.0: the default, which renders in seconds on lavapipe).
    pub density: f32,
}

impl Default for DemoOptions {
    fn default() -> Self {
        Self {
            scene: DemoScene::Forest,
            seed: 1,
            density: 1.0,
        }
    }
}

/// Builds a demo scene and the frame it is viewed in (its camera and lights).
///
/// `options.density` is taken as given (a negative or non-finite one makes no instances;
/// a huge one allocates accordingly): check it with [`check_density`] first.
pub fn build(options: &DemoOptions) -> (Scene, FrameInput) {
    generate(options, true)
}

/// The density the generators use: a non-finite or negative one makes no instances.
fn usable_density(options: &DemoOptions) -> f32 {
    if options.density.is_finite() {
        options.density.max(0.0)
    } else {
        0.0
    }
}

fn generate(options: &DemoOptions, paint: bool) -> (Scene, FrameInput) {
    let density = usable_density(options);
    match options.scene {
        DemoScene::Forest => forest(options.seed, density, paint),
        DemoScene::Grass => grass(options.seed, density, paint),
        DemoScene::Hillside => {
            hillside::hillside(options.seed, density, paint, hillside::View::Rise)
        }
        DemoScene::HillsideGrass => {
            hillside::hillside(options.seed, density, paint, hillside::View::TallGrass)
        }
        DemoScene::Materials => materials::materials(paint),
    }
}

/// Why a density does not fit.
#[derive(Clone, Debug, PartialEq)]
pub enum DensityError {
    /// Not a finite number > 0.
    NotPositive {
        /// The density given.
        density: f32,
    },
    /// The scene would break a limit of the talks' plan (`tiling`'s passes, micro-batch
    /// IDs); `max` is the largest density that fits (to two decimals).
    OverLimit {
        /// The density given.
        density: f32,
        /// The limit, as `tiling` names it.
        limit: String,
        /// The largest density that fits.
        max: f32,
    },
}

impl std::fmt::Display for DensityError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DensityError::NotPositive { density } => {
                write!(f, "density {density} is not a finite number above 0")
            }
            DensityError::OverLimit {
                density,
                limit,
                max,
            } => write!(
                f,
                "density {density} breaks a limit of the talk's plan ({limit}); at most density {max:.2} fits"
            ),
        }
    }
}

impl std::error::Error for DensityError {}

/// Vertices one pass may transform times the passes a plan may have: no demo scene of
/// more instance vertices than this can be planned (the vertex ring, seed 000).
fn vertex_budget() -> u64 {
    let c = tiling::PlanConfig::default();
    c.pass_vertex_budget() * u64::from(c.max_passes)
}

/// Instance vertices of the demo at `options`, counted without placing any instance.
fn instance_vertices(options: &DemoOptions) -> u64 {
    let d = usable_density(options);
    let (scene, _) = generate(
        &DemoOptions {
            density: 0.0,
            ..*options
        },
        false,
    );
    let v = |m: usize| scene.meshes[m].positions.len() as u64;
    let n = |x: f32| count(x, d) as u64;
    match options.scene {
        // Terrain, trunks and canopies (one each per tree), ferns, tufts, rocks.
        DemoScene::Forest => {
            v(0) + n(260.0) * (v(1) + v(2).max(v(6)))
                + n(3000.0) * v(3)
                + n(12_000.0) * v(4)
                + n(300.0) * v(5)
        }
        // Terrain, grass patches (both meshes have the same vertex count), rocks.
        DemoScene::Grass => {
            let side = grass_side(d) as u64;
            v(0) + side * side * v(1).max(v(2)) + n(60.0) * v(3)
        }
        // Terrain, trees (trunk and crown), rocks, grass patches by level of detail.
        DemoScene::Hillside => {
            hillside::instance_vertices(options.seed, d, hillside::View::Rise, &scene.meshes)
        }
        DemoScene::HillsideGrass => {
            hillside::instance_vertices(options.seed, d, hillside::View::TallGrass, &scene.meshes)
        }
        // Fixed: one instance of everything, twenty spheres (the density changes nothing).
        DemoScene::Materials => scene
            .batches
            .iter()
            .map(|b| v(b.mesh.0) * b.instances.len() as u64)
            .sum(),
    }
}

/// A lower bound of [`instance_vertices`] found in time independent of the density: the
/// hillside's instances but its grass (0 for the other scenes, whose count is as quick).
fn instance_vertices_floor(options: &DemoOptions) -> u64 {
    if !matches!(
        options.scene,
        DemoScene::Hillside | DemoScene::HillsideGrass
    ) {
        return 0;
    }
    let (scene, _) = generate(
        &DemoOptions {
            density: 0.0,
            ..*options
        },
        false,
    );
    hillside::vertices_but_grass(usable_density(options), &scene.meshes)
}

/// Checks that the demo at `options` can be planned within the talk's limits, without
/// painting its textures (and, over the vertex budget, without placing its instances).
///
/// # Errors
/// A density that is not finite and above 0, or one over a limit (with the largest that
/// fits).
pub fn check_density(options: &DemoOptions) -> Result<(), DensityError> {
    if !(options.density.is_finite() && options.density > 0.0) {
        return Err(DensityError::NotPositive {
            density: options.density,
        });
    }
    match plan_error(options) {
        None => Ok(()),
        Some(limit) => Err(DensityError::OverLimit {
            density: options.density,
            limit,
            max: max_density(options.scene, options.seed),
        }),
    }
}

/// The limit the demo at `options` breaks, if any.
fn plan_error(options: &DemoOptions) -> Option<String> {
    let over = |vertices: String| {
        Some(format!(
            "{vertices} instance vertices, over {} passes of {} vertices (half the 24 MiB vertex ring)",
            tiling::MAX_PASSES,
            tiling::PlanConfig::default().pass_vertex_budget()
        ))
    };
    // The hillside counts its grass patch by patch, in time proportional to the density:
    // a density whose other instances alone are over the bound is refused first.
    let floor = instance_vertices_floor(options);
    if floor > vertex_budget() {
        return over(format!("at least {floor}"));
    }
    let vertices = instance_vertices(options);
    if vertices > vertex_budget() {
        return over(vertices.to_string());
    }
    let (scene, _) = generate(options, false);
    let positions = scene.instance_positions();
    let batches = scene.tiling_batches(&positions, |m| {
        let m = &scene.meshes[m];
        tiling::Geometry {
            vertex_count: m.positions.len() as u32,
            primitive_count: m.primitive_count() as u32,
            first_index: 0,
            base_vertex: 0,
        }
    });
    tiling::build_plan(&batches, &tiling::PlanConfig::default())
        .err()
        .map(|e| e.to_string())
}

/// The largest density of `scene` (with `seed`) that the talk's plan takes, to two
/// decimals (a bisection over the same check as [`check_density`]).
pub fn max_density(scene: DemoScene, seed: u64) -> f32 {
    let fits = |density: f32| {
        plan_error(&DemoOptions {
            scene,
            seed,
            density,
        })
        .is_none()
    };
    let (mut lo, mut hi) = (0.0f32, 1.0f32);
    while fits(hi) {
        lo = hi;
        hi *= 2.0;
    }
    while hi - lo > 0.005 {
        let mid = 0.5 * (lo + hi);
        if fits(mid) { lo = mid } else { hi = mid }
    }
    (lo * 100.0).floor() / 100.0
}

// ---------------------------------------------------------------------------------------
// Random numbers and noise (integer hashing; deterministic on every platform).

/// Adds `count` local lights in KZ2's manner to `lighting`: lamps 0.5-3 m above the
/// ground plane `y = center.y`, scattered over the square of half-size `half_extent`
/// metres around `center`; two in three are point lights of 2-7 m radius, the rest spots
/// of 4-10 m pointing down at 25-50° half-angles, every other spot casting shadows; warm
/// and cool colours. Deterministic in `seed`.
pub fn scatter_lights(
    lighting: &mut Lighting,
    center: Vec3,
    half_extent: f32,
    count: usize,
    seed: u64,
) {
    let mut rng = Rng::new(seed ^ 0x9e37_79b9_7f4a_7c15);
    for i in 0..count {
        let position = center
            + Vec3::new(
                rng.range(-half_extent, half_extent),
                rng.range(0.5, 3.0),
                rng.range(-half_extent, half_extent),
            );
        let warm = rng.range(0.0, 1.0) < 0.6;
        let color = if warm {
            Vec3::new(12.0, 7.0, 2.8)
        } else {
            Vec3::new(3.0, 6.0, 12.0)
        } * rng.range(0.5, 1.5);
        if i % 3 == 2 {
            let tilt = Vec3::new(rng.range(-0.4, 0.4), -1.0, rng.range(-0.4, 0.4));
            lighting.spot_lights.push(SpotLight {
                position,
                direction: tilt,
                color: color * 2.0,
                radius: rng.range(4.0, 10.0),
                half_angle: rng.range(25.0, 50.0).to_radians(),
                // Every other spot casts shadows (KZ2: some lights shadowed).
                shadow: i % 6 == 2,
                specular: true,
            });
        } else {
            lighting.point_lights.push(PointLight {
                position,
                color,
                radius: rng.range(2.0, 7.0),
                specular: true,
            });
        }
    }
}

fn hash2(x: i32, y: i32, seed: u32) -> u32 {
    let mut h = (x as u32).wrapping_mul(0x8da6_b343)
        ^ (y as u32).wrapping_mul(0xd816_3841)
        ^ seed.wrapping_mul(0xcb1a_b31f);
    h ^= h >> 15;
    h = h.wrapping_mul(0x2c1b_3c6d);
    h ^= h >> 12;
    h = h.wrapping_mul(0x297a_2d39);
    h ^ (h >> 15)
}

fn lattice(x: i32, y: i32, seed: u32) -> f32 {
    hash2(x, y, seed) as f32 / u32::MAX as f32
}

/// Smooth value noise in [0, 1], period `period` lattice cells (tileable when `period > 0`).
fn value_noise(p: Vec2, seed: u32, period: i32) -> f32 {
    let i = p.floor();
    let f = p - i;
    let u = f * f * (Vec2::splat(3.0) - 2.0 * f);
    let (x0, y0) = (i.x as i32, i.y as i32);
    let wrap = |v: i32| if period > 0 { v.rem_euclid(period) } else { v };
    let l = |dx: i32, dy: i32| lattice(wrap(x0 + dx), wrap(y0 + dy), seed);
    let a = l(0, 0) + (l(1, 0) - l(0, 0)) * u.x;
    let b = l(0, 1) + (l(1, 1) - l(0, 1)) * u.x;
    a + (b - a) * u.y
}

fn fbm(p: Vec2, seed: u32, octaves: u32, period: i32) -> f32 {
    let (mut sum, mut amp, mut norm, mut freq) = (0.0, 0.5, 0.0, 1.0);
    for o in 0..octaves {
        let per = if period > 0 { period * freq as i32 } else { 0 };
        sum += amp * value_noise(p * freq, seed.wrapping_add(o * 101), per);
        norm += amp;
        amp *= 0.5;
        freq *= 2.0;
    }
    sum / norm
}

/// Terrain height (metres) at world (x, z).
fn terrain_height(x: f32, z: f32, seed: u32) -> f32 {
    let p = Vec2::new(x, z) / 24.0;
    (fbm(p, seed, 4, 0) - 0.5) * 6.0 + 0.6 * (x * 0.05).sin() * (z * 0.04).cos()
}

fn place(x: f32, z: f32, seed: u32, rng: &mut Rng, scale: f32) -> Affine3A {
    let y = terrain_height(x, z, seed);
    Affine3A::from_scale_rotation_translation(
        Vec3::splat(scale),
        Quat::from_rotation_y(rng.range(0.0, std::f32::consts::TAU)),
        Vec3::new(x, y, z),
    )
}

fn count(n: f32, density: f32) -> usize {
    (n * density).round().max(0.0) as usize
}

fn forest(seed: u64, density: f32, paint: bool) -> (Scene, FrameInput) {
    let mut rng = Rng::new(seed);
    let tseed = seed as u32;
    let size = 160.0;
    let meshes = vec![
        terrain_mesh(size, 160, tseed),
        trunk_mesh(),
        canopy_mesh(&mut rng, 220),
        bush_mesh(&mut rng, 9),
        tuft_mesh(&mut rng, 4, 0.7),
        rock_mesh(tseed ^ 0x55),
        canopy_mesh(&mut rng, 160),
    ];
    // Painting draws no random numbers: skipping it changes nothing else.
    let albedo_layers = if paint { forest_layers() } else { Vec::new() };
    let materials = vec![
        regular(material("ground", ShaderKind::Opaque, 0, 0.9)),
        material("bark", ShaderKind::Opaque, 1, 0.8),
        material("leaves", ShaderKind::AlphaTested, 2, 0.6),
        material("fern", ShaderKind::AlphaTested, 3, 0.6),
        material("grass", ShaderKind::AlphaTested, 4, 0.7),
        regular(material("rock", ShaderKind::Opaque, 5, 0.7)),
        Material {
            tint: Vec3::new(1.15, 1.05, 0.8),
            ..material("leaves (autumn)", ShaderKind::AlphaTested, 2, 0.6)
        },
    ];
    // The camera looks along +Z from the south edge; instances fill a wedge in front of it.
    let camera = Camera::look_at(
        Vec3::new(0.0, terrain_height(0.0, -50.0, tseed) + 1.7, -50.0),
        Vec3::new(0.0, terrain_height(0.0, -30.0, tseed) + 1.2, -30.0),
    );
    let scatter = |n: usize, scale: (f32, f32), rng: &mut Rng| -> Vec<Affine3A> {
        (0..n)
            .map(|_| {
                let x = rng.range(-size * 0.45, size * 0.45);
                let z = rng.range(-size * 0.3, size * 0.48);
                let s = rng.range(scale.0, scale.1);
                place(x, z, tseed, rng, s)
            })
            .collect()
    };
    let trees = scatter(count(260.0, density), (0.8, 1.3), &mut rng);
    let (green, autumn): (Vec<_>, Vec<_>) = trees.iter().enumerate().partition(|(i, _)| i % 5 != 0);
    let green: Vec<Affine3A> = green.into_iter().map(|(_, t)| *t).collect();
    let autumn: Vec<Affine3A> = autumn.into_iter().map(|(_, t)| *t).collect();
    let batches = vec![
        Batch {
            mesh: MeshId(0),
            material: MaterialId(0),
            instances: vec![Affine3A::IDENTITY],
        },
        Batch {
            mesh: MeshId(1),
            material: MaterialId(1),
            instances: trees.clone(),
        },
        Batch {
            mesh: MeshId(2),
            material: MaterialId(2),
            instances: green,
        },
        Batch {
            mesh: MeshId(6),
            material: MaterialId(6),
            instances: autumn,
        },
        Batch {
            mesh: MeshId(3),
            material: MaterialId(3),
            instances: scatter(count(3000.0, density), (0.7, 1.4), &mut rng),
        },
        Batch {
            mesh: MeshId(4),
            material: MaterialId(4),
            instances: scatter(count(12000.0, density), (0.8, 1.3), &mut rng),
        },
        Batch {
            mesh: MeshId(5),
            material: MaterialId(5),
            instances: scatter(count(300.0, density), (0.4, 1.6), &mut rng),
        },
    ];
    let lighting = Lighting {
        point_lights: vec![
            PointLight {
                position: camera.target + Vec3::new(-3.0, 1.5, 4.0),
                color: Vec3::new(4.0, 2.2, 0.8),
                radius: 9.0,
                specular: true,
            },
            PointLight {
                position: camera.target + Vec3::new(5.0, 1.0, 12.0),
                color: Vec3::new(0.8, 2.0, 4.0),
                radius: 10.0,
                specular: true,
            },
        ],
        ..Lighting::default()
    };
    (
        Scene {
            data_layers: Vec::new(),
            meshes,
            materials,
            albedo_layers,
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

/// Patches along each side of the grass field.
fn grass_side(density: f32) -> i32 {
    (44.0 * density.sqrt()).round().max(1.0) as i32
}

fn grass(seed: u64, density: f32, paint: bool) -> (Scene, FrameInput) {
    let mut rng = Rng::new(seed ^ 0x0067_7261_7373);
    let tseed = seed as u32;
    let size = 120.0;
    let patch = 2.0;
    let meshes = vec![
        terrain_mesh(size, 96, tseed),
        blade_patch_mesh(&mut rng, 512, 3, patch * 0.5, 1.1),
        blade_patch_mesh(&mut rng, 512, 3, patch * 0.5, 0.8),
        rock_mesh(tseed ^ 0x99),
    ];
    let albedo_layers = if paint {
        vec![ground_layer(), blade_layer(), rock_layer()]
    } else {
        Vec::new()
    };
    let materials = vec![
        regular(material("ground", ShaderKind::Opaque, 0, 0.9)),
        material("tall grass", ShaderKind::AlphaTested, 1, 0.6),
        Material {
            tint: Vec3::new(1.2, 1.1, 0.75),
            ..material("dry grass", ShaderKind::AlphaTested, 1, 0.6)
        },
        regular(material("rock", ShaderKind::Opaque, 2, 0.7)),
    ];
    let camera = Camera::look_at(
        Vec3::new(0.0, terrain_height(0.0, -40.0, tseed) + 1.3, -40.0),
        Vec3::new(0.0, terrain_height(0.0, -25.0, tseed) - 0.6, -25.0),
    );
    // Patches on a jittered grid over the wedge in front of the camera.
    let side = grass_side(density);
    let (mut tall, mut dry) = (Vec::new(), Vec::new());
    for j in 0..side {
        for i in 0..side {
            let x = (i as f32 - side as f32 * 0.5) * patch * 1.5 * 44.0 / side as f32 * 0.9;
            let z = -38.0 + j as f32 * patch * 1.5 * 44.0 / side as f32 * 0.9;
            let jitter = Vec2::new(rng.range(-0.4, 0.4), rng.range(-0.4, 0.4));
            let s = rng_scale(&mut rng);
            let t = place(x + jitter.x, z + jitter.y, tseed, &mut rng, s);
            if lattice(i / 3, j / 3, tseed) < 0.3 {
                dry.push(t)
            } else {
                tall.push(t)
            }
        }
    }
    let rocks = (0..count(60.0, density))
        .map(|_| {
            let (x, z) = (rng.range(-40.0, 40.0), rng.range(-35.0, 40.0));
            let s = rng.range(0.5, 1.5);
            place(x, z, tseed, &mut rng, s)
        })
        .collect();
    let batches = vec![
        Batch {
            mesh: MeshId(0),
            material: MaterialId(0),
            instances: vec![Affine3A::IDENTITY],
        },
        Batch {
            mesh: MeshId(1),
            material: MaterialId(1),
            instances: tall,
        },
        Batch {
            mesh: MeshId(2),
            material: MaterialId(2),
            instances: dry,
        },
        Batch {
            mesh: MeshId(3),
            material: MaterialId(3),
            instances: rocks,
        },
    ];
    (
        Scene {
            data_layers: Vec::new(),
            meshes,
            materials,
            albedo_layers,
            batches,
            static_setups: Vec::new(),
            wind: None,
        },
        FrameInput::new(camera),
    )
}

fn rng_scale(rng: &mut Rng) -> f32 {
    rng.range(0.85, 1.2)
}

/// The mean distance (metres, in `x`, `z`) between the bases of consecutive blades of a
/// patch mesh whose blades are `per_blade` vertices each, the first two straddling the base.
#[cfg(test)]
fn mean_blade_step(mesh: &Mesh, per_blade: usize) -> f32 {
    let bases: Vec<Vec2> = mesh
        .positions
        .chunks(per_blade)
        .map(|b| {
            let base = (b[0] + b[1]) * 0.5;
            Vec2::new(base.x, base.z)
        })
        .collect();
    let steps = bases.len().saturating_sub(1).max(1);
    bases.windows(2).map(|w| w[0].distance(w[1])).sum::<f32>() / steps as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The grass scene's patch: consecutive blades stand side by side (the mean step
    /// between their bases is 1.04 m in a 2 m patch in draw order).
    #[test]
    fn a_blade_patch_lays_its_blades_out_side_by_side() {
        let (segments, half) = (3, 1.0);
        let mesh = blade_patch_mesh(&mut Rng::new(5), 512, segments, half, 1.1);
        let per_blade = 2 * (segments as usize + 1);
        assert_eq!(mesh.positions.len(), per_blade * 512);
        let mean = mean_blade_step(&mesh, per_blade);
        assert!(mean < 0.1 * 2.0 * half, "consecutive blades {mean} m apart");
    }

    #[test]
    fn demo_scenes_validate_and_are_deterministic() {
        for scene in DemoScene::ALL
            .into_iter()
            .chain([DemoScene::Hillside, DemoScene::HillsideGrass])
        {
            let o = DemoOptions {
                scene,
                seed: 7,
                density: 0.2,
            };
            let (a, frame) = build(&o);
            a.validate()
                .unwrap_or_else(|e| panic!("{}: {e}", scene.name()));
            frame
                .validate()
                .unwrap_or_else(|e| panic!("{}: {e}", scene.name()));
            assert!(a.instance_count() > 10, "{}", scene.name());
            assert_eq!(a, build(&o).0, "{} is not deterministic", scene.name());
        }
    }

    #[test]
    fn densities_are_checked_against_the_plan_limits() {
        let o = |scene, density| DemoOptions {
            scene,
            seed: 1,
            density,
        };
        for bad in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            assert!(matches!(
                check_density(&o(DemoScene::Grass, bad)),
                Err(DensityError::NotPositive { .. })
            ));
        }
        assert!(check_density(&o(DemoScene::Grass, 1.0)).is_ok());
        // The hillside's vertex count is estimated without placing instances: the estimate
        // must count what the built scene holds (its floor no more), at densities 1 and 2
        // of both views, and density 1 fits.
        for scene in [DemoScene::Hillside, DemoScene::HillsideGrass] {
            assert!(check_density(&o(scene, 1.0)).is_ok(), "{}", scene.name());
            for density in [1.0, 2.0] {
                let (hill, _) = generate(&o(scene, density), false);
                let placed: u64 = hill
                    .batches
                    .iter()
                    .map(|b| {
                        b.instances.len() as u64 * hill.meshes[b.mesh.0].positions.len() as u64
                    })
                    .sum();
                assert_eq!(instance_vertices(&o(scene, density)), placed);
                assert!(instance_vertices_floor(&o(scene, density)) < placed);
            }
            // An absurd density is refused by the floor, in time independent of it.
            let limit = plan_error(&o(scene, 1e6)).expect("over the limits");
            assert!(limit.starts_with("at least"), "{limit}");
        }
        // An absurd density is refused by the vertex bound alone, without placing its
        // instances; the largest density that fits is given, and it does fit.
        match check_density(&o(DemoScene::Grass, 1e6)) {
            Err(DensityError::OverLimit { max, limit, .. }) => {
                eprintln!("grass: at most density {max} ({limit})");
                assert!(limit.contains("passes"), "{limit}");
                assert!(max > 1.0 && max < 1e3, "{max}");
                assert!(check_density(&o(DemoScene::Grass, max)).is_ok());
                assert!(check_density(&o(DemoScene::Grass, max * 1.1)).is_err());
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn alpha_tested_layers_have_holes_and_opaque_layers_do_not() {
        let (s, _) = build(&DemoOptions {
            scene: DemoScene::Forest,
            seed: 1,
            density: 0.05,
        });
        for m in &s.materials {
            let layer = &s.albedo_layers[m.albedo_layer as usize];
            let holes = layer.texels.iter().filter(|t| t[3] < 128).count();
            match m.shader {
                ShaderKind::AlphaTested => assert!(holes > layer.texels.len() / 10, "{}", m.name),
                ShaderKind::Opaque => assert_eq!(holes, 0, "{}", m.name),
            }
        }
    }

    /// The forest's leaf layer (alpha-tested, a third of it holes) keeps its coverage
    /// through the mip chain `scene` filters for the renderer.
    #[test]
    fn mips_keep_alpha_coverage() {
        let (scene, _) = build(&DemoOptions {
            density: 0.01,
            ..Default::default()
        });
        let layer = scene.albedo_layers[2].clone();
        let chain = layer.mip_chain();
        assert_eq!(chain.len() as u32, layer.size.ilog2() + 1);
        let cov = |t: &[[u8; 4]]| t.iter().filter(|p| p[3] >= 128).count() as f32 / t.len() as f32;
        let top = cov(&chain[0]);
        for (i, level) in chain.iter().enumerate().take(6) {
            assert!(
                (cov(level) - top).abs() < 0.08,
                "mip {i}: coverage {} vs {top}",
                cov(level)
            );
        }
    }
}
