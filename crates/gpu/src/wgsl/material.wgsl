// gpu: material evaluation shared by the compute resolve and the baseline's fragment
// shader, so both paths write the same G-buffer (deferred's DeferredSurface) from the same
// inputs. The only difference between them is where the UV gradients come from: analytic
// barycentric derivatives (resolve) or the hardware's 2x2-quad differences (baseline).

#import deferred::gbuffer
#import gpu::scene_bindings

// Screen-space motion in pixels (current minus previous, +y down) of a point at
// camera-relative position `p` that did not move in the world: the camera's motion alone
// (frame.prev_view_proj takes this frame's camera-relative positions to last frame's
// clip; equal to view_proj on a first frame, so no motion). Zero where either projection
// is behind the eye.
fn material_motion(p: vec3<f32>) -> vec2<f32> {
    let now = frame.view_proj * vec4<f32>(p, 1.0);
    let before = frame.prev_view_proj * vec4<f32>(p, 1.0);
    if (!(now.w > 0.0 && before.w > 0.0)) {
        return vec2<f32>(0.0);
    }
    let half_size = frame.viewport.xy * vec2<f32>(0.5, -0.5);
    return (now.xy / now.w - before.xy / before.w) * half_size;
}

// `p`: the sample's camera-relative position (for its motion).
fn material_surface(material_index: u32, uv: vec2<f32>, duv_dx: vec2<f32>, duv_dy: vec2<f32>, normal: vec3<f32>, p: vec3<f32>) -> DeferredSurface {
    let m = materials[material_index];
    let texel = textureSampleGrad(albedo, albedo_sampler, uv, m.albedo_layer, duv_dx, duv_dy);
    var s: DeferredSurface;
    s.lighting = vec3<f32>(0.0);
    s.albedo = saturate(texel.rgb * m.tint);
    s.normal = normalize(normal);
    s.roughness = m.roughness;
    s.specular = m.specular;
    s.sun_shadow = 1.0;
    // The scene does not animate yet: the camera's motion is all there is.
    s.motion = material_motion(p);
    return s;
}
