@fragment
fn fs_builtin(in: LaydownOut, @builtin(primitive_index) primitive: u32) -> @location(0) u32 {
    return vis_word(in.id_fields, primitive);
}

@fragment
fn fs_builtin_alpha(in: LaydownOut, @builtin(primitive_index) primitive: u32) -> @location(0) u32 {
    alpha_test(in.uv, in.material);
    return vis_word(in.id_fields, primitive);
}
