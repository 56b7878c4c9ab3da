// gpu: one local light's shading at one pixel, shared by the compute lighting (tiled and
// every-light paths) and the stencil light volumes, so both paths compute the same
// contribution bit for bit where their compilers allow. Lights are in view space. Feature
// `no_specular`: KZ2's no-specular permutation, the specular term compiled out (without
// it, the term follows the light's DEFERRED_LIGHT_FLAG_NO_SPECULAR).

#import deferred::gbuffer
#import deferred::lights

// Rust: passes::lighting::GpuLocalLights (80 bytes).
struct GpuLocalLights {
    // camera-relative world -> view (the camera's rotation)
    view_rotation: mat4x4<f32>,
    // light tiles across and down
    tiles: vec2<u32>,
    pad: vec2<u32>,
}

const LIGHT_SHADING_PI: f32 = 3.14159265;

// Camera-relative position of the image point `xy` (pixels from the top-left corner) at
// reversed-Z depth `d`, with the frame's `inv_view_proj` and `texel` (1 / viewport size,
// FrameUniforms::viewport.zw).
fn light_shading_position_at(inv_view_proj: mat4x4<f32>, texel: vec2<f32>, xy: vec2<f32>, d: f32) -> vec3<f32> {
    let uv = xy * texel;
    let ndc = vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, d, 1.0);
    let p = inv_view_proj * ndc;
    return p.xyz / p.w;
}

// The same at the centre of `pixel`.
fn light_shading_position(inv_view_proj: mat4x4<f32>, texel: vec2<f32>, pixel: vec2<u32>, d: f32) -> vec3<f32> {
    return light_shading_position_at(inv_view_proj, texel, vec2<f32>(pixel) + 0.5, d);
}

// The GGX lobe without its Fresnel: x = D * V * n.l (GGX normal distribution, a
// Smith-style visibility term), y = Schlick's weight (1 - v.h)^5.
fn light_shading_lobe(n: vec3<f32>, v: vec3<f32>, l: vec3<f32>, roughness: f32) -> vec2<f32> {
    let h = normalize(v + l);
    let nh = max(dot(n, h), 0.0);
    let nl = max(dot(n, l), 0.0);
    let nv = max(dot(n, v), 1e-4);
    let a = max(roughness * roughness, 0.02);
    let a2 = a * a;
    let dd = nh * nh * (a2 - 1.0) + 1.0;
    let ndf = a2 / (LIGHT_SHADING_PI * dd * dd);
    let k = a * 0.5;
    let vis = 1.0 / ((nl * (1.0 - k) + k) * (nv * (1.0 - k) + k) * 4.0);
    // Schlick's (1 - v.h)^5 by multiplications (pow is exp2(log2) on GPUs).
    let m = 1.0 - max(dot(v, h), 0.0);
    let m2 = m * m;
    return vec2<f32>(ndf * vis * nl, m2 * m2 * m);
}

// GGX with Schlick's Fresnel from the reflectance `f0` at normal incidence.
fn light_shading_specular(n: vec3<f32>, v: vec3<f32>, l: vec3<f32>, roughness: f32, f0: f32) -> f32 {
    let g = light_shading_lobe(n, v, l, roughness);
    return (f0 + (1.0 - f0) * g.y) * g.x;
}

// The same lobe for a G-buffer surface in the metallic workflow: Fresnel
// mix(specular * F(0.04), F(albedo), metallic) with Schlick's F (deferred::Surface).
fn light_shading_surface_specular(n: vec3<f32>, v: vec3<f32>, l: vec3<f32>, s: DeferredSurface) -> vec3<f32> {
    let g = light_shading_lobe(n, v, l, s.roughness);
    let dielectric = s.specular * (0.04 + 0.96 * g.y);
    let metal = s.albedo + (vec3<f32>(1.0) - s.albedo) * g.y;
    return mix(vec3<f32>(dielectric), metal, s.metallic) * g.x;
}

// A surface as the local lights see it: view-space position, normal and direction to the
// eye, and its diffuse reflectance over pi (the diffuse colour albedo * (1 - metallic)).
struct LightShadingPoint {
    p: vec3<f32>,
    n: vec3<f32>,
    v: vec3<f32>,
    diffuse: vec3<f32>,
}

// The view-space shading point of a pixel at camera-relative `p` with surface `s`
// (`view_rotation`: GpuLocalLights::view_rotation).
fn light_shading_point(view_rotation: mat4x4<f32>, p: vec3<f32>, s: DeferredSurface) -> LightShadingPoint {
    let pv = (view_rotation * vec4<f32>(p, 0.0)).xyz;
    let nv = (view_rotation * vec4<f32>(s.normal, 0.0)).xyz;
    return LightShadingPoint(pv, nv, normalize(-pv), s.albedo * ((1.0 - s.metallic) / LIGHT_SHADING_PI));
}

