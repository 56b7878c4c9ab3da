// tiling: keyed aggregation for the two pixel phases (count_pixels, write_commands). A
// pixel workgroup's 32x32 block lies in one tile, and the tile's counters are contiguous from its first
// (counter_offsets is a prefix sum in tile-major order), so a workgroup histogram indexed
// by `counter - first` aggregates every (pass, group) key of the block at once: one LDS
// atomic per pixel, two or three barriers, and one global atomic per counter present,
// fewer than the wave append loop's one per subgroup and key and without its three
// barriers per key. Tiles with more than TILING_HIST_LIMIT counters take the loop.
// Declares bindings 4 and 5, which mid classify and classify output share. Also the parts
// the two phases share over their own buffers: the importing module defines
// tiling_counter_offset, tiling_counter_add and tiling_scratch_{done, blocks, load, store}.

#import wave::append
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

// Tile `tile`'s first (tile, pass) entry, TILING_NONE when its entries lie past `masks` or
// `counter_offsets` (or the frame has no passes).
fn tiling_tile_first_entry(tile: u32) -> u32 {
    let e0 = tile * params.pass_count;
    let e1 = e0 + params.pass_count - 1u;
    if (params.pass_count == 0u || e1 >= arrayLength(&masks) || e1 >= arrayLength(&counter_offsets)) {
        return TILING_NONE;
    }
    return e0;
}

// Tile `tile`'s first counter, tiling_tile_counters' range.x (0 for a tile past the
// buffers, whose pixels get no command): one load, no workgroup memory or barrier, for a
// pass that needs nothing else of the tile (classify output's scatter).
fn tiling_tile_first_counter(tile: u32) -> u32 {
    let e0 = tiling_tile_first_entry(tile);
    if (e0 == TILING_NONE) {
        return 0u;
    }
    return tiling_counter_offset(e0);
}

// The tile's counters as (first, count), the same in every invocation; a tile past the
// buffers reports TILING_NONE counters (the loop path). Also loads the tile's entries into
// workgroup memory (one invocation per pass), which tiling_counter_of then reads: the
// pixel phases look up a counter per pixel. Call from uniform control flow.
fn tiling_tile_counters(tile: u32, li: u32) -> vec2<u32> {
    let e0 = tiling_tile_first_entry(tile);
    let inside = e0 != TILING_NONE;
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

// The wave-append loop for one pixel of every quad of the workgroup (tiles with more
// counters than the histogram): returns (counter, slot) of this invocation's command, slot
// TILING_NONE without one. The importing module defines `tiling_counter_add(c, n)`, which
// adds to the counter it appends to and returns the old value. Contains barriers: call
// from uniform control flow.
fn tiling_append(key: u32, li: u32) -> vec2<u32> {
    var out = vec2<u32>(0u, TILING_NONE);
    var pending = key != TILING_NONE;
    loop {
        let next = tiling_smallest_pending_key(pending, key, li);
        if (next == TILING_NONE) {
            break;
        }
        let take = pending && key == next;
        let c = tiling_counter_of(next);
        let a = wave_append_begin(take, li);
        var old = 0u;
        if (a.total != 0u) {
            old = tiling_counter_add(c, a.total);
        }
        let slot = wave_append_end(a, old);
        if (take) {
            pending = false;
            out = vec2<u32>(c, slot);
        }
    }
    return out;
}

var<workgroup> tiling_wg_last: u32;

// The end of a block scan's workgroup (counter_offsets_pass, entry_waves; `workgroups` of
// them take part), after it wrote
// its block's sum: whether it is the last workgroup to finish, and if so the blocks' sums
// turned in place into the blocks' first values (exclusive prefix sum) and their total:
// (1, total), else (0, 0). Every value another workgroup wrote is read with an atomic
// load, after storageBarrier's device-scope fences on both sides of the done counter. The
// importing module defines `tiling_scratch_done()` (adds one to its workgroups-done count,
// returns the old), `tiling_scratch_blocks()` (where the block sums start) and
// `tiling_scratch_load(i)` / `tiling_scratch_store(i, v)`. Contains barriers: call from
// uniform control flow.
fn tiling_scan_blocks(li: u32, workgroups: u32, blocks: u32) -> vec2<u32> {
    storageBarrier();
    if (li == 0u) {
        tiling_wg_last = select(0u, 1u, tiling_scratch_done() == workgroups - 1u);
    }
    if (workgroupUniformLoad(&tiling_wg_last) == 0u) {
        return vec2<u32>(0u);
    }
    storageBarrier();
    let r = tiling_wg_range(li, blocks);
    var sum = 0u;
    for (var b = r.x; b < r.y; b++) {
        sum += tiling_scratch_load(tiling_scratch_blocks() + b);
    }
    let scan = tiling_wg_scan(li, sum);
    var run = scan.x;
    for (var b = r.x; b < r.y; b++) {
        let v = tiling_scratch_load(tiling_scratch_blocks() + b);
        tiling_scratch_store(tiling_scratch_blocks() + b, run);
        run += v;
    }
    return vec2<u32>(1u, scan.y);
}

// A command's counter, its workgroup-histogram slot and its rank there (keyed path).
struct TilingRanked {
    counter: u32,
    slot: u32,
    rank: u32,
}

fn tiling_rank(key: u32, range: vec2<u32>) -> TilingRanked {
    if (key == TILING_NONE) {
        return TilingRanked(0u, 0u, 0u);
    }
    return tiling_rank_index(tiling_counter_of(key) - range.x, range);
}

// tiling_rank for a key that is already the counter's index within the tile's counters
// (TILING_NONE: no command).
fn tiling_rank_index(index: u32, range: vec2<u32>) -> TilingRanked {
    if (index == TILING_NONE) {
        return TilingRanked(0u, 0u, 0u);
    }
    let slot = min(index, TILING_HIST_SLOTS - 1u);
    return TilingRanked(range.x + index, slot, atomicAdd(&tiling_hist[slot], 1u));
}

// Zeroes this invocation's histogram slot; a barrier must follow before any tiling_rank
// (the pixel phases call it right before tiling_tile_counters, whose barrier serves: one
// barrier fewer).
fn tiling_hist_zero(li: u32) {
    atomicStore(&tiling_hist[li], 0u);
}

// After every tiling_rank of the workgroup: one global atomic per counter of the block
// (`tiling_counter_add`) for the block's first slot in it, in tiling_hist_first; barriers
// on both sides. Call from uniform control flow.
fn tiling_hist_flush(li: u32, range: vec2<u32>) {
    workgroupBarrier();
    if (li < range.y) {
        let v = atomicLoad(&tiling_hist[li]);
        if (v != 0u) {
            tiling_hist_first[li] = tiling_counter_add(range.x + li, v);
        }
    }
    workgroupBarrier();
}
