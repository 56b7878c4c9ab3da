//! The `render` binary's arguments and run: every value is checked before anything is
//! built (an image size within the device's, a frame count of at least one, a density
//! that is finite, above zero and within the talk's limits), so no input panics.
//!
//! ```no_run
//! use clap::Parser as _;
//!
//! // What `scripts/demo --scene forest --width 320 --height 180 --frames 1` runs.
//! let args = render::Args::parse_from([
//!     "render", "--scene", "forest", "--width", "320", "--height", "180", "--frames", "1",
//! ]);
//! render::run(&args)?; // writes out/forest_*.png and prints the statistics
//! # Ok::<(), anyhow::Error>(())
//! ```
//!
//! `--gltf FILE` renders a glTF 2.0 file instead (imported by `gltf_scene` before the
//! device starts, so a bad file is refused first): the import summary and warnings, then
//! the same report, images and debug views; `--camera` picks the file's camera (default;
//! without one, `auto`), `auto` (gltf_scene::framing_camera: the instances' bounds seen
//! from the front right, above, fitting the narrower field of view) or an eye and target.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::{Parser, ValueEnum};
use demo::{DemoOptions, DemoScene};
use gpu::config::PrimitiveIdPath;
use gpu::{HeadlessOptions, RenderPath, Renderer, RendererConfig};

pub mod report;

use report::Report;

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

/// `--light-paths`: how local lights reach the image.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum LightPathsArg {
    /// KZ2's: small lights by tiles, large ones (or holding the eye) by stencil volumes.
    Classified,
    /// Every light by the 16x16 tiles' lists (the fastest on the H200 and lavapipe).
    Tiled,
    /// Every light by stencil volume.
    Volumes,
    /// Every light tested at every pixel (the reference).
    EveryPixel,
}

impl LightPathsArg {
    /// The renderer's setting.
    pub fn paths(self) -> gpu::config::LightPaths {
        match self {
            LightPathsArg::Classified => gpu::config::LightPaths::Classified,
            LightPathsArg::Tiled => gpu::config::LightPaths::Tiled,
            LightPathsArg::Volumes => gpu::config::LightPaths::Volumes,
            LightPathsArg::EveryPixel => gpu::config::LightPaths::EveryPixel,
        }
    }
}

/// `--gbuffer`: the G-buffer layout.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum GBufferArg {
    /// deferred's octahedral layout: world-space 12+12-bit normal, 20 bytes a pixel.
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
    #[arg(long, default_value_t = 1280, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub width: u32,
    /// Image height in pixels (1 to 16384).
    #[arg(long, default_value_t = 720, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub height: u32,
    /// Output directory for the PNGs.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Which rendering path.
    #[arg(long, value_enum, default_value = "both")]
    pub path: PathArg,
    /// Frames to measure, after 0.5 s of warm-up frames (timings are their mean; 1 to
    /// 100000).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub frames: u32,
    /// Scene seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Instance density multiplier, above 0 (1.0 renders in seconds on lavapipe; the
    /// largest that fits the talk's limits is checked before anything is built).
    #[arg(long, default_value_t = 1.0, value_parser = positive_density, allow_negative_numbers = true)]
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
    /// Skip writing the debug views.
    #[arg(long)]
    pub no_debug_views: bool,
    /// Add this many local lights (two point lights in three, the rest spots) around the
    /// camera's target, KZ2's 100s, at dusk (0 to 4000; 0 keeps the scene's own lights and
    /// daylight).
    #[arg(long, default_value_t = 0, value_parser = clap::value_parser!(u32).range(0..=4000))]
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
    let v: f32 = s
        .trim()
        .parse()
        .map_err(|_| format!("`{s}` is not a number"))?;
    if (0.125..=1.0).contains(&v) {
        Ok(v)
    } else {
        Err(format!("{s} is not between 0.125 and 1"))
    }
}

/// A shadow size threshold given on the command line: finite, 0 to 64 texels.
fn parse_size_threshold(s: &str) -> Result<f32, String> {
    let t: f32 = s
        .trim()
        .parse()
        .map_err(|_| format!("`{s}` is not a number"))?;
    if (0.0..=64.0).contains(&t) {
        Ok(t)
    } else {
        Err(format!("{s} is not between 0 and 64 texels"))
    }
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
    let a: f32 = s
        .trim()
        .parse()
        .map_err(|_| format!("`{s}` is not a number"))?;
    if (1.0..=10_000.0).contains(&a) {
        Ok(a)
    } else {
        Err(format!("{s} is not between 1 and 10000 metres"))
    }
}

/// `frame` with `args.lights` lights scattered within `half_extent` metres of its target,
/// and the sun and ambient dimmed to dusk so that they show; the sun off with `--no-sun`.
fn with_lights(args: &Args, mut frame: gpu::FrameInput, half_extent: f32) -> gpu::FrameInput {
    if args.no_sun {
        frame.lighting.sun_color = gpu::glam::Vec3::ZERO;
    }
    if args.lights > 0 {
        // Dusk, so that the lights show.
        frame.lighting.sun_color *= 0.12;
        frame.lighting.ambient *= 0.35;
        let target = frame.camera.target;
        demo::scatter_lights(
            &mut frame.lighting,
            target,
            args.light_area.unwrap_or(half_extent),
            args.lights as usize,
            args.seed,
        );
    }
    frame
}

