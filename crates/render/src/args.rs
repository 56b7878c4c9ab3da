//! The `render` binary's arguments: the value enums, [`Args`], their parsers and the checks
//! clap cannot make alone. The pieces `view` takes too (`--light-paths`, the image-size,
//! light and frame limits, the density) come from the `cli` crate.

use std::path::PathBuf;

use anyhow::Result;
use clap::{Parser, ValueEnum};
use demo::{DemoOptions, DemoScene};
use gpu::RenderPath;

pub use cli::LightPathsArg;

/// `--scene`.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum SceneArg {
    /// Alpha-tested foliage cards, grass tufts, trees and rocks over a terrain.
    Forest,
    /// A tall-grass field of very high vertex density.
    Grass,
    /// HFW-like foliage from 15 m up: a meadow of tall grass, blade by blade, before a
    /// forest of dense canopies, grass triangles under a pixel wide at 4K; the talk's
    /// forest case (not part of `all`).
    Hillside,
    /// The hillside's tall grass from 5 m above it, grass to the horizon: the talk's
    /// tall-grass case (not part of `all`).
    HillsideGrass,
    /// glTF 2.0's materials: spheres over metallic x roughness, a normal- and
    /// occlusion-mapped brick wall (half of it mirrored), an emissive panel, a
    /// metallic-roughness-mapped plate, double-sided leaf cards (not part of `all`).
    Materials,
    /// HZD's static city (`--instances` of them) through the GPU static query, with
    /// foliage batches along the streets.
    City,
    /// Far Cry 5's water: a river with rapids and rocks, a waterfall into a lake, its
    /// outflow to the ocean's edge, trees and rocks on the banks (the flow baked on the
    /// CPU first, with a progress bar).
    River,
    /// All four, one after the other (the same renderer and device).
    All,
}

/// `--material-shaders`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum MaterialShadersArg {
    /// A resolve pipeline per material permutation (the default).
    PerShader,
    /// One uber resolve.
    Uber,
}

/// `--path`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PathArg {
    /// Visibility buffer, GPU classification, compute material resolve (HFW).
    Deferred,
    /// Depth prepass + depth-equal geometry pass (HZD), the method the talk replaces.
    Baseline,
    /// Both, on the same scene, with an image comparison.
    Both,
    /// Seed 004's geometry pipeline: the depth prepass, then a depth-equal pass with a
    /// position-only vertex shader whose pixel shader pulls the triangle's vertices by the
    /// primitive ID (hardware barycentrics, or the ray-triangle fallback).
    PixelPull,
    /// All three (deferred, baseline, pixel pull) on the same scene, each compared with
    /// the baseline's image.
    All,
}

impl PathArg {
    /// The paths rendered, in order.
    pub fn paths(self) -> &'static [RenderPath] {
        match self {
            PathArg::Deferred => &[RenderPath::Deferred],
            PathArg::Baseline => &[RenderPath::Baseline],
            PathArg::Both => &[RenderPath::Deferred, RenderPath::Baseline],
            PathArg::PixelPull => &[RenderPath::PixelPull],
            PathArg::All => &[
                RenderPath::Deferred,
                RenderPath::Baseline,
                RenderPath::PixelPull,
            ],
        }
    }
}

/// `--occlusion`: where the city's static query gets its HiZ.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum OcclusionArg {
    /// No occlusion test.
    Off,
    /// HZD's: the previous frame's depth, reduced on the GPU (the camera holds still).
    Previous,
    /// Two-pass: last frame's visible set drawn first, its depth reduced on the GPU, the
    /// rest tested against it.
    TwoPass,
    /// The previous frame's depth read back and reduced on the CPU (`HiZ::build`).
    Readback,
}

/// `--gbuffer`: the G-buffer layout.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum GBufferArg {
    /// deferred's octahedral layout: world-space 12+12-bit normal, f16 lighting, 24 bytes a pixel.
    Octahedral,
    /// KZ2's four RGBA8 targets: view-space normal xy as f16, 16 bytes a pixel.
    Kz2,
}

