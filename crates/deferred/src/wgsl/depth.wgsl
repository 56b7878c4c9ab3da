// deferred: position from depth (standard or reversed Z, finite or infinite far plane).
// Binding-free; the Rust crate `deferred` (depth.rs) is the reference.
//
// View space is right-handed, camera looking down -z; view distance is -z. Pixels are
// measured from the viewport's top-left, +y down, centres at +0.5; NDC has +y up. Depth is
// wgpu's NDC z in [0, 1]: for a perspective projection depth = alpha + beta / distance.

// Rust: deferred::DeferredProjection (32 bytes; upload as a uniform).
struct DeferredProjection {
    // tan of half the horizontal and vertical fields of view
    tan_half: vec2<f32>,
    // depth at infinite distance
    alpha: f32,
    // depth - alpha = beta / distance
    beta: f32,
    // width, height, 1 / width, 1 / height (pixels)
    viewport: vec4<f32>,
}

// View distance (-z, > 0) at a depth-buffer value.
fn deferred_view_distance(p: DeferredProjection, depth: f32) -> f32 {
    return p.beta / (depth - p.alpha);
}

// Depth-buffer value of a view distance.
fn deferred_depth_of_distance(p: DeferredProjection, distance: f32) -> f32 {
    return p.alpha + p.beta / distance;
}

fn deferred_ndc_from_pixel(pixel: vec2<f32>, inv_viewport: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(pixel.x * inv_viewport.x * 2.0 - 1.0, 1.0 - pixel.y * inv_viewport.y * 2.0);
}

// View-space position of a pixel position at a depth-buffer value (symmetric projection).
fn deferred_view_position(p: DeferredProjection, pixel: vec2<f32>, depth: f32) -> vec3<f32> {
    let ndc = deferred_ndc_from_pixel(pixel, p.viewport.zw);
    let dist = deferred_view_distance(p, depth);
    return vec3<f32>(ndc.x * p.tan_half.x * dist, ndc.y * p.tan_half.y * dist, -dist);
}

// Position through any inverse projection: the inverse projection gives view space, the
// inverse view-projection world space (camera-relative world if the view had no
// translation). Works for jittered and oblique projections.
fn deferred_position_from_inverse(inv: mat4x4<f32>, pixel: vec2<f32>, viewport: vec2<f32>, depth: f32) -> vec3<f32> {
    let ndc = deferred_ndc_from_pixel(pixel, 1.0 / viewport);
    let h = inv * vec4<f32>(ndc, depth, 1.0);
    return h.xyz / h.w;
}