/// The light tiles of the frame just rendered, into the report, and (unless
/// `--no-debug-views`) their heat map as `{name}_debug_lights_per_tile.png` and the sun
/// shadows' views ([`shadow_views`]).
fn report_lighting(
    args: &Args,
    report: &mut Report,
    renderer: &Renderer,
    frame: &gpu::FrameInput,
    name: &str,
) -> Result<()> {
    let tiles = renderer.inspect().read_light_tiles()?;
    let lights = frame.lighting.point_lights.len() + frame.lighting.spot_lights.len();
    report.light_tiles(lights, &tiles);
    report.light_paths(renderer.inspect().light_path_counts());
    report.conditional_volumes(&renderer.inspect().read_conditional_volumes()?);
    report.uploads(
        renderer.inspect().upload_stats(),
        renderer.config().upload_pool,
    );
    // KZ2's skip: pixels in full baked sun shadow, or facing away, run no sun shader.
    let (surfaces, depth) = (
        renderer.inspect().read_gbuffer()?,
        renderer.inspect().read_depth()?,
    );
    let to_sun = frame
        .lighting
        .sun_direction
        .normalize_or(gpu::glam::Vec3::Y);
    let (mut geometry, mut baked, mut away) = (0u64, 0u64, 0u64);
    for (s, &d) in surfaces.iter().zip(&depth) {
        if d <= 0.0 {
            continue;
        }
        geometry += 1;
        if s.normal.dot(to_sun) <= 0.0 {
            away += 1;
        } else if s.sun_shadow <= 0.0 {
            baked += 1;
        }
    }
    report.sun_skip(geometry, baked, away);
    if !args.no_debug_views {
        let (img, max) = gpu::inspect::debug::lights_per_tile(args.width, args.height, &tiles, 0);
        let file = args.out.join(format!("{name}_debug_lights_per_tile.png"));
        img.write_png(&file)?;
        report.image_named(
            &format!("lights per 16x16 tile (legend at the bottom: 0 black .. {max} white, ticks at quarters)"),
            &file,
        );
        let (img, [culled, bounds, volume]) =
            gpu::inspect::debug::light_paths(&renderer.read_output()?, frame);
        let file = args.out.join(format!("{name}_debug_light_paths.png"));
        img.write_png(&file)?;
        report.image_named(
            &format!(
                "KZ2's path per light: {bounds} depth-bounds (green), {volume} light-volume (red), {culled} culled"
            ),
            &file,
        );
        shadow_views(args, report, renderer, frame.camera.near, name)?;
    }
    Ok(())
}

/// The sun-shadow debug views of the frame just rendered (with shadows on): the shadow
/// maps side by side as `{name}_debug_shadow_atlas.png` (512 texels a side at most) and
/// each pixel's depth slice (for a camera whose near plane is `near` metres) as
/// `{name}_debug_cascades.png`.
fn shadow_views(
    args: &Args,
    report: &mut Report,
    renderer: &Renderer,
    near: f32,
    name: &str,
) -> Result<()> {
    let Some(cascades) = renderer.inspect().shadow_cascades() else {
        return Ok(());
    };
    let maps = renderer.inspect().read_shadow_maps()?;
    let Some(config) = renderer.config().shadows else {
        return Ok(());
    };
    let resolution = config.resolution;
    let step = resolution.div_ceil(512);
    let slices: Vec<String> = (0..config.cascades as usize)
        .map(|k| config.slice_resolution(k).to_string())
        .collect();
    let file = args.out.join(format!("{name}_debug_shadow_atlas.png"));
    gpu::inspect::debug::shadow_atlas(&maps, resolution, step).write_png(&file)?;
    report.image_named(
        &format!(
            "sun shadow maps, nearest slice first ({} texels, each in the corner of a {resolution}-texel layer; 1 in {step} shown; black nearest the sun)",
            slices.join(" / ")
        ),
        &file,
    );
    let splits: Vec<f64> = cascades.cascades().iter().map(|c| c.split[1]).collect();
    let depth = renderer.inspect().read_depth()?;
    let file = args.out.join(format!("{name}_debug_cascades.png"));
    gpu::inspect::debug::cascade_index(args.width, args.height, &depth, near, &splits)
        .write_png(&file)?;
    let ends: Vec<String> = splits.iter().map(|d| format!("{d:.1}")).collect();
    report.image_named(
        &format!(
            "sun depth slice per pixel (red, green, blue, yellow; slices end at {} m)",
            ends.join(" / ")
        ),
        &file,
    );
    Ok(())
}

