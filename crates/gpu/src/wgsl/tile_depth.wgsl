// gpu::tile_depth: pass 1 of tiled light culling (twin of deferred::lights
// `tile_depth_ranges`) over the depth target. One workgroup of 256 per
// DEFERRED_TILE_SIZE^2 tile: each invocation loads its pixel's depth and folds it into the
// tile's nearest and farthest through workgroup atomics on order-preserving words (so any
// float orders as on the CPU); pixels at the far plane's depth and NaN are skipped. Both
// words are maxima (the minimum's complemented), so a skipped pixel contributes 0. (A
// subgroup reduction before the atomics changed nothing on the H200: 80 vs 78 us at 4K.)
// With feature `msaa` the depth is the baseline's multisampled one: every sample counts.

#import deferred::lights
#import wave::common

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

// The tile's nearest and farthest so far, as order-preserving words.
var<workgroup> gpu_tile_near: atomic<u32>;
var<workgroup> gpu_tile_far: atomic<u32>;

// 256 invocations in one dimension: invocation i reads pixel
// (i % 16, i / 16) of the workgroup's tile.
@compute @workgroup_size(256)
fn tile_depth(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) li: u32) {
    let pixel = wid.xy * DEFERRED_TILE_SIZE + vec2<u32>(li % DEFERRED_TILE_SIZE, li / DEFERRED_TILE_SIZE);
    let reversed = params.reversed != 0u;
    let far = select(1.0, 0.0, reversed);
    let empty = DeferredTileDepth(far, select(0.0, 1.0, reversed));
    if (li == 0u) {
        // Reversed: nearest is a maximum (from far = 0), farthest a minimum (from 1).
        // Standard: the other way round. Kept as maximum words: minima complemented.
        atomicStore(&gpu_tile_near, select(~wave_ordered_f32(empty.nearest), wave_ordered_f32(empty.nearest), reversed));
        atomicStore(&gpu_tile_far, select(wave_ordered_f32(empty.farthest), ~wave_ordered_f32(empty.farthest), reversed));
    }
    workgroupBarrier();
    let size = min(params.size, vec2<u32>(textureDimensions(depth_texture)));
    var near_word = 0u;
    var far_word = 0u;
    if (all(pixel < size)) {
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
            let nan = (bitcast<u32>(d) & 0x7fffffffu) > 0x7f800000u;
            if (d != far && !nan) {
                let o = wave_ordered_f32(d);
                near_word = max(near_word, select(~o, o, reversed));
                far_word = max(far_word, select(o, ~o, reversed));
            }
        }
    }
    if (near_word != 0u) {
        atomicMax(&gpu_tile_near, near_word);
        atomicMax(&gpu_tile_far, far_word);
    }
    workgroupBarrier();
    let tile = wid.y * params.tiles_x + wid.x;
    if (li == 0u && wid.x < params.tiles_x && tile < arrayLength(&tile_depths)) {
        let n = atomicLoad(&gpu_tile_near);
        let f = atomicLoad(&gpu_tile_far);
        tile_depths[tile] = DeferredTileDepth(
            wave_unordered_f32(select(~n, n, reversed)),
            wave_unordered_f32(select(f, ~f, reversed)),
        );
    }
}
