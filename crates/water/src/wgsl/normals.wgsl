// water: normals from linear view depth without derivatives. Twin of `water::normals`.
// Depth textures hold linear view depth in metres (> 0; 0, negative or inf = no water);
// pixel (x, y) has its centre at (x + 0.5, y + 0.5), +y down the image; view space is
// right-handed, +y up, looking down -z.

const WATER_TAPS_FIVE: u32 = 5u;
const WATER_TAPS_NINE: u32 = 9u;
const WATER_SMOOTH_RATIO: f32 = 2.0;
const WATER_SMOOTH_EPSILON: f32 = 0.0001;

fn water_depth_valid(d: f32) -> bool {
    return d > 0.0 && d < 3.0e38;
}

fn water_view_position(pixel: vec2<f32>, depth: f32, size: vec2<u32>, tan_half_fov: vec2<f32>) -> vec3<f32> {
    let ndc = vec2<f32>(pixel.x / f32(size.x) * 2.0 - 1.0, 1.0 - pixel.y / f32(size.y) * 2.0);
    return vec3<f32>(ndc.x * tan_half_fov.x * depth, ndc.y * tan_half_fov.y * depth, -depth);
}

// Depth at an integer pixel, +inf outside the image.
fn water_depth_at(depth: texture_2d<f32>, p: vec2<i32>) -> f32 {
    let size = vec2<i32>(textureDimensions(depth));
    if (any(p < vec2<i32>(0)) || any(p >= size)) {
        return 3.4028235e38;
    }
    return textureLoad(depth, p, 0).r;
}

// `RadiusRule::radius`.
fn water_normal_radius(depth: f32, radius_at_1m: f32, max_radius: u32) -> u32 {
    let r = radius_at_1m / depth;
    let m = max(max_radius, 1u);
    if (!(r > 1.0)) {
        return 1u;
    }
    let rr = floor(r + 0.5);
    if (rr >= f32(m)) {
        return m;
    }
    return u32(rr);
}

struct WaterTangent {
    ok: bool,
    t: vec3<f32>,
}

fn water_depth_tangent(depth: texture_2d<f32>, p: vec2<i32>, c: f32, step: vec2<i32>, taps: u32, tan_half_fov: vec2<f32>) -> WaterTangent {
    let size = textureDimensions(depth);
    let pc = water_view_position(vec2<f32>(p) + 0.5, c, size, tan_half_fov);
    let b1 = water_depth_at(depth, p - step);
    let a1 = water_depth_at(depth, p + step);
    let big = 3.4028235e38;
    var eb = big;
    var ea = big;
    var tol = WATER_SMOOTH_EPSILON * c;
    if (taps == WATER_TAPS_NINE) {
        tol = WATER_SMOOTH_EPSILON / c;
        let b2 = water_depth_at(depth, p - 2 * step);
        let a2 = water_depth_at(depth, p + 2 * step);
        if (water_depth_valid(b1) && water_depth_valid(b2)) {
            eb = abs(2.0 / b1 - 1.0 / b2 - 1.0 / c);
        } else if (water_depth_valid(b1)) {
            eb = abs(1.0 / b1 - 1.0 / c) * 2.0;
        }
        if (water_depth_valid(a1) && water_depth_valid(a2)) {
            ea = abs(2.0 / a1 - 1.0 / a2 - 1.0 / c);
        } else if (water_depth_valid(a1)) {
            ea = abs(1.0 / a1 - 1.0 / c) * 2.0;
        }
    } else {
        if (water_depth_valid(b1)) {
            eb = abs(b1 - c);
        }
        if (water_depth_valid(a1)) {
            ea = abs(a1 - c);
        }
    }
    if (eb >= big && ea >= big) {
        return WaterTangent(false, vec3<f32>(0.0));
    }
    let lo = min(eb, ea);
    let hi = max(eb, ea);
    if (hi <= WATER_SMOOTH_RATIO * lo + tol) {
        let before = water_view_position(vec2<f32>(p - step) + 0.5, b1, size, tan_half_fov);
        let after = water_view_position(vec2<f32>(p + step) + 0.5, a1, size, tan_half_fov);
        return WaterTangent(true, (after - before) * 0.5);
    }
    if (eb < ea) {
        return WaterTangent(true, pc - water_view_position(vec2<f32>(p - step) + 0.5, b1, size, tan_half_fov));
    }
    return WaterTangent(true, water_view_position(vec2<f32>(p + step) + 0.5, a1, size, tan_half_fov) - pc);
}

// The view-space normal at pixel p sampling `radius` pixels away with 5 or 9 taps
// (`DepthView::normal`); (0, 0, 0) where none can be made.
fn water_normal_from_depth(depth: texture_2d<f32>, p: vec2<i32>, radius: u32, taps: u32, tan_half_fov: vec2<f32>) -> vec3<f32> {
    let c = water_depth_at(depth, p);
    if (!water_depth_valid(c)) {
        return vec3<f32>(0.0);
    }
    let r = i32(max(radius, 1u));
    let tx = water_depth_tangent(depth, p, c, vec2<i32>(r, 0), taps, tan_half_fov);
    let ty = water_depth_tangent(depth, p, c, vec2<i32>(0, r), taps, tan_half_fov);
    if (!tx.ok || !ty.ok) {
        return vec3<f32>(0.0);
    }
    let n = cross(ty.t, tx.t);
    let l = length(n);
    if (!(l > 0.0)) {
        return vec3<f32>(0.0);
    }
    let nn = n / l;
    let to_camera = -water_view_position(vec2<f32>(p) + 0.5, c, textureDimensions(depth), tan_half_fov);
    return select(nn, -nn, dot(nn, to_camera) < 0.0);
}

// `blend_with_mesh`.
fn water_blend_normals(mesh: vec3<f32>, detail: vec3<f32>, detail_weight: f32) -> vec3<f32> {
    let w = saturate(detail_weight);
    let n = mesh * (1.0 - w) + detail * w;
    let l = length(n);
    if (l > 0.0) {
        return n / l;
    }
    let lm = length(mesh);
    return select(vec3<f32>(0.0), mesh / lm, lm > 0.0);
}
