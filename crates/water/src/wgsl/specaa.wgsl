// water: variance-based specular anti-aliasing (Tokuyoshi and Kaplanyan 2019).
// Twin of `water::specaa`.

const WATER_SPECAA_KAPPA: f32 = 0.18;

fn water_variance_from_derivatives(dndx: vec3<f32>, dndy: vec3<f32>) -> f32 {
    return 0.25 * (dot(dndx, dndx) + dot(dndy, dndy));
}

// GGX alpha widened by a slope variance, capped by the material: `filtered_alpha`.
fn water_filtered_alpha(alpha: f32, variance: f32, kappa: f32, max_alpha: f32) -> f32 {
    let v = select(0.0, variance, variance > 0.0);
    let added = min(2.0 * v, max(kappa, 0.0));
    let cap = clamp(max_alpha, 0.0, 1.0);
    let a2 = min(alpha * alpha + added, cap * cap);
    return sqrt(max(a2, 0.0));
}

fn water_filtered_roughness(roughness: f32, variance: f32, kappa: f32, max_roughness: f32) -> f32 {
    let cap = clamp(max_roughness, 0.0, 1.0);
    return sqrt(water_filtered_alpha(roughness * roughness, variance, kappa, cap * cap));
}
