// gpu: material evaluation shared by the compute resolve and the baseline's fragment
// shader, so both paths write the same G-buffer from the same inputs. The only difference
// between them is where the UV gradients come from: analytic barycentric derivatives
// (resolve) or the hardware's 2x2-quad differences (baseline).
//
// Needs in scope: GpuMaterial, the bindings `materials`, `albedo`, `albedo_sampler`.

struct Surface {
    albedo: vec3<f32>,
    // unit, camera-relative world space
    normal: vec3<f32>,
    roughness: f32,
    specular: f32,
    // baked sun visibility in [0, 1] (KZ2 stores a pre-baked sun shadow term)
    sun_shadow: f32,
}

fn material_surface(material_index: u32, uv: vec2<f32>, duv_dx: vec2<f32>, duv_dy: vec2<f32>, normal: vec3<f32>) -> Surface {
    let m = materials[material_index];
    let texel = textureSampleGrad(albedo, albedo_sampler, uv, m.albedo_layer, duv_dx, duv_dy);
    var s: Surface;
    s.albedo = texel.rgb * m.tint;
    s.normal = normalize(normal);
    s.roughness = m.roughness;
    s.specular = m.specular;
    s.sun_shadow = 1.0;
    return s;
}
