// gpu: the compute visibility laydown (issue 17): one invocation per (instance, triangle)
// of the scene's planned draws, in one dispatch, rasterised in compute into the 64-bit
// visibility target with `atomicMax`. The H200's raster runs on 2 TPCs of 66, compute on
// all of them, and dense foliage is small triangles.
//
// Coverage is the hardware rasteriser's: vertices through `laydown_vertex` (the same clip
// coordinates), counter-clockwise front faces, back faces culled, vertices snapped to
// 1/256 pixel (8 subpixel bits, as Vulkan and D3D devices do), integer edge functions
// sampled at pixel centres with the top-left rule. Alpha-tested draws sample the albedo's
// alpha at the level of the analytic UV derivatives (`textureSampleLevel`; compute has no
// quads) and honour the LOD-fade dither. Triangles the hardware clips (a vertex in front
// of the near plane or at w <= 0) or whose box is wider or taller than
// GPU_COMPUTE_LAYDOWN_MAX_EXTENT pixels go to the hardware part: appended to `hybrid`
// (one atomic per wave), drawn by `gpu::compute_laydown_hybrid` into the same target.

#import gpu::compute_laydown_draws
#import wave::append

// The hardware part's list: a non-indexed indirect draw (3 vertices per listed triangle;
// `vertex_count` may pass 3 x the capacity: the vertex stage drops what did not fit),
// then the items. Cleared to 0 each frame; the first item sets `instance_count` to 1.
struct GpuHybridList {
    vertex_count: atomic<u32>,
    instance_count: u32,
    first_vertex: u32,
    first_instance: u32,
    items: array<u32>,
}

@group(1) @binding(3) var<storage, read_write> hybrid: GpuHybridList;

// The widest or tallest box (pixels) rasterised in compute: larger triangles cost one
// invocation too many pixels and go to the hardware (0: every triangle does). Rust:
// COMPUTE_LAYDOWN_MAX_EXTENT, RendererConfig::compute_laydown_max_extent.
override GPU_COMPUTE_LAYDOWN_MAX_EXTENT: f32 = 32.0;
// Subpixel steps per pixel (8 bits).
const GPU_LAYDOWN_SUBPIXELS: f32 = 256.0;
// Invocations per workgroup and items per dispatch row (shader::MAX_WORKGROUPS_X rows).
const GPU_LAYDOWN_WORKGROUP: u32 = 64u;
const GPU_LAYDOWN_ROW_ITEMS: u32 = 4194240u; // 65535 * 64

fn gpu_finite(v: vec4<f32>) -> bool {
    // Exponent all ones: infinity or NaN (bit test: comparisons may assume no NaN).
    let e = (bitcast<vec4<u32>>(v) >> vec4<u32>(23u)) & vec4<u32>(0xffu);
    return all(e != vec4<u32>(0xffu));
}

// Pixel position (x right, y down) of clip position `c` in an image of `size` pixels.
fn gpu_laydown_screen(c: vec4<f32>, size: vec2<f32>) -> vec2<f32> {
    let ndc = c.xy / c.w;
    return vec2<f32>((ndc.x + 1.0) * 0.5 * size.x, (1.0 - ndc.y) * 0.5 * size.y);
}

fn gpu_cross(a: vec2<i32>, b: vec2<i32>) -> i32 {
    return a.x * b.y - a.y * b.x;
}

// The top-left rule for an edge `e` (end minus start) of a triangle whose edge functions
// are positive inside in y-down pixels: a top edge is horizontal going right, a left edge
// goes up. Samples exactly on other edges are outside (bias -1).
fn gpu_top_left_bias(e: vec2<i32>) -> i32 {
    if ((e.y == 0 && e.x > 0) || e.y < 0) {
        return 0;
    }
    return -1;
}

// One vertex of the triangle being rasterised.
struct GpuRasterVertex {
    // Snapped position relative to the box's corner, 1/256 pixel.
    p: vec2<i32>,
    // Depth (z / w), 1 / w and uv / w (perspective-correct UV).
    z: f32,
    q: f32,
    uq: vec2<f32>,
}

