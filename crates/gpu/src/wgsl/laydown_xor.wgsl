// gpu: the laydown's fragment stage on HFW's XOR path: the XOR of the triangle's three
// per-vertex payloads is its primitive ID, whatever the vertex order.

enable wgpu_per_vertex;
#import gpu::laydown

struct LaydownXorIn {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) @interpolate(flat) instance: u32,
    @location(2) @interpolate(per_vertex) payload: array<u32, 3>,
    @location(3) @interpolate(flat) rate: u32,
}

@fragment
fn fs_vis(in: LaydownXorIn) -> @location(0) u32 {
    return vis_word(in.instance, in.payload[0] ^ in.payload[1] ^ in.payload[2], in.rate);
}

@fragment
fn fs_vis_alpha(in: LaydownXorIn) -> @location(0) u32 {
    alpha_test(in.uv, in.instance, in.clip.xy);
    return vis_word(in.instance, in.payload[0] ^ in.payload[1] ^ in.payload[2], in.rate);
}
