// visbuf: the watertight ray-triangle fallback (Woop, Benthin, Wald 2013; Rust:
// visbuf::ray). Binding-free. Unlike the CPU twin it has no f64 re-evaluation of edge
// functions that are exactly zero: such rays count as hitting (both neighbours may hit),
// which keeps the test crack-free.

struct VisbufRayHit {
    hit: bool,
    // Distance in units of |dir|.
    t: f32,
    // Weights of v0, v1, v2.
    barycentrics: vec3<f32>,
}

fn visbuf_intersect_watertight(origin: vec3<f32>, dir: vec3<f32>, v0: vec3<f32>, v1: vec3<f32>, v2: vec3<f32>) -> VisbufRayHit {
    var out = VisbufRayHit(false, 0.0, vec3<f32>(0.0));
    let a = abs(dir);
    var kz = 2u;
    if (a.x > a.y) {
        if (a.x > a.z) {
            kz = 0u;
        }
    } else if (a.y > a.z) {
        kz = 1u;
    }
    if (dir[kz] == 0.0) {
        return out;
    }
    var kx = (kz + 1u) % 3u;
    var ky = (kz + 2u) % 3u;
    if (dir[kz] < 0.0) {
        let tmp = kx;
        kx = ky;
        ky = tmp;
    }
    let sz = 1.0 / dir[kz];
    let sx = dir[kx] * sz;
    let sy = dir[ky] * sz;
    let r0 = v0 - origin;
    let r1 = v1 - origin;
    let r2 = v2 - origin;
    let ax = r0[kx] - sx * r0[kz];
    let ay = r0[ky] - sy * r0[kz];
    let bx = r1[kx] - sx * r1[kz];
    let by = r1[ky] - sy * r1[kz];
    let cx = r2[kx] - sx * r2[kz];
    let cy = r2[ky] - sy * r2[kz];
    let u = cx * by - cy * bx;
    let v = ax * cy - ay * cx;
    let w = bx * ay - by * ax;
    if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) {
        return out;
    }
    let det = u + v + w;
    if (det == 0.0) {
        return out;
    }
    let t_scaled = u * (sz * r0[kz]) + v * (sz * r1[kz]) + w * (sz * r2[kz]);
    if ((det > 0.0 && t_scaled < 0.0) || (det < 0.0 && t_scaled > 0.0)) {
        return out;
    }
    let inv = 1.0 / det;
    out.hit = true;
    out.t = t_scaled * inv;
    out.barycentrics = vec3<f32>(u, v, w) * inv;
    return out;
}

// Direction of the camera ray from `eye` through `pixel` (towards NDC depth 0.5);
// zero when the matrix maps the pixel to infinity.
fn visbuf_pixel_ray_direction(inv_view_proj: mat4x4<f32>, eye: vec3<f32>, pixel: vec2<f32>, viewport: vec2<f32>) -> vec3<f32> {
    let ndc = vec2<f32>(2.0 * pixel.x / viewport.x - 1.0, 1.0 - 2.0 * pixel.y / viewport.y);
    let p = inv_view_proj * vec4<f32>(ndc, 0.5, 1.0);
    if (p.w == 0.0) {
        return vec3<f32>(0.0);
    }
    return p.xyz / p.w - eye;
}
