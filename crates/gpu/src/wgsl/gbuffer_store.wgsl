// gpu: the G-buffer as the compute resolve writes it, bind group 2: deferred's octahedral
// layout (RT0..RT3 formats: deferred::GBufferLayout::Octahedral, checked against the
// resolve's description), packed by deferred's WGSL.

#import deferred::gbuffer

@group(2) @binding(0) var gbuffer_rt0: texture_storage_2d<rgba8unorm, write>;
@group(2) @binding(1) var gbuffer_rt1: texture_storage_2d<rgba8uint, write>;
@group(2) @binding(2) var gbuffer_rt2: texture_storage_2d<rgba16float, write>;
@group(2) @binding(3) var gbuffer_rt3: texture_storage_2d<rgba8unorm, write>;

fn gbuffer_store(pixel: vec2<u32>, surface: DeferredSurface) {
    let t = deferred_gbuffer_oct_pack(surface);
    textureStore(gbuffer_rt0, vec2<i32>(pixel), t.rt0);
    textureStore(gbuffer_rt1, vec2<i32>(pixel), t.rt1);
    textureStore(gbuffer_rt2, vec2<i32>(pixel), t.rt2);
    textureStore(gbuffer_rt3, vec2<i32>(pixel), t.rt3);
}
