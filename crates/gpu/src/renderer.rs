//! The renderer: owns pipelines and targets on a user's device, prepares scenes, renders
//! frames by either path.

use crate::binding;
use crate::context::{scoped, ActivePaths, PrimitiveIdPath};
use crate::error::{Error, Result};
use crate::frame::{frame_uniforms, FrameUniforms, GpuPointLight};
use crate::geometry::Geometry;
use crate::image::Rgba8Image;
use crate::laydown::{record_draws, LaydownPipelines};
use crate::plan::{Plan, PlannedMicroBatch};
use crate::readback;
use crate::scene::Scene;
use crate::targets::Targets;
use crate::timing::{GpuTimer, Timing};
use crate::upload::{albedo_texture, gpu_materials, storage_buffer};

/// Which rendering path a frame takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RenderPath {
    /// HFW: visibility laydown, GPU classification, compute material resolve.
    Deferred,
    /// HZD: depth prepass with alpha test, then a depth-equal geometry pass.
    Baseline,
}

impl RenderPath {
    /// Short name for file names and tables.
    pub fn name(self) -> &'static str {
        match self {
            RenderPath::Deferred => "deferred",
            RenderPath::Baseline => "baseline",
        }
    }
}

/// Renderer options.
#[derive(Clone, Debug, PartialEq)]
pub struct RendererConfig {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Force a primitive-ID path (it must be supported); `None` picks the best.
    pub primitive_id: Option<PrimitiveIdPath>,
    /// Use subgroup operations where the device has them (else the workgroup fallback).
    pub subgroups: bool,
    /// Mip bias of the compute resolve (log2 units).
    pub mip_bias: f32,
}

impl Default for RendererConfig {
    fn default() -> Self {
        Self { width: 1280, height: 720, primitive_id: None, subgroups: true, mip_bias: 0.0 }
    }
}

/// A renderer on a device.
pub struct Renderer {
    pub(crate) device: wgpu::Device,
    pub(crate) queue: wgpu::Queue,
    pub(crate) config: RendererConfig,
    pub(crate) paths: ActivePaths,
    pub(crate) targets: Targets,
    pub(crate) frame: wgpu::Buffer,
    pub(crate) sampler: wgpu::Sampler,
    pub(crate) laydown: LaydownPipelines,
    pub(crate) timer: GpuTimer,
}

/// A scene uploaded for one renderer.
pub struct PreparedScene {
    /// Geometry encoded for the renderer's primitive-ID path.
    pub geometry: Geometry,
    /// Instance and lookup tables, draws.
    pub plan: Plan,
    pub(crate) frame_uniforms: FrameUniforms,
    pub(crate) index_buffer: wgpu::Buffer,
    pub(crate) scene_group: wgpu::BindGroup,
    pub(crate) _buffers: Vec<wgpu::Buffer>,
    pub(crate) _albedo: wgpu::Texture,
}

/// What one rendered frame reports.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrameTimings {
    /// GPU time per pass label, from timestamp queries (empty without them).
    pub gpu: Vec<Timing>,
    /// Wall-clock time of the frame's submission to completion (ms).
    pub wall_ms: f64,
}

