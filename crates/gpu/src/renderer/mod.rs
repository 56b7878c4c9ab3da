//! The renderer: pipelines and targets on a user's device ([`Renderer::new`]), scenes
//! prepared once ([`Renderer::prepare`]), frames rendered from a [`FrameInput`] by either
//! path ([`Renderer::render`]). The passes themselves are in `passes`; this is the
//! orchestration.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use crate::context::{ActivePaths, OPTIONAL_FEATURES, PrimitiveIdPath, scoped, wait_idle};
use crate::error::{Error, Result};
use crate::frame::{FrameInput, PreviousCamera, frame_uniforms, local_light_rows};
use crate::image::Rgba8Image;
use crate::passes::classify::ClassificationVariant;
use crate::passes::compute_laydown::LaydownTarget;
use crate::passes::lighting::GpuLocalLights;
use crate::passes::lights::{GpuTileDepthParams, LightBuffers};
use crate::passes::query::{PreparedView, StaticQuery};
use crate::passes::static_place::{
    STATIC_COUNTER_BAD_BATCHES, STATIC_COUNTER_DRAWS, STATIC_COUNTER_OVER_CAPACITY,
    STATIC_COUNTER_PLACED, StaticBuffers,
};
use crate::passes::{self, FrameContext, Pipelines, Recording, TargetGroups};
use crate::resources::readback::read_buffer;
use crate::resources::readback::read_texture;
use crate::resources::rows::FrameUniforms;
use crate::resources::targets::Targets;
use crate::resources::uploads::{UploadSink, UploadStats, Uploads};
use crate::resources::{PrepareContext, PreparedScene, prepare};
use crate::scene::Scene;
use crate::statics::{StaticFrameStats, StaticOcclusion, StaticShadowStats, StaticView};
use crate::stats::{ClassificationStats, GpuClassification, classification_statistics};
use crate::timing::{GpuTimer, Timing};

mod water_api;
pub use water_api::{WaterGBuffer, WaterGBufferInput, WaterTiles, WaterView};

mod bench;
mod config;
mod inspect;
mod lights;
mod shadows;
mod statics;

pub use bench::WARM_UP;
pub use config::*;
pub use inspect::{ConditionalLight, Hooks, Inspect, LightTiles};
pub use lights::LightPathCounts;

/// What one rendered frame reports.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrameOutput {
    /// GPU time per pass label, from timestamp queries (empty without them).
    pub gpu: Vec<Timing>,
    /// Wall-clock time of the frame's recording and submission to its completion (ms);
    /// for [`Renderer::submit`], of the call (recording, submission, and any pacing wait).
    pub wall_ms: f64,
    /// The static query's and placement's statistics, in a frame with a static query.
    pub statics: Option<StaticFrameStats>,
    /// Passes missing from `gpu`: begun after the timestamp query set was full. The set
    /// grows for the next frame, so only a frame with more passes than any before it loses
    /// some (0 for a frame not waited for, which reads no timings).
    pub untimed_passes: u32,
}

/// Every renderer gets its own id; prepared scenes carry it, so a scene is never drawn
/// with another renderer's bind groups.
static NEXT_ID: AtomicU64 = AtomicU64::new(1);

/// A renderer on a device: the targets of one resolution, every pass's pipelines, and the
/// frame state (frame index, the previous camera, the uploaded lights).
pub struct Renderer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    config: RendererConfig,
    paths: ActivePaths,
    wave_width: wave::WaveWidth,
    id: u64,
    scenes: AtomicU64,
    targets: Targets,
    pipelines: Pipelines,
    groups: TargetGroups,
    frame: wgpu::Buffer,
    sampler: wgpu::Sampler,
    /// The per-frame uploads (framealloc's pool over one upload buffer).
    uploads: Uploads,
    timer: GpuTimer,
    /// The last frame's camera rotation (camera-relative world to view).
    view_rotation: glam::Mat4,
    /// This frame's scene origin minus camera position (metres).
    origin_offset: glam::Vec3,
    /// Submissions of frames not waited for, oldest first.
    in_flight: std::collections::VecDeque<wgpu::SubmissionIndex>,
    frame_index: u32,
    previous: Option<(u64, PreviousCamera)>,
    /// Local lights: buffers, this frame's split between tiles and volumes, KZ2's
    /// conditional rendering.
    light: lights::LightState,
    /// The sun's cascades and the shadow views' caster culling.
    shadow: shadows::ShadowState,
    /// The static query's frame-to-frame state.
    statics: statics::StaticState,
    /// FC5's water ([`Renderer::set_water`]).
    water: Option<passes::water::WaterState>,
}