/// The motion-vector debug view: one frame from the camera 0.3 m to the left and 0.2 m
/// back a 30th of a second earlier, then the scene's own frame (the measured frames hold
/// the camera still, so their motion is the wind's alone), its G-buffer motion (camera
/// and swaying foliage) as `{name}_debug_motion.png`.
fn motion_view(
    args: &Args,
    report: &mut Report,
    renderer: &mut Renderer,
    prepared: &gpu::PreparedScene,
    frame: &gpu::FrameInput,
    name: &str,
) -> Result<()> {
    let mut before = frame.clone();
    let c = &frame.camera;
    let forward = (c.target - c.position).normalize();
    let right = forward.cross(c.up).normalize();
    let shift = -0.3 * right - 0.2 * forward;
    before.camera.position += shift;
    before.camera.target += shift;
    before.time = frame.time - 1.0 / 30.0;
    renderer.render(prepared, &before, RenderPath::Deferred)?;
    renderer.render(prepared, frame, RenderPath::Deferred)?;
    let (img, scale) = gpu::inspect::debug::motion_vectors(
        args.width,
        args.height,
        &renderer.inspect().read_gbuffer()?,
        0.0,
    );
    let file = args.out.join(format!("{name}_debug_motion.png"));
    img.write_png(&file)?;
    report.image_named(
        &format!(
            "motion vectors after a 0.3 m step right and 0.2 m forward and 1/30 s of wind \
             (hue: direction, full brightness at {scale:.1} px)"
        ),
        &file,
    );
    Ok(())
}

