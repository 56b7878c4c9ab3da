@fragment
fn fs_provoking(in: LaydownOut) -> @location(0) u32 {
    return vis_word(in.instance, in.payload);
}

@fragment
fn fs_provoking_alpha(in: LaydownOut) -> @location(0) u32 {
    alpha_test(in.uv, in.instance);
    return vis_word(in.instance, in.payload);
}
