// water: light transport through water. Twin of `water::optics`.

const WATER_PURE_ABSORPTION_R: f32 = 0.34;
const WATER_PURE_ABSORPTION_G: f32 = 0.0325;
const WATER_PURE_ABSORPTION_B: f32 = 0.0114;

// `WaterMedium`: coefficients (1/m) in xyz.
struct WaterMedium {
    absorption: vec4<f32>,
    scattering: vec4<f32>,
}

// Beer-Lambert: exp(-sigma_t d), negative or NaN distances count as 0.
fn water_transmittance(extinction: vec3<f32>, distance: f32) -> vec3<f32> {
    let d = select(0.0, distance, distance > 0.0);
    return exp(-extinction * d);
}

fn water_albedo(m: WaterMedium) -> vec3<f32> {
    let t = m.absorption.xyz + m.scattering.xyz;
    return select(vec3<f32>(0.0), m.scattering.xyz / t, t > vec3<f32>(0.0));
}

// Single scattering of a uniform in-scattered radiance: light * albedo * (1 - T).
fn water_in_scatter(m: WaterMedium, light: vec3<f32>, distance: f32) -> vec3<f32> {
    let t = water_transmittance(m.absorption.xyz + m.scattering.xyz, distance);
    return light * water_albedo(m) * (vec3<f32>(1.0) - t);
}

// bed * T + in-scatter: `Medium::light_transport`.
fn water_light_transport(m: WaterMedium, bed: vec3<f32>, light: vec3<f32>, distance: f32) -> vec3<f32> {
    return bed * water_transmittance(m.absorption.xyz + m.scattering.xyz, distance) + water_in_scatter(m, light, distance);
}
