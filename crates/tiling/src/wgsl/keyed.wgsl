// tiling: keyed aggregation for the two pixel phases (count_pixels, write_commands). A
// 16x16 workgroup lies in one tile, and the tile's counters are contiguous from its first
// (counter_offsets is a prefix sum in tile-major order), so a workgroup histogram indexed
// by `counter - first` aggregates every (pass, group) key of the block at once: one LDS
// atomic per pixel, two or three barriers, and one global atomic per counter present,
// fewer than the wave append loop's one per subgroup and key and without its three
// barriers per key. Tiles with more than TILING_HIST_LIMIT counters take the loop.
// Declares bindings 4 and 5, which mid classify and classify output share.

#import tiling::pixel

// Per (tile, pass): the batch groups used (phase 1's output).
@group(0) @binding(4) var<storage, read> masks: array<u32>;
// Per (tile, pass): first counter, the exclusive prefix sum of popcount(masks) (written by
// mid classify's count_pixels, read by everything after it). The importing module defines
// `tiling_counter_offset(e)`, where this file reads it: mid classify from its block sums
// (the final values are written while it runs), classify output from this buffer.
@group(0) @binding(5) var<storage, read_write> counter_offsets: array<u32>;

// One histogram slot per invocation of the 16x16 pixel workgroup (each zeroes its own).
const TILING_HIST_SLOTS: u32 = 256u;
// Most counters a tile may have for the histogram path; the device tests set it to 0 to
// run the wave-append loop everywhere.
override TILING_HIST_LIMIT: u32 = TILING_HIST_SLOTS;
// The wave-append loop's current key (the smallest pending in the workgroup).
var<workgroup> tiling_wg_key: atomic<u32>;
var<workgroup> tiling_wg_key_plain: u32;
var<workgroup> tiling_hist: array<atomic<u32>, TILING_HIST_SLOTS>;
var<workgroup> tiling_hist_first: array<u32, TILING_HIST_SLOTS>;
var<workgroup> tiling_hist_range: vec2<u32>;

// The tile's (pass) entries' first counters and masks, for tiling_counter_of.
var<workgroup> tiling_wg_entry_first: array<u32, TILING_MAX_PASSES>;
var<workgroup> tiling_wg_entry_mask: array<u32, TILING_MAX_PASSES>;

// The tile's counters as (first, count), the same in every invocation; a tile past the
// buffers reports TILING_NONE counters (the loop path). Also loads the tile's entries into
// workgroup memory (one invocation per pass), which tiling_counter_of then reads: the
// pixel phases look up a counter per pixel. Call from uniform control flow.
fn tiling_tile_counters(tile: u32, li: u32) -> vec2<u32> {
    let e0 = tile * params.pass_count;
    let e1 = e0 + params.pass_count - 1u;
    let inside = e1 < arrayLength(&masks) && e1 < arrayLength(&counter_offsets);
    if (inside && li < params.pass_count) {
        tiling_wg_entry_first[li] = tiling_counter_offset(e0 + li);
        tiling_wg_entry_mask[li] = masks[e0 + li];
    }
    workgroupBarrier();
    if (li == 0u) {
        if (inside) {
            let first = tiling_wg_entry_first[0];
            let last = params.pass_count - 1u;
            tiling_hist_range = vec2<u32>(first, tiling_wg_entry_first[last] + countOneBits(tiling_wg_entry_mask[last]) - first);
        } else {
            tiling_hist_range = vec2<u32>(0u, TILING_NONE);
        }
    }
    return workgroupUniformLoad(&tiling_hist_range);
}

// Whether the workgroup's tile has (pass, group) key `k` in its masks (after
// tiling_tile_counters returned `range`).
fn tiling_tile_has(range: vec2<u32>, k: u32) -> bool {
    let p = k / TILING_MAX_BATCH_GROUPS;
    return range.y != TILING_NONE && p < params.pass_count
        && ((tiling_wg_entry_mask[p] >> (k % TILING_MAX_BATCH_GROUPS)) & 1u) == 1u;
}

// Counter of (pass, group) key `k` of the workgroup's tile, whose mask has the group (after
// tiling_tile_counters).
fn tiling_counter_of(k: u32) -> u32 {
    let p = min(k / TILING_MAX_BATCH_GROUPS, TILING_MAX_PASSES - 1u);
    let g = k % TILING_MAX_BATCH_GROUPS;
    return tiling_wg_entry_first[p] + countOneBits(tiling_wg_entry_mask[p] & ((1u << g) - 1u));
}

// The smallest key still pending in the workgroup (TILING_NONE when none is), the same in
// every invocation: the wave-append loop takes one (pass, group) at a time, smallest first.
// Contains barriers: call from uniform control flow, from every invocation.
fn tiling_smallest_pending_key(pending: bool, key: u32, li: u32) -> u32 {
    if (li == 0u) {
        atomicStore(&tiling_wg_key, TILING_NONE);
    }
    workgroupBarrier();
    if (pending) {
        atomicMin(&tiling_wg_key, key);
    }
    workgroupBarrier();
    if (li == 0u) {
        tiling_wg_key_plain = atomicLoad(&tiling_wg_key);
    }
    return workgroupUniformLoad(&tiling_wg_key_plain);
}
