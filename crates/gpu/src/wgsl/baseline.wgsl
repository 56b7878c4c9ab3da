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
    let s = material_surface_moved(instances[in.instance].material, in.uv, dpdx(in.uv), dpdy(in.uv), in.normal, in.relative, in.previous);
    return gbuffer_fragment(s, frame.view_rotation);
}
