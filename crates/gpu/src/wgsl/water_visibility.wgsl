// gpu: FC5's water visibility (seed 003: "the first stage is always visibility"). Near
// water bodies are drawn per body: `near_bodies` tests each body's box against the water
// view's frustum, the near radius and the HiZ of this frame's opaque depth, and writes the
// body's indexed indirect draw (instance count 1 or 0; the talk's conditional rendering of
// each mesh instance, with the HiZ standing in for the occlusion query). Far water is one
// draw: `far_sectors`, one workgroup, walks the quadtree of water sectors breadth first
// (each level's nodes tested, the children of those that pass listed for the next) and
// appends the visible leaves to the far sector list, counting them into the far draws'
// indirect arguments (one draw of flat sectors, a quad each, and one of height-map
// sectors, a grid each: the talk's two cases). A node is far water where it holds ocean (at any distance) or water
// beyond the near radius.
//
// The HiZ (staticscene's layout, reversed depth: each texel the farthest depth under it)
// is the camera's; the water view is wider, so a box reaching outside the camera's image
// is never occluded (its margin may show).

#import gpu::frame
#import gpu::water_frame
#import staticscene::query

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var<uniform> water: GpuWaterFrame;
@group(0) @binding(2) var<storage, read> bodies: array<GpuWaterBody>;
// Per body, wgpu's DrawIndexedIndirectArgs (5 words).
@group(0) @binding(3) var<storage, read_write> near_args: array<u32>;
@group(0) @binding(4) var<storage, read> nodes: array<GpuWaterNode>;
// The breadth-first lists: two halves of `sectors^2` node codes (i | j << 16).
@group(0) @binding(5) var<storage, read_write> lists: array<u32>;
// The visible leaves (j * sectors + i), the far draws' instances: flat sectors from the
// front, height-map sectors from the middle (two halves of `sectors^2`).
@group(0) @binding(6) var<storage, read_write> far_list: array<u32>;
// wgpu's DrawIndirectArgs of the two far draws (flat, height map; 4 words each).
@group(0) @binding(7) var<storage, read_write> far_args: array<atomic<u32>>;
@group(0) @binding(8) var<storage, read> hiz: array<u32>;
// GPU_WATER_STAT_*.
@group(0) @binding(9) var<storage, read_write> stats: array<atomic<u32>>;

// Rust: passes::water::STAT_*.
const GPU_WATER_STAT_NEAR: u32 = 0u;
const GPU_WATER_STAT_FAR: u32 = 1u;
const GPU_WATER_STAT_NODES: u32 = 2u;
// Invocations of `far_sectors`' one workgroup.
const GPU_WATER_FAR_GROUP: u32 = 256u;

// Level `level`'s texel (x, y), clamped into the level and the buffer.
fn gpu_water_hiz_texel(level: u32, x: u32, y: u32) -> f32 {
    let w = max(hiz[4u + 4u * level], 1u);
    let h = max(hiz[5u + 4u * level], 1u);
    let at = hiz[6u + 4u * level] + min(y, h - 1u) * w + min(x, w - 1u);
    return bitcast<f32>(hiz[min(at, arrayLength(&hiz) - 1u)]);
}

