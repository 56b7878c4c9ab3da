// gpu: material evaluation shared by the compute resolve and the baseline's fragment
// shader, so both paths write the same G-buffer (deferred's DeferredSurface) from the same
// inputs. The only difference between them is where the UV gradients come from: analytic
// barycentric derivatives (resolve) or the hardware's 2x2-quad differences (baseline).

#import deferred::gbuffer
#import gpu::scene_bindings

// HFW's resolve per material shader: the scene::MaterialFeatures bits whose maps this
// pipeline compiles in. The per-shader resolve pipelines set it to their pass's
// permutation, so a pass's code has no branch, sample or register of a map its materials
// lack; the uber resolve and the raster paths keep the default, every map, chosen per
// material at run time.
override MATERIAL_FEATURES: u32 = 0xffffffffu;
// Rust: scene::MaterialFeatures.
const MATERIAL_NORMAL_MAP: u32 = 1u;
const MATERIAL_METALLIC_ROUGHNESS_MAP: u32 = 2u;
const MATERIAL_OCCLUSION_MAP: u32 = 4u;
const MATERIAL_EMISSIVE: u32 = 8u;

// Whether this pipeline compiles the feature `f` in.
fn material_has(f: u32) -> bool {
    return (MATERIAL_FEATURES & f) != 0u;
}

// Screen-space motion in pixels (current minus previous, +y down) of a point at
// camera-relative position `p` this frame and `p_prev` at the previous frame's time (the
// same for anything that does not animate): the camera's motion and the foliage's
// (frame.prev_view_proj takes this frame's camera-relative positions to last frame's
// clip; equal to view_proj on a first frame, so no camera motion). Zero where either
// projection is behind the eye.
fn material_motion(p: vec3<f32>, p_prev: vec3<f32>) -> vec2<f32> {
    let now = frame.view_proj * vec4<f32>(p, 1.0);
    let before = frame.prev_view_proj * vec4<f32>(p_prev, 1.0);
    if (!(now.w > 0.0 && before.w > 0.0)) {
        return vec2<f32>(0.0);
    }
    let half_size = frame.viewport.xy * vec2<f32>(0.5, -0.5);
    return (now.xy / now.w - before.xy / before.w) * half_size;
}

// KZ2's pre-rendered sun shadow: the sun's visibility at camera-relative `p` (normal `n`)
// in the baked map of the scene's own batches, a 2x2 texel PCF (1 without a baked map or
// off it). Pixels where it is 0 skip the sun's shader in lighting.
fn material_baked_sun(p: vec3<f32>, n: vec3<f32>) -> f32 {
    if (frame.baked_sun[3][3] == 0.0) {
        return 1.0;
    }
    let size = vec2<f32>(textureDimensions(baked_sun_map));
    // One texel of world size, from the matrix's x row scale (orthographic).
    let texel = 2.0 / (length(vec3<f32>(frame.baked_sun[0][0], frame.baked_sun[1][0], frame.baked_sun[2][0])) * size.x);
    let q = p - frame.origin_offset.xyz + n * (1.5 * texel);
    let clip = frame.baked_sun * vec4<f32>(q, 1.0);
    let uv = vec2<f32>(clip.x * 0.5 + 0.5, 0.5 - clip.y * 0.5) * size - 0.5;
    if (!(all(uv >= vec2<f32>(0.0)) && all(uv < size - 1.0) && clip.z <= 1.0)) {
        return 1.0;
    }
    let t = vec2<i32>(floor(uv));
    let f = fract(uv);
    var lit = vec4<f32>(0.0);
    lit.x = select(0.0, 1.0, clip.z <= textureLoad(baked_sun_map, t, 0));
    lit.y = select(0.0, 1.0, clip.z <= textureLoad(baked_sun_map, t + vec2<i32>(1, 0), 0));
    lit.z = select(0.0, 1.0, clip.z <= textureLoad(baked_sun_map, t + vec2<i32>(0, 1), 0));
    lit.w = select(0.0, 1.0, clip.z <= textureLoad(baked_sun_map, t + vec2<i32>(1, 1), 0));
    return mix(mix(lit.x, lit.y, f.x), mix(lit.z, lit.w, f.x), f.y);
}

// The normal map's normal: tangent-space `m` (x along the tangent, y along the bitangent
// cross(n, t) * handedness, z along `n`) in the frame of unit normal `n` and the
// interpolated `tangent` (xyz, handedness in w), made orthogonal to `n` first. A tangent
// parallel to the normal (or zero) leaves `n` unperturbed.
fn material_normal(n: vec3<f32>, tangent: vec4<f32>, m: vec3<f32>) -> vec3<f32> {
    let t0 = tangent.xyz - n * dot(n, tangent.xyz);
    let tl = length(t0);
    if (!(tl > 1e-6)) {
        return n;
    }
    let t = t0 / tl;
    let b = cross(n, t) * select(-1.0, 1.0, tangent.w >= 0.0);
    let r = t * m.x + b * m.y + n * m.z;
    let rl = length(r);
    if (!(rl > 1e-6)) {
        return n;
    }
    return r / rl;
}

