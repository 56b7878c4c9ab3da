@fragment
fn fs_provoking(in: LaydownOut) -> @location(0) u32 {
    return vis_word(in.id_fields, in.payload);
}

@fragment
fn fs_provoking_alpha(in: LaydownOut) -> @location(0) u32 {
    alpha_test(in.uv, in.material);
    return vis_word(in.id_fields, in.payload);
}