/// `--msaa`: KZ2's 4x MSAA on the baseline path.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum MsaaArg {
    /// Single sample.
    Off,
    /// KZ2's tricks: interior pixels lit once, edge pixels per sample with split PCF taps.
    Kz2,
    /// Every sample lit (the tricks' baseline).
    EverySample,
    /// Both, one after the other on the same frames: the baseline path under `kz2`, then
    /// again under `every-sample`.
    Compare,
}

/// `--laydown`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum LaydownArg {
    /// The hardware rasteriser (one indexed draw per micro batch).
    Hardware,
    /// Issue 17's compute laydown (64-bit atomics; large and near-plane triangles through
    /// its hardware part); the hardware laydown where the adapter lacks the atomics, and
    /// in frames with a static query (the report says which laydown each path ran).
    Compute,
    /// Both timed over the first deferred frames, the faster kept (the report says which
    /// and the times it measured).
    Auto,
}

/// `--laydown-target`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum LaydownTargetArg {
    /// The renderer's choice (the buffer, measured faster on the H200).
    Auto,
    /// A row-major storage buffer with 64-bit atomicMax.
    Buffer,
    /// An r64uint storage texture with textureAtomicMax (TEXTURE_INT64_ATOMIC).
    Texture,
}

/// `--vrs`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum VrsArg {
    /// Every pixel shaded.
    Off,
    /// HFW's rule (`gpu::config::VrsConfig::default`): by distance, coarser when moving.
    On,
    /// Every triangle 2x2 (the rule's result at speed).
    #[value(name = "all-2x2")]
    All2x2,
}

/// `--vertex-ring`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum VertexRingArg {
    /// No vertex side: the resolve transforms its triangle's vertices per pixel.
    Off,
    /// HFW's PS4 ring, 12 MiB (a pass at most 192k vertices).
    Ps4,
    /// HFW's PS5 ring, 24 MiB (a pass at most 384k vertices).
    Ps5,
}

/// `--primitive-id`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PrimitiveIdArg {
    /// The best the adapter supports.
    Auto,
    /// `@builtin(primitive_index)`.
    Builtin,
    /// HFW's XOR of per-vertex payloads.
    Xor,
    /// A flat payload on the provoking vertex.
    Provoking,
}

