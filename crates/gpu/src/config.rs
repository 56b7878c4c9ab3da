//! What a renderer is asked for ([`RendererConfig`], grouped: image, geometry, lighting,
//! frames), the enums its fields take, how `Laydown::Auto` chose, the vertex ring's sizes,
//! the compute laydown's limits and the device paths the renderer found. Defined here,
//! below the passes, which read it.

use crate::error::{Error, Result};

pub use crate::context::{ActivePaths, PrimitiveIdPath};
pub use crate::resources::vis64::{
    COMPUTE_LAYDOWN_FEATURES, LAYDOWN_TEXTURE_FEATURES, LaydownTarget,
};
pub use crate::shadows::ShadowConfig;
pub use crate::spot_shadows::{MAX_SPOT_SHADOW_MAPS, SpotShadowConfig};
/// The talk's vertex ring sizes (PS4 12 MiB, PS5 24 MiB), for `RendererConfig::geometry.vertex_ring`.
pub use tiling::{RING_BYTES_PS4, RING_BYTES_PS5};

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
/// method) either way. [`Renderer::laydown_choice`] says which one the frames take and why.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Laydown {
    /// The hardware rasteriser: one indexed draw per micro batch. Faster wherever the
    /// raster units are a fair share of the chip.
    Hardware,
    /// Issue 17's compute laydown: triangles rasterised in compute into a 64-bit target
    /// with `atomicMax` (depth bits high, vis word low), an invocation each, or the
    /// large-triangle pass's workgroups past the split
    /// ([`COMPUTE_LAYDOWN_MAX_EXTENT`](crate::config::COMPUTE_LAYDOWN_MAX_EXTENT)); one pass
    /// to the depth target and vis texture; then those crossing the near plane drawn by
    /// the hardware over them. Faster on the H200, whose raster units are 2 of its 66
    /// TPCs (0.56-0.81x of the hardware laydown; BENCHMARKS.md). Needs
    /// [`COMPUTE_LAYDOWN_FEATURES`](crate::config::COMPUTE_LAYDOWN_FEATURES) (64-bit storage-buffer
    /// atomics); on a device without them, and in frames with a static query (whose
    /// indirect draw lists the hardware draws), the hardware laydown runs instead, and
    /// [`FrameOutput::laydown`](crate::FrameOutput::laydown) says so.
    Compute,
    /// The default: the first deferred frames without a static query alternate the two
    /// laydowns, [`AUTO_LAYDOWN_FRAMES`](crate::config::AUTO_LAYDOWN_FRAMES) timed frames
    /// each after one untimed frame each (waited for, so [`Renderer::submit`] waits
    /// during the trial), and every later frame takes the one whose median frame time
    /// (the GPU's timestamps, else wall time) was lower. A device without the compute
    /// laydown's features takes the hardware one at once.
    #[default]
    Auto,
}

