// gpu: the laydown's fragment stage on the provoking-vertex path (every adapter).

#import gpu::laydown

@fragment
fn fs_vis(in: LaydownOut) -> @location(0) u32 {
    return vis_word(in.instance, in.payload, in.rate);
}

@fragment
fn fs_vis_alpha(in: LaydownOut) -> @location(0) u32 {
    alpha_test(in.uv, in.instance, in.clip.xy);
    return vis_word(in.instance, in.payload, in.rate);
}
