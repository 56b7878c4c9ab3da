//! Visibility-buffer formats from Horizon Forbidden West's deferred texturing (GDC 2022,
//! seed 000) and the pixel-side vertex pulling of "Future geometry pipeline" (seed 004):
//! what the laydown writes, what the classification decodes and what the material resolve
//! needs, each as a CPU function that is the reference for its WGSL twin.
//!
//! - [`id`]: the 32-bit vis-buffer word (micro-batch ID, optional 2-bit VRS rate, instance
//!   field, `ceil(log2(primitives))` primitive bits), the reserved [`VIS_NONE`], and the
//!   micro-batch-ID ranges that carry instance overflow ([`VisIdRanges`]).
//! - [`encode`]: mesh preprocessing for the primitive ID in the laydown's pixel shader:
//!   provoking-vertex payloads ([`encode_provoking`]) and HFW's XOR payloads
//!   ([`encode_xor`]), plus the talk's greedy passes as baselines.
//! - [`vertex`]: the 32-byte transformed vertex of the ring buffer ([`VisbufVertex`]) in
//!   its standard and interpolant layouts, with per-field worst-case errors, and z from w
//!   ([`ZFromW`]).
//! - [`bary`]: perspective-correct barycentrics and their screen-space derivatives by the
//!   analytic method, attribute interpolation, mip level selection.
//! - [`ray`]: the watertight ray-triangle fallback and the pixel ray.
//!
//! `#![no_std]` with `alloc` (the mesh encoders and [`VisIdRanges`] allocate); float math
//! through `std` (default) or the `libm` feature.
//!
//! ```
//! use visbuf::{PrimitiveBits, ShadingRate, VisFields, VisId, VisLayout};
//!
//! // A 5000-triangle geometry needs 13 primitive bits, leaving 3 instance bits.
//! let bits = PrimitiveBits::for_count(5000)?;
//! assert_eq!((bits.get(), bits.instance_bits()), (13, 3));
//! let f = VisFields { micro_batch: 42, instance: 5, primitive: 4999, rate: ShadingRate::Rate1x1 };
//! let word = VisId::pack(VisLayout::Standard, bits, f)?;
//! assert_eq!(word.0, (42 << 16) | (5 << 13) | 4999);
//! assert_eq!(word.unpack(VisLayout::Standard, bits), Some(f));
//!
//! // The resolve: weights and derivatives of a pixel inside a triangle.
//! use visbuf::glam::{Vec2, Vec4};
//! let clip = [Vec4::new(-1.0, -1.0, 0.0, 1.0), Vec4::new(1.0, -1.0, 0.0, 1.0), Vec4::new(-1.0, 1.0, 0.0, 1.0)];
//! let b = visbuf::bary::barycentrics(clip, Vec2::new(10.5, 90.5), Vec2::new(100.0, 100.0));
//! assert!((b.lambda.x + b.lambda.y + b.lambda.z - 1.0).abs() < 1e-6);
//! assert!((b.ddx.y - 0.01).abs() < 1e-6); // vertex 1's weight grows 1/100 per pixel right
//! # Ok::<(), visbuf::Error>(())
//! ```
//!
//! # WGSL
//!
//! Four binding-free library modules ([`wgsl::ID`], [`wgsl::VERTEX`], [`wgsl::BARY`],
//! [`wgsl::RAY`]; [`wgsl::MODULES`] lists them), imported by a pass with `#import
//! visbuf::id` and composed by the `shader` crate. They hold only
//! `const`s, structs and functions, every name prefixed `visbuf_` / `VISBUF_` / `Visbuf`,
//! take plain values (u32 words, clip-space `vec4`s, the viewport size) and need no
//! optional capability (naga validates each with `Caps::CORE`; f16 conversion is written
//! out instead of `pack2x16float`, which needs a downlevel flag). Each `const` equals the
//! Rust constant of the same meaning: unit tests read them back, and check the WGSL struct
//! layouts against the Rust ones.
//!
//! **`visbuf::id`** ([`wgsl::ID`])
//!
//! | WGSL | takes | gives |
//! | --- | --- | --- |
//! | `VISBUF_NONE` | - | the reserved "no geometry" word, `0xffffffffu`: clear the vis buffer to it |
//! | `visbuf_is_none(word)` | vis word | `word == VISBUF_NONE` |
//! | `visbuf_micro_batch(word)` / `_vrs(word)` | vis word | micro-batch ID (16 / 14 bits) |
//! | `visbuf_shading_rate_vrs(word)` | vis word (VRS layout) | rate code 0..3 ([`ShadingRate`]) |
//! | `visbuf_rate_size(rate)` | rate code | block size in pixels, `vec2<u32>` |
//! | `visbuf_instance_field(word, p)` | vis word, primitive bits | instance field |
//! | `visbuf_primitive(word, p)` | vis word, primitive bits | primitive index |
//! | `visbuf_primitive_bits(n)` | primitive count 1..=65536 | `ceil(log2(n))` |
//! | `visbuf_pack_id(mb, inst, prim, p)` | fields (masked to their widths) | vis word |
//! | `visbuf_pack_id_vrs(rate, mb, inst, prim, p)` | fields (masked) | vis word, VRS layout |
//! | `visbuf_instance_index(mb, first, inst, p)` | word's micro batch, range start, field | instance index in batch |
//! | `visbuf_split_instance(first, instance, p)` | range start, instance index | `vec2(micro batch, field)` |
//! | `VisbufIdRange` | - | [`VisbufIdRange`], 16 bytes |
//!
//! **`visbuf::vertex`** ([`wgsl::VERTEX`], layout table in [`vertex`])
//!
//! | WGSL | takes | gives |
//! | --- | --- | --- |
//! | `VisbufVertex` | - | [`VisbufVertex`], 32 bytes, same field names; `array<VisbufVertex>` has stride 32 |
//! | `visbuf_decode_vertex_core(v, z_from_w)` | vertex, `vec2(a, b)` of [`ZFromW`] | `VisbufVertexCore { clip, normal, tangent, prev_hpos }` |
//! | `visbuf_vertex_clip(hpos_xy, hpos_w, z_from_w)` | words 0, 1 | clip `vec4` with z = a w + b |
//! | `visbuf_vertex_hpos` / `visbuf_vertex_prev_hpos` | words 0, 1 / 6, 7 | clip (x, y, w) |
//! | `visbuf_unpack_uv(word)` / `visbuf_pack_uv(uv)` | word 2 / UV in [0, 8) | UV / word |
//! | `visbuf_unpack_snorm_10_10_10_2` / `visbuf_pack_snorm_10_10_10_2` | word / `vec4` | `vec4` / word |
//! | `visbuf_unpack_half(bits)` / `visbuf_pack_half(x)`, `..._half2` | f16 bits / f32 | exact, round to nearest even |
//! | `visbuf_vertex_slot_bits(v, i)`, `visbuf_slot_half(bits)`, `visbuf_unpack_sqrt_unorm8x2(bits)`, `visbuf_pack_sqrt_unorm8x2(c)` | interpolant slots | slot values |
//! | `visbuf_encode_vertex(hpos, uv, color, normal, tangent, prev_hpos, extra)` | the vertex pass's outputs | `VisbufVertex`, standard layout |
//!
//! **`visbuf::bary`** ([`wgsl::BARY`]; conventions in [`bary`]: pixel relative to the viewport's top-left,
//! +y down, centres at +0.5)
//!
//! | WGSL | takes | gives |
//! | --- | --- | --- |
//! | `visbuf_barycentrics(c0, c1, c2, pixel, viewport)` | clip `vec4`s, pixel, viewport size | `VisbufBarycentrics { lambda, ddx, ddy }`, exact derivatives |
//! | `visbuf_barycentrics_quad(...)` | same | forward one-pixel differences (like `dpdxFine`) |
//! | `visbuf_interpolate1/2/3/4(b, a0, a1, a2)` | weights, per-vertex f32 / vec2 / vec3 / vec4 | `VisbufInterpN { value, ddx, ddy }` |
//! | `visbuf_mip_level(duv_dx, duv_dy, size, bias)` | UV gradients, texture size | isotropic level, unclamped |
//! | `visbuf_mip_bias_scale(bias)` | bias | `exp2(bias)`: scale both gradients for `textureSampleGrad` |
//!
//! **`visbuf::ray`** ([`wgsl::RAY`])
//!
//! | WGSL | takes | gives |
//! | --- | --- | --- |
//! | `visbuf_intersect_watertight(origin, dir, v0, v1, v2)` | ray, camera-relative positions | `VisbufRayHit { hit, t, barycentrics }` |
//! | `visbuf_pixel_ray_direction(inv_view_proj, eye, pixel, viewport)` | inverse view-projection | ray direction (zero if none) |
//!
//! The CPU side is the reference. This crate's device tests (`crates/visbuf/tests/device.rs`,
//! on testkit's device) run the ID and barycentric functions on a device against the CPU
//! functions of the same name; the vertex and ray modules are so far only validated by
//! naga (and the half conversions by a Rust transliteration), not run on a device.

