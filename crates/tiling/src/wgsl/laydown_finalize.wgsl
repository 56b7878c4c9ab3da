// tiling: phase 1, laydown finalise (Rust twin: tiling::laydown_finalize). Bindings 0-3
// are tiling::pixel's; entry point and dispatch: `tiling::LAYDOWN_FINALIZE`.

#import tiling::pixel

// Per (tile, pass), t * P + p: bit g set when batch group g is used. Zero before the pass.
@group(0) @binding(4) var<storage, read_write> masks: array<atomic<u32>>;

// This workgroup's masks, one per pass (all its pixels lie in one tile).
var<workgroup> tiling_wg_masks: array<atomic<u32>, TILING_MAX_PASSES>;

// The (pass, group) key of pixel k of `gid`'s quad with word `word`, TILING_NONE unless
// it is valid.
fn tiling_finalize_key(gid: vec3<u32>, k: u32, word: u32) -> u32 {
    let p = tiling_quad_pixel(gid, k);
    if (p.x >= params.width || p.y >= params.height) {
        return TILING_NONE;
    }
#if timing_no_table
    if (word != VISBUF_NONE) {
        return visbuf_micro_batch(word) % 64u;
    }
    return TILING_NONE;
#else
    let px = tiling_decode(word, p.y * params.width + p.x);
    return select(TILING_NONE, px.pg, px.kind == TILING_PX_VALID);
#endif
}

// Sets key `key`'s bit in the workgroup's masks, reading first: the block's pixels set few
// bits, and a shared atomic per pixel on the same word serialises the workgroup.
fn tiling_finalize_mark(key: u32) {
    if (key == TILING_NONE) {
        return;
    }
    let slot = key / TILING_MAX_BATCH_GROUPS;
    let bit = 1u << (key % TILING_MAX_BATCH_GROUPS);
    if ((atomicLoad(&tiling_wg_masks[slot]) & bit) == 0u) {
        atomicOr(&tiling_wg_masks[slot], bit);
    }
}

@compute @workgroup_size(16, 16)
fn laydown_finalize(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
) {
    atomicStore(&tiling_wg_masks[li], 0u);
    let words = tiling_quad_words(gid);
    workgroupBarrier();
#if timing_load_only
    atomicOr(&tiling_wg_masks[0], (words.x ^ words.y ^ words.z ^ words.w) & 1u);
#else
    // The quad decoded first, then the atomics (which would order the next table read).
    let keys = vec4<u32>(
        tiling_finalize_key(gid, 0u, words.x),
        tiling_finalize_key(gid, 1u, words.y),
        tiling_finalize_key(gid, 2u, words.z),
        tiling_finalize_key(gid, 3u, words.w),
    );
    tiling_finalize_mark(keys.x);
    tiling_finalize_mark(keys.y);
    tiling_finalize_mark(keys.z);
    tiling_finalize_mark(keys.w);
#endif
    workgroupBarrier();
    let tile = tiling_block_tile(wid);
    if (li < params.pass_count) {
        let m = atomicLoad(&tiling_wg_masks[li]);
        let e = tile * params.pass_count + li;
        if (m != 0u && e < arrayLength(&masks)) {
            atomicOr(&masks[e], m);
        }
    }
}
