//! Every record the GPU reads, as `#[repr(C)]` Pod structs named after their WGSL twins in
//! `gpu::frame` and `gpu::scene` (sizes and member offsets checked against naga's layout
//! in the tests below).

use crate::scene::{Material, ShaderKind};
use bytemuck::{Pod, Zeroable};

/// Per-frame constants (WGSL `FrameUniforms`): 496 bytes. See `wgsl/frame.wgsl` for the
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
    /// Local lights (point and spot) bound.
    pub local_light_count: u32,
    /// log2 scale applied to the resolve's texture gradients.
    pub mip_bias: f32,
    /// Frames rendered since the renderer was made.
    pub frame_index: u32,
    /// The frame input's time (seconds).
    pub time: f32,
    /// Origin-relative position to the baked sun map's clip space (KZ2's pre-rendered sun
    /// shadow); all zero when there is none.
    pub baked_sun: [[f32; 4]; 4],
    /// Camera-relative world to view space: the camera's rotation (the KZ2 G-buffer
    /// stores view-space normals).
    pub view_rotation: [[f32; 4]; 4],
    /// The scene's wind (`Wind::uniform`: direction times amplitude in x, z, angular
    /// frequency, 1 / height); all zero without one (nothing sways).
    pub wind: [f32; 4],
    /// The previous frame's time (seconds; this frame's on a first frame), for the
    /// animated foliage's motion vectors.
    pub prev_time: f32,
    /// Padding to `vrs`'s 16-byte alignment.
    pub _pad: [f32; 3],
    /// HFW's software VRS (`VrsConfig::uniform`): distances (metres) where 2x1 and 2x2
    /// begin, screen speeds (pixels per frame) that force 2x1 and 2x2; all zero: off (the
    /// standard vis layout).
    pub vrs: [f32; 4],
}
const _: () = assert!(size_of::<FrameUniforms>() == 496);

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
    /// The mesh's primitive bits (`visbuf::PrimitiveBits`) in the low 8 bits; for static
    /// instances, the LOD fade above them (`GPU_INSTANCE_FADE_CELLS_SHIFT`,
    /// `GPU_INSTANCE_FADING`, `GPU_INSTANCE_FADING_OUT`), written by the placement.
    pub primitive_bits: u32,
    /// Index into the material table.
    pub material: u32,
}
const _: () = assert!(size_of::<GpuInstance>() == 64);

/// `GpuInstance::primitive_bits`: the mesh's primitive bits.
pub(crate) const GPU_INSTANCE_PRIMITIVE_BITS_MASK: u32 = 0xff;
/// `GpuInstance::primitive_bits`: the Bayer cells (of 16) a fading instance keeps.
#[cfg_attr(
    not(test),
    expect(
        dead_code,
        reason = "written on the GPU only; the WGSL is checked against it"
    )
)]
pub(crate) const GPU_INSTANCE_FADE_CELLS_SHIFT: u32 = 8;
/// `GpuInstance::primitive_bits`: the instance is fading (the laydown dithers it).
#[cfg_attr(
    not(test),
    expect(
        dead_code,
        reason = "written on the GPU only; the WGSL is checked against it"
    )
)]
pub(crate) const GPU_INSTANCE_FADING: u32 = 0x1_0000;
/// `GpuInstance::primitive_bits`: it is fading out (the complementary pattern).
#[cfg_attr(
    not(test),
    expect(
        dead_code,
        reason = "written on the GPU only; the WGSL is checked against it"
    )
)]
pub(crate) const GPU_INSTANCE_FADING_OUT: u32 = 0x2_0000;
const _: () = assert!(visbuf::MAX_PRIMITIVE_BITS <= GPU_INSTANCE_PRIMITIVE_BITS_MASK);

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

/// One material (WGSL `GpuMaterial`): 80 bytes. Map layers are [`NO_MAP`] where the
/// material has no such map.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct GpuMaterial {
    /// Linear RGB tint (the base colour factor).
    pub tint: [f32; 3],
    /// Albedo array layer of the base colour.
    pub albedo_layer: u32,
    /// Alpha-test cutoff (0 for opaque materials: nothing is discarded).
    pub alpha_cutoff: f32,
    /// Perceptual roughness.
    pub roughness: f32,
    /// Specular intensity.
    pub specular: f32,
    /// `ShaderKind::id`.
    pub shader: u32,
    /// Emitted radiance, linear RGB.
    pub emissive: [f32; 3],
    /// Metalness.
    pub metallic: f32,
    /// Data array layer of the tangent-space normal map.
    pub normal_layer: u32,
    /// The normal map's XY scale.
    pub normal_scale: f32,
    /// Data array layer of the metallic-roughness map (G roughness, B metallic).
    pub metallic_roughness_layer: u32,
    /// Data array layer of the occlusion map (R).
    pub occlusion_layer: u32,
    /// The occlusion map's strength.
    pub occlusion_strength: f32,
    /// Albedo array layer of the emissive map.
    pub emissive_layer: u32,
    /// `MaterialFeatures` bits.
    pub features: u32,
    /// Padding to 16 bytes.
    pub pad: u32,
}
const _: () = assert!(size_of::<GpuMaterial>() == 80);

