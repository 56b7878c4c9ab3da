//! FC5's water in the frame (seed 003), one module per pass; the order, the targets and
//! the per-frame constants are here. [`crate::water_scene`] has the API and the table of
//! passes, `water::draw` the CPU side (meshes, sector tree, material map);
//! this module runs them after the opaque frame's lighting:
//!
//! hiz -> [`visibility`] -> [`position`] -> [`displacement`] -> [`tiles`] -> depth copy ->
//! [`tessellation`] -> light tiles -> [`normals`] -> [`foam`] -> [`composite`]
//!
//! Everything sized by the image lives in [`WaterTargets`] (made with the state), the
//! world's data in [`WaterData`] (made by `Renderer::set_water`).

pub(crate) mod composite;
pub(crate) mod displacement;
pub(crate) mod foam;
pub(crate) mod normals;
pub(crate) mod position;
pub(crate) mod tessellation;
pub(crate) mod tiles;
pub(crate) mod visibility;

use bytemuck::{Pod, Zeroable};
use glam::Mat4;
use wgpu::util::DeviceExt;

use super::FrameContext;
use super::lights::{LightBuffers, TILE_DEPTH};
use crate::error::Result;
use crate::frame::FrameInput;
use crate::resources::targets::{DEPTH_FORMAT, texture};
use crate::timing::GpuTimer;
use crate::water_scene::{MAX_WATER_DECALS, WaterDecal, WaterOptions, WaterScene, WaterStats};
use shader::pipeline::ComputePass;
use water::draw::{MaterialMap, NearMeshes, SectorTree};

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

/// The mini G-buffer's size for an image of `width` x `height` at `scale`.
pub(crate) fn buffer_size(width: u32, height: u32, scale: f32) -> [u32; 2] {
    [
        ((width as f32 * scale).round() as u32).clamp(1, water::tiles::MAX_BUFFER_SIZE),
        ((height as f32 * scale).round() as u32).clamp(1, water::tiles::MAX_BUFFER_SIZE),
    ]
}

/// Textures and buffers sized by the image (and the mini G-buffer).
pub(crate) struct WaterTargets {
    /// The mini G-buffer's size.
    pub size: [u32; 2],
    pub data: (wgpu::Texture, wgpu::TextureView),
    pub normal: (wgpu::Texture, wgpu::TextureView),
    pub linear: (wgpu::Texture, wgpu::TextureView),
    pub depth: wgpu::TextureView,
    pub displacement: (wgpu::Texture, wgpu::TextureView),
    /// The tessellation's vertices: per mini G-buffer pixel the displaced point in clip
    /// space (the displacement pass writes them).
    pub vertices: wgpu::Buffer,
    /// The depth with water (full resolution).
    pub depth_water: (wgpu::Texture, wgpu::TextureView),
    /// The tessellation's view depth and mini G-buffer UV (full resolution).
    pub surface: (wgpu::Texture, wgpu::TextureView),
    pub normals: (wgpu::Texture, wgpu::TextureView),
    pub foam: (wgpu::Texture, wgpu::TextureView),
    /// Lighting's HDR colour before tone mapping.
    pub hdr: (wgpu::Texture, wgpu::TextureView),
    /// The water's light tiles.
    pub tile_depths: wgpu::Buffer,
    pub light_counts: wgpu::Buffer,
    pub light_indices: wgpu::Buffer,
    pub light_counters: wgpu::Buffer,
    /// Tiles of the mini G-buffer: counts, list, and the grid's indexed indirect args.
    pub tile_counts: wgpu::Buffer,
    pub tile_list: wgpu::Buffer,
    pub tile_args: wgpu::Buffer,
    /// The grid's 16-bit vertex words, as an index buffer.
    pub grid: wgpu::Buffer,
    pub tiles: [u32; 2],
}

fn storage(
    device: &wgpu::Device,
    label: &str,
    bytes: u64,
    extra: wgpu::BufferUsages,
) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(16).next_multiple_of(4),
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC
            | extra,
        mapped_at_creation: false,
    })
}

fn init(
    device: &wgpu::Device,
    label: &str,
    bytes: &[u8],
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    crate::resources::buffer_init(
        device,
        label,
        bytes,
        16,
        usage | wgpu::BufferUsages::STORAGE,
    )
}

