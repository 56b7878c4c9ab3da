//! The "city" demo: `staticscene`'s demo city (facade blocks with two-level LODs in
//! buildings that collapse to one box far away, street props, trees) drawn through HZD's
//! static query on the GPU, over a ground plane with grass tufts and bushes along the
//! streets (planned batches, so the deferred texturing still has foliage to resolve).
//!
//! The city's setup handles are renumbered into [`Scene::static_setups`] indices; each
//! setup's mesh is a box of its leaf bounds (facade parts, props) or crossed leaf cards
//! (trees, alpha-tested), and its capacity is its instance count over the whole city (the
//! most that can be visible at once).

use std::collections::BTreeMap;

use glam::{Affine3A, DVec3, Quat, Vec2, Vec3};
use staticscene::MeshNode;
use staticscene::demo::{CityConfig, street_camera};

use super::{
    MeshBuilder, Rng, bark_layer, bush_mesh, grass_layer, leaf_layer, material, rock_layer,
    tuft_mesh,
};
use scene::{
    Batch, Camera, FrameInput, Material, MaterialId, Mesh, MeshId, Scene, ShaderKind, StaticSetup,
};

/// The city demo: the renderer's scene, the static world it queries, and a street view.
/// `gpu::statics::stream_static_world` activates the world's tiles on a GPU static query.
pub struct City {
    /// Meshes, materials, layers, the ground and foliage batches, the static setups.
    pub scene: Scene,
    /// `staticscene`'s city with setup handles renumbered to `scene.static_setups`.
    pub world: staticscene::demo::City,
    /// The city's layout.
    pub config: CityConfig,
    /// A view down a street, from 6 m up, towards the far skyline.
    pub frame: FrameInput,
}

/// Material indices of the city.
const FACADE: usize = 0;
const GLASS: usize = 1;
const TRIM: usize = 2;
const PROP: usize = 3;
const CAR: usize = 4;
const TREE: usize = 5;
const GROUND: usize = 6;
const GRASS: usize = 7;
const BUSH: usize = 8;

/// What an original city handle draws: its material and whether it is a tree.
fn kind(handle: u64) -> (usize, bool) {
    if handle >> 16 == 1 {
        return match (handle >> 4) & 0xf {
            2 => (TREE, true),
            3 => (CAR, false),
            _ => (PROP, false),
        };
    }
    match handle & 0xff {
        2 => (GLASS, false),
        3 | 4 => (TRIM, false),
        _ => (FACADE, false),
    }
}

/// A closed box of `[min, max]` (metres) with per-face normals, faces counter-clockwise seen
/// from outside, and UVs in metres / 3 (the city's facades tile every 3 m).
pub fn box_mesh(name: &str, min: Vec3, max: Vec3) -> Mesh {
    let mut b = MeshBuilder::new(name);
    let c = [min, max];
    let corner = |x: usize, y: usize, z: usize| Vec3::new(c[x].x, c[y].y, c[z].z);
    // Each face: four corners counter-clockwise seen from outside, and the normal.
    type Face = ([(usize, usize, usize); 4], Vec3);
    let faces: [Face; 6] = [
        ([(1, 0, 0), (1, 1, 0), (1, 1, 1), (1, 0, 1)], Vec3::X),
        ([(0, 0, 1), (0, 1, 1), (0, 1, 0), (0, 0, 0)], Vec3::NEG_X),
        ([(0, 1, 0), (0, 1, 1), (1, 1, 1), (1, 1, 0)], Vec3::Y),
        ([(0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1)], Vec3::NEG_Y),
        ([(0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)], Vec3::Z),
        ([(1, 0, 0), (0, 0, 0), (0, 1, 0), (1, 1, 0)], Vec3::NEG_Z),
    ];
    for (corners, n) in faces {
        let (u_axis, v_axis) = if n.x != 0.0 {
            (Vec3::Z, Vec3::Y)
        } else if n.y != 0.0 {
            (Vec3::X, Vec3::Z)
        } else {
            (Vec3::X, Vec3::Y)
        };
        let v: Vec<u16> = corners
            .iter()
            .map(|&(x, y, z)| {
                let p = corner(x, y, z);
                b.vertex(p, n, Vec2::new(p.dot(u_axis), -p.dot(v_axis)) / 3.0)
            })
            .collect();
        b.quad(v[0], v[1], v[2], v[3]);
    }
    b.finish()
}

