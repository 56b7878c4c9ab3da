// gpu::tile_range: the light tiles' depth ranges as a workgroup reduces them (twin of
// deferred::lights `tile_depth_ranges`), shared by the lights' pass 1 (gpu::tile_depth)
// and the compute laydown's unpack. A workgroup covers 2x2 tiles (tile k of its block at
// (k % 2, k / 2)) and folds its pixels into them through workgroup atomics on
// order-preserving words (so any float orders as on the CPU); pixels at the far plane's
// depth and NaN are skipped. Both words are maxima (reversed Z: nearest is the largest
// depth, farthest the smallest, kept complemented; standard depth the other way round), so
// a skipped pixel contributes 0.

#import deferred::lights
#import wave::common

var<workgroup> gpu_tile_near: array<atomic<u32>, 4>;
var<workgroup> gpu_tile_far: array<atomic<u32>, 4>;

// Empties the block's four ranges (nearest at the far plane, farthest at the near one):
// call with the local invocation index, a barrier before the first fold.
fn gpu_tile_range_begin(li: u32, reversed: bool) {
    if (li < 4u) {
        let far = select(1.0, 0.0, reversed);
        let near = select(0.0, 1.0, reversed);
        atomicStore(&gpu_tile_near[li], select(~wave_ordered_f32(far), wave_ordered_f32(far), reversed));
        atomicStore(&gpu_tile_far[li], select(wave_ordered_f32(near), ~wave_ordered_f32(near), reversed));
    }
}

// The (nearest, farthest) words of depth `d`: 0 at the far plane or NaN.
fn gpu_tile_range_words(d: f32, reversed: bool) -> vec2<u32> {
    let nan = (bitcast<u32>(d) & 0x7fffffffu) > 0x7f800000u;
    if (d == select(1.0, 0.0, reversed) || nan) {
        return vec2<u32>(0u);
    }
    let o = wave_ordered_f32(d);
    return vec2<u32>(select(~o, o, reversed), select(o, ~o, reversed));
}

// Folds words (gpu_tile_range_words, or their max over samples) into tile k of the block.
fn gpu_tile_range_fold(k: u32, words: vec2<u32>) {
    if (words.x != 0u) {
        atomicMax(&gpu_tile_near[k], words.x);
        atomicMax(&gpu_tile_far[k], words.y);
    }
}

// Tiles across and down an image of `size` pixels (deferred::lights::tile_counts).
fn gpu_tile_range_tiles(size: vec2<u32>) -> vec2<u32> {
    return (size + vec2<u32>(DEFERRED_TILE_SIZE - 1u)) / DEFERRED_TILE_SIZE;
}

// Row-major index of tile k of workgroup `wid`'s block among `tiles`, or GPU_TILE_RANGE_NONE
// outside them.
const GPU_TILE_RANGE_NONE: u32 = 0xffffffffu;
fn gpu_tile_range_index(k: u32, wid: vec2<u32>, tiles: vec2<u32>) -> u32 {
    let xy = wid * 2u + vec2<u32>(k % 2u, k / 2u);
    if (any(xy >= tiles)) {
        return GPU_TILE_RANGE_NONE;
    }
    return xy.y * tiles.x + xy.x;
}

// Tile k's range, after every fold of the block (a barrier between).
fn gpu_tile_range(k: u32, reversed: bool) -> DeferredTileDepth {
    let n = atomicLoad(&gpu_tile_near[k]);
    let f = atomicLoad(&gpu_tile_far[k]);
    return DeferredTileDepth(
        wave_unordered_f32(select(~n, n, reversed)),
        wave_unordered_f32(select(f, ~f, reversed)),
    );
}