impl Renderer {
    /// The device features the renderer cannot run without: none (each optional one
    /// selects a faster path; see [`Renderer::optional_features`]).
    pub fn required_features() -> wgpu::Features {
        wgpu::Features::empty()
    }

    /// The features the renderer uses when the device has them (request them all; see
    /// [`ActivePaths`] for what each selects).
    pub fn optional_features() -> wgpu::Features {
        OPTIONAL_FEATURES
    }

    /// The device limits a renderer with `config` needs, as `wgpu::Limits::default()`
    /// raised where its passes need more (counted from every pass's bindings: classify
    /// output binds 17 storage buffers in one stage, past WebGPU's default 8 and some GL
    /// drivers' 16; four bind groups, the image size, buffers of `width * height`
    /// words). Request these, or the adapter's own limits, when you create the device.
    pub fn required_limits(config: &RendererConfig) -> wgpu::Limits {
        let c = passes::stage_counts();
        let d = wgpu::Limits::default();
        let pixels = u64::from(config.width) * u64::from(config.height);
        // The largest buffers: the vis words (4 bytes a pixel) and the wave commands (16
        // bytes per command, at most a pixel's worth each for wave width 1; 8 lanes on
        // lavapipe make it 2 bytes a pixel plus one per counter).
        // The compute laydown's 64-bit target: 8 bytes a pixel.
        let per_pixel = if config.laydown == Laydown::Compute {
            8
        } else {
            4
        };
        let largest = (pixels * per_pixel).max(64 << 20);
        wgpu::Limits {
            max_storage_buffers_per_shader_stage: d
                .max_storage_buffers_per_shader_stage
                .max(c.storage_buffers),
            max_storage_textures_per_shader_stage: d
                .max_storage_textures_per_shader_stage
                .max(c.storage_textures),
            max_sampled_textures_per_shader_stage: d
                .max_sampled_textures_per_shader_stage
                .max(c.sampled_textures),
            max_samplers_per_shader_stage: d.max_samplers_per_shader_stage.max(c.samplers),
            max_uniform_buffers_per_shader_stage: d
                .max_uniform_buffers_per_shader_stage
                .max(c.uniform_buffers),
            max_dynamic_uniform_buffers_per_pipeline_layout: d
                .max_dynamic_uniform_buffers_per_pipeline_layout
                .max(c.dynamic_uniform_buffers),
            max_bind_groups: d.max_bind_groups.max(c.bind_groups),
            max_bindings_per_bind_group: d.max_bindings_per_bind_group.max(c.bindings_per_group),
            max_compute_invocations_per_workgroup: d
                .max_compute_invocations_per_workgroup
                .max(c.invocations_per_workgroup),
            max_texture_dimension_2d: d
                .max_texture_dimension_2d
                .max(config.width)
                .max(config.height),
            max_storage_buffer_binding_size: d.max_storage_buffer_binding_size.max(largest),
            max_buffer_size: d.max_buffer_size.max(largest),
            ..d
        }
    }