impl WaterTargets {
    pub(crate) fn new(device: &wgpu::Device, width: u32, height: u32, scale: f32) -> Result<Self> {
        use wgpu::TextureUsages as U;
        let size = buffer_size(width, height, scale);
        let [w, h] = size;
        let rw = U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC | U::COPY_DST;
        let sw = U::STORAGE_BINDING | U::TEXTURE_BINDING | U::COPY_SRC | U::COPY_DST;
        let grid = water::tiles::TileGrid::new(w, h, water::tiles::TILE_SIZE)?;
        let tiles = [grid.tiles_x(), grid.tiles_y()];
        let tile_count = u64::from(grid.tile_count());
        let mesh = water::tiles::GridMesh::new(GRID_QUADS)?;
        let (ltx, lty) = deferred::lights::tile_counts(width, height);
        let light_tiles = u64::from(ltx) * u64::from(lty);
        Ok(Self {
            size,
            data: texture(device, "water data", w, h, wgpu::TextureFormat::R32Uint, rw),
            normal: texture(
                device,
                "water mesh normal",
                w,
                h,
                wgpu::TextureFormat::Rgba16Float,
                rw,
            ),
            linear: texture(
                device,
                "water view depth",
                w,
                h,
                wgpu::TextureFormat::R32Float,
                rw,
            ),
            depth: texture(
                device,
                "water position depth",
                w,
                h,
                DEPTH_FORMAT,
                U::RENDER_ATTACHMENT,
            )
            .1,
            displacement: texture(
                device,
                "water displacement",
                w,
                h,
                wgpu::TextureFormat::Rgba32Float,
                sw,
            ),
            vertices: storage(
                device,
                "water grid vertices",
                u64::from(w) * u64::from(h) * 16,
                wgpu::BufferUsages::empty(),
            ),
            depth_water: texture(
                device,
                "depth with water",
                width,
                height,
                DEPTH_FORMAT,
                U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC | U::COPY_DST,
            ),
            surface: texture(
                device,
                "water surface",
                width,
                height,
                wgpu::TextureFormat::Rgba32Float,
                rw,
            ),
            normals: texture(
                device,
                "water normals",
                width,
                height,
                wgpu::TextureFormat::Rgba16Float,
                sw,
            ),
            foam: texture(
                device,
                "water foam",
                width,
                height,
                wgpu::TextureFormat::R32Float,
                sw,
            ),
            hdr: texture(
                device,
                "scene hdr",
                width,
                height,
                wgpu::TextureFormat::Rgba16Float,
                sw,
            ),
            tile_depths: storage(
                device,
                "water light tile depths",
                light_tiles * 8,
                wgpu::BufferUsages::empty(),
            ),
            light_counts: storage(
                device,
                "water light counts",
                light_tiles * 4,
                wgpu::BufferUsages::empty(),
            ),
            light_indices: storage(
                device,
                "water light indices",
                light_tiles * u64::from(deferred::lights::MAX_LIGHTS_PER_TILE) * 4,
                wgpu::BufferUsages::empty(),
            ),
            light_counters: storage(
                device,
                "water light counters",
                size_of::<deferred::pass::LightCullCounters>() as u64,
                wgpu::BufferUsages::empty(),
            ),
            tile_counts: storage(
                device,
                "water tile counts",
                tile_count * 4,
                wgpu::BufferUsages::empty(),
            ),
            tile_list: storage(
                device,
                "water tile list",
                tile_count * 4,
                wgpu::BufferUsages::empty(),
            ),
            tile_args: storage(device, "water tile args", 20, wgpu::BufferUsages::INDIRECT),
            grid: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("water grid words"),
                contents: bytemuck::cast_slice(&pad_even(mesh.vertices())),
                usage: wgpu::BufferUsages::INDEX,
            }),
            tiles,
        })
    }

    /// Tiles of the mini G-buffer.
    pub(crate) fn tile_count(&self) -> u32 {
        self.tiles[0] * self.tiles[1]
    }
}

/// `words` padded to an even count (buffers are whole words).
fn pad_even(words: &[u16]) -> Vec<u16> {
    let mut v = words.to_vec();
    if v.len() % 2 == 1 {
        v.push(0);
    }
    v
}

/// A texture of `data` (one mip, one layer unless `layers`).
#[allow(clippy::too_many_arguments)]
fn upload_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    size: [u32; 3],
    format: wgpu::TextureFormat,
    data: &[u8],
) -> wgpu::TextureView {
    let array = size[2] > 1;
    let t = device.create_texture_with_data(
        queue,
        &wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: size[0].max(1),
                height: size[1].max(1),
                depth_or_array_layers: size[2].max(1),
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        data,
    );
    t.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(if array {
            wgpu::TextureViewDimension::D2Array
        } else {
            wgpu::TextureViewDimension::D2
        }),
        ..Default::default()
    })
}