#![no_std]

extern crate alloc;
#[cfg(feature = "std")]
extern crate std;

#[cfg(not(any(feature = "std", feature = "libm")))]
compile_error!("visbuf needs float math: enable the `std` (default) or `libm` feature");

pub mod bary;
pub mod encode;
mod error;
pub mod id;
mod math;
pub mod ray;
pub mod vertex;
pub mod wgsl;

pub use encode::{
    MAX_PACKED_VERTICES, MAX_VERTICES_PER_GEOMETRY, PrimitiveIdMesh, encode_provoking,
    encode_provoking_greedy, encode_xor, encode_xor_greedy,
};
pub use error::Error;
/// The glam version this crate's API uses; use `visbuf::glam` to avoid a version mismatch
/// with a `glam` of your own.
pub use glam;
pub use id::{
    MAX_INSTANCES_PER_MICRO_BATCH, MAX_PRIMITIVE_BITS, MAX_PRIMITIVES_PER_GEOMETRY,
    MICRO_BATCH_IDS, MICRO_BATCH_IDS_VRS, PrimitiveBits, ResolvedVisId, ShadingRate,
    VIS_INSTANCE_PRIMITIVE_BITS, VIS_INSTANCE_PRIMITIVE_MASK, VIS_MICRO_BATCH_BITS,
    VIS_MICRO_BATCH_BITS_VRS, VIS_MICRO_BATCH_SHIFT, VIS_NONE, VIS_RATE_BITS, VIS_RATE_SHIFT,
    VisFields, VisId, VisIdRanges, VisLayout, VisbufIdRange, instance_index,
    micro_batch_ids_needed, split_instance,
};
pub use vertex::{Slot, Vertex, VertexCore, VisbufVertex, ZFromW};
