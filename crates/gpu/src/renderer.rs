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

/// Wall time [`Renderer::render_frames`] renders before it starts measuring.
pub const WARM_UP: Duration = Duration::from_millis(500);

/// Which rendering path a frame takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RenderPath {
    /// HFW: visibility laydown, GPU classification, compute material resolve.
    Deferred,
    /// HZD: depth prepass with alpha test, then a depth-equal geometry pass.
    Baseline,
    /// Diagnostic: laydown, then a full-screen resolve of every pixel (no classification).
    DeferredFullScreen,
    /// Seed 004's geometry pipeline: the baseline's depth prepass, then a depth-equal pass
    /// whose vertex stage writes only positions and whose fragment stage pulls its
    /// triangle's vertices by the primitive ID (the laydown's primitive-ID path) and
    /// interpolates them with hardware barycentrics (`SHADER_BARYCENTRICS`) or, without
    /// them, the pixel's camera ray against the triangle (`visbuf::ray`). Single-sample.
    PixelPull,
}

impl RenderPath {
    /// Short name for file names and tables.
    pub fn name(self) -> &'static str {
        match self {
            RenderPath::Deferred => "deferred",
            RenderPath::Baseline => "baseline",
            RenderPath::DeferredFullScreen => "deferred-fullscreen",
            RenderPath::PixelPull => "pixel-pull",
        }
    }
}

/// How the deferred paths ([`RenderPath::Deferred`], [`RenderPath::DeferredFullScreen`])
/// lay down depth and the vis buffer. The baseline keeps its hardware depth prepass (HZD's
/// method) either way.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Laydown {
    /// The hardware rasteriser: one indexed draw per micro batch. The default: faster
    /// wherever the raster units are a fair share of the chip (and on lavapipe).
    #[default]
    Hardware,
    /// Issue 17's compute laydown: triangles rasterised in compute into a 64-bit target
    /// with `atomicMax` (depth bits high, vis word low), an invocation each, or the
    /// large-triangle pass's workgroups past the split
    /// ([`COMPUTE_LAYDOWN_MAX_EXTENT`](crate::COMPUTE_LAYDOWN_MAX_EXTENT)); one pass
    /// to the depth target and vis texture; then those crossing the near plane drawn by
    /// the hardware over them. Faster on the H200, whose raster units are 2 of its 66
    /// TPCs (0.56-0.81x of the hardware laydown; BENCHMARKS.md). Needs
    /// [`COMPUTE_LAYDOWN_FEATURES`](crate::COMPUTE_LAYDOWN_FEATURES) (64-bit storage-buffer
    /// atomics); on a device without them, and in frames with a static query (whose
    /// indirect draw lists the hardware draws), the hardware laydown runs instead:
    /// [`Renderer::laydown`] says which one a renderer got.
    Compute,
}

impl Laydown {
    /// Short name for tables and CLI flags.
    pub fn name(self) -> &'static str {
        match self {
            Laydown::Hardware => "hardware",
            Laydown::Compute => "compute",
        }
    }
}

/// How local lights reach the image. Every path gives the same image up to rounding:
/// each light's shading is exactly zero outside its volume, and the paths differ only in
/// which pixels they try.
///
/// The default is [`LightPaths::Tiled`]: measured fastest on the H200 (whose raster
/// units are few: a light volume covering much of a 4K screen costs 0.1-0.5 ms there,
/// against about a microsecond per light per tile in the compute lighting) and on
/// lavapipe; BENCHMARKS.md has the figures. KZ2's classification suits GPUs with
/// rasterisers to spare.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum LightPaths {
    /// KZ2's classification per light and frame ([`deferred::lights::LightClassifier`]):
    /// small lights take the tiles (the per-tile depth-bounds test, wgpu having none),
    /// lights covering at least 20% of the screen or holding the eye take stencil volumes.
    Classified,
    /// Every light through the 16x16 tiles' lists (the per-tile depth-bounds test).
    #[default]
    Tiled,
    /// Every light as a stencil volume.
    Volumes,
    /// Every light tested at every pixel (no tiles, no volumes): the reference.
    EveryPixel,
}

impl LightPaths {
    /// Whether some light may take the stencil-volume path.
    pub fn volumes(self) -> bool {
        matches!(self, LightPaths::Classified | LightPaths::Volumes)
    }
}

/// MSAA samples per pixel of the baseline path with [`RendererConfig::msaa`] on: 4, the
/// count wgpu guarantees for every G-buffer format.
pub const MSAA_SAMPLES: u32 = 4;

/// How the baseline path lights its 4x multisampled G-buffer ([`RendererConfig::msaa`]).
/// Both give the same image but where the PCF split rounds (edge pixels' shadows).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MsaaLighting {
    /// KZ2's tricks: a pixel whose samples hold one surface (equal G-buffer words, every
    /// sample on sample 0's plane within a pixel's width) is lit once, at its centre, with
    /// the full PCF kernel; the others, the
    /// edges, are appended to a list (wave-aggregated) and lit per sample by a second,
    /// indirect dispatch, each sample filtering with its own disjoint part of the PCF taps
    /// ([`deferred::msaa::split_taps`]): the pixel's average sees the whole kernel once.
    Kz2,
    /// Every sample of every pixel lit with the full kernel: the measurement baseline.
    EverySample,
}

/// Renderer options.
#[derive(Clone, Debug, PartialEq)]
pub struct RendererConfig {
    /// Image width in pixels, at least 1.
    pub width: u32,
    /// Image height in pixels, at least 1.
    pub height: u32,
    /// Force a primitive-ID path (the device must have its feature); `None` picks the
    /// best the device has.
    pub primitive_id: Option<PrimitiveIdPath>,
    /// Use subgroup operations where the device has them (else the workgroup fallback).
    pub subgroups: bool,
    /// Mip bias of the compute resolve (log2 units, in [-16, 16]).
    pub mip_bias: f32,
    /// How local lights reach the image: the tiles (the default), KZ2's classification
    /// between tiles and stencil volumes, stencil volumes alone, or every light tested at
    /// every pixel (the reference and measurement baseline).
    pub light_paths: LightPaths,
    /// The sun's cascaded shadow maps; `None`: the sun is unshadowed (but for the
    /// G-buffer's baked sun term).
    pub shadows: Option<crate::ShadowConfig>,
    /// The G-buffer layout: `deferred`'s octahedral one (the default: world-space 12+12-bit
    /// normal, 20 bytes a pixel) or KZ2's four RGBA8 targets (view-space normal xy as f16,
    /// lighting and glow, motion and log specular power, albedo and sun shadow; 16 bytes a
    /// pixel). Both render the same scene; the KZ2 preset rounds more (BENCHMARKS.md has
    /// the image difference). The depth target stays `Depth32Float` in both.
    pub gbuffer: deferred::GBufferLayout,
    /// Shadow views (sun slices, spot maps) draw only the casters whose chunk of instances
    /// (64 consecutive instances of a batch, in Morton order) meets the view; off, every
    /// caster (the maps are the same: the test compares them).
    pub cull_shadow_casters: bool,
    /// Frames [`Renderer::submit`] lets run ahead of the GPU before it waits for the
    /// oldest (at least 1; default 2: one recording while one renders).
    pub frames_in_flight: u32,
    /// The per-frame upload pool (KZ2's render-memory allocator, `framealloc`): every
    /// frame's uniforms, lights and query parameters are sub-allocated from its blocks
    /// and freed when the GPU has finished the frame. Default: KZ2's 22 MiB in 256 KiB
    /// blocks.
    pub upload_pool: framealloc::PoolConfig,
    /// Shadow maps for the spot lights that cast shadows (KZ2's fade, the largest first);
    /// `None`: every spot lights unshadowed.
    pub spot_shadows: Option<crate::SpotShadowConfig>,
    /// KZ2's pre-rendered sun shadow: a low-resolution map of the scene's batches
    /// (1024² texels), rendered when the scene or the sun
    /// direction changes, written into the G-buffer's sun term; pixels where it is 0 skip
    /// the sun's shader. Off: the term is 1 everywhere.
    pub baked_sun: bool,
    /// KZ2's MSAA on the baseline path ([`RenderPath::Baseline`]): its depth prepass and
    /// G-buffer pass render [`MSAA_SAMPLES`] samples a pixel, lighting resolves them into
    /// the output image (the average of the samples' tone-mapped colours). `None`: single
    /// sample. The visibility-buffer paths stay single-sample (a vis word names one
    /// triangle a pixel), and so do the static query's HiZ and the stencil volumes:
    /// MSAA needs a light path without volumes, and static frames on the baseline path
    /// are refused with it. [`Renderer::read_depth`] and [`Renderer::read_gbuffer`] read
    /// the single-sample targets.
    pub msaa: Option<MsaaLighting>,
    /// KZ2's conditional rendering, emulated with indirect draws: a light on the
    /// stencil-volume path that owns a spot shadow map first counts the pixels its shading
    /// would cover (an occlusion query over a test draw of its volume), and a compute pass
    /// turns the count into the indirect arguments of its map's caster draws and of its
    /// volume draws, so a light behind a wall or lighting only air draws neither, with no
    /// CPU round trip. The image is the same either way. Takes effect with a light path
    /// that has volumes on a device with `INDIRECT_FIRST_INSTANCE` (else the draws are
    /// direct); default on.
    pub conditional_volumes: bool,
    /// How the deferred paths lay down depth and the vis buffer (default: the hardware
    /// rasteriser; [`Laydown::Compute`] falls back to it on a device without 64-bit
    /// atomics).
    pub laydown: Laydown,
    /// The compute laydown's split: triangles whose screen box is wider or taller than this
    /// many pixels, or larger than a quarter of its square in area, go to its
    /// large-triangle pass instead of an invocation each (0: every one; at most
    /// [`COMPUTE_LAYDOWN_EXTENT_LIMIT`](crate::COMPUTE_LAYDOWN_EXTENT_LIMIT), where the
    /// fixed-point edge functions still fit 32 bits). Default
    /// [`COMPUTE_LAYDOWN_MAX_EXTENT`](crate::COMPUTE_LAYDOWN_MAX_EXTENT).
    pub compute_laydown_max_extent: f32,
    /// Force the compute laydown's 64-bit target (the device must have its features);
    /// `None` picks [`LaydownTarget::best_for`] the device: the storage buffer (measured
    /// faster than the `r64uint` texture on the H200).
    pub compute_laydown_target: Option<LaydownTarget>,
    /// HFW's mixed frame on [`RenderPath::Deferred`]: batches of
    /// [`Material::regular`](crate::Material::regular) materials (the demo scenes' terrain
    /// and rocks) leave the vis buffer and are drawn by a regular geometry pass after the
    /// laydown, which writes the G-buffer from a fragment shader and clears those pixels'
    /// bits in the classification's validity bitmask (the talk's stencil bit), so only
    /// pixels still valid are classified and resolved. Mid classify is recorded before
    /// that pass (its counts conservative), classify output after it. Needs
    /// `Features::SHADER_EARLY_DEPTH_TEST` (the pass's depth test must run before its
    /// shader clears a bit). Off (the default): today's all-vis-buffer frame.
    /// [`RenderPath::DeferredFullScreen`] draws the regular batches after its resolve;
    /// the other paths are unchanged either way.
    pub mixed_frame: bool,
    /// HFW's vertex ring (seed 000: 12 MiB on PS4, 24 MiB on PS5; `gpu::RING_BYTES_PS4`,
    /// `gpu::RING_BYTES_PS5`): bytes of the ring the deferred path transforms each pass's
    /// visible 64-vertex chunks into (tiling's vertex wave commands, built on the GPU from
    /// the vertex cull buffer, which mid classify then fills:
    /// `tiling::ClassifyConfig::vertex_cull`), a pass never more than half of it. `None`
    /// (the default): no vertex side and no chunk marks (the classification reads no
    /// index), the resolve transforms its triangle's vertices per pixel.
    pub vertex_ring: Option<u64>,
    /// With [`vertex_ring`](Self::vertex_ring): the resolve reads its triangle's three
    /// transformed vertices from the ring (each pass's transform recorded right before
    /// its resolve; default). Off: the ring is still filled (and timed alone), the resolve
    /// transforms per pixel, for comparison.
    pub ring_resolve: bool,
    /// HFW's software variable-rate shading on the deferred path (`None`: off, the
    /// default): a shading rate per triangle from its provoking vertex's distance and
    /// screen speed, in the vis word's two rate bits (visbuf's VRS layout, 14-bit
    /// micro-batch IDs), quad commands from the classification, and the resolve shading
    /// one sample per quad command and broadcasting it through workgroup memory.
    pub vrs: Option<VrsConfig>,
}

