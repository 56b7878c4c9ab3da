// gpu: the G-buffer as a fragment shader writes it (the baseline's geometry pass): colour
// attachments RT0..RT3 in deferred's octahedral layout or (feature `kz2_gbuffer`) KZ2's
// four RGBA8 targets.

#import deferred::gbuffer

struct GBufferOut {
    @location(0) rt0: vec4<f32>,
#if kz2_gbuffer
    @location(1) rt1: vec4<f32>,
#else
    @location(1) rt1: vec4<u32>,
#endif
    @location(2) rt2: vec4<f32>,
    @location(3) rt3: vec4<f32>,
}

// `surface.normal` is camera-relative world; `view_rotation` (FrameUniforms) turns it
// into view space for the KZ2 preset.
fn gbuffer_fragment(surface: DeferredSurface, view_rotation: mat4x4<f32>) -> GBufferOut {
#if kz2_gbuffer
    var s = surface;
    s.normal = (view_rotation * vec4<f32>(surface.normal, 0.0)).xyz;
    let t = deferred_gbuffer_kz2_pack(s);
#else
    let t = deferred_gbuffer_oct_pack(surface);
#endif
    return GBufferOut(t.rt0, t.rt1, t.rt2, t.rt3);
}
