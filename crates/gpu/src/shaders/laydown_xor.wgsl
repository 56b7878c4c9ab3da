struct LaydownXorIn {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) @interpolate(flat) instance: u32,
    @location(2) @interpolate(per_vertex) payload: array<u32, 3>,
}

@fragment
fn fs_xor(in: LaydownXorIn) -> @location(0) u32 {
    return vis_word(in.instance, in.payload[0] ^ in.payload[1] ^ in.payload[2]);
}

@fragment
fn fs_xor_alpha(in: LaydownXorIn) -> @location(0) u32 {
    alpha_test(in.uv, in.instance);
    return vis_word(in.instance, in.payload[0] ^ in.payload[1] ^ in.payload[2]);
}