/// HFW's rule for the shading rate, chosen in the vertex stage ("blends through 1x1 and
/// 2x1 to 2x2 depending on distance ... when we are moving at pace, everything blends
/// towards using 2x2"): the coarser of the distance's rate and the speed's. Steps, not a
/// blend: 1x1 nearer than `distance_2x1`, 2x1 up to `distance_2x2`, 2x2 beyond; at least
/// 2x1 from `speed_2x1` pixels per frame of screen motion (camera and wind), 2x2 from
/// `speed_2x2`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VrsConfig {
    /// View distance (metres, along the view axis) where 2x1 begins, > 0.
    pub distance_2x1: f32,
    /// Where 2x2 begins, >= `distance_2x1`.
    pub distance_2x2: f32,
    /// Screen speed (pixels per frame) from which a triangle shades at least 2x1, > 0.
    pub speed_2x1: f32,
    /// Screen speed from which it shades 2x2, >= `speed_2x1`.
    pub speed_2x2: f32,
}

impl Default for VrsConfig {
    /// 1x1 within 12 m, 2x1 to 30 m, 2x2 beyond; 2x1 from 8 px a frame, 2x2 from 24.
    fn default() -> Self {
        Self {
            distance_2x1: 12.0,
            distance_2x2: 30.0,
            speed_2x1: 8.0,
            speed_2x2: 24.0,
        }
    }
}

impl VrsConfig {
    /// The frame uniform (`FrameUniforms::vrs`).
    pub(crate) fn uniform(&self) -> [f32; 4] {
        [
            self.distance_2x1,
            self.distance_2x2.max(f32::MIN_POSITIVE),
            self.speed_2x1,
            self.speed_2x2,
        ]
    }

    fn validate(&self) -> Result<()> {
        let ok = self.distance_2x1 > 0.0
            && self.distance_2x2 >= self.distance_2x1
            && self.speed_2x1 > 0.0
            && self.speed_2x2 >= self.speed_2x1
            && self.distance_2x2.is_finite()
            && self.speed_2x2.is_finite();
        if ok {
            Ok(())
        } else {
            Error::config(
                "RendererConfig::vrs",
                f64::from(self.distance_2x1),
                "finite thresholds, 0 < distance_2x1 <= distance_2x2, 0 < speed_2x1 <= speed_2x2",
            )
        }
    }
}

impl RendererConfig {
    /// Checks the image size and the mip bias (the device's limits are checked by
    /// [`Renderer::new`]).
    ///
    /// # Errors
    /// [`Error::Config`] naming the field and its allowed range.
    pub fn validate(&self) -> Result<()> {
        let bad = Error::config;
        if self.width == 0 {
            return bad("RendererConfig::width", 0.0, "at least 1 pixel");
        }
        if self.height == 0 {
            return bad("RendererConfig::height", 0.0, "at least 1 pixel");
        }
        if self.mip_bias.is_nan() || self.mip_bias.abs() > 16.0 {
            return bad(
                "RendererConfig::mip_bias",
                f64::from(self.mip_bias),
                "[-16, 16] (log2 units)",
            );
        }
        if self.frames_in_flight == 0 {
            return bad("RendererConfig::frames_in_flight", 0.0, "at least 1 frame");
        }
        if let Some(s) = &self.shadows {
            s.validate()?;
        }
        if let Some(s) = &self.spot_shadows {
            s.validate()?;
        }
        let extent = self.compute_laydown_max_extent;
        if !(0.0..=crate::COMPUTE_LAYDOWN_EXTENT_LIMIT).contains(&extent) {
            return bad(
                "RendererConfig::compute_laydown_max_extent",
                f64::from(extent),
                "[0, 254] pixels",
            );
        }
        if let Some(bytes) = self.vertex_ring {
            // Two halves of at least one 64-vertex chunk; slots in u32.
            let min = 2 * 64 * passes::vertex_ring::RING_VERTEX_BYTES;
            if !(min..=1 << 36).contains(&bytes) {
                return bad(
                    "RendererConfig::vertex_ring",
                    bytes as f64,
                    "4096 bytes to 64 GiB (the device's storage binding limit applies)",
                );
            }
        }
        if let Some(v) = &self.vrs {
            v.validate()?;
        }
        if self.msaa.is_some() && self.light_paths.volumes() {
            return bad(
                "RendererConfig::msaa",
                f64::from(MSAA_SAMPLES),
                "off with a light path that has stencil volumes (they are single-sample)",
            );
        }
        Ok(())
    }
}

impl Default for RendererConfig {
    fn default() -> Self {
        Self {
            width: 1280,
            height: 720,
            primitive_id: None,
            subgroups: true,
            mip_bias: 0.0,
            light_paths: LightPaths::Tiled,
            shadows: Some(crate::ShadowConfig::default()),
            spot_shadows: Some(crate::SpotShadowConfig::default()),
            baked_sun: true,
            upload_pool: framealloc::PoolConfig::KZ2,
            frames_in_flight: 2,
            cull_shadow_casters: true,
            gbuffer: deferred::GBufferLayout::Octahedral,
            msaa: None,
            conditional_volumes: true,
            laydown: Laydown::Hardware,
            compute_laydown_max_extent: crate::COMPUTE_LAYDOWN_MAX_EXTENT,
            compute_laydown_target: None,
            mixed_frame: false,
            vertex_ring: None,
            ring_resolve: true,
            vrs: None,
        }
    }
}

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

/// The last frame's light tiles ([`Renderer::read_light_tiles`]), in the layout of
/// `deferred::lights::cull_tiles`: tiles of 16x16 pixels, row-major from the top-left.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LightTiles {
    /// Tiles across and down.
    pub tiles: [u32; 2],
    /// Per tile: the nearest and farthest depth of its geometry (reversed Z).
    pub depths: Vec<deferred::DeferredTileDepth>,
    /// Per tile: its lights (at most `MAX_LIGHTS_PER_TILE`).
    pub counts: Vec<u32>,
    /// Per tile, `MAX_LIGHTS_PER_TILE` slots: its lights' indices (ascending) in
    /// [`LightTiles::lights`], the first `counts[t]` valid.
    pub indices: Vec<u32>,
    /// The lights that took the tiled path in the last frame, in view space: all of
    /// [`local_light_rows`](crate::local_light_rows), in its order, under
    /// [`LightPaths::Tiled`]; under [`LightPaths::Classified`], those KZ2's classifier
    /// left to the tiles, in the same relative order.
    pub lights: Vec<deferred::DeferredLight>,
    /// Tiles with geometry, (tile, light) pairs, tiles that overflowed.
    pub stats: deferred::lights::CullStats,
}

