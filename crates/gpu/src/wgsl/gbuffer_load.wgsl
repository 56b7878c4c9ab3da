// gpu: the G-buffer as lighting reads it, bind group 1, in deferred's octahedral layout or
// (feature `kz2_gbuffer`) KZ2's four RGBA8 targets, unpacked by deferred's WGSL. With
// feature `msaa`, the baseline's multisampled targets, read a sample at a time.

#import deferred::gbuffer
#import deferred::shadow

#if msaa
@group(1) @binding(0) var gbuffer_tex0: texture_multisampled_2d<f32>;
#if kz2_gbuffer
@group(1) @binding(1) var gbuffer_tex1: texture_multisampled_2d<f32>;
#else
@group(1) @binding(1) var gbuffer_tex1: texture_multisampled_2d<u32>;
#endif
@group(1) @binding(2) var gbuffer_tex2: texture_multisampled_2d<f32>;
@group(1) @binding(3) var gbuffer_tex3: texture_multisampled_2d<f32>;
#else
@group(1) @binding(0) var gbuffer_tex0: texture_2d<f32>;
#if kz2_gbuffer
@group(1) @binding(1) var gbuffer_tex1: texture_2d<f32>;
#else
@group(1) @binding(1) var gbuffer_tex1: texture_2d<u32>;
#endif
@group(1) @binding(2) var gbuffer_tex2: texture_2d<f32>;
@group(1) @binding(3) var gbuffer_tex3: texture_2d<f32>;
#endif

// The raw texels of sample `sample` at `pixel` (single-sample: the texel; `sample`
// unused).
struct GBufferTexels {
    rt0: vec4<f32>,
#if kz2_gbuffer
    rt1: vec4<f32>,
#else
    rt1: vec4<u32>,
#endif
    rt2: vec4<f32>,
    rt3: vec4<f32>,
}

fn gbuffer_texels(pixel: vec2<u32>, sample: u32) -> GBufferTexels {
    let p = vec2<i32>(pixel);
#if msaa
    let s = i32(sample);
#else
    let s = 0;
#endif
    return GBufferTexels(textureLoad(gbuffer_tex0, p, s), textureLoad(gbuffer_tex1, p, s),
        textureLoad(gbuffer_tex2, p, s), textureLoad(gbuffer_tex3, p, s));
}

// Whether two samples' texels differ in any bit (MSAA's edge test).
fn gbuffer_texels_differ(a: GBufferTexels, b: GBufferTexels) -> bool {
    return deferred_words_differ(bitcast<vec4<u32>>(a.rt0), bitcast<vec4<u32>>(b.rt0))
        || deferred_words_differ(bitcast<vec4<u32>>(a.rt1), bitcast<vec4<u32>>(b.rt1))
        || deferred_words_differ(bitcast<vec4<u32>>(a.rt2), bitcast<vec4<u32>>(b.rt2))
        || deferred_words_differ(bitcast<vec4<u32>>(a.rt3), bitcast<vec4<u32>>(b.rt3));
}

// The surface of texels `t`, its normal camera-relative world (`view_rotation`, from
// FrameUniforms, turns the KZ2 preset's view-space normal back).
fn gbuffer_unpack(t: GBufferTexels, view_rotation: mat4x4<f32>) -> DeferredSurface {
#if kz2_gbuffer
    var s = deferred_gbuffer_kz2_unpack(t.rt0, t.rt1, t.rt2, t.rt3);
    s.normal = (transpose(view_rotation) * vec4<f32>(s.normal, 0.0)).xyz;
    return s;
#else
    return deferred_gbuffer_oct_unpack(t.rt0, t.rt1, t.rt2, t.rt3);
#endif
}

// The surface at `pixel` (sample 0).
fn gbuffer_surface(pixel: vec2<u32>, view_rotation: mat4x4<f32>) -> DeferredSurface {
    return gbuffer_unpack(gbuffer_texels(pixel, 0u), view_rotation);
}
