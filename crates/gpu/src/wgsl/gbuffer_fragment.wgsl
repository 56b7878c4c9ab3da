// gpu: the G-buffer as a fragment shader writes it (the baseline's geometry pass): colour
// attachments RT0..RT3 in deferred's octahedral layout.

#import deferred::gbuffer

struct GBufferOut {
    @location(0) rt0: vec4<f32>,
    @location(1) rt1: vec4<u32>,
    @location(2) rt2: vec4<f32>,
    @location(3) rt3: vec4<f32>,
}

fn gbuffer_fragment(surface: DeferredSurface) -> GBufferOut {
    let t = deferred_gbuffer_oct_pack(surface);
    return GBufferOut(t.rt0, t.rt1, t.rt2, t.rt3);
}
