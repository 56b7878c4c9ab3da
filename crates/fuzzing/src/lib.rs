//! The bodies of every fuzz target in the workspace.
//!
//! A fuzz target in `fuzz/fuzz_targets/<name>.rs` is one line that calls the function of
//! the same name here, so the same check runs under libFuzzer (`cargo +nightly fuzz run
//! <name>`) and in ordinary tests: `tests/fuzz_regressions.rs` replays every file under
//! `fuzz/regressions/<name>/` through [`TARGETS`], plus a few thousand pseudo-random
//! inputs, on stable Rust in CI.
//!
//! Each body panics only when the code under test is wrong (a decoder that panicked, a
//! roundtrip that did not hold); arbitrary input itself must never make it panic.
//!
//! ```
//! for (name, body) in fuzzing::TARGETS {
//!     body(&[]); // every target accepts empty input
//!     assert!(!name.is_empty());
//! }
//! ```

mod deferred;
mod framealloc;
mod gltf;
mod morton;
mod shader;
mod staticscene;
mod tiling;
mod visbuf;
mod water;
mod wave;
pub use deferred::*;
pub use framealloc::*;
pub use gltf::*;
pub use morton::*;
pub use shader::*;
pub use staticscene::*;
pub use tiling::*;
pub use visbuf::*;
pub use water::*;
pub use wave::*;

/// A fuzz target body: takes arbitrary bytes, panics only on a real defect.
pub type Body = fn(&[u8]);

/// Every fuzz target, by the name of its file in `fuzz/fuzz_targets/`.
pub const TARGETS: &[(&str, Body)] = &[
    ("deferred_gbuffer_decode", deferred_gbuffer_decode),
    ("deferred_normal_codecs", deferred_normal_codecs),
    ("framealloc_pool_ops", framealloc_pool_ops),
    ("framealloc_stream_ops", framealloc_stream_ops),
    ("gltf_import", gltf_import),
    ("morton_decode", morton_decode),
    ("morton_roundtrip", morton_roundtrip),
    ("shader_compose", shader_compose),
    ("staticscene_instance_decode", staticscene_instance_decode),
    ("staticscene_build", staticscene_build),
    ("staticscene_query", staticscene_query),
    ("staticscene_tile_parts", staticscene_tile_parts),
    ("tiling_classify", tiling_classify),
    ("tiling_plan", tiling_plan),
    ("visbuf_id_decode", visbuf_id_decode),
    ("visbuf_vertex_decode", visbuf_vertex_decode),
    ("visbuf_encode_provoking", visbuf_encode_provoking),
    ("visbuf_encode_xor", visbuf_encode_xor),
    ("water_query", water_query),
    ("water_world_decode", water_world_decode),
    ("water_edt", water_edt),
    ("water_flow_bake", water_flow_bake),
    ("water_atlas_decode", water_atlas_decode),
    ("water_data_word", water_data_word),
    ("wave_append", wave_append),
    ("wave_batch", wave_batch),
];

/// Reads little-endian words from fuzz input, yielding zeros once it runs out, so a body
/// can pull as many fields as it needs from any input length.
#[derive(Clone, Debug)]
pub struct Input<'a> {
    data: &'a [u8],
}

impl<'a> Input<'a> {
    /// Wraps fuzz input.
    pub fn new(data: &'a [u8]) -> Self {
        Self { data }
    }

    /// Bytes not yet read.
    pub fn remaining(&self) -> usize {
        self.data.len()
    }

    /// Takes `N` bytes, zero-padded past the end.
    pub fn bytes<const N: usize>(&mut self) -> [u8; N] {
        let mut out = [0u8; N];
        let n = N.min(self.data.len());
        out[..n].copy_from_slice(&self.data[..n]);
        self.data = &self.data[n..];
        out
    }

    /// One byte.
    pub fn u8(&mut self) -> u8 {
        self.bytes::<1>()[0]
    }

    /// A little-endian u16.
    pub fn u16(&mut self) -> u16 {
        u16::from_le_bytes(self.bytes())
    }

    /// A little-endian u32.
    pub fn u32(&mut self) -> u32 {
        u32::from_le_bytes(self.bytes())
    }

    /// A little-endian u64.
    pub fn u64(&mut self) -> u64 {
        u64::from_le_bytes(self.bytes())
    }

    /// An f32 from arbitrary bits: NaN, infinities and subnormals included.
    pub fn f32(&mut self) -> f32 {
        f32::from_bits(self.u32())
    }

    /// The rest of the input.
    pub fn rest(&mut self) -> &'a [u8] {
        core::mem::take(&mut self.data)
    }
}
