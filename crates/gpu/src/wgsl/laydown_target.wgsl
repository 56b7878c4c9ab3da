// gpu: the compute laydown's 64-bit target into the depth target, for frames whose later
// raster passes test against it (the stencil light volumes): frag_depth from a
// full-screen triangle, since depth formats cannot be storage textures. Raster fill (2.4 ms
// at 4K on the H200's two raster TPCs), so frames without such passes skip it: the
// compute passes read the float depth `gpu::laydown_unpack` writes. A pixel whose depth
// bits are 0 was never drawn: the far plane.

#import visbuf::id
#import gpu::frame

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
// The target as (vis word, depth bits) pairs: little-endian halves of each u64.
@group(0) @binding(1) var<storage, read> laydown_target: array<vec2<u32>>;

@vertex
fn vs_full(@builtin(vertex_index) vertex: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((vertex << 1u) & 2u), f32(vertex & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

@fragment
fn fs_target(@builtin(position) position: vec4<f32>) -> @builtin(frag_depth) f32 {
    let size = vec2<u32>(frame.viewport.xy);
    let p = vec2<u32>(position.xy);
    let i = p.y * size.x + p.x;
    var t = vec2<u32>(VISBUF_NONE, 0u);
    if (p.x < size.x && i < arrayLength(&laydown_target)) {
        t = laydown_target[i];
    }
    if (t.y == 0u) {
        return 0.0;
    }
    return bitcast<f32>(t.y);
}
