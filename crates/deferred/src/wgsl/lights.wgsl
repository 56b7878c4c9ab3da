// deferred: tiled light culling (the per-tile test of the culling pass) and KZ2's
// depth-bounds emulation. Binding-free; the Rust crate `deferred` (lights.rs) is the
// reference.
//
// Lights are in view space (right-handed, camera looking down -z), metres. Tiles are
// DEFERRED_TILE_SIZE^2 pixels from the top-left. Pass 1 reduces each tile's depth to
// DeferredTileDepth (atomicMax / atomicMin on the depth bits: non-negative floats order
// like their bits); pass 2 tests every light against the tile's frustum with
// deferred_light_in_tile and appends the passing indices (up to
// DEFERRED_MAX_LIGHTS_PER_TILE) in ascending order.

#import deferred::depth

const DEFERRED_TILE_SIZE: u32 = 16u;
const DEFERRED_MAX_LIGHTS_PER_TILE: u32 = 256u;
const DEFERRED_LIGHT_FLAG_SHADOW: u32 = 1u;
const DEFERRED_LIGHT_FLAG_SPOT: u32 = 2u;
// No specular term: diffuse alone (KZ2's no-specular permutation).
const DEFERRED_LIGHT_FLAG_NO_SPECULAR: u32 = 4u;

// Rust: deferred::DeferredLight (48 bytes).
struct DeferredLight {
    position: vec3<f32>,
    range: f32,
    // spot axis, unit
    direction: vec3<f32>,
    // cos of the spot half-angle, in (0, 1)
    cos_outer: f32,
    color: vec3<f32>,
    flags: u32,
}

// Rust: deferred::DeferredTileDepth (8 bytes). Empty tile: nearest == the far plane depth.
struct DeferredTileDepth {
    nearest: f32,
    farthest: f32,
}

// Rust: deferred::lights::TileFrustum. Planes through the eye, n . p >= 0 inside.
struct DeferredTileFrustum {
    left: vec3<f32>,
    right: vec3<f32>,
    bottom: vec3<f32>,
    top: vec3<f32>,
    near: f32,
    far: f32,
}

fn deferred_tile_frustum(p: DeferredProjection, tile: vec2<u32>, depth: DeferredTileDepth) -> DeferredTileFrustum {
    let w = p.viewport.x;
    let h = p.viewport.y;
    let x0 = f32(tile.x * DEFERRED_TILE_SIZE);
    let x1 = min(f32((tile.x + 1u) * DEFERRED_TILE_SIZE), w);
    let y0 = f32(tile.y * DEFERRED_TILE_SIZE);
    let y1 = min(f32((tile.y + 1u) * DEFERRED_TILE_SIZE), h);
    let left = (x0 / w * 2.0 - 1.0) * p.tan_half.x;
    let right = (x1 / w * 2.0 - 1.0) * p.tan_half.x;
    let top = (1.0 - y0 / h * 2.0) * p.tan_half.y;
    let bottom = (1.0 - y1 / h * 2.0) * p.tan_half.y;
    var f: DeferredTileFrustum;
    f.left = normalize(vec3<f32>(1.0, 0.0, left));
    f.right = normalize(vec3<f32>(-1.0, 0.0, -right));
    f.bottom = normalize(vec3<f32>(0.0, 1.0, bottom));
    f.top = normalize(vec3<f32>(0.0, -1.0, -top));
    f.near = deferred_view_distance(p, depth.nearest);
    f.far = deferred_view_distance(p, depth.farthest);
    return f;
}

fn deferred_light_is_spot(l: DeferredLight) -> bool {
    return (l.flags & DEFERRED_LIGHT_FLAG_SPOT) != 0u;
}

fn deferred_light_has_specular(l: DeferredLight) -> bool {
    return (l.flags & DEFERRED_LIGHT_FLAG_NO_SPECULAR) == 0u;
}

