// tiling: phase 2, mid classify (Rust twin: tiling::mid_classify). Two entry points, in
// this order (dispatches and zeroed buffers: `tiling::MID_CLASSIFY`):
//   counter_offsets_pass  prefix sums of popcount(masks) per block of entries, and of blocks
//   count_pixels          counts, vertex cull buffer, records, the final counter offsets
// (The counts' prefix sum, the pixel offsets, is classify output's first entry point,
// where the counts are plain loads.)
// Bindings 0-3 are tiling::pixel's, 4 and 5 tiling::keyed's.

#import wave::append
#import tiling::keyed
// The `timing_*` features are timing experiments only (gpu's `classify_variants`; the
// output comes out wrong): no vertex-cull atomics, or no index reads at all.
// Per counter: commands counted (pixels, or VRS samples). Zero before count_pixels.
@group(0) @binding(6) var<storage, read_write> counts: array<atomic<u32>>;
// One byte per 64-vertex chunk, four per word (chunk c: byte c % 4 of word c / 4).
// Zero before count_pixels.
@group(0) @binding(7) var<storage, read_write> vertex_cull: array<atomic<u32>>;
// The shared index buffer: three indices per triangle, local to the geometry.
@group(0) @binding(8) var<storage, read> indices: array<u32>;
// counter_count (written by counter_offsets_pass).
@group(0) @binding(9) var<storage, read_write> totals: TilingTotals;
// tiling::PixelStats of count_pixels. Zero before count_pixels.
@group(0) @binding(10) var<storage, read_write> stats: array<atomic<u32>, 8>;
// counter_offsets_pass' sums (layout above tiling_counter_offset). Zero first.
@group(0) @binding(12) var<storage, read_write> offset_scratch: array<atomic<u32>>;

// Per 2x2 quad, row-major over ceil(width / 2) x ceil(height / 2): its pixels' records
// (TILING_RECORD_*, tiling::pixel), pixel k in component k, for classify output. One
// 16-byte store per invocation: four scalar stores two words apart cost 5x the bytes'
// time on the H200 (partial sectors).
@group(0) @binding(11) var<storage, read_write> slots: array<vec4<u32>>;

fn tiling_put_records(gid: vec3<u32>, records: vec4<u32>) {
#if timing_omit_records
    return;
#endif
    let q = tiling_quad_index(gid);
    if (q < arrayLength(&slots)) {
        slots[q] = records;
    }
}

// offset_scratch, in words (Rust: tiling::wgsl::offset_scratch_words; read and written
// through tiling_scratch_*, keyed.wgsl's tiling_scan_blocks): [0] workgroups
// done, then per (tile, pass) entry its counters' offset within its block of
// TILING_ENTRY_BLOCK entries, then per block its sum (the last workgroup turns these into
// the blocks' first counters).

fn tiling_scratch_load(i: u32) -> u32 {
    if (i >= arrayLength(&offset_scratch)) {
        return 0u;
    }
    return atomicLoad(&offset_scratch[i]);
}

fn tiling_scratch_store(i: u32, v: u32) {
    if (i < arrayLength(&offset_scratch)) {
        atomicStore(&offset_scratch[i], v);
    }
}

fn tiling_scratch_done() -> u32 {
    return atomicAdd(&offset_scratch[0], 1u);
}

fn tiling_scratch_blocks() -> u32 {
    return TILING_SCRATCH_ENTRIES + params.tiles_x * params.tiles_y * params.pass_count;
}

// The first counter of (tile, pass) entry e (keyed.wgsl): its block's plus its offset in
// the block, while count_pixels writes counter_offsets.
fn tiling_counter_offset(e: u32) -> u32 {
    return tiling_scratch_load(TILING_SCRATCH_ENTRIES + e)
        + tiling_scratch_load(tiling_scratch_blocks() + e / TILING_ENTRY_BLOCK);
}