/// The layer of a map a material does not have (WGSL `GPU_MATERIAL_NO_MAP`).
pub(crate) const NO_MAP: u32 = u32::MAX;

impl GpuMaterial {
    /// The row of `m`.
    pub(crate) fn new(m: &Material) -> Self {
        let maps = &m.maps;
        GpuMaterial {
            tint: m.tint.to_array(),
            albedo_layer: m.albedo_layer,
            alpha_cutoff: match m.shader {
                ShaderKind::AlphaTested => m.alpha_cutoff,
                ShaderKind::Opaque => 0.0,
            },
            roughness: m.roughness,
            specular: m.specular,
            shader: m.shader.id(),
            emissive: m.emissive.to_array(),
            metallic: m.metallic,
            normal_layer: maps.normal.map_or(NO_MAP, |n| n.layer),
            normal_scale: maps.normal.map_or(1.0, |n| n.scale),
            metallic_roughness_layer: maps.metallic_roughness.unwrap_or(NO_MAP),
            occlusion_layer: maps.occlusion.map_or(NO_MAP, |o| o.layer),
            occlusion_strength: maps.occlusion.map_or(0.0, |o| o.strength),
            emissive_layer: maps.emissive.unwrap_or(NO_MAP),
            features: m.features().0,
            pad: 0,
        }
    }
}

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

/// What one static setup handle draws and where its reserved slots and micro-batch IDs
/// are (WGSL `GpuStaticSetup`, `gpu::static_place`), 48 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub(crate) struct GpuStaticSetup {
    /// The mesh's first index.
    pub first_index: u32,
    /// Its index count (3 × primitives).
    pub index_count: u32,
    /// Its base vertex.
    pub base_vertex: u32,
    /// The instance-table slot of rank 0.
    pub first_slot: u32,
    /// Slots reserved (most instances placed per frame).
    pub capacity: u32,
    /// The micro-batch ID of rank 0.
    pub first_id: u32,
    /// The mesh's primitive bits.
    pub primitive_bits: u32,
    /// The material index.
    pub material: u32,
    /// The draw list: 0 opaque, 1 alpha-tested.
    pub list: u32,
    /// Zero.
    pub pad0: u32,
    /// Zero.
    pub pad1: u32,
    /// Zero.
    pub pad2: u32,
}
const _: () = assert!(size_of::<GpuStaticSetup>() == 48);

