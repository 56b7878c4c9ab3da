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
    // HFW's software VRS: the vertex's shading rate code (visbuf::ShadingRate; 0 without
    // VRS); the provoking vertex's rates the triangle.
    @location(3) @interpolate(flat) rate: u32,
}

// The shading rate code (visbuf::ShadingRate, the VRS layout's rate field) of a vertex at clip
// position `now` that was at `before` in the previous frame's clip space: HFW's rule
// (gpu::VrsConfig), the coarser of the distance's rate (1x1, then 2x1 from frame.vrs.x
// metres, 2x2 from frame.vrs.y) and the screen speed's (2x1 from frame.vrs.z pixels per
// frame, 2x2 from frame.vrs.w). 0 (1x1) without VRS.
fn gpu_shading_rate(now: vec4<f32>, before: vec4<f32>) -> u32 {
    if (!gpu_vrs_layout()) {
        return 0u;
    }
    var level = 0u;
    if (now.w >= frame.vrs.y) {
        level = 2u;
    } else if (now.w >= frame.vrs.x) {
        level = 1u;
    }
    if (now.w > 0.0 && before.w > 0.0) {
        let speed = length((now.xy / now.w - before.xy / before.w) * frame.viewport.xy * 0.5);
        if (speed >= frame.vrs.w) {
            level = 2u;
        } else if (speed >= frame.vrs.z) {
            level = max(level, 1u);
        }
    }
    return array<u32, 3>(0u, VISBUF_RATE_2X1, VISBUF_RATE_2X2)[level];
}

fn laydown_vertex(vertex: u32, instance: u32) -> LaydownOut {
    let v = vertices[vertex];
    let inst = instances[instance];
    var out: LaydownOut;
    out.clip = frame.view_proj * vec4<f32>(gpu_position(inst, v.position), 1.0);
    out.uv = vec2<f32>(v.u, v.v);
    out.instance = instance;
    out.payload = 0u;
    out.rate = 0u;
    if (gpu_vrs_layout()) {
        let before = frame.prev_view_proj * vec4<f32>(gpu_previous_position(inst, v.position), 1.0);
        out.rate = gpu_shading_rate(out.clip, before);
    }
    return out;
}

// HZD's LOD fade as a dither: a fading instance keeps the pixels whose 4x4 Bayer rank is
// below its cells (fading in) or at or above 16 minus its cells (fading out), so a pair
// fading across each other (cells c and 16 - c) covers every pixel exactly once. Instances
// not fading keep everything.
fn gpu_fade_keeps(bits: u32, pixel: vec2<u32>) -> bool {
    if ((bits & GPU_INSTANCE_FADING) == 0u) {
        return true;
    }
    let cells = (bits >> GPU_INSTANCE_FADE_CELLS_SHIFT) & 0xffu;
    let p = pixel & vec2<u32>(3u);
    // The 4x4 Bayer matrix, one row per word, one rank per nibble (x = 0 in the top one).
    let rows = array<u32, 4>(0x082au, 0xc4e6u, 0x3b19u, 0xf7d5u);
    let rank = (rows[p.y] >> (4u * (3u - p.x))) & 0xfu;
    if ((bits & GPU_INSTANCE_FADING_OUT) != 0u) {
        return rank + cells >= 16u;
    }
    return rank < cells;
}

// The laydown's alpha-tested fragments (and every static instance's, which may fade):
// the fade dither, then the material's alpha cutoff. `pixel`: the fragment's position.
fn alpha_test(uv: vec2<f32>, instance: u32, pixel: vec2<f32>) {
    if (!gpu_fade_keeps(instances[instance].primitive_bits, vec2<u32>(pixel))) {
        discard;
    }
    let m = materials[instances[instance].material];
    let a = textureSample(albedo, albedo_sampler, uv, m.albedo_layer).a;
    if a < m.alpha_cutoff {
        discard;
    }
}

// `rate`: the shading rate's code (LaydownOut::rate; visbuf::ShadingRate), packed in the
// VRS layout (14-bit micro-batch IDs) when the plan uses it.
fn vis_word(instance: u32, primitive: u32, rate: u32) -> u32 {
    let inst = instances[instance];
    let bits = inst.primitive_bits & GPU_INSTANCE_PRIMITIVE_BITS_MASK;
    if (gpu_vrs_layout()) {
        return visbuf_pack_id_vrs(rate, inst.micro_batch, inst.instance_field, primitive, bits);
    }
    return visbuf_pack_id(inst.micro_batch, inst.instance_field, primitive, bits);
}