impl Laydown {
    /// Short name for tables and CLI flags.
    pub fn name(self) -> &'static str {
        match self {
            Laydown::Hardware => "hardware",
            Laydown::Compute => "compute",
            Laydown::Auto => "auto",
        }
    }

    /// Whether the renderer builds the compute laydown's pipelines and targets (where the
    /// device has its features).
    pub(crate) fn wants_compute(self) -> bool {
        matches!(self, Laydown::Compute | Laydown::Auto)
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

/// MSAA samples per pixel of the baseline path with [`RendererConfig::image.msaa`](crate::config::ImageConfig::msaa) on: 4, the
/// count wgpu guarantees for every G-buffer format.
pub const MSAA_SAMPLES: u32 = 4;

/// How the baseline path lights its 4x multisampled G-buffer ([`RendererConfig::image.msaa`](crate::config::ImageConfig::msaa)).
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

/// Renderer options, grouped by concern: [`image`](Self::image), [`geometry`](Self::geometry)
/// (the laydown and HFW's vertex side), [`lighting`](Self::lighting) (lights and shadows)
/// and [`frames`](Self::frames) (pacing and uploads). Start from
/// [`RendererConfig::recommended`] and change what you need:
///
/// ```
/// # fn f(adapter: &wgpu::Adapter) {
/// let mut config = gpu::RendererConfig::recommended(adapter, 1920, 1080);
/// config.lighting.light_paths = gpu::config::LightPaths::Classified;
/// config.frames.frames_in_flight = 3;
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct RendererConfig {
    /// The image: its size, the G-buffer layout, MSAA on the baseline path and the
    /// resolve's mip bias.
    pub image: ImageConfig,
    /// Geometry: how the deferred paths lay down depth and the vis buffer (hardware or
    /// compute, and the compute laydown's split and target), the primitive-ID path,
    /// subgroups, HFW's mixed frame, vertex ring and software VRS.
    pub geometry: GeometryConfig,
    /// Lighting and shadows: the local lights' paths, the sun's cascades and baked term,
    /// the spot maps, caster culling and KZ2's conditional volumes.
    pub lighting: LightingConfig,
    /// Frame pacing and uploads: frames in flight and the per-frame upload pool.
    pub frames: FrameConfig,
}

/// The image: its size, the G-buffer layout, MSAA on the baseline path and the resolve's
/// mip bias.
#[derive(Clone, Debug, PartialEq)]
pub struct ImageConfig {
    /// Image width in pixels, at least 1.
    pub width: u32,
    /// Image height in pixels, at least 1.
    pub height: u32,
    /// The G-buffer layout: `deferred`'s octahedral one (the default: world-space 12+12-bit
    /// normal, 20 bytes a pixel) or KZ2's four RGBA8 targets (view-space normal xy as f16,
    /// lighting and glow, motion and log specular power, albedo and sun shadow; 16 bytes a
    /// pixel). Both render the same scene; the KZ2 preset rounds more (BENCHMARKS.md has
    /// the image difference). The depth target stays `Depth32Float` in both.
    pub gbuffer: deferred::GBufferLayout,
    /// KZ2's MSAA on the baseline path ([`RenderPath::Baseline`]): its depth prepass and
    /// G-buffer pass render [`MSAA_SAMPLES`] samples a pixel, lighting resolves them into
    /// the output image (the average of the samples' tone-mapped colours). `None`: single
    /// sample. The visibility-buffer paths stay single-sample (a vis word names one
    /// triangle a pixel), and so do the static query's HiZ and the stencil volumes:
    /// MSAA needs a light path without volumes, and static frames on the baseline path
    /// are refused with it. [`Inspect::read_depth`] and [`Inspect::read_gbuffer`] read
    /// the single-sample targets.
    pub msaa: Option<MsaaLighting>,
    /// Mip bias of the compute resolve (log2 units, in [-16, 16]).
    pub mip_bias: f32,
}

/// Geometry: how the deferred paths lay down depth and the vis buffer (hardware or
/// compute, and the compute laydown's split and target), the primitive-ID path, subgroups,
/// HFW's mixed frame, vertex ring and software VRS.
#[derive(Clone, Debug, PartialEq)]
pub struct GeometryConfig {
    /// How the deferred paths lay down depth and the vis buffer (default
    /// [`Laydown::Auto`]: both timed over the first frames, the faster kept;
    /// [`Laydown::Compute`] falls back to the hardware laydown on a device without 64-bit
    /// atomics, and so does every frame with a static query).
    pub laydown: Laydown,
    /// The compute laydown's split: triangles whose screen box is wider or taller than this
    /// many pixels, or larger than a quarter of its square in area, go to its
    /// large-triangle pass instead of an invocation each (0: every one; at most
    /// [`COMPUTE_LAYDOWN_EXTENT_LIMIT`](crate::config::COMPUTE_LAYDOWN_EXTENT_LIMIT), where the
    /// fixed-point edge functions still fit 32 bits). Default
    /// [`COMPUTE_LAYDOWN_MAX_EXTENT`](crate::config::COMPUTE_LAYDOWN_MAX_EXTENT).
    pub compute_laydown_max_extent: f32,
    /// Force the compute laydown's 64-bit target (the device must have its features);
    /// `None` picks [`LaydownTarget::best_for`] the device: the storage buffer (measured
    /// faster than the `r64uint` texture on the H200).
    pub compute_laydown_target: Option<LaydownTarget>,
    /// Force a primitive-ID path (the device must have its feature); `None` picks the
    /// best the device has.
    pub primitive_id: Option<PrimitiveIdPath>,
    /// Use subgroup operations where the device has them (else the workgroup fallback).
    pub subgroups: bool,
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
    /// HFW's resolve per material shader (the default): `tiling` splits passes by
    /// [`Material::shader_key`](crate::Material::shader_key), and each pass of the
    /// wave-command resolve dispatches a pipeline specialised for its permutation (only the
    /// maps its materials have compiled in; pipelines cached by permutation, counted in
    /// [`SceneSummary::resolve_pipelines`](crate::SceneSummary::resolve_pipelines)). Off:
    /// one uber resolve for every pass, each map chosen per material at run time (the
    /// measurement's baseline).
    pub material_permutations: bool,
}

/// Lighting and shadows: the local lights' paths, the sun's cascades and baked term, the
/// spot maps, caster culling and KZ2's conditional volumes.
#[derive(Clone, Debug, PartialEq)]
pub struct LightingConfig {
    /// How local lights reach the image: the tiles (the default), KZ2's classification
    /// between tiles and stencil volumes, stencil volumes alone, or every light tested at
    /// every pixel (the reference and measurement baseline).
    pub light_paths: LightPaths,
    /// The sun's cascaded shadow maps; `None`: the sun is unshadowed (but for the
    /// G-buffer's baked sun term).
    pub shadows: Option<ShadowConfig>,
    /// Shadow maps for the spot lights that cast shadows (KZ2's fade, the largest first);
    /// `None`: every spot lights unshadowed.
    pub spot_shadows: Option<SpotShadowConfig>,
    /// KZ2's pre-rendered sun shadow: a low-resolution map of the scene's batches
    /// (1024² texels), rendered when the scene or the sun
    /// direction changes, written into the G-buffer's sun term; pixels where it is 0 skip
    /// the sun's shader. Off: the term is 1 everywhere.
    pub baked_sun: bool,
    /// Shadow views (sun slices, spot maps) draw only the casters whose chunk of instances
    /// (64 consecutive instances of a batch, in Morton order) meets the view; off, every
    /// caster (the maps are the same: the test compares them).
    pub cull_shadow_casters: bool,
    /// KZ2's conditional rendering, emulated with indirect draws: a light on the
    /// stencil-volume path that owns a spot shadow map first counts the pixels its shading
    /// would cover (an occlusion query over a test draw of its volume), and a compute pass
    /// turns the count into the indirect arguments of its map's caster draws and of its
    /// volume draws, so a light behind a wall or lighting only air draws neither, with no
    /// CPU round trip. The image is the same either way. Takes effect with a light path
    /// that has volumes on a device with `INDIRECT_FIRST_INSTANCE` (else the draws are
    /// direct); default on.
    pub conditional_volumes: bool,
}

/// Frame pacing and uploads: frames in flight and the per-frame upload pool.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameConfig {
    /// Frames [`Renderer::submit`] lets run ahead of the GPU before it waits for the
    /// oldest (at least 1; default 2: one recording while one renders).
    pub frames_in_flight: u32,
    /// The per-frame upload pool (KZ2's render-memory allocator, `framealloc`): every
    /// frame's uniforms, lights and query parameters are sub-allocated from its blocks
    /// and freed when the GPU has finished the frame. Default: KZ2's 22 MiB in 256 KiB
    /// blocks.
    pub upload_pool: framealloc::PoolConfig,
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
                "RendererConfig::geometry.vrs",
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
        if self.image.width == 0 {
            return bad("RendererConfig::image.width", 0.0, "at least 1 pixel");
        }
        if self.image.height == 0 {
            return bad("RendererConfig::image.height", 0.0, "at least 1 pixel");
        }
        if self.image.mip_bias.is_nan() || self.image.mip_bias.abs() > 16.0 {
            return bad(
                "RendererConfig::image.mip_bias",
                f64::from(self.image.mip_bias),
                "[-16, 16] (log2 units)",
            );
        }
        if self.frames.frames_in_flight == 0 {
            return bad(
                "RendererConfig::frames.frames_in_flight",
                0.0,
                "at least 1 frame",
            );
        }
        if let Some(s) = &self.lighting.shadows {
            s.validate()?;
        }
        if let Some(s) = &self.lighting.spot_shadows {
            s.validate()?;
        }
        let extent = self.geometry.compute_laydown_max_extent;
        if !(0.0..=COMPUTE_LAYDOWN_EXTENT_LIMIT).contains(&extent) {
            return bad(
                "RendererConfig::geometry.compute_laydown_max_extent",
                f64::from(extent),
                "[0, 254] pixels",
            );
        }
        if let Some(bytes) = self.geometry.vertex_ring {
            // Two halves of at least one 64-vertex chunk; slots in u32.
            let min = 2 * 64 * crate::resources::ring::RING_VERTEX_BYTES;
            if !(min..=1 << 36).contains(&bytes) {
                return bad(
                    "RendererConfig::geometry.vertex_ring",
                    bytes as f64,
                    "4096 bytes to 64 GiB (the device's storage binding limit applies)",
                );
            }
        }
        if let Some(v) = &self.geometry.vrs {
            v.validate()?;
        }
        if self.image.msaa.is_some() && self.lighting.light_paths.volumes() {
            return bad(
                "RendererConfig::image.msaa",
                f64::from(MSAA_SAMPLES),
                "off with a light path that has stencil volumes (they are single-sample)",
            );
        }
        Ok(())
    }
}

