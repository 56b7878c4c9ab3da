// gpu: depth + visibility laydown (seed 000, "Depth + Visibility" pass), and the depth-only
// prepass of the baseline. Vertices are pulled from storage; one draw per micro batch, with
// `instance_index` indexing the global instance table.
//
// Preceded by: visbuf ID WGSL, gpu SCENE_WGSL (GpuVertex, GpuMaterial), frame.wgsl.
// The primitive-ID path is chosen by which fragment entry point the pipeline uses:
//   fs_builtin   @builtin(primitive_index)                       (Features::PRIMITIVE_INDEX)
//   fs_xor       XOR of three @interpolate(per_vertex) payloads  (Features::SHADER_PER_VERTEX)
//   fs_provoking a flat payload on the provoking (first) vertex  (every adapter)
// Each comes in an alpha-tested variant (`_alpha`) that discards below the material cutoff.

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var<storage, read> vertices: array<GpuVertex>;
@group(0) @binding(2) var<storage, read> instances: array<GpuInstance>;
@group(0) @binding(3) var<storage, read> materials: array<GpuMaterial>;
@group(0) @binding(4) var<storage, read> payloads: array<u32>;
@group(0) @binding(5) var albedo: texture_2d_array<f32>;
@group(0) @binding(6) var albedo_sampler: sampler;

struct LaydownOut {
    @invariant @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) @interpolate(flat) instance: u32,
    @location(2) @interpolate(flat) payload: u32,
}

fn laydown_vertex(vertex: u32, instance: u32) -> LaydownOut {
    let v = vertices[vertex];
    let inst = instances[instance];
    var out: LaydownOut;
    out.clip = frame.view_proj * vec4<f32>(gpu_transform_point(inst, v.position), 1.0);
    out.uv = vec2<f32>(v.u, v.v);
    out.instance = instance;
    out.payload = 0u;
    return out;
}

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

fn alpha_test(uv: vec2<f32>, instance: u32) {
    let m = materials[instances[instance].material];
    let a = textureSample(albedo, albedo_sampler, uv, m.albedo_layer).a;
    if a < m.alpha_cutoff {
        discard;
    }
}

fn vis_word(instance: u32, primitive: u32) -> u32 {
    let inst = instances[instance];
    return visbuf_pack_id(inst.micro_batch, inst.instance_field, primitive, inst.primitive_bits);
}

// Depth-only prepass (baseline): no colour output.
@fragment
fn fs_depth_alpha(in: LaydownOut) {
    alpha_test(in.uv, in.instance);
}