/// Crossed leaf cards filling `[min, max]` (a tree's crown and trunk as one card set).
fn tree_mesh(name: &str, min: Vec3, max: Vec3, cards: u32) -> Mesh {
    let mut b = MeshBuilder::new(name);
    let centre = (min + max) * 0.5;
    let half = (max - min) * 0.5;
    for k in 0..cards {
        let a = k as f32 / cards as f32 * std::f32::consts::PI;
        let r = Vec3::new(a.cos() * half.x, 0.0, a.sin() * half.z);
        b.card(
            centre,
            r,
            Vec3::Y * half.y,
            Vec2::ZERO,
            Vec2::ONE,
            Vec3::ZERO,
        );
    }
    b.finish()
}

/// Renumbers every static leaf's handle (first seen, first numbered) and returns the
/// original handle and bounds of each new one.
fn renumber(
    node: &mut MeshNode,
    setups: &mut BTreeMap<u64, usize>,
    out: &mut Vec<(u64, Vec3, Vec3)>,
) {
    match node {
        MeshNode::Lod { levels, .. } => {
            for l in levels {
                renumber(&mut l.node, setups, out);
            }
        }
        MeshNode::Multi(parts) => {
            for p in parts {
                renumber(&mut p.node, setups, out);
            }
        }
        MeshNode::Static(m) => {
            let next = out.len();
            let i = *setups.entry(m.setup).or_insert(next);
            if i == next {
                out.push((m.setup, m.bounds.min, m.bounds.max));
            }
            m.setup = i as u64;
        }
        MeshNode::Skinned { .. } => {}
    }
}

/// Adds the leaves of `node` per (renumbered) setup handle to `counts`.
fn count_leaves(node: &MeshNode, counts: &mut [u32]) {
    match node {
        MeshNode::Lod { levels, .. } => levels.iter().for_each(|l| count_leaves(&l.node, counts)),
        MeshNode::Multi(parts) => parts.iter().for_each(|p| count_leaves(&p.node, counts)),
        MeshNode::Static(m) => counts[m.setup as usize] += 1,
        MeshNode::Skinned { .. } => {}
    }
}

/// The city for about `instances` static instances (`CityConfig::with_instances`).
#[must_use]
pub fn city(instances: usize) -> City {
    city_with(CityConfig::with_instances(instances))
}