impl RendererConfig {
    /// [`RendererConfig::default`] at `width` x `height`: the portable, deterministic
    /// set-up tests and tools start from (an embedder starts from
    /// [`RendererConfig::recommended`]).
    #[must_use]
    pub fn sized(width: u32, height: u32) -> Self {
        Self {
            image: ImageConfig {
                width,
                height,
                ..ImageConfig::default()
            },
            ..Self::default()
        }
    }

    /// The recommended pipeline for `adapter` at `width` x `height`: the pipeline the
    /// README describes and `render` runs by default. [`Laydown::Auto`] (the compute
    /// laydown where it measures faster, as on GPUs with few raster units such as the
    /// H100/H200), HFW's 24 MiB vertex ring, subgroups where the adapter has them, the
    /// tiled light lists, the sun's cascades and the spot maps. Every other field is
    /// [`RendererConfig::default`]'s.
    #[must_use]
    pub fn recommended(adapter: &wgpu::Adapter, width: u32, height: u32) -> Self {
        let features = adapter.features();
        Self {
            image: ImageConfig {
                width,
                height,
                ..ImageConfig::default()
            },
            geometry: GeometryConfig {
                subgroups: features.contains(wgpu::Features::SUBGROUP),
                laydown: Laydown::Auto,
                vertex_ring: Some(RING_BYTES_PS5),
                ..GeometryConfig::default()
            },
            ..Self::default()
        }
    }
}