    /// Creates the renderer's targets and pipelines on `device` (made by the caller, with
    /// any features of [`Renderer::optional_features`] and at least
    /// [`Renderer::required_limits`]). Optional features the device lacks select fallback
    /// paths.
    ///
    /// # Errors
    /// A zero image size or a mip bias outside [-16, 16] ([`Error::Config`]), a limit of
    /// [`Renderer::required_limits`] the device lacks ([`Error::DeviceLimit`] names it), or
    /// a forced primitive-ID path whose feature the device lacks.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, config: RendererConfig) -> Result<Self> {
        config.validate()?;
        check_limits(&Self::required_limits(&config), &device.limits())?;
        let mut paths = ActivePaths::for_device(device.features(), &device.adapter_info());
        if let Some(p) = config.primitive_id {
            if !device.features().contains(p.required_features()) {
                return Err(Error::MissingFeature {
                    feature: p.feature_name(),
                    needed_by: "the forced primitive-ID path",
                });
            }
            paths.primitive_id = p;
        }
        if !config.subgroups {
            paths.subgroup_size = None;
        }
        let laydown_target = match config.compute_laydown_target {
            Some(t) if !device.features().contains(t.required_features()) => {
                return Err(Error::MissingFeature {
                    feature: match t {
                        LaydownTarget::Buffer => "SHADER_INT64_ATOMIC_MIN_MAX",
                        LaydownTarget::Texture => "TEXTURE_INT64_ATOMIC",
                    },
                    needed_by: "the forced compute-laydown target",
                });
            }
            Some(t) => Some(t),
            None => LaydownTarget::best_for(device.features()),
        };
        if config.mixed_frame
            && !device
                .features()
                .contains(passes::regular::REGULAR_FEATURES)
        {
            return Err(Error::MissingFeature {
                feature: "SHADER_EARLY_DEPTH_TEST",
                needed_by: "RendererConfig::mixed_frame (the regular geometry pass)",
            });
        }
        // The commands are built for the widest subgroup the device may run; lavapipe: 8.
        let wave_width = paths
            .subgroup_size
            .and_then(|(_, hi)| wave::WaveWidth::from_lanes(hi).ok())
            .unwrap_or(wave::WaveWidth::W32);
        scoped(device, || {
            let targets = Targets::new(
                device,
                config.width,
                config.height,
                config.shadows,
                config.light_paths.volumes(),
                config.gbuffer,
                config.spot_shadows,
                config.msaa.is_some(),
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
            // Indirect draws of volume rows and caster instances need first_instance.
            let conditional = config.conditional_volumes
                && device
                    .features()
                    .contains(wgpu::Features::INDIRECT_FIRST_INSTANCE);
            // The compute laydown where asked for and the device has 64-bit atomics.
            let compute_laydown = (config.laydown == Laydown::Compute && paths.int64_atomics)
                .then_some(laydown_target)
                .flatten();
            let pipelines = Pipelines::new(
                device,
                &paths,
                wave_width.lanes(),
                config.light_paths,
                config.gbuffer,
                config.msaa,
                conditional,
                compute_laydown,
                config.compute_laydown_max_extent,
                config.mixed_frame,
                config.vrs.is_some(),
            )?;
            let conditional = pipelines
                .conditional
                .as_ref()
                .map(|c| c.buffers(device, 64))
                .transpose()?;
            let local = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("local lights"),
                size: size_of::<GpuLocalLights>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let lights = LightBuffers::new(device, &targets, 64)?;
            let mut targets = targets;
            targets.vis64 = compute_laydown.map(|kind| {
                passes::compute_laydown::TargetResource::new(
                    device,
                    kind,
                    config.width,
                    config.height,
                )
            });
            let groups = TargetGroups {
                vis_copy: pipelines.vis_copy.group(device, &targets)?,
                laydown_target: match (&pipelines.compute_laydown, &targets.vis64) {
                    (Some(c), Some(t)) => {
                        Some(c.target_groups(device, &targets, t, &lights.tile_depths)?)
                    }
                    _ => None,
                },
                gbuffer_store: pipelines
                    .resolve
                    .gbuffer_group(device, &targets.gbuffer_views)?,
                lighting: pipelines
                    .lighting
                    .groups(device, &targets, &frame, &local, &lights)?,
                lights: pipelines.lights.groups(device, &targets, &lights)?,
                light_volumes: pipelines
                    .light_volumes
                    .as_ref()
                    .map(|v| {
                        v.groups(
                            device,
                            &targets,
                            &frame,
                            &local,
                            &lights.lights,
                            &lights.volumes,
                        )
                    })
                    .transpose()?,
            };
            // The frame's passes, and up to 8 slices' static shadow query and placement.
            let timer = GpuTimer::new(device, queue, 256);
            let uploads = Uploads::new(device, config.upload_pool)?;
            Ok(Self {
                device: device.clone(),
                queue: queue.clone(),
                config,
                paths,
                wave_width,
                id: NEXT_ID.fetch_add(1, Ordering::Relaxed),
                scenes: AtomicU64::new(0),
                targets,
                pipelines,
                groups,
                frame,
                sampler,
                uploads,
                timer,
                in_flight: Default::default(),
                view_rotation: glam::Mat4::IDENTITY,
                origin_offset: glam::Vec3::ZERO,
                frame_index: 0,
                previous: None,
                light: lights::LightState::new(local, lights, conditional),
                shadow: Default::default(),
                statics: Default::default(),
                water: None,
            })
        })
    }

