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
// of the near plane or at w <= 0) go to the hardware part: appended to `hybrid` (one
// atomic per wave), drawn by `gpu::compute_laydown_hybrid` after the conversion. Triangles
// whose box is wider or taller than GPU_COMPUTE_LAYDOWN_MAX_EXTENT pixels, or larger than
// a quarter of its square, are appended to `large` and rasterised by `raster_large`, a
// 256-invocation workgroup per GPU_LAYDOWN_LARGE_BATCH triangles over the 8x8 blocks of
// their boxes that they touch, with 64-bit edge functions (the raster units are the
// scarce ones on the H200).

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

// The large triangles' list: `raster_large`'s indirect dispatch (written by `large_args`;
// rows of GPU_LAYDOWN_ROWS workgroups), the count, then the items. Cleared each frame.
struct GpuLargeList {
    dispatch: array<u32, 3>,
    count: atomic<u32>,
    items: array<u32>,
}

@group(1) @binding(4) var<storage, read_write> large: GpuLargeList;

// Workgroups per row of `raster_large`'s dispatch (shader::MAX_WORKGROUPS_X).
const GPU_LAYDOWN_ROWS: u32 = 65535u;
// Invocations of a `raster_large` workgroup.
const GPU_LAYDOWN_LARGE_WORKGROUP: u32 = 256u;
// A box wider or taller than this (pixels) goes to the hardware part even from the large
// path: the 64-bit edge functions' products stay far below 2^63.
const GPU_LAYDOWN_LARGE_LIMIT: f32 = 1048576.0;

// The widest or tallest box (pixels) one invocation rasterises, and four times the largest
// box area: larger triangles cost one invocation too many pixels and go to `raster_large`
// (0: every triangle does). Rust: COMPUTE_LAYDOWN_MAX_EXTENT,
// RendererConfig::compute_laydown_max_extent.
override GPU_COMPUTE_LAYDOWN_MAX_EXTENT: f32 = 24.0;
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

// What the pixels of a triangle share once it is set up: its vertices' depth, 1 / w and
// uv / w (a, b, c: the order whose edge functions are positive inside), the barycentric
// derivatives per pixel, and what the alpha test reads.
struct GpuRasterShade {
    z: vec3<f32>,
    q: vec3<f32>,
    uq0: vec2<f32>,
    uq1: vec2<f32>,
    uq2: vec2<f32>,
    dbdx: vec3<f32>,
    dbdy: vec3<f32>,
    word: u32,
    alpha: bool,
    fade_bits: u32,
    layer: u32,
    cutoff: f32,
    tex: vec2<f32>,
}

// A triangle set up for rasterising: `kind` GPU_RASTER_NONE (nothing to draw),
// GPU_RASTER_HARDWARE, GPU_RASTER_LARGE or GPU_RASTER_SMALL; then its snapped vertices
// (a, b, c, in 1/256 pixel relative to `corner`, below 2^29), its box clipped to the
// image, and shading.
struct GpuRasterTriangle {
    kind: u32,
    corner: vec2<i32>,
    a: vec2<i32>,
    b: vec2<i32>,
    c: vec2<i32>,
    x0: i32,
    x1: i32,
    y0: i32,
    y1: i32,
    // 1 / the edge functions' sum (twice the area in subpixels squared)
    inv_area: f32,
    shade: GpuRasterShade,
}

const GPU_RASTER_NONE: u32 = 0u;
const GPU_RASTER_HARDWARE: u32 = 1u;
const GPU_RASTER_LARGE: u32 = 2u;
const GPU_RASTER_SMALL: u32 = 3u;

