// tiling: keyed aggregation for the two pixel phases (count_pixels, write_commands). A
// 16x16 workgroup lies in one tile, and the tile's counters are contiguous from its first
// (counter_offsets is a prefix sum in tile-major order), so a workgroup histogram indexed
// by `counter - first` aggregates every (pass, group) key of the block at once: one LDS
// atomic per pixel, two or three barriers, and one global atomic per counter present,
// fewer than the wave append loop's one per subgroup and key and without its three
// barriers per key. Tiles with more than TILING_HIST_LIMIT counters take the loop.
// Needs `masks` and `counter_offsets` (bindings 4 and 5 of both phases) in scope.

// One histogram slot per invocation of the 16x16 pixel workgroup (each zeroes its own).
const TILING_HIST_SLOTS: u32 = 256u;
// Most counters a tile may have for the histogram path (tests lower it to force the loop).
const TILING_HIST_LIMIT: u32 = TILING_HIST_SLOTS;
var<workgroup> tiling_hist: array<atomic<u32>, TILING_HIST_SLOTS>;
var<workgroup> tiling_hist_first: array<u32, TILING_HIST_SLOTS>;
var<workgroup> tiling_hist_range: vec2<u32>;

// The tile's counters as (first, count), read by the workgroup's first invocation and made
// uniform; a tile past the buffers reports TILING_NONE counters (the loop path).
fn tiling_tile_counters(tile: u32, li: u32) -> vec2<u32> {
    if (li == 0u) {
        let e0 = tile * params.pass_count;
        let e1 = e0 + params.pass_count - 1u;
        if (e1 < arrayLength(&masks) && e1 < arrayLength(&counter_offsets)) {
            let first = counter_offsets[e0];
            tiling_hist_range = vec2<u32>(first, counter_offsets[e1] + countOneBits(masks[e1]) - first);
        } else {
            tiling_hist_range = vec2<u32>(0u, TILING_NONE);
        }
    }
    return workgroupUniformLoad(&tiling_hist_range);
}