// Per (tile, pass) entry (one invocation each, TILING_ENTRY_BLOCK per workgroup): the
// exclusive prefix of popcount(masks) within the block and the block's sum; the last
// workgroup to finish turns the block sums into the blocks' first counters and writes
// totals.counter_count (cross-workgroup values are atomics, ordered by storageBarrier's
// device-scope fences). One workgroup walking every entry took 75 us at 82 passes.
@compute @workgroup_size(256)
fn counter_offsets_pass(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
) {
    let n = min(params.tiles_x * params.tiles_y * params.pass_count, arrayLength(&masks));
    let block = wid.y * groups.x + wid.x;
    let e = block * TILING_ENTRY_BLOCK + li;
    var bits = 0u;
    if (e < n) {
        bits = countOneBits(masks[e]);
    }
    let scan = tiling_wg_scan(li, bits);
    if (e < n) {
        tiling_scratch_store(TILING_SCRATCH_ENTRIES + e, scan.x);
    }
    if (li == 0u) {
        tiling_scratch_store(tiling_scratch_blocks() + block, scan.y);
    }
    let last = tiling_scan_blocks(li, groups.x * groups.y * groups.z, (n + TILING_ENTRY_BLOCK - 1u) / TILING_ENTRY_BLOCK);
    if (last.x == 0u) {
        return;
    }
    if (li == 0u) {
        totals.counter_count = last.y;
    }
}

// Whether pixel (x, y) with vis word `word` starts a triangle run (tiling::first_of_run):
// neither its left nor its upper neighbour holds the same word with its validity bit set.
// `left` / `up`: those neighbours' words when they lie in the pixel's quad (the caller has
// them), VISBUF_NONE to read them here. Every valid pixel's word is also held by a run
// start, so reading the triangle's indices and marking its chunks only at run starts marks
// every visible triangle.
fn tiling_run_start(x: u32, y: u32, word: u32, left_in_quad: bool, left: u32, up_in_quad: bool, up: u32) -> bool {
    let i = y * params.width + x;
    if (x > 0u) {
        let l = select(tiling_word(i - 1u), left, left_in_quad);
        if (l == word && tiling_valid_bit(i - 1u)) {
            return false;
        }
    }
    if (y > 0u) {
        let u = select(tiling_word(i - params.width), up, up_in_quad);
        if (u == word && tiling_valid_bit(i - params.width)) {
            return false;
        }
    }
    return true;
}

// Whether count_pixels holds the vertex-cull code at all. A pipeline built with false has
// none (and ignores TILING_FLAG_VERTEX_CULL): its registers alone cost 7-9 us of the
// pass on the H200 though the uniform flag skips it, so frames without vertex culling
// take that pipeline.
override TILING_VERTEX_CULL_CODE: bool = true;

// The chunks this workgroup marked last, direct-mapped by a hash of the chunk: neighbouring
// run starts mostly hit the same few chunks, and a global atomic per mark serialises on
// their words (grass and the hillside: most pixels start a run).
const TILING_CHUNK_CACHE: u32 = 256u;
var<workgroup> tiling_chunk_cache: array<atomic<u32>, TILING_CHUNK_CACHE>;

// Sets chunk `chunk`'s byte in the cull buffer unless this workgroup set it already or it
// is set (a plain read first: most marks find it set).
fn tiling_mark_chunk(chunk: u32) {
    let slot = (chunk * 2654435761u) >> 24u;
    if (atomicExchange(&tiling_chunk_cache[slot], chunk) == chunk) {
        return;
    }
    let bit = 1u << ((chunk % 4u) * 8u);
    if ((atomicLoad(&vertex_cull[chunk / 4u]) & bit) == 0u) {
        atomicOr(&vertex_cull[chunk / 4u], bit);
    }
}

