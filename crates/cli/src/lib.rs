//! The command-line pieces the `render` and `view` binaries share, so that neither
//! depends on the other: [`LightPathsArg`] (`--light-paths`, the same choices in both),
//! the value parsers whose limits and messages both binaries give ([`image_side`],
//! [`light_count`], [`frame_count`], [`positive_density`], [`number_between`]), the
//! density check that names `--density` ([`check_density`]) and the first frame's
//! lighting from `--no-sun` and `--lights` ([`lighting`]).
//!
//! Each binary keeps its own `Args` (its options, defaults and help text are its own); the
//! pieces here only give both the same parsing and the same meaning. Every parser returns
//! a message instead of panicking; clap puts the flag's name in front of it.
//!
//! ```
//! use clap::Parser;
//!
//! #[derive(Parser)]
//! struct Args {
//!     #[arg(long, value_enum, default_value = "tiled")]
//!     light_paths: cli::LightPathsArg,
//!     #[arg(long, default_value_t = 1.0, value_parser = cli::positive_density)]
//!     density: f32,
//! }
//!
//! let args = Args::try_parse_from(["x", "--light-paths", "every-pixel"]).unwrap();
//! assert_eq!(args.light_paths.paths(), gpu::config::LightPaths::EveryPixel);
//! assert!(Args::try_parse_from(["x", "--density", "0"]).is_err());
//! ```

use anyhow::Context as _;
use clap::ValueEnum;
use clap::builder::RangedI64ValueParser;
use demo::DemoOptions;
use gpu::Lighting;
use gpu::glam::Vec3;

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

/// `--width` and `--height`: an image side in pixels, 1 to 16384.
pub fn image_side() -> RangedI64ValueParser<u32> {
    clap::value_parser!(u32).range(1..=16384)
}

/// `--lights`: a number of local lights, 0 to 4000.
pub fn light_count() -> RangedI64ValueParser<u32> {
    clap::value_parser!(u32).range(0..=4000)
}

/// `render --frames` and `view --script-frames`: a number of frames, 1 to 100000.
pub fn frame_count() -> RangedI64ValueParser<u32> {
    clap::value_parser!(u32).range(1..=100_000)
}

/// `--density`: a finite number above zero.
///
/// # Errors
/// `s` is not a number, or not a finite one above zero.
pub fn positive_density(s: &str) -> Result<f32, String> {
    let d = number(s)?;
    if d.is_finite() && d > 0.0 {
        Ok(d)
    } else {
        Err(format!("{s} is not a finite number above 0"))
    }
}

/// A number from `lo` to `hi` (both included; finite bounds), `unit` (with its leading
/// space, or empty) named in the message.
///
/// # Errors
/// `s` is not a number, or not one within the bounds (NaN never is).
pub fn number_between(s: &str, lo: f32, hi: f32, unit: &str) -> Result<f32, String> {
    let v = number(s)?;
    if (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        Err(format!("{s} is not between {lo} and {hi}{unit}"))
    }
}

/// `s` as a number (white space around it allowed).
fn number(s: &str) -> Result<f32, String> {
    s.trim()
        .parse()
        .map_err(|_| format!("`{s}` is not a number"))
}

/// Checks a demo scene's density against the talk's limits, the error naming `--density`
/// and the scene (and, from `demo`, the limit and the largest density that fits).
///
/// # Errors
/// The density does not fit.
pub fn check_density(options: &DemoOptions) -> anyhow::Result<()> {
    demo::check_density(options)
        .with_context(|| format!("--density for the {} scene", options.scene.name()))
}

/// `--no-sun` and `--lights`: what [`lighting`] changes in a scene's lighting.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocalLights {
    /// Switch the sun off.
    pub no_sun: bool,
    /// How many local lights to add (none: the scene's own lights and daylight).
    pub count: u32,
    /// Half-size in metres of the square around the target they are scattered over.
    pub half_extent: f32,
    /// Where they fall (`demo::scatter_lights`'s seed).
    pub seed: u64,
}

/// `lighting` with the sun off for `--no-sun`, and for `--lights` dusk (sun and ambient
/// dimmed so that local lights show) with [`LocalLights::count`] lights scattered around
/// `target` (`demo::scatter_lights`).
pub fn lighting(mut lighting: Lighting, target: Vec3, lights: &LocalLights) -> Lighting {
    if lights.no_sun {
        lighting.sun_color = Vec3::ZERO;
    }
    if lights.count > 0 {
        // Dusk, so that the lights show.
        lighting.sun_color *= 0.12;
        lighting.ambient *= 0.35;
        demo::scatter_lights(
            &mut lighting,
            target,
            lights.half_extent,
            lights.count as usize,
            lights.seed,
        );
    }
    lighting
}
