// gpu: the compute laydown's 64-bit target into what the rest of the frame reads, in one
// compute pass over the pixels: the row-major vis words (classification), the vis texture
// (resolve, debug views) and the float depth (light tiles, lighting). It replaces the
// hardware frames' vis copy, and it is the classification's laydown finalise as well
// (tiling::finalize: each pixel's (pass, group) bit into its tile's masks), so no second
// pass reads the image for it. A pixel whose depth bits are 0 was never drawn: VIS_NONE
// and the far plane (0, reversed Z). The texture target is reset to 0 here, for the next
// frame (the buffer target is cleared before the raster).
//
// Group 0 is tiling::finalize's (params, valid, table, masks) with the vis words at binding
// 1; group 1 the target and the two textures.

#import visbuf::id
#import tiling::finalize

@group(0) @binding(1) var<storage, read_write> vis_words: array<u32>;

#if texture_target
@group(1) @binding(0) var laydown_target: texture_storage_2d<r64uint, atomic>;
#else
// The target as (vis word, depth bits) pairs: little-endian halves of each u64.
@group(1) @binding(0) var<storage, read> laydown_target: array<vec2<u32>>;
#endif
@group(1) @binding(1) var vis_out: texture_storage_2d<r32uint, write>;
@group(1) @binding(2) var depth_float: texture_storage_2d<r32float, write>;

// A 16x16 workgroup covers 16x16 pixels of one 128x128 tile (tiling::finalize's rule).
@compute @workgroup_size(16, 16)
fn unpack(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
) {
    tiling_finalize_begin(li);
    let size = textureDimensions(depth_float);
    var key = TILING_NONE;
    if (all(id.xy < size)) {
        let i = id.y * size.x + id.x;
        var t = vec2<u32>(VISBUF_NONE, 0u);
#if texture_target
        if (all(id.xy < textureDimensions(laydown_target))) {
            let v = textureLoad(laydown_target, id.xy).x;
            t = vec2<u32>(u32(v & 0xfffffffflu), u32(v >> 32u));
            textureStore(laydown_target, id.xy, vec4<u64>(0lu));
        }
#else
        if (i < arrayLength(&laydown_target)) {
            t = laydown_target[i];
        }
#endif
        var word = VISBUF_NONE;
        var depth = 0.0;
        if (t.y != 0u) {
            word = t.x;
            depth = bitcast<f32>(t.y);
        }
        if (i < arrayLength(&vis_words)) {
            vis_words[i] = word;
        }
        textureStore(vis_out, id.xy, vec4<u32>(word, 0u, 0u, 0u));
        textureStore(depth_float, id.xy, vec4<f32>(depth, 0.0, 0.0, 0.0));
        key = tiling_finalize_key(id.xy, word);
    }
    workgroupBarrier();
    tiling_finalize_mark(key);
    workgroupBarrier();
    tiling_finalize_flush(li, (wid.y * 16u / TILING_TILE_SIZE) * params.tiles_x + wid.x * 16u / TILING_TILE_SIZE);
}
