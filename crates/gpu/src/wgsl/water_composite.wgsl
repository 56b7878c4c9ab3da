// gpu: FC5's surface composite (seed 003), over the lit opaque image, per pixel the
// tessellated surface covers (the opaque pixels around it are left as lighting wrote
// them). Light transport from the water-type table instead of an artist's colour
// (water::optics: the material's absorption and scattering, Beer-Lambert over the path
// from the surface down to the opaque point behind it, single scattering of the ambient
// and sun light), that point's colour refracted by the normal (the lit opaque scene, HDR,
// before tone mapping), reflection of the sky (and, with GPU_WATER_FLAG_SSR, screen-space
// reflections of the opaque scene along the reflected ray) by Fresnel, the sun's GGX
// highlight with the roughness widened by the normal's variance (variance-based specular
// AA: the neighbours' normals and the FBM octaves the LOD dropped), the frame's local
// lights from the water's own 16x16 tile lists, foam on top, and the material blended
// over `material_map.w` metres (the talk's 6) where two bodies meet, only the fields
// that need it. Tone mapped as lighting does into the output image.
//
// With feature `f16` (SHADER_F16) the material blend, the light transport and the
// composition run in half precision (the talk's min16float, which freed nine VGPRs of
// this pass on AMD); without it in f32.

#if f16
enable f16;
alias gpu_water_float = f16;
alias gpu_water_vec3 = vec3<f16>;
#else
alias gpu_water_float = f32;
alias gpu_water_vec3 = vec3<f32>;
#endif

#import gpu::frame
#import gpu::water_frame
#import gpu::light_shading
#import water::gbuffer
#import water::material
#import water::optics
#import water::specaa

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var<uniform> water: GpuWaterFrame;
@group(0) @binding(2) var<uniform> local: GpuLocalLights;
@group(0) @binding(3) var<storage, read> lights: array<DeferredLight>;
@group(0) @binding(4) var<storage, read> light_counts: array<u32>;
@group(0) @binding(5) var<storage, read> light_indices: array<u32>;
@group(0) @binding(6) var surface: texture_2d<f32>;
@group(0) @binding(7) var normals: texture_2d<f32>;
@group(0) @binding(8) var foam: texture_2d<f32>;
@group(0) @binding(9) var data: texture_2d<u32>;
@group(0) @binding(10) var<storage, read> materials: array<WaterMaterialGpu>;
@group(0) @binding(11) var material_map: texture_2d<u32>;
@group(0) @binding(12) var scene_hdr: texture_2d<f32>;
@group(0) @binding(13) var scene_depth: texture_depth_2d;
@group(0) @binding(14) var output: texture_storage_2d<rgba8unorm, write>;

// The fields of a material the composite blends and shades with, in the pass's precision.
struct GpuWaterShading {
    absorption: gpu_water_vec3,
    scattering: gpu_water_vec3,
    roughness: gpu_water_float,
    max_roughness: gpu_water_float,
}

fn gpu_water_shading(m: WaterMaterialGpu) -> GpuWaterShading {
    return GpuWaterShading(
        gpu_water_vec3(m.absorption.xyz),
        gpu_water_vec3(m.scattering.xyz),
        gpu_water_float(m.absorption.w),
        gpu_water_float(m.scattering.w),
    );
}

// water::material's blend on the fields the composite reads (`water_material_blend`).
fn gpu_water_blend(a: GpuWaterShading, b: GpuWaterShading, t: gpu_water_float) -> GpuWaterShading {
    return GpuWaterShading(
        mix(a.absorption, b.absorption, gpu_water_vec3(t)),
        mix(a.scattering, b.scattering, gpu_water_vec3(t)),
        mix(a.roughness, b.roughness, t),
        mix(a.max_roughness, b.max_roughness, t),
    );
}

// `water_light_transport` in the pass's precision: bed * T + light * albedo * (1 - T).
fn gpu_water_transport(m: GpuWaterShading, bed: gpu_water_vec3, light: gpu_water_vec3, d: gpu_water_float) -> gpu_water_vec3 {
    let sigma = m.absorption + m.scattering;
    let t = exp(-sigma * max(d, gpu_water_float(0.0)));
    let albedo = select(gpu_water_vec3(0.0), m.scattering / sigma, sigma > gpu_water_vec3(0.0));
    return bed * t + light * albedo * (gpu_water_vec3(1.0) - t);
}