/// The placement's per-view constants (WGSL `GpuStaticParams`), 48 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct GpuStaticParams {
    /// The query's floating origin minus the scene's origin, metres (whole numbers), `w` 0.
    pub offset: [f32; 4],
    /// Setups in the table.
    pub setup_count: u32,
    /// Workgroups per dispatch row (`shader::MAX_WORKGROUPS_X`).
    pub row_width: u32,
    /// First draw of the alpha-tested list (the opaque setups' count).
    pub alpha_base: u32,
    /// The first reserved slot: slot `s`'s debug word is `debug[s - debug_base]`
    /// (`u32::MAX`: no debug words, as for shadow views).
    pub debug_base: u32,
    /// The slot of the instance buffer's first row: slot `s` is written to row
    /// `s - row_base` and drawn as instance `s - row_base` (0: the scene's instance table,
    /// for the camera view; the first reserved slot: a shadow view's own rows, which hold
    /// the reserved slots only).
    pub row_base: u32,
    /// Zero.
    pub pad0: u32,
    /// Zero.
    pub pad1: u32,
    /// Zero.
    pub pad2: u32,
}
const _: () = assert!(size_of::<GpuStaticParams>() == 48);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shaders::LIBRARY;

    fn check(module: &str, name: &str, size: usize, members: &[(&str, u32)]) {
        let m = shadercheck::assert_composed(LIBRARY, module, &[], shadercheck::Caps::CORE);
        shadercheck::assert_struct_layout(&m, name, size, members);
    }

    #[test]
    fn instance_fade_bits_match_the_wgsl() {
        let m = shadercheck::assert_composed(LIBRARY, "gpu::frame", &[], shadercheck::Caps::CORE);
        for (name, v) in [
            (
                "GPU_INSTANCE_PRIMITIVE_BITS_MASK",
                GPU_INSTANCE_PRIMITIVE_BITS_MASK,
            ),
            (
                "GPU_INSTANCE_FADE_CELLS_SHIFT",
                GPU_INSTANCE_FADE_CELLS_SHIFT,
            ),
            ("GPU_INSTANCE_FADING", GPU_INSTANCE_FADING),
            ("GPU_INSTANCE_FADING_OUT", GPU_INSTANCE_FADING_OUT),
        ] {
            assert_eq!(shadercheck::const_u32(&m, name), Some(v), "{name}");
        }
        // The wind sways the alpha-tested materials (GpuMaterial::shader).
        let m = shadercheck::assert_composed(
            LIBRARY,
            "gpu::scene_bindings",
            &[],
            shadercheck::Caps::CORE,
        );
        assert_eq!(
            shadercheck::const_u32(&m, "GPU_SHADER_ALPHA_TESTED"),
            Some(ShaderKind::AlphaTested.id())
        );
        assert_eq!(
            shadercheck::const_u32(&m, "GPU_MATERIAL_NO_MAP"),
            Some(NO_MAP)
        );
        // The material's permutation bits are scene::MaterialFeatures'.
        let m =
            shadercheck::assert_composed(LIBRARY, "gpu::material", &[], shadercheck::Caps::CORE);
        use crate::scene::MaterialFeatures as F;
        for (name, f) in [
            ("MATERIAL_NORMAL_MAP", F::NORMAL_MAP),
            ("MATERIAL_METALLIC_ROUGHNESS_MAP", F::METALLIC_ROUGHNESS_MAP),
            ("MATERIAL_OCCLUSION_MAP", F::OCCLUSION_MAP),
            ("MATERIAL_EMISSIVE", F::EMISSIVE),
        ] {
            assert_eq!(shadercheck::const_u32(&m, name), Some(f.0), "{name}");
        }
    }

    #[test]
    fn wgsl_structs_have_the_rust_layouts() {
        use shadercheck::members;
        check(
            "gpu::frame",
            "FrameUniforms",
            size_of::<FrameUniforms>(),
            &members!(FrameUniforms {
                view_proj,
                inv_view_proj,
                prev_view_proj,
                camera_position,
                origin_offset,
                viewport,
                sun_direction,
                sun_color,
                ambient,
                sky,
                local_light_count,
                mip_bias,
                frame_index,
                time,
                baked_sun,
                view_rotation,
                wind,
                prev_time,
                vrs,
            }),
        );
        // The Rust rows array is three WGSL members.
        let rows = core::mem::offset_of!(GpuInstance, rows) as u32;
        let rest = members!(GpuInstance {
            micro_batch,
            instance_field,
            primitive_bits,
            material,
        });
        let instance: Vec<(&str, u32)> = [("row0", rows), ("row1", rows + 16), ("row2", rows + 32)]
            .into_iter()
            .chain(rest)
            .collect();
        check(
            "gpu::frame",
            "GpuInstance",
            size_of::<GpuInstance>(),
            &instance,
        );
        check(
            "gpu::scene",
            "GpuVertex",
            size_of::<GpuVertex>(),
            &members!(GpuVertex {
                position,
                u,
                normal,
                v,
                tangent
            }),
        );
        check(
            "gpu::scene",
            "GpuMaterial",
            size_of::<GpuMaterial>(),
            &members!(GpuMaterial {
                tint,
                albedo_layer,
                alpha_cutoff,
                roughness,
                specular,
                shader,
                emissive,
                metallic,
                normal_layer,
                normal_scale,
                metallic_roughness_layer,
                occlusion_layer,
                occlusion_strength,
                emissive_layer,
                features,
                pad
            }),
        );
        check(
            "gpu::scene",
            "GpuMesh",
            size_of::<GpuMesh>(),
            &members!(GpuMesh {
                first_index,
                primitive_count,
                base_vertex,
                vertex_count
            }),
        );
        check(
            "gpu::scene",
            "GpuMicroBatch",
            size_of::<GpuMicroBatch>(),
            &members!(GpuMicroBatch {
                first_instance,
                first_id,
                mesh,
                primitive_bits
            }),
        );
        check(
            "gpu::static_place",
            "GpuStaticSetup",
            size_of::<GpuStaticSetup>(),
            &members!(GpuStaticSetup {
                first_index,
                index_count,
                base_vertex,
                first_slot,
                capacity,
                first_id,
                primitive_bits,
                material,
                list,
                pad0,
                pad1,
                pad2
            }),
        );
        check(
            "gpu::static_place",
            "GpuStaticParams",
            size_of::<GpuStaticParams>(),
            &members!(GpuStaticParams {
                offset,
                setup_count,
                row_width,
                alpha_base,
                debug_base,
                row_base,
                pad0,
                pad1,
                pad2
            }),
        );
    }
}