// Whether the camera-relative box [lo, hi] lies behind the opaque depth everywhere it
// covers on the camera's image (false when it reaches outside the image, crosses the near
// plane, or there is no HiZ).
fn gpu_water_occluded(lo: vec3<f32>, hi: vec3<f32>) -> bool {
    if (arrayLength(&hiz) < STATICSCENE_HIZ_HEADER_WORDS) {
        return false;
    }
    let levels = min(hiz[0], STATICSCENE_HIZ_MAX_LEVELS);
    if (levels == 0u) {
        return false;
    }
    var rmin = vec2<f32>(3.0e38);
    var rmax = vec2<f32>(-3.0e38);
    var zmax = 0.0;
    for (var c = 0u; c < 8u; c++) {
        let corner = vec3<f32>(
            select(lo.x, hi.x, (c & 1u) != 0u),
            select(lo.y, hi.y, (c & 2u) != 0u),
            select(lo.z, hi.z, (c & 4u) != 0u),
        );
        let clip = frame.view_proj * vec4<f32>(corner, 1.0);
        if (!(clip.w > water.camera.w * 0.5)) {
            return false;
        }
        let ndc = clip.xyz / clip.w;
        let px = (ndc.xy * vec2<f32>(0.5, -0.5) + 0.5) * frame.viewport.xy;
        rmin = min(rmin, px);
        rmax = max(rmax, px);
        zmax = max(zmax, ndc.z);
    }
    // The part on the camera's image: a box wholly in the water view's margin is kept
    // (no depth there); one reaching into the margin is tested by its part on the image
    // (a margin holds only what displacement could pull a few pixels in, behind the same
    // occluders).
    let size = frame.viewport.xy;
    if (any(rmax <= vec2<f32>(0.0)) || any(rmin >= size)) {
        return false;
    }
    rmin = clamp(rmin, vec2<f32>(0.0), size - 1.0);
    rmax = clamp(rmax, vec2<f32>(0.0), size - 1.0);
    let extent = max(rmax.x - rmin.x, rmax.y - rmin.y);
    // At this level the box spans at most two texels a side (three with an odd start).
    let level = u32(clamp(ceil(log2(max(extent, 1.0))), 0.0, f32(levels - 1u)));
    let scale = 1.0 / f32(1u << level);
    let t0 = vec2<u32>(rmin * scale);
    let t1 = vec2<u32>(rmax * scale);
    var farthest = 3.0e38;
    for (var y = t0.y; y <= min(t1.y, t0.y + 3u); y++) {
        for (var x = t0.x; x <= min(t1.x, t0.x + 3u); x++) {
            farthest = min(farthest, gpu_water_hiz_texel(level, x, y));
        }
    }
    // Reversed depth: the box's nearest point is farther than the farthest opaque depth.
    return zmax < farthest;
}

// Whether the camera-relative box [lo, hi] is outside the water view's frustum.
fn gpu_water_outside(lo: vec3<f32>, hi: vec3<f32>) -> bool {
    for (var i = 0u; i < 6u; i++) {
        let p = water.planes[i];
        let far_corner = select(lo, hi, p.xyz >= vec3<f32>(0.0));
        if (dot(p.xyz, far_corner) + p.w < 0.0) {
            return true;
        }
    }
    return false;
}

// Nearest and farthest distance from the camera (the origin) to the box [lo, hi].
fn gpu_water_box_distance(lo: vec3<f32>, hi: vec3<f32>) -> vec2<f32> {
    let near = max(max(lo, -hi), vec3<f32>(0.0));
    let far = max(abs(lo), abs(hi));
    return vec2<f32>(length(near), length(far));
}

@compute @workgroup_size(64)
fn near_bodies(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.y * MAX_WORKGROUPS_X_ITEMS + gid.x;
    let count = min(min(water.grid.w, arrayLength(&bodies)), arrayLength(&near_args) / 5u);
    if (i >= count) {
        return;
    }
    let b = bodies[i];
    // Displaced water rises above the body's box by at most this.
    let margin = vec3<f32>(water.shore.w);
    let lo = b.min.xyz - water.camera.xyz - margin;
    let hi = b.max.xyz - water.camera.xyz + margin;
    var visible = b.index_count > 0u;
    if (gpu_water_box_distance(lo, hi).x >= water.sectors.w) {
        visible = false;
    }
    if (visible && gpu_water_outside(lo, hi)) {
        visible = false;
    }
    if (visible && gpu_water_occluded(lo, hi)) {
        visible = false;
    }
    near_args[5u * i] = b.index_count;
    near_args[5u * i + 1u] = select(0u, 1u, visible);
    near_args[5u * i + 2u] = b.first_index;
    near_args[5u * i + 3u] = 0u;
    near_args[5u * i + 4u] = 0u;
    if (visible) {
        atomicAdd(&stats[GPU_WATER_STAT_NEAR], 1u);
    }
}