/// Render a procedural demo scene with HFW's deferred texturing and/or HZD's depth-equal
/// baseline; write PNGs and print statistics.
#[derive(Debug, Parser)]
#[command(version, about)]
pub struct Args {
    /// Which demo scene.
    #[arg(long, value_enum, default_value = "all")]
    pub scene: SceneArg,
    /// Image width in pixels (1 to 16384).
    #[arg(long, default_value_t = 1280, value_parser = cli::image_side())]
    pub width: u32,
    /// Image height in pixels (1 to 16384).
    #[arg(long, default_value_t = 720, value_parser = cli::image_side())]
    pub height: u32,
    /// Output directory for the PNGs.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Which rendering path.
    #[arg(long, value_enum, default_value = "both")]
    pub path: PathArg,
    /// Frames to measure, after 0.5 s of warm-up frames (timings are their mean; 1 to
    /// 100000).
    #[arg(long, default_value_t = 3, value_parser = cli::frame_count())]
    pub frames: u32,
    /// Scene seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Instance density multiplier, above 0 (1.0 renders in seconds on lavapipe; the
    /// largest that fits the talk's limits is checked before anything is built).
    #[arg(long, default_value_t = 1.0, value_parser = cli::positive_density, allow_negative_numbers = true)]
    pub density: f32,
    /// Static instances of the city scene (about; 1000 to 4000000).
    #[arg(long, default_value_t = 500_000, value_parser = clap::value_parser!(u64).range(1000..=4_000_000))]
    pub instances: u64,
    /// Where the city's occlusion test gets its HiZ.
    #[arg(long, value_enum, default_value = "off")]
    pub occlusion: OcclusionArg,
    /// Move the city's camera this many metres per frame down the street (warm-up frames
    /// included), so occlusion and LOD fade see motion; 0 holds it still.
    #[arg(long, default_value_t = 0.0, value_parser = parse_walk)]
    pub walk: f32,
    /// How the laydown gets primitive IDs.
    #[arg(long, value_enum, default_value = "auto")]
    pub primitive_id: PrimitiveIdArg,
    /// How the deferred paths lay down depth and the vis buffer (the baseline keeps its
    /// hardware depth prepass).
    #[arg(long, value_enum, default_value = "auto")]
    pub laydown: LaydownArg,
    /// The compute laydown's split: triangles whose screen box is wider or taller than this
    /// many pixels, or larger than a quarter of its square in area, take its
    /// large-triangle pass (0 to 254; 0: every one). Triangles crossing the near plane go
    /// to its hardware part.
    #[arg(long, default_value_t = gpu::config::COMPUTE_LAYDOWN_MAX_EXTENT, value_parser = parse_extent)]
    pub laydown_max_extent: f32,
    /// The compute laydown's 64-bit target.
    #[arg(long, value_enum, default_value = "auto")]
    pub laydown_target: LaydownTargetArg,
    /// Use the workgroup-atomic fallback even where subgroups exist.
    #[arg(long)]
    pub no_subgroups: bool,
    /// Leave the device's hardware barycentrics off: the pixel-pull path traces the
    /// pixel's ray against its triangle (its fallback) even where the adapter has them.
    #[arg(long)]
    pub no_barycentrics: bool,
    /// HFW's vertex ring on the deferred path: vertex wave commands from the vertex cull
    /// buffer, each pass's visible chunks transformed into the ring, the resolve reading
    /// its three vertices from it.
    #[arg(long, value_enum, default_value = "ps5")]
    pub vertex_ring: VertexRingArg,
    /// With a vertex ring: fill it (and time its transform alone) but let the resolve
    /// transform its vertices per pixel, for comparison.
    #[arg(long)]
    pub per_pixel_transform: bool,
    /// The material resolve: one pipeline per material permutation (HFW's resolve per
    /// material shader), or one uber pipeline choosing every map at run time.
    #[arg(long, value_enum, default_value = "per-shader")]
    pub material_shaders: MaterialShadersArg,
    /// HFW's software VRS on the deferred path: a shading rate per triangle from distance
    /// and screen speed (`gpu::config::VrsConfig::default`), quad commands, one shaded sample per
    /// quad broadcast to its pixels. `all-2x2` rates everything 2x2, what HFW's rule gives
    /// "when we are moving at pace" (the measured frames hold the camera still).
    #[arg(long, value_enum, default_value = "off")]
    pub vrs: VrsArg,
    /// Hold the demo scenes' foliage still (HFW's wind animation, `gpu::scene::Wind::default`,
    /// sways every alpha-tested instance otherwise).
    #[arg(long)]
    pub no_wind: bool,
    /// Give every demo material every map of glTF's model, derived from its albedo
    /// (`demo::add_material_maps`: normal, metallic-roughness, occlusion, emissive), to
    /// measure the resolve with all maps.
    #[arg(long)]
    pub material_maps: bool,
    /// Skip writing the debug views.
    #[arg(long)]
    pub no_debug_views: bool,
    /// Add this many local lights (two point lights in three, the rest spots) around the
    /// camera's target, KZ2's 100s, at dusk (0 to 4000; 0 keeps the scene's own lights and
    /// daylight).
    #[arg(long, default_value_t = 0, value_parser = cli::light_count())]
    pub lights: u32,
    /// The G-buffer layout.
    #[arg(long, value_enum, default_value = "octahedral")]
    pub gbuffer: GBufferArg,
    /// How local lights reach the image.
    #[arg(long, value_enum, default_value = "tiled")]
    pub light_paths: LightPathsArg,
    /// Short for `--light-paths every-pixel`: every local light at every pixel (the
    /// reference and baseline of the tiled path).
    #[arg(long, conflicts_with = "light_paths")]
    pub all_lights: bool,
    /// Half-size in metres of the square around the camera's target that `--lights`
    /// scatters over (how densely they overlap); default 25 (forest, grass), 60 (city).
    #[arg(long, value_parser = parse_light_area)]
    pub light_area: Option<f32>,
    /// Switch the sun off (night: ambient and local lights only).
    #[arg(long)]
    pub no_sun: bool,
    /// Render no sun shadow maps (the sun lights everything but for the baked term).
    #[arg(long)]
    pub no_shadows: bool,
    /// No baked sun term (KZ2's pre-rendered sun shadow): every pixel runs the sun's shader.
    #[arg(long)]
    pub no_baked_sun: bool,
    /// HFW's mixed frame on the deferred path: terrain and rocks (regular materials) skip
    /// the vis buffer and are drawn by a regular geometry pass after the laydown, which
    /// clears their pixels' validity bits before classify output (needs the device feature
    /// SHADER_EARLY_DEPTH_TEST).
    #[arg(long)]
    pub mixed_frame: bool,
    /// Render every shadow slice every frame (no reuse of a slice whose stable matrix did
    /// not move: with a still camera the cache skips them all).
    #[arg(long)]
    pub no_shadow_cache: bool,
    /// Every sun slice at the full shadow resolution (default: KZ2's per-slice
    /// resolutions, the last slice at half).
    #[arg(long)]
    pub uniform_shadow_resolution: bool,
    /// Shadow views draw every caster (no culling of instance chunks per view).
    #[arg(long)]
    pub no_caster_culling: bool,
    /// No spot shadow maps: shadow-casting spots light unshadowed.
    #[arg(long)]
    pub no_spot_shadows: bool,
    /// KZ2's 4x MSAA on the baseline path (the deferred path stays single-sample).
    #[arg(long, value_enum, default_value = "off")]
    pub msaa: MsaaArg,
    /// KZ2's size threshold of the city's static shadow query, in each sun slice's texels:
    /// static casters whose bounding sphere spans fewer are left out of that slice (and,
    /// in the bake's texels, of the baked sun map); 0 keeps every caster (0 to 64). The
    /// report lists each slice's static casters and those dropped.
    #[arg(long, default_value_t = gpu::config::ShadowConfig::default().static_size_threshold, value_parser = parse_size_threshold)]
    pub shadow_size_threshold: f32,
    /// Draw the maps and shading of shadowed volume lights directly, even where their
    /// volume covers no pixel (no emulation of KZ2's conditional rendering: no test pass,
    /// no indirect arguments); only matters with volumes in `--light-paths`.
    #[arg(long)]
    pub no_conditional_volumes: bool,
    /// Create the device with wgpu's validation of indirect arguments (the compute pass
    /// it injects before indirect dispatches and draws; off by default: the renderer's
    /// own arguments are valid by construction).
    #[arg(long)]
    pub indirect_validation: bool,
    /// Render this glTF 2.0 file (`.gltf` or `.glb`) instead of the demo scenes (`--scene`
    /// is ignored): both paths, every debug view, the statistics and the import summary.
    #[arg(long, value_name = "FILE")]
    pub gltf: Option<PathBuf>,
    /// The water composite's precision (the river): `f16` where the adapter has
    /// SHADER_F16 (else f32), or `f32` always.
    #[arg(long, value_enum, default_value = "f16")]
    pub water_precision: WaterPrecisionArg,
    /// The water's mini G-buffer size over the image's, per axis (the river; 0.125 to 1).
    #[arg(long, default_value_t = gpu::WaterOptions::default().resolution_scale, value_parser = parse_water_scale)]
    pub water_scale: f32,
    /// The glTF file's camera: `file` (its first perspective camera, else `auto`), `auto`
    /// (framing the scene's bounds: gltf_scene::framing_camera) or the eye and the point
    /// looked at, `EX,EY,EZ,TX,TY,TZ` (metres, +Y up).
    #[arg(long, default_value = "file", value_parser = parse_camera, allow_hyphen_values = true)]
    pub camera: CameraArg,
}

