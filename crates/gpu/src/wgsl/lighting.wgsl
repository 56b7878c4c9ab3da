// gpu: deferred lighting in compute (KZ2's sun + ambient + point lights over the G-buffer),
// then tone mapping into the sRGB-encoded output image. 8x8 pixels per workgroup.

#import gpu::frame
#import gpu::gbuffer_load

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var depth_texture: texture_depth_2d;
@group(0) @binding(2) var<storage, read> point_lights: array<GpuPointLight>;
@group(0) @binding(3) var output: texture_storage_2d<rgba8unorm, write>;
// Group 1: the G-buffer (gpu::gbuffer_load).

const LIGHTING_PI: f32 = 3.14159265;

// Camera-relative position of a pixel centre at reversed-Z depth `d`.
fn lighting_position(pixel: vec2<u32>, d: f32) -> vec3<f32> {
    let uv = (vec2<f32>(pixel) + 0.5) * frame.viewport.zw;
    let ndc = vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, d, 1.0);
    let p = frame.inv_view_proj * ndc;
    return p.xyz / p.w;
}

// GGX normal distribution with Schlick Fresnel and a Smith-style visibility term.
fn lighting_specular(n: vec3<f32>, v: vec3<f32>, l: vec3<f32>, roughness: f32, f0: f32) -> f32 {
    let h = normalize(v + l);
    let nh = max(dot(n, h), 0.0);
    let nl = max(dot(n, l), 0.0);
    let nv = max(dot(n, v), 1e-4);
    let a = max(roughness * roughness, 0.02);
    let a2 = a * a;
    let dd = nh * nh * (a2 - 1.0) + 1.0;
    let ndf = a2 / (LIGHTING_PI * dd * dd);
    let k = a * 0.5;
    let vis = 1.0 / ((nl * (1.0 - k) + k) * (nv * (1.0 - k) + k) * 4.0);
    let f = f0 + (1.0 - f0) * pow(1.0 - max(dot(v, h), 0.0), 5.0);
    return ndf * vis * f * nl;
}

// Narkowicz's ACES fit.
fn lighting_tonemap(x: vec3<f32>) -> vec3<f32> {
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), vec3<f32>(0.0), vec3<f32>(1.0));
}

fn lighting_srgb(c: vec3<f32>) -> vec3<f32> {
    let lo = c * 12.92;
    let hi = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(hi, lo, c <= vec3<f32>(0.0031308));
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(frame.viewport.xy);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let pixel = id.xy;
    let d = textureLoad(depth_texture, vec2<i32>(pixel), 0);
    var color = frame.sky.rgb;
    if d > 0.0 {
        let s = gbuffer_surface(pixel);
        let p = lighting_position(pixel, d);
        let v = normalize(-p);
        let n = s.normal;
        let l = frame.sun_direction.xyz;
        let nl = max(dot(n, l), 0.0);
        let diffuse = s.albedo / LIGHTING_PI;
        color = s.lighting + s.albedo * frame.ambient.rgb * (0.6 + 0.4 * n.y);
        color += frame.sun_color.rgb * (diffuse * nl * s.sun_shadow + s.specular * lighting_specular(n, v, l, s.roughness, 0.04) * s.sun_shadow);
        for (var i = 0u; i < frame.point_light_count; i++) {
            let light = point_lights[i];
            let to_light = light.position_radius.xyz + frame.origin_offset.xyz - p;
            let dist = length(to_light);
            let radius = light.position_radius.w;
            if dist < radius {
                let ll = to_light / dist;
                let falloff = pow(clamp(1.0 - pow(dist / radius, 4.0), 0.0, 1.0), 2.0) / (dist * dist + 1.0);
                let nll = max(dot(n, ll), 0.0);
                color += light.color.rgb * falloff * (diffuse * nll + s.specular * lighting_specular(n, v, ll, s.roughness, 0.04));
            }
        }
    }
    textureStore(output, vec2<i32>(pixel), vec4<f32>(lighting_srgb(lighting_tonemap(color)), 1.0));
}
