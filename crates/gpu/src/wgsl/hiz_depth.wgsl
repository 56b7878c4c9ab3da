// gpu::hiz_depth: the finest levels of staticscene's HiZ buffer from the frame's depth
// target in one dispatch (the buffer's layout: staticscene pass::hiz_header, written by
// the CPU when the size changes; staticscene::hiz_pass reduces the coarser levels after).
// Each 8x8 workgroup owns a 16x16 block of depth: every invocation copies a 2x2 quad into
// level 0 and reduces it into level 1, then the workgroup reduces its block through
// workgroup memory into levels 2, 3 and 4 (8x8 -> 4x4 -> 2x2 -> 1x1). A texel is the
// farthest of the up to 2x2 texels under it that lie inside their level (HiZ::build's
// ceil-halved levels keep an odd edge's last row and column): equal to the CPU's texel for
// texel. Header words: 0 the level count, 4 + 4k / 5 + 4k / 6 + 4k level k's width,
// height and first texel word.

struct GpuHizDepthStep {
    // The first level written (always 0 here; the reduction's uniform layout).
    level: u32,
    // Non-zero for reversed depth (levels keep the minimum).
    reversed: u32,
    pad: vec2<u32>,
}

@group(0) @binding(0) var<uniform> step: GpuHizDepthStep;
@group(0) @binding(1) var depth: texture_depth_2d;
@group(0) @binding(2) var<storage, read_write> hiz: array<u32>;

// Levels this pass writes at most (0..=4).
const GPU_HIZ_DEPTH_LEVELS: u32 = 5u;

var<workgroup> gpu_hiz_l1: array<f32, 64>;
var<workgroup> gpu_hiz_l2: array<f32, 16>;
var<workgroup> gpu_hiz_l3: array<f32, 4>;

// Stands for a texel outside its level: never the farthest.
fn gpu_hiz_none() -> f32 {
    return select(-3.0e38, 3.0e38, step.reversed != 0u);
}

fn gpu_hiz_farthest(a: f32, b: f32) -> f32 {
    return select(max(a, b), min(a, b), step.reversed != 0u);
}

// Writes texel (x, y) of `level` when the buffer has that level and the texel lies inside.
fn gpu_hiz_store(level: u32, x: u32, y: u32, v: f32) {
    if (level >= min(hiz[0], GPU_HIZ_DEPTH_LEVELS)) {
        return;
    }
    let w = hiz[4u + 4u * level];
    let h = hiz[5u + 4u * level];
    if (x >= w || y >= h) {
        return;
    }
    let at = hiz[6u + 4u * level] + y * w + x;
    if (at < arrayLength(&hiz)) {
        hiz[at] = bitcast<u32>(v);
    }
}

// Whether texel (x, y) lies inside `level` (a level past the count has no texels).
fn gpu_hiz_inside(level: u32, x: u32, y: u32) -> bool {
    return level < hiz[0] && x < hiz[4u + 4u * level] && y < hiz[5u + 4u * level];
}

@compute @workgroup_size(8, 8)
fn depth_to_hiz(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
) {
    let size = textureDimensions(depth);
    // Level 0 and level 1: this invocation's 2x2 quad.
    let q = wid.xy * 8u + lid.xy;
    var v1 = gpu_hiz_none();
    for (var j = 0u; j < 2u; j++) {
        for (var i = 0u; i < 2u; i++) {
            let p = q * 2u + vec2<u32>(i, j);
            if (gpu_hiz_inside(0u, p.x, p.y) && p.x < size.x && p.y < size.y) {
                let d = textureLoad(depth, vec2<i32>(p), 0);
                gpu_hiz_store(0u, p.x, p.y, d);
                v1 = gpu_hiz_farthest(v1, d);
            }
        }
    }
    gpu_hiz_store(1u, q.x, q.y, v1);
    let li = lid.y * 8u + lid.x;
    gpu_hiz_l1[li] = v1;
    workgroupBarrier();
    // Level 2: 4x4 of the block.
    if (lid.x < 4u && lid.y < 4u) {
        var v = gpu_hiz_none();
        for (var j = 0u; j < 2u; j++) {
            for (var i = 0u; i < 2u; i++) {
                v = gpu_hiz_farthest(v, gpu_hiz_l1[(lid.y * 2u + j) * 8u + lid.x * 2u + i]);
            }
        }
        gpu_hiz_store(2u, wid.x * 4u + lid.x, wid.y * 4u + lid.y, v);
        gpu_hiz_l2[lid.y * 4u + lid.x] = v;
    }
    workgroupBarrier();
    // Level 3: 2x2.
    if (lid.x < 2u && lid.y < 2u) {
        var v = gpu_hiz_none();
        for (var j = 0u; j < 2u; j++) {
            for (var i = 0u; i < 2u; i++) {
                v = gpu_hiz_farthest(v, gpu_hiz_l2[(lid.y * 2u + j) * 4u + lid.x * 2u + i]);
            }
        }
        gpu_hiz_store(3u, wid.x * 2u + lid.x, wid.y * 2u + lid.y, v);
        gpu_hiz_l3[lid.y * 2u + lid.x] = v;
    }
    workgroupBarrier();
    // Level 4: the block's one texel.
    if (li == 0u) {
        let v = gpu_hiz_farthest(
            gpu_hiz_farthest(gpu_hiz_l3[0], gpu_hiz_l3[1]),
            gpu_hiz_farthest(gpu_hiz_l3[2], gpu_hiz_l3[3]),
        );
        gpu_hiz_store(4u, wid.x, wid.y, v);
    }
}
