//! The renderer: owns pipelines and targets on a user's device, prepares scenes, renders
//! frames by either path.

use crate::binding;
use crate::classify::{ClassifyBuffers, ClassifyPipelines, ClassifySizes, GpuClassification};
use crate::context::{ActivePaths, PrimitiveIdPath, scoped};
use crate::error::SceneError;
use crate::error::{Error, Result};
use crate::frame::{FrameUniforms, GpuPointLight, frame_uniforms};
use crate::gbuffer;
use crate::geometry::Geometry;
use crate::image::Rgba8Image;
use crate::laydown::{LaydownPipelines, record_draws};
use crate::plan::{Plan, PlannedMicroBatch};
use crate::readback;
use crate::report::ClassificationStats;
use crate::scene::Scene;
use crate::targets::Targets;
use crate::timing::{GpuTimer, Timing};
use crate::upload::{albedo_texture, gpu_materials, storage_buffer};
use wgpu::util::DeviceExt as _;

/// Wall time [`Renderer::render_frames`] renders before it starts measuring.
pub const WARM_UP: std::time::Duration = std::time::Duration::from_millis(500);

/// Which rendering path a frame takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RenderPath {
    /// HFW: visibility laydown, GPU classification, compute material resolve.
    Deferred,
    /// HZD: depth prepass with alpha test, then a depth-equal geometry pass.
    Baseline,
    /// Diagnostic: laydown, then a full-screen resolve of every pixel (no classification).
    DeferredFullScreen,
}

