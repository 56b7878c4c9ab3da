//! The `view` binary: the `gpu` renderer in a window. A demo scene (or any [`gpu::Scene`]
//! a loader returns, with its camera if it has one: [`load_scene`]) is prepared once and
//! drawn every frame through HFW's deferred texturing or HZD's depth-equal baseline; the
//! renderer's output texture is blitted to a winit window's wgpu surface on the renderer's
//! own device. A fly camera (WASD, Q/E down and up, mouse look while a button is held,
//! speed on the wheel), switches for the path, every debug view `gpu::inspect::debug` offers (shown
//! instead of the image, made on the CPU from read-backs), MSAA, the light paths and the
//! shadows (each of those recreates the renderer and prepares the scene again, as a
//! resize does), an overlay with the per-pass GPU times of the last frame (timestamp
//! queries) and the key counters, and a screenshot key (F12) writing the displayed image
//! as PNG.
//!
//! ```text
//! view --scene forest                      # open the forest in a 1280x720 window
//! view --scene grass --lights 200          # the grass field at dusk with 200 local lights
//! view --scene city --instances 200000     # HZD's static city through the GPU query
//! view --gltf scene.glb                    # your own glTF 2.0 file
//! view --scene forest --width 320 --height 180 --script-frames 5 \
//!      --camera 0,3,12,0,1,0 --screenshot out.png --exit      # scripted: tests and CI
//! ```
//!
//! Keys (when the overlay does not hold the keyboard): `W`/`A`/`S`/`D` move, `Q`/`E` down
//! and up, `Shift` four times faster, the wheel changes the speed, a held mouse button
//! looks around; `P` cycles the path (deferred, baseline, pixel pull); `0`-`8` pick a view (0 the image), `V`/`Shift+V`
//! cycle them; `M` cycles MSAA, `L` the light paths, `O` toggles the sun shadows, `C` the
//! city's static occlusion (off, the previous frame's depth, two-pass); `R` resets the
//! camera; `F1` hides the overlay; `F12` writes a screenshot; `Esc` quits.
//!
//! **Scripted mode** (`--script-frames N`): the window path renders N frames from a fixed
//! camera (`--camera`, else the scene's) at exactly `--width` x `--height` (the blit
//! letterboxes if the window came out another size), then `--screenshot` writes the
//! displayed image (read back from the same blit into an offscreen target, so the test
//! sees what the window shows, without the overlay), and `--exit` closes the viewer.
//! Animation time stays 0 in scripted mode.
//!
//! **Why egui** (through `egui-winit` 0.37 for input and `egui-wgpu` 0.37 to draw): the
//! overlay is a table rebuilt from each frame's [`gpu::FrameOutput`] and a few switches,
//! which suits an immediate-mode UI (no retained widgets to keep in step with the
//! renderer's state); egui-wgpu draws with wgpu 30 on the renderer's own device, in the
//! same render pass as the blit, so no second graphics API or context is needed; it is
//! maintained, pure Rust, and needs no system libraries beyond winit's. The 0.37 releases
//! take exactly the workspace's wgpu 30 and winit 0.30.
//!
//! The viewer needs a display: any Vulkan GPU on a desktop, or Xvfb with lavapipe (the
//! test `tests/xvfb.rs` runs it there and compares its screenshot with a headless render).

use std::path::PathBuf;

use anyhow::{Context as _, Result, bail};
use clap::{Parser, ValueEnum};
use demo::{DemoOptions, DemoScene};
use gpu::glam::Vec3;
use gpu::{Camera, Lighting, RenderPath, RendererConfig, Scene};

pub mod app;
pub mod blit;
pub mod camera;
pub mod views;

pub use views::DebugView;

/// `--scene`: the demo scenes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SceneArg {
    /// Alpha-tested foliage cards, grass tufts, trees and rocks over a terrain.
    Forest,
    /// A tall-grass field of very high vertex density.
    Grass,
    /// glTF 2.0's materials: spheres over metallic x roughness, a normal-mapped brick
    /// wall, an emissive panel, a metallic-roughness-mapped plate, leaf cards.
    Materials,
    /// HZD's static city (`--instances` of them) through the GPU static query, in front
    /// of every frame; `C` switches its occlusion.
    City,
}

/// `--path`: the rendering path the viewer starts on (`P` switches it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PathArg {
    /// Visibility buffer, GPU classification, compute material resolve (HFW).
    Deferred,
    /// Depth prepass + depth-equal geometry pass (HZD).
    Baseline,
    /// Depth prepass + depth-equal pass pulling vertices in the pixel shader (seed 004).
    PixelPull,
}

