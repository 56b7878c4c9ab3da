// gpu: where the vertex ring holds a vertex (binding-free; the transform writes there, the
// resolve reads there). Rust twin: gpu::passes::vertex_ring::ring_slot.

// A pass whose vertices are not in the ring (ring_pass.y / the resolve's pass uniform .y).
const GPU_RING_NONE: u32 = 0xffffffffu;
// VisbufVertex's spare 16 bits: the vertex's UV is outside the 16:16 / 8 code's [0, 8),
// read it from the vertex buffer.
const GPU_RING_UV_FROM_VERTICES: u32 = 1u;

// Slot of vertex `vertex` of instance `instance` (within its micro batch) of a micro batch
// at `ring_offset` in its pass's half starting at `half_base`, its mesh `vertex_count`
// vertices.
fn gpu_ring_slot(half_base: u32, ring_offset: u32, vertex_count: u32, instance: u32, vertex: u32) -> u32 {
    return half_base + ring_offset + instance * vertex_count + vertex;
}