// Narkowicz's ACES fit and the sRGB encode: lighting's (gpu::lighting), so the water
// meets the opaque image with the same curve.
fn gpu_water_tonemap(x: vec3<f32>) -> vec3<f32> {
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), vec3<f32>(0.0), vec3<f32>(1.0));
}

fn gpu_water_srgb(c: vec3<f32>) -> vec3<f32> {
    let lo = c * 12.92;
    let hi = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(hi, lo, c <= vec3<f32>(0.0031308));
}

fn gpu_water_clamp_pixel(p: vec2<i32>, size: vec2<u32>) -> vec2<u32> {
    return vec2<u32>(clamp(p, vec2<i32>(0), vec2<i32>(max(size, vec2<u32>(1u))) - 1));
}

// The opaque scene's camera-relative point at pixel `p` of reversed depth `ds` (0: sky).
fn gpu_water_opaque(p: vec2<u32>, ds: f32) -> vec3<f32> {
    return gpu_water_relative(water, vec2<f32>(p) + 0.5, water.camera.w / ds, water.size.xy, water.tan_half.xy);
}

// The sky seen along world direction `r`: the frame's sky colour towards the zenith,
// brighter at the horizon.
fn gpu_water_sky(r: vec3<f32>) -> vec3<f32> {
    let horizon = mix(frame.sky.rgb, vec3<f32>(1.0), 0.35);
    return mix(horizon, frame.sky.rgb * 0.85, sqrt(saturate(r.y)));
}

// Screen-space reflection of the opaque scene along `dir` from camera-relative `start`:
// rgb and a weight (0: missed). Geometric steps, then a bisection of the last interval.
fn gpu_water_ssr(start: vec3<f32>, dir: vec3<f32>) -> vec4<f32> {
    let steps = u32(clamp(water.misc.w, 0.0, 64.0));
    let size = water.size.xy;
    var t0 = 0.0;
    var t = 0.25;
    for (var i = 0u; i < steps; i++) {
        let q = start + dir * t;
        let clip = frame.view_proj * vec4<f32>(q, 1.0);
        if (!(clip.w > water.camera.w)) {
            return vec4<f32>(0.0);
        }
        let ndc = clip.xy / clip.w;
        if (any(abs(ndc) >= vec2<f32>(1.0))) {
            return vec4<f32>(0.0);
        }
        let uv = ndc * vec2<f32>(0.5, -0.5) + 0.5;
        let px = gpu_water_clamp_pixel(vec2<i32>(uv * vec2<f32>(size)), size);
        let ds = textureLoad(scene_depth, px, 0);
        let ray = gpu_water_view_depth(water, q);
        if (ds > 0.0) {
            let scene = water.camera.w / ds;
            if (ray > scene && ray - scene < max(0.5, 0.1 * t)) {
                // Bisection between the last two samples.
                var a = t0;
                var b = t;
                for (var k = 0u; k < 4u; k++) {
                    let mid = 0.5 * (a + b);
                    let qm = start + dir * mid;
                    let cm = frame.view_proj * vec4<f32>(qm, 1.0);
                    let um = (cm.xy / cm.w) * vec2<f32>(0.5, -0.5) + 0.5;
                    let pm = gpu_water_clamp_pixel(vec2<i32>(um * vec2<f32>(size)), size);
                    let dm = textureLoad(scene_depth, pm, 0);
                    if (dm > 0.0 && gpu_water_view_depth(water, qm) > water.camera.w / dm) {
                        b = mid;
                    } else {
                        a = mid;
                    }
                }
                let cb = frame.view_proj * vec4<f32>(start + dir * b, 1.0);
                let ub = (cb.xy / cb.w) * vec2<f32>(0.5, -0.5) + 0.5;
                let pb = gpu_water_clamp_pixel(vec2<i32>(ub * vec2<f32>(size)), size);
                let edge = min(min(ub.x, 1.0 - ub.x), min(ub.y, 1.0 - ub.y));
                let fade = saturate(edge * 10.0) * (1.0 - f32(i) / f32(max(steps, 1u)));
                let c = textureLoad(scene_hdr, pb, 0).rgb;
                return vec4<f32>(select(vec3<f32>(0.0), c, c == c), fade);
            }
        }
        t0 = t;
        t *= 1.4;
    }
    return vec4<f32>(0.0);
}

// Where a pixel blends towards another material, and how far.
struct GpuWaterBlend {
    other: u32,
    t: f32,
}