    /// The paths this renderer uses.
    pub fn paths(&self) -> &ActivePaths {
        &self.paths
    }

    /// The laydown the deferred paths use in frames without a static query:
    /// [`Laydown::Compute`] where asked for and the device has its features, else
    /// [`Laydown::Hardware`].
    pub fn laydown(&self) -> Laydown {
        if self.pipelines.compute_laydown.is_some() {
            Laydown::Compute
        } else {
            Laydown::Hardware
        }
    }

    /// The compute laydown's 64-bit target (`None` without the compute laydown).
    pub fn laydown_target(&self) -> Option<LaydownTarget> {
        self.pipelines.compute_laydown.as_ref().map(|c| c.kind())
    }

    /// The configuration.
    pub fn config(&self) -> &RendererConfig {
        &self.config
    }

    /// Validates `scene` (every mesh, material, layer, batch and instance), encodes its
    /// meshes for the renderer's primitive-ID path, builds micro batches and passes with
    /// `tiling` (batches sorted by shader, material and a Morton code of their instances'
    /// mean position; the talk's PS5 limits), and uploads everything a frame reads, relative
    /// to a floating origin at the instances' bounds centre. An empty scene renders the
    /// sky.
    ///
    /// # Errors
    /// A value or reference the scene's validation rejects, or a limit from the talks or
    /// the device (each names the limit and the item).
    pub fn prepare(&self, scene: &Scene) -> Result<PreparedScene> {
        let id = (self.id << 32) | self.scenes.fetch_add(1, Ordering::Relaxed);
        prepare(
            &PrepareContext {
                device: &self.device,
                queue: &self.queue,
                pipelines: &self.pipelines,
                frame: &self.frame,
                sampler: &self.sampler,
                targets: &self.targets,
                path: self.paths.primitive_id,
                wave_width: self.wave_width,
                id,
                multi_draw_count: self
                    .device
                    .features()
                    .contains(wgpu::Features::MULTI_DRAW_INDIRECT_COUNT),
                indirect_first_instance: self
                    .device
                    .features()
                    .contains(wgpu::Features::INDIRECT_FIRST_INSTANCE),
                baked_sun: self.config.baked_sun,
                ring_bytes: self.config.vertex_ring,
                ring_resolve: self.config.ring_resolve,
                vrs: self.config.vrs.is_some(),
            },
            scene,
        )
    }

    fn check_scene(&self, scene: &PreparedScene) -> Result<()> {
        if scene.id >> 32 == self.id {
            Ok(())
        } else {
            Err(Error::ForeignScene)
        }
    }