// `p`: the sample's camera-relative position (for its motion and the baked sun), a point
// that does not animate.
fn material_surface(material_index: u32, uv: vec2<f32>, duv_dx: vec2<f32>, duv_dy: vec2<f32>, normal: vec3<f32>, tangent: vec4<f32>, p: vec3<f32>) -> DeferredSurface {
    return material_surface_moved(material_index, uv, duv_dx, duv_dy, normal, tangent, p, p);
}

// `p`: the sample's camera-relative position (for its motion and the baked sun);
// `p_prev`: where it was at the previous frame's time, in this frame's camera-relative
// space (gpu_previous_position interpolated).
fn material_surface_moved(material_index: u32, uv: vec2<f32>, duv_dx: vec2<f32>, duv_dy: vec2<f32>, normal: vec3<f32>, tangent: vec4<f32>, p: vec3<f32>, p_prev: vec3<f32>) -> DeferredSurface {
    return material_surface_motion(material_index, uv, duv_dx, duv_dy, normal, tangent, p, material_motion(p, p_prev));
}

// The surface of material `material_index` at one sample: glTF 2.0's metallic-roughness
// model (scene::Material). `normal` and `tangent` (xyz, handedness in w): the interpolated
// vertex normal and tangent in camera-relative world space, not necessarily unit;
// `uv` and its screen gradients `duv_dx`, `duv_dy` choose every map's mip level.
// `motion`: the sample's screen motion in pixels. The lighting accumulation gets what the
// geometry pass owns (KZ2's "indirect light"): the ambient hemisphere on the diffuse
// colour, darkened by the occlusion map, plus the emission.
fn material_surface_motion(material_index: u32, uv: vec2<f32>, duv_dx: vec2<f32>, duv_dy: vec2<f32>, normal: vec3<f32>, tangent: vec4<f32>, p: vec3<f32>, motion: vec2<f32>) -> DeferredSurface {
    let m = materials[material_index];
    let texel = textureSampleGrad(albedo, albedo_sampler, uv, m.albedo_layer, duv_dx, duv_dy);
    var s: DeferredSurface;
    s.albedo = saturate(texel.rgb * m.tint);
    var n = normalize(normal);
    if (material_has(MATERIAL_NORMAL_MAP) && m.normal_layer != GPU_MATERIAL_NO_MAP) {
        let t = textureSampleGrad(data_maps, albedo_sampler, uv, m.normal_layer, duv_dx, duv_dy).xyz * 2.0 - 1.0;
        n = material_normal(n, tangent, vec3<f32>(t.xy * m.normal_scale, t.z));
    }
    s.normal = n;
    s.roughness = m.roughness;
    s.metallic = m.metallic;
    // glTF's usual packing puts occlusion in the red of the metallic-roughness texture
    // (ORM): one layer, sampled once.
    var mr = vec4<f32>(1.0);
    let has_mr = material_has(MATERIAL_METALLIC_ROUGHNESS_MAP) && m.metallic_roughness_layer != GPU_MATERIAL_NO_MAP;
    if (has_mr) {
        mr = textureSampleGrad(data_maps, albedo_sampler, uv, m.metallic_roughness_layer, duv_dx, duv_dy);
        s.roughness *= mr.g;
        s.metallic *= mr.b;
    }
    var occlusion = 1.0;
    if (material_has(MATERIAL_OCCLUSION_MAP) && m.occlusion_layer != GPU_MATERIAL_NO_MAP) {
        var o = mr.r;
        if (!(has_mr && m.occlusion_layer == m.metallic_roughness_layer)) {
            o = textureSampleGrad(data_maps, albedo_sampler, uv, m.occlusion_layer, duv_dx, duv_dy).r;
        }
        occlusion = 1.0 + m.occlusion_strength * (o - 1.0);
    }
    var emissive = vec3<f32>(0.0);
    if (material_has(MATERIAL_EMISSIVE)) {
        emissive = m.emissive;
    }
    if (material_has(MATERIAL_EMISSIVE) && m.emissive_layer != GPU_MATERIAL_NO_MAP) {
        // The base colour's texture doubling as the emissive map is sampled once.
        var glow = texel.rgb;
        if (m.emissive_layer != m.albedo_layer) {
            glow = textureSampleGrad(albedo, albedo_sampler, uv, m.emissive_layer, duv_dx, duv_dy).rgb;
        }
        emissive *= glow;
    }
    let diffuse = s.albedo * (1.0 - s.metallic);
    s.lighting = emissive + diffuse * frame.ambient.rgb * ((0.6 + 0.4 * n.y) * occlusion);
    s.specular = m.specular;
    s.sun_shadow = material_baked_sun(p, s.normal);
    s.motion = motion;
    return s;
}