// The material blend at water-space `p` for material `own`: each of the four material map
// texels around `p` (own material, the other material within reach, the distance to
// their boundary on the own side) gives water::material's weight, interpolated.
fn gpu_water_blend_at(p: vec2<f32>, own: u32) -> GpuWaterBlend {
    var out = GpuWaterBlend(own, 0.0);
    if ((water.counts.y & GPU_WATER_FLAG_MATERIAL_MAP) == 0u) {
        return out;
    }
    let size = min(water.counts.zw, textureDimensions(material_map));
    if (size.x == 0u || size.y == 0u) {
        return out;
    }
    let t = (p - water.material_map.xy) / max(water.material_map.z, 1e-6) - 0.5;
    if (!(t.x >= 0.0 && t.y >= 0.0 && t.x < f32(size.x - 1u) && t.y < f32(size.y - 1u))) {
        return out;
    }
    let f = floor(t);
    let a = t - f;
    let base = vec2<u32>(f);
    let blend = max(water.material_map.w, 1e-3);
    var weight = 0.0;
    var total = 0.0;
    for (var k = 0u; k < 4u; k++) {
        let c = base + vec2<u32>(k & 1u, k >> 1u);
        let w = textureLoad(material_map, c, 0).r;
        let texel_own = w & 0x7ffu;
        let other = (w >> 11u) & 0x7ffu;
        let d = f32(w >> 22u) / 1023.0 * blend * 0.5;
        let wk = select(1.0 - a.x, a.x, (k & 1u) != 0u) * select(1.0 - a.y, a.y, (k >> 1u) != 0u);
        if (texel_own == own && other != GPU_WATER_NO_MATERIAL) {
            weight += wk * water_blend_weight(d, blend);
            out.other = other;
        }
        total += wk;
    }
    out.t = select(0.0, weight / total, total > 0.0);
    return out;
}