impl RenderPath {
    /// Short name for file names and tables.
    pub fn name(self) -> &'static str {
        match self {
            RenderPath::Deferred => "deferred",
            RenderPath::Baseline => "baseline",
            RenderPath::DeferredFullScreen => "deferred-fullscreen",
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
        Self {
            width: 1280,
            height: 720,
            primitive_id: None,
            subgroups: true,
            mip_bias: 0.0,
        }
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
    pub(crate) resolve_layouts: Vec<wgpu::BindGroupLayout>,
    pub(crate) resolve_fullscreen: wgpu::ComputePipeline,
    pub(crate) resolve_waves: wgpu::ComputePipeline,
    pub(crate) classify: ClassifyPipelines,
    pub(crate) wave_width: wave::WaveWidth,
    pub(crate) lighting: ComputeStage,
    pub(crate) baseline: wgpu::RenderPipeline,
    pub(crate) gbuffer_store_group: wgpu::BindGroup,
    pub(crate) gbuffer_load_group: wgpu::BindGroup,
    pub(crate) timer: GpuTimer,
}

/// A compute pipeline with the layouts of its bind groups.
pub(crate) struct ComputeStage {
    pub(crate) layouts: Vec<wgpu::BindGroupLayout>,
    pub(crate) pipeline: wgpu::ComputePipeline,
}

impl ComputeStage {
    fn new(
        device: &wgpu::Device,
        label: &str,
        source: &str,
        entry: &str,
        groups: Vec<Vec<wgpu::BindGroupLayoutEntry>>,
    ) -> Self {
        let layouts: Vec<wgpu::BindGroupLayout> = groups
            .iter()
            .enumerate()
            .map(|(i, e)| binding::layout(device, &format!("{label} group {i}"), e))
            .collect();
        let refs: Vec<&wgpu::BindGroupLayout> = layouts.iter().collect();
        let pl = binding::pipeline_layout(device, label, &refs);
        let module = binding::module(device, label, source);
        let pipeline = binding::compute_pipeline(device, label, &pl, &module, entry, &[]);
        Self { layouts, pipeline }
    }
}

/// A scene uploaded for one renderer.
pub struct PreparedScene {
    /// Geometry encoded for the renderer's primitive-ID path.
    pub geometry: Geometry,
    /// Instance and lookup tables, draws.
    pub plan: Plan,
    /// `tiling`'s micro batches, MicroBatchInfoTable, order buffer and passes.
    pub tiling: tiling::Plan,
    /// The classification's buffers.
    pub classification: ClassifyBuffers,
    pub(crate) waves_group: wgpu::BindGroup,
    pub(crate) pass_stride: u32,
    pub(crate) frame_uniforms: FrameUniforms,
    pub(crate) index_buffer: wgpu::Buffer,
    pub(crate) scene_group: wgpu::BindGroup,
    pub(crate) resolve_group: wgpu::BindGroup,
    pub(crate) lighting_group: wgpu::BindGroup,
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
            return Err(Error::DeviceLimit {
                limit: "image size (width and height must be at least 1)",
                needed: 1,
                available: 0,
            });
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
            let targets = Targets::new(
                device,
                config.width,
                config.height,
                &gbuffer::color_formats(),
            );
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
            let c = wgpu::ShaderStages::COMPUTE;
            let wave_width = paths
                .subgroup_size
                .and_then(|(_, hi)| wave::WaveWidth::from_lanes(hi).ok())
                .unwrap_or(wave::WaveWidth::W32);
            let resolve_layouts = vec![
                binding::layout(device, "resolve scene", &resolve_layout_entries()),
                binding::layout(
                    device,
                    "resolve gbuffer",
                    &gbuffer::store_layout_entries(0, c),
                ),
                binding::layout(device, "resolve waves", &wave_layout_entries()),
            ];
            let resolve_module = binding::module(
                device,
                "resolve",
                &crate::shaders::resolve(wave_width.lanes()),
            );
            let pl2 = binding::pipeline_layout(
                device,
                "resolve (full screen)",
                &[&resolve_layouts[0], &resolve_layouts[1]],
            );
            let resolve_fullscreen = binding::compute_pipeline(
                device,
                "resolve (full screen)",
                &pl2,
                &resolve_module,
                "resolve_fullscreen",
                &[],
            );
            let pl3 = binding::pipeline_layout(
                device,
                "resolve (wave commands)",
                &[
                    &resolve_layouts[0],
                    &resolve_layouts[1],
                    &resolve_layouts[2],
                ],
            );
            let resolve_waves = binding::compute_pipeline(
                device,
                "resolve (wave commands)",
                &pl3,
                &resolve_module,
                "resolve_waves",
                &[],
            );
            let classify = ClassifyPipelines::new(device, paths.subgroup_size.is_some());
            let lighting = ComputeStage::new(
                device,
                "lighting",
                &crate::shaders::lighting(),
                "main",
                vec![
                    vec![
                        binding::uniform(0, c),
                        binding::texture(
                            1,
                            c,
                            wgpu::TextureSampleType::Depth,
                            wgpu::TextureViewDimension::D2,
                        ),
                        binding::storage(2, c, true),
                        binding::storage_texture(3, c, crate::targets::OUTPUT_FORMAT),
                    ],
                    gbuffer::load_layout_entries(0, c),
                ],
            );
            let baseline = baseline_pipeline(device, &laydown.layout, paths.primitive_id);
            let views: Vec<wgpu::TextureView> = targets
                .gbuffer
                .iter()
                .map(|t| t.create_view(&Default::default()))
                .collect();
            let resources: Vec<wgpu::BindingResource<'_>> = views
                .iter()
                .map(wgpu::BindingResource::TextureView)
                .collect();
            let gbuffer_store_group =
                binding::group(device, "gbuffer store", &resolve_layouts[1], &resources);
            let gbuffer_load_group =
                binding::group(device, "gbuffer load", &lighting.layouts[1], &resources);
            let timer = GpuTimer::new(device, queue, 32);
            Ok(Self {
                device: device.clone(),
                queue: queue.clone(),
                config,
                paths,
                targets,
                frame,
                sampler,
                laydown,
                resolve_layouts,
                resolve_fullscreen,
                resolve_waves,
                classify,
                wave_width,
                lighting,
                baseline,
                gbuffer_store_group,
                gbuffer_load_group,
                timer,
            })
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

