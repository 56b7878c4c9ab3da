use super::targets::{init, storage};
use crate::error::Result;
use crate::passes::depth_reductions::hiz_steps;
use crate::passes::water::rows::FLAG_FLOW;
use crate::passes::water::rows::FLAG_MATERIAL_MAP;
use crate::passes::water::rows::FLAG_SHORE;
use crate::passes::water::rows::FLAG_SSR;
use crate::passes::water::rows::GRID_QUADS;
use crate::passes::water::rows::GpuWaterBody;
use crate::passes::water::rows::GpuWaterDecal;
use crate::passes::water::rows::GpuWaterFrame;
use crate::passes::water::rows::STAT_WORDS;
use crate::passes::water::targets::WaterTargets;
use crate::resources::uniforms::FrameInput;
use crate::water_scene::{MAX_WATER_DECALS, WaterOptions, WaterScene};
use glam::Mat4;
use staticscene::pass::{HizGrid, hiz_header};
use water::draw::MaterialMap;
use water::draw::NearMeshes;
use water::draw::SectorTree;
use wgpu::util::DeviceExt;

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
    pub hiz: WaterHiz,
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
            indices: crate::resources::buffers::buffer_init(
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
            hiz: WaterHiz::new(device, frame_size)?,
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

/// The water's HiZ of the opaque depth: the buffer in staticscene's layout and one step
/// uniform per `gpu::hiz_depth` dispatch.
pub(crate) struct WaterHiz {
    pub buffer: wgpu::Buffer,
    pub(crate) steps: Vec<(wgpu::Buffer, HizGrid)>,
}

impl WaterHiz {
    /// The HiZ of a `width` x `height` depth target (reversed depth).
    pub(crate) fn new(device: &wgpu::Device, [width, height]: [u32; 2]) -> Result<Self> {
        let (header, len) = hiz_header(width, height)?;
        let buffer = crate::resources::buffers::buffer_init(
            device,
            "water hiz",
            bytemuck::cast_slice(&header),
            len as u64 * 4,
            wgpu::BufferUsages::STORAGE,
        );
        let steps = hiz_steps(device, &header, true, "water hiz step");
        Ok(Self { buffer, steps })
    }
}
