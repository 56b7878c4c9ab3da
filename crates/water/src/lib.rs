//! Far Cry 5's water (GDC 2018, seed 003) as CPU code that is the reference for its WGSL
//! twins.
//!
//! (Crate docs are completed below as modules land.)
//!
//! ```
//! let tex = water::noise::NoiseTexture::default_water();
//! let fbm = water::noise::Fbm::new(&tex, water::noise::FbmParams::default())?;
//! let s = fbm.sample(glam::Vec2::new(10.0, 20.0), 100.0);
//! assert!(s.octaves < 9.0 && s.dropped_variance > 0.0);
//! # Ok::<(), water::Error>(())
//! ```

#![no_std]
// `!(x > 0.0)` is how this crate says "not positive, or NaN": user input can be NaN and
// must land in the safe branch, which `x <= 0.0` would not do.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

extern crate alloc;
#[cfg(feature = "std")]
extern crate std;

#[cfg(not(any(feature = "std", feature = "libm")))]
compile_error!("water needs float math: enable the `std` (default) or `libm` feature");

pub mod atlas;
pub mod decal;
pub mod edt;
mod error;
pub mod flow;
pub mod flowbake;
pub mod foam;
pub mod gbuffer;
pub mod hash;
pub mod material;
pub mod math;
pub mod noise;
pub mod normals;
pub mod optics;
#[cfg(feature = "parallel")]
pub mod parallel;
pub mod progress;
pub mod specaa;
pub mod tiles;
mod wgsl;
pub mod world;

pub use error::Error;
pub use progress::{Progress, Stage, no_progress};
pub use wgsl::{
    ATLAS_WGSL, DECAL_WGSL, FLOW_WGSL, FOAM_WGSL, GBUFFER_WGSL, MATERIAL_WGSL, NOISE_WGSL,
    NORMALS_WGSL, OPTICS_WGSL, SPECAA_WGSL, TILES_WGSL, WGSL, WORLD_WGSL,
};
