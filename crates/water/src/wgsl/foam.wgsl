// water: foam amount and coverage. Twin of `water::foam`.

// `FoamParams`, 32 bytes.
struct WaterFoamParams {
    shore_width: f32,
    speed_start: f32,
    speed_full: f32,
    shallow_depth: f32,
    softness: f32,
    mask_bias: f32,
    intensity: f32,
    _pad: f32,
}

// `FoamInputs`.
struct WaterFoamInputs {
    signed_distance: f32,
    flow_speed: f32,
    depth: f32,
    detail_noise: f32,
    mask_noise: f32,
    displacement_foam: f32,
}

fn water_smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = saturate((x - e0) / (e1 - e0));
    return t * t * (3.0 - 2.0 * t);
}

// `foam_amount`.
fn water_foam_amount(i: WaterFoamInputs, p: WaterFoamParams) -> f32 {
    let shore = 1.0 - water_smoothstep(0.0, max(p.shore_width, 1e-6), i.signed_distance);
    let speed = water_smoothstep(p.speed_start, max(p.speed_full, p.speed_start + 1e-6), i.flow_speed);
    let shallow = 1.0 - water_smoothstep(0.0, max(p.shallow_depth, 1e-6), i.depth);
    return saturate(max(max(shore, speed), shallow));
}

// `foam`.
fn water_foam(i: WaterFoamInputs, p: WaterFoamParams) -> f32 {
    let amount = water_foam_amount(i, p);
    let pattern = saturate(0.5 + 0.5 * i.detail_noise) * saturate(0.5 + 0.5 * i.mask_noise + p.mask_bias);
    let edge = 1.0 - amount;
    var covered = 0.0;
    if (amount > 0.0) {
        covered = water_smoothstep(edge, edge + max(p.softness, 1e-6), pattern);
    }
    return saturate(saturate(covered * p.intensity) + saturate(i.displacement_foam));
}
