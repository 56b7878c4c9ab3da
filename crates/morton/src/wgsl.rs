//! The WGSL twin: the library module `morton::codes` ([`CODES`]), imported by a pass
//! with `#import morton::codes` (see the `shader` crate).

use shader::Module;

/// Morton codes on the GPU: a binding-free WGSL module (functions and constants, prefixed
/// `morton_` / `MORTON_`) for the 32-bit codes, identical bit for bit to the CPU functions:
///
/// | WGSL | CPU twin |
/// | --- | --- |
/// | `morton_encode2_u32(x, y) -> u32` | [`crate::encode2_u32`] |
/// | `morton_decode2_u32(code) -> vec2<u32>` | [`crate::decode2_u32`] |
/// | `morton_encode3_u32(x, y, z) -> u32` | [`crate::encode3_u32`] |
/// | `morton_decode3_u32(code) -> vec3<u32>` | [`crate::decode3_u32`] |
/// | `morton_part1by1`, `morton_compact1by1`, `morton_part1by2`, `morton_compact1by2` | the spread/gather steps of [`crate::magic`] |
/// | `morton_quantize3(p, box_min, scale, bits) -> vec3<u32>` | [`crate::Quantizer3::quantize`] with `scale` = [`crate::Quantizer3::scale`] |
/// | `morton_key3_u32(p, box_min, scale, bits) -> u32` | [`crate::Quantizer3::morton_u32`] |
/// | `MORTON_BITS2_U32`, `MORTON_BITS3_U32` | [`crate::BITS2_U32`], [`crate::BITS3_U32`] |
/// | `MORTON_MASK2_X_U32`, `MORTON_MASK2_Y_U32`, `MORTON_MASK3_{X,Y,Z}_U32` | [`crate::MASK2_X_U32`], ..., [`crate::MASK3_Z_U32`] |
///
/// WGSL has no 64-bit integers in core, so the u64 codes stay on the CPU. Validated by naga
/// (core capabilities only) with its constants and names checked in
/// `crates/morton/tests/wgsl.rs`; `crates/morton/tests/device.rs` runs it on testkit's
/// device against the CPU functions.
pub const CODES: Module = Module::new("morton::codes", include_str!("wgsl/codes.wgsl"));

/// This crate's modules.
pub const MODULES: &[Module] = &[CODES];