impl Renderer {
    /// Creates the renderer's pipelines and targets on `device`. Optional features the
    /// device lacks select fallbacks; a forced primitive-ID path the device cannot run is
    /// an error naming the feature.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, config: RendererConfig) -> Result<Self> {
        if config.width == 0 || config.height == 0 {
            return Err(Error::DeviceLimit { limit: "image size (width and height must be at least 1)", needed: 1, available: 0 });
        }
        let max = device.limits().max_texture_dimension_2d;
        if config.width.max(config.height) > max {
            return Err(Error::DeviceLimit {
                limit: "max_texture_dimension_2d",
                needed: u64::from(config.width.max(config.height)),
                available: u64::from(max),
            });
        }
        let mut paths = ActivePaths::for_device(device.features(), &device.adapter_info());
        if let Some(p) = config.primitive_id {
            if !device.features().contains(p.required_features()) {
                return Err(Error::RequestDevice(format!(
                    "primitive-ID path `{}` needs {:?}, which the device does not have",
                    p.name(),
                    p.required_features()
                )));
            }
            paths.primitive_id = p;
        }
        if !config.subgroups {
            paths.subgroup_size = None;
        }
        scoped(device, || {
            let targets = Targets::new(device, config.width, config.height, &[]);
            let frame = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("frame uniforms"),
                size: size_of::<FrameUniforms>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("albedo"),
                address_mode_u: wgpu::AddressMode::Repeat,
                address_mode_v: wgpu::AddressMode::Repeat,
                address_mode_w: wgpu::AddressMode::Repeat,
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                mipmap_filter: wgpu::MipmapFilterMode::Linear,
                anisotropy_clamp: 1,
                ..Default::default()
            });
            let laydown = LaydownPipelines::new(device, paths.primitive_id);
            let timer = GpuTimer::new(device, queue, 32);
            Ok(Self { device: device.clone(), queue: queue.clone(), config, paths, targets, frame, sampler, laydown, timer })
        })
    }

    /// The paths this renderer uses.
    pub fn paths(&self) -> &ActivePaths {
        &self.paths
    }

    /// The configuration.
    pub fn config(&self) -> &RendererConfig {
        &self.config
    }

    /// Uploads `scene` with micro batches given by the caller (the `tiling` builder's output
    /// in [`Renderer::prepare`]).
    pub fn prepare_with_micro_batches(&self, scene: &Scene, micro_batches: &[PlannedMicroBatch]) -> Result<PreparedScene> {
        scene.validate()?;
        let geometry = Geometry::build(&scene.meshes, self.paths.primitive_id)?;
        let plan = Plan::new(scene, &geometry, micro_batches, scene.camera.position);
        let device = &self.device;
        scoped(device, || {
            let none = wgpu::BufferUsages::empty();
            let vertices = storage_buffer(device, "vertices", bytemuck::cast_slice(&geometry.vertices), none);
            let payloads = storage_buffer(device, "payloads", bytemuck::cast_slice(&geometry.payloads), none);
            let index_buffer = storage_buffer(device, "indices", bytemuck::cast_slice(&geometry.indices), wgpu::BufferUsages::INDEX);
            let instances = storage_buffer(device, "instances", bytemuck::cast_slice(&plan.instances), none);
            let materials = storage_buffer(device, "materials", bytemuck::cast_slice(&gpu_materials(scene)), none);
            let albedo = albedo_texture(device, &self.queue, &scene.albedo_layers);
            let albedo_view = albedo.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            });
            let scene_group = binding::group(
                device,
                "scene",
                &self.laydown.layout,
                &[
                    self.frame.as_entire_binding(),
                    vertices.as_entire_binding(),
                    instances.as_entire_binding(),
                    materials.as_entire_binding(),
                    payloads.as_entire_binding(),
                    wgpu::BindingResource::TextureView(&albedo_view),
                    wgpu::BindingResource::Sampler(&self.sampler),
                ],
            );
            let lights: Vec<GpuPointLight> = scene
                .lighting
                .point_lights
                .iter()
                .map(|l| GpuPointLight {
                    position_radius: (l.position - scene.camera.position).extend(l.radius).to_array(),
                    color: l.color.extend(0.0).to_array(),
                })
                .collect();
            let point_lights = storage_buffer(device, "point lights", bytemuck::cast_slice(&lights), none);
            let mut frame_uniforms =
                frame_uniforms(&scene.camera, &scene.lighting, self.config.width, self.config.height, lights.len() as u32);
            frame_uniforms.mip_bias = self.config.mip_bias;
            Ok(PreparedScene {
                geometry,
                plan,
                frame_uniforms,
                index_buffer,
                scene_group,
                _buffers: vec![vertices, payloads, instances, materials, point_lights],
                _albedo: albedo,
            })
        })
    }

    /// Records the depth + visibility laydown into `encoder`.
    fn record_laydown(&mut self, encoder: &mut wgpu::CommandEncoder, scene: &PreparedScene) {
        let depth_view = self.targets.depth.create_view(&Default::default());
        let vis_view = self.targets.vis.create_view(&Default::default());
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("depth + visibility laydown"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &vis_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color { r: f64::from(visbuf::VIS_NONE), g: 0.0, b: 0.0, a: 0.0 }),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth_view,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(0.0), store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            timestamp_writes: self.timer.render("laydown"),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        record_draws(
            &mut pass,
            &scene.plan.draws,
            &self.laydown.vis_opaque,
            &self.laydown.vis_alpha,
            &scene.scene_group,
            &scene.index_buffer,
        );
    }

    /// Renders the laydown only and returns the vis buffer (row-major words) and the depth
    /// buffer: what the classification passes and their CPU twins read.
    pub fn render_laydown(&mut self, scene: &PreparedScene) -> Result<(Vec<u32>, Vec<f32>)> {
        let device = self.device.clone();
        scoped(&device, || {
            self.queue.write_buffer(&self.frame, 0, bytemuck::bytes_of(&scene.frame_uniforms));
            let mut encoder = device.create_command_encoder(&Default::default());
            self.record_laydown(&mut encoder, scene);
            self.queue.submit([encoder.finish()]);
            Ok(())
        })?;
        let _ = self.timer.read(&self.device, &self.queue)?;
        let vis = readback::read_texture(&self.device, &self.queue, &self.targets.vis, wgpu::TextureAspect::All, 4)?;
        let depth = readback::read_texture(&self.device, &self.queue, &self.targets.depth, wgpu::TextureAspect::DepthOnly, 4)?;
        Ok((bytemuck::pod_collect_to_vec(&vis), bytemuck::pod_collect_to_vec(&depth)))
    }

    /// The vis buffer colour-coded by (micro batch, instance, primitive), like the talk's
    /// slide; pixels without vis-buffer geometry are yellow.
    pub fn vis_debug_view(&self, vis: &[u32]) -> Rgba8Image {
        let mut img = Rgba8Image::new(self.config.width, self.config.height, [0, 0, 0, 255]);
        for (p, &w) in img.pixels.iter_mut().zip(vis) {
            *p = if w == visbuf::VIS_NONE { [230, 200, 40, 255] } else { crate::image::id_color(w) };
        }
        img
    }
}
