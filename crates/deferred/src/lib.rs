//! Killzone 2's deferred-shading pieces (Valient, "The Rendering Technology of Killzone
//! 2", GDC 2009, seed 002), each a CPU function that is the reference for its WGSL twin:
//! the G-buffer the material pass writes and the lighting pass reads, position from depth,
//! tiled light culling with KZ2's per-light decisions, stable cascaded shadow maps, and
//! the MSAA tricks.
//!
//! - [`gbuffer`]: what a G-buffer sample holds ([`Surface`]), KZ2's four-RGBA8 layout as a
//!   named preset ([`GBufferLayout::Kz2`]) and the improved octahedral-normal layout
//!   ([`GBufferLayout::Octahedral`]), with the wgpu format and channel meaning of every
//!   target, and the pack/unpack of each ([`Kz2Texels`], [`OctTexels`]).
//! - [`normal`]: the octahedral 12+12-bit normal code (nearest and precise encoders) and
//!   KZ2's view-space X/Y-as-f16 encoding, with its negative-z failure measured
//!   ([`normal::negative_z_fraction`]).
//! - [`depth`]: view- and world-space position from the depth buffer, standard or reversed
//!   Z, finite or infinite far plane ([`Perspective`], [`DeferredProjection`]).
//! - [`lights`]: tiled light culling, the CPU twin of a two-pass compute culling
//!   ([`tile_depth_ranges`], [`cull_tiles`]), point and spot lights ([`DeferredLight`]),
//!   exact sphere screen rectangles, KZ2's light-volume / depth-bounds classification and
//!   small-light shadow fade ([`LightClassifier`], [`ShadowFade`]).
//! - [`pass`]: the light culling as a GPU compute pass ([`pass::LIGHT_CULL_PASS`], WGSL
//!   `deferred::light_cull_pass` in [`wgsl::PASS_MODULES`]), the twin of [`cull_tiles`]
//!   (device tests compare the two; `gpu` runs it in its frame).
//! - [`cascades`]: stable cascaded shadow maps in f64: practical splits, rotation-invariant
//!   slice spheres, texel-snapped world-anchored projections ([`StableCascades`]).
//! - [`msaa`]: the PCF kernel split into per-sample tap subsets for 2x and 4x
//!   ([`msaa::split_taps`]) and the edge-pixel classifier ([`msaa::classify_edges`]).
//!
//! `#![no_std]` without allocation; float math through `std` (default) or the `libm`
//! feature. Every fallible entry point returns [`Error`]; packing sanitises instead of
//! failing (NaN to 0, values clamped to their ranges).
//!
//! ```
//! use deferred::{GBufferLayout, OctTexels, Surface};
//! use deferred::glam::{Vec2, Vec3};
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
//!
//! // Tiled light culling: tile depth ranges, then per-tile light lists.
//! use deferred::lights::{MAX_LIGHTS_PER_TILE, tile_counts};
//! use deferred::{DeferredLight, DeferredTileDepth, DepthMode, Perspective};
//! let (w, h) = (64, 32);
//! let p = Perspective::try_new(1.0, 2.0, 0.1, None, DepthMode::Reversed)?;
//! let depth = vec![p.linearize().depth(10.0); w * h]; // a wall 10 m away
//! let (tx, ty) = tile_counts(w as u32, h as u32);
//! let mut tiles = vec![DeferredTileDepth::default(); (tx * ty) as usize];
//! deferred::tile_depth_ranges(&depth, w as u32, h as u32, DepthMode::Reversed, &mut tiles)?;
//! let lights = [DeferredLight::point(Vec3::new(0.0, 0.0, -9.0), 2.0, Vec3::ONE)];
//! let mut counts = vec![0; tiles.len()];
//! let mut indices = vec![0; tiles.len() * MAX_LIGHTS_PER_TILE as usize];
//! let proj = p.gpu(Vec2::new(w as f32, h as f32));
//! let stats = deferred::cull_tiles(&proj, &tiles, &lights, &mut counts, &mut indices)?;
//! assert!(stats.pairs > 0 && stats.pairs < tiles.len() as u64);
//! # Ok::<(), deferred::Error>(())
//! ```
//!
//! # The G-buffer from wgpu
//!
//! Create one texture per entry of [`GBufferLayout::color_formats`] (in that order: RT0..
//! RT3; [`TargetFormat::wgpu_name`] is the `wgpu::TextureFormat` variant) with
//! `RENDER_ATTACHMENT | STORAGE_BINDING | TEXTURE_BINDING`: every colour format of both
//! layouts is storage-capable and 4x-multisampleable in core wgpu. A compute material pass
//! writes a sample with the layout's pack function and `textureStore`; lighting reads the
//! four texels with `textureLoad` and unpacks. The octahedral layout:
//!
//! ```wgsl
//! #import deferred::gbuffer
//! @group(1) @binding(0) var rt0: texture_storage_2d<rgba16float, write>; // RT0: lighting rgb (HDR)
//! @group(1) @binding(1) var rt1: texture_storage_2d<rgba8uint, write>;   // RT1: normal code + roughness
//! @group(1) @binding(2) var rt2: texture_storage_2d<rgba16float, write>; // RT2: motion xy, specular, metallic
//! @group(1) @binding(3) var rt3: texture_storage_2d<rgba8unorm, write>;  // RT3: albedo (sRGB) + sun shadow
//!
//! fn write_gbuffer(pixel: vec2<u32>, s: DeferredSurface) {
//!     let t = deferred_gbuffer_oct_pack(s); // s.normal: world (or camera-relative) space
//!     textureStore(rt0, pixel, t.rt0);
//!     textureStore(rt1, pixel, t.rt1);
//!     textureStore(rt2, pixel, t.rt2);
//!     textureStore(rt3, pixel, t.rt3);
//! }
//!
//! // In the lighting pass, with the same textures bound as texture_2d<f32> / <u32>:
//! fn read_gbuffer(pixel: vec2<i32>) -> DeferredSurface {
//!     return deferred_gbuffer_oct_unpack(textureLoad(g0, pixel, 0), textureLoad(g1, pixel, 0),
//!                                        textureLoad(g2, pixel, 0), textureLoad(g3, pixel, 0));
//! }
//! ```
//!
//! For KZ2's preset all four targets are `rgba8unorm` (`vec4<f32>` values both ways),
//! `deferred_gbuffer_kz2_pack` wants a *view-space* normal (multiply a world normal by the
//! view rotation first) and `deferred_gbuffer_kz2_unpack` returns one with `z >= 0`. A
//! render-pass geometry pass returns the same four values from its fragment shader at
//! `@location(0..3)`. Position is not stored: reconstruct it from depth with `deferred::depth`
//! (`deferred_view_position`, or `deferred_position_from_inverse` with the inverse
//! view-projection for camera-relative world space).
//!
//! # WGSL
//!
//! Binding-free library modules ([`wgsl::MODULES`]), imported by a pass with `#import
//! deferred::gbuffer` and the like and composed by the `shader` crate. They hold only
//! `const`s, structs and functions, every name prefixed `deferred_` / `DEFERRED_` /
//! `Deferred`, and need no optional capability (naga validates each with `Caps::CORE`).
//! Each `const` equals the Rust constant of the same meaning and each struct has the Rust
//! struct's layout: unit tests read them back. `tests/device.rs` runs the G-buffer pack and
//! unpack (both layouts), `deferred_view_position` and the tile-frustum light test on a
//! device against the Rust functions; on lavapipe, of 20 003 surfaces, 2 sRGB codes and 1
//! specular code come out one off (the device's `pow`), and the light-in-tile decisions
//! are equal. The shadow lookup (`deferred::shadow`), `deferred_position_from_inverse` and
//! the depth-bounds tests are checked by naga only until a pass dispatches them.
//!
//! **`deferred::gbuffer`** ([`wgsl::GBUFFER`]; the tables in [`gbuffer`] give every target's format and channels)
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
//! **`deferred::depth`** ([`wgsl::DEPTH`]; conventions in [`depth`])
//!
//! | WGSL | takes | gives |
//! | --- | --- | --- |
//! | `DeferredProjection` | - | [`DeferredProjection`], 32 bytes: `tan_half`, `alpha`, `beta`, `viewport` ([`Perspective::gpu`]) |
//! | `deferred_view_distance(p, depth)` / `deferred_depth_of_distance(p, d)` | depth value / view distance | view distance (`-z`) / depth value |
//! | `deferred_view_position(p, pixel, depth)` | pixel position (centres at +0.5), depth | view-space position |
//! | `deferred_position_from_inverse(inv, pixel, viewport, depth)` | inverse (view-)projection | view / world position, any projection |
//! | `deferred_ndc_from_pixel(pixel, inv_viewport)` | pixel position | NDC `xy` |
//!
//! **`deferred::lights`** ([`wgsl::LIGHTS`], imports `deferred::depth`; conventions in [`lights`])
//!
//! | WGSL | takes | gives |
//! | --- | --- | --- |
//! | `DeferredLight` / `DeferredTileDepth` | - | [`DeferredLight`] (48 bytes), [`DeferredTileDepth`] (8 bytes) |
//! | `deferred_tile_frustum(p, tile, depth)` | projection, tile coordinates, tile depth range | `DeferredTileFrustum` ([`lights::TileFrustum`]) |
//! | `deferred_light_in_tile(f, light)` | tile frustum, view-space light | whether to list the light ([`lights::TileFrustum::light_visible`]) |
//! | `deferred_light_affects(light, p)` | light, view-space point | inside its volume ([`DeferredLight::affects`]) |
//! | `deferred_light_bounding_sphere(light)` | light | `vec4(centre, radius)` ([`DeferredLight::bounding_sphere`]) |
//! | `deferred_depth_bounds_overlap(tile, bounds, reversed)` | tile depth range, [`LightClass::depth_bounds`] | the depth-bounds test per tile ([`lights::depth_bounds_overlap`]) |
//! | `deferred_tile_is_empty(tile, far_depth)` | tile depth | no geometry in the tile |
//!
//! **`deferred::shadow`** ([`wgsl::SHADOW`])
//!
//! | WGSL | takes | gives |
//! | --- | --- | --- |
//! | `DeferredCascade` | - | [`DeferredCascade`], 80 bytes ([`cascades::Cascade::gpu`]) |
//! | `deferred_shadow_coord(c, rel)` | cascade, camera-relative position | shadow-map `uv` (+v down) and depth |
//! | `DeferredPcfTap` | - | [`msaa::DeferredPcfTap`], 16 bytes ([`msaa::TapSplit::taps`]) |
//! | `deferred_words_differ(a, b)` / `deferred_depth_differs(d0, d, tol)` | two samples' words / depths | the edge tests of [`msaa::is_edge`] |

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
pub mod pass;
mod tables;
pub mod wgsl;

pub use cascades::{
    Cascade, CascadeCamera, CascadeParams, DeferredCascade, StableCascades, practical_splits,
};
pub use depth::{DeferredProjection, DepthMode, Linearize, Perspective};
pub use error::Error;
pub use gbuffer::{GBufferLayout, Kz2Texels, NormalSpace, OctTexels, Surface, TargetFormat};
/// The glam version this crate's API uses; use `deferred::glam` to avoid a version mismatch
/// with a `glam` of your own.
pub use glam;
pub use lights::{
    DeferredLight, DeferredTileDepth, LightClass, LightClassifier, LightPath, ShadowFade,
    cull_tiles, tile_depth_ranges,
};
