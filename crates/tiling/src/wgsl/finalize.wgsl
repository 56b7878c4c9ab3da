// tiling: laydown finalise's per-pixel part (Rust twin: tiling::laydown_finalize): each
// pixel's (pass, group) bit in its workgroup's masks, flushed into the (tile, pass) masks
// with one atomic per pass that has bits. Binding 4; tiling::decode's 0, 2 and 3. The
// workgroup's pixels must lie in one tile. Used by laydown_finalize (over the vis words)
// and by gpu's compute laydown unpack (over the words it unpacks: no second pass over the
// image).

#import tiling::decode

// Per (tile, pass), t * P + p: bit g set when batch group g is used. Zero before the pass.
@group(0) @binding(4) var<storage, read_write> masks: array<atomic<u32>>;

// This workgroup's masks, one per pass (all its pixels lie in one tile).
var<workgroup> tiling_wg_masks: array<atomic<u32>, TILING_MAX_PASSES>;

// Zeroes the workgroup's masks: call from uniform control flow with the local invocation
// index of a workgroup of at least TILING_MAX_PASSES invocations, a barrier after it.
fn tiling_finalize_begin(li: u32) {
    if (li < TILING_MAX_PASSES) {
        atomicStore(&tiling_wg_masks[li], 0u);
    }
}

// The (pass, group) key of pixel `p` holding `word`, TILING_NONE unless the pixel is
// inside the image and valid.
fn tiling_finalize_key(p: vec2<u32>, word: u32) -> u32 {
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

// After every mark of the workgroup (a barrier between): ORs its masks into tile `tile`'s,
// one invocation per pass. Call with the local invocation index.
fn tiling_finalize_flush(li: u32, tile: u32) {
    if (li < params.pass_count) {
        let m = atomicLoad(&tiling_wg_masks[li]);
        let e = tile * params.pass_count + li;
        if (m != 0u && e < arrayLength(&masks)) {
            atomicOr(&masks[e], m);
        }
    }
}
