// gpu: material evaluation shared by the compute resolve and the baseline's fragment
// shader, so both paths write the same G-buffer (deferred's DeferredSurface) from the same
// inputs. The only difference between them is where the UV gradients come from: analytic
// barycentric derivatives (resolve) or the hardware's 2x2-quad differences (baseline).

#import deferred::gbuffer
#import gpu::scene_bindings

fn material_surface(material_index: u32, uv: vec2<f32>, duv_dx: vec2<f32>, duv_dy: vec2<f32>, normal: vec3<f32>) -> DeferredSurface {
    let m = materials[material_index];
    let texel = textureSampleGrad(albedo, albedo_sampler, uv, m.albedo_layer, duv_dx, duv_dy);
    var s: DeferredSurface;
    s.lighting = vec3<f32>(0.0);
    s.albedo = saturate(texel.rgb * m.tint);
    s.normal = normalize(normal);
    s.roughness = m.roughness;
    s.specular = m.specular;
    s.sun_shadow = 1.0;
    // Static geometry: the motion of the camera alone is not written yet.
    s.motion = vec2<f32>(0.0);
    return s;
}
