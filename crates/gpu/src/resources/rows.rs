//! Every record the GPU reads, as `#[repr(C)]` Pod structs named after their WGSL twins in
//! `gpu::frame` and `gpu::scene` (sizes and member offsets checked against naga's layout
//! in the tests below).

use bytemuck::{Pod, Zeroable};

/// Per-frame constants (WGSL `FrameUniforms`): 320 bytes. See `wgsl/frame.wgsl` for the
/// spaces: positions are camera-relative, stored origin-relative.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct FrameUniforms {
    /// Camera-relative position to clip: the camera's rotation and projection only.
    pub view_proj: [[f32; 4]; 4],
    /// Inverse of `view_proj`.
    pub inv_view_proj: [[f32; 4]; 4],
    /// This frame's camera-relative position to last frame's clip.
    pub prev_view_proj: [[f32; 4]; 4],
    /// Camera position (world, metres), w = 1.
    pub camera_position: [f32; 4],
    /// Scene origin minus camera position (metres), w = 0.
    pub origin_offset: [f32; 4],
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
    /// Point lights bound.
    pub point_light_count: u32,
    /// log2 scale applied to the resolve's texture gradients.
    pub mip_bias: f32,
    /// Frames rendered since the renderer was made.
    pub frame_index: u32,
    /// The frame input's time (seconds).
    pub time: f32,
}
const _: () = assert!(size_of::<FrameUniforms>() == 320);

/// One instance (WGSL `GpuInstance`): object-to-origin-relative transform rows and its
/// place in the vis buffer. 64 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct GpuInstance {
    /// Rows 0..2 of the 3x4 object-to-origin-relative transform.
    pub rows: [[f32; 4]; 3],
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

/// One point light (WGSL `GpuPointLight`): origin-relative position and radius, colour.
/// 32 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct GpuPointLight {
    /// Origin-relative position (xyz) and radius (w), metres.
    pub position_radius: [f32; 4],
    /// Linear RGB intensity.
    pub color: [f32; 4],
}
const _: () = assert!(size_of::<GpuPointLight>() == 32);

/// One vertex as every pass pulls it (WGSL `GpuVertex`): 48 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct GpuVertex {
    /// Object-space position (metres).
    pub position: [f32; 3],
    /// Texture coordinate u.
    pub u: f32,
    /// Object-space unit normal.
    pub normal: [f32; 3],
    /// Texture coordinate v.
    pub v: f32,
    /// Object-space tangent, handedness in w.
    pub tangent: [f32; 4],
}
const _: () = assert!(size_of::<GpuVertex>() == 48);

/// One material (WGSL `GpuMaterial`): 32 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct GpuMaterial {
    /// Linear RGB tint.
    pub tint: [f32; 3],
    /// Albedo array layer.
    pub albedo_layer: u32,
    /// Alpha-test cutoff (0 for opaque materials: nothing is discarded).
    pub alpha_cutoff: f32,
    /// Perceptual roughness.
    pub roughness: f32,
    /// Specular intensity.
    pub specular: f32,
    /// `ShaderKind::id`.
    pub shader: u32,
}
const _: () = assert!(size_of::<GpuMaterial>() == 32);

/// Where one mesh sits in the concatenated buffers (WGSL `GpuMesh`). 16 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub(crate) struct GpuMesh {
    /// First index in the index array.
    pub first_index: u32,
    /// Primitives (index count / 3).
    pub primitive_count: u32,
    /// Added to every index (the mesh's first vertex in the vertex array).
    pub base_vertex: u32,
    /// Vertices after encoding.
    pub vertex_count: u32,
}
const _: () = assert!(size_of::<GpuMesh>() == 16);

/// What the resolve looks up per micro-batch ID (WGSL `GpuMicroBatch`), indexed by the
/// 16-bit ID of the vis word: every ID of a micro batch's range holds the same row. 16
/// bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub(crate) struct GpuMicroBatch {
    /// Global index (in the instance table) of the micro batch's instance 0.
    pub first_instance: u32,
    /// The first micro-batch ID of the micro batch's range.
    pub first_id: u32,
    /// Index of the mesh record.
    pub mesh: u32,
    /// The mesh's primitive bits.
    pub primitive_bits: u32,
}
const _: () = assert!(size_of::<GpuMicroBatch>() == 16);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::passes::LIBRARY;

    /// (size, member offsets) of every struct of `module`, by name.
    fn layouts(module: &str) -> Vec<(String, u32, Vec<u32>)> {
        let m = shadercheck::assert_composed(LIBRARY, module, &[], shadercheck::Caps::CORE);
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(m.to_ctx()).unwrap();
        m.types
            .iter()
            .filter_map(|(h, t)| match &t.inner {
                naga::TypeInner::Struct { members, .. } => Some((
                    t.name.clone()?,
                    layouter[h].size,
                    members.iter().map(|m| m.offset).collect(),
                )),
                _ => None,
            })
            .collect()
    }

    fn check(module: &str, name: &str, size: usize, offsets: &[usize]) {
        let all = layouts(module);
        let (_, s, o) = all
            .iter()
            .find(|(n, _, _)| n == name)
            .unwrap_or_else(|| panic!("{module} has no struct {name}"));
        assert_eq!(*s as usize, size, "{name} size");
        let o: Vec<usize> = o.iter().map(|&x| x as usize).collect();
        assert_eq!(o, offsets, "{name} member offsets");
    }

    #[test]
    fn wgsl_structs_have_the_rust_layouts() {
        use core::mem::offset_of as at;
        type F = FrameUniforms;
        check(
            "gpu::frame",
            "FrameUniforms",
            size_of::<F>(),
            &[
                at!(F, view_proj),
                at!(F, inv_view_proj),
                at!(F, prev_view_proj),
                at!(F, camera_position),
                at!(F, origin_offset),
                at!(F, viewport),
                at!(F, sun_direction),
                at!(F, sun_color),
                at!(F, ambient),
                at!(F, sky),
                at!(F, point_light_count),
                at!(F, mip_bias),
                at!(F, frame_index),
                at!(F, time),
            ],
        );
        type I = GpuInstance;
        check(
            "gpu::frame",
            "GpuInstance",
            size_of::<I>(),
            &[
                at!(I, rows),
                at!(I, rows) + 16,
                at!(I, rows) + 32,
                at!(I, micro_batch),
                at!(I, instance_field),
                at!(I, primitive_bits),
                at!(I, material),
            ],
        );
        check(
            "gpu::frame",
            "GpuPointLight",
            size_of::<GpuPointLight>(),
            &[0, 16],
        );
        type V = GpuVertex;
        check(
            "gpu::scene",
            "GpuVertex",
            size_of::<V>(),
            &[
                at!(V, position),
                at!(V, u),
                at!(V, normal),
                at!(V, v),
                at!(V, tangent),
            ],
        );
        type M = GpuMaterial;
        check(
            "gpu::scene",
            "GpuMaterial",
            size_of::<M>(),
            &[
                at!(M, tint),
                at!(M, albedo_layer),
                at!(M, alpha_cutoff),
                at!(M, roughness),
                at!(M, specular),
                at!(M, shader),
            ],
        );
        check(
            "gpu::scene",
            "GpuMesh",
            size_of::<GpuMesh>(),
            &[0, 4, 8, 12],
        );
        check(
            "gpu::scene",
            "GpuMicroBatch",
            size_of::<GpuMicroBatch>(),
            &[0, 4, 8, 12],
        );
    }
}
