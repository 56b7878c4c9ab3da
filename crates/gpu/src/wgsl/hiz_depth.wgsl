// gpu::hiz_depth: staticscene's HiZ pyramid (layout: staticscene pass::hiz_header, written
// by the CPU when the size changes) built four levels per dispatch. Each 8x8 workgroup
// owns a 16x16 block of its source level: every invocation reduces a 2x2 quad into level
// base + 1, then the workgroup reduces its block through workgroup memory into base + 2,
// + 3 and + 4 (8x8 -> 4x4 -> 2x2 -> 1x1). The source is the depth target (base 0, whose
// texels are also copied into level 0) or, with feature `from_buffer`, level `step.level`
// of the pyramid itself. A texel is the farthest of the up to 2x2 texels under it that lie
// inside their level (HiZ::build's ceil-halved levels keep an odd edge's last row and
// column): equal to the CPU's texel for texel. Header words: 0 the level count,
// 4 + 4k / 5 + 4k / 6 + 4k level k's width, height and first texel word.

#import staticscene::query

struct GpuHizDepthStep {
    // The source level: 0 for the depth target, else a level of the pyramid.
    level: u32,
    // Non-zero for reversed depth (levels keep the minimum).
    reversed: u32,
    pad: vec2<u32>,
}

@group(0) @binding(0) var<uniform> step: GpuHizDepthStep;
// Read only without `from_buffer` (bound either way: one layout for both variants).
@group(0) @binding(1) var depth: texture_depth_2d;
@group(0) @binding(2) var<storage, read_write> hiz: array<u32>;

// Levels one dispatch reduces.
const GPU_HIZ_DEPTH_LEVELS_PER_DISPATCH: u32 = 4u;

// The block's levels base + 1 to base + 4 (8x8, 4x4, 2x2, 1x1 texels) one after the other.
var<workgroup> gpu_hiz_scratch: array<f32, 85>;

// Stands for a texel outside its level: never the farthest.
fn gpu_hiz_none() -> f32 {
    return select(-3.0e38, 3.0e38, step.reversed != 0u);
}

fn gpu_hiz_farthest(a: f32, b: f32) -> f32 {
    return select(max(a, b), min(a, b), step.reversed != 0u);
}

// Whether texel (x, y) lies inside `level` (a level past the count has no texels).
fn gpu_hiz_inside(level: u32, x: u32, y: u32) -> bool {
    return level < min(hiz[0], STATICSCENE_HIZ_MAX_LEVELS) && x < hiz[4u + 4u * level] && y < hiz[5u + 4u * level];
}

// Writes texel (x, y) of `level` when the buffer has that level and the texel lies inside.
fn gpu_hiz_store(level: u32, x: u32, y: u32, v: f32) {
    if (!gpu_hiz_inside(level, x, y)) {
        return;
    }
    let at = hiz[6u + 4u * level] + y * hiz[4u + 4u * level] + x;
    if (at < arrayLength(&hiz)) {
        hiz[at] = bitcast<u32>(v);
    }
}

// Texel p of the source level, or none outside it.
fn gpu_hiz_source(p: vec2<u32>) -> f32 {
    let level = step.level;
    if (!gpu_hiz_inside(level, p.x, p.y)) {
        return gpu_hiz_none();
    }
#if from_buffer
    let at = hiz[6u + 4u * level] + p.y * hiz[4u + 4u * level] + p.x;
    return bitcast<f32>(hiz[min(at, arrayLength(&hiz) - 1u)]);
#else
    let size = textureDimensions(depth);
    if (p.x >= size.x || p.y >= size.y) {
        return gpu_hiz_none();
    }
    let d = textureLoad(depth, vec2<i32>(p), 0);
    gpu_hiz_store(0u, p.x, p.y, d);
    return d;
#endif
}

@compute @workgroup_size(8, 8)
fn reduce_hiz(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
) {
    let base = step.level;
    // Level base + 1: this invocation's 2x2 quad of the source.
    let q = wid.xy * 8u + lid.xy;
    var v1 = gpu_hiz_none();
    for (var j = 0u; j < 2u; j++) {
        for (var i = 0u; i < 2u; i++) {
            v1 = gpu_hiz_farthest(v1, gpu_hiz_source(q * 2u + vec2<u32>(i, j)));
        }
    }
    gpu_hiz_store(base + 1u, q.x, q.y, v1);
    gpu_hiz_scratch[lid.y * 8u + lid.x] = v1;
    // Levels base + 2, + 3, + 4 of the block: 4x4, 2x2, 1x1 texels, each from the 2x2
    // under it in the scratch (levels at words 0, 64, 80, 84).
    let at = array<u32, 4>(0u, 64u, 80u, 84u);
    for (var k = 1u; k < GPU_HIZ_DEPTH_LEVELS_PER_DISPATCH; k++) {
        workgroupBarrier();
        let side = 8u >> k;
        if (lid.x < side && lid.y < side) {
            var v = gpu_hiz_none();
            for (var j = 0u; j < 2u; j++) {
                for (var i = 0u; i < 2u; i++) {
                    v = gpu_hiz_farthest(v, gpu_hiz_scratch[at[k - 1u] + (lid.y * 2u + j) * side * 2u + lid.x * 2u + i]);
                }
            }
            gpu_hiz_store(base + 1u + k, wid.x * side + lid.x, wid.y * side + lid.y, v);
            gpu_hiz_scratch[at[k] + lid.y * side + lid.x] = v;
        }
    }
}
