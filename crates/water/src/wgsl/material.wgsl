// water: water materials and their blend. Twin of `water::material`.

const WATER_DEFAULT_BLEND_DISTANCE: f32 = 6.0;

// `WaterMaterialGpu`, 64 bytes.
struct WaterMaterialGpu {
    absorption: vec4<f32>,
    scattering: vec4<f32>,
    displacement_amplitude: f32,
    foam_intensity: f32,
    shore_width: f32,
    detail_weight: f32,
    ids: u32,
    foam_texture: u32,
    algae_texture: u32,
    _pad: u32,
}

// Weight of the other material at a signed distance from the boundary.
fn water_blend_weight(signed_distance: f32, blend_distance: f32) -> f32 {
    if (!(blend_distance > 0.0)) {
        return select(0.0, 1.0, signed_distance < 0.0);
    }
    return saturate(0.5 - signed_distance / blend_distance);
}

// Interpolates only what needs it; indices come from the dominant material.
fn water_material_blend(a: WaterMaterialGpu, b: WaterMaterialGpu, t_in: f32) -> WaterMaterialGpu {
    let t = saturate(t_in);
    var out = a;
    if (t >= 0.5) {
        out = b;
    }
    out.absorption = a.absorption + (b.absorption - a.absorption) * t;
    out.scattering = a.scattering + (b.scattering - a.scattering) * t;
    out.displacement_amplitude = a.displacement_amplitude + (b.displacement_amplitude - a.displacement_amplitude) * t;
    out.foam_intensity = a.foam_intensity + (b.foam_intensity - a.foam_intensity) * t;
    out.shore_width = a.shore_width + (b.shore_width - a.shore_width) * t;
    out.detail_weight = a.detail_weight + (b.detail_weight - a.detail_weight) * t;
    return out;
}