/// The world's data on the GPU (made by `Renderer::set_water`).
pub(crate) struct WaterData {
    pub world: wgpu::TextureView,
    pub atlas: wgpu::TextureView,
    pub shore: wgpu::TextureView,
    pub material_map: wgpu::TextureView,
    pub noise: wgpu::TextureView,
    pub decal_texels: wgpu::TextureView,
    pub materials: wgpu::Buffer,
    pub vertices: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub bodies: wgpu::Buffer,
    pub near_args: wgpu::Buffer,
    pub nodes: wgpu::Buffer,
    pub lists: wgpu::Buffer,
    pub far_list: wgpu::Buffer,
    pub far_args: wgpu::Buffer,
    pub stats: wgpu::Buffer,
    pub decals: wgpu::Buffer,
    pub frame: wgpu::Buffer,
    pub hiz: visibility::WaterHiz,
    /// Bodies drawn per body.
    pub body_count: u32,
    /// The far tree's shape.
    pub tree: SectorTreeInfo,
    /// The frame constants that stay (everything but the camera's and the time).
    pub constants: GpuWaterFrame,
    /// Per decal texture: first layer, frames, width, height.
    pub decal_textures: Vec<[u32; 4]>,
    /// This frame's decals.
    pub decals_cpu: Vec<GpuWaterDecal>,
    pub options: WaterOptions,
}

/// What the frame constants need of the far tree.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct SectorTreeInfo {
    pub levels: u32,
}

/// Everything `set_water` built on the CPU.
pub(crate) struct Built {
    pub near: NearMeshes,
    pub tree: SectorTree,
    pub map: MaterialMap,
    pub max_displacement: f32,
}