// Rasterises `item`'s triangle into the target; true when it goes to the hardware part.
fn gpu_raster_item(item: u32) -> bool {
    let t = gpu_laydown_triangle(item);
    if (!t.valid) {
        return false;
    }
    let o0 = laydown_vertex(t.vertices.x, t.instance);
    let o1 = laydown_vertex(t.vertices.y, t.instance);
    let o2 = laydown_vertex(t.vertices.z, t.instance);
    let c0 = o0.clip;
    let c1 = o1.clip;
    let c2 = o2.clip;
    if (!(gpu_finite(c0) && gpu_finite(c1) && gpu_finite(c2))) {
        return false;
    }
    // Outside one clip plane with all three vertices: nothing to draw (the near plane of
    // reversed Z is z = w; behind the eye z > w too).
    let near = vec3<bool>(c0.z > c0.w, c1.z > c1.w, c2.z > c2.w);
    if (all(near)
        || (c0.x > c0.w && c1.x > c1.w && c2.x > c2.w)
        || (c0.x < -c0.w && c1.x < -c1.w && c2.x < -c2.w)
        || (c0.y > c0.w && c1.y > c1.w && c2.y > c2.w)
        || (c0.y < -c0.w && c1.y < -c1.w && c2.y < -c2.w)
        || (c0.z < 0.0 && c1.z < 0.0 && c2.z < 0.0)) {
        return false;
    }
    // Crossing the near or far plane, or too close to w = 0 to divide: the hardware clips.
    let eps = 1e-6;
    if (any(near) || c0.w <= eps || c1.w <= eps || c2.w <= eps
        || c0.z < 0.0 || c1.z < 0.0 || c2.z < 0.0) {
        return true;
    }
    let size = frame.viewport.xy;
    let s0 = gpu_laydown_screen(c0, size);
    let s1 = gpu_laydown_screen(c1, size);
    let s2 = gpu_laydown_screen(c2, size);
    let lo = min(s0, min(s1, s2));
    let hi = max(s0, max(s1, s2));
    // No pixel centre of the image inside the box.
    if (hi.x < 0.0 || hi.y < 0.0 || lo.x > size.x || lo.y > size.y) {
        return false;
    }
    if (any(hi - lo > vec2<f32>(GPU_COMPUTE_LAYDOWN_MAX_EXTENT))) {
        return true;
    }
    // Fixed point relative to the box's whole-pixel corner: at most (extent + 2) x 256,
    // so the edge functions' products stay below 2^31 up to an extent of 254 pixels.
    let corner = floor(lo) - 1.0;
    var v: array<GpuRasterVertex, 3>;
    let cs = array<vec4<f32>, 3>(c0, c1, c2);
    let ss = array<vec2<f32>, 3>(s0, s1, s2);
    let uvs = array<vec2<f32>, 3>(o0.uv, o1.uv, o2.uv);
    for (var k = 0u; k < 3u; k++) {
        v[k].p = vec2<i32>(round((ss[k] - corner) * GPU_LAYDOWN_SUBPIXELS));
        v[k].q = 1.0 / cs[k].w;
        v[k].z = cs[k].z * v[k].q;
        v[k].uq = uvs[k] * v[k].q;
    }
    // Front faces are counter-clockwise in clip space: clockwise in y-down pixels, where
    // this cross product is negative. Back faces and degenerate ones are culled.
    let area0 = gpu_cross(v[1].p - v[0].p, v[2].p - v[0].p);
    if (area0 >= 0) {
        return false;
    }
    // Swap two vertices so the edge functions are positive inside.
    let a = v[0];
    let b = v[2];
    let c = v[1];
    let area = -area0;
    let eab = b.p - a.p;
    let ebc = c.p - b.p;
    let eca = a.p - c.p;
    let bias = vec3<i32>(gpu_top_left_bias(ebc), gpu_top_left_bias(eca), gpu_top_left_bias(eab));
    let inv_area = 1.0 / f32(area);
    let word = vis_word(t.instance, t.primitive);
    let alpha = (t.flags & GPU_LAYDOWN_DRAW_ALPHA_TESTED) != 0u;
    // Analytic derivatives of the barycentrics (weights of a, b, c) per pixel.
    let dbdx = vec3<f32>(f32(-ebc.y), f32(-eca.y), f32(-eab.y)) * (GPU_LAYDOWN_SUBPIXELS * inv_area);
    let dbdy = vec3<f32>(f32(ebc.x), f32(eca.x), f32(eab.x)) * (GPU_LAYDOWN_SUBPIXELS * inv_area);
    let inst = instances[t.instance];
    let material = materials[min(inst.material, arrayLength(&materials) - 1u)];
    let tex = vec2<f32>(textureDimensions(albedo, 0));
    let w = i32(size.x);
    let h = i32(size.y);
    let x0 = max(i32(floor(lo.x - 0.01)), 0);
    let x1 = min(i32(floor(hi.x + 0.01)), w - 1);
    let y0 = max(i32(floor(lo.y - 0.01)), 0);
    let y1 = min(i32(floor(hi.y + 0.01)), h - 1);
    let cx = i32(corner.x);
    let cy = i32(corner.y);
    let len = arrayLength(&laydown_target);
    for (var y = y0; y <= y1; y++) {
        for (var x = x0; x <= x1; x++) {
            // The pixel centre in the triangle's fixed point.
            let p = vec2<i32>((x - cx) * 256 + 128, (y - cy) * 256 + 128);
            let e = vec3<i32>(
                gpu_cross(ebc, p - b.p),
                gpu_cross(eca, p - c.p),
                gpu_cross(eab, p - a.p),
            );
            if (any(e + bias < vec3<i32>(0))) {
                continue;
            }
            let bary = vec3<f32>(e) * inv_area;
            if (alpha) {
                if (!gpu_fade_keeps(inst.primitive_bits, vec2<u32>(u32(x), u32(y)))) {
                    continue;
                }
                // Perspective-correct UV and its screen derivatives: uv = N / D.
                let d = dot(bary, vec3<f32>(a.q, b.q, c.q));
                let uv = (bary.x * a.uq + bary.y * b.uq + bary.z * c.uq) / d;
                let ddx = dot(dbdx, vec3<f32>(a.q, b.q, c.q));
                let ddy = dot(dbdy, vec3<f32>(a.q, b.q, c.q));
                let duvdx = (dbdx.x * a.uq + dbdx.y * b.uq + dbdx.z * c.uq - uv * ddx) / d;
                let duvdy = (dbdy.x * a.uq + dbdy.y * b.uq + dbdy.z * c.uq - uv * ddy) / d;
                let rho = max(length(duvdx * tex), length(duvdy * tex));
                let lod = log2(max(rho, 1e-8));
                let alpha_value = textureSampleLevel(albedo, albedo_sampler, uv, material.albedo_layer, lod).a;
                if (alpha_value < material.alpha_cutoff) {
                    continue;
                }
            }
            let depth = clamp(dot(bary, vec3<f32>(a.z, b.z, c.z)), 0.0, 1.0);
            let i = u32(y) * u32(w) + u32(x);
            if (i < len) {
                atomicMax(&laydown_target[i], gpu_laydown_value(depth, word));
            }
        }
    }
    return false;
}

@compute @workgroup_size(64)
fn raster(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) li: u32) {
    let item = wid.y * GPU_LAYDOWN_ROW_ITEMS + wid.x * GPU_LAYDOWN_WORKGROUP + li;
    var to_hardware = false;
    if (item < laydown_draws.items) {
        to_hardware = gpu_raster_item(item);
    }
    if (item == 0u) {
        hybrid.instance_count = 1u;
    }
    // Three vertices per listed triangle: the counter is the indirect draw's vertex count.
    let a = wave_append_n_begin(select(0u, 3u, to_hardware), li);
    var old = 0u;
    if (a.total != 0u) {
        old = atomicAdd(&hybrid.vertex_count, a.total);
    }
    let at = wave_append_end(a, old);
    if (to_hardware && at != WAVE_NO_SLOT && at / 3u < arrayLength(&hybrid.items)) {
        hybrid.items[at / 3u] = item;
    }
}