// Sets up `item`'s triangle. Each vertex snaps in whole image subpixels first, so a vertex
// that triangles share snaps the same in each (a difference from each box's corner in f32
// rounds differently per box past 2^24 subpixels, 65 536 px, and opened cracks between
// huge triangles); x 256 and round are exact in f32, and with the box at most
// GPU_LAYDOWN_LARGE_LIMIT past an image of at most 32 768 px every coordinate is below
// 2^29 subpixels, so i32 holds it and its difference from the corner exactly.
fn gpu_raster_setup(item: u32) -> GpuRasterTriangle {
    var r: GpuRasterTriangle;
    r.kind = GPU_RASTER_NONE;
    let t = gpu_laydown_triangle(item);
    if (!t.valid) {
        return r;
    }
    let o0 = laydown_vertex(t.vertices.x, t.instance);
    let o1 = laydown_vertex(t.vertices.y, t.instance);
    let o2 = laydown_vertex(t.vertices.z, t.instance);
    let c0 = o0.clip;
    let c1 = o1.clip;
    let c2 = o2.clip;
    if (!(gpu_finite(c0) && gpu_finite(c1) && gpu_finite(c2))) {
        return r;
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
        return r;
    }
    // Crossing the near or far plane, or too close to w = 0 to divide: the hardware clips.
    let eps = 1e-6;
    if (any(near) || c0.w <= eps || c1.w <= eps || c2.w <= eps
        || c0.z < 0.0 || c1.z < 0.0 || c2.z < 0.0) {
        r.kind = GPU_RASTER_HARDWARE;
        return r;
    }
    let size = frame.viewport.xy;
    let s0 = gpu_laydown_screen(c0, size);
    let s1 = gpu_laydown_screen(c1, size);
    let s2 = gpu_laydown_screen(c2, size);
    let lo = min(s0, min(s1, s2));
    let hi = max(s0, max(s1, s2));
    // No pixel centre of the image inside the box.
    if (hi.x < 0.0 || hi.y < 0.0 || lo.x > size.x || lo.y > size.y) {
        return r;
    }
    let extent = hi - lo;
    if (any(extent > vec2<f32>(GPU_LAYDOWN_LARGE_LIMIT))) {
        r.kind = GPU_RASTER_HARDWARE;
        return r;
    }
    let split = GPU_COMPUTE_LAYDOWN_MAX_EXTENT;
    let small = !any(extent > vec2<f32>(split)) && extent.x * extent.y <= 0.25 * split * split;
    // Fixed point relative to the box's whole-pixel corner.
    let corner = floor(lo) - 1.0;
    let cs = array<vec4<f32>, 3>(c0, c1, c2);
    let ss = array<vec2<f32>, 3>(s0, s1, s2);
    let uvs = array<vec2<f32>, 3>(o0.uv, o1.uv, o2.uv);
    let base = vec2<i32>(corner) * 256;
    var p: array<vec2<i32>, 3>;
    var q: array<f32, 3>;
    var z: array<f32, 3>;
    var uq: array<vec2<f32>, 3>;
    for (var k = 0u; k < 3u; k++) {
        p[k] = vec2<i32>(round(ss[k] * GPU_LAYDOWN_SUBPIXELS)) - base;
        q[k] = 1.0 / cs[k].w;
        z[k] = cs[k].z * q[k];
        uq[k] = uvs[k] * q[k];
    }
    // Front faces are counter-clockwise in clip space: clockwise in y-down pixels, where
    // this cross product is negative. Back faces and degenerate ones are culled.
    let area0 = gpu_cross64(p[1] - p[0], p[2] - p[0]);
    if (area0 >= 0li) {
        return r;
    }
    // Swap two vertices so the edge functions are positive inside: a = 0, b = 2, c = 1.
    r.a = p[0];
    r.b = p[2];
    r.c = p[1];
    let inv_area = 1.0 / f32(-area0);
    r.inv_area = inv_area;
    let eab = vec2<f32>(r.b - r.a);
    let ebc = vec2<f32>(r.c - r.b);
    let eca = vec2<f32>(r.a - r.c);
    var sh: GpuRasterShade;
    sh.z = vec3<f32>(z[0], z[2], z[1]);
    sh.q = vec3<f32>(q[0], q[2], q[1]);
    sh.uq0 = uq[0];
    sh.uq1 = uq[2];
    sh.uq2 = uq[1];
    // Analytic derivatives of the barycentrics (weights of a, b, c) per pixel.
    sh.dbdx = vec3<f32>(-ebc.y, -eca.y, -eab.y) * (GPU_LAYDOWN_SUBPIXELS * inv_area);
    sh.dbdy = vec3<f32>(ebc.x, eca.x, eab.x) * (GPU_LAYDOWN_SUBPIXELS * inv_area);
    sh.word = vis_word(t.instance, t.primitive, o0.rate);
    sh.alpha = (t.flags & GPU_LAYDOWN_DRAW_ALPHA_TESTED) != 0u;
    let inst = instances[t.instance];
    sh.fade_bits = inst.primitive_bits;
    let material = materials[min(inst.material, arrayLength(&materials) - 1u)];
    sh.layer = material.albedo_layer;
    sh.cutoff = material.alpha_cutoff;
    sh.tex = vec2<f32>(textureDimensions(albedo, 0));
    r.shade = sh;
    r.corner = vec2<i32>(corner);
    let w = i32(size.x);
    let h = i32(size.y);
    r.x0 = max(i32(floor(max(lo.x, -1.0) - 0.01)), 0);
    r.x1 = min(i32(floor(min(hi.x, size.x + 1.0) + 0.01)), w - 1);
    r.y0 = max(i32(floor(max(lo.y, -1.0) - 0.01)), 0);
    r.y1 = min(i32(floor(min(hi.y, size.y + 1.0) + 0.01)), h - 1);
    r.kind = select(GPU_RASTER_LARGE, GPU_RASTER_SMALL, small);
    return r;
}

