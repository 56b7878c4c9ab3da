//! "hillside": a scene shaped like HFW's foliage views, where the talk's tables come from
//! (seed 000): from a rise, a meadow of individual grass blades runs down into a valley of
//! dense tree canopies. At 3840x2160 most of its triangles cover a few pixels or less
//! (blades a centimetre wide tens of metres away, canopy cards hundreds of metres away), so
//! most 2x2 quads hold several triangles: the case deferred texturing was built for.

use glam::{Affine3A, Vec3};

use super::{
    Rng, bark_layer, blade_layer, blade_patch_mesh, canopy_mesh, count, grass_layer, ground_layer,
    leaf_layer, material, place, rock_layer, rock_mesh, terrain_height, terrain_mesh, trunk_mesh,
    tuft_mesh,
};
use crate::frame::{Camera, FrameInput};
use crate::scene::{Batch, Material, MaterialId, MeshId, Scene, ShaderKind};

/// The terrain's side (metres) and the grass field's spacing (metres between patch
/// centres; each patch is a square of this side).
const SIZE: f32 = 500.0;
const PATCH: f32 = 3.0;

/// Grass patches along each side of the meadow at `density` (1600 patches of 512 blades at
/// 1.0).
pub(super) fn meadow_side(density: f32) -> i32 {
    (40.0 * density.sqrt()).round() as i32
}

/// Grass tufts (crossed alpha-tested cards) over the meadow at 1.0.
pub(super) const TUFTS: f32 = 60_000.0;
/// Trees in the valley at 1.0.
pub(super) const TREES: f32 = 3000.0;
/// Rocks in the meadow at 1.0.
pub(super) const ROCKS: f32 = 150.0;

pub(super) fn hillside(seed: u64, density: f32, paint: bool) -> (Scene, FrameInput) {
    let mut rng = Rng(seed ^ 0x6869_6c6c);
    let tseed = seed as u32;
    let meshes = vec![
        // 180 cells: 64 800 triangles, under the 16-bit index limit.
        terrain_mesh(SIZE, 180, tseed),
        blade_patch_mesh(&mut rng, 512, 3, PATCH * 0.5, 0.9),
        trunk_mesh(),
        canopy_mesh(&mut rng, 160),
        rock_mesh(tseed ^ 0x77),
        tuft_mesh(&mut rng, 4, 0.8),
    ];
    let albedo_layers = if paint {
        vec![
            ground_layer(),
            blade_layer(),
            bark_layer(),
            leaf_layer(),
            rock_layer(),
            grass_layer(),
        ]
    } else {
        Vec::new()
    };
    let materials = vec![
        material("ground", ShaderKind::Opaque, 0, 0.9),
        material("meadow grass", ShaderKind::AlphaTested, 1, 0.6),
        material("bark", ShaderKind::Opaque, 2, 0.8),
        material("canopy", ShaderKind::AlphaTested, 3, 0.6),
        Material {
            tint: Vec3::new(0.75, 0.9, 0.7),
            ..material("rock", ShaderKind::Opaque, 4, 0.7)
        },
        material("meadow tufts", ShaderKind::AlphaTested, 5, 0.7),
    ];
    // On a rise at the south end, 30 m above the ground, looking down over the meadow at
    // the forest beyond.
    let eye = Vec3::new(0.0, terrain_height(0.0, -220.0, tseed) + 30.0, -220.0);
    let camera = Camera::look_at(
        eye,
        Vec3::new(0.0, terrain_height(0.0, -40.0, tseed) - 10.0, -40.0),
    );
    // The meadow: a jittered grid of patches from just below the camera to 60 m out.
    let side = meadow_side(density);
    let mut grass = Vec::with_capacity((side * side).max(0) as usize);
    for j in 0..side {
        for i in 0..side {
            let x = (i as f32 + 0.5 - side as f32 * 0.5) * 160.0 / side.max(1) as f32;
            let z = -190.0 + (j as f32 + 0.5) * 170.0 / side.max(1) as f32;
            let (jx, jz) = (rng.range(-0.5, 0.5), rng.range(-0.5, 0.5));
            let s = rng.range(0.85, 1.2);
            grass.push(place(x + jx, z + jz, tseed, &mut rng, s));
        }
    }
    // The valley: trees from the meadow's far edge to the horizon, densest far away.
    let trees: Vec<Affine3A> = (0..count(TREES, density))
        .map(|_| {
            let x = rng.range(-SIZE * 0.45, SIZE * 0.45);
            let z = rng.range(-25.0, SIZE * 0.3);
            let s = rng.range(0.9, 1.4);
            place(x, z, tseed, &mut rng, s)
        })
        .collect();
    let tufts: Vec<Affine3A> = (0..count(TUFTS, density))
        .map(|_| {
            let (x, z) = (rng.range(-85.0, 85.0), rng.range(-195.0, -20.0));
            let s = rng.range(0.8, 1.4);
            place(x, z, tseed, &mut rng, s)
        })
        .collect();
    let rocks = (0..count(ROCKS, density))
        .map(|_| {
            let (x, z) = (rng.range(-80.0, 80.0), rng.range(-185.0, -25.0));
            let s = rng.range(0.6, 2.0);
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
            instances: grass,
        },
        Batch {
            mesh: MeshId(2),
            material: MaterialId(2),
            instances: trees.clone(),
        },
        Batch {
            mesh: MeshId(3),
            material: MaterialId(3),
            instances: trees,
        },
        Batch {
            mesh: MeshId(4),
            material: MaterialId(4),
            instances: rocks,
        },
        Batch {
            mesh: MeshId(5),
            material: MaterialId(5),
            instances: tufts,
        },
    ];
    (
        Scene {
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