// Marks the 64-vertex chunks of a valid pixel's triangle; false if an index is bad (past
// the index buffer, at or past the vertex count, or a chunk past the cull buffer).
fn tiling_mark_triangle(px: TilingPixel) -> bool {
    // The row's three fields, not the whole 64-byte row.
    let first_index = table[px.mb].first_index;
    let vertex_count = table[px.mb].vertex_count;
    let first_chunk = table[px.mb].first_chunk;
    let first = tiling_add_sat(first_index, 3u * px.prim);
    let n = arrayLength(&indices);
    if (n < 3u || first > n - 3u) {
        return false;
    }
    // chunk = first_chunk + (instance * vertex_count + v) / 64 without 64-bit integers,
    // exactly (a saturated sum is past any chunk count): with vertex_count = 64 a + b,
    // v = 64 c + d and instance = 64 q + r it is
    // first_chunk + instance a + c + q b + (r b + d) / 64.
    let a = vertex_count / TILING_CHUNK_SIZE;
    let b = vertex_count % TILING_CHUNK_SIZE;
    let q = px.instance / TILING_CHUNK_SIZE;
    let r = px.instance % TILING_CHUNK_SIZE;
    let whole = tiling_add_sat(tiling_add_sat(first_chunk, tiling_mul_sat(px.instance, a)), q * b);
    var ok = true;
    // A triangle's vertices mostly share a chunk: one workgroup atomic for it, not three
    // on the same slot (-7 us of count_pixels on hillside-grass at 4K on the H200).
    var last = TILING_NONE;
    for (var k = 0u; k < 3u; k++) {
        let v = indices[first + k];
        if (v >= vertex_count) {
            ok = false;
            continue;
        }
        let part = (r * b + v % TILING_CHUNK_SIZE) / TILING_CHUNK_SIZE;
        let chunk = tiling_add_sat(whole, v / TILING_CHUNK_SIZE + part);
        if (chunk >= params.chunk_count || chunk / 4u >= arrayLength(&vertex_cull)) {
            ok = false;
            continue;
        }
        if (chunk != last) {
#if !timing_omit_cull_marks
            tiling_mark_chunk(chunk);
#endif
            last = chunk;
        }
    }
    return ok;
}

// One pixel's part in count_pixels: its key (TILING_NONE: no command), sample mask and
// record (kind and dropped flag; the command fields come after the histogram).
struct TilingCounted {
    key: u32,
    mask: u32,
    record: u32,
}

// Pixel k of `gid`'s quad, word `word`: decode, stats, chunk marks at run starts, key.
// `left` / `up` as tiling_run_start's.
fn tiling_count_pixel(gid: vec3<u32>, k: u32, word: u32, left_in_quad: bool, left: u32, up_in_quad: bool, up: u32, range: vec2<u32>) -> TilingCounted {
    var out = TilingCounted(TILING_NONE, 0u, TILING_PX_EMPTY);
    let p = tiling_quad_pixel(gid, k);
    if (p.x >= params.width || p.y >= params.height) {
        return out;
    }
    let px = tiling_decode(word, p.y * params.width + p.x);
    tiling_stat_kind(px.kind);
    out.record = px.kind;
    if (px.kind != TILING_PX_VALID) {
        return out;
    }
#if !timing_omit_index_reads
    // Only where the frame culls vertex chunks (a uniform branch): the index reads are
    // a third of this pass.
    if (TILING_VERTEX_CULL_CODE && (params.flags & TILING_FLAG_VERTEX_CULL) != 0u && tiling_run_start(p.x, p.y, word, left_in_quad, left, up_in_quad, up)
        && !tiling_mark_triangle(px)) {
        tiling_stat(TILING_STAT_BAD_INDICES, 1u);
    }
#endif
    let mask = tiling_sample_mask(p.x, p.y, word);
    if (mask == 0u) {
        tiling_stat(TILING_STAT_NO_SAMPLE, 1u);
    } else if (tiling_tile_has(range, px.pg)) {
        // Counted with the quad's other commands (count_pixels).
        out.key = px.pg;
        out.mask = mask;
    } else {
        out.record |= TILING_RECORD_DROPPED;
        tiling_stat(TILING_STAT_DROPPED, 1u);
    }
    return out;
}

// Adds `n` to counter c's count and returns the old count (keyed.wgsl's tiling_append).
fn tiling_counter_add(c: u32, n: u32) -> u32 {
    if (c >= arrayLength(&counts)) {
        return 0u;
    }
    return atomicAdd(&counts[c], n);
}