// a x b of subpixel vectors, exactly, in 64 bits.
fn gpu_cross64(a: vec2<i32>, b: vec2<i32>) -> i64 {
    return i64(a.x) * i64(b.y) - i64(a.y) * i64(b.x);
}

// The top-left rule's bias of edge `e` (subpixels).
fn gpu_top_left_bias64(e: vec2<i32>) -> i64 {
    if ((e.y == 0 && e.x > 0) || e.y < 0) {
        return 0li;
    }
    return -1li;
}

// Pixel (x, y) of triangle `r` whose barycentric weights of a, b, c are `bary`: the alpha
// test and the LOD-fade dither, then the depth and vis word into the target.
fn gpu_raster_shade(x: i32, y: i32, bary: vec3<f32>, sh: GpuRasterShade, w: i32) {
    if (sh.alpha) {
        if (!gpu_fade_keeps(sh.fade_bits, vec2<u32>(u32(x), u32(y)))) {
            return;
        }
        // Perspective-correct UV and its screen derivatives: uv = N / D.
        let d = dot(bary, sh.q);
        let uv = (bary.x * sh.uq0 + bary.y * sh.uq1 + bary.z * sh.uq2) / d;
        let ddx = dot(sh.dbdx, sh.q);
        let ddy = dot(sh.dbdy, sh.q);
        let duvdx = (sh.dbdx.x * sh.uq0 + sh.dbdx.y * sh.uq1 + sh.dbdx.z * sh.uq2 - uv * ddx) / d;
        let duvdy = (sh.dbdy.x * sh.uq0 + sh.dbdy.y * sh.uq1 + sh.dbdy.z * sh.uq2 - uv * ddy) / d;
        let rho = max(length(duvdx * sh.tex), length(duvdy * sh.tex));
        let lod = log2(max(rho, 1e-8));
        let alpha_value = textureSampleLevel(albedo, albedo_sampler, uv, sh.layer, lod).a;
        if (alpha_value < sh.cutoff) {
            return;
        }
    }
    let depth = clamp(dot(bary, sh.z), 0.0, 1.0);
    gpu_laydown_plot(vec2<u32>(u32(x), u32(y)), u32(w), gpu_laydown_value(depth, sh.word));
}

// The weights of a, b, c at pixel (x, y) of a small `r` (32-bit edge functions: its
// subpixel positions are below 2^16), or a negative x weight outside (the top-left rule:
// samples on an edge that is not top or left are outside).
fn gpu_raster_weights_small(r: GpuRasterTriangle, x: i32, y: i32) -> vec3<f32> {
    let a = r.a;
    let b = r.b;
    let c = r.c;
    let p = vec2<i32>((x - r.corner.x) * 256 + 128, (y - r.corner.y) * 256 + 128);
    let e = vec3<i32>(gpu_cross(c - b, p - b), gpu_cross(a - c, p - c), gpu_cross(b - a, p - a));
    let bias = vec3<i32>(gpu_top_left_bias(c - b), gpu_top_left_bias(a - c), gpu_top_left_bias(b - a));
    if (any(e + bias < vec3<i32>(0))) {
        return vec3<f32>(-1.0);
    }
    return vec3<f32>(e) * r.inv_area;
}

// Rasterises `item`'s triangle into the target when it is small; returns its kind (the
// caller lists the hardware and large ones).
fn gpu_raster_item(item: u32) -> u32 {
    let r = gpu_raster_setup(item);
    if (r.kind != GPU_RASTER_SMALL) {
        return r.kind;
    }
    let w = i32(frame.viewport.x);
    for (var y = r.y0; y <= r.y1; y++) {
        for (var x = r.x0; x <= r.x1; x++) {
            let bary = gpu_raster_weights_small(r, x, y);
            if (bary.x >= 0.0) {
                gpu_raster_shade(x, y, bary, r.shade, w);
            }
        }
    }
    return r.kind;
}