    /// Validates `scene`, encodes its meshes for the renderer's primitive-ID path, builds
    /// micro batches and passes with `tiling` (batches sorted by shader, material and a
    /// Morton code of their instances' mean position; the talk's PS5 limits), and uploads
    /// everything a frame reads. Limits are errors naming them
    /// ([`SceneError::Tiling`] for the plan's).
    pub fn prepare(&self, scene: &Scene) -> Result<PreparedScene> {
        scene.validate()?;
        let geometry = Geometry::build(&scene.meshes, self.paths.primitive_id)?;
        let positions: Vec<Vec<[f32; 3]>> = scene
            .batches
            .iter()
            .map(|b| {
                b.instances
                    .iter()
                    .map(|t| t.translation.to_array())
                    .collect()
            })
            .collect();
        let batches: Vec<tiling::Batch<'_>> = scene
            .batches
            .iter()
            .zip(&positions)
            .map(|(b, pos)| {
                let m = geometry.meshes[b.mesh.0];
                tiling::Batch {
                    shader: scene.materials[b.material.0].shader.id(),
                    batch_data: b.material.0 as u64,
                    geometry: tiling::Geometry {
                        vertex_count: m.vertex_count,
                        primitive_count: m.primitive_count,
                        first_index: m.first_index,
                        base_vertex: m.base_vertex,
                    },
                    instances: pos,
                }
            })
            .collect();
        let tiling_plan = tiling::build_plan(&batches, &tiling::PlanConfig::default())
            .map_err(|e| Error::Scene(SceneError::Tiling(e.to_string())))?;
        let micro_batches: Vec<PlannedMicroBatch> = tiling_plan
            .micro_batches
            .iter()
            .map(|m| PlannedMicroBatch {
                batch: m.batch,
                first_instance: m.batch_first_instance,
                instance_count: m.instance_count,
                first_id: m.first_id,
                id_count: m.id_count,
                pass: m.pass,
                batch_group: m.batch_group,
            })
            .collect();
        self.upload(scene, geometry, &micro_batches, tiling_plan)
    }

