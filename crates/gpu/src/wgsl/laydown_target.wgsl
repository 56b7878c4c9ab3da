// gpu: the compute laydown's 64-bit target into what the rest of the frame reads: the
// depth target (frag_depth; depth formats cannot be storage textures) and the R32Uint vis
// texture (colour); the hardware part draws over both after it, then the vis copy makes
// the words. A full-screen triangle. A pixel whose depth bits are 0 was never drawn: far plane and VIS_NONE.

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

struct TargetOut {
    @builtin(frag_depth) depth: f32,
    @location(0) vis: u32,
}

@fragment
fn fs_target(@builtin(position) position: vec4<f32>) -> TargetOut {
    let size = vec2<u32>(frame.viewport.xy);
    let p = vec2<u32>(position.xy);
    let i = p.y * size.x + p.x;
    var t = vec2<u32>(VISBUF_NONE, 0u);
    if (p.x < size.x && i < arrayLength(&laydown_target)) {
        t = laydown_target[i];
    }
    var out: TargetOut;
    out.depth = 0.0;
    out.vis = VISBUF_NONE;
    if (t.y != 0u) {
        out.depth = bitcast<f32>(t.y);
        out.vis = t.x;
    }
    return out;
}