// Whether view-space `p` is inside the sphere of centre `pr.xyz`, radius `pr.w` (the
// first, cheap part of deferred_light_affects).
fn light_shading_in_sphere(pr: vec4<f32>, p: vec3<f32>) -> bool {
    let d = p - pr.xyz;
    return dot(d, d) <= pr.w * pr.w;
}

// One local light's contribution at `at`, or exactly zero outside its volume (so that any
// conservative coverage of the volume gives the same sum).
fn light_shading_local(l: DeferredLight, at: LightShadingPoint, s: DeferredSurface) -> vec3<f32> {
    if (!deferred_light_affects(l, at.p)) {
        return vec3<f32>(0.0);
    }
    let to_light = l.position - at.p;
    let dist = length(to_light);
    if (!(dist > 0.0)) {
        return vec3<f32>(0.0);
    }
    let ll = to_light / dist;
    // Facing away: both terms below carry this factor, so the light gives exactly zero;
    // skipping the GGX term here changes no pixel.
    let nll = max(dot(at.n, ll), 0.0);
    if (nll <= 0.0) {
        return vec3<f32>(0.0);
    }
    let r2 = dist * dist / (l.range * l.range);
    let window = clamp(1.0 - r2 * r2, 0.0, 1.0);
    var falloff = window * window / (dist * dist + 1.0);
    if (deferred_light_is_spot(l)) {
        // Soft edge over the outer quarter of the cone's cosine range.
        falloff *= smoothstep(l.cos_outer, mix(l.cos_outer, 1.0, 0.25), dot(-ll, l.direction));
    }
#if no_specular
    // KZ2's no-specular light shader (the volumes' pipeline for such lights): the term
    // compiled out; x + 0 is x, so the sum below rounds as the branch's does.
    let specular = vec3<f32>(0.0);
#else
    // The light's flag (the compute lighting has one shader for every light).
    var specular = vec3<f32>(0.0);
    if (deferred_light_has_specular(l)) {
        specular = light_shading_surface_specular(at.n, at.v, ll, s);
    }
#endif
    return l.color * falloff * (at.diffuse * nll + specular);
}

// Rust: spot_shadows::LIGHT_SHADOW_SLOT_SHIFT: a light row's flags carry its spot shadow
// map's slot + 1 from this bit (0: no map).
const GPU_LIGHT_SHADOW_SLOT_SHIFT: u32 = 8u;

// Rust: spot_shadows::GpuSpotShadow (80 bytes).
struct GpuSpotShadow {
    // view space -> the map's clip space (depth 0 at the light's near plane)
    view_to_clip: mat4x4<f32>,
    // KZ2's fade: 1 full shadow, towards 0 lit
    strength: f32,
    // texel size per metre of distance from the light (normal offset)
    texel_per_metre: f32,
    resolution: u32,
    pad: u32,
}

// The shadow-map slot + 1 of light `l` (0: no map this frame).
fn light_shading_shadow_slot(l: DeferredLight) -> u32 {
    return l.flags >> GPU_LIGHT_SHADOW_SLOT_SHIFT;
}

// Visibility of light `l` at `at` through its map (layer `layer` of `map`, row `s`): a 3x3
// PCF of `depth <= stored`, the point pushed 1.5 texels along its normal, blended towards
// lit by the fade. 1 off the map (outside the cone, where the light gives nothing anyway).
fn light_shading_spot_visibility(map: texture_depth_2d_array, s: GpuSpotShadow, layer: u32, l: DeferredLight, at: LightShadingPoint) -> f32 {
    let dist = length(l.position - at.p);
    let pushed = at.p + at.n * (1.5 * s.texel_per_metre * dist);
    let clip = s.view_to_clip * vec4<f32>(pushed, 1.0);
    if (!(clip.w > 0.0)) {
        return 1.0;
    }
    let ndc = clip.xyz / clip.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if (!(all(uv >= vec2<f32>(0.0)) && all(uv < vec2<f32>(1.0)) && ndc.z <= 1.0)) {
        return 1.0;
    }
    let size = min(vec2<i32>(i32(s.resolution)), vec2<i32>(textureDimensions(map)));
    let centre = vec2<i32>(uv * vec2<f32>(size));
    var lit = 0.0;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let t = clamp(centre + vec2<i32>(dx, dy), vec2<i32>(0), size - 1);
            lit += select(0.0, 1.0, ndc.z <= textureLoad(map, t, i32(layer), 0));
        }
    }
    return mix(1.0, lit / 9.0, clamp(s.strength, 0.0, 1.0));
}
