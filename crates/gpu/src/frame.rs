//! Per-frame constants and per-instance records, the Rust twins of `shaders/frame.wgsl`.

use bytemuck::{Pod, Zeroable};
use glam::{Affine3A, Mat4, Vec3, Vec4};

use crate::scene::{Camera, Lighting};

/// WGSL of [`FrameUniforms`], [`GpuInstance`] and [`GpuPointLight`] with transform helpers.
pub const FRAME_WGSL: &str = include_str!("shaders/frame.wgsl");

/// Per-frame constants (WGSL `FrameUniforms`): 304 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct FrameUniforms {
    /// Camera-relative world to clip: the camera's rotation and projection only.
    pub view_proj: [[f32; 4]; 4],
    /// Inverse of `view_proj`: clip to camera-relative world.
    pub inv_view_proj: [[f32; 4]; 4],
    /// Last frame's `view_proj` (motion vectors; equal to `view_proj` for a still camera).
    pub prev_view_proj: [[f32; 4]; 4],
    /// Camera position (world, metres), w = 1.
    pub camera_position: [f32; 4],
    /// Width, height, 1/width, 1/height in pixels.
    pub viewport: [f32; 4],
    /// Unit direction towards the sun (xyz).
    pub sun_direction: [f32; 4],
    /// Sun colour (linear RGB).
    pub sun_color: [f32; 4],
    /// Ambient colour (linear RGB).
    pub ambient: [f32; 4],
    /// Sky colour (linear RGB).
    pub sky: [f32; 4],
    /// Number of point lights bound.
    pub point_light_count: u32,
    /// log2 scale applied to the resolve's texture gradients (0: none).
    pub mip_bias: f32,
    /// Frame counter.
    pub frame_index: u32,
    /// Padding.
    pub pad0: u32,
}
const _: () = assert!(size_of::<FrameUniforms>() == 304);

/// One instance (WGSL `GpuInstance`): object-to-camera-relative transform rows and its
/// place in the vis buffer. 64 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuInstance {
    /// Row 0 of the 3x4 object-to-camera-relative transform.
    pub row0: [f32; 4],
    /// Row 1.
    pub row1: [f32; 4],
    /// Row 2.
    pub row2: [f32; 4],
    /// The micro-batch ID its vis-buffer words carry.
    pub micro_batch: u32,
    /// Its instance field within that micro-batch ID.
    pub instance_field: u32,
    /// The mesh's primitive bits (`visbuf::PrimitiveBits`).
    pub primitive_bits: u32,
    /// Index into the material table.
    pub material: u32,
}
const _: () = assert!(size_of::<GpuInstance>() == 64);

/// One point light (WGSL `GpuPointLight`). 32 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuPointLight {
    /// Camera-relative position (xyz) and radius (w), metres.
    pub position_radius: [f32; 4],
    /// Linear RGB intensity.
    pub color: [f32; 4],
}
const _: () = assert!(size_of::<GpuPointLight>() == 32);

/// The 3x4 rows of `transform` moved to camera-relative space.
pub fn camera_relative_rows(transform: &Affine3A, camera: Vec3) -> [[f32; 4]; 3] {
    let m = Mat4::from(Affine3A::from_translation(-camera) * *transform);
    let r = m.transpose();
    [
        r.x_axis.to_array(),
        r.y_axis.to_array(),
        r.z_axis.to_array(),
    ]
}

/// The camera-relative view-projection: rotation and projection only.
pub fn camera_relative_view_proj(camera: &Camera, aspect: f32) -> Mat4 {
    let view = camera.view();
    let rotation_only = Mat4::from_cols(view.x_axis, view.y_axis, view.z_axis, Vec4::W);
    camera.projection(aspect) * rotation_only
}

/// Fills the frame constants for `camera` and `lighting` at `width` × `height` pixels.
pub fn frame_uniforms(
    camera: &Camera,
    lighting: &Lighting,
    width: u32,
    height: u32,
    point_lights: u32,
) -> FrameUniforms {
    let aspect = width as f32 / height.max(1) as f32;
    let vp = camera_relative_view_proj(camera, aspect);
    FrameUniforms {
        view_proj: vp.to_cols_array_2d(),
        inv_view_proj: vp.inverse().to_cols_array_2d(),
        prev_view_proj: vp.to_cols_array_2d(),
        camera_position: camera.position.extend(1.0).to_array(),
        viewport: [
            width as f32,
            height as f32,
            1.0 / width.max(1) as f32,
            1.0 / height.max(1) as f32,
        ],
        sun_direction: lighting
            .sun_direction
            .normalize_or(Vec3::Y)
            .extend(0.0)
            .to_array(),
        sun_color: lighting.sun_color.extend(0.0).to_array(),
        ambient: lighting.ambient.extend(0.0).to_array(),
        sky: lighting.sky.extend(0.0).to_array(),
        point_light_count: point_lights,
        mip_bias: 0.0,
        frame_index: 0,
        pad0: 0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn camera_relative_transform_matches_world_transform() {
        let t = Affine3A::from_scale_rotation_translation(
            Vec3::splat(1.5),
            glam::Quat::from_rotation_y(0.7),
            Vec3::new(100.0, 2.0, -40.0),
        );
        let cam = Vec3::new(98.0, 1.0, -45.0);
        let rows = camera_relative_rows(&t, cam);
        let p = Vec3::new(0.3, -0.2, 1.0);
        let world = t.transform_point3(p);
        let rel: Vec<f32> = rows
            .iter()
            .map(|r| Vec4::from(*r).dot(p.extend(1.0)))
            .collect();
        for k in 0..3 {
            assert!((rel[k] - (world - cam)[k]).abs() < 1e-4);
        }
    }

    #[test]
    fn camera_relative_projection_matches_the_full_one() {
        let camera = Camera {
            position: Vec3::new(10.0, 2.0, -5.0),
            target: Vec3::new(12.0, 1.0, 5.0),
            fov_y: 1.0,
            near: 0.1,
        };
        let full = camera.view_projection(16.0 / 9.0);
        let rel = camera_relative_view_proj(&camera, 16.0 / 9.0);
        let p = Vec3::new(13.0, 0.5, 9.0);
        let a = full * p.extend(1.0);
        let b = rel * (p - camera.position).extend(1.0);
        assert!((a / a.w - b / b.w).abs().max_element() < 1e-5, "{a} {b}");
    }

    #[test]
    fn wgsl_structs_match_rust_sizes() {
        let src = format!(
            "{}{}",
            FRAME_WGSL, "@group(0) @binding(0) var<uniform> f: FrameUniforms;"
        );
        let m = shadercheck::assert_valid("frame.wgsl", &src, shadercheck::Caps::CORE);
        let size = |name: &str| {
            m.types.iter().find_map(|(_, t)| match &t.inner {
                naga::TypeInner::Struct { span, .. } if t.name.as_deref() == Some(name) => {
                    Some(*span as usize)
                }
                _ => None,
            })
        };
        assert_eq!(size("FrameUniforms"), Some(size_of::<FrameUniforms>()));
        assert_eq!(size("GpuInstance"), Some(size_of::<GpuInstance>()));
        assert_eq!(size("GpuPointLight"), Some(size_of::<GpuPointLight>()));
    }
}
