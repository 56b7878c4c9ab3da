// gpu: depth + visibility laydown (seed 000, "Depth + Visibility" pass), and the depth-only
// prepass of the baseline. Vertices are pulled from storage; one draw per micro batch, with
// `instance_index` indexing the global instance table. The fragment stage of each
// primitive-ID path is in the module that imports this one:
//   gpu::laydown_builtin    @builtin(primitive_index)                      (PRIMITIVE_INDEX)
//   gpu::laydown_xor        XOR of three @interpolate(per_vertex) payloads (SHADER_PER_VERTEX)
//   gpu::laydown_provoking  a flat payload on the provoking (first) vertex (every adapter)
// each with an alpha-tested variant (`_alpha`) that discards below the material cutoff.

#import gpu::geometry

// One payload per vertex (zeros on the builtin path).
@group(1) @binding(0) var<storage, read> payloads: array<u32>;

@vertex
fn vs_main(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> LaydownOut {
    return laydown_vertex(vertex, instance);
}

// The vertex stage of the provoking-vertex and XOR paths: also passes the vertex's payload.
@vertex
fn vs_payload(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> LaydownOut {
    var out = laydown_vertex(vertex, instance);
    out.payload = payloads[vertex];
    return out;
}

// Depth-only prepass (baseline), alpha-tested materials: no colour output.
@fragment
fn fs_depth_alpha(in: LaydownOut) {
    alpha_test(in.uv, in.instance, in.clip.xy);
}