impl PathArg {
    /// The renderer's path.
    pub fn path(self) -> RenderPath {
        match self {
            PathArg::Deferred => RenderPath::Deferred,
            PathArg::Baseline => RenderPath::Baseline,
            PathArg::PixelPull => RenderPath::PixelPull,
        }
    }
}

/// `--msaa`: KZ2's 4x MSAA on the baseline path.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum MsaaArg {
    /// Single sample.
    Off,
    /// KZ2's tricks: interior pixels lit once, edges per sample with split PCF taps.
    Kz2,
    /// Every sample lit.
    EverySample,
}

impl MsaaArg {
    /// The renderer's setting.
    pub fn msaa(self) -> Option<gpu::config::MsaaLighting> {
        match self {
            MsaaArg::Off => None,
            MsaaArg::Kz2 => Some(gpu::config::MsaaLighting::Kz2),
            MsaaArg::EverySample => Some(gpu::config::MsaaLighting::EverySample),
        }
    }
}

/// `--light-paths`: the `render` binary's (the same choices and names: the `cli` crate's).
pub use cli::LightPathsArg;

/// Open a demo scene in a window and fly through it; switch paths and debug views; read the
/// per-pass GPU times live.
#[derive(Debug, Parser)]
#[command(name = "view", version, about)]
pub struct Args {
    /// Which demo scene.
    #[arg(long, value_enum, default_value = "forest")]
    pub scene: SceneArg,
    /// Open this glTF 2.0 file (`.gltf` or `.glb`) instead of a demo scene (`--scene` is
    /// ignored); its first camera, else one framing the scene.
    #[arg(long, value_name = "FILE")]
    pub gltf: Option<PathBuf>,
    /// Static instances of the city scene (about; 1 000 to 4 000 000).
    #[arg(long, default_value_t = 100_000, value_parser = clap::value_parser!(u32).range(1_000..=4_000_000))]
    pub instances: u32,
    /// Scene seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Instance density multiplier, above 0 (checked against the talk's limits before
    /// anything is built).
    #[arg(long, default_value_t = 1.0, value_parser = cli::positive_density, allow_negative_numbers = true)]
    pub density: f32,
    /// Window (and image) width in pixels, 1 to 16384.
    #[arg(long, default_value_t = 1280, value_parser = cli::image_side())]
    pub width: u32,
    /// Window (and image) height in pixels, 1 to 16384.
    #[arg(long, default_value_t = 720, value_parser = cli::image_side())]
    pub height: u32,
    /// The path to start on.
    #[arg(long, value_enum, default_value = "deferred")]
    pub path: PathArg,
    /// The view to start on (`image`: the rendered frame).
    #[arg(long, value_enum, default_value = "image")]
    pub debug_view: DebugView,
    /// The starting camera as `px,py,pz,tx,ty,tz` (eye position, then the point looked
    /// at; world metres); default: the scene's own camera.
    #[arg(long, value_parser = parse_camera, allow_negative_numbers = true)]
    pub camera: Option<Camera>,
    /// Add this many local lights (two point lights in three, the rest spots) around the
    /// camera's target, at dusk (0 to 4000).
    #[arg(long, default_value_t = 0, value_parser = cli::light_count())]
    pub lights: u32,
    /// Switch the sun off.
    #[arg(long)]
    pub no_sun: bool,
    /// KZ2's 4x MSAA on the baseline path (`M` cycles it).
    #[arg(long, value_enum, default_value = "off")]
    pub msaa: MsaaArg,
    /// How local lights reach the image (`L` cycles it).
    #[arg(long, value_enum, default_value = "tiled")]
    pub light_paths: LightPathsArg,
    /// No sun shadow maps (`O` toggles them).
    #[arg(long)]
    pub no_shadows: bool,
    /// No spot shadow maps.
    #[arg(long)]
    pub no_spot_shadows: bool,
    /// Scripted mode: render this many frames (1 to 100000) through the window at exactly
    /// `--width` x `--height` from a still camera, then take `--screenshot` (and with
    /// `--exit`, close).
    #[arg(long, value_parser = cli::frame_count())]
    pub script_frames: Option<u32>,
    /// Where screenshots go: with `--script-frames`, the PNG written after the last
    /// scripted frame; otherwise the file F12 writes (default
    /// `view-<scene>-<frame>.png` in the current directory).
    #[arg(long)]
    pub screenshot: Option<PathBuf>,
    /// Close the viewer after the scripted frames (needs `--script-frames`).
    #[arg(long, requires = "script_frames")]
    pub exit: bool,
    /// Start with the overlay hidden (`F1` shows it).
    #[arg(long)]
    pub no_overlay: bool,
}

