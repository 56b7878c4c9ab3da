//! Killzone 2's deferred-shading pieces (Valient, GDC 2009, seed 002), each a CPU function
//! that is the reference for its WGSL twin: the G-buffer encodings the material pass
//! writes and the lighting pass reads.
//!
//! - [`gbuffer`]: what a G-buffer sample holds ([`Surface`]), KZ2's four-RGBA8 layout as a
//!   named preset ([`GBufferLayout::Kz2`]) and the improved octahedral-normal layout
//!   ([`GBufferLayout::Octahedral`]), with the wgpu format and channel meaning of every
//!   target, and the pack/unpack of each ([`Kz2Texels`], [`OctTexels`]).
//! - [`normal`]: the octahedral 12+12-bit normal code (fast and precise encoders) and KZ2's
//!   view-space X/Y-as-f16 encoding, with its negative-z failure measured
//!   ([`normal::negative_z_fraction`]).
//!
//! `#![no_std]` without allocation; float math through `std` (default) or the `libm`
//! feature.
//!
//! ```
//! use deferred::{GBufferLayout, OctTexels, Surface};
//! use glam::{Vec2, Vec3};
//!
//! let s = Surface {
//!     albedo: Vec3::new(0.8, 0.4, 0.1),
//!     normal: Vec3::new(0.0, 0.6, 0.8), // world space for the octahedral layout
//!     roughness: 0.35,
//!     motion: Vec2::new(1.5, -0.25),
//!     ..Surface::default()
//! };
//! let texels = OctTexels::pack(&s); // the bytes of RT0..RT3
//! let back = texels.unpack();
//! assert!(back.normal.angle_between(s.normal).to_degrees() < 0.05);
//! assert_eq!(back.motion, s.motion);
//! assert_eq!(GBufferLayout::Octahedral.color_formats()[1].wgpu_name(), "Rgba8Uint");
//! ```
//!
//! # WGSL
//!
//! Binding-free snippets, each a string constant ([`GBUFFER_WGSL`]; [`WGSL`] is all of them
//! concatenated). They hold only `const`s, structs and functions, every name prefixed
//! `deferred_` / `DEFERRED_` / `Deferred`, and need no optional capability (naga validates
//! each with `Caps::CORE`). Each `const` equals the Rust constant of the same meaning: unit
//! tests read them back.
//!
//! **[`GBUFFER_WGSL`]** (the tables in [`gbuffer`] give every target's format and channels)
//!
//! | WGSL | takes | gives |
//! | --- | --- | --- |
//! | `DeferredSurface` | - | [`Surface`]: `lighting`, `albedo`, `normal`, `roughness`, `specular`, `sun_shadow`, `motion` |
//! | `deferred_gbuffer_kz2_pack(s)` | surface, view-space normal | `DeferredKz2Targets { rt0, rt1, rt2, rt3 }`: four `vec4<f32>` for the four `rgba8unorm` targets |
//! | `deferred_gbuffer_kz2_unpack(rt0, rt1, rt2, rt3)` | the four `vec4<f32>` `textureLoad` returns | `DeferredSurface` (normal `z >= 0`) |
//! | `deferred_gbuffer_oct_pack(s)` | surface, world-space normal | `DeferredOctTargets { rt0: vec4<f32>, rt1: vec4<u32>, rt2: vec4<f32>, rt3: vec4<f32> }` for `rgba8unorm`, `rgba8uint`, `rgba16float`, `rgba8unorm` |
//! | `deferred_gbuffer_oct_unpack(rt0, rt1, rt2, rt3)` | the values `textureLoad` returns | `DeferredSurface` |
//! | `deferred_oct_encode(n)` / `deferred_oct_encode_fast(n)` / `deferred_oct_decode(word)` | direction / 24-bit code | [`normal::oct_encode_precise`], [`normal::oct_encode_fast`], [`normal::oct_decode`] |
//! | `deferred_kz2_normal_encode(n)` / `deferred_kz2_normal_decode(word)` | view normal / word | [`normal::kz2_encode_view_normal`], [`normal::kz2_decode_view_normal`] |
//! | `deferred_pack_half(x)` / `deferred_unpack_half(bits)` / `deferred_f16_round(x)` | f32 / f16 bits | binary16, round to nearest even |
//! | `deferred_srgb_encode(x)` / `deferred_srgb_decode(x)` | `[0, 1]` | [`gbuffer::srgb_encode`], [`gbuffer::srgb_decode`] |
//! | `deferred_spec_power_from_roughness(r)` / `deferred_roughness_from_spec_power(p)` | | [`gbuffer::spec_power_from_roughness`], [`gbuffer::roughness_from_spec_power`] |
//! | `deferred_unpack_lighting(rt0)` | RT0 value | HDR lighting ([`gbuffer::reconstruct_hdr`]) |
//!
//! The pack functions quantise exactly as the Rust side does (they store `code / 255` into
//! unorm8 channels and f16-representable values into f16 channels, so the hardware's
//! conversion is exact): a readback of the targets equals [`Kz2Texels::pack`] /
//! [`OctTexels::pack`] byte for byte, up to one code where `pow` (sRGB) or `log2` round
//! differently on the device.

#![no_std]

#[cfg(test)]
extern crate alloc;
#[cfg(feature = "std")]
extern crate std;

#[cfg(not(any(feature = "std", feature = "libm")))]
compile_error!("deferred needs float math: enable the `std` (default) or `libm` feature");

pub mod cascades;
pub mod depth;
mod error;
pub mod gbuffer;
pub mod lights;
mod math;
pub mod msaa;
pub mod normal;
mod tables;
mod wgsl;

pub use cascades::{
    Cascade, CascadeCamera, CascadeParams, DeferredCascade, StableCascades, practical_splits,
};
pub use depth::{DeferredProjection, DepthMode, Linearize, Perspective};
pub use error::Error;
pub use gbuffer::{GBufferLayout, Kz2Texels, NormalSpace, OctTexels, Surface, TargetFormat};
/// The `glam` this crate's API uses (re-exported so callers match its version).
pub use glam;
pub use lights::{
    DeferredLight, DeferredTileDepth, LightClass, LightClassifier, LightPath, ShadowFade,
    cull_tiles, tile_depth_ranges,
};
pub use wgsl::{DEPTH_WGSL, GBUFFER_WGSL, LIGHTS_WGSL, SHADOW_WGSL, WGSL};