// A pixel's record: the command's slot and counter when it has one that fits the fields
// (corrupt buffers get none), else its kind.
fn tiling_record(px: TilingCounted, counter: u32, slot: u32, range: vec2<u32>) -> u32 {
    let index = counter - range.x;
    if (px.key != TILING_NONE && slot <= TILING_RECORD_SLOT_MASK && index <= TILING_RECORD_COUNTER_MASK) {
        return TILING_RECORD_COMMAND | slot | (index << TILING_RECORD_COUNTER_SHIFT) | (px.mask << TILING_RECORD_MASK_SHIFT);
    }
    return px.record;
}

// The quad's four pixels are spelled out, never indexed by a loop variable (tiling::pixel).
@compute @workgroup_size(16, 16)
fn count_pixels(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
) {
    atomicStore(&tiling_chunk_cache[li], TILING_NONE);
    let w = tiling_quad_words(gid);
    tiling_stats_zero(li);
    tiling_hist_zero(li);
    let tile = tiling_block_tile(wid);
    let range = tiling_tile_counters(tile, li);
    // The tile's first block writes the tile's final counter offsets.
    if ((wid.x * TILING_BLOCK_SIZE) % TILING_TILE_SIZE == 0u && (wid.y * TILING_BLOCK_SIZE) % TILING_TILE_SIZE == 0u
        && li < params.pass_count) {
        let e = tile * params.pass_count + li;
        if (range.y != TILING_NONE && e < arrayLength(&counter_offsets)) {
            counter_offsets[e] = tiling_wg_entry_first[li];
        }
    }
    // Pixels 0 1 / 2 3 of the quad: 1's left is 0, 2's upper is 0, 3's are 2 and 1.
    let p0 = tiling_count_pixel(gid, 0u, w.x, false, 0u, false, 0u, range);
    let p1 = tiling_count_pixel(gid, 1u, w.y, true, w.x, false, 0u, range);
    let p2 = tiling_count_pixel(gid, 2u, w.z, false, 0u, true, w.x, range);
    let p3 = tiling_count_pixel(gid, 3u, w.w, true, w.z, true, w.y, range);
    tiling_stat(TILING_STAT_COMMANDS, u32(p0.key != TILING_NONE) + u32(p1.key != TILING_NONE)
        + u32(p2.key != TILING_NONE) + u32(p3.key != TILING_NONE));
    // Each command's slot within its counter, as classify output's write_commands takes
    // them (the commands' order within a counter is free).
    var counters = vec4<u32>(0u);
    var slots = vec4<u32>(TILING_NONE);
    if (range.y <= TILING_HIST_LIMIT) {
        // Keyed histogram (keyed.wgsl): one global atomic per counter of the block.
        let r0 = tiling_rank(p0.key, range);
        let r1 = tiling_rank(p1.key, range);
        let r2 = tiling_rank(p2.key, range);
        let r3 = tiling_rank(p3.key, range);
        tiling_hist_flush(li, range);
        counters = vec4<u32>(r0.counter, r1.counter, r2.counter, r3.counter);
        slots = vec4<u32>(
            tiling_hist_first[r0.slot] + r0.rank,
            tiling_hist_first[r1.slot] + r1.rank,
            tiling_hist_first[r2.slot] + r2.rank,
            tiling_hist_first[r3.slot] + r3.rank,
        );
    }
#if !timing_omit_append_loop
    else {
        // Aggregated appends, one pixel of the quads at a time.
        let a0 = tiling_append(p0.key, li);
        let a1 = tiling_append(p1.key, li);
        let a2 = tiling_append(p2.key, li);
        let a3 = tiling_append(p3.key, li);
        counters = vec4<u32>(a0.x, a1.x, a2.x, a3.x);
        slots = vec4<u32>(a0.y, a1.y, a2.y, a3.y);
    }
#endif
    tiling_put_records(gid, vec4<u32>(
        tiling_record(p0, counters.x, slots.x, range),
        tiling_record(p1, counters.y, slots.y, range),
        tiling_record(p2, counters.z, slots.z, range),
        tiling_record(p3, counters.w, slots.w, range),
    ));
    workgroupBarrier();
    if (li < TILING_STAT_COUNT) {
        let v = tiling_stats_field(wid, li);
        if (v != 0u) {
            atomicAdd(&stats[li], v);
        }
    }
}
