// gpu: the G-buffer as lighting reads it, bind group 1, in deferred's octahedral layout or
// (feature `kz2_gbuffer`) KZ2's four RGBA8 targets, unpacked by deferred's WGSL.

#import deferred::gbuffer

@group(1) @binding(0) var gbuffer_tex0: texture_2d<f32>;
#if kz2_gbuffer
@group(1) @binding(1) var gbuffer_tex1: texture_2d<f32>;
#else
@group(1) @binding(1) var gbuffer_tex1: texture_2d<u32>;
#endif
@group(1) @binding(2) var gbuffer_tex2: texture_2d<f32>;
@group(1) @binding(3) var gbuffer_tex3: texture_2d<f32>;

// The surface at `pixel`, its normal camera-relative world (`view_rotation`, from
// FrameUniforms, turns the KZ2 preset's view-space normal back).
fn gbuffer_surface(pixel: vec2<u32>, view_rotation: mat4x4<f32>) -> DeferredSurface {
    let p = vec2<i32>(pixel);
#if kz2_gbuffer
    var s = deferred_gbuffer_kz2_unpack(textureLoad(gbuffer_tex0, p, 0), textureLoad(gbuffer_tex1, p, 0),
        textureLoad(gbuffer_tex2, p, 0), textureLoad(gbuffer_tex3, p, 0));
    s.normal = (transpose(view_rotation) * vec4<f32>(s.normal, 0.0)).xyz;
    return s;
#else
    return deferred_gbuffer_oct_unpack(textureLoad(gbuffer_tex0, p, 0), textureLoad(gbuffer_tex1, p, 0),
        textureLoad(gbuffer_tex2, p, 0), textureLoad(gbuffer_tex3, p, 0));
#endif
}