@compute @workgroup_size(GPU_LAYDOWN_WORKGROUP)
fn raster(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) li: u32) {
    let item = wid.y * GPU_LAYDOWN_ROW_ITEMS + wid.x * GPU_LAYDOWN_WORKGROUP + li;
    var kind = GPU_RASTER_NONE;
    if (item < laydown_draws.items) {
        kind = gpu_raster_item(item);
    }
    if (item == 0u) {
        hybrid.instance_count = 1u;
    }
    // Three vertices per listed triangle: the counter is the indirect draw's vertex count.
    let to_hardware = kind == GPU_RASTER_HARDWARE;
    let a = wave_append_n_begin(select(0u, 3u, to_hardware), li);
    var old = 0u;
    if (a.total != 0u) {
        old = atomicAdd(&hybrid.vertex_count, a.total);
    }
    let at = wave_append_end(a, old);
    if (to_hardware && at != WAVE_NO_SLOT && at / 3u < arrayLength(&hybrid.items)) {
        hybrid.items[at / 3u] = item;
    }
    let is_large = kind == GPU_RASTER_LARGE;
    let b = wave_append_begin(is_large, li);
    var old_large = 0u;
    if (b.total != 0u) {
        old_large = atomicAdd(&large.count, b.total);
    }
    let at_large = wave_append_end(b, old_large);
    if (is_large && at_large != WAVE_NO_SLOT && at_large < arrayLength(&large.items)) {
        large.items[at_large] = item;
    }
}

// Large triangles a `raster_large` workgroup takes: its first lanes set them up at once
// (the setup is a chain of dependent loads: one lane at a time left the workgroup idle),
// then the whole workgroup tests and shades their blocks together.
const GPU_LAYDOWN_LARGE_BATCH: u32 = 16u;

// The large list's count as `raster_large`'s indirect arguments.
@compute @workgroup_size(1)
fn large_args() {
    let n = min(atomicLoad(&large.count), arrayLength(&large.items));
    let groups = (n + GPU_LAYDOWN_LARGE_BATCH - 1u) / GPU_LAYDOWN_LARGE_BATCH;
    large.dispatch[0] = min(groups, GPU_LAYDOWN_ROWS);
    large.dispatch[1] = (groups + GPU_LAYDOWN_ROWS - 1u) / GPU_LAYDOWN_ROWS;
    large.dispatch[2] = 1u;
}

// The large triangles of a `raster_large` workgroup, set up by its first lanes (their edge
// functions below).
var<workgroup> gpu_large_triangles: array<GpuRasterTriangle, GPU_LAYDOWN_LARGE_BATCH>;

// A large triangle's edge functions over its box: at the box's first pixel centre, their
// steps per pixel right and down, and the least value inside (1 where the top-left rule
// puts samples on the edge outside, else 0). Each of the three is linear in the pixel.
struct GpuLargeEdges {
    at_origin: vec3<i64>,
    step_x: vec3<i64>,
    step_y: vec3<i64>,
    least: vec3<i64>,
    // The steps in 32 bits when a block's worth of each fits (steps32: 1): a pixel's
    // offset from its block's first pixel then takes i32 products instead of i64 ones
    // (the i64 ones cost the large pass 0.07-0.9 ms of 0.9-19 ms at 4K on the H200).
    step_x32: vec3<i32>,
    step_y32: vec3<i32>,
    steps32: u32,
}

var<workgroup> gpu_large_edges: array<GpuLargeEdges, GPU_LAYDOWN_LARGE_BATCH>;

// Side (pixels) of the square blocks `raster_large` tests a whole at a time.
const GPU_LAYDOWN_BLOCK: u32 = 8u;
// Pixels of a block; the workgroup shades GPU_LAYDOWN_LARGE_WORKGROUP / this blocks at once.
const GPU_LAYDOWN_BLOCK_PIXELS: u32 = 64u;

// The blocks of this round that may hold a pixel of their triangle: their index in its box
// (row-major), and their edge functions at their first pixel. About 16 000 bytes of
// workgroup memory in all, under wgpu's default 16 KiB (shadercheck checks).
var<workgroup> gpu_large_blocks: array<u32, GPU_LAYDOWN_LARGE_WORKGROUP>;
var<workgroup> gpu_large_block_edges: array<vec3<i64>, GPU_LAYDOWN_LARGE_WORKGROUP>;
var<workgroup> gpu_large_block_count: atomic<u32>;
var<workgroup> gpu_large_round_blocks: u32;

