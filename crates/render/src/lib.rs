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
//!
//! The crate by concern: `args` (the options, their parsers and checks; the pieces `view`
//! shares come from the `cli` crate), `config` (the device and renderer they ask for),
//! `scenes` (choosing, importing and building the scenes), `city` (the static city's
//! frames), `outputs` (images, debug views) and [`report`] (the statistics table).

use anyhow::{Context, Result};
use gpu::{Renderer, RendererConfig};

mod args;
mod city;
mod config;
mod outputs;
pub mod report;
mod scenes;

pub use args::{
    Args, CameraArg, GBufferArg, LaydownArg, LaydownTargetArg, LightPathsArg, MsaaArg,
    OcclusionArg, PathArg, PrimitiveIdArg, SceneArg, VertexRingArg, VrsArg, WaterPrecisionArg,
};

/// Renders every scene `args` names; writes the images; prints the reports.
///
/// # Errors
/// Arguments that do not fit ([`Args::check`]), no adapter, a device error, an image that
/// cannot be written, or a GPU classification that differs from its CPU twin.
pub fn run(args: &Args) -> Result<()> {
    args.check()?;
    // A glTF file is imported first: its errors come before any device or directory.
    let imported = scenes::import_gltf(args)?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let ctx = gpu::headless(&args.headless_options())?;
    let config = args.renderer_config();
    // `--msaa compare`: a second renderer lighting every sample.
    let mut every_sample = match args.msaa {
        MsaaArg::Compare => Some(Renderer::new(
            &ctx.device,
            &ctx.queue,
            RendererConfig {
                image: gpu::config::ImageConfig {
                    msaa: Some(gpu::config::MsaaLighting::EverySample),
                    ..config.clone().image
                },
                ..config.clone()
            },
        )?),
        _ => None,
    };
    let mut renderer = Renderer::new(&ctx.device, &ctx.queue, config)?;
    scenes::render_chosen(args, &ctx, &mut renderer, every_sample.as_mut(), imported)
}