    fn upload(
        &self,
        scene: &Scene,
        geometry: Geometry,
        micro_batches: &[PlannedMicroBatch],
        tiling_plan: tiling::Plan,
    ) -> Result<PreparedScene> {
        let plan = Plan::new(scene, &geometry, micro_batches, scene.camera.position);
        debug_assert!(
            tiling_plan
                .micro_batches
                .iter()
                .zip(&plan.draws)
                .all(|(m, d)| m.first_instance == d.first_instance),
            "the instance table follows tiling's processing order"
        );
        let device = &self.device;
        scoped(device, || {
            let none = wgpu::BufferUsages::empty();
            let vertices = storage_buffer(
                device,
                "vertices",
                bytemuck::cast_slice(&geometry.vertices),
                none,
            );
            let payloads = storage_buffer(
                device,
                "payloads",
                bytemuck::cast_slice(&geometry.payloads),
                none,
            );
            let index_buffer = storage_buffer(
                device,
                "indices",
                bytemuck::cast_slice(&geometry.indices),
                wgpu::BufferUsages::INDEX,
            );
            let instances = storage_buffer(
                device,
                "instances",
                bytemuck::cast_slice(&plan.instances),
                none,
            );
            let materials = storage_buffer(
                device,
                "materials",
                bytemuck::cast_slice(&gpu_materials(scene)),
                none,
            );
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
                    position_radius: (l.position - scene.camera.position)
                        .extend(l.radius)
                        .to_array(),
                    color: l.color.extend(0.0).to_array(),
                })
                .collect();
            // At least one row: the binding's size must hold one struct even with no lights
            // (the uniform's light count says how many rows are real).
            let rows: &[GpuPointLight] = if lights.is_empty() {
                &[GpuPointLight::default()]
            } else {
                &lights
            };
            let point_lights =
                storage_buffer(device, "point lights", bytemuck::cast_slice(rows), none);
            let meshes = storage_buffer(
                device,
                "meshes",
                bytemuck::cast_slice(&geometry.meshes),
                none,
            );
            let micro_batches = storage_buffer(
                device,
                "micro batches",
                bytemuck::cast_slice(&plan.micro_batch_ids),
                none,
            );
            let vis_view = self.targets.vis.create_view(&Default::default());
            let resolve_group = binding::group(
                device,
                "resolve",
                &self.resolve_layouts[0],
                &[
                    self.frame.as_entire_binding(),
                    vertices.as_entire_binding(),
                    instances.as_entire_binding(),
                    materials.as_entire_binding(),
                    index_buffer.as_entire_binding(),
                    meshes.as_entire_binding(),
                    micro_batches.as_entire_binding(),
                    wgpu::BindingResource::TextureView(&albedo_view),
                    wgpu::BindingResource::Sampler(&self.sampler),
                    wgpu::BindingResource::TextureView(&vis_view),
                ],
            );
            let depth_view = self.targets.depth.create_view(&Default::default());
            let output_view = self.targets.output.create_view(&Default::default());
            let lighting_group = binding::group(
                device,
                "lighting",
                &self.lighting.layouts[0],
                &[
                    self.frame.as_entire_binding(),
                    wgpu::BindingResource::TextureView(&depth_view),
                    point_lights.as_entire_binding(),
                    wgpu::BindingResource::TextureView(&output_view),
                ],
            );
            let mut frame_uniforms = frame_uniforms(
                &scene.camera,
                &scene.lighting,
                self.config.width,
                self.config.height,
                lights.len() as u32,
            );
            frame_uniforms.mip_bias = self.config.mip_bias;
            let config = tiling::ClassifyConfig::for_plan(&tiling_plan, self.wave_width);
            let batch_groups: usize = tiling_plan.pass_groups.iter().map(Vec::len).sum();
            let sizes = ClassifySizes::new(
                self.config.width,
                self.config.height,
                &config,
                batch_groups as u32,
            );
            let classification = ClassifyBuffers::new(
                device,
                &self.classify,
                sizes,
                config,
                &tiling_plan.table,
                tiling_plan.order.len() as u32,
                &vis_view,
                &index_buffer,
            );
            let stride = u64::from(device.limits().min_uniform_buffer_offset_alignment).max(16);
            let mut pass_words = vec![0u8; (stride * u64::from(sizes.passes)) as usize];
            for p in 0..sizes.passes {
                let at = (stride * u64::from(p)) as usize;
                pass_words[at..at + 4].copy_from_slice(&p.to_le_bytes());
            }
            let pass_uniforms = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("resolve pass index"),
                contents: &pass_words,
                usage: wgpu::BufferUsages::UNIFORM,
            });
            let waves_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("resolve waves"),
                layout: &self.resolve_layouts[2],
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: classification.waves.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: classification.commands.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: classification.pass_dispatch.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                            buffer: &pass_uniforms,
                            offset: 0,
                            size: wgpu::BufferSize::new(16),
                        }),
                    },
                ],
            });
            Ok(PreparedScene {
                geometry,
                plan,
                tiling: tiling_plan,
                classification,
                waves_group,
                pass_stride: stride as u32,
                frame_uniforms,
                index_buffer,
                scene_group,
                resolve_group,
                lighting_group,
                _buffers: vec![
                    vertices,
                    payloads,
                    instances,
                    materials,
                    point_lights,
                    meshes,
                    micro_batches,
                    pass_uniforms,
                ],
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
                    load: wgpu::LoadOp::Clear(wgpu::Color {
                        r: f64::from(visbuf::VIS_NONE),
                        g: 0.0,
                        b: 0.0,
                        a: 0.0,
                    }),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Store,
                }),
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

    /// Records the full-screen compute resolve into the G-buffer.
    fn record_resolve_fullscreen(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        scene: &PreparedScene,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("material resolve (full screen)"),
            timestamp_writes: self.timer.compute("resolve"),
        });
        pass.set_pipeline(&self.resolve_fullscreen);
        pass.set_bind_group(0, &scene.resolve_group, &[]);
        pass.set_bind_group(1, &self.gbuffer_store_group, &[]);
        pass.dispatch_workgroups(
            self.config.width.div_ceil(8),
            self.config.height.div_ceil(8),
            1,
        );
    }

    /// Records the material resolve by wave commands: one indirect dispatch per pass.
    fn record_resolve_waves(&mut self, encoder: &mut wgpu::CommandEncoder, scene: &PreparedScene) {
        let c = &scene.classification;
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("material resolve (wave commands)"),
            timestamp_writes: self.timer.compute("resolve (wave commands)"),
        });
        pass.set_pipeline(&self.resolve_waves);
        pass.set_bind_group(0, &scene.resolve_group, &[]);
        pass.set_bind_group(1, &self.gbuffer_store_group, &[]);
        for p in 0..c.sizes.passes {
            pass.set_bind_group(2, &scene.waves_group, &[p * scene.pass_stride]);
            pass.dispatch_workgroups_indirect(
                &c.pass_dispatch,
                u64::from(p) * size_of::<tiling::PassDispatch>() as u64,
            );
        }
    }

    /// Records lighting and tone mapping into the output image.
    fn record_lighting(&mut self, encoder: &mut wgpu::CommandEncoder, scene: &PreparedScene) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("lighting"),
            timestamp_writes: self.timer.compute("lighting"),
        });
        pass.set_pipeline(&self.lighting.pipeline);
        pass.set_bind_group(0, &scene.lighting_group, &[]);
        pass.set_bind_group(1, &self.gbuffer_load_group, &[]);
        pass.dispatch_workgroups(
            self.config.width.div_ceil(8),
            self.config.height.div_ceil(8),
            1,
        );
    }

    /// Records HZD's method: depth prepass with alpha test, then the depth-equal geometry
    /// pass writing the G-buffer.
    fn record_baseline(&mut self, encoder: &mut wgpu::CommandEncoder, scene: &PreparedScene) {
        let depth_view = self.targets.depth.create_view(&Default::default());
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("baseline depth prepass"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(0.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: self.timer.render("depth prepass"),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            record_draws(
                &mut pass,
                &scene.plan.draws,
                &self.laydown.depth_opaque,
                &self.laydown.depth_alpha,
                &scene.scene_group,
                &scene.index_buffer,
            );
        }
        let views: Vec<wgpu::TextureView> = self
            .targets
            .gbuffer
            .iter()
            .map(|t| t.create_view(&Default::default()))
            .collect();
        let colors: Vec<Option<wgpu::RenderPassColorAttachment<'_>>> = views
            .iter()
            .map(|v| {
                Some(wgpu::RenderPassColorAttachment {
                    view: v,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    },
                })
            })
            .collect();
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("baseline depth-equal geometry pass"),
            color_attachments: &colors,
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: self.timer.render("depth-equal geometry pass"),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        // No alpha test here: the prepass decided coverage, depth-equal keeps the survivors.
        record_draws(
            &mut pass,
            &scene.plan.draws,
            &self.baseline,
            &self.baseline,
            &scene.scene_group,
            &scene.index_buffer,
        );
    }

    /// Renders `path` for at least [`WARM_UP`] of wall time (at least one frame) to bring the
    /// GPU's clocks up, then `frames` more, and returns the mean timings of those `frames`.
    /// Without the warm-up, a GPU that idled while the CPU worked (a read-back, the CPU
    /// twin) measures its first frames at idle clocks: on the H100 the SM clock falls to
    /// 345 MHz within ~0.5 s of idling and the next frames ran up to 2x slower.
    pub fn render_frames(
        &mut self,
        scene: &PreparedScene,
        path: RenderPath,
        frames: u32,
    ) -> Result<FrameTimings> {
        let start = std::time::Instant::now();
        loop {
            self.render(scene, path)?;
            if start.elapsed() >= WARM_UP {
                break;
            }
        }
        let mut all = Vec::new();
        for _ in 0..frames.max(1) {
            all.push(self.render(scene, path)?);
        }
        let steady: Vec<&FrameTimings> = all.iter().collect();
        let n = steady.len() as f64;
        let mut gpu: Vec<Timing> = Vec::new();
        for f in &steady {
            for t in &f.gpu {
                match gpu.iter_mut().find(|g| g.label == t.label) {
                    Some(g) => g.ms += t.ms / n,
                    None => gpu.push(Timing {
                        label: t.label,
                        ms: t.ms / n,
                        passes: t.passes,
                    }),
                }
            }
        }
        let wall_ms = steady.iter().map(|f| f.wall_ms).sum::<f64>() / n;
        Ok(FrameTimings { gpu, wall_ms })
    }

    /// Renders one frame of `path` into the output image and waits for it.
    pub fn render(&mut self, scene: &PreparedScene, path: RenderPath) -> Result<FrameTimings> {
        let device = self.device.clone();
        let t0 = std::time::Instant::now();
        scoped(&device, || {
            self.queue
                .write_buffer(&self.frame, 0, bytemuck::bytes_of(&scene.frame_uniforms));
            let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some(path.name()),
            });
            match path {
                RenderPath::Deferred => {
                    self.record_laydown(&mut encoder, scene);
                    scene
                        .classification
                        .record_copy(&mut encoder, &self.classify, &mut self.timer);
                    scene.classification.record_classification(
                        &mut encoder,
                        &self.classify,
                        &mut self.timer,
                    );
                    self.record_resolve_waves(&mut encoder, scene);
                }
                RenderPath::DeferredFullScreen => {
                    self.record_laydown(&mut encoder, scene);
                    self.record_resolve_fullscreen(&mut encoder, scene);
                }
                RenderPath::Baseline => self.record_baseline(&mut encoder, scene),
            }
            self.record_lighting(&mut encoder, scene);
            self.timer.resolve(&mut encoder);
            self.queue.submit([encoder.finish()]);
            crate::context::wait_idle(&device)
        })?;
        let wall_ms = t0.elapsed().as_secs_f64() * 1e3;
        let gpu = self.timer.read(&self.device, &self.queue)?;
        Ok(FrameTimings { gpu, wall_ms })
    }

    /// Reads the output image back (sRGB-encoded RGBA8).
    pub fn read_output(&self) -> Result<Rgba8Image> {
        let bytes = readback::read_texture(
            &self.device,
            &self.queue,
            &self.targets.output,
            wgpu::TextureAspect::All,
            4,
        )?;
        Ok(Rgba8Image {
            width: self.config.width,
            height: self.config.height,
            pixels: bytemuck::pod_collect_to_vec(&bytes),
        })
    }

    /// Renders the laydown only and returns the vis buffer (row-major words) and the depth
    /// buffer: what the classification passes and their CPU twins read.
    pub fn render_laydown(&mut self, scene: &PreparedScene) -> Result<(Vec<u32>, Vec<f32>)> {
        let device = self.device.clone();
        scoped(&device, || {
            self.queue
                .write_buffer(&self.frame, 0, bytemuck::bytes_of(&scene.frame_uniforms));
            let mut encoder = device.create_command_encoder(&Default::default());
            self.record_laydown(&mut encoder, scene);
            self.queue.submit([encoder.finish()]);
            Ok(())
        })?;
        let _ = self.timer.read(&self.device, &self.queue)?;
        let vis = readback::read_texture(
            &self.device,
            &self.queue,
            &self.targets.vis,
            wgpu::TextureAspect::All,
            4,
        )?;
        let depth = readback::read_texture(
            &self.device,
            &self.queue,
            &self.targets.depth,
            wgpu::TextureAspect::DepthOnly,
            4,
        )?;
        Ok((
            bytemuck::pod_collect_to_vec(&vis),
            bytemuck::pod_collect_to_vec(&depth),
        ))
    }

    /// Replaces the WGSL of classification phases 2 and 3 (same bindings and entry points
    /// as `tiling::wgsl`'s), for timing experiments (`examples/classify_variants.rs`). A
    /// source that fails validation is an error, after which deferred frames fail until a
    /// valid source is set.
    #[doc(hidden)]
    pub fn set_classification_sources(&mut self, mid: &str, output: &str) -> Result<()> {
        let device = self.device.clone();
        scoped(&device, || {
            self.classify.rebuild(&device, mid, output);
            Ok(())
        })
    }

    /// Reads back what the last deferred frame's classification wrote.
    pub fn read_classification(&self, scene: &PreparedScene) -> Result<GpuClassification> {
        scene.classification.read(&self.device, &self.queue)
    }

    /// Uploads `words` (row-major, `width * height`, any values: bad IDs are the
    /// classification's to count) as the vis buffer, runs the three classification phases
    /// on them alone, and reads the result back. How tests feed random vis buffers.
    pub fn classify_words(
        &mut self,
        scene: &PreparedScene,
        words: &[u32],
    ) -> Result<GpuClassification> {
        let s = scene.classification.sizes;
        let n = (s.width * s.height) as usize;
        if words.len() != n {
            return Err(Error::DeviceLimit {
                limit: "vis words (must be width * height of the renderer)",
                needed: words.len() as u64,
                available: n as u64,
            });
        }
        let device = self.device.clone();
        scoped(&device, || {
            self.queue.write_buffer(
                &scene.classification.vis_words,
                0,
                bytemuck::cast_slice(words),
            );
            let mut encoder = device.create_command_encoder(&Default::default());
            scene.classification.record_classification(
                &mut encoder,
                &self.classify,
                &mut self.timer,
            );
            self.timer.resolve(&mut encoder);
            self.queue.submit([encoder.finish()]);
            crate::context::wait_idle(&device)
        })?;
        let _ = self.timer.read(&self.device, &self.queue)?;
        self.read_classification(scene)
    }

    /// The talk's counters for a read-back classification: runs `tiling`'s CPU twin
    /// (`classify_phases`) on the same vis words, compares every output, and measures
    /// depth-equal waves and chunk-culled vertices with `tiling::measure`.
    pub fn classification_statistics(
        &self,
        scene: &PreparedScene,
        gpu: &GpuClassification,
    ) -> Result<(ClassificationStats, Option<String>)> {
        let s = scene.classification.sizes;
        let t = &scene.tiling;
        let err = |e: tiling::Error| Error::Scene(SceneError::Tiling(e.to_string()));
        let vis = tiling::VisBuffer::new(&gpu.vis, s.width, s.height, visbuf::VisLayout::Standard)
            .map_err(err)?;
        let config = scene.classification.config;
        let cpu = tiling::classify_phases(&vis, &t.table, &scene.geometry.indices, &config)
            .map_err(err)?;
        let mismatch = gpu.mismatch(&cpu);
        let vertex = tiling::vertex_wave_commands(
            &cpu.mid.vertex_cull,
            t.chunk_count,
            &t.table,
            &t.order,
            &t.passes,
        )
        .map_err(err)?;
        let m = tiling::measure(&vis, &t.table, &config, &cpu, &vertex).map_err(err)?;
        let stats = ClassificationStats {
            vis_pixels: u64::from(gpu.output_stats.valid),
            passes: t.passes.len() as u32,
            batch_groups: t.pass_groups.iter().map(Vec::len).sum::<usize>() as u32,
            tile_groups: u64::from(gpu.totals.counter_count),
            pixel_commands: u64::from(gpu.totals.command_count),
            wave_commands: u64::from(gpu.totals.wave_count),
            wave_width: config.wave_width.lanes(),
            unfilled_lanes: (u64::from(gpu.totals.wave_count)
                * u64::from(config.wave_width.lanes()))
            .saturating_sub(u64::from(gpu.totals.command_count)),
            depth_equal_waves: m.depth_equal_waves,
            scene_vertices: m.scene_vertices,
            vertices_after_chunk_culling: m.visible_vertices,
            command_bytes: cpu.command_bytes(),
            gpu_matches_cpu: Some(mismatch.is_none()),
        };
        Ok((stats, mismatch))
    }

    /// The vis buffer colour-coded by (micro batch, instance, primitive), like the talk's
    /// slide; pixels without vis-buffer geometry are yellow.
    pub fn vis_debug_view(&self, vis: &[u32]) -> Rgba8Image {
        let mut img = Rgba8Image::new(self.config.width, self.config.height, [0, 0, 0, 255]);
        for (p, &w) in img.pixels.iter_mut().zip(vis) {
            *p = if w == visbuf::VIS_NONE {
                [230, 200, 40, 255]
            } else {
                crate::image::id_color(w)
            };
        }
        img
    }
}