@compute @workgroup_size(8, 8)
fn composite(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = min(textureDimensions(surface), water.size.xy);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let s = textureLoad(surface, id.xy, 0);
    if (!gpu_water_depth_ok(s.r)) {
        return;
    }
    let pixel = id.xy;
    let gsize = max(textureDimensions(data), vec2<u32>(1u));
    let gp = clamp(s.gb * vec2<f32>(gsize), vec2<f32>(0.0), vec2<f32>(gsize - vec2<u32>(1u)));
    let g = select(vec2<u32>(0u), vec2<u32>(gp), gp == gp);
    let word = textureLoad(data, g, 0).r;
    let count = max(min(water.counts.x, arrayLength(&materials)), 1u);
    let own = min(word >> WATER_MATERIAL_SHIFT, count - 1u);
    let rel = gpu_water_relative(water, vec2<f32>(pixel) + 0.5, s.r, size, water.tan_half.xy);
    let p = rel + water.camera.xyz;
    let dist = length(rel);
    let v = -rel / max(dist, 1e-6);
    var n = textureLoad(normals, pixel, 0).xyz;
    if (!(dot(n, n) > 0.25) || !(dot(n, n) < 4.0)) {
        n = vec3<f32>(0.0, 1.0, 0.0);
    }
    n = normalize(n);
    if (dot(n, v) < 0.0) {
        n = normalize(n - v * (dot(n, v) - 1e-3));
    }
    // Variance-based specular AA: the normal's spread over the pixel's footprint (its
    // neighbours) plus the slope variance the FBM's octave LOD left out.
    let nsize = textureDimensions(normals);
    let nx = textureLoad(normals, gpu_water_clamp_pixel(vec2<i32>(pixel) + vec2<i32>(1, 0), nsize), 0).xyz;
    let ny = textureLoad(normals, gpu_water_clamp_pixel(vec2<i32>(pixel) + vec2<i32>(0, 1), nsize), 0).xyz;
    let dx = select(vec3<f32>(0.0), nx - n, dot(nx, nx) > 0.25 && dot(nx, nx) < 4.0);
    let dy = select(vec3<f32>(0.0), ny - n, dot(ny, ny) > 0.25 && dot(ny, ny) < 4.0);
    let own_m = materials[own];
    let variance = water_variance_from_derivatives(dx, dy)
        + gpu_water_dropped_variance(water.fbm, dist, own_m.displacement_amplitude);
    // The 6 m material blend where two bodies meet.
    let wp = gpu_water_xy(p);
    let b = gpu_water_blend_at(wp, own);
    var m = gpu_water_shading(own_m);
    if (b.t > 0.0) {
        m = gpu_water_blend(m, gpu_water_shading(materials[min(b.other, count - 1u)]), gpu_water_float(b.t));
    }
    let roughness = water_filtered_roughness(f32(m.roughness), variance, water.normals.z, f32(m.max_roughness));
    // Refraction: the opaque scene behind, shifted by the normal, where it is still behind
    // the water; the path through the water down to it.
    let ssize = textureDimensions(scene_depth);
    let nv = (local.view_rotation * vec4<f32>(n, 0.0)).xyz;
    let strength = water.misc.y * f32(size.y) * 0.5 / (water.tan_half.y * max(s.r, 0.5));
    var rp = gpu_water_clamp_pixel(vec2<i32>(vec2<f32>(pixel) + nv.xy * vec2<f32>(1.0, -1.0) * strength), ssize);
    var ds = textureLoad(scene_depth, rp, 0);
    let surface_depth = water.camera.w / s.r;
    if (ds > surface_depth) {
        rp = min(pixel, ssize - vec2<u32>(1u));
        ds = textureLoad(scene_depth, rp, 0);
    }
    var thickness = 1.0e4;
    if (ds > 0.0) {
        thickness = distance(gpu_water_opaque(rp, ds), rel);
    }
    var bed = textureLoad(scene_hdr, rp, 0).rgb;
    bed = select(vec3<f32>(0.0), bed, (bed == bed) & (bed < vec3<f32>(6.0e4)));
    let l = frame.sun_direction.xyz;
    let sun_up = max(l.y, 0.0);
    // The radiance the water scatters towards the eye: the sky's ambient and the sun
    // through an isotropic phase function (1 / 4 pi).
    let light_in = frame.ambient.rgb * 0.5 + frame.sun_color.rgb * (0.08 * sun_up);
    let transmitted = gpu_water_transport(m, gpu_water_vec3(bed), gpu_water_vec3(light_in), gpu_water_float(min(thickness, 1.0e4)));
    // Reflection: the sky, or the opaque scene along the reflected ray.
    let r = reflect(-v, n);
    var reflected = gpu_water_sky(r);
    if ((water.counts.y & GPU_WATER_FLAG_SSR) != 0u && r.y < 0.98) {
        let hit = gpu_water_ssr(rel, r);
        reflected = mix(reflected, hit.rgb, hit.a);
    }
    let nv_dot = max(dot(n, v), 0.0);
    let m5 = (1.0 - nv_dot) * (1.0 - nv_dot) * (1.0 - nv_dot) * (1.0 - nv_dot) * (1.0 - nv_dot);
    let fresnel = gpu_water_float(0.02 + 0.98 * m5);
    var color = mix(transmitted, gpu_water_vec3(reflected), gpu_water_vec3(fresnel));
    // The sun's highlight and the local lights.
    let highlight = frame.sun_color.rgb * light_shading_specular(n, v, l, roughness, 0.02);
    var lit = select(vec3<f32>(0.0), highlight, highlight == highlight);
    let f = saturate(textureLoad(foam, min(pixel, textureDimensions(foam) - vec2<u32>(1u)), 0).r);
    let foam_albedo = vec3<f32>(0.85) * f;
    let light_count = min(frame.local_light_count, arrayLength(&lights));
    let tile = (pixel.y / DEFERRED_TILE_SIZE) * local.tiles.x + pixel.x / DEFERRED_TILE_SIZE;
    if (light_count > 0u && tile < arrayLength(&light_counts)) {
        let surf = DeferredSurface(vec3<f32>(0.0), foam_albedo + vec3<f32>(0.02), n, roughness, 1.0, 0.0, 1.0, vec2<f32>(0.0));
        let at = light_shading_point(local.view_rotation, rel, surf);
        let lc = min(light_counts[tile], DEFERRED_MAX_LIGHTS_PER_TILE);
        for (var k = 0u; k < lc; k++) {
            let slot = tile * DEFERRED_MAX_LIGHTS_PER_TILE + k;
            if (slot >= arrayLength(&light_indices)) {
                break;
            }
            let i = light_indices[slot];
            if (i < light_count) {
                lit += light_shading_local(lights[i], at, surf);
            }
        }
    }
    // Foam on top: lit diffusely by the sun and the ambient.
    let foam_light = foam_albedo * (frame.ambient.rgb + frame.sun_color.rgb * max(dot(n, l), 0.0));
    color = mix(color, gpu_water_vec3(foam_light), gpu_water_float(f));
    var out = vec3<f32>(color) + lit;
    out = select(vec3<f32>(0.0), out, out == out);
    textureStore(output, pixel, vec4<f32>(gpu_water_srgb(gpu_water_tonemap(max(out, vec3<f32>(0.0)))), 1.0));
}