    /// Uploads the frame constants of `frame` for `scene`, and its point lights when they
    /// differ from the last upload.
    fn upload_frame(
        &mut self,
        scene: &PreparedScene,
        frame: &FrameInput,
        statics: Option<&mut StaticView<'_>>,
    ) -> Result<()> {
        let static_frame = statics.is_some();
        frame.validate()?;
        self.check_scene(scene)?;
        let previous = self
            .previous
            .filter(|(id, _)| *id == scene.id)
            .map(|(_, p)| p);
        let origin = scene.summary.origin;
        let mut uniforms = frame_uniforms(
            frame,
            scene.wind.as_ref(),
            origin,
            (self.config.width, self.config.height),
            self.config.mip_bias,
            self.frame_index,
            previous,
        );
        uniforms.vrs = self.config.vrs.map_or([0.0; 4], |v| v.uniform());
        self.bake_sun(scene, frame, &mut uniforms, statics)?;
        uniforms.local_light_count = self.upload_lights(frame, &uniforms)?;
        // Swaying foliage moves its shadows: a cached slice is stale once time moved.
        let animated = scene.wind.is_some() && uniforms.prev_time != uniforms.time;
        self.upload_shadows(scene.id, static_frame || animated, frame, &uniforms)?;
        self.uploads
            .write(&self.frame, 0, bytemuck::bytes_of(&uniforms));
        if let Some(w) = &self.water {
            let aspect = self.config.width as f32 / self.config.height as f32;
            let u = w.data.frame_constants(frame, aspect);
            self.uploads.write(&w.data.frame, 0, bytemuck::bytes_of(&u));
            if !w.data.decals_cpu.is_empty() {
                self.uploads
                    .write(&w.data.decals, 0, bytemuck::cast_slice(&w.data.decals_cpu));
            }
        }
        self.view_rotation = frame.camera.view_rotation();
        self.origin_offset = glam::Vec4::from(uniforms.origin_offset).truncate();
        self.plan_conditional(scene)?;
        let aspect = self.config.width as f32 / self.config.height as f32;
        self.previous = Some((
            scene.id,
            PreviousCamera {
                view_proj: frame.camera.relative_view_projection(aspect),
                position: frame.camera.position,
                time: frame.time,
            },
        ));
        self.frame_index = self.frame_index.wrapping_add(1);
        Ok(())
    }