// xyz: centre, w: radius of a sphere around the light's volume.
fn deferred_light_bounding_sphere(l: DeferredLight) -> vec4<f32> {
    if !deferred_light_is_spot(l) {
        return vec4<f32>(l.position, l.range);
    }
    let c = l.cos_outer;
    if c >= 0.70710677 {
        let r = l.range / (2.0 * c);
        return vec4<f32>(l.position + l.direction * r, r);
    }
    let s = sqrt(max(1.0 - c * c, 0.0));
    return vec4<f32>(l.position + l.direction * (l.range * c), l.range * s);
}

// (min, max) of dot(v, p) over the cone with apex a, unit axis d, height h, cos half-angle.
fn deferred_cone_extent(a: vec3<f32>, d: vec3<f32>, h: f32, cos_outer: f32, v: vec3<f32>) -> vec2<f32> {
    let tan_outer = sqrt(max(1.0 - cos_outer * cos_outer, 0.0)) / cos_outer;
    let rho = h * tan_outer;
    let base = dot(a + d * h, v);
    let q = v - d * dot(v, d);
    let perp = sqrt(dot(q, q));
    let apex = dot(a, v);
    return vec2<f32>(min(apex, base - rho * perp), max(apex, base + rho * perp));
}

fn deferred_sphere_in_tile(f: DeferredTileFrustum, center: vec3<f32>, radius: f32) -> bool {
    let d = -center.z;
    if d + radius < f.near || d - radius > f.far {
        return false;
    }
    return dot(f.left, center) >= -radius && dot(f.right, center) >= -radius
        && dot(f.bottom, center) >= -radius && dot(f.top, center) >= -radius;
}

// Whether a light's volume meets a tile's frustum (conservative).
fn deferred_light_in_tile(f: DeferredTileFrustum, l: DeferredLight) -> bool {
    let s = deferred_light_bounding_sphere(l);
    if !deferred_sphere_in_tile(f, s.xyz, s.w) {
        return false;
    }
    if !deferred_light_is_spot(l) {
        return true;
    }
    let z = deferred_cone_extent(l.position, l.direction, l.range, l.cos_outer, vec3<f32>(0.0, 0.0, -1.0));
    if z.y < f.near || z.x > f.far {
        return false;
    }
    return deferred_cone_extent(l.position, l.direction, l.range, l.cos_outer, f.left).y >= 0.0
        && deferred_cone_extent(l.position, l.direction, l.range, l.cos_outer, f.right).y >= 0.0
        && deferred_cone_extent(l.position, l.direction, l.range, l.cos_outer, f.bottom).y >= 0.0
        && deferred_cone_extent(l.position, l.direction, l.range, l.cos_outer, f.top).y >= 0.0;
}

// Whether a view-space point is inside the light's volume (the per-pixel test).
fn deferred_light_affects(l: DeferredLight, p: vec3<f32>) -> bool {
    let d = p - l.position;
    let d2 = dot(d, d);
    if d2 > l.range * l.range {
        return false;
    }
    if !deferred_light_is_spot(l) {
        return true;
    }
    let along = dot(d, l.direction);
    return along >= 0.0 && along * along >= d2 * l.cos_outer * l.cos_outer;
}

fn deferred_tile_is_empty(t: DeferredTileDepth, far_depth: f32) -> bool {
    return t.nearest == far_depth;
}

// The depth-bounds test per tile: the tile's geometry depths meet a light's depth range
// (bounds = LightClass::depth_bounds: x nearest, y farthest, in depth-buffer units).
fn deferred_depth_bounds_overlap(t: DeferredTileDepth, bounds: vec2<f32>, reversed: bool) -> bool {
    if reversed {
        return t.nearest != 0.0 && t.nearest >= bounds.y && t.farthest <= bounds.x;
    }
    return t.nearest != 1.0 && t.nearest <= bounds.y && t.farthest >= bounds.x;
}
