// gpu: the vertex transform every geometry pass shares (laydown, depth prepass, baseline),
// so their depths are bit-identical (`@invariant` positions, the same arithmetic), and the
// alpha test and vis-word packing of the laydown's fragment stages.

#import visbuf::id
#import gpu::scene_bindings

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
    out.clip = frame.view_proj * vec4<f32>(gpu_camera_relative(inst, v.position), 1.0);
    out.uv = vec2<f32>(v.u, v.v);
    out.instance = instance;
    out.payload = 0u;
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
