// gpu: deferred lighting in compute (KZ2's sun + ambient + local lights over the
// G-buffer), then tone mapping into the sRGB-encoded output image. One 16x16 workgroup
// per light tile: each pixel reads its tile's light list (deferred's culling pass) and
// shades the lights whose volume holds it; with feature `all_lights`, every light is
// tested at every pixel instead (the reference the tiled path must equal). With feature
// `light_volumes`, the lights drawn as stencil volumes before (their sum in
// `light_accumulation`) are added. Local lights
// are in view space: the pixel's camera-relative position and normal are rotated into it
// (dot products, and so the shading, do not change). The sun is shadowed by its slice of
// the cascaded shadow maps (gpu::shadows) and the G-buffer's baked term, the darker of the
// two; its shader is skipped where the baked term is 0.

#import gpu::frame
#import gpu::gbuffer_load
#import deferred::lights
#import deferred::shadow
#import gpu::light_shading

// Rust: gpu::shadows::GpuSunShadow (720 bytes).
struct GpuSunShadow {
    cascades: array<DeferredCascade, 8>,
    // cascades in use; 0: no real-time sun shadow
    count: u32,
    // texels per side of each map
    resolution: u32,
    pad: vec2<u32>,
    // per slice: its PCF radius in texels, at most GPU_MAX_PCF_RADIUS
    pcf_radius: array<vec4<u32>, 2>,
    // per slice: texels per side of its map, in the corner of its layer
    slice_texels: array<vec4<u32>, 2>,
}

// Rust: shadows::MAX_PCF_RADIUS.
const GPU_MAX_PCF_RADIUS: u32 = 2u;

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var depth_texture: texture_depth_2d;
@group(0) @binding(2) var<uniform> local: GpuLocalLights;
@group(0) @binding(3) var<storage, read> lights: array<DeferredLight>;
@group(0) @binding(4) var<storage, read> light_counts: array<u32>;
@group(0) @binding(5) var<storage, read> light_indices: array<u32>;
@group(0) @binding(6) var shadow_map: texture_depth_2d_array;
@group(0) @binding(7) var<uniform> sun_shadow: GpuSunShadow;
@group(0) @binding(8) var output: texture_storage_2d<rgba8unorm, write>;
// The stencil light volumes' sum (read with feature `light_volumes`).
@group(0) @binding(9) var light_accumulation: texture_2d<f32>;
// The shadowed spots' maps and rows (spot_shadows.rs).
@group(0) @binding(10) var spot_shadow_map: texture_depth_2d_array;
@group(0) @binding(11) var<storage, read> spot_shadows: array<GpuSpotShadow>;
// Group 1: the G-buffer (gpu::gbuffer_load).

// Narkowicz's ACES fit.
fn lighting_tonemap(x: vec3<f32>) -> vec3<f32> {
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), vec3<f32>(0.0), vec3<f32>(1.0));
}

fn lighting_srgb(c: vec3<f32>) -> vec3<f32> {
    let lo = c * 12.92;
    let hi = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(hi, lo, c <= vec3<f32>(0.0031308));
}

// The sun's visibility at camera-relative `p` (normal `n`, view distance `dist`): the
// first cascade whose slice reaches `dist`, the point pushed 1.5 texels along its normal
// (against acne on slopes), a (2r + 1)^2 texel PCF of `depth <= stored` (0 nearest the
// sun) with the slice's radius r (KZ2: each slice its own tap count). 1 beyond the last
// slice, off the map, or with shadows off.
fn lighting_sun_visibility(p: vec3<f32>, n: vec3<f32>, dist: f32) -> f32 {
    let count = min(sun_shadow.count, 8u);
    var k = 0u;
    while (k < count && dist > sun_shadow.cascades[k].split_far) {
        k += 1u;
    }
    if (k >= count || k >= textureNumLayers(shadow_map)) {
        return 1.0;
    }
    let c = sun_shadow.cascades[k];
    let coord = deferred_shadow_coord(c, p + n * (1.5 * c.texel_size));
    // The slice's own resolution (KZ2: per slice), within its layer.
    let layer = vec2<i32>(textureDimensions(shadow_map));
    let size = min(vec2<i32>(i32(sun_shadow.slice_texels[k / 4u][k % 4u])), layer);
    if (!(all(coord.xy >= vec2<f32>(0.0)) && all(coord.xy < vec2<f32>(1.0)) && coord.z <= 1.0)) {
        return 1.0;
    }
    let centre = vec2<i32>(coord.xy * vec2<f32>(size));
    let r = i32(min(sun_shadow.pcf_radius[k / 4u][k % 4u], GPU_MAX_PCF_RADIUS));
    var lit = 0.0;
    for (var dy = -r; dy <= r; dy++) {
        for (var dx = -r; dx <= r; dx++) {
            let t = clamp(centre + vec2<i32>(dx, dy), vec2<i32>(0), size - 1);
            let stored = textureLoad(shadow_map, t, i32(k), 0);
            lit += select(0.0, 1.0, coord.z <= stored);
        }
    }
    let side = f32(2 * r + 1);
    return lit / (side * side);
}

