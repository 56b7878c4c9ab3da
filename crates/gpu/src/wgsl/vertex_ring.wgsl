// gpu: HFW's vertex transform into the ring buffer (seed 000: "we transform the vertices
// into a ring buffer ... vertex wave commands that tell us what chunks of vertices we
// need to shade"). One workgroup of 64 lanes per vertex wave command (one 64-vertex chunk
// of a micro batch, numbered instance-major), one `dispatch_workgroups_indirect` per pass
// with tiling's vertex PassDispatch. Each lane positions its vertex exactly as every other
// pass (gpu_position, so the wind too) and writes a visbuf::VisbufVertex at its slot.
//
// Ring slots (the resolve's `gpu_ring_slot` reads the same): a pass owns half the ring,
// alternating (pass p starts at `ring_pass.y`, 0 or half), and within it each micro batch
// its planned range from `ring_offset` (tiling's plan: a pass's vertices fit half the
// ring), vertex `instance * vertex_count + vertex`. Culled chunks leave their slots
// unwritten.

#import visbuf::vertex
#import tiling::common
#import gpu::scene_bindings
#import gpu::ring_slots

// Group 1: the transform's inputs and the ring.
@group(1) @binding(0) var<storage, read> table: array<TilingMicroBatchInfo>;
@group(1) @binding(1) var<storage, read> meshes: array<GpuMesh>;
@group(1) @binding(2) var<storage, read> micro_batches: array<GpuMicroBatch>;
@group(1) @binding(3) var<storage, read> vertex_commands: array<TilingVertexWaveCommand>;
@group(1) @binding(4) var<storage, read> vertex_dispatches: array<TilingPassDispatch>;
@group(1) @binding(5) var<storage, read_write> ring: array<VisbufVertex>;
// x: the pass; y: its half's first slot, or GPU_RING_NONE (a pass the ring does not hold:
// the static setups', whose vertex counts only the GPU knows). A dynamic offset per pass.
@group(1) @binding(6) var<uniform> ring_pass: vec4<u32>;

@compute @workgroup_size(64)
fn transform_vertices(@builtin(workgroup_id) wg: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    let dispatch = vertex_dispatches[ring_pass.x];
    let k = wg.y * TILING_MAX_DISPATCH_X + wg.x;
    if k >= dispatch.count || ring_pass.y == GPU_RING_NONE {
        return;
    }
    let command = vertex_commands[dispatch.first + k];
    if command.micro_batch >= arrayLength(&table) || command.micro_batch >= arrayLength(&micro_batches) {
        return;
    }
    let row = table[command.micro_batch];
    let v = command.chunk * 64u + lane;
    if row.vertex_count == 0u || v >= row.vertex_count * row.instance_count {
        return;
    }
    let mb = micro_batches[command.micro_batch];
    let instance_index = mb.first_instance + v / row.vertex_count;
    let vertex = v % row.vertex_count;
    if mb.mesh >= arrayLength(&meshes) || instance_index >= arrayLength(&instances) {
        return;
    }
    let mesh = meshes[mb.mesh];
    let vi = mesh.base_vertex + vertex;
    let slot = gpu_ring_slot(ring_pass.y, row.ring_offset, row.vertex_count, v / row.vertex_count, vertex);
    if vi >= arrayLength(&vertices) || slot >= arrayLength(&ring) {
        return;
    }
    let src = vertices[vi];
    let inst = instances[instance_index];
    let now = frame.view_proj * vec4<f32>(gpu_position(inst, src.position), 1.0);
    let before = frame.prev_view_proj * vec4<f32>(gpu_previous_position(inst, src.position), 1.0);
    let uv = vec2<f32>(src.u, src.v);
    // UVs the 16:16 / 8 code cannot hold are read from the vertex buffer by the resolve
    // (the talk's "kicked out of the fixed format"); the spare 16 bits say so.
    let uv_out = any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(VISBUF_UV_MAX));
    ring[slot] = visbuf_encode_vertex(
        now.xyw,
        uv,
        vec4<f32>(1.0),
        gpu_transform_normal(inst, src.normal),
        vec4<f32>(gpu_transform_direction(inst, src.tangent.xyz), src.tangent.w),
        before.xyw,
        select(0u, GPU_RING_UV_FROM_VERTICES, uv_out),
    );
}
