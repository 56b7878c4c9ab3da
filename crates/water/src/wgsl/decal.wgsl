// water: vector displacement decals. Twin of `water::decal`.

// What the displacement target is cleared to before the max blend.
const WATER_CLEAR_DISPLACEMENT: f32 = -3.4028235e38;

fn water_decal_smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = saturate((x - e0) / (e1 - e0));
    return t * t * (3.0 - 2.0 * t);
}

// The edge fade of a box-local point in [-1, 1]^3: `edge_fade`.
fn water_decal_fade(local: vec3<f32>, fade: f32) -> f32 {
    let f = max(fade, 1e-6);
    let e = vec3<f32>(1.0) - abs(local);
    return water_decal_smoothstep(0.0, f, e.x) * water_decal_smoothstep(0.0, f, e.y) * water_decal_smoothstep(0.0, f, e.z);
}

// Whether a box-local point is inside the box (else clip the pixel).
fn water_decal_inside(local: vec3<f32>) -> bool {
    return all(abs(local) <= vec3<f32>(1.0));
}

// The decal texture UV of a box-local point.
fn water_decal_uv(local: vec3<f32>) -> vec2<f32> {
    return (local.xy + 1.0) * 0.5;
}

// A component nobody wrote (still the clear value) reads as 0.
fn water_decal_resolve(v: vec3<f32>) -> vec3<f32> {
    return select(v, vec3<f32>(0.0), v == vec3<f32>(WATER_CLEAR_DISPLACEMENT));
}