/// A density given on the command line: a finite number above zero.
fn positive_density(s: &str) -> Result<f32, String> {
    let d: f32 = s
        .trim()
        .parse()
        .map_err(|_| format!("`{s}` is not a number"))?;
    if d.is_finite() && d > 0.0 {
        Ok(d)
    } else {
        Err(format!("{s} is not a finite number above 0"))
    }
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
            demo::check_density(&DemoOptions {
                scene,
                seed: self.seed,
                density: self.density,
            })
            .with_context(|| format!("--density for the {} scene", scene.name()))?;
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

/// Files from this size on (bytes) show a progress bar while they import.
const PROGRESS_BYTES: u64 = 4 << 20;

/// A one-line text progress bar on stderr, redrawn when a step's percentage changes.
#[derive(Default)]
struct ProgressBar {
    last: Option<(gltf_scene::Stage, u64)>,
}

impl ProgressBar {
    fn show(&mut self, p: gltf_scene::Progress) {
        let percent = (p.done.min(p.total) * 100)
            .checked_div(p.total)
            .unwrap_or(100);
        if self.last == Some((p.stage, percent)) {
            return;
        }
        self.last = Some((p.stage, percent));
        let filled = (percent / 5) as usize;
        let stage = format!("{:?}", p.stage).to_lowercase();
        eprint!(
            "\rimporting: {stage:<8} [{}{}] {} / {}",
            "#".repeat(filled),
            "-".repeat(20 - filled),
            p.done,
            p.total
        );
        if percent == 100 {
            eprintln!();
        }
    }
}

/// Renders every scene `args` names; writes the images; prints the reports.
///
/// # Errors
/// Arguments that do not fit ([`Args::check`]), no adapter, a device error, an image that
/// cannot be written, or a GPU classification that differs from its CPU twin.
pub fn run(args: &Args) -> Result<()> {
    args.check()?;
    // A glTF file is imported first: its errors come before any device or directory.
    let imported = match &args.gltf {
        Some(path) => {
            let t0 = std::time::Instant::now();
            // A progress bar on stderr for large files (small ones load in a blink).
            let large = std::fs::metadata(path).is_ok_and(|m| m.len() >= PROGRESS_BYTES);
            let mut bar = ProgressBar::default();
            let imported = gltf_scene::load_with_progress(
                path,
                &gltf_scene::LoadOptions::default(),
                &mut |p| {
                    if large {
                        bar.show(p);
                    }
                },
            )
            .with_context(|| format!("importing {}", path.display()))?;
            Some((path.as_path(), imported, t0.elapsed().as_secs_f64() * 1e3))
        }
        None => None,
    };
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let mut disable = wgpu::Features::empty();
    if args.no_subgroups {
        disable |= wgpu::Features::SUBGROUP;
    }
    if args.no_barycentrics {
        disable |= wgpu::Features::SHADER_BARYCENTRICS;
    }
    let ctx = gpu::headless(&HeadlessOptions {
        disable_features: disable,
        indirect_validation: args.indirect_validation,
        ..Default::default()
    })?;
    let primitive_id = match args.primitive_id {
        PrimitiveIdArg::Auto => None,
        PrimitiveIdArg::Builtin => Some(PrimitiveIdPath::Builtin),
        PrimitiveIdArg::Xor => Some(PrimitiveIdPath::PerVertexXor),
        PrimitiveIdArg::Provoking => Some(PrimitiveIdPath::ProvokingVertex),
    };
    let config = RendererConfig {
        width: args.width,
        height: args.height,
        primitive_id,
        light_paths: if args.all_lights {
            gpu::config::LightPaths::EveryPixel
        } else {
            args.light_paths.paths()
        },
        shadows: (!args.no_shadows).then(|| gpu::config::ShadowConfig {
            cache: !args.no_shadow_cache,
            resolution_divisor: if args.uniform_shadow_resolution {
                [1; 8]
            } else {
                gpu::config::ShadowConfig::default().resolution_divisor
            },
            static_size_threshold: args.shadow_size_threshold,
            ..gpu::config::ShadowConfig::default()
        }),
        baked_sun: !args.no_baked_sun,
        spot_shadows: (!args.no_spot_shadows).then(gpu::config::SpotShadowConfig::default),
        cull_shadow_casters: !args.no_caster_culling,
        conditional_volumes: !args.no_conditional_volumes,
        gbuffer: match args.gbuffer {
            GBufferArg::Octahedral => gpu::deferred::GBufferLayout::Octahedral,
            GBufferArg::Kz2 => gpu::deferred::GBufferLayout::Kz2,
        },
        msaa: match args.msaa {
            MsaaArg::Off => None,
            MsaaArg::Kz2 | MsaaArg::Compare => Some(gpu::config::MsaaLighting::Kz2),
            MsaaArg::EverySample => Some(gpu::config::MsaaLighting::EverySample),
        },
        laydown: match args.laydown {
            LaydownArg::Hardware => gpu::Laydown::Hardware,
            LaydownArg::Compute => gpu::Laydown::Compute,
            LaydownArg::Auto => gpu::Laydown::Auto,
        },
        compute_laydown_max_extent: args.laydown_max_extent,
        compute_laydown_target: match args.laydown_target {
            LaydownTargetArg::Auto => None,
            LaydownTargetArg::Buffer => Some(gpu::config::LaydownTarget::Buffer),
            LaydownTargetArg::Texture => Some(gpu::config::LaydownTarget::Texture),
        },
        mixed_frame: args.mixed_frame,
        vertex_ring: match args.vertex_ring {
            VertexRingArg::Off => None,
            VertexRingArg::Ps4 => Some(gpu::config::RING_BYTES_PS4),
            VertexRingArg::Ps5 => Some(gpu::config::RING_BYTES_PS5),
        },
        ring_resolve: !args.per_pixel_transform,
        vrs: match args.vrs {
            VrsArg::Off => None,
            VrsArg::On => Some(gpu::config::VrsConfig::default()),
            VrsArg::All2x2 => Some(gpu::config::VrsConfig {
                distance_2x1: 1e-6,
                distance_2x2: 1e-6,
                ..gpu::config::VrsConfig::default()
            }),
        },
        ..RendererConfig::default()
    };
    // `--msaa compare`: a second renderer lighting every sample.
    let mut every_sample = match args.msaa {
        MsaaArg::Compare => Some(Renderer::new(
            &ctx.device,
            &ctx.queue,
            RendererConfig {
                msaa: Some(gpu::config::MsaaLighting::EverySample),
                ..config.clone()
            },
        )?),
        _ => None,
    };
    let mut renderer = Renderer::new(&ctx.device, &ctx.queue, config)?;
    if let Some((path, imported, build_ms)) = &imported {
        let gltf = (*path, imported, *build_ms);
        return render_gltf(args, &ctx, &mut renderer, every_sample.as_mut(), gltf);
    }
    for (k, &scene_kind) in args.scenes().iter().enumerate() {
        if k > 0 {
            println!();
        }
        println!("== {} ==", scene_kind.name());
        let t0 = std::time::Instant::now();
        let (mut scene, frame) = demo::build(&DemoOptions {
            scene: scene_kind,
            seed: args.seed,
            density: args.density,
        });
        scene.wind = (!args.no_wind).then(gpu::scene::Wind::default);
        let frame = with_lights(args, frame, 25.0);
        let build_ms = t0.elapsed().as_secs_f64() * 1e3;
        let built = Built {
            name: scene_kind.name(),
            scene: &scene,
            frame: &frame,
            build: ("scene build (CPU)", build_ms),
            water: None,
        };
        render_scene(args, &ctx, &mut renderer, every_sample.as_mut(), &built)?;
    }
    if args.city() {
        if !args.scenes().is_empty() {
            println!();
        }
        println!("== city ==");
        render_city(args, &ctx, &mut renderer)?;
    }
    if args.river() {
        if !args.scenes().is_empty() || args.city() {
            println!();
        }
        println!("== river ==");
        render_river(args, &ctx, &mut renderer, every_sample.as_mut())?;
    }
    Ok(())
}

/// A one-line progress bar on stderr for the water bakes (world, distance field, flow,
/// atlas), redrawn when a stage's percentage changes.
#[derive(Default)]
struct WaterProgressBar {
    last: Option<(gpu::water::Stage, u32)>,
}

impl WaterProgressBar {
    fn show(&mut self, p: gpu::water::Progress) -> std::ops::ControlFlow<()> {
        let percent = (p.fraction() * 100.0) as u32;
        if self.last == Some((p.stage, percent)) {
            return std::ops::ControlFlow::Continue(());
        }
        if self.last.is_some_and(|(s, pc)| s != p.stage && pc < 100) {
            eprintln!();
        }
        self.last = Some((p.stage, percent));
        let filled = (percent / 5) as usize;
        let stage = format!("{:?}", p.stage);
        eprint!(
            "\rwater bake: {stage:<16} [{}{}] {percent:3}%",
            "#".repeat(filled),
            "-".repeat(20 - filled),
        );
        if percent == 100 {
            eprintln!();
        }
        std::ops::ControlFlow::Continue(())
    }
}

/// The river: built (the water bakes behind a progress bar), given to the renderer as its
/// water, rendered as a demo scene with the water passes' statistics; the renderer's water
/// taken away after.
fn render_river(
    args: &Args,
    ctx: &gpu::GpuContext,
    renderer: &mut Renderer,
    every_sample: Option<&mut Renderer>,
) -> Result<()> {
    if renderer.config().msaa.is_some() {
        eprintln!("--msaa: the river renders without water (its passes are single-sample)");
    }
    let t0 = std::time::Instant::now();
    let mut bar = WaterProgressBar::default();
    let demo = demo::river::river(args.seed, args.density, &mut |p| bar.show(p))
        .context("building the river scene")?;
    let frame = with_lights(args, demo.frame.clone(), 40.0);
    let build_ms = t0.elapsed().as_secs_f64() * 1e3;
    let mut water = demo.water.clone();
    water.options.half_precision = args.water_precision == WaterPrecisionArg::F16;
    water.options.resolution_scale = args.water_scale;
    let built = Built {
        name: "river",
        scene: &demo.scene,
        frame: &frame,
        build: ("scene build and water bakes (CPU)", build_ms),
        water: (renderer.config().msaa.is_none()).then_some((&water, demo.decals.as_slice())),
    };
    let out = render_scene(args, ctx, renderer, every_sample, &built);
    renderer.set_water(None)?;
    out
}

/// The city: streamed into the GPU static query, prepared with its static setups, rendered
/// with the query in front of the frame (optionally with occlusion: `--occlusion`); images
/// and the query's statistics.
fn render_city(args: &Args, ctx: &gpu::GpuContext, renderer: &mut Renderer) -> Result<()> {
    use gpu::staticscene::{HiZ, QueryOptions};
    let t0 = std::time::Instant::now();
    let city = demo::city::city(args.instances as usize);
    let mut query = gpu::statics::StaticQuery::new(&ctx.device, &ctx.queue)?;
    let mut cpu = gpu::statics::stream_static_world(
        &ctx.device,
        &ctx.queue,
        &mut query,
        &city.world.resources,
        &city.world.groups,
    )?;
    let build_ms = t0.elapsed().as_secs_f64() * 1e3;
    let t1 = std::time::Instant::now();
    let prepared = renderer.prepare(&city.scene)?;
    let prepare_ms = t1.elapsed().as_secs_f64() * 1e3;
    let frame = with_lights(args, city.frame.clone(), 60.0);
    let mut report = Report::new(ctx, renderer, &prepared);
    report.indirect_validation(args.indirect_validation);
    report.cpu_ms("city build, tiles built and activated (CPU)", build_ms);
    report.cpu_ms("prepare: meshes, reservations, upload (CPU)", prepare_ms);
    let paths: &[RenderPath] = match args.path {
        // The MSAA baseline takes no static frames (its HiZ would read single-sample
        // depth): the city's frames stay on the deferred path.
        _ if renderer.config().msaa.is_some() => {
            eprintln!("--msaa: the city's static frames render the deferred path only");
            &[RenderPath::Deferred]
        }
        path => path.paths(),
    };
    let (w, h) = (args.width, args.height);
    let mut desc = gpu::statics::static_view_desc(&frame.camera, w, h);
    let occlusion = match args.occlusion {
        OcclusionArg::Off | OcclusionArg::Readback => gpu::statics::StaticOcclusion::Given,
        OcclusionArg::Previous => gpu::statics::StaticOcclusion::PreviousFrame,
        OcclusionArg::TwoPass => gpu::statics::StaticOcclusion::TwoPass,
    };
    // A freshly streamed city fades in over `fade_frames` frames: render them first, so
    // the measured frames (whose warm-up is 0.5 s, a few frames on a slow adapter) and the
    // images of both paths show it settled, not at different steps of the dither. With
    // `readback`, the last of them (at least one) is the previous frame whose depth is read
    // back and reduced into the HiZ the measured frames test against (the camera holds
    // still).
    let readback = args.occlusion == OcclusionArg::Readback;
    for _ in 0..desc.fade_frames.max(u32::from(readback)) {
        let mut view = gpu::statics::StaticView {
            query: &mut query,
            scene: &mut cpu,
            view: desc,
            options: QueryOptions::default(),
            occlusion,
        };
        renderer.render_static(&prepared, &frame, RenderPath::Deferred, &mut view)?;
    }
    if readback {
        let hiz = HiZ::build(&renderer.inspect().read_depth()?, w, h, true)?;
        query.set_hiz(&ctx.device, &ctx.queue, Some(&hiz))?;
        desc.occlusion_camera = Some(desc.camera);
    }
    let mut images = Vec::new();
    for &path in paths {
        let mut view = gpu::statics::StaticView {
            query: &mut query,
            scene: &mut cpu,
            view: desc,
            options: QueryOptions::default(),
            occlusion,
        };
        let frames = if args.walk > 0.0 {
            let base = frame.clone();
            let ahead = (base.camera.target - base.camera.position).normalize();
            let occlusion_camera = desc.occlusion_camera.is_some();
            renderer.render_static_sequence(&prepared, path, &mut view, args.frames, |i| {
                let step = ahead * args.walk * i as f32;
                let mut frame = base.clone();
                frame.camera.position += step;
                frame.camera.target += step;
                let mut d = gpu::statics::static_view_desc(&frame.camera, w, h);
                if occlusion_camera {
                    d.occlusion_camera = Some(d.camera);
                }
                (frame, d)
            })?
        } else {
            renderer.render_static_frames(&prepared, &frame, path, &mut view, args.frames)?
        };
        let image = renderer.read_output()?;
        let file = args.out.join(format!("city_{}.png", path.name()));
        image.write_png(&file)?;
        report.image(path, &file);
        report.timings(path, &frames);
        report.laydown_ran(path, renderer, &frames);
        if path == RenderPath::Deferred {
            report_lighting(args, &mut report, renderer, &frame, "city")?;
        }
        if let (Some(s), true) = (&frames.statics, images.is_empty()) {
            report.static_query(s, cpu.instance_count() as u64);
            report.static_shadows(s);
        }
        if path == RenderPath::Deferred {
            let classified = renderer.inspect().read_classification(&prepared)?;
            let (stats, mismatch) = renderer
                .inspect()
                .classification_statistics(&prepared, &classified)?;
            report.classification(&stats);
            if !args.no_debug_views {
                let file = args.out.join("city_debug_vis_ids.png");
                gpu::inspect::debug::vis_ids(w, h, &classified.vis).write_png(&file)?;
                report.image_named("vis IDs", &file);
                let statics = renderer.inspect().read_static_debug(&prepared)?;
                let file = args.out.join("city_debug_lod_fade.png");
                gpu::inspect::debug::static_lod_fade(w, h, &classified.vis, &statics)
                    .write_png(&file)?;
                report.image_named("static setups and LOD fade", &file);
                if args.occlusion == OcclusionArg::TwoPass {
                    let file = args.out.join("city_debug_two_pass.png");
                    gpu::inspect::debug::static_two_pass(w, h, &classified.vis, &statics)
                        .write_png(&file)?;
                    report.image_named("two-pass: drawn early / found late", &file);
                }
            }
            if let Some(m) = &mismatch {
                print!("{report}");
                anyhow::bail!("the GPU classification differs from its CPU twin: {m}");
            }
        }
        images.push(image);
    }
    compare_with_baseline(&mut report, paths, &images);
    if args.occlusion != OcclusionArg::Off && !args.no_debug_views {
        let (texels, size) = query.read_hiz(&ctx.device, &ctx.queue)?;
        let file = args.out.join("city_debug_hiz.png");
        gpu::inspect::debug::hiz_mips(&texels, size).write_png(&file)?;
        report.image_named("HiZ mips the query tested against", &file);
    }
    if args.occlusion != OcclusionArg::Off && !args.no_debug_views && args.walk == 0.0 {
        // What occlusion culls, from the CPU twin on this view: without occlusion, and
        // against the last frame's depth (the camera holds still).
        let hiz = HiZ::build(&renderer.inspect().read_depth()?, w, h, true)?;
        let mut off_view = desc;
        off_view.occlusion_camera = None;
        let mut on_view = desc;
        on_view.occlusion_camera = Some(desc.camera);
        let mut outputs = Vec::new();
        for (view, hiz) in [(off_view, None), (on_view, Some(&hiz))] {
            let mut out = gpu::staticscene::QueryOutput::new();
            cpu.clone().query(
                &gpu::staticscene::QueryParams::new(&view)?,
                hiz,
                &QueryOptions::default(),
                &mut out,
            )?;
            outputs.push(out);
        }
        let overlay = gpu::inspect::debug::occlusion_overlay(
            &images[0],
            &cpu,
            &gpu::staticscene::QueryParams::new(&desc)?,
            &outputs[0].instances,
            &outputs[1].instances,
        );
        let file = args.out.join("city_debug_occlusion.png");
        overlay.write_png(&file)?;
        report.image_named("occlusion: drawn (green) / culled (red)", &file);
    }
    // HZD's mode on the same view: the CPU waits for the query, reads its batches back
    // and plans them (tiling::build_plan at prepare), then renders them as any scene.
    let params = gpu::staticscene::QueryParams::new(&desc)?;
    let t = std::time::Instant::now();
    let out = query.run(
        &ctx.device,
        &ctx.queue,
        &mut cpu,
        &params,
        &QueryOptions::default(),
        gpu::statics::QueryReadback::Full,
    )?;
    let read_ms = t.elapsed().as_secs_f64() * 1e3;
    let t = std::time::Instant::now();
    let planned = gpu::statics::scene_from_query(&city.scene, &out, &params)?;
    let prepared_hzd = renderer.prepare(&planned)?;
    let plan_ms = t.elapsed().as_secs_f64() * 1e3;
    let frames =
        renderer.render_frames(&prepared_hzd, &frame, RenderPath::Deferred, args.frames)?;
    report.cpu_ms("HZD's mode: query, wait, read back (wall)", read_ms);
    report.cpu_ms(
        "HZD's mode: batches planned (tiling::build_plan) and uploaded (CPU)",
        plan_ms,
    );
    report.gpu_frame_ms(
        "HZD's mode: deferred frame on the planned batches (GPU)",
        &frames,
    );
    print!("{report}");
    Ok(())
}

/// A scene to render, built or imported.
struct Built<'a> {
    /// The images' file-name prefix.
    name: &'a str,
    scene: &'a gpu::Scene,
    frame: &'a gpu::FrameInput,
    /// What building it is called in the report, and its CPU time (ms).
    build: (&'a str, f64),
    /// Its water and this frame's decals, if any.
    water: Option<(&'a gpu::WaterScene, &'a [gpu::water_scene::WaterDecal])>,
}

/// A glTF file (`--gltf`) imported (its path, what came of it, the import's CPU time in
/// ms): prints the import summary and warnings, picks the camera (`--camera`), then renders
/// it as a demo scene: images, debug views, report.
fn render_gltf(
    args: &Args,
    ctx: &gpu::GpuContext,
    renderer: &mut Renderer,
    every_sample: Option<&mut Renderer>,
    (path, imported, build_ms): (&std::path::Path, &gltf_scene::Imported, f64),
) -> Result<()> {
    let name = path
        .file_stem()
        .map(|s| {
            s.to_string_lossy()
                .replace(|c: char| !c.is_ascii_alphanumeric() && c != '-', "_")
        })
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "gltf".to_owned());
    println!("== {name} (glTF) ==");
    println!("{}", imported.summary);
    for w in &imported.warnings {
        println!("  warning: {w}");
    }
    let aspect = args.width as f32 / args.height as f32;
    let auto = || gltf_scene::framing_camera(&imported.scene, aspect);
    let camera = match args.camera {
        CameraArg::File => imported.camera.unwrap_or_else(auto),
        CameraArg::Auto => auto(),
        CameraArg::LookAt { eye, target } => gpu::Camera::look_at(eye.into(), target.into()),
    };
    let which = match (args.camera, imported.camera) {
        (CameraArg::File, Some(_)) => "the file's",
        (CameraArg::LookAt { .. }, _) => "--camera's",
        _ => "framing the scene's bounds",
    };
    println!(
        "  camera ({which}): eye {:.2}, looking at {:.2}, {:.0}° vertical field of view",
        camera.position,
        camera.target,
        camera.fov_y.to_degrees()
    );
    // Lights over the square the framed view covers.
    let half_extent = (0.5 * camera.position.distance(camera.target)).clamp(1.0, 10_000.0);
    let frame = with_lights(args, gpu::FrameInput::new(camera), half_extent);
    let built = Built {
        name: &name,
        scene: &imported.scene,
        frame: &frame,
        build: (
            "glTF import: parse, decode, build the scene (CPU)",
            build_ms,
        ),
        water: None,
    };
    render_scene(args, ctx, renderer, every_sample, &built)
}

