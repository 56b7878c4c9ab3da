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
    out.clip = frame.view_proj * vec4<f32>(gpu_position(inst, v.position), 1.0);
    out.uv = vec2<f32>(v.u, v.v);
    out.instance = instance;
    out.payload = 0u;
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

fn vis_word(instance: u32, primitive: u32) -> u32 {
    let inst = instances[instance];
    return visbuf_pack_id(inst.micro_batch, inst.instance_field, primitive, inst.primitive_bits & GPU_INSTANCE_PRIMITIVE_BITS_MASK);
}
