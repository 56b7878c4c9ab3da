// water: two-phase flow-map sampling (Vlachos 2010) and the per-pixel phase noise.
// Twin of `water::flow`. Uses `water_hash3` and `water_hash_unit` from `water::noise`.

#import water::noise

const WATER_UV_JUMP_X: f32 = 0.311;
const WATER_UV_JUMP_Y: f32 = 0.243;

// `FlowParams`, 16 bytes.
struct WaterFlowParams {
    interval: f32,
    distance: f32,
    noise_strength: f32,
    _pad: f32,
}

// `FlowLayers`: sample w0 * tex(uv0) + w1 * tex(uv1).
struct WaterFlowLayers {
    uv0: vec2<f32>,
    uv1: vec2<f32>,
    w0: f32,
    w1: f32,
    phase0: f32,
}

// A Vlachos RG texel read as unorm in [0, 1]: rg * 2 - 1.
fn water_decode_flow_rg(rg: vec2<f32>) -> vec2<f32> {
    return rg * 2.0 - 1.0;
}

fn water_flow_jump(c: f32) -> vec2<f32> {
    return vec2<f32>(fract(c * WATER_UV_JUMP_X), fract(c * WATER_UV_JUMP_Y));
}

// `flow_layers`.
fn water_flow_layers(uv: vec2<f32>, flow: vec2<f32>, time: f32, noise: f32, prm: WaterFlowParams) -> WaterFlowLayers {
    let t = time / (2.0 * prm.interval) + noise * prm.noise_strength;
    let phase0 = fract(t);
    let phase1 = fract(t + 0.5);
    let uv0 = uv - flow * (phase0 * prm.distance) + water_flow_jump(floor(t));
    let uv1 = uv - flow * (phase1 * prm.distance) + water_flow_jump(floor(t + 0.5)) + 0.5;
    let w1 = abs(2.0 * phase0 - 1.0);
    return WaterFlowLayers(uv0, uv1, 1.0 - w1, w1, phase0);
}

// Smooth value noise in [0, 1) from the integer hash: `phase_noise`.
fn water_value_noise(p: vec2<f32>, seed: u32) -> f32 {
    let fl = floor(p);
    let t = p - fl;
    let ix = bitcast<u32>(i32(fl.x));
    let iy = bitcast<u32>(i32(fl.y));
    let s = t * t * (3.0 - 2.0 * t);
    let v00 = water_hash_unit(water_hash3(ix, iy, seed));
    let v10 = water_hash_unit(water_hash3(ix + 1u, iy, seed));
    let v01 = water_hash_unit(water_hash3(ix, iy + 1u, seed));
    let v11 = water_hash_unit(water_hash3(ix + 1u, iy + 1u, seed));
    let a = v00 + (v10 - v00) * s.x;
    let b = v01 + (v11 - v01) * s.x;
    return a + (b - a) * s.y;
}