/// The portable, deterministic configuration every frame of which runs the same passes
/// (what the tests start from): 1280x720, the hardware laydown, no vertex ring, no VRS,
/// no MSAA, the tiled light lists, the sun's cascades, the spot maps, the baked sun.
/// An embedder starts from [`RendererConfig::recommended`].
impl Default for RendererConfig {
    fn default() -> Self {
        Self {
            image: ImageConfig::default(),
            geometry: GeometryConfig::default(),
            lighting: LightingConfig::default(),
            frames: FrameConfig::default(),
        }
    }
}

impl Default for ImageConfig {
    fn default() -> Self {
        Self {
            width: 1280,
            height: 720,
            gbuffer: deferred::GBufferLayout::Octahedral,
            msaa: None,
            mip_bias: 0.0,
        }
    }
}

impl Default for GeometryConfig {
    fn default() -> Self {
        Self {
            laydown: Laydown::Hardware,
            compute_laydown_max_extent: COMPUTE_LAYDOWN_MAX_EXTENT,
            compute_laydown_target: None,
            primitive_id: None,
            subgroups: true,
            mixed_frame: false,
            vertex_ring: None,
            ring_resolve: true,
            vrs: None,
            material_permutations: true,
        }
    }
}

impl Default for LightingConfig {
    fn default() -> Self {
        Self {
            light_paths: LightPaths::Tiled,
            shadows: Some(ShadowConfig::default()),
            spot_shadows: Some(SpotShadowConfig::default()),
            baked_sun: true,
            cull_shadow_casters: true,
            conditional_volumes: true,
        }
    }
}

