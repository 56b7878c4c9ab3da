// tiling: phase 1, laydown finalise (Rust twin: tiling::laydown_finalize). Bindings 0-3
// are tiling::pixel's; entry point and dispatch: `tiling::LAYDOWN_FINALIZE`.

#import tiling::pixel

// Per (tile, pass), t * P + p: bit g set when batch group g is used. Zero before the pass.
@group(0) @binding(4) var<storage, read_write> masks: array<atomic<u32>>;

// This workgroup's masks, one per pass (all its pixels lie in one tile).
var<workgroup> tiling_wg_masks: array<atomic<u32>, TILING_MAX_PASSES>;

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
    for (var k = 0u; k < 4u; k++) {
        let p = tiling_quad_pixel(gid, k);
        if (p.x < params.width && p.y < params.height) {
            let i = p.y * params.width + p.x;
#if timing_no_table
            var px = TilingPixel(select(TILING_PX_VALID, TILING_PX_EMPTY, words[k] == VISBUF_NONE), visbuf_micro_batch(words[k]) % 64u, 0u, 0u, 0u);
#else
            let px = tiling_decode(words[k], i);
#endif
            // Read first: the block's pixels set few bits, and a shared atomic per pixel on
            // the same word serialises the workgroup.
            let slot = px.pg / TILING_MAX_BATCH_GROUPS;
            let bit = 1u << (px.pg % TILING_MAX_BATCH_GROUPS);
            if (px.kind == TILING_PX_VALID && (atomicLoad(&tiling_wg_masks[slot]) & bit) == 0u) {
                atomicOr(&tiling_wg_masks[slot], bit);
            }
        }
    }
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
