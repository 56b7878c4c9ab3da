// visbuf: analytic perspective-correct barycentrics and their screen-space derivatives for
// the material resolve (Rust: visbuf::bary). Binding-free.
//
// pixel: framebuffer position relative to the viewport's top-left, +y down, centres at
// +0.5; viewport: (width, height) in pixels; c0..c2: clip positions as the vertex stage
// wrote them (x, y, z, w; z unused). ddx = change per pixel right, ddy = per pixel down.
// Degenerate triangles give lambda = (1/3, 1/3, 1/3) and zero derivatives.

const VISBUF_DEGENERATE_EPSILON: f32 = 9.094947e-13;
const VISBUF_MIN_MAGNITUDE: f32 = 7.888609e-31;
const VISBUF_MIN_RELATIVE: f32 = 9.094947e-13;
const VISBUF_MAX_NDC: f32 = 1048576.0;
const VISBUF_F32_MAX: f32 = 3.4028235e38;
const VISBUF_F32_MIN_POSITIVE: f32 = 1.17549435e-38;

struct VisbufBarycentrics {
    lambda: vec3<f32>,
    ddx: vec3<f32>,
    ddy: vec3<f32>,
}

struct VisbufInterp1 { value: f32, ddx: f32, ddy: f32, }
struct VisbufInterp2 { value: vec2<f32>, ddx: vec2<f32>, ddy: vec2<f32>, }
struct VisbufInterp3 { value: vec3<f32>, ddx: vec3<f32>, ddy: vec3<f32>, }
struct VisbufInterp4 { value: vec4<f32>, ddx: vec4<f32>, ddy: vec4<f32>, }

fn visbuf_degenerate_barycentrics() -> VisbufBarycentrics {
    return VisbufBarycentrics(vec3<f32>(1.0 / 3.0), vec3<f32>(0.0), vec3<f32>(0.0));
}

// The weights clamped to the triangle (negative ones 0, all scaled to sum to 1; inside
// they move by an ulp at most), the derivatives kept: attributes of a pixel whose centre
// the vertex ring's f16 positions leave outside a sub-pixel or edge-on triangle stay
// within its range. No branch for the inside: it cost the resolve registers. For finite
// weights (what visbuf_barycentrics returns). Rust: Barycentrics::clamped.
fn visbuf_clamp_barycentrics(b: VisbufBarycentrics) -> VisbufBarycentrics {
    let l = max(b.lambda, vec3<f32>(0.0));
    let sum = l.x + l.y + l.z;
    if (!(sum > 0.0)) {
        return visbuf_degenerate_barycentrics();
    }
    return VisbufBarycentrics(l / sum, b.ddx, b.ddy);
}

fn visbuf_max_abs3(v: vec3<f32>) -> f32 {
    let a = abs(v);
    return max(max(a.x, a.y), a.z);
}

// Edge functions of the pixel-relative positions (clip scaled by a power of two to at
// most 1), and their
// derivatives in NDC: rows e, de/dqx, de/dqy. `ok` is false when degenerate.
struct VisbufEdges {
    e: vec3<f32>,
    ex: vec3<f32>,
    ey: vec3<f32>,
    ok: bool,
}

fn visbuf_edges(c0: vec4<f32>, c1: vec4<f32>, c2: vec4<f32>, q_in: vec2<f32>) -> VisbufEdges {
    var out: VisbufEdges;
    out.ok = false;
    let m0 = max(max(visbuf_max_abs3(c0.xyw), visbuf_max_abs3(c1.xyw)), visbuf_max_abs3(c2.xyw));
    if (!(m0 >= VISBUF_MIN_MAGNITUDE && m0 <= VISBUF_F32_MAX)) {
        return out;
    }
    let s0 = ldexp(1.0, -frexp(m0).exp);
    let q = clamp(q_in, vec2<f32>(-VISBUF_MAX_NDC), vec2<f32>(VISBUF_MAX_NDC));
    let a0 = c0.xyw * s0;
    let a1 = c1.xyw * s0;
    let a2 = c2.xyw * s0;
    let p0 = vec3<f32>(a0.x - q.x * a0.z, a0.y - q.y * a0.z, a0.z);
    let p1 = vec3<f32>(a1.x - q.x * a1.z, a1.y - q.y * a1.z, a1.z);
    let p2 = vec3<f32>(a2.x - q.x * a2.z, a2.y - q.y * a2.z, a2.z);
    out.e = vec3<f32>(p1.x * p2.y - p2.x * p1.y, p2.x * p0.y - p0.x * p2.y, p0.x * p1.y - p1.x * p0.y);
    out.ex = vec3<f32>(p2.z * p1.y - p1.z * p2.y, p0.z * p2.y - p2.z * p0.y, p1.z * p0.y - p0.z * p1.y);
    out.ey = vec3<f32>(p1.z * p2.x - p2.z * p1.x, p2.z * p0.x - p0.z * p2.x, p0.z * p1.x - p1.z * p0.x);
    let m1 = max(max(visbuf_max_abs3(p0), visbuf_max_abs3(p1)), visbuf_max_abs3(p2));
    out.ok = m1 >= VISBUF_MIN_RELATIVE
        && abs(out.e.x + out.e.y + out.e.z) >= VISBUF_DEGENERATE_EPSILON * (m1 * m1);
    return out;
}