/// How the last frame's local lights were drawn ([`Renderer::light_path_counts`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LightPathCounts {
    /// Lights in the tiles' lists (or, under [`LightPaths::EveryPixel`], tested at every
    /// pixel).
    pub tiled: u32,
    /// Lights drawn as stencil volumes (those wholly behind the near plane are not).
    pub volumes: u32,
    /// Of `volumes`, those drawn from inside (the eye in the mesh or the mesh reaching the
    /// near plane): back faces alone, no stencil.
    pub volumes_from_inside: u32,
    /// Spot lights that rendered a shadow map (shadow-casting, not faded out, among the
    /// largest [`SpotShadowConfig::maps`](crate::SpotShadowConfig::maps)), or had one to
    /// render: see the next two.
    pub spot_shadow_maps: u32,
    /// Of `volumes`, those tested for KZ2's conditional rendering
    /// ([`RendererConfig::conditional_volumes`]): lights with a spot map, whose map and
    /// shading the GPU skips if their test counts no pixel.
    pub volumes_tested: u32,
    /// Of `spot_shadow_maps`, those the CPU skipped under
    /// [`RendererConfig::conditional_volumes`]: their light takes the volume path but has
    /// no volume draw (wholly behind the near plane).
    pub spot_shadow_maps_skipped: u32,
}

/// One light the last frame tested for KZ2's conditional rendering, as the GPU decided
/// ([`Renderer::read_conditional_volumes`]): a test and measurement aid.
#[doc(hidden)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ConditionalLight {
    /// Its row (view space; its spot map's slot + 1 in `flags` bits 8-15).
    pub light: deferred::DeferredLight,
    /// What its occlusion query counted (non-zero: some pixel is shaded).
    pub samples: u64,
    /// Instances of its volume draws' indirect arguments: 1, or 0 where skipped.
    pub volume_instances: u32,
    /// Its map's caster draws: rows the CPU culled, the count words' total (0 where
    /// skipped), and the instances their arguments hold (0 where skipped).
    pub caster_rows: u32,
    pub caster_count: u32,
    pub caster_instances: u64,
    /// The static query's draws its map draws (the placement's counts, or 0 where
    /// skipped; 0 in a frame without static content).
    pub static_count: u32,
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
    /// Lighting's view rotation and tile counts (`GpuLocalLights`).
    local: wgpu::Buffer,
    /// The lights in view space and the light tiles.
    lights: LightBuffers,
    /// This frame's lights on the tiled path (the tiles' indices point into it), in the
    /// light buffer's order.
    tiled_lights: Vec<deferred::DeferredLight>,
    /// The per-frame uploads (framealloc's pool over one upload buffer).
    uploads: Uploads,
    /// The last frame's camera rotation (camera-relative world to view).
    view_rotation: glam::Mat4,
    /// This frame's shadow views' caster culling.
    casters: crate::shadows::CasterCulls,
    /// This frame's scene origin minus camera position (metres).
    origin_offset: glam::Vec3,
    /// Submissions of frames not waited for, oldest first.
    in_flight: std::collections::VecDeque<wgpu::SubmissionIndex>,
    /// This frame's stencil volume draws.
    volume_draws: Vec<passes::light_volumes::VolumeDraw>,
    /// This frame's spot-map slots of the lights on the volume path (drawn or not).
    volume_map_slots: Vec<u32>,
    /// This frame's lights on the volume path (`GpuLightVolume` order).
    volume_rows: Vec<deferred::DeferredLight>,
    /// KZ2's conditional rendering emulated: buffers and this frame's plan.
    conditional: Option<passes::conditional::ConditionalBuffers>,
    /// The sun's cascades of the last frame (f64), with shadows on.
    cascades: Option<deferred::cascades::StableCascades>,
    timer: GpuTimer,
    frame_index: u32,
    previous: Option<(u64, PreviousCamera)>,
    /// The scene and the camera of the static view the depth target was last rendered
    /// for (`None` after a frame without a static query):
    /// [`StaticOcclusion::PreviousFrame`]'s HiZ, for frames of the same scene.
    depth_camera: Option<(u64, staticscene::Camera)>,
    /// Per sun slice: whether this frame's static query placed the slice's own static
    /// casters (its shadow view).
    static_slices: Vec<bool>,
    /// The last bake's static shadow view, until a frame's statistics report it.
    bake_stats: Option<StaticShadowStats>,
    /// FC5's water ([`Renderer::set_water`]).
    water: Option<passes::water::WaterState>,
}

/// A frame's static query as recorded: the prepared view, whether its second pass
/// (two-pass occlusion) is still to record after the first geometry pass, and the shadow
/// views of the sun slices (slice, texels per side, view).
struct StaticFrame {
    view: PreparedView,
    two_pass: bool,
    shadows: Vec<(u32, u32, PreparedView)>,
}