/// A camera given as `px,py,pz,tx,ty,tz`: six finite numbers, the target away from the eye.
///
/// # Errors
/// A message saying what is wrong (clap puts the flag's name in front of it).
pub fn parse_camera(s: &str) -> Result<Camera, String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != 6 {
        return Err(format!(
            "`{s}` has {} numbers; expected six: px,py,pz,tx,ty,tz",
            parts.len()
        ));
    }
    let mut v = [0f32; 6];
    for (slot, p) in v.iter_mut().zip(&parts) {
        let x: f32 = p.parse().map_err(|_| format!("`{p}` is not a number"))?;
        if !x.is_finite() || x.abs() > 1e7 {
            return Err(format!("{p} is not a finite number within ±1e7 metres"));
        }
        *slot = x;
    }
    let position = Vec3::new(v[0], v[1], v[2]);
    let target = Vec3::new(v[3], v[4], v[5]);
    let camera = Camera::look_at(position, target);
    camera
        .validate()
        .map_err(|e| format!("camera {position} -> {target}: {e}"))?;
    Ok(camera)
}

/// Where a scene comes from: a demo scene, the static city or a glTF 2.0 file.
#[derive(Clone, Debug, PartialEq)]
pub enum SceneSource {
    /// A procedural demo scene.
    Demo(DemoOptions),
    /// The static city of about this many instances (`demo::city`).
    City(usize),
    /// A `.gltf` or `.glb` file, imported by `gltf_scene`.
    Gltf(PathBuf),
}

impl SceneSource {
    /// A short name for titles and file names.
    pub fn name(&self) -> String {
        match self {
            SceneSource::Demo(o) => o.scene.name().to_string(),
            SceneSource::City(_) => "city".to_string(),
            SceneSource::Gltf(p) => p
                .file_stem()
                .map_or_else(|| "gltf".into(), |s| s.to_string_lossy().into_owned()),
        }
    }
}

/// What a loader hands the viewer: the scene, its camera if it has one (otherwise the
/// viewer frames the scene's bounds: `gltf_scene::framing_camera`), its lighting, and
/// for the city its static world (streamed into a `gpu::statics::StaticQuery` on the viewer's
/// device, queried in front of every frame).
#[derive(Clone)]
pub struct LoadedScene {
    /// A short name for titles and file names.
    pub name: String,
    /// The scene.
    pub scene: Scene,
    /// The scene's own camera, if it has one.
    pub camera: Option<Camera>,
    /// Sun, sky and local lights.
    pub lighting: Lighting,
    /// The static city, for a scene with static content.
    pub city: Option<std::sync::Arc<demo::city::City>>,
}

impl std::fmt::Debug for LoadedScene {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LoadedScene")
            .field("name", &self.name)
            .field("instances", &self.scene.instance_count())
            .field("camera", &self.camera)
            .field("city", &self.city.is_some())
            .finish_non_exhaustive()
    }
}

/// Loads `source`.
///
/// # Errors
/// A demo density over the talk's limits (naming `--density` and the largest that fits);
/// a glTF file that cannot be imported (naming the file, the object and the problem).
pub fn load_scene(source: &SceneSource) -> Result<LoadedScene> {
    match source {
        SceneSource::Gltf(path) => {
            let imported = gltf_scene::load(path, &gltf_scene::LoadOptions::default())
                .with_context(|| format!("--gltf {}", path.display()))?;
            for w in &imported.warnings {
                eprintln!("warning: {w}");
            }
            Ok(LoadedScene {
                name: source.name(),
                scene: imported.scene,
                camera: imported.camera,
                lighting: Lighting::default(),
                city: None,
            })
        }
        SceneSource::City(instances) => {
            let city = demo::city::city(*instances);
            Ok(LoadedScene {
                name: source.name(),
                scene: city.scene.clone(),
                camera: Some(city.frame.camera),
                lighting: city.frame.lighting.clone(),
                city: Some(std::sync::Arc::new(city)),
            })
        }
        SceneSource::Demo(options) => {
            cli::check_density(options)?;
            let (scene, frame) = demo::build(options);
            Ok(LoadedScene {
                name: source.name(),
                scene,
                camera: Some(frame.camera),
                lighting: frame.lighting,
                city: None,
            })
        }
    }
}