#if !all_lights
// The tile's lights, staged once per workgroup (DEFERRED_MAX_LIGHTS_PER_TILE is the
// workgroup's size: one load per invocation), as three vec4 arrays so that the sphere
// test reads one vector and only lights that reach the pixel read the rest.
var<workgroup> lighting_pos_range: array<vec4<f32>, DEFERRED_MAX_LIGHTS_PER_TILE>;
var<workgroup> lighting_dir_cos: array<vec4<f32>, DEFERRED_MAX_LIGHTS_PER_TILE>;
var<workgroup> lighting_color_flags: array<vec4<f32>, DEFERRED_MAX_LIGHTS_PER_TILE>;
var<workgroup> lighting_tile_count: u32;
#endif

// Local light `l` at `at`, shadowed through its spot map if it has one this frame.
fn lighting_local_light(l: DeferredLight, at: LightShadingPoint, s: DeferredSurface) -> vec3<f32> {
    let c = light_shading_local(l, at, s);
    let slot = light_shading_shadow_slot(l);
    if (slot == 0u || slot > arrayLength(&spot_shadows) || !any(c > vec3<f32>(0.0))) {
        return c;
    }
    return c * light_shading_spot_visibility(spot_shadow_map, spot_shadows[slot - 1u], slot - 1u, l, at);
}

@compute @workgroup_size(16, 16)
fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) li: u32) {
    let light_count = min(frame.local_light_count, arrayLength(&lights));
#if !all_lights
    // Staging first (a chain of three loads: count, index, light), then the pixel's own
    // loads and the sun, so that the two overlap before the barrier. Every invocation
    // takes part, whether its pixel exists or holds geometry.
    let tile = wid.y * local.tiles.x + wid.x;
    var count = 0u;
    if (tile < arrayLength(&light_counts)) {
        count = min(light_counts[tile], DEFERRED_MAX_LIGHTS_PER_TILE);
    }
    let slot = tile * DEFERRED_MAX_LIGHTS_PER_TILE + li;
    if (li < count && slot < arrayLength(&light_indices)) {
        let i = light_indices[slot];
        let l = lights[min(i, max(light_count, 1u) - 1u)];
        // A corrupt index stages a light that lights nothing.
        let range = select(0.0, l.range, i < light_count);
        lighting_pos_range[li] = vec4<f32>(l.position, range);
        lighting_dir_cos[li] = vec4<f32>(l.direction, l.cos_outer);
        lighting_color_flags[li] = vec4<f32>(l.color, bitcast<f32>(l.flags));
    }
    if (li == 0u) {
        lighting_tile_count = count;
    }
#endif
    let size = vec2<u32>(frame.viewport.xy);
    let inside = id.x < size.x && id.y < size.y;
    let pixel = min(id.xy, max(size, vec2<u32>(1u)) - 1u);
    let d = textureLoad(depth_texture, vec2<i32>(pixel), 0);
    let lit = inside && d > 0.0;
    var color = frame.sky.rgb;
    var s: DeferredSurface;
    var at = LightShadingPoint(vec3<f32>(0.0), vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(0.0));
    if (lit) {
        s = gbuffer_surface(pixel, frame.view_rotation);
        let p = light_shading_position(frame.inv_view_proj, frame.viewport.zw, pixel, d);
        at = light_shading_point(local.view_rotation, p, s);
        let v = normalize(-p);
        let n = s.normal;
        let l = frame.sun_direction.xyz;
        let nl = max(dot(n, l), 0.0);
        color = s.lighting + s.albedo * frame.ambient.rgb * (0.6 + 0.4 * n.y);
        // KZ2's mix of the baked sun term and the real-time shadow: the darker of the two;
        // the sun's shader is skipped where the baked term is 0 (fully in baked shadow) or
        // the surface faces away.
        var sun = s.sun_shadow;
        if (sun > 0.0 && nl > 0.0) {
            sun = min(sun, lighting_sun_visibility(p, n, -at.p.z));
        }
        color += frame.sun_color.rgb * (at.diffuse * nl * sun + s.specular * light_shading_specular(n, v, l, s.roughness, 0.04) * sun);
#if light_volumes
        // The lights the stencil volumes drew (passes::light_volumes), summed there.
        color += textureLoad(light_accumulation, vec2<i32>(pixel), 0).rgb;
#endif
    }
#if all_lights
    if (lit) {
        for (var i = 0u; i < light_count; i++) {
            let l = lights[i];
            if (light_shading_in_sphere(vec4<f32>(l.position, l.range), at.p)) {
                color += lighting_local_light(l, at, s);
            }
        }
    }
#else
    let staged = workgroupUniformLoad(&lighting_tile_count);
    if (lit) {
        for (var k = 0u; k < staged; k++) {
            let pr = lighting_pos_range[k];
            if (!light_shading_in_sphere(pr, at.p)) {
                continue;
            }
            let dc = lighting_dir_cos[k];
            let cf = lighting_color_flags[k];
            let l = DeferredLight(pr.xyz, pr.w, dc.xyz, dc.w, cf.xyz, bitcast<u32>(cf.w));
            color += lighting_local_light(l, at, s);
        }
    }
#endif
    if (inside) {
        textureStore(output, vec2<i32>(pixel), vec4<f32>(lighting_srgb(lighting_tonemap(color)), 1.0));
    }
}
