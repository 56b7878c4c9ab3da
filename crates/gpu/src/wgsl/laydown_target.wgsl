// gpu: the compute laydown's depth into the depth target, for frames whose later raster
// passes test against it (stencil light volumes, the mixed frame's regular pass, the water):
// the float depth the unpack wrote, as
// frag_depth from a full-screen triangle (depth formats cannot be storage textures).
// Raster fill (1.05 ms at 4K on the H200's two raster TPCs), so frames without such passes
// skip it.

@group(0) @binding(0) var depth_float: texture_2d<f32>;

@vertex
fn vs_full(@builtin(vertex_index) vertex: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((vertex << 1u) & 2u), f32(vertex & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

@fragment
fn fs_target(@builtin(position) position: vec4<f32>) -> @builtin(frag_depth) f32 {
    let p = vec2<u32>(position.xy);
    if (any(p >= textureDimensions(depth_float))) {
        return 0.0;
    }
    return textureLoad(depth_float, p, 0).x;
}