impl WaterData {
    /// Uploads `scene` and what was built from it.
    pub(crate) fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &WaterScene,
        built: &Built,
        targets: &WaterTargets,
        frame_size: [u32; 2],
    ) -> Result<Self> {
        let o = &scene.options;
        // The world's words as a texture 4096 (or 8192) texels wide.
        let words = scene.world.words().len() as u64;
        let width = if words > 4096 * 8192 { 8192 } else { 4096 };
        let (texels, w, h) = scene.world.to_texture(width);
        let max_dim = device.limits().max_texture_dimension_2d;
        if w > max_dim || h > max_dim {
            return Err(crate::Error::DeviceLimit {
                limit: "max_texture_dimension_2d",
                needed: u64::from(w.max(h)),
                available: u64::from(max_dim),
            });
        }
        let world = upload_texture(
            device,
            queue,
            "water world",
            [w, h, 1],
            wgpu::TextureFormat::R32Uint,
            bytemuck::cast_slice(&texels),
        );
        let atlas = match &scene.flow {
            Some(a) => upload_texture(
                device,
                queue,
                "water flow atlas",
                [a.width(), a.height(), 1],
                wgpu::TextureFormat::R32Uint,
                bytemuck::cast_slice(a.texels()),
            ),
            None => upload_texture(
                device,
                queue,
                "no flow atlas",
                [1, 1, 1],
                wgpu::TextureFormat::R32Uint,
                &[0; 4],
            ),
        };
        let shore = match &scene.shore {
            Some(s) => upload_texture(
                device,
                queue,
                "water shore distance",
                [s.field.width(), s.field.height(), 1],
                wgpu::TextureFormat::R32Float,
                bytemuck::cast_slice(
                    &s.field
                        .values()
                        .iter()
                        .map(|v| v.clamp(-1.0e6, 1.0e6))
                        .collect::<Vec<f32>>(),
                ),
            ),
            None => upload_texture(
                device,
                queue,
                "no shore distance",
                [1, 1, 1],
                wgpu::TextureFormat::R32Float,
                &[0; 4],
            ),
        };
        let map = &built.map;
        let material_map = if map.words.is_empty() {
            upload_texture(
                device,
                queue,
                "no material map",
                [1, 1, 1],
                wgpu::TextureFormat::R32Uint,
                &[0; 4],
            )
        } else {
            upload_texture(
                device,
                queue,
                "water material map",
                [map.width, map.height, 1],
                wgpu::TextureFormat::R32Uint,
                bytemuck::cast_slice(&map.words),
            )
        };
        let n = scene.noise.size();
        let noise = upload_texture(
            device,
            queue,
            "water noise",
            [n, n, 1],
            wgpu::TextureFormat::R32Float,
            bytemuck::cast_slice(scene.noise.texels()),
        );
        // Decal textures: each frame a layer of the largest size, in its corner.
        let (dw, dh) = scene.decal_textures.iter().fold((1u32, 1u32), |(w, h), t| {
            (w.max(t.width()), h.max(t.height()))
        });
        let mut layers = 0u32;
        let mut decal_textures = Vec::with_capacity(scene.decal_textures.len());
        for t in &scene.decal_textures {
            if t.width().max(t.height()) > crate::water_scene::MAX_WATER_DECAL_SIZE {
                return Err(crate::water_scene::limit(
                    "a decal texture's side",
                    u64::from(t.width().max(t.height())),
                    u64::from(crate::water_scene::MAX_WATER_DECAL_SIZE),
                    "MAX_WATER_DECAL_SIZE",
                ));
            }
            decal_textures.push([layers, t.frames(), t.width(), t.height()]);
            layers = layers.saturating_add(t.frames());
        }
        if layers > crate::water_scene::MAX_WATER_DECAL_LAYERS {
            return Err(crate::water_scene::limit(
                "decal texture frames",
                u64::from(layers),
                u64::from(crate::water_scene::MAX_WATER_DECAL_LAYERS),
                "MAX_WATER_DECAL_LAYERS",
            ));
        }
        let mut decal_data = vec![[0.0f32; 4]; (dw * dh * layers.max(1)) as usize];
        let mut layer = 0usize;
        for t in &scene.decal_textures {
            let (tw, th) = (t.width() as usize, t.height() as usize);
            for f in 0..t.frames() as usize {
                for y in 0..th {
                    for x in 0..tw {
                        let v = t.texels()[(f * th + y) * tw + x];
                        decal_data[(layer * dh as usize + y) * dw as usize + x] =
                            [v.x, v.y, v.z, 0.0];
                    }
                }
                layer += 1;
            }
        }
        let decal_texels = upload_texture(
            device,
            queue,
            "water decal textures",
            [dw, dh, layers.max(1)],
            wgpu::TextureFormat::Rgba32Float,
            bytemuck::cast_slice(&decal_data),
        );
        let decal_texels = if layers.max(1) == 1 {
            // One layer still binds as an array.
            decal_texels
                .texture()
                .create_view(&wgpu::TextureViewDescriptor {
                    dimension: Some(wgpu::TextureViewDimension::D2Array),
                    ..Default::default()
                })
        } else {
            decal_texels
        };
        let materials: Vec<water::material::WaterMaterialGpu> =
            scene.materials.iter().map(|m| m.to_gpu()).collect();
        let near = &built.near;
        let bodies: Vec<GpuWaterBody> = near
            .bodies
            .iter()
            .map(
                |&(lo, hi, first_index, index_count, body, material)| GpuWaterBody {
                    min: lo.extend(0.0).to_array(),
                    max: hi.extend(0.0).to_array(),
                    first_index,
                    index_count,
                    body,
                    material,
                },
            )
            .collect();
        let tree = &built.tree;
        let cap = u64::from(tree.sectors_per_side.max(1)).pow(2);
        let mut constants = GpuWaterFrame {
            size: [
                frame_size[0],
                frame_size[1],
                targets.size[0],
                targets.size[1],
            ],
            grid: [
                targets.tiles[0],
                targets.tiles[1],
                GRID_QUADS,
                bodies.len() as u32,
            ],
            far: [tree.sectors_per_side, tree.levels, o.far_quads, 0],
            counts: [
                materials.len() as u32,
                [
                    (scene.flow.is_some(), FLAG_FLOW),
                    (scene.shore.is_some(), FLAG_SHORE),
                    (o.ssr, FLAG_SSR),
                    (!map.words.is_empty(), FLAG_MATERIAL_MAP),
                ]
                .iter()
                .filter(|(on, _)| *on)
                .fold(0, |a, (_, f)| a | f),
                map.width,
                map.height,
            ],
            sectors: [
                tree.origin.x,
                tree.origin.y,
                tree.sector_size,
                o.near_radius,
            ],
            material_map: [map.origin.x, map.origin.y, map.texel, o.blend_distance],
            misc: [
                0.0,
                o.refraction,
                o.foam_frequency,
                if o.ssr { 24.0 } else { 0.0 },
            ],
            normals: [
                o.normal_radius.radius_at_1m,
                o.normal_radius.max_radius as f32,
                water::specaa::DEFAULT_KAPPA,
                n as f32,
            ],
            fbm: water::noise::Fbm::new(&scene.noise, scene.fbm)?.gpu_params(),
            flow: [o.flow.interval, o.flow.distance, o.flow.noise_strength, 0.0],
            foam: [
                o.foam.shore_width,
                o.foam.speed_start,
                o.foam.speed_full,
                o.foam.shallow_depth,
                o.foam.softness,
                o.foam.mask_bias,
                o.foam.intensity,
                0.0,
            ],
            ..GpuWaterFrame::default()
        };
        if let Some(s) = &scene.shore {
            constants.shore = [s.origin.x, s.origin.y, s.texel_size, built.max_displacement];
            constants.shore_size = [s.field.width(), s.field.height(), 0, 0];
        } else {
            constants.shore = [0.0, 0.0, 1.0, built.max_displacement];
        }
        let u = wgpu::BufferUsages::empty();
        Ok(Self {
            world,
            atlas,
            shore,
            material_map,
            noise,
            decal_texels,
            materials: init(
                device,
                "water materials",
                bytemuck::cast_slice(&materials),
                u,
            ),
            vertices: init(
                device,
                "water near vertices",
                bytemuck::cast_slice(&near.vertices),
                u,
            ),
            indices: crate::resources::buffer_init(
                device,
                "water near indices",
                bytemuck::cast_slice(&near.indices),
                16,
                wgpu::BufferUsages::INDEX,
            ),
            bodies: init(device, "water bodies", bytemuck::cast_slice(&bodies), u),
            near_args: storage(
                device,
                "water near args",
                (bodies.len().max(1) * 20) as u64,
                wgpu::BufferUsages::INDIRECT,
            ),
            nodes: init(
                device,
                "water sector nodes",
                bytemuck::cast_slice(&tree.nodes),
                u,
            ),
            lists: storage(device, "water sector lists", cap * 8, u),
            far_list: storage(device, "water far sectors", cap * 8, u),
            far_args: storage(device, "water far args", 32, wgpu::BufferUsages::INDIRECT),
            stats: storage(device, "water stats", STAT_WORDS * 4, u),
            decals: storage(
                device,
                "water decals",
                u64::from(MAX_WATER_DECALS) * size_of::<GpuWaterDecal>() as u64,
                u,
            ),
            frame: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("water frame"),
                size: size_of::<GpuWaterFrame>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            hiz: visibility::WaterHiz::new(device, frame_size)?,
            body_count: bodies.len() as u32,
            tree: SectorTreeInfo {
                levels: tree.levels,
            },
            constants,
            decal_textures,
            decals_cpu: Vec::new(),
            options: *o,
        })
    }

    /// This frame's constants for `frame`'s camera at `aspect`.
    pub(crate) fn frame_constants(&self, frame: &FrameInput, aspect: f32) -> GpuWaterFrame {
        let c = &frame.camera;
        let k = self.options.fov_scale;
        let tan_y = (c.fov_y * 0.5).tan();
        let fov_w = 2.0 * (tan_y * k).atan();
        let rotation = c.view_rotation();
        let view_proj = Mat4::perspective_infinite_reverse_rh(fov_w, aspect, c.near) * rotation;
        let planes = crate::shadows::clip_planes(view_proj);
        let mut u = self.constants;
        u.view_proj = view_proj.to_cols_array_2d();
        u.inv_rotation = rotation.transpose().to_cols_array_2d();
        u.planes = planes.map(|p| p.to_array());
        u.camera = c.position.extend(c.near).to_array();
        u.tan_half = [tan_y * aspect, tan_y, tan_y * aspect * k, tan_y * k];
        u.far[3] = self.decals_cpu.len() as u32;
        // Time wrapped at a whole number of flow cycles (f32 keeps its fraction).
        let cycle = 2.0 * self.options.flow.interval.max(1e-3);
        u.misc[0] = frame.time.rem_euclid(cycle * 1024.0);
        u
    }
}

