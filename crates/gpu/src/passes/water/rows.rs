use bytemuck::{Pod, Zeroable};
use shader::{Binding, Group, Kind, Sample};

use crate::resources::rows::FrameUniforms;
/// The per-frame water constants (WGSL `GpuWaterFrame`), 496 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct GpuWaterFrame {
    pub view_proj: [[f32; 4]; 4],
    pub inv_rotation: [[f32; 4]; 4],
    pub planes: [[f32; 4]; 6],
    pub camera: [f32; 4],
    pub tan_half: [f32; 4],
    pub size: [u32; 4],
    pub grid: [u32; 4],
    pub far: [u32; 4],
    pub counts: [u32; 4],
    pub sectors: [f32; 4],
    pub shore: [f32; 4],
    pub material_map: [f32; 4],
    pub misc: [f32; 4],
    pub normals: [f32; 4],
    pub fbm: water::noise::WaterFbmParams,
    pub flow: [f32; 4],
    pub foam: [f32; 8],
    pub shore_size: [u32; 4],
}
const _: () = assert!(size_of::<GpuWaterFrame>() == 496);

/// A near body's record (WGSL `GpuWaterBody`), 48 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct GpuWaterBody {
    pub min: [f32; 4],
    pub max: [f32; 4],
    pub first_index: u32,
    pub index_count: u32,
    pub body: u32,
    pub material: u32,
}
const _: () = assert!(size_of::<GpuWaterBody>() == 48);

/// A displacement decal (WGSL `GpuWaterDecal`), 160 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct GpuWaterDecal {
    pub world_to_box: [[f32; 4]; 4],
    pub box_to_world: [[f32; 4]; 4],
    pub params: [f32; 4],
    pub texture: [u32; 4],
}
const _: () = assert!(size_of::<GpuWaterDecal>() == 160);

/// WGSL `GPU_WATER_FLAG_*`.
pub(crate) const FLAG_FLOW: u32 = 1;

pub(crate) const FLAG_SHORE: u32 = 2;

pub(crate) const FLAG_SSR: u32 = 4;

pub(crate) const FLAG_MATERIAL_MAP: u32 = 8;

/// The visibility pass's counters (WGSL `GPU_WATER_STAT_*`).
pub(crate) const STAT_NEAR: usize = 0;

pub(crate) const STAT_FAR: usize = 1;

pub(crate) const STAT_NODES: usize = 2;

/// Words of the counters.
pub(crate) const STAT_WORDS: u64 = 4;

/// Quads per tile side at the talk's density: a 32-pixel tile in 2 x 2-pixel quads
/// (`GridMesh::for_buffer(512, 32)`).
pub(crate) const GRID_QUADS: u32 = 16;

/// The frame's uniforms, which most water groups bind first.
pub(crate) const FRAME: Binding = Binding::new("frame", Kind::uniform(size_of::<FrameUniforms>()));
/// The water's per-frame constants ([`GpuWaterFrame`]).
pub(crate) const WATER: Binding = Binding::new("water", Kind::uniform(size_of::<GpuWaterFrame>()));
/// The water materials (`water::material::WaterMaterialGpu` rows).
pub(crate) const MATERIALS: Binding = Binding::new(
    "materials",
    Kind::read(size_of::<water::material::WaterMaterialGpu>()),
);

/// An unfilterable float texture named `name` (the passes read it with `textureLoad`).
pub(crate) const fn float_texture(name: &'static str) -> Binding {
    Binding::new(name, Kind::texture_2d(Sample::Float { filterable: false }))
}

/// A water pass's group `water` (the name its WGSL and the water's bind groups use) over
/// `bindings`.
pub(crate) const fn water_group(bindings: &'static [Binding]) -> Group {
    Group {
        name: "water",
        bindings,
    }
}