/// `--water-precision`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum WaterPrecisionArg {
    /// Half precision where the adapter has SHADER_F16.
    F16,
    /// Single precision.
    F32,
}

/// A water resolution scale given on the command line: 0.125 to 1.
fn parse_water_scale(s: &str) -> Result<f32, String> {
    cli::number_between(s, 0.125, 1.0, "")
}

/// A shadow size threshold given on the command line: finite, 0 to 64 texels.
fn parse_size_threshold(s: &str) -> Result<f32, String> {
    cli::number_between(s, 0.0, 64.0, " texels")
}

/// `--camera`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CameraArg {
    /// The file's camera, else `Auto`.
    File,
    /// A camera framing the scene's bounds.
    Auto,
    /// Eye and target (world, metres).
    LookAt {
        /// Eye position.
        eye: [f32; 3],
        /// The point looked at.
        target: [f32; 3],
    },
}

/// `file`, `auto`, or six finite numbers (eye, then target) with the eye away from the
/// target.
fn parse_camera(s: &str) -> Result<CameraArg, String> {
    match s.trim() {
        "file" => return Ok(CameraArg::File),
        "auto" => return Ok(CameraArg::Auto),
        _ => {}
    }
    let v: Vec<f32> = s
        .split(',')
        .map(|x| x.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("`{s}` is not `file`, `auto` or six comma-separated numbers"))?;
    let [ex, ey, ez, tx, ty, tz] = v[..] else {
        return Err(format!(
            "`{s}`: six numbers (eye x,y,z then target x,y,z), not {}",
            v.len()
        ));
    };
    let (eye, target) = ([ex, ey, ez], [tx, ty, tz]);
    if !v.iter().all(|x| x.is_finite()) {
        return Err(format!("`{s}`: every number must be finite"));
    }
    let camera = gpu::Camera::look_at(eye.into(), target.into());
    camera.validate().map_err(|e| format!("`{s}`: {e}"))?;
    Ok(CameraArg::LookAt { eye, target })
}

