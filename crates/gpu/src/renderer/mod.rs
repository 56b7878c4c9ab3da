//! The renderer: pipelines and targets on a user's device ([`Renderer::new`]), scenes
//! prepared once ([`Renderer::prepare`]), frames rendered from a [`FrameInput`] by either
//! path ([`Renderer::render`]). The passes themselves are in `passes`; this is the
//! orchestration.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use crate::context::{ActivePaths, OPTIONAL_FEATURES, scoped, wait_idle};
use crate::error::{Error, Result};
use crate::frame::prepare::{PrepareContext, prepare};
use crate::frame::{Pipelines, Recording};
use crate::image::Rgba8Image;
use crate::passes::classify::ClassificationVariant;
use crate::passes::query::{PreparedView, StaticQuery};
use crate::passes::{self, context::FrameContext};
use crate::resources::PreparedScene;
use crate::resources::groups::TargetGroups;
use crate::resources::lights::GpuLocalLights;
use crate::resources::lights::GpuTileDepthParams;
use crate::resources::lights::LightBuffers;
use crate::resources::readback::read_buffer;
use crate::resources::readback::read_texture;
use crate::resources::rows::FrameUniforms;
use crate::resources::static_draws::{
    STATIC_COUNTER_BAD_BATCHES, STATIC_COUNTER_DRAWS, STATIC_COUNTER_OVER_CAPACITY,
    STATIC_COUNTER_PLACED, StaticBuffers,
};
use crate::resources::targets::Targets;
use crate::resources::uniforms::{FrameInput, PreviousCamera, frame_uniforms, local_light_rows};
use crate::resources::uploads::{UploadSink, UploadStats, Uploads};
use crate::resources::vis64::LaydownTarget;
use crate::scene::Scene;
use crate::statics::{StaticFrameStats, StaticOcclusion, StaticShadowStats, StaticView};
use crate::stats::{ClassificationStats, GpuClassification, classification_statistics};
use crate::timing::{GpuTimer, Timing};

mod water_api;
pub use water_api::{WaterGBuffer, WaterGBufferInput, WaterTiles, WaterView};

mod bench;
mod device;
mod frame;
mod inspect;
mod laydown;
mod lights;
mod shadows;
mod statics;

pub use crate::config::{
    AUTO_LAYDOWN_FRAMES, Laydown, LaydownChoice, LaydownReason, LightPaths, MSAA_SAMPLES,
    RenderPath, RendererConfig,
};
pub use bench::WARM_UP;
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
    /// The laydown this frame ran (`None` for a path without one: the baseline, pixel
    /// pull). A frame with a static query runs the hardware laydown whatever
    /// [`RendererConfig::geometry.laydown`](crate::config::GeometryConfig::laydown) asks.
    pub laydown: Option<Laydown>,
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
    /// [`Laydown::Auto`]'s trial and verdict.
    auto: laydown::AutoLaydown,
}

