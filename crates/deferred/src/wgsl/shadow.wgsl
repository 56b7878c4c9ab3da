// deferred: stable cascade lookup, the MSAA PCF tap record and the edge tests.
// Binding-free; the Rust crate `deferred` (cascades.rs, msaa.rs) is the reference.

// Rust: deferred::DeferredCascade (80 bytes). Maps camera-relative world positions to the
// cascade's shadow clip space (x, y in [-1, 1], +y up; depth in [0, 1], 0 nearest the sun).
struct DeferredCascade {
    relative_to_clip: mat4x4<f32>,
    // a pixel uses the first cascade whose split_far is beyond its view distance
    split_far: f32,
    texel_size: f32,
    radius: f32,
    pad: f32,
}

// Rust: deferred::msaa::DeferredPcfTap (16 bytes): the taps of sample s are contiguous.
struct DeferredPcfTap {
    // shadow-map texels
    offset: vec2<f32>,
    // within its sample's subset (a subset's weights sum to 1)
    weight: f32,
    sample: u32,
}

// Shadow-map uv (texture space, +v down) and depth of a camera-relative position.
fn deferred_shadow_coord(c: DeferredCascade, rel: vec3<f32>) -> vec3<f32> {
    let clip = c.relative_to_clip * vec4<f32>(rel, 1.0);
    return vec3<f32>(clip.x * 0.5 + 0.5, 0.5 - clip.y * 0.5, clip.z);
}

// Whether two samples' G-buffer words differ (up to four words per target group).
fn deferred_words_differ(a: vec4<u32>, b: vec4<u32>) -> bool {
    return any(a != b);
}

// Whether two samples' depths differ by more than `tolerance` relative (NaN: yes).
fn deferred_depth_differs(d0: f32, d: f32, tolerance: f32) -> bool {
    let diff = abs(d - d0);
    return !(diff <= tolerance * max(abs(d0), abs(d)));
}
