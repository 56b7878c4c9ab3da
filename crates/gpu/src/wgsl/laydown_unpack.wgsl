// gpu: the compute laydown's 64-bit target into what the rest of the frame reads, in one
// compute pass over the pixels: the row-major vis words (classification), the vis texture
// (resolve, debug views) and the float depth (light tiles, lighting). It replaces the
// hardware frames' vis copy, and it is the classification's laydown finalise as well
// (tiling::finalize: each pixel's (pass, group) bit into its tile's masks), so no second
// pass reads the image for it. A pixel whose depth bits are 0 was never drawn: VIS_NONE
// and the far plane (0, reversed Z). The texture target is reset to 0 here, for the next
// frame (the buffer target is cleared before the raster). It also reduces the depth to the
// light tiles' depth ranges (gpu::tile_depth's twin, the lights' pass 1, which then does
// not run where nothing draws depth after the laydown): a block is 2x2 light tiles, and
// each invocation's four pixels lie one in each.
//
// Group 0 is tiling::finalize's (params, valid, table, masks) with the vis words at binding
// 1; group 1 the target, the two textures and the light tiles' depth ranges.

#import visbuf::id
#import tiling::finalize
#import gpu::tile_range

@group(0) @binding(1) var<storage, read_write> vis_words: array<u32>;

#if texture_target
@group(1) @binding(0) var laydown_target: texture_storage_2d<r64uint, atomic>;
#else
// The target as (vis word, depth bits) pairs: little-endian halves of each u64.
@group(1) @binding(0) var<storage, read> laydown_target: array<vec2<u32>>;
#endif
@group(1) @binding(1) var vis_out: texture_storage_2d<r32uint, write>;
@group(1) @binding(2) var depth_float: texture_storage_2d<r32float, write>;
// Per light tile, row-major (gpu_tile_range_tiles of the image).
@group(1) @binding(3) var<storage, read_write> tile_depths: array<DeferredTileDepth>;

// Pixel `p`'s (vis word, depth bits) from the target (the texture target reset for the next
// frame); depth bits 0 outside the image.
fn unpack_load(p: vec2<u32>, size: vec2<u32>) -> vec2<u32> {
    var t = vec2<u32>(VISBUF_NONE, 0u);
    if (any(p >= size)) {
        return t;
    }
#if texture_target
    if (all(p < textureDimensions(laydown_target))) {
        let v = textureLoad(laydown_target, p).x;
        t = vec2<u32>(u32(v & 0xfffffffflu), u32(v >> 32u));
        textureStore(laydown_target, p, vec4<u64>(0lu));
    }
#else
    let i = p.y * size.x + p.x;
    if (i < arrayLength(&laydown_target)) {
        t = laydown_target[i];
    }
#endif
    return t;
}

// Pixel `p` with target value `t` into the three outputs, and its (pass, group) key for
// laydown finalise (TILING_NONE outside the image or not valid).
fn unpack_store(p: vec2<u32>, size: vec2<u32>, t: vec2<u32>) -> u32 {
    if (any(p >= size)) {
        return TILING_NONE;
    }
    var word = VISBUF_NONE;
    var depth = 0.0;
    if (t.y != 0u) {
        word = t.x;
        depth = bitcast<f32>(t.y);
    }
    let i = p.y * size.x + p.x;
    if (i < arrayLength(&vis_words)) {
        vis_words[i] = word;
    }
    textureStore(vis_out, p, vec4<u32>(word, 0u, 0u, 0u));
    textureStore(depth_float, p, vec4<f32>(depth, 0.0, 0.0, 0.0));
    return tiling_finalize_key(p, word);
}

// A 16x16 workgroup covers a TILING_BLOCK_SIZE block of one 128x128 tile (tiling::finalize's
// rule, tiling's pixel-phase blocks), an invocation the four pixels half a block apart in x
// and y: four loads in flight (the buffer target's loads all before any store: the compiler
// may not move a load of one binding past a store to another; the texture target's reset
// store follows each load), a quarter of the workgroups, barriers and mask flushes, and
// each store instruction of a subgroup still covers whole rows of 16 neighbouring pixels
// (2x2 quads per invocation cost 1.7x the time: the texture stores).
@compute @workgroup_size(16, 16)
fn unpack(
    @builtin(local_invocation_id) lid: vec3<u32>,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
) {
    tiling_finalize_begin(li);
    gpu_tile_range_begin(li, true);
    let size = textureDimensions(depth_float);
    let half = TILING_BLOCK_SIZE / 2u;
    let p0 = TILING_BLOCK_SIZE * wid.xy + lid.xy;
    let p1 = p0 + vec2<u32>(half, 0u);
    let p2 = p0 + vec2<u32>(0u, half);
    let p3 = p0 + vec2<u32>(half, half);
    let t0 = unpack_load(p0, size);
    let t1 = unpack_load(p1, size);
    let t2 = unpack_load(p2, size);
    let t3 = unpack_load(p3, size);
    let k0 = unpack_store(p0, size, t0);
    let k1 = unpack_store(p1, size, t1);
    let k2 = unpack_store(p2, size, t2);
    let k3 = unpack_store(p3, size, t3);
    workgroupBarrier();
    tiling_finalize_mark(k0);
    tiling_finalize_mark(k1);
    tiling_finalize_mark(k2);
    tiling_finalize_mark(k3);
    gpu_tile_range_fold(0u, gpu_tile_range_words(bitcast<f32>(t0.y), true));
    gpu_tile_range_fold(1u, gpu_tile_range_words(bitcast<f32>(t1.y), true));
    gpu_tile_range_fold(2u, gpu_tile_range_words(bitcast<f32>(t2.y), true));
    gpu_tile_range_fold(3u, gpu_tile_range_words(bitcast<f32>(t3.y), true));
    workgroupBarrier();
    tiling_finalize_flush(li, tiling_block_tile(wid));
    // The light tiles' ranges (reversed Z).
    let tile = gpu_tile_range_index(li, wid.xy, gpu_tile_range_tiles(size));
    if (li < 4u && tile < arrayLength(&tile_depths)) {
        tile_depths[tile] = gpu_tile_range(li, true);
    }
}
