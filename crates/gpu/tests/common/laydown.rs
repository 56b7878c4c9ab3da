//! The laydown tests' scene, camera and device check (`tests/laydown*.rs`).

use gpu::glam::{Affine3A, Quat, Vec3};
use gpu::scene::{MaterialId, MeshId, ShaderKind};
use gpu::{Batch, Camera, FrameInput, Scene};
use testkit::device::ctx;

use super::material;

/// The laydown tests' image size.
pub const W: u32 = 160;
/// The laydown tests' image height.
pub const H: u32 = 96;

pub fn test_scene() -> (Scene, FrameInput) {
    let (demo, _) = demo::build(&demo::DemoOptions {
        density: 0.01,
        ..Default::default()
    });
    // Rocks (opaque, closed) scattered below a camera looking down; one big ground quad
    // made of the terrain mesh.
    let rock = demo.meshes.iter().position(|m| m.name == "rock").unwrap();
    let terrain = demo
        .meshes
        .iter()
        .position(|m| m.name == "terrain")
        .unwrap();
    let meshes = vec![demo.meshes[terrain].clone(), demo.meshes[rock].clone()];
    let mat = material("stone", ShaderKind::Opaque);
    let mut rocks = Vec::new();
    for i in 0..40 {
        let a = i as f32 * 0.7;
        rocks.push(Affine3A::from_scale_rotation_translation(
            Vec3::splat(0.8 + 0.05 * (i % 7) as f32),
            Quat::from_rotation_y(a),
            Vec3::new(
                (a * 1.3).sin() * 8.0,
                2.0 + (i % 5) as f32 * 0.7,
                (a * 0.9).cos() * 6.0,
            ),
        ));
    }
    let scene = Scene {
        data_layers: Vec::new(),
        meshes,
        materials: vec![mat],
        albedo_layers: vec![demo.albedo_layers[0].clone()],
        batches: vec![
            Batch {
                mesh: MeshId(0),
                material: MaterialId(0),
                instances: vec![Affine3A::from_scale_rotation_translation(
                    Vec3::splat(0.15),
                    Quat::IDENTITY,
                    Vec3::new(0.0, -3.0, 0.0),
                )],
            },
            Batch {
                mesh: MeshId(1),
                material: MaterialId(0),
                instances: rocks,
            },
        ],
        static_setups: Vec::new(),
        wind: None,
    };
    let camera = Camera {
        fov_y: 1.0,
        near: 0.5,
        ..Camera::look_at(Vec3::new(0.5, 22.0, -9.0), Vec3::new(0.0, 0.0, 0.5))
    };
    (scene, FrameInput::new(camera))
}

/// Whether the test device runs the compute laydown: lavapipe and the H200 do, so a device
/// without it fails here, not silently.
pub fn compute_device() -> bool {
    let probe = ctx();
    assert!(
        probe.paths.int64_atomics,
        "no 64-bit atomics on {}: the compute laydown needs them (lavapipe has them)",
        probe.adapter_line()
    );
    true
}

/// 5 m up the z axis looking at the origin, 1 rad vertical field of view, near plane 0.5 m.
pub fn front_camera() -> Camera {
    Camera {
        fov_y: 1.0,
        near: 0.5,
        ..Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO)
    }
}
