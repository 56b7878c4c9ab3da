//! The local lights' GPU data: the light buffers of one target size ([`LightBuffers`]), the
//! stencil volumes' rows and per-frame draws, and the volumes' targets.

use crate::error::Result;
use crate::resources::static_pool::empty_storage;
use crate::resources::targets::Targets;
use bytemuck::{Pod, Zeroable};
use deferred::lights::{DeferredLight, DeferredTileDepth, MAX_LIGHTS_PER_TILE, tile_counts};
use deferred::pass::{LightCullCounters, LightCullParams};
/// The light buffers of one target size: the lights (grown as needed), the per-tile depth
/// ranges and lists, the counters and the two passes' uniforms.
#[derive(Clone)]
pub(crate) struct LightBuffers {
    pub tile_params: wgpu::Buffer,
    pub cull_params: wgpu::Buffer,
    pub lights: wgpu::Buffer,
    /// The stencil volumes' rows (`GpuLightVolume`), as many as lights.
    pub volumes: wgpu::Buffer,
    pub tile_depths: wgpu::Buffer,
    pub counts: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub counters: wgpu::Buffer,
    /// Tiles across and down.
    pub tiles: [u32; 2],
    /// Lights `lights` holds.
    pub capacity: usize,
}

impl LightBuffers {
    /// Buffers for `targets` and `capacity` lights.
    pub(crate) fn new(device: &wgpu::Device, targets: &Targets, capacity: usize) -> Result<Self> {
        let (tx, ty) = tile_counts(targets.width, targets.height);
        let tiles = u64::from(tx) * u64::from(ty);
        let uniform = |label, size: usize| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let capacity = capacity.max(1);
        let (lights, volumes) = Self::light_rows(device, capacity)?;
        Ok(Self {
            tile_params: uniform("light tile depth params", size_of::<GpuTileDepthParams>()),
            cull_params: uniform("light culling params", size_of::<LightCullParams>()),
            lights,
            volumes,
            tile_depths: empty_storage(
                device,
                "light tile depths",
                tiles * size_of::<DeferredTileDepth>() as u64,
            )?,
            counts: empty_storage(device, "light tile counts", tiles * 4)?,
            indices: empty_storage(
                device,
                "light tile indices",
                tiles * u64::from(MAX_LIGHTS_PER_TILE) * 4,
            )?,
            counters: empty_storage(
                device,
                "light culling counters",
                size_of::<LightCullCounters>() as u64,
            )?,
            tiles: [tx, ty],
            capacity,
        })
    }

    /// These buffers with room for `capacity` lights: new light and volume rows, the same
    /// per-tile buffers (so what binds them outside the light passes, the compute laydown's
    /// unpack writing the tile depths, stays bound).
    pub(crate) fn with_capacity(&self, device: &wgpu::Device, capacity: usize) -> Result<Self> {
        let capacity = capacity.max(1);
        let (lights, volumes) = Self::light_rows(device, capacity)?;
        Ok(Self {
            lights,
            volumes,
            capacity,
            ..self.clone()
        })
    }

    /// The light rows and volume rows for `capacity` lights.
    fn light_rows(device: &wgpu::Device, capacity: usize) -> Result<(wgpu::Buffer, wgpu::Buffer)> {
        Ok((
            empty_storage(
                device,
                "local lights",
                (capacity * size_of::<DeferredLight>()) as u64,
            )?,
            empty_storage(
                device,
                "light volumes",
                (capacity * size_of::<GpuLightVolume>()) as u64,
            )?,
        ))
    }
}

/// What lighting needs of the local lights besides the lights (WGSL `GpuLocalLights`),
/// 80 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct GpuLocalLights {
    /// Camera-relative world to view space: the camera's rotation.
    pub view_rotation: [[f32; 4]; 4],
    /// Light tiles across and down.
    pub tiles: [u32; 2],
    /// Zero.
    pub pad: [u32; 2],
}

/// One light drawn as a volume (WGSL `GpuLightVolume`), 32 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct GpuLightVolume {
    /// View-space centre of the light's bounding sphere and its radius (metres): the unit
    /// mesh is scaled by it.
    pub sphere: [f32; 4],
    /// The light's index in the light buffer.
    pub light: u32,
    /// Zero.
    pub pad: [u32; 3],
}

/// One light's draw: its volume row and whether the eye may be inside its mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct VolumeDraw {
    /// Index of its [`GpuLightVolume`] (the draw's instance).
    pub volume: u32,
    /// Back faces alone, no stencil (the front faces may be clipped by the near plane).
    pub inside: bool,
    /// The light's spot shadow map this frame (its slot), if it has one: the shading
    /// permutation that reads it.
    pub map: Option<u32>,
    /// The light has a specular term: else the permutation compiled without it.
    pub specular: bool,
}

/// The tile-depth pass's parameters (WGSL `GpuTileDepthParams`), 16 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub(crate) struct GpuTileDepthParams {
    /// Viewport width and height in pixels.
    pub size: [u32; 2],
    /// Tiles across.
    pub tiles_x: u32,
    /// Non-zero for reversed depth.
    pub reversed: u32,
}
