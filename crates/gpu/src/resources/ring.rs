//! HFW's vertex ring's record layout: what the vertex-ring pass writes and the resolve
//! reads.

/// Bytes of one ring vertex (`visbuf::VisbufVertex`).
pub const RING_VERTEX_BYTES: u64 = size_of::<visbuf::VisbufVertex>() as u64;

/// Bytes of the per-pass uniform (pass, half base), bound at a dynamic offset.
pub(crate) const RING_PASS_UNIFORM_BYTES: u64 = 16;

/// The per-pass uniform's `y` for a pass the ring does not hold (WGSL `GPU_RING_NONE`).
pub(crate) const RING_NONE: u32 = u32::MAX;

/// The spare 16 bits' flag: the vertex's UV is read from the vertex buffer (WGSL
/// `GPU_RING_UV_FROM_VERTICES`).
pub const RING_UV_FROM_VERTICES: u16 = 1;

/// The slot of vertex `vertex` of instance `instance` (within its micro batch, whose mesh
/// has `vertex_count` vertices and whose planned range starts at `ring_offset`) in pass
/// `pass` of a ring of `ring_vertices` slots. WGSL twin: `gpu_ring_slot` with the pass's
/// half base.
#[must_use]
pub fn ring_slot(
    ring_vertices: u32,
    pass: u32,
    ring_offset: u32,
    vertex_count: u32,
    instance: u32,
    vertex: u32,
) -> u32 {
    (pass % 2) * (ring_vertices / 2) + ring_offset + instance * vertex_count + vertex
}