impl Default for FrameConfig {
    fn default() -> Self {
        Self {
            frames_in_flight: 2,
            upload_pool: framealloc::PoolConfig::KZ2,
        }
    }
}

/// Frames of each laydown [`Laydown::Auto`] times before it chooses (after one untimed
/// frame of each, which pays for first-use costs such as pipeline compilation).
pub const AUTO_LAYDOWN_FRAMES: usize = 3;

/// Which laydown the deferred frames without a static query take, and why
/// ([`Renderer::laydown_choice`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaydownChoice {
    /// The laydown the next such frame takes (during [`Laydown::Auto`]'s trial: the one
    /// it tries next).
    pub laydown: Laydown,
    /// Why.
    pub reason: LaydownReason,
}

/// Why a renderer's deferred frames take the laydown they take.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LaydownReason {
    /// [`RendererConfig::geometry.laydown`](crate::config::GeometryConfig::laydown) asked for it and the device can run it.
    Asked,
    /// The compute laydown (asked for, or [`Laydown::Auto`]) needs
    /// [`COMPUTE_LAYDOWN_FEATURES`](crate::config::COMPUTE_LAYDOWN_FEATURES), which the device
    /// lacks: the hardware laydown runs instead.
    NoComputeFeatures,
    /// [`Laydown::Auto`] is still timing both: `frames_left` deferred frames to go.
    Trial {
        /// Deferred frames (without a static query) until the choice.
        frames_left: u32,
    },
    /// [`Laydown::Auto`] timed both and kept the faster.
    Measured {
        /// Median time of the frames with the hardware laydown (ms; GPU time where the
        /// device has timestamps, else wall time).
        hardware_ms: f64,
        /// Median time of the frames with the compute laydown (ms, the same measure).
        compute_ms: f64,
        /// Whether the times are the GPU's timestamps (else wall-clock times).
        gpu_timed: bool,
    },
}

/// The compute raster's default split (pixels): a triangle whose screen box is at most this
/// wide and tall, and at most a quarter of this squared in area, is drawn by one
/// invocation looping over its box; any other by the large-triangle pass (a workgroup per
/// batch of triangles, 8x8 blocks of the box rejected whole). The area bound sends long
/// slanted triangles, whose boxes are mostly empty, to the blocks. 24 was the fastest on
/// every demo scene at 4K on the H200 (BENCHMARKS.md)
/// ([`RendererConfig::geometry.compute_laydown_max_extent`](crate::config::GeometryConfig::compute_laydown_max_extent) sets it; WGSL:
/// the override `GPU_COMPUTE_LAYDOWN_MAX_EXTENT`).
pub const COMPUTE_LAYDOWN_MAX_EXTENT: f32 = 24.0;

/// The largest extent the raster's fixed point holds: edge functions of boxes up to
/// (254 + 2) x 256 subpixels stay below 2^31.
pub const COMPUTE_LAYDOWN_EXTENT_LIMIT: f32 = 254.0;