// Rust: shader::MAX_WORKGROUPS_X times the workgroup size: `Dispatch::Items` rows.
const MAX_WORKGROUPS_X_ITEMS: u32 = 4194240u;

var<workgroup> gpu_water_in_count: u32;
var<workgroup> gpu_water_out_count: atomic<u32>;

// Node (level, i, j) of the level-major quadtree: levels before `level` hold
// (4^level - 1) / 3 nodes.
fn gpu_water_node_index(level: u32, i: u32, j: u32) -> u32 {
    return ((1u << (2u * level)) - 1u) / 3u + j * (1u << level) + i;
}

@compute @workgroup_size(256)
fn far_sectors(@builtin(local_invocation_index) li: u32) {
    let side = water.far.x;
    let levels = min(water.far.y, 7u);
    let cap = min(side * side, arrayLength(&lists) / 2u);
    if (li == 0u) {
        lists[0] = 0u;
        gpu_water_in_count = select(0u, 1u, levels > 0u && cap > 0u);
        atomicStore(&gpu_water_out_count, 0u);
    }
    storageBarrier();
    workgroupBarrier();
    let quads = water.far.z;
    for (var level = 0u; level < levels; level++) {
        let n = workgroupUniformLoad(&gpu_water_in_count);
        let src = (level & 1u) * cap;
        let dst = ((level + 1u) & 1u) * cap;
        let leaf = level + 1u == levels;
        for (var k = li; k < n; k += GPU_WATER_FAR_GROUP) {
            let code = lists[min(src + k, arrayLength(&lists) - 1u)];
            let i = code & 0xffffu;
            let j = code >> 16u;
            let at = gpu_water_node_index(level, i, j);
            if (at >= arrayLength(&nodes)) {
                continue;
            }
            atomicAdd(&stats[GPU_WATER_STAT_NODES], 1u);
            let node = nodes[at];
            let flags = bitcast<u32>(node.min.w);
            if ((flags & GPU_WATER_NODE_WATER) == 0u) {
                continue;
            }
            let margin = vec3<f32>(water.shore.w);
            let lo = node.min.xyz - water.camera.xyz - margin;
            let hi = node.max.xyz - water.camera.xyz + margin;
            // Lakes and rivers wholly within the near radius are the near draws'.
            if ((flags & GPU_WATER_NODE_OCEAN) == 0u && gpu_water_box_distance(lo, hi).y < water.sectors.w) {
                continue;
            }
            if (gpu_water_outside(lo, hi) || gpu_water_occluded(lo, hi)) {
                continue;
            }
            if (leaf) {
                // The talk's two cases: flat water, and height-map water.
                let flat = (flags & GPU_WATER_NODE_FLAT) != 0u;
                let args = select(5u, 1u, flat);
                let slot = atomicAdd(&far_args[args], 1u);
                let half = arrayLength(&far_list) / 2u;
                if (slot < half) {
                    far_list[select(half, 0u, flat) + slot] = j * side + i;
                }
            } else {
                let base = atomicAdd(&gpu_water_out_count, 4u);
                for (var c = 0u; c < 4u; c++) {
                    let ci = 2u * i + (c & 1u);
                    let cj = 2u * j + (c >> 1u);
                    if (base + c < cap) {
                        lists[dst + base + c] = ci | (cj << 16u);
                    }
                }
            }
        }
        storageBarrier();
        workgroupBarrier();
        if (li == 0u) {
            gpu_water_in_count = min(atomicLoad(&gpu_water_out_count), cap);
            atomicStore(&gpu_water_out_count, 0u);
        }
        workgroupBarrier();
    }
    if (li == 0u) {
        // The far draws' vertex counts, and their instances clamped to the list.
        let half = arrayLength(&far_list) / 2u;
        atomicStore(&far_args[0], 6u);
        atomicStore(&far_args[4], 6u * quads * quads);
        let flat = min(atomicLoad(&far_args[1]), half);
        let height = min(atomicLoad(&far_args[5]), half);
        atomicStore(&far_args[1], flat);
        atomicStore(&far_args[5], height);
        atomicStore(&stats[GPU_WATER_STAT_FAR], flat + height);
    }
}