/// Labels of the static shadow views' passes (timed together, all views summed).
const STATIC_SHADOW_QUERY: &str = "static shadow query";
const STATIC_SHADOW_PLACEMENT: &str = "static shadow placement";

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
                local,
                lights,
                tiled_lights: Vec::new(),
                uploads,
                in_flight: Default::default(),
                view_rotation: glam::Mat4::IDENTITY,
                casters: Default::default(),
                origin_offset: glam::Vec3::ZERO,
                volume_draws: Vec::new(),
                volume_map_slots: Vec::new(),
                volume_rows: Vec::new(),
                conditional,
                cascades: None,
                timer,
                frame_index: 0,
                previous: None,
                depth_camera: None,
                static_slices: Vec::new(),
                bake_stats: None,
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
            self.static_slices.clear();
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
                        volumes: &self.volume_draws,
                        casters: &self.casters,
                        static_slices: &self.static_slices,
                        conditional: self.conditional.as_ref(),
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
        self.depth_camera = match (&view, statics.as_deref()) {
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

    /// The scene's static buffers, or the error for a scene without static setups.
    fn static_buffers(scene: &PreparedScene) -> Result<&StaticBuffers> {
        scene.statics.as_ref().ok_or_else(|| {
            Error::Scene(crate::error::SceneError::StaticSetup {
                setup: 0,
                problem: "the prepared scene has none; render_static draws static setups".into(),
            })
        })
    }

    /// Records the static query of `v` (with [`StaticOcclusion::PreviousFrame`], the HiZ
    /// of the depth target first; with [`StaticOcclusion::TwoPass`], its first pass) and
    /// the placement of its output into `scene`'s reserved slots and draw lists.
    fn record_static(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        scene: &PreparedScene,
        v: &mut StaticView<'_>,
        sun_shadows: bool,
        frame: &FrameInput,
    ) -> Result<StaticFrame> {
        let b = Self::static_buffers(scene)?;
        let size = (self.config.width, self.config.height);
        let mut first = v.view;
        let mut second = None;
        let depth_hiz = match v.occlusion {
            StaticOcclusion::Given => false,
            StaticOcclusion::PreviousFrame => {
                first.occlusion_pass = staticscene::OcclusionPass::Single;
                // Another scene's depth occludes nothing of this one.
                first.occlusion_camera = self
                    .depth_camera
                    .filter(|(id, _)| *id == scene.id)
                    .map(|(_, c)| c);
                first.occlusion_camera.is_some()
            }
            StaticOcclusion::TwoPass => {
                first.occlusion_pass = staticscene::OcclusionPass::First;
                first.occlusion_camera = None;
                let mut s = v.view;
                s.occlusion_pass = staticscene::OcclusionPass::Second;
                s.occlusion_camera = Some(v.view.camera);
                second = Some(staticscene::QueryParams::new(&s)?);
                true
            }
        };
        if depth_hiz {
            if !v.view.camera.reversed_depth {
                return Err(Error::StaticScene(staticscene::Error::Config {
                    what: "a HiZ of the depth target needs a reversed-depth camera (the renderer's depth is reversed Z)",
                }));
            }
            // Before the query's bind groups: this may grow the HiZ buffer.
            v.query
                .prepare_depth_hiz(&self.device, &self.queue, size, true)?;
        }
        let params = staticscene::QueryParams::new(&first)?;
        let view = v.query.prepare_view(
            &self.device,
            &mut self.uploads,
            v.scene,
            &params,
            second.as_ref(),
            &v.options,
        )?;
        if depth_hiz && second.is_none() {
            self.record_hiz(encoder, v.query)?;
        }
        let offset = Self::query_offset(scene, &params);
        self.uploads
            .write(&b.params, 0, bytemuck::bytes_of(&b.params(offset)));
        self.record_query_and_place(encoder, scene, v.query, &view, false)?;
        let shadows = if sun_shadows {
            self.record_static_shadows(encoder, scene, v, frame)?
        } else {
            Vec::new()
        };
        Ok(StaticFrame {
            view,
            two_pass: second.is_some(),
            shadows,
        })
    }

    /// The static query's shadow view of each sun slice this frame re-renders (KZ2's
    /// shadow query with size threshold, HZD's orthographic sun query): the slice's
    /// volume seen from the sun, LODs from the camera view's LOD point, casters below
    /// [`ShadowConfig::static_size_threshold`](crate::ShadowConfig) of the slice's texels
    /// dropped; each placed into the slice's own rows and draw lists, which its shadow
    /// pass draws instead of the camera's. Recorded after the camera view's placement
    /// (the views share nothing it reads), one view's query and placement after the
    /// other's (they share the query's shadow outputs).
    fn record_static_shadows(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        scene: &PreparedScene,
        v: &mut StaticView<'_>,
        frame: &FrameInput,
    ) -> Result<Vec<(u32, u32, PreparedView)>> {
        let maps = &self.targets.shadows;
        let (Some(config), Some(cascades)) = (maps.config, &self.cascades) else {
            return Ok(Vec::new());
        };
        let to_sun = frame.lighting.sun_direction.as_dvec3();
        let mut slices = Vec::new();
        let mut params = Vec::new();
        for (k, c) in cascades.cascades().iter().enumerate() {
            if k >= scene.static_shadows.len() || !maps.dirty.get(k).copied().unwrap_or(true) {
                continue;
            }
            let texels = config.slice_resolution(k);
            let camera = crate::shadows::sun_query_camera(c.world_to_clip, c.center, to_sun);
            let view = crate::shadows::sun_query_view(
                camera,
                texels,
                v.view.lod_position,
                v.view.lod_scale,
                config.static_size_threshold,
            );
            params.push(staticscene::QueryParams::new(&view)?);
            slices.push((k as u32, texels));
        }
        if params.is_empty() {
            return Ok(Vec::new());
        }
        let views = v.query.prepare_shadow_views(
            &self.device,
            &mut self.uploads,
            v.scene,
            &params,
            &v.options,
        )?;
        self.static_slices = vec![false; cascades.cascades().len()];
        let mut out = Vec::with_capacity(views.len());
        for ((view, p), (k, texels)) in views.into_iter().zip(&params).zip(slices) {
            let set = &scene.static_shadows[k as usize];
            let offset = Self::query_offset(scene, p);
            self.uploads.write(
                &set.buffers.params,
                0,
                bytemuck::bytes_of(&set.buffers.params(offset)),
            );
            Self::record_view_and_place(
                &self.device,
                &self.pipelines,
                &mut self.timer,
                encoder,
                v.query,
                &view,
                (&set.buffers, &set.instances),
                (STATIC_SHADOW_QUERY, STATIC_SHADOW_PLACEMENT),
            )?;
            self.static_slices[k as usize] = true;
            out.push((k, texels, view));
        }
        Ok(out)
    }

    /// The query's floating origin minus the scene's origin (whole metres both: exact in
    /// f64, and in f32 below 2^24 m).
    fn query_offset(scene: &PreparedScene, params: &staticscene::QueryParams) -> glam::Vec3 {
        let o = params.origin;
        let origin = glam::DVec3::new(f64::from(o[0]), f64::from(o[1]), f64::from(o[2]));
        (origin - scene.summary.origin.as_dvec3()).as_vec3()
    }

    /// Records a prepared shadow view's query and its placement into `buffers` and their
    /// rows, timed under `labels` (query, placement).
    #[expect(
        clippy::too_many_arguments,
        reason = "the renderer's parts borrowed apart, beside the encoder"
    )]
    fn record_view_and_place(
        device: &wgpu::Device,
        pipelines: &Pipelines,
        timer: &mut GpuTimer,
        encoder: &mut wgpu::CommandEncoder,
        query: &StaticQuery,
        view: &PreparedView,
        (buffers, rows): (&StaticBuffers, &wgpu::Buffer),
        (query_label, place_label): (&'static str, &'static str),
    ) -> Result<()> {
        {
            let mut pass = timer.begin_compute(encoder, query_label);
            query.record_view(&mut pass, view, false);
        }
        let group =
            pipelines
                .static_place
                .group(device, buffers, rows, &query.view_outputs(view))?;
        pipelines
            .static_place
            .record_labelled(encoder, buffers, &group, timer, false, place_label);
        Ok(())
    }

    /// Two-pass occlusion after the first geometry pass: the HiZ of its depth, the query's
    /// second pass against it, and the placement of what it found (late draw lists).
    fn record_static_late(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        scene: &PreparedScene,
        v: &mut StaticView<'_>,
        view: &PreparedView,
    ) -> Result<()> {
        self.record_hiz(encoder, v.query)?;
        self.record_query_and_place(encoder, scene, v.query, view, true)
    }

    /// Records the HiZ of the depth target (laid out by `prepare_depth_hiz` first).
    fn record_hiz(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        query: &StaticQuery,
    ) -> Result<()> {
        query.record_depth_hiz(
            &self.device,
            encoder,
            &self.targets.depth_view,
            &mut self.timer,
            "hiz build",
        )
    }

    /// Records one pass of the static query (`second`: two-pass occlusion's second) and the
    /// placement of its output into `scene`'s reserved slots and draw lists.
    fn record_query_and_place(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        scene: &PreparedScene,
        query: &StaticQuery,
        view: &PreparedView,
        second: bool,
    ) -> Result<()> {
        let b = Self::static_buffers(scene)?;
        let label = if second {
            "static query (second pass)"
        } else {
            "static query"
        };
        {
            let mut pass = self.timer.begin_compute(encoder, label);
            query.record_view(&mut pass, view, second);
        }
        let group = self.pipelines.static_place.group(
            &self.device,
            b,
            &scene.instances,
            &query.outputs(second),
        )?;
        self.pipelines
            .static_place
            .record(encoder, b, &group, &mut self.timer, second);
        Ok(())
    }

    /// Reads the query's and the placement's counters after a frame with a static query.
    fn read_static_stats(
        &mut self,
        scene: &PreparedScene,
        v: &StaticView<'_>,
        frame: StaticFrame,
    ) -> Result<StaticFrameStats> {
        let view = frame.view;
        let shadow_slices = frame
            .shadows
            .iter()
            .map(|(k, texels, sv)| {
                let set = &scene.static_shadows[*k as usize];
                self.read_shadow_stats(scene, v.query, sv, &set.buffers, (*k, *texels))
            })
            .collect::<Result<Vec<_>>>()?;
        let counters = v.query.read_counters(&self.device, &self.queue, false)?;
        let second = if frame.two_pass {
            Some(v.query.read_counters(&self.device, &self.queue, true)?)
        } else {
            None
        };
        let Some(b) = &scene.statics else {
            return Ok(StaticFrameStats::default());
        };
        let words = self.read_static_counters(b)?;
        let w = |i: u32| words[i as usize];
        Ok(StaticFrameStats {
            query: counters.stats(&view.plan.stats),
            second_pass: second.map(|c| c.stats(&view.plan.stats)),
            threads: view.threads,
            batches: counters.batches + second.map_or(0, |c| c.batches),
            instances: counters.instances + second.map_or(0, |c| c.instances),
            placed: placed_instances(scene, b, &words),
            over_capacity: w(STATIC_COUNTER_OVER_CAPACITY),
            bad_batches: w(STATIC_COUNTER_BAD_BATCHES),
            draws: [w(STATIC_COUNTER_DRAWS), w(STATIC_COUNTER_DRAWS + 1)],
            skipped_tiles: view.plan.skipped_tiles,
            shadow_slices,
            baked: self.bake_stats.take(),
        })
    }

    /// The static placement's counters (placed per setup after the fixed ones).
    fn read_static_counters(&self, b: &StaticBuffers) -> Result<Vec<u32>> {
        Ok(bytemuck::pod_collect_to_vec(&read_buffer(
            &self.device,
            &self.queue,
            &b.counters,
            0,
            4 * u64::from(STATIC_COUNTER_PLACED + b.setup_count),
        )?))
    }

    /// Reads what a static shadow view's query and placement did (after its submission).
    fn read_shadow_stats(
        &self,
        scene: &PreparedScene,
        query: &StaticQuery,
        view: &PreparedView,
        b: &StaticBuffers,
        (slice, texels): (u32, u32),
    ) -> Result<StaticShadowStats> {
        let counters = query.read_view_counters(&self.device, &self.queue, view)?;
        let words = self.read_static_counters(b)?;
        let w = |i: u32| words[i as usize];
        Ok(StaticShadowStats {
            slice,
            texels,
            query: counters.stats(&view.plan.stats),
            threads: view.threads,
            instances: counters.instances,
            batches: counters.batches,
            placed: placed_instances(scene, b, &words),
            over_capacity: w(STATIC_COUNTER_OVER_CAPACITY),
            bad_batches: w(STATIC_COUNTER_BAD_BATCHES),
            draws: [w(STATIC_COUNTER_DRAWS), w(STATIC_COUNTER_DRAWS + 1)],
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

    /// What the last frame's uploads took from the upload pool: bytes, blocks, the CPU
    /// time spent in `framealloc`, the pool's free blocks and the frames in flight.
    pub fn upload_stats(&self) -> &UploadStats {
        self.uploads.stats()
    }

    /// Holds the GPU's completion notices back from the upload pool (`true`), as a GPU
    /// that is slow to finish would: no block of a held frame is handed out again. `false`
    /// delivers the held notices and resumes. For tests of the allocator in the frame.
    #[doc(hidden)]
    pub fn hold_upload_completions(&self, hold: bool) {
        self.uploads.hold_completions(hold);
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

    /// Renders `path` for at least [`WARM_UP`] of wall time (at least one frame) to bring the
    /// GPU's clocks up, then `frames` more, and returns the mean timings of those `frames`.
    /// Without the warm-up, a GPU that idled while the CPU worked (a read-back, the CPU
    /// twin) measures its first frames at idle clocks: on the H100 the SM clock falls to
    /// 345 MHz within ~0.5 s of idling and the next frames ran up to 2x slower.
    ///
    /// # Errors
    /// `frames` is 0, or as [`Renderer::render`].
    pub fn render_frames(
        &mut self,
        scene: &PreparedScene,
        frame: &FrameInput,
        path: RenderPath,
        frames: u32,
    ) -> Result<FrameOutput> {
        self.measure(frames, |r| r.render(scene, frame, path))
    }

    /// [`Renderer::render_static`] measured as [`Renderer::render_frames`] measures
    /// [`Renderer::render`]; the static statistics are the last frame's.
    ///
    /// # Errors
    /// `frames` is 0, or as [`Renderer::render_static`].
    pub fn render_static_frames(
        &mut self,
        scene: &PreparedScene,
        frame: &FrameInput,
        path: RenderPath,
        statics: &mut StaticView<'_>,
        frames: u32,
    ) -> Result<FrameOutput> {
        self.measure(frames, |r| r.render_static(scene, frame, path, statics))
    }

    /// [`Renderer::render_static_frames`] with a moving view: frame `i` (counting the
    /// warm-up frames from 0) is `sequence(i)`'s frame input and static view, so occlusion
    /// and LOD fade see motion. The static statistics are the last frame's.
    ///
    /// # Errors
    /// `frames` is 0, or as [`Renderer::render_static`].
    pub fn render_static_sequence(
        &mut self,
        scene: &PreparedScene,
        path: RenderPath,
        statics: &mut StaticView<'_>,
        frames: u32,
        mut sequence: impl FnMut(u32) -> (FrameInput, staticscene::ViewDesc),
    ) -> Result<FrameOutput> {
        let mut i = 0;
        self.measure(frames, |r| {
            let (frame, view) = sequence(i);
            i += 1;
            statics.view = view;
            r.render_static(scene, &frame, path, statics)
        })
    }

    /// Renders for [`WARM_UP`], then `frames` more (at least one), and averages those.
    fn measure(
        &mut self,
        frames: u32,
        mut render: impl FnMut(&mut Self) -> Result<FrameOutput>,
    ) -> Result<FrameOutput> {
        if frames == 0 {
            return Err(Error::Length {
                what: "frames to measure",
                got: 0,
                expected: 1,
            });
        }
        let start = Instant::now();
        loop {
            render(self)?;
            if start.elapsed() >= WARM_UP {
                break;
            }
        }
        let mut all = Vec::new();
        for _ in 0..frames {
            all.push(render(self)?);
        }
        let n = all.len() as f64;
        let mut gpu: Vec<Timing> = Vec::new();
        for f in &all {
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
        let wall_ms = all.iter().map(|f| f.wall_ms).sum::<f64>() / n;
        Ok(FrameOutput {
            gpu,
            wall_ms,
            statics: all.last().and_then(|f| f.statics.clone()),
            untimed_passes: all.iter().map(|f| f.untimed_passes).max().unwrap_or(0),
        })
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

    /// Renders the laydown alone and returns the vis buffer (row-major words) and the depth
    /// buffer: what the classification passes and their CPU twins read.
    ///
    /// # Errors
    /// As [`Renderer::render`].
    pub fn render_laydown(
        &mut self,
        scene: &PreparedScene,
        frame: &FrameInput,
    ) -> Result<(Vec<u32>, Vec<f32>)> {
        self.run(scene, frame, "laydown", Recording::Laydown, None, true)?;
        let read =
            |t: &wgpu::Texture, aspect| read_texture(&self.device, &self.queue, t, aspect, 4);
        let vis = read(&self.targets.vis, wgpu::TextureAspect::All)?;
        let depth = read(&self.targets.depth, wgpu::TextureAspect::DepthOnly)?;
        Ok((
            bytemuck::pod_collect_to_vec(&vis),
            bytemuck::pod_collect_to_vec(&depth),
        ))
    }

    /// Reads the G-buffer of the last frame back, one [`deferred::Surface`] per pixel
    /// (row-major; world-space normals, turned back from view space under the KZ2 preset;
    /// motion in pixels, `+y` down): what lighting read.
    ///
    /// # Errors
    /// A device or mapping error.
    pub fn read_gbuffer(&self) -> Result<Vec<deferred::Surface>> {
        let targets: Vec<(Vec<u8>, usize)> = self
            .targets
            .gbuffer
            .iter()
            .map(|t| {
                let texel = t.format().block_copy_size(None).unwrap_or(4) as usize;
                let bytes = read_texture(
                    &self.device,
                    &self.queue,
                    t,
                    wgpu::TextureAspect::All,
                    texel as u32,
                )?;
                Ok((bytes, texel))
            })
            .collect::<Result<_>>()?;
        let n = (self.config.width * self.config.height) as usize;
        let mut texel = Vec::with_capacity(20);
        // The KZ2 preset's view-space normals, back to world directions.
        let to_world = self.view_rotation.transpose();
        (0..n)
            .map(|i| {
                texel.clear();
                for (bytes, size) in &targets {
                    texel.extend_from_slice(&bytes[i * size..(i + 1) * size]);
                }
                let layout = self.config.gbuffer;
                let mut s = layout.unpack_bytes(&texel).ok_or_else(|| {
                    Error::Map(format!(
                        "a G-buffer texel read back as {} bytes, not the layout's",
                        texel.len()
                    ))
                })?;
                if layout.normal_space() == deferred::NormalSpace::View {
                    s.normal = to_world.transform_vector3(s.normal);
                }
                Ok(s)
            })
            .collect()
    }

    /// Reads the depth buffer of the last single-sampled frame back (row-major, reversed
    /// Z: 1 at the near plane, 0 for the sky): what lighting read and what a HiZ for the
    /// next frame's occlusion is built from.
    ///
    /// # Errors
    /// A device or mapping error.
    pub fn read_depth(&self) -> Result<Vec<f32>> {
        let depth = read_texture(
            &self.device,
            &self.queue,
            &self.targets.depth_float,
            wgpu::TextureAspect::All,
            4,
        )?;
        Ok(bytemuck::pod_collect_to_vec(&depth))
    }

    /// What the last compute laydown of `scene` drew: its triangles and those the hardware
    /// part drew. `None` where the renderer or the scene has no compute laydown.
    ///
    /// # Errors
    /// A scene prepared by another renderer, or a device or mapping error.
    pub fn read_laydown_stats(&self, scene: &PreparedScene) -> Result<Option<crate::LaydownStats>> {
        self.check_scene(scene)?;
        let Some(g) = &scene.compute_laydown else {
            return Ok(None);
        };
        let words = read_buffer(&self.device, &self.queue, &g.list, 0, 4)?;
        let vertex_count = u32::from_le_bytes([words[0], words[1], words[2], words[3]]);
        let words = read_buffer(&self.device, &self.queue, &g.large, 12, 4)?;
        let large = u32::from_le_bytes([words[0], words[1], words[2], words[3]]);
        Ok(Some(passes::compute_laydown::stats(
            g.items,
            vertex_count,
            large,
        )))
    }

    /// Reads the static placement's debug words of the last frame with a static query of
    /// `scene` (what [`debug::static_lod_fade`](crate::debug::static_lod_fade) and
    /// [`debug::static_two_pass`](crate::debug::static_two_pass) colour the vis buffer by).
    ///
    /// # Errors
    /// A scene without static setups, a scene prepared by another renderer, or a device
    /// or mapping error.
    pub fn read_static_debug(&self, scene: &PreparedScene) -> Result<crate::StaticDebug> {
        self.check_scene(scene)?;
        let b = Self::static_buffers(scene)?;
        let words = bytemuck::pod_collect_to_vec(&read_buffer(
            &self.device,
            &self.queue,
            &b.debug,
            0,
            b.debug.size(),
        )?);
        let mut ranges: Vec<_> = scene
            .static_table
            .iter()
            .enumerate()
            .map(|(i, s)| (i as u32, *s))
            .collect();
        ranges.sort_by_key(|(_, s)| s.first_id);
        Ok(crate::StaticDebug {
            ranges,
            words,
            base: b.debug_base,
        })
    }

    /// How the last frame's local lights were split between the tiles and the stencil
    /// volumes.
    pub fn light_path_counts(&self) -> LightPathCounts {
        LightPathCounts {
            tiled: self.tiled_lights.len() as u32,
            volumes: self.volume_draws.len() as u32,
            volumes_from_inside: self.volume_draws.iter().filter(|d| d.inside).count() as u32,
            spot_shadow_maps: self.targets.spot_shadows.active,
            volumes_tested: self
                .conditional
                .as_ref()
                .map_or(0, |c| c.plan.tests.len() as u32),
            spot_shadow_maps_skipped: self.conditional.as_ref().map_or(0, |c| {
                c.plan
                    .maps
                    .iter()
                    .filter(|m| **m == passes::conditional::MapDraw::Skipped)
                    .count() as u32
            }),
        }
    }

    /// Reads back what the last frame's GPU decided for each light tested for KZ2's
    /// conditional rendering (empty with the emulation off or no light tested): its query's
    /// count and the indirect arguments of its volume and its map's casters.
    ///
    /// # Errors
    /// A device or mapping error.
    #[doc(hidden)]
    pub fn read_conditional_volumes(&self) -> Result<Vec<ConditionalLight>> {
        use passes::conditional::{COUNT_WORDS, DRAW_WORDS, MapDraw};
        let Some(c) = &self.conditional else {
            return Ok(Vec::new());
        };
        let n = c.plan.tests.len() as u64;
        if n == 0 {
            return Ok(Vec::new());
        }
        let words = |buffer: &wgpu::Buffer, bytes: u64| -> Result<Vec<u32>> {
            let b = read_buffer(&self.device, &self.queue, buffer, 0, bytes)?;
            Ok(bytemuck::pod_collect_to_vec(&b))
        };
        let samples = words(&c.resolved, n * 8)?;
        let volumes = words(&c.volume_args, n * 4 * u64::from(DRAW_WORDS))?;
        let counts = words(&c.counts, n * 4 * u64::from(COUNT_WORDS))?;
        let casters = if c.casters > 0 {
            words(
                &c.caster_args,
                u64::from(c.casters) * 4 * u64::from(DRAW_WORDS),
            )?
        } else {
            Vec::new()
        };
        let (w, cw) = (DRAW_WORDS as usize, COUNT_WORDS as usize);
        Ok((0..n as usize)
            .map(|t| {
                let (first, rows) = c
                    .plan
                    .maps
                    .iter()
                    .find_map(|m| match *m {
                        MapDraw::Indirect {
                            test,
                            first,
                            opaque,
                            alpha,
                        } if test as usize == t => {
                            Some((first as usize, (opaque + alpha) as usize))
                        }
                        _ => None,
                    })
                    .unwrap_or((0, 0));
                ConditionalLight {
                    light: c.plan.lights.get(t).copied().unwrap_or_default(),
                    samples: u64::from(samples[2 * t]) | u64::from(samples[2 * t + 1]) << 32,
                    volume_instances: volumes[t * w + 1],
                    caster_rows: rows as u32,
                    caster_count: counts[cw * t] + counts[cw * t + 1],
                    static_count: counts[cw * t + 2] + counts[cw * t + 3],
                    caster_instances: (first..first + rows)
                        .filter_map(|r| casters.get(r * w + 1))
                        .map(|&i| u64::from(i))
                        .sum(),
                }
            })
            .collect())
    }

    /// Reads back the last frame's light tiles: each 16x16 tile's depth range, light count
    /// and list, and what the culling pass counted.
    ///
    /// # Errors
    /// A device or mapping error.
    pub fn read_light_tiles(&self) -> Result<LightTiles> {
        let b = &self.lights;
        let n = u64::from(b.tiles[0]) * u64::from(b.tiles[1]);
        let read = |buffer: &wgpu::Buffer, bytes: u64| {
            read_buffer(&self.device, &self.queue, buffer, 0, bytes)
        };
        let depths = read(&b.tile_depths, n * 8)?;
        let counts = read(&b.counts, n * 4)?;
        let indices = read(
            &b.indices,
            n * u64::from(deferred::lights::MAX_LIGHTS_PER_TILE) * 4,
        )?;
        let counters = read(
            &b.counters,
            size_of::<deferred::pass::LightCullCounters>() as u64,
        )?;
        let counters: deferred::pass::LightCullCounters = bytemuck::pod_read_unaligned(&counters);
        Ok(LightTiles {
            tiles: b.tiles,
            depths: bytemuck::pod_collect_to_vec(&depths),
            counts: bytemuck::pod_collect_to_vec(&counts),
            indices: bytemuck::pod_collect_to_vec(&indices),
            lights: self.tiled_lights.clone(),
            stats: counters.stats(),
        })
    }

    /// Reads back the edge pixels of the last MSAA baseline frame under
    /// [`MsaaLighting::Kz2`]: row-major pixel indices, ascending (the pixels whose samples
    /// hold more than one surface, lit per sample). Empty without MSAA or after a frame
    /// that lit every sample.
    ///
    /// # Errors
    /// A device or mapping error.
    pub fn read_msaa_edges(&self) -> Result<Vec<u32>> {
        let Some(t) = &self.targets.msaa else {
            return Ok(Vec::new());
        };
        let header_bytes = crate::resources::targets::MSAA_EDGES_HEADER;
        let header = read_buffer(&self.device, &self.queue, &t.edges, 0, header_bytes)?;
        let pixels = u64::from(self.targets.width) * u64::from(self.targets.height);
        let count = u64::from(bytemuck::pod_read_unaligned::<[u32; 4]>(&header)[3]).min(pixels);
        if count == 0 {
            return Ok(Vec::new());
        }
        let words = read_buffer(&self.device, &self.queue, &t.edges, header_bytes, count * 4)?;
        let mut edges: Vec<u32> = bytemuck::pod_collect_to_vec::<u8, u32>(&words)
            .into_iter()
            .map(|w| (w >> 16) * self.targets.width + (w & 0xffff))
            .collect();
        edges.sort_unstable();
        Ok(edges)
    }

    /// Reads the vis buffer of the last frame back (row-major words, `visbuf`'s layout;
    /// `VIS_NONE` where nothing was drawn).
    ///
    /// # Errors
    /// A device or mapping error.
    pub fn read_vis(&self) -> Result<Vec<u32>> {
        let vis = read_texture(
            &self.device,
            &self.queue,
            &self.targets.vis,
            wgpu::TextureAspect::All,
            4,
        )?;
        Ok(bytemuck::pod_collect_to_vec(&vis))
    }

    /// Reads back what the last deferred frame's classification wrote.
    ///
    /// # Errors
    /// A scene prepared by another renderer, or a device error.
    pub fn read_classification(&self, scene: &PreparedScene) -> Result<GpuClassification> {
        self.check_scene(scene)?;
        GpuClassification::read(
            &self.device,
            &self.queue,
            &scene.classification,
            &self.targets.vis_words,
        )
    }

    /// What HFW's vertex side wrote in the last deferred frame of `scene` (vertex wave
    /// commands, dispatches, the ring), read back; `None` without
    /// [`RendererConfig::vertex_ring`].
    ///
    /// # Errors
    /// A scene of another renderer, or a device error.
    pub fn read_vertex_ring(
        &self,
        scene: &PreparedScene,
    ) -> Result<Option<crate::VertexRingReadback>> {
        self.check_scene(scene)?;
        scene
            .vertex_ring
            .as_ref()
            .map(|b| crate::VertexRingReadback::read(&self.device, &self.queue, b))
            .transpose()
    }

    /// Uploads `words` (row-major, `width * height`, any values: bad IDs are the
    /// classification's to count) as the vis buffer, runs the three classification phases
    /// on them alone, and reads the result back. How tests feed random vis buffers.
    ///
    /// # Errors
    /// `words` is not `width * height` long ([`Error::Length`]), or a device error.
    pub fn classify_words(
        &mut self,
        scene: &PreparedScene,
        words: &[u32],
    ) -> Result<GpuClassification> {
        let n = (self.config.width * self.config.height) as usize;
        if words.len() != n {
            return Err(Error::Length {
                what: "vis words (width * height of the renderer)",
                got: words.len(),
                expected: n,
            });
        }
        self.check_scene(scene)?;
        let device = self.device.clone();
        scoped(&device, || {
            self.queue
                .write_buffer(&self.targets.vis_words, 0, bytemuck::cast_slice(words));
            let mut encoder = device.create_command_encoder(&Default::default());
            let f = FrameContext {
                scene,
                targets: &self.targets,
                groups: &self.groups,
                static_query: false,
                volumes: &[],
                casters: &self.casters,
                static_slices: &[],
                conditional: None,
                origin_offset: self.origin_offset,
                msaa: false,
                compute_laydown: false,
                water: None,
            };
            self.pipelines
                .record(Recording::Classification, &mut encoder, &f, &mut self.timer);
            self.timer.resolve(&mut encoder);
            self.queue.submit([encoder.finish()]);
            wait_idle(&device)
        })?;
        let _ = self.timer.read(&self.device, &self.queue)?;
        self.read_classification(scene)
    }

    /// Overwrites `scene`'s primitive-ID payloads (one word per vertex of its encoded
    /// geometry, any values) until it is prepared again: how tests feed corrupt primitive
    /// IDs to the passes that read them (the laydown's payload paths, the pixel-pull
    /// path), which must never read out of bounds.
    ///
    /// # Errors
    /// `words` is not one per vertex ([`Error::Length`]), or a scene prepared by another
    /// renderer.
    #[doc(hidden)]
    pub fn write_payloads(&self, scene: &PreparedScene, words: &[u32]) -> Result<()> {
        self.check_scene(scene)?;
        let buffer = scene.payloads();
        let expected = (buffer.size() / 4) as usize;
        if words.len() != expected {
            return Err(Error::Length {
                what: "payloads (one per vertex)",
                got: words.len(),
                expected,
            });
        }
        self.queue
            .write_buffer(buffer, 0, bytemuck::cast_slice(words));
        Ok(())
    }

    /// The talk's counters for a read-back classification: runs `tiling`'s CPU twin on the
    /// same vis words, compares every output (returning the first difference, if any), and
    /// measures depth-equal waves and chunk-culled vertices with `tiling::measure`.
    ///
    /// # Errors
    /// A read-back that the CPU twin rejects (a wrong-sized vis buffer).
    pub fn classification_statistics(
        &self,
        scene: &PreparedScene,
        gpu: &GpuClassification,
    ) -> Result<(ClassificationStats, Option<String>)> {
        classification_statistics(scene, gpu)
    }

    /// KZ2's pre-rendered sun shadow: the baked map of `scene`'s batches, and in a frame
    /// with a static query of its static casters, for this frame's sun, rendered (in a
    /// submission of its own) when the scene, the sun direction or the set of active
    /// static tiles changed, its matrix put into `uniforms`. Off
    /// (`RendererConfig::baked_sun`), or for a scene with nothing to cast, the matrix stays
    /// zero: no baked shadow.
    ///
    /// The static casters come from the static query's shadow view over the bake's
    /// orthographic box (the size threshold in the bake's texels), placed into slice 0's
    /// rows and lists before the frame's own work reuses them. Not every static instance
    /// drawn: the reserved slots hold a frame's visible instances (each setup's capacity),
    /// not the whole world, and every LOD level of every instance would overlap; the query
    /// picks one LOD per instance (from the camera's LOD point at bake time: the map keeps
    /// those LODs until it is re-baked, a texel-sized difference at its resolution) and
    /// drops what is too small for its texels.
    fn bake_sun(
        &mut self,
        scene: &PreparedScene,
        frame: &FrameInput,
        uniforms: &mut FrameUniforms,
        mut statics: Option<&mut StaticView<'_>>,
    ) -> Result<()> {
        if !self.config.baked_sun {
            return Ok(());
        }
        // The static casters' bounds (origin-relative) and which tiles they came from.
        let origin = scene.summary.origin.as_dvec3();
        let static_part = statics
            .as_deref()
            .filter(|_| !scene.static_shadows.is_empty())
            .map(|v| {
                let mut bounds: Option<(glam::Vec3, glam::Vec3)> = None;
                let mut ids = std::collections::hash_map::DefaultHasher::new();
                for t in v.scene.tiles() {
                    std::hash::Hash::hash(&t.id().0, &mut ids);
                    let cull = t.cull();
                    if cull.filter & staticscene::FILTER_SUN_SHADOW == 0
                        || !(cull.bounds.min.cmple(cull.bounds.max).all())
                    {
                        continue;
                    }
                    let anchor = t.anchor().as_dvec3() - origin;
                    let lo = (anchor + cull.bounds.min.as_dvec3()).as_vec3();
                    let hi = (anchor + cull.bounds.max.as_dvec3()).as_vec3();
                    bounds = Some(match bounds {
                        Some((a, b)) => (a.min(lo), b.max(hi)),
                        None => (lo, hi),
                    });
                }
                (bounds, std::hash::Hasher::finish(&ids))
            });
        let static_bounds = static_part.and_then(|(b, _)| b);
        let bounds = match (scene.bounds, static_bounds) {
            (Some((a, b)), Some((c, d))) => (a.min(c), b.max(d)),
            (Some(b), None) | (None, Some(b)) => b,
            (None, None) => return Ok(()),
        };
        let sun = frame.lighting.sun_direction.normalize_or(glam::Vec3::Y);
        let matrix = crate::shadows::baked_sun_matrix(bounds, sun);
        uniforms.baked_sun = matrix.to_cols_array_2d();
        let key = (
            scene.id,
            sun.to_array().map(f32::to_bits),
            static_part.map(|(_, tiles)| tiles),
        );
        if self.targets.shadows.baked_for == Some(key) {
            return Ok(());
        }
        let mut bake = *uniforms;
        bake.view_proj = matrix.to_cols_array_2d();
        bake.origin_offset = [0.0; 4];
        bake.baked_sun = [[0.0; 4]; 4];
        self.queue.write_buffer(
            &self.targets.shadows.baked_frame,
            0,
            bytemuck::bytes_of(&bake),
        );
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("baked sun map"),
            });
        // The static casters' shadow view: uploads straight to the queue (they land before
        // this submission, which runs before the frame's uploads overwrite set 0).
        let mut placed = None;
        if let (Some(v), Some(set)) = (statics.as_deref_mut(), scene.static_shadows.first())
            && static_part.is_some()
            && let Some(group) = &set.bake_group
        {
            // World to the bake's clip space, f64: the matrix takes origin-relative points.
            let world_to_clip = matrix.as_dmat4() * glam::DMat4::from_translation(-origin);
            let centre = origin + ((bounds.0 + bounds.1) * 0.5).as_dvec3();
            let camera = crate::shadows::sun_query_camera(world_to_clip, centre, sun.as_dvec3());
            let threshold = self
                .config
                .shadows
                .unwrap_or_default()
                .static_size_threshold;
            let view = crate::shadows::sun_query_view(
                camera,
                crate::shadows::BAKED_SUN_RESOLUTION,
                v.view.lod_position,
                v.view.lod_scale,
                threshold,
            );
            let params = staticscene::QueryParams::new(&view)?;
            let mut queue = self.queue.clone();
            let mut views = v.query.prepare_shadow_views(
                &self.device,
                &mut queue,
                v.scene,
                std::slice::from_ref(&params),
                &v.options,
            )?;
            let prepared = views.pop().ok_or(Error::Length {
                what: "static shadow views prepared for the bake",
                got: 0,
                expected: 1,
            })?;
            let offset = Self::query_offset(scene, &params);
            self.queue.write_buffer(
                &set.buffers.params,
                0,
                bytemuck::bytes_of(&set.buffers.params(offset)),
            );
            // Untimed: the bake is its own submission, outside the frame's timings.
            Self::record_view_and_place(
                &self.device,
                &self.pipelines,
                &mut GpuTimer::inert(),
                &mut encoder,
                v.query,
                &prepared,
                (&set.buffers, &set.instances),
                ("baked sun static query", "baked sun static placement"),
            )?;
            placed = Some((prepared, &set.buffers, group));
        }
        self.pipelines.laydown.record_bake(
            &mut encoder,
            scene,
            &self.targets.shadows.baked_view,
            placed.as_ref().map(|(_, b, g)| (*b, *g)),
        );
        self.queue.submit([encoder.finish()]);
        self.targets.shadows.baked_for = Some(key);
        if let (Some((view, b, _)), Some(v)) = (&placed, statics.as_deref()) {
            self.bake_stats = Some(self.read_shadow_stats(
                scene,
                v.query,
                view,
                b,
                (0, crate::shadows::BAKED_SUN_RESOLUTION),
            )?);
        }
        Ok(())
    }

    /// Fits the sun's cascades to this frame's camera and uploads each cascade's frame
    /// uniforms (`uniforms` with the cascade's camera-relative matrix as `view_proj`) and
    /// what lighting reads; with shadows off, a zero cascade count.
    fn upload_shadows(
        &mut self,
        scene_id: u64,
        static_frame: bool,
        frame: &FrameInput,
        uniforms: &FrameUniforms,
    ) -> Result<()> {
        let maps = &mut self.targets.shadows;
        let Some(config) = maps.config else {
            self.uploads.write(
                &maps.sun,
                0,
                bytemuck::bytes_of(&crate::shadows::GpuSunShadow::default()),
            );
            return Ok(());
        };
        let aspect = self.config.width as f32 / self.config.height as f32;
        let cascades = config.fit(&frame.camera, aspect, frame.lighting.sun_direction)?;
        let origin = frame.camera.position.as_dvec3();
        self.casters.slices.clear();
        for (i, c) in cascades.cascades().iter().enumerate() {
            let planes = shadow_view(
                &mut self.uploads,
                &maps.frames,
                i,
                uniforms,
                c.relative_matrix(origin),
            );
            if self.config.cull_shadow_casters {
                self.casters.slices.push(planes);
            }
        }
        self.uploads.write(
            &maps.sun,
            0,
            bytemuck::bytes_of(&crate::shadows::GpuSunShadow::new(
                &cascades, origin, &config,
            )),
        );
        let keys = cascades
            .cascades()
            .iter()
            .map(|c| (scene_id, c.world_to_clip.to_cols_array().map(f64::to_bits)))
            .collect();
        maps.plan(keys, static_frame);
        self.cascades = Some(cascades);
        Ok(())
    }

    /// The sun's cascades fitted to the last frame's camera (world space, f64), with
    /// shadows on: each map's slice, snapped centre, texel size and matrix.
    #[must_use]
    pub fn shadow_cascades(&self) -> Option<&deferred::cascades::StableCascades> {
        self.cascades.as_ref()
    }

    /// Reads the last frame's sun shadow maps back, one `resolution`² depth layer per
    /// cascade (row-major, 0 nearest the sun, 1 where nothing casts); empty with shadows
    /// off.
    ///
    /// # Errors
    /// A device or mapping error.
    pub fn read_shadow_maps(&self) -> Result<Vec<Vec<f32>>> {
        let maps = &self.targets.shadows;
        self.read_depth_layers(&maps.texture, maps.cascades())
    }

    /// Layers `0..layers` of the depth-array `texture`, each row-major.
    fn read_depth_layers(&self, texture: &wgpu::Texture, layers: u32) -> Result<Vec<Vec<f32>>> {
        (0..layers)
            .map(|layer| {
                let bytes = crate::resources::readback::read_texture_layer(
                    &self.device,
                    &self.queue,
                    texture,
                    wgpu::TextureAspect::DepthOnly,
                    4,
                    layer,
                )?;
                Ok(bytemuck::pod_collect_to_vec(&bytes))
            })
            .collect()
    }

    /// Reads the last frame's spot shadow maps back, one `resolution`² depth layer per map
    /// in slot order (0 at the light's near plane, 1 where nothing casts): a test aid.
    ///
    /// # Errors
    /// A device or mapping error.
    #[doc(hidden)]
    pub fn read_spot_shadow_maps(&self) -> Result<Vec<Vec<f32>>> {
        let maps = &self.targets.spot_shadows;
        self.read_depth_layers(&maps.texture, maps.active.min(maps.layers()))
    }

    /// Uploads the frame's local lights in view space and the light passes' uniforms (the
    /// lights move in view space with the camera, so every frame), growing the light
    /// buffers when they are short. Splits the lights between the tiles and the stencil
    /// volumes as [`RendererConfig::light_paths`] says: the tiled ones first in the light
    /// buffer (their count is returned, for the frame uniforms), the volumes' after them.
    fn upload_lights(&mut self, frame: &FrameInput, uniforms: &FrameUniforms) -> Result<u32> {
        use crate::passes::light_volumes::{GpuLightVolume, VolumeDraw};
        use deferred::lights::{LightClassifier, LightPath};
        let (width, height) = (self.config.width, self.config.height);
        let camera = &frame.camera;
        let projection = deferred::Perspective::try_new(
            camera.fov_y,
            width as f32 / height as f32,
            camera.near,
            None,
            deferred::DepthMode::Reversed,
        )
        .map_err(|e| {
            Error::Frame(crate::error::FrameError::OutOfRange {
                field: "camera".into(),
                value: camera.fov_y,
                allowed: if matches!(e, deferred::Error::InvalidParameter { name: "near", .. }) {
                    "a near plane > 0"
                } else {
                    "a field of view in (0, π)"
                },
            })
        })?
        .gpu(glam::Vec2::new(width as f32, height as f32));
        let mut all = local_light_rows(&frame.lighting, camera);
        let classifier = LightClassifier::default();
        self.upload_spot_shadows(&mut all, &projection, uniforms);
        let volume = |l: &deferred::DeferredLight| match self.config.light_paths {
            LightPaths::Tiled | LightPaths::EveryPixel => false,
            LightPaths::Volumes => true,
            // A light the classifier culls stays with the tiles, whose own test decides.
            LightPaths::Classified => classifier.classify(&projection, l).path == LightPath::Volume,
        };
        let (volume_lights, tiled): (Vec<_>, Vec<_>) = all.into_iter().partition(volume);
        let count = tiled.len() as u32;
        let reach = self
            .pipelines
            .light_volumes
            .as_ref()
            .map_or(1.0, |v| v.reach);
        let mut volumes = Vec::with_capacity(volume_lights.len().max(1));
        self.volume_draws.clear();
        self.volume_map_slots.clear();
        for (k, l) in volume_lights.iter().enumerate() {
            let map = (l.flags >> crate::spot_shadows::LIGHT_SHADOW_SLOT_SHIFT).checked_sub(1);
            self.volume_map_slots.extend(map);
            let (c, r) = l.bounding_sphere();
            volumes.push(GpuLightVolume {
                sphere: [c.x, c.y, c.z, r],
                light: count + k as u32,
                pad: [0; 3],
            });
            // View depths of the mesh's bounding sphere. All of it nearer than the near
            // plane (or behind the eye): it lights no visible point, no draw. Reaching the
            // near plane (as it does with the eye inside): its front faces may be clipped,
            // so it is drawn from inside.
            let (nearest, farthest) = (-c.z - r * reach, -c.z + r * reach);
            if farthest < camera.near {
                continue;
            }
            self.volume_draws.push(VolumeDraw {
                volume: k as u32,
                inside: nearest <= camera.near * 1.001,
                map,
                specular: l.has_specular(),
            });
        }
        let mut rows = tiled.clone();
        rows.extend_from_slice(&volume_lights);
        self.volume_rows = volume_lights;
        self.tiled_lights = tiled;
        if rows.is_empty() {
            // A binding holds at least one light; the counts say none are real.
            rows.push(deferred::DeferredLight::default());
        }
        if volumes.is_empty() {
            volumes.push(GpuLightVolume::default());
        }
        if rows.len() > self.lights.capacity {
            self.lights = self
                .lights
                .with_capacity(&self.device, rows.len().next_power_of_two())?;
            self.groups.lighting = self.pipelines.lighting.groups(
                &self.device,
                &self.targets,
                &self.frame,
                &self.local,
                &self.lights,
            )?;
            self.groups.lights =
                self.pipelines
                    .lights
                    .groups(&self.device, &self.targets, &self.lights)?;
            self.groups.light_volumes = self
                .pipelines
                .light_volumes
                .as_ref()
                .map(|v| {
                    v.groups(
                        &self.device,
                        &self.targets,
                        &self.frame,
                        &self.local,
                        &self.lights.lights,
                        &self.lights.volumes,
                    )
                })
                .transpose()?;
            self.refresh_water_groups()?;
        }
        let b = &self.lights;
        self.uploads
            .write(&b.lights, 0, bytemuck::cast_slice(&rows));
        self.uploads
            .write(&b.volumes, 0, bytemuck::cast_slice(&volumes));
        self.uploads.write(
            &b.cull_params,
            0,
            bytemuck::bytes_of(&deferred::pass::LightCullParams::new(projection, count)),
        );
        self.uploads.write(
            &b.tile_params,
            0,
            bytemuck::bytes_of(&GpuTileDepthParams {
                size: [width, height],
                tiles_x: b.tiles[0],
                reversed: 1,
            }),
        );
        self.uploads.write(
            &self.local,
            0,
            bytemuck::bytes_of(&GpuLocalLights {
                view_rotation: camera.view_rotation().to_cols_array_2d(),
                tiles: b.tiles,
                pad: [0; 2],
            }),
        );
        Ok(count)
    }

    /// KZ2's conditional rendering emulated: plans this frame's tests (the volume draws of
    /// lights with a spot map, at most one per map), their maps' caster draws (culled as
    /// the direct draws are) and the maps the CPU skips, and uploads the tests and the
    /// caster rows. Nothing with the emulation off.
    fn plan_conditional(&mut self, scene: &PreparedScene) -> Result<()> {
        use passes::conditional::{
            ConditionalPlan, GpuCasterDraw, GpuConditionalParams, GpuConditionalTest, MAX_TESTS,
            MapDraw,
        };
        let (Some(pass), Some(b)) = (&self.pipelines.conditional, &mut self.conditional) else {
            return Ok(());
        };
        let active = self.targets.spot_shadows.active as usize;
        let mut plan = ConditionalPlan {
            tests: Vec::new(),
            draw_test: vec![None; self.volume_draws.len()],
            maps: vec![MapDraw::Direct; active],
            lights: Vec::new(),
        };
        // A map of a light on the volume path is read by its volume draws alone.
        for &slot in &self.volume_map_slots {
            if let Some(m) = plan.maps.get_mut(slot as usize) {
                *m = MapDraw::Skipped;
            }
        }
        let mut tests = Vec::new();
        let mut rows = Vec::new();
        for (k, d) in self.volume_draws.iter().enumerate() {
            let Some(slot) = d.map.filter(|&s| (s as usize) < active) else {
                continue;
            };
            if tests.len() >= MAX_TESTS as usize {
                plan.maps[slot as usize] = MapDraw::Direct;
                continue;
            }
            let test = tests.len() as u32;
            let first = rows.len() as u32;
            let mut counts = [0u32; 2];
            for (kind, alpha) in [false, true].into_iter().enumerate() {
                passes::laydown::for_each_caster(
                    scene,
                    self.casters.spots.get(slot as usize),
                    self.origin_offset,
                    alpha,
                    |draw, first_instance, instance_count| {
                        rows.push(GpuCasterDraw {
                            index_count: draw.index_count,
                            instance_count,
                            first_index: draw.first_index,
                            base_vertex: draw.base_vertex as i32,
                            first_instance,
                            test,
                            pad: [0; 2],
                        });
                        counts[kind] += 1;
                    },
                );
            }
            tests.push(GpuConditionalTest {
                volume: d.volume,
                opaque: counts[0],
                alpha: counts[1],
                pad: 0,
            });
            plan.tests.push(k as u32);
            plan.draw_test[k] = Some(test);
            plan.maps[slot as usize] = MapDraw::Indirect {
                test,
                first,
                opaque: counts[0],
                alpha: counts[1],
            };
        }
        plan.lights = plan
            .tests
            .iter()
            .map(|&k| {
                let volume = self.volume_draws[k as usize].volume as usize;
                self.volume_rows.get(volume).copied().unwrap_or_default()
            })
            .collect();
        if rows.len() > b.capacity as usize {
            *b = pass.buffers(&self.device, (rows.len() as u32).next_power_of_two())?;
        }
        let reach = self
            .pipelines
            .light_volumes
            .as_ref()
            .map_or(0, |v| v.index_count());
        self.uploads.write(
            &b.params,
            0,
            bytemuck::bytes_of(&GpuConditionalParams {
                tests: tests.len() as u32,
                casters: rows.len() as u32,
                volume_indices: reach,
                pad: 0,
            }),
        );
        if !tests.is_empty() {
            self.uploads
                .write(&b.tests, 0, bytemuck::cast_slice(&tests));
        }
        if !rows.is_empty() {
            self.uploads
                .write(&b.caster_rows, 0, bytemuck::cast_slice(&rows));
        }
        b.casters = rows.len() as u32;
        b.plan = plan;
        Ok(())
    }

    /// KZ2's shadowed spots: picks this frame's maps (fade by coverage, largest first),
    /// writes each chosen light's slot into its row, and uploads each map's frame uniforms
    /// (`uniforms` drawn from the light) and the rows lighting reads.
    fn upload_spot_shadows(
        &mut self,
        rows: &mut [deferred::DeferredLight],
        projection: &deferred::DeferredProjection,
        uniforms: &FrameUniforms,
    ) {
        use crate::spot_shadows::{GpuSpotShadow, assign_maps};
        let maps = &mut self.targets.spot_shadows;
        let Some(config) = maps.config else {
            maps.active = 0;
            return;
        };
        let classifier = deferred::lights::LightClassifier {
            fade: config.fade,
            ..deferred::lights::LightClassifier::default()
        };
        let chosen = assign_maps(rows, &config, |l| {
            let c = classifier.classify(projection, l);
            (c.coverage, c.shadow)
        });
        let view_rotation = glam::Mat4::from_cols_array_2d(&uniforms.view_rotation);
        let mut gpu_rows = Vec::with_capacity(chosen.len().max(1));
        self.casters.spots.clear();
        for (slot, map) in chosen.iter().enumerate() {
            let m = map.view_to_clip * view_rotation;
            let planes = shadow_view(&mut self.uploads, &maps.frames, slot, uniforms, m);
            if self.config.cull_shadow_casters {
                self.casters.spots.push(planes);
            }
            gpu_rows.push(GpuSpotShadow::new(map, config.resolution));
        }
        if !gpu_rows.is_empty() {
            self.uploads
                .write(&maps.rows, 0, bytemuck::cast_slice(&gpu_rows));
        }
        maps.active = chosen.len() as u32;
    }

    /// Replaces the classification phases' `override`s and skips entry points, for timing
    /// experiments (`examples/classify_variants.rs`).
    #[doc(hidden)]
    pub fn set_classification_variant(&mut self, variant: &ClassificationVariant) -> Result<()> {
        let device = self.device.clone();
        scoped(&device, || {
            self.pipelines.classify.set_variant(&device, variant)
        })
    }
}

/// The first limit of `needed` that `available` falls short of (wgpu's own comparison of
/// every limit), as an error naming it.
/// Uploads the frame uniforms of shadow view `index` (`uniforms` drawn through `m`, a
/// camera-relative matrix) into `frames` and returns the view's clip planes.
/// Instances the placement put in their setups' reserved slots, from its counters
/// (placed per setup after the fixed ones; ranks past a setup's capacity are not drawn).
fn placed_instances(scene: &PreparedScene, b: &StaticBuffers, words: &[u32]) -> u64 {
    (0..b.setup_count)
        .map(|s| {
            let placed = words
                .get((STATIC_COUNTER_PLACED + s) as usize)
                .copied()
                .unwrap_or(0);
            let cap = scene
                .static_capacities
                .get(s as usize)
                .copied()
                .unwrap_or(0);
            u64::from(placed.min(cap))
        })
        .sum()
}

fn shadow_view(
    uploads: &mut Uploads,
    frames: &wgpu::Buffer,
    index: usize,
    uniforms: &FrameUniforms,
    m: glam::Mat4,
) -> [glam::Vec4; 6] {
    let mut u = *uniforms;
    u.view_proj = m.to_cols_array_2d();
    uploads.write(
        frames,
        index as u64 * crate::shadows::CASCADE_FRAME_STRIDE,
        bytemuck::bytes_of(&u),
    );
    crate::shadows::clip_planes(m)
}

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
