//! Far Cry 5's water (Grudzik and Kudocheres, GDC 2018; seed 003) as CPU code that is the
//! reference for its WGSL twins: the one water query physics and gameplay call, the surface
//! detail, the offline bakes, and the per-pixel inputs of the screen-space tessellation
//! and lighting passes.
//!
//! ```
//! use water::glam::{Vec2, Vec3};
//! use water::world::{Lake, Ocean, River, RiverPoint, WaterWorldBuilder};
//!
//! // One query for every kind of water: a lake, a river (slopes and waterfalls allowed)
//! // and the ocean, baked into one word array that the GPU reads too.
//! let mut b = WaterWorldBuilder::new();
//! b.ocean = Some(Ocean { level: 0.0, material: 0 });
//! b.lakes.push(Lake {
//!     polygon: vec![Vec2::new(0.0, 0.0), Vec2::new(50.0, 0.0), Vec2::new(50.0, 40.0), Vec2::new(0.0, 40.0)],
//!     height: 12.0,
//!     material: 1,
//! });
//! let point = |x: f32, z: f32| RiverPoint { position: Vec3::new(x, 100.0, z), width: 10.0, depth: 2.0, speed: 3.0 };
//! b.rivers.push(River { points: vec![point(0.0, 30.0), point(100.0, 25.0)], material: 2 });
//! let world = b.build(&mut water::no_progress)?;
//!
//! let lake = world.query(Vec2::new(25.0, 20.0)).unwrap();
//! assert_eq!((lake.height, lake.material), (12.0, 1));
//! let river = world.query(Vec2::new(50.0, 101.0)).unwrap();
//! assert!((river.height - 27.5).abs() < 0.05 && river.flow.x > 2.0);
//! assert_eq!(world.query(Vec2::new(500.0, 500.0)).unwrap().height, 0.0); // the ocean
//! assert!(world.query(Vec2::NAN).is_none());
//!
//! // Surface detail: 9 octaves near, fading to 3 far, with the slope variance the fade
//! // drops, for specular anti-aliasing.
//! let noise = water::noise::NoiseTexture::default_water();
//! let fbm = water::noise::Fbm::new(&noise, water::noise::FbmParams::default())?;
//! let s = fbm.sample(Vec2::new(10.0, 20.0), 200.0);
//! let alpha = water::specaa::filtered_alpha(0.05, s.dropped_variance, water::specaa::DEFAULT_KAPPA, 1.0);
//! assert!(s.octaves < 9.0 && alpha > 0.05);
//! # Ok::<(), water::Error>(())
//! ```
//!
//! # What is where
//!
//! | module | the talk's piece |
//! | --- | --- |
//! | [`world`] | the water query API: [`world::WaterWorld`] answers height, body, material, bed depth and flow at a world position (lakes exact, rivers baked to height tiles, ocean; a quadtree finds the body) |
//! | [`noise`] | the tileable noise texture (integer-hashed gradient noise) and FBM: frequency doubling, 9 octaves near and 3 far with a smooth fade, the dropped octaves' slope variance |
//! | [`flow`] | flow maps sampled with two phase-offset layers (Vlachos 2010), the per-pixel phase noise |
//! | [`foam`] | foam from the shore distance, flow speed and shallows, noise modulated by noise, plus displacement foam |
//! | [`decal`] | vector displacement decals: projected boxes faded to zero at their edges, max-blended |
//! | [`material`] | water materials, blended over a distance (6 m by default) on only the fields that need it |
//! | [`edt`] | the exact signed Euclidean distance transform of a shore / rock mask (Felzenszwalb–Huttenlocher) |
//! | [`flowbake`] | flow baking by an SDF-guided flood fill from river splines and sources |
//! | [`atlas`] | the world flow map (8 m per texel) and the high-resolution tile atlas, found through a sector remap table stored in the same texture |
//! | [`optics`] | light transport: a table of water types, Beer–Lambert transmittance, single scattering |
//! | [`specaa`] | variance-based specular anti-aliasing (Tokuyoshi and Kaplanyan 2019) |
//! | [`normals`] | normals from depth without derivatives (5 and 9 taps), radius growing near the camera, blend with the mesh normal |
//! | [`gbuffer`] | the mini G-buffer's data word (shader ID, flags, material, foam and algae mips) |
//! | [`draw`] | what the renderer draws a world from: the near bodies' low-resolution meshes, the far sectors' quadtree, the 6 m material map, and their limits |
//! | [`tiles`] | 32 x 32 screen-tile classification, the indirect draw, the tessellated grid with 16-bit vertices and degenerate-triangle kills |
//! | [`parallel`] | rayon versions of the distance transform and the flow bake (feature `parallel`; equal results) |
//! | [`progress`] | progress reporting and cancellation for the bakers |
//! | [`axes`] | the conversion between this crate's +Z-up world and the renderer's +Y up |
//! | [`math`], [`hash`] | the one module for transcendental functions (`libm`), the PCG integer hash |
//!
//! # Conventions
//!
//! - World space is metres, right-handed, **+Z up**: horizontal positions are `(x, y)`,
//!   heights are z. Flow is m/s along +x and +y. This differs from the rest of the
//!   workspace (`gpu`, `deferred`'s cascades and `staticscene`'s demo are +Y up):
//!   [`axes`] holds the one conversion, `(x, y, z)` here is `(x, z, -y)` there
//!   ([`axes::y_up_from_z_up`], [`axes::z_up_from_y_up`], [`axes::horizontal_from_y_up`]);
//!   convert at the boundary, not inside this crate.
//! - Grids (masks, distance fields, flow fields) are row-major, texel `(i, j)` at index
//!   `j * width + i`, its centre at `origin + (i + 0.5, j + 0.5) * texel_size` where a grid
//!   has an origin.
//! - Screen buffers have pixel `(x, y)` with its centre at `(x + 0.5, y + 0.5)`, +y down.
//! - Bad input is an [`Error`] naming the limit, value and item; queries on non-finite
//!   positions answer "no water"; nothing panics on user input (the fuzz targets in
//!   `crates/fuzzing/src/water.rs` check this).
//!
//! # Features
//!
//! `std` (default): `std::error::Error`, glam's std math. `libm`: glam without std; this
//! crate's own transcendental math always goes through `libm` ([`math`]), so results are the
//! same on every platform. `parallel`: [`parallel`] (rayon). `#![no_std]` with `alloc`.
//!
//! # WGSL
//!
//! Binding-free library modules ([`wgsl::MODULES`]), imported by a pass with `#import
//! water::noise` and the like and composed by the `shader` crate. Every name is prefixed
//! `water_` / `WATER_` / `Water`; naga validates each module (with its imports) with the
//! core capabilities; constants and GPU structs are tied to the Rust ones by unit tests; run
//! against the CPU on testkit's device (`tests/device.rs`: bit-exact or within 1e-5 on
//! lavapipe, 6e-5 m for FBM through the sampler's f16 texels; each test states its
//! tolerance). Textures are passed as function arguments (`texture_2d` is a valid parameter
//! type), so a pass binds them however it likes.
//!
//! | module | functions (takes -> gives) |
//! | --- | --- |
//! | `water::noise` ([`wgsl::NOISE`]) | `water_pcg`, `water_hash2/3`, `water_hash_unit`; `water_noise_texel(i, j, size, cells, seed)` (generate the texture); `water_fbm(tex, p, WaterFbmParams) -> f32`, `water_fbm_sample(tex, p, distance, prm) -> WaterFbmSample { height, gradient, dropped_variance, octaves }` (exact, `textureLoad`); `water_fbm_filtered(tex, sampler, p, prm)` (one fetch per octave) |
//! | `water::flow` ([`wgsl::FLOW`], imports `water::noise`) | `water_flow_layers(uv, flow, time, noise, WaterFlowParams) -> WaterFlowLayers`, `water_value_noise(p, seed)`, `water_decode_flow_rg` |
//! | `water::foam` ([`wgsl::FOAM`]) | `water_foam_amount`, `water_foam(WaterFoamInputs, WaterFoamParams) -> f32` |
//! | `water::decal` ([`wgsl::DECAL`]) | `water_decal_fade(local, fade)`, `water_decal_inside`, `water_decal_uv`, `water_decal_resolve`, `WATER_CLEAR_DISPLACEMENT` |
//! | `water::optics` ([`wgsl::OPTICS`]) | `water_transmittance(sigma_t, d)`, `water_in_scatter(WaterMedium, light, d)`, `water_light_transport(m, bed, light, d)` |
//! | `water::specaa` ([`wgsl::SPECAA`]) | `water_variance_from_derivatives`, `water_filtered_alpha(alpha, variance, kappa, max_alpha)`, `water_filtered_roughness` |
//! | `water::normals` ([`wgsl::NORMALS`]) | `water_normal_from_depth(depth_tex, pixel, radius, taps, tan_half_fov) -> vec3`, `water_normal_radius`, `water_view_position`, `water_blend_normals` |
//! | `water::gbuffer` ([`wgsl::GBUFFER`]) | `water_pack_data(shader, flags, material, foam_mip, algae_mip) -> u32`, `water_unpack_data(w) -> WaterData`, `water_data_is_valid`, `water_mip_level` |
//! | `water::tiles` ([`wgsl::TILES`]) | `water_grid_vertex(w) -> WaterGridVertex`, `water_grid_position`, `water_grid_corner_pixel`, `water_tile_origin`, `water_tile_of`, `WATER_COLLAPSED_CLIP` |
//! | `water::material` ([`wgsl::MATERIAL`]) | `WaterMaterialGpu`, `water_material_blend(a, b, t)`, `water_blend_weight(d, blend_distance)` |
//! | `water::world` ([`wgsl::WORLD`]) | `water_world_query(world_tex: texture_2d<u32>, p) -> WaterQuery { found, height, body, material, depth, flow }` |
//! | `water::atlas` ([`wgsl::ATLAS`]) | `water_flow_atlas_sample(atlas_tex: texture_2d<u32>, p) -> vec3` (flow in xy, 1 in z if inside) |

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
pub mod axes;
pub mod decal;
pub mod draw;
pub mod edt;
mod error;
pub mod flow;
pub mod flowbake;
pub mod foam;
pub mod gbuffer;
mod grid;
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
pub mod wgsl;
pub mod world;

pub use error::Error;
/// The glam version this crate's API uses; use `water::glam` to avoid a version mismatch
/// with a `glam` of your own.
pub use glam;
pub use progress::{Progress, Stage, no_progress};