    /// Records `what` after uploading `frame` (and, with `statics`, the static query and
    /// the placement of its output first), submits, waits, and reads the timings and the
    /// static statistics.
    fn run(
        &mut self,
        scene: &PreparedScene,
        frame: &FrameInput,
        label: &str,
        what: Recording,
        mut statics: Option<&mut StaticView<'_>>,
        wait: bool,
    ) -> Result<FrameOutput> {
        if statics.is_some() && what == Recording::Baseline && self.targets.msaa.is_some() {
            return Error::config(
                "RendererConfig::msaa",
                f64::from(MSAA_SAMPLES),
                "off for static frames on the baseline path (the static query's HiZ reads \
                 the single-sample depth)",
            );
        }
        let device = self.device.clone();
        let t0 = Instant::now();
        let view = scoped(&device, || {
            let static_frame = statics.is_some();
            self.statics.slices.clear();
            self.upload_frame(scene, frame, statics.as_deref_mut())?;
            self.timer.fit(&device);
            let mut encoder = device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label) });
            let view = match statics.as_deref_mut() {
                Some(v) => {
                    Some(self.record_static(&mut encoder, scene, v, what.lights(), frame)?)
                }
                None => None,
            };
            let static_query = view.is_some();
            // Field by field, so the timer can be borrowed beside it.
            macro_rules! context {
                () => {
                    FrameContext {
                        scene,
                        targets: &self.targets,
                        groups: &self.groups,
                        static_query,
                        volumes: &self.light.volume_draws,
                        casters: &self.shadow.casters,
                        static_slices: &self.statics.slices,
                        conditional: self.light.conditional.as_ref(),
                        origin_offset: self.origin_offset,
                        msaa: what == Recording::Baseline && self.targets.msaa.is_some(),
                        compute_laydown: !static_query,
                        water: if what.lights()
                            && !(what == Recording::Baseline && self.targets.msaa.is_some())
                        {
                            self.water.as_ref()
                        } else {
                            None
                        },
                    }
                };
            }
            self.pipelines
                .record_geometry(what, &mut encoder, &context!(), &mut self.timer, false);
            if let (Some(sf), Some(v)) = (&view, statics.as_deref_mut())
                && sf.two_pass
            {
                self.record_static_late(&mut encoder, scene, v, &sf.view)?;
                self.pipelines.record_geometry(
                    what,
                    &mut encoder,
                    &context!(),
                    &mut self.timer,
                    true,
                );
            }
            self.pipelines
                .record_after_geometry(what, &mut encoder, &context!(), &mut self.timer);
            self.timer.resolve(&mut encoder);
            let uploads = self.uploads.commit(&device, &self.queue)?;
            let index = self.queue.submit([uploads, encoder.finish()]);
            self.uploads.submitted(&self.queue);
            if wait {
                wait_idle(&device)?;
                self.in_flight.clear();
            } else {
                // Frame pacing: at most `frames_in_flight` frames ahead of the GPU.
                self.in_flight.push_back(index);
                while self.in_flight.len() > self.config.frames_in_flight as usize {
                    let oldest = self.in_flight.pop_front();
                    device
                        .poll(wgpu::PollType::Wait {
                            submission_index: oldest,
                            timeout: None,
                        })
                        .map_err(|e| Error::Poll(e.to_string()))?;
                }
            }
            if what.lights() {
                self.targets.shadows.rendered(static_frame);
            }
            Ok(view)
        });
        if view.is_err() {
            // The maps' contents are unknown after a failed frame, and its queued uploads
            // go with it.
            self.targets.shadows.rendered.clear();
            self.uploads.discard();
        }
        // The depth target now holds this frame (or, after an error, nothing known).
        self.statics.depth_camera = match (&view, statics.as_deref()) {
            (Ok(Some(_)), Some(v)) => Some((scene.id, v.view.camera)),
            _ => None,
        };
        let view = view?;
        let wall_ms = t0.elapsed().as_secs_f64() * 1e3;
        if !wait {
            // Not waited for: no timings or statistics to read.
            self.timer.discard();
            return Ok(FrameOutput {
                gpu: Vec::new(),
                wall_ms,
                statics: None,
                untimed_passes: 0,
            });
        }
        let gpu = self.timer.read(&self.device, &self.queue)?;
        let statics = match (view, statics) {
            (Some(view), Some(v)) => Some(self.read_static_stats(scene, v, view)?),
            _ => None,
        };
        Ok(FrameOutput {
            gpu,
            wall_ms,
            statics,
            untimed_passes: self.timer.untimed(),
        })
    }

    /// Renders one frame of `scene` as `frame` describes by `path` into the output image,
    /// and waits for it. Uploads the frame constants (camera, time, sun; the previous
    /// frame's view-projection and the frame index for motion), and the point lights only
    /// when they changed.
    ///
    /// # Errors
    /// A frame input value out of range ([`Error::Frame`] names it), a scene prepared by
    /// another renderer, or a device error.
    pub fn render(
        &mut self,
        scene: &PreparedScene,
        frame: &FrameInput,
        path: RenderPath,
    ) -> Result<FrameOutput> {
        let what = Recording::of(path);
        self.run(scene, frame, path.name(), what, None, true)
    }

    /// Records and submits one frame of `scene` as [`Renderer::render`] does, without
    /// waiting for the GPU (unless [`RendererConfig::frames_in_flight`] frames are already
    /// running: then for the oldest): the next frame's CPU work overlaps this one's GPU
    /// work, and its uploads take other blocks of the upload pool (those of finished
    /// frames are reused). Reads no timings ([`FrameOutput::gpu`] is empty); [`Renderer::wait`], a
    /// read-back or [`Renderer::render`] waits.
    ///
    /// # Errors
    /// As [`Renderer::render`]; [`Error::UploadPoolExhausted`] when the upload pool is
    /// still full after waiting for the device.
    pub fn submit(
        &mut self,
        scene: &PreparedScene,
        frame: &FrameInput,
        path: RenderPath,
    ) -> Result<FrameOutput> {
        let what = Recording::of(path);
        self.run(scene, frame, path.name(), what, None, false)
    }

    /// Waits until the GPU has finished every submitted frame.
    ///
    /// # Errors
    /// A device error.
    pub fn wait(&mut self) -> Result<()> {
        self.in_flight.clear();
        wait_idle(&self.device)
    }

    /// Renders one frame as [`Renderer::render`] does, with HZD's static query in front:
    /// the CPU pre-culls `statics.view` on `statics.scene`, then one command buffer runs
    /// the query, places its batches into the scene's reserved instance slots and indirect
    /// draw lists (no CPU round trip), and draws them with the scene's batches in the
    /// laydown (or the baseline's passes). Reads the query's and the placement's counters
    /// back after the frame ([`FrameOutput::statics`]).
    ///
    /// # Errors
    /// As [`Renderer::render`]; a scene without static setups ([`Error::Config`]); a view
    /// the query rejects ([`Error::StaticScene`]).
    pub fn render_static(
        &mut self,
        scene: &PreparedScene,
        frame: &FrameInput,
        path: RenderPath,
        statics: &mut StaticView<'_>,
    ) -> Result<FrameOutput> {
        let what = Recording::of(path);
        self.run(scene, frame, path.name(), what, Some(statics), true)
    }

    /// What the last frame's uploads took from the upload pool: bytes, blocks, the CPU
    /// time spent in `framealloc`, the pool's free blocks and the frames in flight.
    pub fn upload_stats(&self) -> &UploadStats {
        self.uploads.stats()
    }

    /// The output image's texture, for showing a frame without reading it back (a window's
    /// blit): `config.width` x `config.height`, format `Rgba8Unorm` holding **sRGB-encoded**
    /// values (the lighting pass writes them through a storage binding, which cannot be an
    /// sRGB format), usages `TEXTURE_BINDING | STORAGE_BINDING | COPY_SRC`. Sample or load it
    /// into a non-sRGB view of the target, so the values pass through unchanged, or decode
    /// them to linear before writing an sRGB target. It holds the last frame's image (the
    /// same bytes as [`Renderer::read_output`]) once the frame's work has run; the texture
    /// lives as long as the renderer.
    pub fn output_texture(&self) -> &wgpu::Texture {
        &self.targets.output
    }

    /// A view of [`Renderer::output_texture`] (the whole texture, its own format).
    pub fn output_view(&self) -> &wgpu::TextureView {
        &self.targets.output_view
    }

    /// Reads the output image back (sRGB-encoded RGBA8).
    ///
    /// # Errors
    /// A device or mapping error.
    pub fn read_output(&self) -> Result<Rgba8Image> {
        let bytes = read_texture(
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
}

/// The first limit of `needed` that `available` falls short of (wgpu's own comparison of
/// every limit), as an error naming it.
fn check_limits(needed: &wgpu::Limits, available: &wgpu::Limits) -> Result<()> {
    let mut first = None;
    needed.check_limits_with_fail_fn(available, true, |limit, needed, available| {
        first = Some(Error::DeviceLimit {
            limit,
            needed,
            available,
        });
    });
    first.map_or(Ok(()), Err)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_limits_fall_short_by_name_and_the_required_ones_pass() {
        let config = RendererConfig::default();
        let needed = Renderer::required_limits(&config);
        assert!(check_limits(&needed, &needed).is_ok());
        match check_limits(&needed, &wgpu::Limits::default()) {
            Err(Error::DeviceLimit { limit, needed, .. }) => {
                assert_eq!(limit, "max_storage_buffers_per_shader_stage");
                assert!(needed >= 17, "{needed}");
            }
            other => panic!("{other:?}"),
        }
        // A 16K image needs a larger texture dimension than the defaults.
        let big = Renderer::required_limits(&RendererConfig {
            width: 16_384,
            height: 16,
            ..RendererConfig::default()
        });
        assert_eq!(big.max_texture_dimension_2d, 16_384);
    }
}