/// [`city`] with `staticscene`'s layout given in full (sector size, seed, ...).
#[must_use]
pub fn city_with(config: CityConfig) -> City {
    let mut world = staticscene::demo::city(&config);
    let mut handles = BTreeMap::new();
    let mut setups = Vec::new();
    for r in &mut world.resources {
        renumber(r, &mut handles, &mut setups);
    }
    // Capacities: every leaf of every placed static object (misfits go to the dynamic list).
    let mut per_resource = vec![vec![0u32; setups.len()]; world.resources.len()];
    for (r, counts) in world.resources.iter().zip(&mut per_resource) {
        count_leaves(r, counts);
    }
    let mut capacity = vec![0u32; setups.len()];
    for g in &world.groups {
        for o in &g.objects {
            if world.misfit_resources.contains(&o.resource) {
                continue;
            }
            for (c, n) in capacity.iter_mut().zip(&per_resource[o.resource]) {
                *c += n;
            }
        }
    }

    let mut rng = Rng::new(7);
    let tint = |m: Material, t: Vec3| Material { tint: t, ..m };
    let materials = vec![
        tint(
            material("facade", ShaderKind::Opaque, 0, 0.8),
            Vec3::new(1.25, 1.1, 0.95),
        ),
        Material {
            specular: 0.8,
            ..tint(
                material("window glass", ShaderKind::Opaque, 0, 0.15),
                Vec3::new(0.25, 0.35, 0.45),
            )
        },
        tint(
            material("trim", ShaderKind::Opaque, 0, 0.6),
            Vec3::splat(1.8),
        ),
        tint(
            material("street props", ShaderKind::Opaque, 0, 0.4),
            Vec3::new(0.6, 0.65, 0.7),
        ),
        tint(
            material("cars", ShaderKind::Opaque, 0, 0.3),
            Vec3::new(1.6, 0.3, 0.25),
        ),
        material("tree leaves", ShaderKind::AlphaTested, 2, 0.7),
        tint(
            material("asphalt", ShaderKind::Opaque, 0, 0.9),
            Vec3::splat(0.6),
        ),
        material("grass", ShaderKind::AlphaTested, 3, 0.8),
        tint(
            material("bushes", ShaderKind::AlphaTested, 2, 0.7),
            Vec3::new(0.8, 1.0, 0.7),
        ),
    ];
    let mut meshes = Vec::new();
    let mut static_setups = Vec::new();
    for (i, &(handle, min, max)) in setups.iter().enumerate() {
        let (mat, tree) = kind(handle);
        let name = format!("setup {i} ({handle:#x})");
        meshes.push(if tree {
            tree_mesh(&name, min, max, if handle & 1 == 0 { 3 } else { 2 })
        } else {
            box_mesh(&name, min, max)
        });
        static_setups.push(StaticSetup {
            mesh: MeshId(i),
            material: MaterialId(mat),
            capacity: capacity[i].max(1),
        });
    }
    // The ground, grass tufts and bushes along the streets (planned batches).
    let size = config.lots[0].max(config.lots[1]) as f32 * config.lot_size;
    let ground = meshes.len();
    meshes.push(box_mesh(
        "ground",
        Vec3::new(0.0, -0.2, 0.0),
        Vec3::new(1.0, 0.0, 1.0),
    ));
    let tuft = meshes.len();
    meshes.push(tuft_mesh(&mut rng, 3, 0.6));
    let bush = meshes.len();
    meshes.push(bush_mesh(&mut rng, 7));
    let origin = config.origin.as_vec3();
    let ground_t = Affine3A::from_scale_rotation_translation(
        Vec3::new(size + 200.0, 1.0, size + 200.0),
        Quat::IDENTITY,
        origin - Vec3::new(100.0, 0.0, 100.0),
    );
    let (mut tufts, mut bushes) = (Vec::new(), Vec::new());
    for lz in 0..config.lots[1] {
        for lx in 0..config.lots[0] {
            let corner = origin + Vec3::new(lx as f32, 0.0, lz as f32) * config.lot_size;
            for k in 0..12 {
                let along = rng.range(0.0, config.lot_size);
                let side = rng.range(1.6, 3.0);
                let p = if k % 2 == 0 {
                    corner + Vec3::new(along, 0.0, side)
                } else {
                    corner + Vec3::new(side, 0.0, along)
                };
                let t = Affine3A::from_scale_rotation_translation(
                    Vec3::splat(rng.range(0.7, 1.3)),
                    Quat::from_rotation_y(rng.range(0.0, std::f32::consts::TAU)),
                    p,
                );
                if k < 3 { bushes.push(t) } else { tufts.push(t) }
            }
        }
    }
    let batches = vec![
        Batch {
            mesh: MeshId(ground),
            material: MaterialId(GROUND),
            instances: vec![ground_t],
        },
        Batch {
            mesh: MeshId(tuft),
            material: MaterialId(GRASS),
            instances: tufts,
        },
        Batch {
            mesh: MeshId(bush),
            material: MaterialId(BUSH),
            instances: bushes,
        },
    ];
    let albedo_layers = vec![rock_layer(), bark_layer(), leaf_layer(), grass_layer()];
    let scene = Scene {
        data_layers: Vec::new(),
        meshes,
        materials,
        albedo_layers,
        batches,
        static_setups,
        wind: None,
    };
    let street = street_camera(&config);
    let forward = (street.rotation * DVec3::NEG_Z).as_vec3();
    // Above the parked cars, so the street leads the eye to the skyline.
    let eye = street.position.as_vec3() + Vec3::Y * 4.5;
    let camera = Camera {
        fov_y: 1.0,
        ..Camera::look_at(eye, eye + forward * 10.0 + Vec3::Y * 1.2)
    };
    City {
        scene,
        world,
        config,
        frame: FrameInput::new(camera),
    }
}
