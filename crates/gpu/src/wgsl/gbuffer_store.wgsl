// gpu: the G-buffer as the compute resolve writes it, bind group 2, in deferred's
// octahedral layout or (feature `kz2_gbuffer`) KZ2's four RGBA8 targets (formats:
// deferred::GBufferLayout, checked against the resolve's descriptions), packed by
// deferred's WGSL.

#import deferred::gbuffer

#if kz2_gbuffer
@group(2) @binding(0) var gbuffer_rt0: texture_storage_2d<rgba8unorm, write>;
@group(2) @binding(1) var gbuffer_rt1: texture_storage_2d<rgba8unorm, write>;
@group(2) @binding(2) var gbuffer_rt2: texture_storage_2d<rgba8unorm, write>;
@group(2) @binding(3) var gbuffer_rt3: texture_storage_2d<rgba8unorm, write>;
#else
@group(2) @binding(0) var gbuffer_rt0: texture_storage_2d<rgba16float, write>;
@group(2) @binding(1) var gbuffer_rt1: texture_storage_2d<rgba8uint, write>;
@group(2) @binding(2) var gbuffer_rt2: texture_storage_2d<rgba16float, write>;
@group(2) @binding(3) var gbuffer_rt3: texture_storage_2d<rgba8unorm, write>;
#endif

// `surface.normal` is camera-relative world; `view_rotation` (FrameUniforms) turns it
// into view space for the KZ2 preset.
fn gbuffer_store(pixel: vec2<u32>, surface: DeferredSurface, view_rotation: mat4x4<f32>) {
#if kz2_gbuffer
    var s = surface;
    s.normal = (view_rotation * vec4<f32>(surface.normal, 0.0)).xyz;
    let t = deferred_gbuffer_kz2_pack(s);
#else
    let t = deferred_gbuffer_oct_pack(surface);
#endif
    textureStore(gbuffer_rt0, vec2<i32>(pixel), t.rt0);
    textureStore(gbuffer_rt1, vec2<i32>(pixel), t.rt1);
    textureStore(gbuffer_rt2, vec2<i32>(pixel), t.rt2);
    textureStore(gbuffer_rt3, vec2<i32>(pixel), t.rt3);
}
