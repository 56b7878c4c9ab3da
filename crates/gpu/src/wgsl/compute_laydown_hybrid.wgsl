// gpu: the compute laydown's hardware part (issue 17): the triangles the compute raster
// listed (those the hardware must clip: crossing the near plane, or a box too large for
// the fixed point), drawn by one non-indexed indirect draw whose vertex stage fetches
// (instance, vertex) from the list, each fragment an `atomicMax` into the same 64-bit
// target (no colour target, no depth test: the target is the depth), so one compute pass
// after it unpacks everything. Same vertex transform, culling and alpha test as the
// hardware laydown.

#import gpu::compute_laydown_draws

struct GpuHybridListRead {
    vertex_count: u32,
    instance_count: u32,
    first_vertex: u32,
    first_instance: u32,
    items: array<u32>,
}

@group(1) @binding(3) var<storage, read> hybrid: GpuHybridListRead;

@vertex
fn vs_hybrid(@builtin(vertex_index) vertex: u32) -> LaydownOut {
    let e = vertex / 3u;
    var out: LaydownOut;
    // Past the list's capacity or an invalid item: all three vertices at one point, a
    // zero-area triangle the rasteriser drops.
    out.clip = vec4<f32>(0.0, 0.0, 0.0, 1.0);
    if (e >= arrayLength(&hybrid.items)) {
        return out;
    }
    let t = gpu_laydown_triangle(hybrid.items[e]);
    if (!t.valid) {
        return out;
    }
    out = laydown_vertex(t.vertices[vertex % 3u], t.instance);
    out.payload = t.primitive;
    return out;
}

@fragment
fn fs_hybrid(in: LaydownOut) {
    // Opaque materials have a cutoff of 0: the test keeps every fragment.
    alpha_test(in.uv, in.instance, in.clip.xy);
    let value = gpu_laydown_value(in.clip.z, vis_word(in.instance, in.payload, in.rate));
    gpu_laydown_plot(vec2<u32>(in.clip.xy), u32(frame.viewport.x), value);
}