/// Every water pass's pipelines, and the lighting variant's group.
/// Records `pass`, one grid dispatch over `size` with `group`, as a compute pass of its own
/// timed under its description's name: the water's grid passes (displacement, normals,
/// foam, composite).
fn record_grid(
    e: &mut wgpu::CommandEncoder,
    pass: &ComputePass<[u32; 2]>,
    group: &wgpu::BindGroup,
    size: [u32; 2],
    timer: &mut GpuTimer,
) {
    let mut compute = timer.begin_compute(e, pass.pass.name);
    pass.record(&mut compute, &[group], &size);
}

pub(crate) struct WaterPasses {
    pub visibility: visibility::Visibility,
    pub position: position::Position,
    pub displacement: ComputePass<[u32; 2]>,
    pub tiles: tiles::Tiles,
    pub tessellation: tessellation::Tessellation,
    pub tile_depth: ComputePass<[u32; 2]>,
    pub cull: ComputePass<deferred::pass::LightCullParams>,
    pub normals: ComputePass<[u32; 2]>,
    pub foam: ComputePass<[u32; 2]>,
    pub composite: ComputePass<[u32; 2]>,
}

impl WaterPasses {
    pub(crate) fn new(device: &wgpu::Device, subgroups: bool, half: bool) -> Result<Self> {
        Ok(Self {
            visibility: visibility::Visibility::new(device)?,
            position: position::Position::new(device)?,
            displacement: displacement::new(device)?,
            tiles: tiles::Tiles::new(device, subgroups)?,
            tessellation: tessellation::Tessellation::new(device)?,
            tile_depth: ComputePass::new(device, &TILE_DEPTH, &[], &[])?,
            cull: ComputePass::new(device, &deferred::pass::LIGHT_CULL_PASS, &[], &[])?,
            normals: normals::new(device)?,
            foam: foam::new(device)?,
            composite: composite::new(device, half)?,
        })
    }
}

