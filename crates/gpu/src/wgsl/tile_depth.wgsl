// gpu::tile_depth: pass 1 of tiled light culling over the depth target: the tiles' depth
// ranges (gpu::tile_range's reduction, twin of deferred::lights `tile_depth_ranges`). One
// workgroup of DEFERRED_TILE_SIZE^2 per 2x2 tiles: each invocation loads one pixel of each
// tile (the four loads in flight at once). (A subgroup reduction before the atomics
// changed nothing on the H200: 80 vs 78 us at 4K, with a workgroup per tile and a pixel per
// invocation.) With feature `msaa` the depth is the baseline's multisampled one: every
// sample counts.

#import deferred::lights
#import gpu::tile_range

// Rust: passes::lights::GpuTileDepthParams (16 bytes).
struct GpuTileDepthParams {
    // viewport width, height in pixels
    size: vec2<u32>,
    // tiles across
    tiles_x: u32,
    // non-zero for reversed depth (far plane at 0)
    reversed: u32,
}

@group(0) @binding(0) var<uniform> params: GpuTileDepthParams;
#if msaa
@group(0) @binding(1) var depth_texture: texture_depth_multisampled_2d;
#else
// The float copy of the depth (`Targets::depth_float`).
@group(0) @binding(1) var depth_texture: texture_2d<f32>;
#endif
@group(0) @binding(2) var<storage, read_write> tile_depths: array<DeferredTileDepth>;

// The (nearest, farthest) words of pixel `pixel`, their maxima over its samples with
// `msaa`; 0 outside `size`.
fn gpu_tile_pixel(pixel: vec2<u32>, size: vec2<u32>, reversed: bool) -> vec2<u32> {
    var words = vec2<u32>(0u);
    if (any(pixel >= size)) {
        return words;
    }
#if msaa
    let samples = textureNumSamples(depth_texture);
#else
    let samples = 1u;
#endif
    for (var s = 0u; s < samples; s++) {
#if msaa
        let d = textureLoad(depth_texture, vec2<i32>(pixel), i32(s));
#else
        let d = textureLoad(depth_texture, vec2<i32>(pixel), 0).x;
#endif
        words = max(words, gpu_tile_range_words(d, reversed));
    }
    return words;
}

// Invocation (x, y) reads pixel (x, y) of each of the block's four tiles.
@compute @workgroup_size(DEFERRED_TILE_SIZE, DEFERRED_TILE_SIZE)
fn tile_depth(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
) {
    let reversed = params.reversed != 0u;
    gpu_tile_range_begin(li, reversed);
    workgroupBarrier();
    let size = min(params.size, vec2<u32>(textureDimensions(depth_texture)));
    let p = wid.xy * (2u * DEFERRED_TILE_SIZE) + lid.xy;
    let t = DEFERRED_TILE_SIZE;
    let w0 = gpu_tile_pixel(p, size, reversed);
    let w1 = gpu_tile_pixel(p + vec2<u32>(t, 0u), size, reversed);
    let w2 = gpu_tile_pixel(p + vec2<u32>(0u, t), size, reversed);
    let w3 = gpu_tile_pixel(p + vec2<u32>(t, t), size, reversed);
    gpu_tile_range_fold(0u, w0);
    gpu_tile_range_fold(1u, w1);
    gpu_tile_range_fold(2u, w2);
    gpu_tile_range_fold(3u, w3);
    workgroupBarrier();
    let tiles = vec2<u32>(params.tiles_x, gpu_tile_range_tiles(params.size).y);
    let tile = gpu_tile_range_index(li, wid.xy, tiles);
    if (li < 4u && tile < arrayLength(&tile_depths)) {
        tile_depths[tile] = gpu_tile_range(li, reversed);
    }
}
