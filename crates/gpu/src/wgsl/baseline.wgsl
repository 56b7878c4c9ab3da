// gpu: HZD's geometry pass, the method the talk replaces: after the depth prepass (with
// alpha test), every batch is drawn again with depth test Equal and no alpha test, writing
// the G-buffer from a fragment shader whose UV gradients come from the hardware's quads.
// The vertex transform is the laydown's (gpu::geometry), so the depths are bit-identical.

#import gpu::geometry
#import gpu::material
#import gpu::gbuffer_fragment

struct BaselineOut {
    @invariant @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) @interpolate(flat) instance: u32,
    @location(2) normal: vec3<f32>,
    // camera-relative position (for the motion vector)
    @location(3) relative: vec3<f32>,
    // the same point at the previous frame's time (animated foliage's motion)
    @location(4) previous: vec3<f32>,
    // camera-relative world tangent, handedness in w (the normal map's frame)
    @location(5) tangent: vec4<f32>,
}

@vertex
fn vs_baseline(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> BaselineOut {
    let l = laydown_vertex(vertex, instance);
    var out: BaselineOut;
    out.clip = l.clip;
    out.uv = l.uv;
    out.instance = instance;
    out.normal = gpu_transform_normal(instances[instance], vertices[vertex].normal);
    out.relative = gpu_position(instances[instance], vertices[vertex].position);
    out.previous = gpu_previous_position(instances[instance], vertices[vertex].position);
    let t = vertices[vertex].tangent;
    out.tangent = vec4<f32>(gpu_transform_direction(instances[instance], t.xyz), t.w);
    return out;
}

// The static instances' variant: the laydown's fade dither first (a fading instance's
// dithered-away pixels would pass a coplanar partner's depth-equal test).
@fragment
fn fs_baseline_fade(in: BaselineOut) -> GBufferOut {
    if (!gpu_fade_keeps(instances[in.instance].primitive_bits, vec2<u32>(in.clip.xy))) {
        discard;
    }
    return baseline_gbuffer(in);
}

@fragment
fn fs_baseline(in: BaselineOut) -> GBufferOut {
    return baseline_gbuffer(in);
}

fn baseline_gbuffer(in: BaselineOut) -> GBufferOut {
    let s = material_surface_moved(instances[in.instance].material, in.uv, dpdx(in.uv), dpdy(in.uv), in.normal, in.tangent, in.relative, in.previous);
    return gbuffer_fragment(s, frame.view_rotation);
}

#if regular
// HFW's mixed frame: the regular geometry pass after the laydown draws the batches whose
// material is `regular` (terrain, rocks) with depth test Greater over the laydown's depth,
// writing the G-buffer, and clears each drawn pixel's validity bit (the talk's stencil bit,
// which wgpu cannot bind as storage: a bitmask in a buffer, bit i % 32 of word i / 32 for
// pixel i), so classify output leaves the pixel to this pass. The depth test must run
// before the shader (`early_depth_test(force)`): a fragment behind the vis buffer's must
// not clear the bit. Any fragment that passes is in front of the laydown's surface, and
// later fragments of this pass can only replace it, so the bit is cleared exactly where
// the final pixel is this pass's.
@group(1) @binding(0) var<storage, read_write> validity: array<atomic<u32>>;

@fragment
@early_depth_test(force)
fn fs_regular(in: BaselineOut) -> GBufferOut {
    let out = baseline_gbuffer(in);
    let p = vec2<u32>(in.clip.xy);
    let i = p.y * u32(frame.viewport.x) + p.x;
    // Bounds-checked: a pixel past the mask (a mask sized for another image) clears nothing.
    if ((i >> 5u) < arrayLength(&validity)) {
        atomicAnd(&validity[i >> 5u], ~(1u << (i & 31u)));
    }
    return out;
}
#endif