/// The water's bind groups.
pub(crate) struct WaterGroups {
    pub hiz: Vec<(bool, wgpu::BindGroup, staticscene::pass::HizGrid)>,
    pub visibility: wgpu::BindGroup,
    pub position: wgpu::BindGroup,
    pub displacement: wgpu::BindGroup,
    pub tiles: wgpu::BindGroup,
    pub tessellation: wgpu::BindGroup,
    pub tile_depth: wgpu::BindGroup,
    pub cull: wgpu::BindGroup,
    pub normals: wgpu::BindGroup,
    pub foam: wgpu::BindGroup,
    pub composite: wgpu::BindGroup,
    /// Lighting's group 2: the HDR target.
    pub hdr: wgpu::BindGroup,
}

/// What the groups are made over: the renderer's frame uniforms, depth, output and light
/// buffers.
pub(crate) struct Shared<'a> {
    pub frame: &'a wgpu::Buffer,
    pub depth: &'a wgpu::TextureView,
    pub output: &'a wgpu::TextureView,
    pub local: &'a wgpu::Buffer,
    pub lights: &'a LightBuffers,
    /// The lighting's water layouts (group `water`: the HDR target).
    pub hdr_layout: &'a shader::pipeline::Layouts,
}

/// The water in a renderer: pipelines, targets, the world's data and their groups.
pub(crate) struct WaterState {
    pub passes: WaterPasses,
    pub targets: WaterTargets,
    pub data: WaterData,
    pub groups: WaterGroups,
    /// Whether the composite runs in half precision.
    pub half: bool,
    /// A mini G-buffer given for the next frames instead of the position pass's (tests:
    /// garbage words).
    pub gbuffer_given: bool,
}

