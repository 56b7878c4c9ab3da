// gpu: FC5's foam (seed 003: "just a noise texture modulated by a noise texture", the flow
// map "sampled using two different offset phases in order to avoid pulsing", shown where
// "a signed distance field based on the shorelines and the rocks" says, with "the
// displacement foam" blended in). Per water pixel at full resolution: the world flow atlas
// sampled by world position (water::atlas), the two Vlachos layers with a per-pixel phase
// (water::flow), detail and mask noise from the FBM's noise texture through both layers,
// the shore distance field, the water depth down to the opaque bed, the decals' foam, and
// water::foam's `water_foam` with the material's shore width and intensity. The data
// word's foam mip fades the detail noise where it would alias.

#import gpu::frame
#import gpu::water_frame
#import water::gbuffer
#import water::material
#import water::atlas

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var<uniform> water: GpuWaterFrame;
@group(0) @binding(2) var surface: texture_2d<f32>;
@group(0) @binding(3) var data: texture_2d<u32>;
@group(0) @binding(4) var<storage, read> materials: array<WaterMaterialGpu>;
@group(0) @binding(5) var atlas: texture_2d<u32>;
@group(0) @binding(6) var shore: texture_2d<f32>;
@group(0) @binding(7) var noise: texture_2d<f32>;
@group(0) @binding(8) var displacement: texture_2d<f32>;
@group(0) @binding(9) var scene_depth: texture_depth_2d;
@group(0) @binding(10) var foam: texture_storage_2d<r32float, write>;

fn gpu_water_foam_pixel(uv: vec2<f32>, size: vec2<u32>) -> vec2<u32> {
    let s = max(size, vec2<u32>(1u));
    let p = clamp(uv * vec2<f32>(s), vec2<f32>(0.0), vec2<f32>(s - vec2<u32>(1u)));
    return select(vec2<u32>(0u), vec2<u32>(p), p == p);
}

// The noise texture at `uv` (texture periods), bilinear, wrapping.
fn gpu_water_noise(uv: vec2<f32>) -> f32 {
    return water_noise_bilinear(noise, water_to_fixed(uv.x), water_to_fixed(uv.y)).x;
}

// The shore distance (metres, positive in water) at water-space `p`, bilinear over texel
// centres; far from any shore outside the field or without one.
fn gpu_water_shore(p: vec2<f32>) -> f32 {
    if ((water.counts.y & GPU_WATER_FLAG_SHORE) == 0u) {
        return 1.0e4;
    }
    let size = min(water.shore_size.xy, textureDimensions(shore));
    if (size.x == 0u || size.y == 0u) {
        return 1.0e4;
    }
    let t = (p - water.shore.xy) / max(water.shore.z, 1e-6) - 0.5;
    if (!(t.x >= -0.5 && t.y >= -0.5 && t.x <= f32(size.x) - 0.5 && t.y <= f32(size.y) - 0.5)) {
        return 1.0e4;
    }
    let tc = clamp(t, vec2<f32>(0.0), vec2<f32>(size - vec2<u32>(1u)));
    let f = floor(tc);
    let a = tc - f;
    let x0 = u32(f.x);
    let y0 = u32(f.y);
    let x1 = min(x0 + 1u, size.x - 1u);
    let y1 = min(y0 + 1u, size.y - 1u);
    let top = mix(textureLoad(shore, vec2<u32>(x0, y0), 0).r, textureLoad(shore, vec2<u32>(x1, y0), 0).r, a.x);
    let bottom = mix(textureLoad(shore, vec2<u32>(x0, y1), 0).r, textureLoad(shore, vec2<u32>(x1, y1), 0).r, a.x);
    let d = mix(top, bottom, a.y) * water.shore.z;
    return select(1.0e4, d, abs(d) < 1.0e6);
}

@compute @workgroup_size(8, 8)
fn foam_pass(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(surface);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let s = textureLoad(surface, id.xy, 0);
    if (!gpu_water_depth_ok(s.r)) {
        textureStore(foam, id.xy, vec4<f32>(0.0));
        return;
    }
    let g = gpu_water_foam_pixel(s.gb, textureDimensions(data));
    let word = textureLoad(data, g, 0).r;
    let count = max(min(water.counts.x, arrayLength(&materials)), 1u);
    let m = materials[min(word >> WATER_MATERIAL_SHIFT, count - 1u)];
    let rel = gpu_water_relative(water, vec2<f32>(id.xy) + 0.5, s.r, size, water.tan_half.xy);
    let p = rel + water.camera.xyz;
    let wp = gpu_water_xy(p);
    var flow = vec2<f32>(0.0);
    if ((water.counts.y & GPU_WATER_FLAG_FLOW) != 0u) {
        flow = water_flow_atlas_sample(atlas, wp).xy;
        flow = select(vec2<f32>(0.0), flow, abs(flow) < vec2<f32>(1.0e4));
    }
    // The water depth: the surface down to the opaque point behind it.
    var depth = 1.0e4;
    let sd = textureDimensions(scene_depth);
    let ds = textureLoad(scene_depth, min(id.xy, sd - vec2<u32>(1u)), 0);
    if (ds > 0.0) {
        let bed = gpu_water_relative(water, vec2<f32>(id.xy) + 0.5, water.camera.w / ds, size, water.tan_half.xy);
        depth = max(rel.y - bed.y, 0.0);
    }
    // Two phase-offset layers over the noise, the texture moving with the flow: a layer
    // scrolls `flow * distance` UV per cycle of 2 * interval seconds.
    let freq = water.misc.z;
    let uv = wp * freq;
    let cycle = 2.0 * max(water.flow.interval, 1e-3);
    let flow_uv = flow * freq * cycle / max(water.flow.distance, 1e-3);
    let phase = water_value_noise(wp * 0.37, 17u);
    let l = water_flow_layers(uv, flow_uv, water.misc.x, phase, water.flow);
    let mip = water_unpack_data(word).foam_mip;
    let detail_weight = saturate(1.0 - mip * 0.25);
    let detail = (l.w0 * gpu_water_noise(l.uv0 * 4.0) + l.w1 * gpu_water_noise(l.uv1 * 4.0)) * detail_weight;
    let mask = l.w0 * gpu_water_noise(l.uv0 * 0.5 + 0.3) + l.w1 * gpu_water_noise(l.uv1 * 0.5 + 0.3);
    let dsize = textureDimensions(displacement);
    let splash = textureLoad(displacement, gpu_water_foam_pixel(s.gb, dsize), 0).w;
    var prm = water.foam;
    prm.shore_width = m.shore_width;
    prm.intensity = m.foam_intensity;
    let inputs = WaterFoamInputs(gpu_water_shore(wp), length(flow), depth, detail, mask, select(0.0, splash, splash == splash));
    let f = water_foam(inputs, prm);
    textureStore(foam, id.xy, vec4<f32>(select(0.0, f, f == f), 0.0, 0.0, 0.0));
}
