//! Visibility-buffer formats from Horizon Forbidden West's deferred texturing (GDC 2022,
//! seed 000) and the pixel-side vertex pulling of "Future geometry pipeline" (seed 004):
//! what the laydown writes, what the classification decodes and what the material resolve
//! needs, each as a CPU function that is the reference for its WGSL twin.
//!
//! - [`id`]: the 32-bit vis-buffer word (micro-batch ID, optional 2-bit VRS rate, instance
//!   field, `ceil(log2(primitives))` primitive bits), the reserved [`VIS_NONE`], and the
//!   micro-batch-ID ranges that carry instance overflow.
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
//! # Ok::<(), visbuf::Error>(())
//! ```
//!
//! # WGSL
//!
//! [`ID_WGSL`] holds the shader side: binding-free `const`s, structs and functions, every
//! name prefixed `visbuf_` / `VISBUF_`, meant to be concatenated in front of a pass. Each
//! `const` equals the Rust constant of the same meaning (unit tests read them back).
//!
//! | WGSL | takes | gives |
//! | --- | --- | --- |
//! | `VISBUF_NONE` | - | the reserved "no geometry" word, `0xffffffffu` |
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
mod wgsl;

pub use encode::{
    MAX_PACKED_VERTICES, MAX_VERTICES_PER_GEOMETRY, PrimitiveIdMesh, encode_provoking,
    encode_provoking_greedy, encode_xor, encode_xor_greedy,
};
pub use error::Error;
pub use id::{
    MAX_INSTANCES_PER_MICRO_BATCH, MAX_PRIMITIVE_BITS, MAX_PRIMITIVES_PER_GEOMETRY,
    MICRO_BATCH_IDS, MICRO_BATCH_IDS_VRS, PrimitiveBits, ResolvedVisId, ShadingRate,
    VIS_INSTANCE_PRIMITIVE_BITS, VIS_INSTANCE_PRIMITIVE_MASK, VIS_MICRO_BATCH_BITS,
    VIS_MICRO_BATCH_BITS_VRS, VIS_MICRO_BATCH_SHIFT, VIS_NONE, VIS_RATE_BITS, VIS_RATE_SHIFT,
    VisFields, VisId, VisIdRanges, VisLayout, VisbufIdRange, instance_index,
    micro_batch_ids_needed, split_instance,
};
pub use vertex::{Slot, Vertex, VertexCore, VisbufVertex, ZFromW};
pub use wgsl::{BARY_WGSL, ID_WGSL, RAY_WGSL, VERTEX_WGSL, WGSL};