impl WaterState {
    /// The bind groups over the targets, the data and `s`.
    pub(crate) fn groups(
        device: &wgpu::Device,
        passes: &WaterPasses,
        t: &WaterTargets,
        d: &WaterData,
        s: &Shared<'_>,
    ) -> Result<WaterGroups> {
        use wgpu::BindingResource::TextureView as T;
        fn b(x: &wgpu::Buffer) -> wgpu::BindingResource<'_> {
            x.as_entire_binding()
        }
        Ok(WaterGroups {
            hiz: d.hiz.groups(device, &passes.visibility, s.depth)?,
            visibility: passes.visibility.pass.bind_group(
                device,
                "water",
                &[
                    ("frame", b(s.frame)),
                    ("water", b(&d.frame)),
                    ("bodies", b(&d.bodies)),
                    ("near_args", b(&d.near_args)),
                    ("nodes", b(&d.nodes)),
                    ("lists", b(&d.lists)),
                    ("far_list", b(&d.far_list)),
                    ("far_args", b(&d.far_args)),
                    ("hiz", b(&d.hiz.buffer)),
                    ("stats", b(&d.stats)),
                ],
            )?,
            position: passes.position.layouts.bind_group(
                device,
                "water",
                &[
                    ("frame", b(s.frame)),
                    ("water", b(&d.frame)),
                    ("world", T(&d.world)),
                    ("materials", b(&d.materials)),
                    ("vertices", b(&d.vertices)),
                    ("nodes", b(&d.nodes)),
                    ("far_list", b(&d.far_list)),
                    ("hiz", b(&d.hiz.buffer)),
                ],
            )?,
            displacement: passes.displacement.bind_group(
                device,
                "water",
                &[
                    ("frame", b(s.frame)),
                    ("water", b(&d.frame)),
                    ("data", T(&t.data.1)),
                    ("depth", T(&t.linear.1)),
                    ("materials", b(&d.materials)),
                    ("noise", T(&d.noise)),
                    ("decals", b(&d.decals)),
                    ("decal_texels", T(&d.decal_texels)),
                    ("displacement", T(&t.displacement.1)),
                    ("vertices", b(&t.vertices)),
                ],
            )?,
            tiles: passes.tiles.pass.bind_group(
                device,
                "water",
                &[
                    ("water", b(&d.frame)),
                    ("data", T(&t.data.1)),
                    ("counts", b(&t.tile_counts)),
                    ("tile_list", b(&t.tile_list)),
                    ("args", b(&t.tile_args)),
                ],
            )?,
            tessellation: passes.tessellation.layouts.bind_group(
                device,
                "water",
                &[
                    ("frame", b(s.frame)),
                    ("water", b(&d.frame)),
                    ("vertices", b(&t.vertices)),
                    ("tile_list", b(&t.tile_list)),
                ],
            )?,
            tile_depth: passes.tile_depth.bind_group(
                device,
                "tiles",
                &[
                    ("params", b(&s.lights.tile_params)),
                    ("depth_texture", T(&t.depth_water.1)),
                    ("tile_depths", b(&t.tile_depths)),
                ],
            )?,
            cull: passes.cull.bind_group(
                device,
                "cull",
                &[
                    ("params", b(&s.lights.cull_params)),
                    ("tile_depths", b(&t.tile_depths)),
                    ("lights", b(&s.lights.lights)),
                    ("counts", b(&t.light_counts)),
                    ("indices", b(&t.light_indices)),
                    ("counters", b(&t.light_counters)),
                ],
            )?,
            normals: passes.normals.bind_group(
                device,
                "water",
                &[
                    ("frame", b(s.frame)),
                    ("water", b(&d.frame)),
                    ("surface", T(&t.surface.1)),
                    ("data", T(&t.data.1)),
                    ("mesh_normal", T(&t.normal.1)),
                    ("materials", b(&d.materials)),
                    ("normals", T(&t.normals.1)),
                ],
            )?,
            foam: passes.foam.bind_group(
                device,
                "water",
                &[
                    ("frame", b(s.frame)),
                    ("water", b(&d.frame)),
                    ("surface", T(&t.surface.1)),
                    ("data", T(&t.data.1)),
                    ("materials", b(&d.materials)),
                    ("atlas", T(&d.atlas)),
                    ("shore", T(&d.shore)),
                    ("noise", T(&d.noise)),
                    ("displacement", T(&t.displacement.1)),
                    ("scene_depth", T(s.depth)),
                    ("foam", T(&t.foam.1)),
                ],
            )?,
            composite: passes.composite.bind_group(
                device,
                "water",
                &[
                    ("frame", b(s.frame)),
                    ("water", b(&d.frame)),
                    ("local", b(s.local)),
                    ("lights", b(&s.lights.lights)),
                    ("light_counts", b(&t.light_counts)),
                    ("light_indices", b(&t.light_indices)),
                    ("surface", T(&t.surface.1)),
                    ("normals", T(&t.normals.1)),
                    ("foam", T(&t.foam.1)),
                    ("data", T(&t.data.1)),
                    ("materials", b(&d.materials)),
                    ("material_map", T(&d.material_map)),
                    ("scene_hdr", T(&t.hdr.1)),
                    ("scene_depth", T(s.depth)),
                    ("output", T(s.output)),
                ],
            )?,
            hdr: s
                .hdr_layout
                .bind_group(device, "water", &[("scene_hdr", T(&t.hdr.1))])?,
        })
    }

    /// Records every water pass, after lighting.
    pub(crate) fn record(
        &self,
        e: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
    ) {
        let (t, d, g, p) = (&self.targets, &self.data, &self.groups, &self.passes);
        e.clear_buffer(&t.tile_counts, 0, None);
        e.clear_buffer(&t.tile_args, 0, None);
        e.clear_buffer(&t.light_counters, 0, None);
        if !self.gbuffer_given {
            e.clear_buffer(&d.far_args, 0, None);
            e.clear_buffer(&d.stats, 0, None);
            {
                let mut pass = timer.begin_compute(e, "water hiz");
                p.visibility.record_hiz(&mut pass, &g.hiz);
            }
            p.visibility.record(e, g, d, timer);
            p.position.record(e, t, d, g, timer);
        }
        record_grid(e, &p.displacement, &g.displacement, t.size, timer);
        p.tiles.record(e, t, g, timer);
        // The depth with water starts as the opaque depth.
        e.copy_texture_to_texture(
            f.targets.depth.as_image_copy(),
            t.depth_water.0.as_image_copy(),
            t.depth_water.0.size(),
        );
        p.tessellation.record(e, t, g, timer);
        {
            let mut pass = timer.begin_compute(e, "water light tiles");
            let size = [f.targets.width, f.targets.height];
            p.tile_depth.record(&mut pass, &[&g.tile_depth], &size);
            let (tx, ty) = deferred::lights::tile_counts(size[0], size[1]);
            let dispatch = deferred::pass::LightCullParams {
                tiles: [tx, ty],
                ..Default::default()
            };
            p.cull.record(&mut pass, &[&g.cull], &dispatch);
        }
        let size = [f.targets.width, f.targets.height];
        record_grid(e, &p.normals, &g.normals, size, timer);
        record_grid(e, &p.foam, &g.foam, size, timer);
        record_grid(e, &p.composite, &g.composite, size, timer);
    }

    /// Sets this frame's decals (checked against the scene's textures and the limit).
    pub(crate) fn set_decals(&mut self, decals: &[WaterDecal]) -> Result<()> {
        if decals.len() as u64 > u64::from(MAX_WATER_DECALS) {
            return Err(crate::water_scene::limit(
                "water decals in a frame",
                decals.len() as u64,
                u64::from(MAX_WATER_DECALS),
                "MAX_WATER_DECALS",
            ));
        }
        self.data.decals_cpu = decals
            .iter()
            .map(|d| crate::water_scene::decal_record(d, &self.data.decal_textures))
            .collect::<Result<_>>()?;
        Ok(())
    }

    /// Reads the last frame's counters back.
    pub(crate) fn stats(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<WaterStats> {
        use crate::resources::readback::read_buffer;
        let words = |b: &wgpu::Buffer, bytes: u64| -> Result<Vec<u32>> {
            Ok(bytemuck::pod_collect_to_vec(&read_buffer(
                device, queue, b, 0, bytes,
            )?))
        };
        let stats = words(&self.data.stats, STAT_WORDS * 4)?;
        let args = words(&self.targets.tile_args, 20)?;
        let tiles_total = self.targets.tile_count();
        let counts = words(&self.targets.tile_counts, u64::from(tiles_total) * 4)?;
        let tiles = args[1].min(tiles_total);
        Ok(WaterStats {
            buffer: self.targets.size,
            half_precision: self.half,
            near_bodies: stats[STAT_NEAR],
            far_sectors: stats[STAT_FAR],
            nodes_tested: stats[STAT_NODES],
            water_pixels: counts.iter().map(|&c| u64::from(c)).sum(),
            tiles,
            tiles_total,
            triangles: u64::from(tiles) * u64::from(args[0] / 3),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shadercheck::{Caps, assert_struct_layout, members};

    #[test]
    fn structs_match_their_wgsl_twins() {
        let m = shadercheck::assert_composed(
            super::super::LIBRARY,
            "gpu::water_frame",
            &[],
            Caps::CORE,
        );
        assert_struct_layout(
            &m,
            "GpuWaterFrame",
            size_of::<GpuWaterFrame>(),
            &members!(GpuWaterFrame {
                view_proj,
                inv_rotation,
                planes,
                camera,
                tan_half,
                size,
                grid,
                far,
                counts,
                sectors,
                shore,
                material_map,
                misc,
                normals,
                fbm,
                flow,
                foam,
                shore_size
            }),
        );
        assert_struct_layout(
            &m,
            "GpuWaterBody",
            size_of::<GpuWaterBody>(),
            &members!(GpuWaterBody {
                min,
                max,
                first_index,
                index_count,
                body,
                material
            }),
        );
        assert_struct_layout(
            &m,
            "GpuWaterDecal",
            size_of::<GpuWaterDecal>(),
            &members!(GpuWaterDecal {
                world_to_box,
                box_to_world,
                params,
                texture
            }),
        );
        let (size, _) = shadercheck::struct_layout(&m, "GpuWaterVertex").unwrap();
        assert_eq!(size, 32);
        let (size, _) = shadercheck::struct_layout(&m, "GpuWaterNode").unwrap();
        assert_eq!(size, 32);
        let u = |n: &str| shadercheck::const_u32(&m, n);
        assert_eq!(u("GPU_WATER_FLAG_FLOW"), Some(FLAG_FLOW));
        assert_eq!(u("GPU_WATER_FLAG_SHORE"), Some(FLAG_SHORE));
        assert_eq!(u("GPU_WATER_FLAG_SSR"), Some(FLAG_SSR));
        assert_eq!(u("GPU_WATER_FLAG_MATERIAL_MAP"), Some(FLAG_MATERIAL_MAP));
        use water::draw::{
            NODE_FLAT, NODE_MATERIAL_SHIFT, NODE_OCEAN, NODE_PURE, NODE_WATER, WATER_NO_MATERIAL,
        };
        assert_eq!(u("GPU_WATER_NODE_PURE"), Some(NODE_PURE));
        assert_eq!(
            u("GPU_WATER_NODE_MATERIAL_SHIFT"),
            Some(NODE_MATERIAL_SHIFT)
        );
        assert_eq!(u("GPU_WATER_NODE_WATER"), Some(NODE_WATER));
        assert_eq!(u("GPU_WATER_NODE_OCEAN"), Some(NODE_OCEAN));
        assert_eq!(u("GPU_WATER_NODE_FLAT"), Some(NODE_FLAT));
        assert_eq!(
            u("GPU_WATER_OCEAN_BODY"),
            Some(water::world::BodyId::OCEAN.0)
        );
        assert_eq!(u("GPU_WATER_NO_MATERIAL"), Some(WATER_NO_MATERIAL));
        assert_eq!(u("GPU_WATER_FAR_BODY"), Some(u32::MAX));
    }
}