fn visbuf_pixel_to_ndc(pixel: vec2<f32>, viewport: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(2.0 * pixel.x / viewport.x - 1.0, 1.0 - 2.0 * pixel.y / viewport.y);
}

// Weights with their exact derivatives (the analytic gradient at the pixel centre).
fn visbuf_barycentrics(c0: vec4<f32>, c1: vec4<f32>, c2: vec4<f32>, pixel: vec2<f32>, viewport: vec2<f32>) -> VisbufBarycentrics {
    if (!(viewport.x > 0.0 && viewport.y > 0.0)) {
        return visbuf_degenerate_barycentrics();
    }
    let k = visbuf_edges(c0, c1, c2, visbuf_pixel_to_ndc(pixel, viewport));
    if (!k.ok) {
        return visbuf_degenerate_barycentrics();
    }
    let inv = 1.0 / (k.e.x + k.e.y + k.e.z);
    let lambda = k.e * inv;
    let dqx = (k.ex - lambda * (k.ex.x + k.ex.y + k.ex.z)) * inv;
    let dqy = (k.ey - lambda * (k.ey.x + k.ey.y + k.ey.z)) * inv;
    return VisbufBarycentrics(lambda, dqx * (2.0 / viewport.x), dqy * (-2.0 / viewport.y));
}

fn visbuf_quad_step(e: vec3<f32>, s: f32, lambda: vec3<f32>, de: vec3<f32>, d: f32) -> vec3<f32> {
    let ds = de.x + de.y + de.z;
    let s1 = s + ds * d;
    if (abs(s1) >= VISBUF_DEGENERATE_EPSILON) {
        return (e + de * d) * (1.0 / s1) - lambda;
    }
    return (de - lambda * ds) * (1.0 / s) * d;
}

// Weights with one-pixel forward differences (like dpdxFine/dpdyFine on a quad's top-left
// pixel) instead of exact derivatives.
fn visbuf_barycentrics_quad(c0: vec4<f32>, c1: vec4<f32>, c2: vec4<f32>, pixel: vec2<f32>, viewport: vec2<f32>) -> VisbufBarycentrics {
    if (!(viewport.x > 0.0 && viewport.y > 0.0)) {
        return visbuf_degenerate_barycentrics();
    }
    let k = visbuf_edges(c0, c1, c2, visbuf_pixel_to_ndc(pixel, viewport));
    if (!k.ok) {
        return visbuf_degenerate_barycentrics();
    }
    let s = k.e.x + k.e.y + k.e.z;
    let lambda = k.e * (1.0 / s);
    return VisbufBarycentrics(
        lambda,
        visbuf_quad_step(k.e, s, lambda, k.ex, 2.0 / viewport.x),
        visbuf_quad_step(k.e, s, lambda, k.ey, -2.0 / viewport.y),
    );
}

fn visbuf_interpolate1(b: VisbufBarycentrics, a0: f32, a1: f32, a2: f32) -> VisbufInterp1 {
    let a = vec3<f32>(a0, a1, a2);
    return VisbufInterp1(dot(a, b.lambda), dot(a, b.ddx), dot(a, b.ddy));
}

fn visbuf_interpolate2(b: VisbufBarycentrics, a0: vec2<f32>, a1: vec2<f32>, a2: vec2<f32>) -> VisbufInterp2 {
    return VisbufInterp2(
        a0 * b.lambda.x + a1 * b.lambda.y + a2 * b.lambda.z,
        a0 * b.ddx.x + a1 * b.ddx.y + a2 * b.ddx.z,
        a0 * b.ddy.x + a1 * b.ddy.y + a2 * b.ddy.z,
    );
}

fn visbuf_interpolate3(b: VisbufBarycentrics, a0: vec3<f32>, a1: vec3<f32>, a2: vec3<f32>) -> VisbufInterp3 {
    return VisbufInterp3(
        a0 * b.lambda.x + a1 * b.lambda.y + a2 * b.lambda.z,
        a0 * b.ddx.x + a1 * b.ddx.y + a2 * b.ddx.z,
        a0 * b.ddy.x + a1 * b.ddy.y + a2 * b.ddy.z,
    );
}

fn visbuf_interpolate4(b: VisbufBarycentrics, a0: vec4<f32>, a1: vec4<f32>, a2: vec4<f32>) -> VisbufInterp4 {
    return VisbufInterp4(
        a0 * b.lambda.x + a1 * b.lambda.y + a2 * b.lambda.z,
        a0 * b.ddx.x + a1 * b.ddx.y + a2 * b.ddx.z,
        a0 * b.ddy.x + a1 * b.ddy.y + a2 * b.ddy.z,
    );
}

// Isotropic mip level: log2(max(|duv_dx * size|, |duv_dy * size|)) + bias, unclamped.
fn visbuf_mip_level(duv_dx: vec2<f32>, duv_dy: vec2<f32>, texture_size: vec2<f32>, bias: f32) -> f32 {
    let x = duv_dx * texture_size;
    let y = duv_dy * texture_size;
    let rho2 = clamp(max(dot(x, x), dot(y, y)), VISBUF_F32_MIN_POSITIVE, VISBUF_F32_MAX);
    return 0.5 * log2(rho2) + bias;
}

// The factor to scale both UV gradients by to move textureSampleGrad's level by `bias`.
fn visbuf_mip_bias_scale(bias: f32) -> f32 {
    return exp2(bias);
}