// The largest edge component (subpixels) whose steps a whole block adds up in i32.
const GPU_LAYDOWN_STEPS32_LIMIT: i32 = 2147483647 / (256 * 2 * i32(GPU_LAYDOWN_BLOCK - 1u)) + 1;

fn gpu_large_edges_of(r: GpuRasterTriangle) -> GpuLargeEdges {
    var g: GpuLargeEdges;
    let p = vec2<i32>((r.x0 - r.corner.x) * 256 + 128, (r.y0 - r.corner.y) * 256 + 128);
    let e0 = r.c - r.b;
    let e1 = r.a - r.c;
    let e2 = r.b - r.a;
    g.at_origin = vec3<i64>(gpu_cross64(e0, p - r.b), gpu_cross64(e1, p - r.c), gpu_cross64(e2, p - r.a));
    // E = e.x (p.y - v.y) - e.y (p.x - v.x): a pixel (256 subpixels) right adds -256 e.y.
    g.step_x = vec3<i64>(i64(-e0.y), i64(-e1.y), i64(-e2.y)) * 256li;
    g.step_y = vec3<i64>(i64(e0.x), i64(e1.x), i64(e2.x)) * 256li;
    g.least = -vec3<i64>(gpu_top_left_bias64(e0), gpu_top_left_bias64(e1), gpu_top_left_bias64(e2));
    // A pixel's offset, |step_x| dx + |step_y| dy with dx, dy < GPU_LAYDOWN_BLOCK, below
    // 2^31: |e| * 256 * 2 (GPU_LAYDOWN_BLOCK - 1) < 2^31.
    let most = max(max(abs(e0), abs(e1)), abs(e2));
    g.steps32 = u32(max(most.x, most.y) < GPU_LAYDOWN_STEPS32_LIMIT);
    if (g.steps32 == 1u) {
        g.step_x32 = vec3<i32>(-e0.y, -e1.y, -e2.y) * 256;
        g.step_y32 = vec3<i32>(e0.x, e1.x, e2.x) * 256;
    }
    return g;
}

// The blocks of the workgroup's triangles before each one (exclusive prefix, the last
// entry the total), and each triangle's blocks per row.
var<workgroup> gpu_large_first_block: array<u32, GPU_LAYDOWN_LARGE_BATCH + 1u>;
var<workgroup> gpu_large_row_blocks: array<u32, GPU_LAYDOWN_LARGE_BATCH>;
// Which triangle of the batch each kept block belongs to.
var<workgroup> gpu_large_block_triangle: array<u32, GPU_LAYDOWN_LARGE_WORKGROUP>;