/// Bind-group 2 of the wave-command resolve: wave commands, pixel commands, pass
/// dispatches, and the pass index (a uniform at a dynamic offset per pass).
fn wave_layout_entries() -> Vec<wgpu::BindGroupLayoutEntry> {
    let c = wgpu::ShaderStages::COMPUTE;
    vec![
        binding::storage(0, c, true),
        binding::storage(1, c, true),
        binding::storage(2, c, true),
        wgpu::BindGroupLayoutEntry {
            binding: 3,
            visibility: c,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: true,
                min_binding_size: wgpu::BufferSize::new(16),
            },
            count: None,
        },
    ]
}

/// Bind-group 0 of the resolve (see `shaders/resolve_common.wgsl`).
fn resolve_layout_entries() -> Vec<wgpu::BindGroupLayoutEntry> {
    let c = wgpu::ShaderStages::COMPUTE;
    vec![
        binding::uniform(0, c),
        binding::storage(1, c, true),
        binding::storage(2, c, true),
        binding::storage(3, c, true),
        binding::storage(4, c, true),
        binding::storage(5, c, true),
        binding::storage(6, c, true),
        binding::texture(
            7,
            c,
            wgpu::TextureSampleType::Float { filterable: true },
            wgpu::TextureViewDimension::D2Array,
        ),
        binding::sampler(8, c),
        binding::texture(
            9,
            c,
            wgpu::TextureSampleType::Uint,
            wgpu::TextureViewDimension::D2,
        ),
    ]
}

/// HZD's depth-equal geometry pass: same vertex transform as the prepass, depth `Equal`
/// without writes, G-buffer from the fragment shader.
fn baseline_pipeline(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    path: PrimitiveIdPath,
) -> wgpu::RenderPipeline {
    let pl = binding::pipeline_layout(device, "baseline", &[layout]);
    let module = binding::module(device, "baseline", &crate::shaders::baseline(path));
    let targets = gbuffer::color_targets();
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("baseline geometry pass"),
        layout: Some(&pl),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs_baseline"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: crate::laydown::primitive_state(),
        depth_stencil: Some(wgpu::DepthStencilState {
            depth_write_enabled: Some(false),
            depth_compare: Some(wgpu::CompareFunction::Equal),
            ..crate::laydown::depth_write_state()
        }),
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs_baseline"),
            compilation_options: Default::default(),
            targets: &targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}
