@fragment
fn fs_builtin(in: LaydownOut, @builtin(primitive_index) primitive: u32) -> @location(0) u32 {
    return vis_word(in.instance, primitive);
}

@fragment
fn fs_builtin_alpha(in: LaydownOut, @builtin(primitive_index) primitive: u32) -> @location(0) u32 {
    alpha_test(in.uv, in.instance);
    return vis_word(in.instance, primitive);
}