// GPU_LAYDOWN_LARGE_BATCH large triangles a workgroup, their blocks taken together. A box
// is cut into 8x8 blocks; each round, one lane per block (of any of the triangles)
// rejects the blocks some edge leaves entirely outside (edge functions at the block's
// corners, in 64 bits), then the workgroup shades the pixels of the blocks kept, 64 lanes
// a block, each pixel's edge functions a few adds from its block's. Thin and slanted
// cards fill a small part of their box, and a pixel costs adds, not products; taking the
// triangles together keeps the lanes busy when boxes hold few blocks.
@compute @workgroup_size(GPU_LAYDOWN_LARGE_WORKGROUP)
fn raster_large(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) li: u32) {
    if (li < GPU_LAYDOWN_LARGE_BATCH) {
        // Strided over the list: neighbours in it (the same mesh, often alike in size)
        // go to different workgroups, so no workgroup gets a run of the biggest.
        let n = min(atomicLoad(&large.count), arrayLength(&large.items));
        let groups = (n + GPU_LAYDOWN_LARGE_BATCH - 1u) / GPU_LAYDOWN_LARGE_BATCH;
        let k = wid.y * GPU_LAYDOWN_ROWS + wid.x + li * groups;
        var r: GpuRasterTriangle;
        r.kind = GPU_RASTER_NONE;
        if (k < n) {
            r = gpu_raster_setup(large.items[k]);
        }
        gpu_large_triangles[li] = r;
        var bw = 0u;
        var blocks = 0u;
        if (r.kind == GPU_RASTER_LARGE || r.kind == GPU_RASTER_SMALL) {
            gpu_large_edges[li] = gpu_large_edges_of(r);
            let nx = u32(max(r.x1 - r.x0 + 1, 0));
            let ny = u32(max(r.y1 - r.y0 + 1, 0));
            bw = (nx + GPU_LAYDOWN_BLOCK - 1u) / GPU_LAYDOWN_BLOCK;
            blocks = bw * ((ny + GPU_LAYDOWN_BLOCK - 1u) / GPU_LAYDOWN_BLOCK);
        }
        gpu_large_row_blocks[li] = bw;
        gpu_large_first_block[li + 1u] = blocks;
    }
    workgroupBarrier();
    if (li == 0u) {
        atomicStore(&gpu_large_block_count, 0u);
        gpu_large_first_block[0] = 0u;
        for (var t = 1u; t <= GPU_LAYDOWN_LARGE_BATCH; t++) {
            gpu_large_first_block[t] += gpu_large_first_block[t - 1u];
        }
    }
    let total = workgroupUniformLoad(&gpu_large_first_block[GPU_LAYDOWN_LARGE_BATCH]);
    let w = i32(frame.viewport.x);
    // This lane's pixel in the blocks it shades.
    let px = li % GPU_LAYDOWN_BLOCK_PIXELS;
    let dx = px % GPU_LAYDOWN_BLOCK;
    let dy = px / GPU_LAYDOWN_BLOCK;
    let lanes_per_block = GPU_LAYDOWN_LARGE_WORKGROUP / GPU_LAYDOWN_BLOCK_PIXELS;
    for (var first = 0u; first < total; first += GPU_LAYDOWN_LARGE_WORKGROUP) {
        let b = first + li;
        if (b < total) {
            var t = 0u;
            while (t + 1u < GPU_LAYDOWN_LARGE_BATCH && gpu_large_first_block[t + 1u] <= b) {
                t++;
            }
            let g = gpu_large_edges[t];
            let local = b - gpu_large_first_block[t];
            let bw = gpu_large_row_blocks[t];
            let e = g.at_origin + g.step_x * i64((local % bw) * GPU_LAYDOWN_BLOCK)
                + g.step_y * i64((local / bw) * GPU_LAYDOWN_BLOCK);
            // Over a block, an edge function ranges from its first pixel's value plus the
            // negative steps to it plus the positive ones (7 pixels each way).
            let span = i64(GPU_LAYDOWN_BLOCK - 1u);
            let high = max(g.step_x * span, vec3<i64>(0li)) + max(g.step_y * span, vec3<i64>(0li));
            if (all(e + high >= g.least)) {
                let slot = atomicAdd(&gpu_large_block_count, 1u);
                gpu_large_blocks[slot] = local;
                gpu_large_block_triangle[slot] = t;
                gpu_large_block_edges[slot] = e;
            }
        }
        workgroupBarrier();
        if (li == 0u) {
            gpu_large_round_blocks = atomicLoad(&gpu_large_block_count);
            atomicStore(&gpu_large_block_count, 0u);
        }
        let kept = workgroupUniformLoad(&gpu_large_round_blocks);
        for (var s = li / GPU_LAYDOWN_BLOCK_PIXELS; s < kept; s += lanes_per_block) {
            let t = gpu_large_block_triangle[s];
            let local = gpu_large_blocks[s];
            let bw = gpu_large_row_blocks[t];
            let x0 = gpu_large_triangles[t].x0;
            let y0 = gpu_large_triangles[t].y0;
            let x = x0 + i32((local % bw) * GPU_LAYDOWN_BLOCK + dx);
            let y = y0 + i32((local / bw) * GPU_LAYDOWN_BLOCK + dy);
            var e = gpu_large_block_edges[s];
            if (gpu_large_edges[t].steps32 == 1u) {
                let o = gpu_large_edges[t].step_x32 * i32(dx) + gpu_large_edges[t].step_y32 * i32(dy);
                e += vec3<i64>(o);
            } else {
                e += gpu_large_edges[t].step_x * i64(dx) + gpu_large_edges[t].step_y * i64(dy);
            }
            if (x <= gpu_large_triangles[t].x1 && y <= gpu_large_triangles[t].y1
                && all(e >= gpu_large_edges[t].least)) {
                gpu_raster_shade(x, y, vec3<f32>(e) * gpu_large_triangles[t].inv_area,
                    gpu_large_triangles[t].shade, w);
            }
        }
        workgroupBarrier();
    }
}
