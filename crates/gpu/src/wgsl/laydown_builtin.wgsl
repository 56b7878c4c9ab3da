// gpu: the laydown's fragment stage on the `primitive_index` path.

enable primitive_index;
#import gpu::laydown

@fragment
fn fs_vis(in: LaydownOut, @builtin(primitive_index) primitive: u32) -> @location(0) u32 {
    return vis_word(in.instance, primitive, in.rate);
}

@fragment
fn fs_vis_alpha(in: LaydownOut, @builtin(primitive_index) primitive: u32) -> @location(0) u32 {
    alpha_test(in.uv, in.instance, in.clip.xy);
    return vis_word(in.instance, primitive, in.rate);
}