impl Renderer {
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
        device::check_limits(&Self::required_limits(&config), &device.limits())?;
        let mut paths = ActivePaths::for_device(device.features(), &device.adapter_info());
        if let Some(p) = config.geometry.primitive_id {
            if !device.features().contains(p.required_features()) {
                return Err(Error::MissingFeature {
                    feature: p.feature_name(),
                    needed_by: "the forced primitive-ID path",
                });
            }
            paths.primitive_id = p;
        }
        if !config.geometry.subgroups {
            paths.subgroup_size = None;
        }
        let laydown_target = match config.geometry.compute_laydown_target {
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
        if config.geometry.mixed_frame
            && !device
                .features()
                .contains(passes::regular::REGULAR_FEATURES)
        {
            return Err(Error::MissingFeature {
                feature: "SHADER_EARLY_DEPTH_TEST",
                needed_by: "RendererConfig::geometry.mixed_frame (the regular geometry pass)",
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
                config.image.width,
                config.image.height,
                config.lighting.shadows,
                config.lighting.light_paths.volumes(),
                config.image.gbuffer,
                config.lighting.spot_shadows,
                config.image.msaa.is_some(),
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
            let conditional = config.lighting.conditional_volumes
                && device
                    .features()
                    .contains(wgpu::Features::INDIRECT_FIRST_INSTANCE);
            // The compute laydown where asked for and the device has 64-bit atomics.
            let compute_laydown = (config.geometry.laydown.wants_compute() && paths.int64_atomics)
                .then_some(laydown_target)
                .flatten();
            let pipelines = Pipelines::new(
                device,
                &paths,
                wave_width.lanes(),
                config.lighting.light_paths,
                config.image.gbuffer,
                config.image.msaa,
                conditional,
                compute_laydown,
                config.geometry.compute_laydown_max_extent,
                config.geometry.mixed_frame,
                config.geometry.vrs.is_some(),
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
                crate::resources::vis64::TargetResource::new(
                    device,
                    kind,
                    config.image.width,
                    config.image.height,
                )
            });
            let groups = TargetGroups::new(device, &pipelines, &targets, &frame, &local, &lights)?;
            // The frame's passes, and up to 8 slices' static shadow query and placement.
            let timer = GpuTimer::new(device, queue, 256);
            let uploads = Uploads::new(device, config.frames.upload_pool)?;
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
                auto: Default::default(),
                water: None,
            })
        })
    }

    /// The paths this renderer uses.
    pub fn paths(&self) -> &ActivePaths {
        &self.paths
    }

    /// The laydown the next deferred frame without a static query takes
    /// ([`Renderer::laydown_choice`] says why).
    pub fn laydown(&self) -> Laydown {
        self.laydown_choice().laydown
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
                baked_sun: self.config.lighting.baked_sun,
                ring_bytes: self.config.geometry.vertex_ring,
                ring_resolve: self.config.geometry.ring_resolve,
                material_permutations: self.config.geometry.material_permutations,
                vrs: self.config.geometry.vrs.is_some(),
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
                "RendererConfig::image.msaa",
                f64::from(MSAA_SAMPLES),
                "off for static frames on the baseline path (the static query's HiZ reads \
                 the single-sample depth)",
            );
        }
        // Laydown::Auto's trial frames are waited for and timed.
        let trial = self.auto_trial_frame(what, statics.is_some());
        let wait = wait || trial;
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
            let compute_laydown = self.compute_laydown_for(what, static_query);
            // FC5's water runs after lighting (not in the baseline's MSAA frame).
            let with_water =
                what.lights() && !(what == Recording::Baseline && self.targets.msaa.is_some());
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
                        compute_laydown,
                        water_hdr: if with_water {
                            self.water.as_ref().map(|w| &w.groups.hdr)
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
            self.pipelines.record_after_geometry(
                what,
                &mut encoder,
                &context!(),
                self.water.as_ref().filter(|_| with_water),
                &mut self.timer,
            );
            let laydown = what.lays_down().then(|| {
                if self.pipelines.laid_down_in_compute(&context!()) {
                    Laydown::Compute
                } else {
                    Laydown::Hardware
                }
            });
            self.timer.resolve(&mut encoder);
            let uploads = self.uploads.commit(&device, &self.queue)?;
            let index = self.queue.submit([uploads, encoder.finish()]);
            self.uploads.submitted(&self.queue);
            self.pace(index, wait)?;
            if what.lights() {
                self.targets.shadows.rendered(static_frame);
            }
            Ok((view, laydown, compute_laydown))
        });
        if view.is_err() {
            // The maps' contents are unknown after a failed frame, and its queued uploads
            // go with it.
            self.targets.shadows.rendered.clear();
            self.uploads.discard();
        }
        // The depth target now holds this frame (or, after an error, nothing known).
        self.statics.depth_camera = match (&view, statics.as_deref()) {
            (Ok((Some(_), ..)), Some(v)) => Some((scene.id, v.view.camera)),
            _ => None,
        };
        let (view, laydown, asked_compute) = view?;
        let wall_ms = t0.elapsed().as_secs_f64() * 1e3;
        if !wait {
            // Not waited for: no timings or statistics to read.
            self.timer.discard();
            return Ok(FrameOutput {
                gpu: Vec::new(),
                wall_ms,
                statics: None,
                untimed_passes: 0,
                laydown,
            });
        }
        let gpu = self.timer.read(&self.device, &self.queue)?;
        if trial {
            let asked = if asked_compute {
                Laydown::Compute
            } else {
                Laydown::Hardware
            };
            let gpu_ms: f64 = gpu.iter().map(|t| t.ms).sum();
            let timed = !gpu.is_empty();
            self.auto
                .record(asked, if timed { gpu_ms } else { wall_ms }, timed);
        }
        let statics = match (view, statics) {
            (Some(view), Some(v)) => Some(self.read_static_stats(scene, v, view)?),
            _ => None,
        };
        Ok(FrameOutput {
            gpu,
            wall_ms,
            statics,
            untimed_passes: self.timer.untimed(),
            laydown,
        })
    }

    /// After a frame's submission `index`: waits for it (`wait`), or keeps at most
    /// [`RendererConfig::frames.frames_in_flight`](crate::config::FrameConfig::frames_in_flight) frames ahead of the GPU.
    fn pace(&mut self, index: wgpu::SubmissionIndex, wait: bool) -> Result<()> {
        if wait {
            self.in_flight.clear();
            return wait_idle(&self.device);
        }
        self.in_flight.push_back(index);
        while self.in_flight.len() > self.config.frames.frames_in_flight as usize {
            let oldest = self.in_flight.pop_front();
            self.device
                .poll(wgpu::PollType::Wait {
                    submission_index: oldest,
                    timeout: None,
                })
                .map_err(|e| Error::Poll(e.to_string()))?;
        }
        Ok(())
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
    /// waiting for the GPU (unless [`RendererConfig::frames.frames_in_flight`](crate::config::FrameConfig::frames_in_flight) frames are already
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
        Ok(Rgba8Image {
            width: self.config.image.width,
            height: self.config.image.height,
            pixels: self.texels(&self.targets.output, wgpu::TextureAspect::All)?,
        })
    }
}
