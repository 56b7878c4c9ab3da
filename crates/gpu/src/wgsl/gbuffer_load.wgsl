// gpu: the G-buffer as lighting reads it, bind group 1 (deferred's octahedral layout,
// unpacked by deferred's WGSL).

#import deferred::gbuffer

@group(1) @binding(0) var gbuffer_tex0: texture_2d<f32>;
@group(1) @binding(1) var gbuffer_tex1: texture_2d<u32>;
@group(1) @binding(2) var gbuffer_tex2: texture_2d<f32>;
@group(1) @binding(3) var gbuffer_tex3: texture_2d<f32>;

fn gbuffer_surface(pixel: vec2<u32>) -> DeferredSurface {
    let p = vec2<i32>(pixel);
    return deferred_gbuffer_oct_unpack(textureLoad(gbuffer_tex0, p, 0), textureLoad(gbuffer_tex1, p, 0),
        textureLoad(gbuffer_tex2, p, 0), textureLoad(gbuffer_tex3, p, 0));
}