/// A light area given on the command line: finite, 1 to 10000 metres.
fn parse_light_area(s: &str) -> Result<f32, String> {
    cli::number_between(s, 1.0, 10_000.0, " metres")
}

impl Args {
    /// The demo scenes to render (the city aside: [`Args::city`]; none with `--gltf`).
    pub fn scenes(&self) -> &'static [DemoScene] {
        if self.gltf.is_some() {
            return &[];
        }
        match self.scene {
            SceneArg::Forest => &[DemoScene::Forest],
            SceneArg::Grass => &[DemoScene::Grass],
            SceneArg::Hillside => &[DemoScene::Hillside],
            SceneArg::HillsideGrass => &[DemoScene::HillsideGrass],
            SceneArg::Materials => &[DemoScene::Materials],
            SceneArg::City | SceneArg::River => &[],
            SceneArg::All => &DemoScene::ALL,
        }
    }

    /// Whether the river is rendered (not with `--gltf`).
    pub fn river(&self) -> bool {
        self.gltf.is_none() && matches!(self.scene, SceneArg::River | SceneArg::All)
    }

    /// Whether the city is rendered (not with `--gltf`).
    pub fn city(&self) -> bool {
        self.gltf.is_none() && matches!(self.scene, SceneArg::City | SceneArg::All)
    }

    /// Checks what clap cannot alone: every scene's density against the talk's limits
    /// (the message names the limit and the largest density that fits).
    ///
    /// # Errors
    /// The first scene whose density does not fit.
    pub fn check(&self) -> Result<()> {
        for &scene in self.scenes() {
            cli::check_density(&DemoOptions {
                scene,
                seed: self.seed,
                density: self.density,
            })?;
        }
        if self.walk > 0.0 && self.occlusion == OcclusionArg::Readback {
            anyhow::bail!(
                "--occlusion readback tests one read-back pyramid: it needs a still camera (--walk 0)"
            );
        }
        Ok(())
    }
}

fn parse_extent(v: &str) -> Result<f32, String> {
    match v.parse::<f32>() {
        Ok(e) if (0.0..=gpu::config::COMPUTE_LAYDOWN_EXTENT_LIMIT).contains(&e) => Ok(e),
        Ok(e) => Err(format!("{e} pixels: 0 to 254")),
        Err(e) => Err(e.to_string()),
    }
}

fn parse_walk(v: &str) -> Result<f32, String> {
    match v.parse::<f32>() {
        Ok(m) if (0.0..=50.0).contains(&m) => Ok(m),
        Ok(m) => Err(format!("{m} m per frame: 0 to 50")),
        Err(e) => Err(e.to_string()),
    }
}