/// Prepares and renders one scene; writes its images; prints its report.
fn render_scene(
    args: &Args,
    ctx: &gpu::GpuContext,
    renderer: &mut Renderer,
    mut every_sample: Option<&mut Renderer>,
    built: &Built<'_>,
) -> Result<()> {
    let (scene, frame) = (built.scene, built.frame);
    let t1 = std::time::Instant::now();
    let prepared = renderer.prepare(scene)?;
    let prepare_ms = t1.elapsed().as_secs_f64() * 1e3;

    let paths: &[RenderPath] = args.path.paths();
    let mut report = Report::new(ctx, renderer, &prepared);
    report.indirect_validation(args.indirect_validation);
    report.cpu_ms(built.build.0, built.build.1);
    report.cpu_ms(
        "prepare: encode meshes, micro batches, upload (CPU)",
        prepare_ms,
    );
    if let Some((water, decals)) = built.water {
        let summary = renderer.set_water(Some(water))?;
        renderer.set_water_decals(decals)?;
        if let Some(s) = summary {
            report.water_summary(&s);
        }
    }
    let mut images = Vec::new();
    for &path in paths {
        let frames = renderer.render_frames(&prepared, frame, path, args.frames)?;
        let image = renderer.read_output()?;
        let file = args.out.join(format!("{}_{}.png", built.name, path.name()));
        image.write_png(&file)?;
        report.image(path, &file);
        report.timings(path, &frames);
        report.laydown_ran(path, renderer, &frames);
        let name = built.name;
        if path == RenderPath::Baseline && renderer.config().msaa.is_some() {
            let edges = renderer.inspect().read_msaa_edges()?;
            if renderer.config().msaa == Some(gpu::config::MsaaLighting::Kz2) {
                report.msaa_edges(edges.len(), (args.width * args.height) as usize);
            }
            if let Some(r) = every_sample.as_deref_mut() {
                let p = r.prepare(scene)?;
                let t = r.render_frames(&p, frame, path, args.frames)?;
                report.timings_named("baseline, MSAA every sample", &t);
            }
        }
        if path == RenderPath::Deferred {
            // The same frames submitted back to back: the uploads of each in its own
            // blocks of the framealloc pool, no CPU wait between frames.
            // Warmed up as render_frames is: writing the image let the clocks fall.
            let warm = std::time::Instant::now();
            while warm.elapsed() < gpu::inspect::WARM_UP {
                renderer.submit(&prepared, frame, path)?;
            }
            let t = std::time::Instant::now();
            let mut in_flight = 0;
            let mut cpu_ms = 0.0;
            for _ in 0..args.frames {
                cpu_ms += renderer.submit(&prepared, frame, path)?.wall_ms;
                in_flight = in_flight.max(renderer.inspect().upload_stats().frames_in_flight);
            }
            renderer.wait()?;
            let n = f64::from(args.frames);
            let pipelined = t.elapsed().as_secs_f64() * 1e3 / n;
            report.frame_pacing(frames.wall_ms, pipelined, cpu_ms / n, in_flight);
            if let Some(s) = renderer.inspect().read_laydown_stats(&prepared)? {
                report.laydown_stats(&s);
            }
            if let Some(s) = renderer.inspect().water_stats()? {
                report.water_stats(&s);
            }
            report_lighting(args, &mut report, renderer, frame, name)?;
            let t = std::time::Instant::now();
            let classified = renderer.inspect().read_classification(&prepared)?;
            let (stats, mismatch) = renderer
                .inspect()
                .classification_statistics(&prepared, &classified)?;
            report.cpu_ms(
                "read-back + CPU twin + talk measurements (CPU)",
                t.elapsed().as_secs_f64() * 1e3,
            );
            report.classification(&stats);
            if let Some(ring) = renderer.inspect().read_vertex_ring(&prepared)? {
                report.vertex_ring(&ring, &stats);
            }
            if let Some(m) = &mismatch {
                eprintln!("GPU classification differs from the CPU twin: {m}");
            }
            if !args.no_debug_views {
                let (w, h) = (args.width, args.height);
                let file = args.out.join(format!("{name}_debug_vis_ids.png"));
                gpu::inspect::debug::vis_ids(w, h, &classified.vis).write_png(&file)?;
                report.image_named("vis IDs", &file);
                let (heat, max) = gpu::inspect::debug::wave_heatmap(w, h, &classified);
                let file = args.out.join(format!("{name}_debug_waves_per_tile.png"));
                heat.write_png(&file)?;
                report.image_named(&format!("waves per tile (max {max})"), &file);
                if args.vrs != VrsArg::Off {
                    let (rates, n) = gpu::inspect::debug::shading_rate(w, h, &classified.vis);
                    let file = args.out.join(format!("{name}_debug_shading_rate.png"));
                    rates.write_png(&file)?;
                    report.image_named(
                        &format!(
                            "VRS shading rate per pixel (1x1 dark green {}, 2x1 orange {}, 2x2 red {}; 1x2 blue {})",
                            n[0], n[2], n[3], n[1]
                        ),
                        &file,
                    );
                }
                let (quads, mean) = gpu::inspect::debug::quad_overdraw(w, h, &classified.vis);
                let file = args.out.join(format!("{name}_debug_quad_overdraw.png"));
                quads.write_png(&file)?;
                report.image_named(
                    &format!("depth-equal quad overdraw (mean {mean:.2})"),
                    &file,
                );
                motion_view(args, &mut report, renderer, &prepared, frame, name)?;
            }
            if mismatch.is_some() {
                print!("{report}");
                anyhow::bail!("the GPU classification differs from its CPU twin");
            }
        }
        images.push(image);
    }
    compare_with_baseline(&mut report, paths, &images);
    if let Some(b) = paths.iter().position(|&p| p == RenderPath::Baseline) {
        for (&path, image) in paths.iter().zip(&images) {
            if path == RenderPath::Baseline {
                continue;
            }
            let file = match path {
                RenderPath::Deferred => args.out.join(format!("{}_diff.png", built.name)),
                _ => args
                    .out
                    .join(format!("{}_diff_{}.png", built.name, path.name())),
            };
            gpu::inspect::diff_image(image, &images[b]).write_png(&file)?;
            report.image_named(&format!("diff, {} vs baseline", path.name()), &file);
        }
    }
    print!("{report}");
    Ok(())
}

/// Each rendered path's image against the baseline's (`images[i]` is `paths[i]`'s), where
/// the baseline was rendered.
fn compare_with_baseline(report: &mut Report, paths: &[RenderPath], images: &[gpu::Rgba8Image]) {
    let Some(baseline) = paths
        .iter()
        .position(|&p| p == RenderPath::Baseline)
        .and_then(|b| images.get(b))
    else {
        return;
    };
    for (&path, image) in paths.iter().zip(images) {
        if path != RenderPath::Baseline {
            report.compare(
                &format!("{} vs baseline image", path.name()),
                image,
                baseline,
            );
        }
    }
}