impl Args {
    /// The scene the arguments name.
    pub fn source(&self) -> SceneSource {
        if let Some(path) = &self.gltf {
            return SceneSource::Gltf(path.clone());
        }
        SceneSource::Demo(DemoOptions {
            scene: match self.scene {
                SceneArg::Forest => DemoScene::Forest,
                SceneArg::Grass => DemoScene::Grass,
                SceneArg::Materials => DemoScene::Materials,
                SceneArg::City => return SceneSource::City(self.instances as usize),
            },
            seed: self.seed,
            density: self.density,
        })
    }

    /// The renderer configuration the arguments ask for, at `width` x `height`; the rest
    /// as [`RendererConfig::default`].
    pub fn renderer_config(&self, width: u32, height: u32) -> RendererConfig {
        {
            let mut rc = RendererConfig::sized(width, height);
            rc.image.msaa = self.msaa.msaa();
            rc.lighting.light_paths = self.light_paths.paths();
            rc.lighting.shadows = (!self.no_shadows).then(gpu::config::ShadowConfig::default);
            rc.lighting.spot_shadows =
                (!self.no_spot_shadows).then(gpu::config::SpotShadowConfig::default);
            rc
        }
    }

    /// Checks what clap cannot alone.
    ///
    /// # Errors
    /// A combination the renderer refuses, named by its flags.
    pub fn check(&self) -> Result<()> {
        if self.msaa != MsaaArg::Off && self.light_paths.paths().volumes() {
            bail!(
                "--msaa {:?} needs --light-paths tiled or every-pixel (stencil volumes are single-sample)",
                self.msaa
            );
        }
        if self
            .screenshot
            .as_ref()
            .is_some_and(|p| p.as_os_str().is_empty())
        {
            bail!("--screenshot: an empty file name");
        }
        Ok(())
    }

    /// The lighting of the first frame: the scene's, dusk with `--lights` local lights
    /// scattered within 25 m of `target`, the sun off with `--no-sun`.
    pub fn lighting(&self, lighting: Lighting, target: Vec3) -> Lighting {
        let lights = cli::LocalLights {
            no_sun: self.no_sun,
            count: self.lights,
            half_extent: 25.0,
            seed: self.seed,
        };
        cli::lighting(lighting, target, &lights)
    }
}

/// Opens the window and runs the viewer until it is closed (or the script ends).
///
/// # Errors
/// Bad arguments ([`Args::check`]), a scene that does not load, no display, no adapter
/// that can present to the window, a device or renderer error, or a screenshot that
/// cannot be written.
pub fn run(args: Args) -> Result<()> {
    args.check()?;
    let loaded = load_scene(&args.source())?;
    app::run(args, loaded)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cameras_parse_and_bad_ones_are_refused() {
        let c = parse_camera("0, 3, 12, 0,1,0").unwrap();
        assert_eq!(c.position, Vec3::new(0.0, 3.0, 12.0));
        assert_eq!(c.target, Vec3::new(0.0, 1.0, 0.0));
        assert!(parse_camera("1,2,3").unwrap_err().contains("six"));
        assert!(parse_camera("1,2,3,4,5,x").unwrap_err().contains("`x`"));
        assert!(parse_camera("1,2,3,4,5,inf").is_err());
        assert!(parse_camera("1,2,3,1,2,3").is_err());
    }

    #[test]
    fn flags_are_named_in_errors() {
        let e = Args::try_parse_from(["view", "--camera", "1,2"]).unwrap_err();
        assert!(e.to_string().contains("--camera"), "{e}");
        let e = Args::try_parse_from(["view", "--width", "0"]).unwrap_err();
        assert!(e.to_string().contains("--width"), "{e}");
        let e = Args::try_parse_from(["view", "--exit"]).unwrap_err();
        assert!(e.to_string().contains("--script-frames"), "{e}");
        let a =
            Args::try_parse_from(["view", "--msaa", "kz2", "--light-paths", "volumes"]).unwrap();
        assert!(a.check().unwrap_err().to_string().contains("--msaa"));
        let a = Args::try_parse_from(["view", "--density", "1e9"]).unwrap();
        let e = load_scene(&a.source()).unwrap_err();
        assert!(format!("{e:#}").contains("--density"), "{e:#}");
    }

    #[test]
    fn a_missing_gltf_file_is_an_error_naming_it() {
        let a = Args::try_parse_from(["view", "--gltf", "/nonexistent/scene.glb"]).unwrap();
        assert_eq!(a.source().name(), "scene");
        let e = load_scene(&a.source()).unwrap_err();
        assert!(format!("{e:#}").contains("scene.glb"), "{e:#}");
    }
}
