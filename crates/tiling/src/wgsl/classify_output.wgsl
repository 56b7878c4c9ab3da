// tiling: phase 3, classify output (Rust twin: tiling::classify_output). Entry points, in
// this order (dispatches and zeroed buffers: `tiling::CLASSIFY_OUTPUT`). With a validity
// mask (the mixed frame):
//   pixel_offsets_pass         the counts' prefix sum (one workgroup; the CPU twin's mid
//                              classify has it, here the counts are plain loads)
//   write_commands             pixel (or quad) commands, classifying the final mask again
//                              (from count_pixels' records where the layout is standard)
//   entry_waves                final counts, each entry's first wave in its block, the
//                              blocks' first waves, the passes' sums
//   write_waves                wave offsets and wave commands; its first workgroup the
//                              pass dispatches
// Without one the final counts are mid classify's counts, and the same work takes two
// dispatches:
//   pixel_offsets_entry_waves  pixel_offsets_pass' workgroup, then entry_waves' (and the
//                              stats: mid classify's)
//   scatter_write_waves        write_waves' workgroups, then the commands from mid
//                              classify's per-pixel records
// Bindings 0-3 are tiling::pixel's, 4 and 5 tiling::keyed's.

#import wave::append
#import tiling::keyed

// The `timing_*` features are timing experiments only (gpu's `classify_variants`; the
// output comes out wrong): a plain store instead of the packed `atomicOr` (write_commands
// and the scatter).
// Per counter: room for commands, phase 2's counts.
@group(0) @binding(6) var<storage, read> counts: array<u32>;
// Per counter: first command, the exclusive prefix sum of the counts (pixel_offsets_pass).
@group(0) @binding(7) var<storage, read_write> pixel_offsets: array<u32>;
// Per counter: commands written (clamped to `counts` by entry_waves). Zero first.
@group(0) @binding(8) var<storage, read_write> final_counts: array<atomic<u32>>;
// The 16-bit commands, two per word (command i: bits 16 (i % 2) of word i / 2). Zero first.
@group(0) @binding(9) var<storage, read_write> commands: array<atomic<u32>>;
// Per counter: first wave command.
@group(0) @binding(10) var<storage, read_write> wave_offsets: array<u32>;
// The wave commands, pass-major.
@group(0) @binding(11) var<storage, read_write> waves: array<TilingWaveCommand>;
// Per pass: the shading dispatch.
@group(0) @binding(12) var<storage, read_write> passes: array<TilingPassDispatch>;
// command_count (written by pixel_offsets_pass), wave_count (by write_waves).
@group(0) @binding(13) var<storage, read_write> totals: TilingTotals;
// tiling::PixelStats of write_commands. Zero first.
@group(0) @binding(14) var<storage, read_write> stats: array<atomic<u32>, 8>;
// entry_waves' sums (layout above tiling_entry_count). Zero first.
@group(0) @binding(15) var<storage, read_write> wave_scratch: array<atomic<u32>>;
// count_pixels' records, a vec4 per quad (TILING_RECORD_*, tiling::pixel).
@group(0) @binding(16) var<storage, read> slots: array<vec4<u32>>;
// Mid classify's tiling::PixelStats: without a validity mask both phases classify alike,
// and pixel_offsets_entry_waves copies them into this phase's.
@group(0) @binding(17) var<storage, read> mid_stats: array<u32, 8>;

// Adds `n` to counter c's commands written and returns the old value (keyed.wgsl's
// tiling_append).
fn tiling_counter_add(c: u32, n: u32) -> u32 {
    if (c >= arrayLength(&final_counts)) {
        return 0u;
    }
    return atomicAdd(&final_counts[c], n);
}

// The first counter of (tile, pass) entry e (keyed.wgsl).
fn tiling_counter_offset(e: u32) -> u32 {
    return counter_offsets[e];
}

// Counter i's count, 0 past the buffer.
fn tiling_count(i: u32) -> u32 {
    if (i >= arrayLength(&counts)) {
        return 0u;
    }
    return counts[i];
}

// The sum of the counts [r.x, r.y), four loads in flight at a time (a loop of one load an
// iteration waits for each).
fn tiling_count_sum(r: vec2<u32>) -> u32 {
    var sum = 0u;
    var i = r.x;
    for (; i + 4u <= r.y; i += 4u) {
        sum += tiling_count(i) + tiling_count(i + 1u) + tiling_count(i + 2u) + tiling_count(i + 3u);
    }
    for (; i < r.y; i++) {
        sum += tiling_count(i);
    }
    return sum;
}

fn tiling_put_pixel_offset(i: u32, v: u32) {
    if (i < arrayLength(&pixel_offsets)) {
        pixel_offsets[i] = v;
    }
}

// One workgroup: pixel_offsets and totals.command_count from the counts (each invocation a
// contiguous run of counters).
fn tiling_pixel_offsets(li: u32) {
    let n = min(totals.counter_count, arrayLength(&counts));
    let r = tiling_wg_range(li, n);
    let scan = tiling_wg_scan(li, tiling_count_sum(r));
    var run = scan.x;
    var i = r.x;
    for (; i + 4u <= r.y; i += 4u) {
        let c = vec4<u32>(tiling_count(i), tiling_count(i + 1u), tiling_count(i + 2u), tiling_count(i + 3u));
        tiling_put_pixel_offset(i, run);
        tiling_put_pixel_offset(i + 1u, run + c.x);
        tiling_put_pixel_offset(i + 2u, run + c.x + c.y);
        tiling_put_pixel_offset(i + 3u, run + c.x + c.y + c.z);
        run += c.x + c.y + c.z + c.w;
    }
    for (; i < r.y; i++) {
        tiling_put_pixel_offset(i, run);
        run += tiling_count(i);
    }
    if (li == 0u) {
        totals.command_count = scan.y;
    }
}

@compute @workgroup_size(256)
fn pixel_offsets_pass(@builtin(local_invocation_index) li: u32) {
    tiling_pixel_offsets(li);
}

// Whether the frame has a validity mask (the mixed frame): then write_commands classifies
// the final mask again; without one scatter_write_waves places count_pixels' records.
fn tiling_has_validity() -> bool {
    return (params.flags & TILING_FLAG_VALIDITY) != 0u;
}

// Writes command `cmd` at `slot` of counter `c` (two 16-bit commands per word) when the
// counter has room for it: 1 if written, else 0 and counted as dropped.
fn tiling_put_command(c: u32, slot: u32, cmd: u32) -> u32 {
    if (c < arrayLength(&counts) && slot < counts[c]) {
        let at = pixel_offsets[c] + slot;
        if (at / 2u < arrayLength(&commands)) {
#if timing_store_commands
            atomicStore(&commands[at / 2u], cmd);
#else
            atomicOr(&commands[at / 2u], cmd << ((at % 2u) * 16u));
#endif
        }
        return 1u;
    }
    tiling_stat(TILING_STAT_DROPPED, 1u);
    return 0u;
}

// Pixel k of `gid`'s quad, word `word`: decode, stats, and its (key, command), key
// TILING_NONE without one.
fn tiling_write_pixel(gid: vec3<u32>, k: u32, word: u32, range: vec2<u32>) -> vec2<u32> {
    let p = tiling_quad_pixel(gid, k);
    if (p.x >= params.width || p.y >= params.height) {
        return vec2<u32>(TILING_NONE, 0u);
    }
    let px = tiling_decode(word, p.y * params.width + p.x);
    tiling_stat_kind(px.kind);
    if (px.kind != TILING_PX_VALID) {
        return vec2<u32>(TILING_NONE, 0u);
    }
    let mask = tiling_sample_mask(p.x, p.y, word);
    if (mask == 0u) {
        tiling_stat(TILING_STAT_NO_SAMPLE, 1u);
        return vec2<u32>(TILING_NONE, 0u);
    }
    if (!tiling_tile_has(range, px.pg)) {
        tiling_stat(TILING_STAT_DROPPED, 1u);
        return vec2<u32>(TILING_NONE, 0u);
    }
    return vec2<u32>(px.pg, tiling_command(p.x, p.y, mask));
}

// `kc` (key, command) from tiling_write_pixel with its key turned into the counter's index
// among the tile's (`range` from tiling_tile_counters), the key tiling_rank_index takes.
fn tiling_index_key(kc: vec2<u32>, range: vec2<u32>) -> vec2<u32> {
    if (kc.x == TILING_NONE) {
        return kc;
    }
    return vec2<u32>(tiling_counter_of(kc.x) - range.x, kc.y);
}

// Pixel k of `gid`'s quad under the final mask from count_pixels' record `r` (standard
// layout only: a VRS sample's mask depends on its block's validity bits, which changed):
// (counter index within the tile, command), TILING_NONE without one. The mask only shrinks
// in the mixed frame, so a pixel still valid classifies as its record says, without the
// decode. A record without a pixel (empty then: no vis ID, or a mask that has grown since)
// is classified from its word.
fn tiling_record_pixel(gid: vec3<u32>, k: u32, r: u32, range: vec2<u32>) -> vec2<u32> {
    let p = tiling_quad_pixel(gid, k);
    if (p.x >= params.width || p.y >= params.height) {
        return vec2<u32>(TILING_NONE, 0u);
    }
    let i = p.y * params.width + p.x;
    if (!tiling_valid_bit(i)) {
        return vec2<u32>(TILING_NONE, 0u);
    }
    if ((r & TILING_RECORD_COMMAND) != 0u) {
        return vec2<u32>(tiling_record_counter(r), tiling_command(p.x, p.y, tiling_record_mask(r)));
    }
    let kind = tiling_record_kind(r);
    if (kind == TILING_PX_EMPTY) {
        return tiling_index_key(tiling_write_pixel(gid, k, tiling_word(i), range), range);
    }
    tiling_stat_kind(kind);
    if (kind == TILING_PX_VALID) {
        tiling_stat(select(TILING_STAT_NO_SAMPLE, TILING_STAT_DROPPED, (r & TILING_RECORD_DROPPED) != 0u), 1u);
    }
    return vec2<u32>(TILING_NONE, 0u);
}

// Pixel's command `kc` (key, command) at the slot the keyed histogram gave it: 1 if
// written.
fn tiling_put_ranked(kc: vec2<u32>, r: TilingRanked) -> u32 {
    if (kc.x != TILING_NONE) {
        return tiling_put_command(r.counter, tiling_hist_first[r.slot] + r.rank, kc.y);
    }
    return 0u;
}

// Pixel's command `kc` through the wave-append loop (keyed.wgsl; barriers inside): 1 if
// written.
fn tiling_put_appended(kc: vec2<u32>, li: u32) -> u32 {
    let a = tiling_append(kc.x, li);
    if (a.y != TILING_NONE) {
        return tiling_put_command(a.x, a.y, kc.y);
    }
    return 0u;
}

// With a validity mask (the mixed frame): classifies the final mask again, from
// count_pixels' records where it can (tiling_record_pixel: no decode), else from the words.
// The quad's four pixels are spelled out, never indexed by a loop variable (tiling::pixel).
@compute @workgroup_size(16, 16)
fn write_commands(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
) {
    tiling_stats_zero(li);
    tiling_hist_zero(li);
    let range = tiling_tile_counters(tiling_block_tile(wid), li);
    if (range.y <= TILING_HIST_LIMIT) {
        // (counter index, command) per pixel.
        var c0: vec2<u32>;
        var c1: vec2<u32>;
        var c2: vec2<u32>;
        var c3: vec2<u32>;
        if (!tiling_vrs()) {
            var records = vec4<u32>(0u);
            let q = tiling_quad_index(gid);
            if (q < arrayLength(&slots)) {
                records = slots[q];
            }
            c0 = tiling_record_pixel(gid, 0u, records.x, range);
            c1 = tiling_record_pixel(gid, 1u, records.y, range);
            c2 = tiling_record_pixel(gid, 2u, records.z, range);
            c3 = tiling_record_pixel(gid, 3u, records.w, range);
        } else {
            let w = tiling_quad_words(gid);
            c0 = tiling_index_key(tiling_write_pixel(gid, 0u, w.x, range), range);
            c1 = tiling_index_key(tiling_write_pixel(gid, 1u, w.y, range), range);
            c2 = tiling_index_key(tiling_write_pixel(gid, 2u, w.z, range), range);
            c3 = tiling_index_key(tiling_write_pixel(gid, 3u, w.w, range), range);
        }
        // Keyed histogram (keyed.wgsl): a rank within the block per command, one global
        // atomic per counter of the block for the block's first slot.
        let r0 = tiling_rank_index(c0.x, range);
        let r1 = tiling_rank_index(c1.x, range);
        let r2 = tiling_rank_index(c2.x, range);
        let r3 = tiling_rank_index(c3.x, range);
        tiling_hist_flush(li, range);
        tiling_stat(TILING_STAT_COMMANDS, tiling_put_ranked(c0, r0) + tiling_put_ranked(c1, r1)
            + tiling_put_ranked(c2, r2) + tiling_put_ranked(c3, r3));
    } else {
        // Aggregated appends, one pixel of the quads at a time.
        let w = tiling_quad_words(gid);
        let c0 = tiling_write_pixel(gid, 0u, w.x, range);
        let c1 = tiling_write_pixel(gid, 1u, w.y, range);
        let c2 = tiling_write_pixel(gid, 2u, w.z, range);
        let c3 = tiling_write_pixel(gid, 3u, w.w, range);
        let a0 = tiling_put_appended(c0, li);
        let a1 = tiling_put_appended(c1, li);
        let a2 = tiling_put_appended(c2, li);
        let a3 = tiling_put_appended(c3, li);
        tiling_stat(TILING_STAT_COMMANDS, a0 + a1 + a2 + a3);
    }
    workgroupBarrier();
    if (li < TILING_STAT_COUNT) {
        let v = tiling_stats_field(wid, li);
        if (v != 0u) {
            atomicAdd(&stats[li], v);
        }
    }
}

// The (tile, pass) entry t * P + p of pass-major position p * T + t.
fn tiling_entry_of(pass_major: u32) -> u32 {
    let tiles = params.tiles_x * params.tiles_y;
    return (pass_major % tiles) * params.pass_count + pass_major / tiles;
}

fn tiling_waves_of(n: u32) -> u32 {
    return (n + params.wave_width - 1u) / params.wave_width;
}

// Whether counter c is within the buffers whose final count makes its waves (a counter past
// them has none; entry_waves and write_waves must agree).
fn tiling_counter_in_buffers(c: u32) -> bool {
    return c < arrayLength(&final_counts) && c < arrayLength(&counts);
}

// wave_scratch, in words (Rust: tiling::wgsl::wave_scratch_words): [0] workgroups done,
// then per pass-major entry its first wave within its block of TILING_ENTRY_BLOCK entries,
// then per block its sum (the last workgroup turns these into the blocks' first waves), then
// per pass its waves and its commands.

fn tiling_entry_count() -> u32 {
    return params.tiles_x * params.tiles_y * params.pass_count;
}

fn tiling_scratch_blocks() -> u32 {
    return TILING_SCRATCH_ENTRIES + tiling_entry_count();
}

fn tiling_scratch_pass_waves() -> u32 {
    return tiling_scratch_blocks() + (tiling_entry_count() + TILING_ENTRY_BLOCK - 1u) / TILING_ENTRY_BLOCK;
}

fn tiling_scratch_pass_items() -> u32 {
    return tiling_scratch_pass_waves() + params.pass_count;
}

fn tiling_scratch_load(i: u32) -> u32 {
    if (i >= arrayLength(&wave_scratch)) {
        return 0u;
    }
    return atomicLoad(&wave_scratch[i]);
}

fn tiling_scratch_store(i: u32, v: u32) {
    if (i < arrayLength(&wave_scratch)) {
        atomicStore(&wave_scratch[i], v);
    }
}

fn tiling_scratch_done() -> u32 {
    return atomicAdd(&wave_scratch[0], 1u);
}

fn tiling_scratch_add(i: u32, v: u32) {
    if (v != 0u && i < arrayLength(&wave_scratch)) {
        atomicAdd(&wave_scratch[i], v);
    }
}

// Places pixel k of `gid`'s quad's command from its record `r` (tile's first counter
// `first`); 1 when the counter has no room for it (corrupt counts), else 0.
fn tiling_scatter_pixel(gid: vec3<u32>, k: u32, r: u32, first: u32) -> u32 {
    let p = tiling_quad_pixel(gid, k);
    if (p.x >= params.width || p.y >= params.height || (r & TILING_RECORD_COMMAND) == 0u) {
        return 0u;
    }
    let c = first + tiling_record_counter(r);
    let slot = r & TILING_RECORD_SLOT_MASK;
    if (c >= arrayLength(&counts) || slot >= counts[c]) {
        return 1u;
    }
    let at = pixel_offsets[c] + slot;
    if (at / 2u < arrayLength(&commands)) {
        let cmd = tiling_command(p.x, p.y, tiling_record_mask(r));
#if timing_store_commands
        atomicStore(&commands[at / 2u], cmd);
#else
        atomicOr(&commands[at / 2u], cmd << ((at % 2u) * 16u));
#endif
    }
    return 0u;
}

// Frames without a validity mask: every pixel's command from its record, at the slot mid
// classify took for it (no decode, no histogram: mid and output classify alike), for the
// 16x16 quads of 2D workgroup `wid` (`gid`: this invocation's quad). No per-pixel stats:
// the pixels classify as in mid classify (pixel_offsets_entry_waves copied its stats); only
// commands that find no room here (corrupt counts) move from commands to dropped.
fn tiling_scatter_commands(gid: vec3<u32>, wid: vec3<u32>) {
    var records = vec4<u32>(0u);
    let q = tiling_quad_index(gid);
    if (q < arrayLength(&slots)) {
        records = slots[q];
    }
    let first = tiling_tile_first_counter(tiling_block_tile(wid));
    let lost = tiling_scatter_pixel(gid, 0u, records.x, first) + tiling_scatter_pixel(gid, 1u, records.y, first)
        + tiling_scatter_pixel(gid, 2u, records.z, first) + tiling_scatter_pixel(gid, 3u, records.w, first);
    if (lost != 0u) {
        // Mid classify counted them as commands (pixel_offsets_entry_waves copied its stats).
        tiling_stat_sub_saturating(TILING_STAT_COMMANDS, lost);
        atomicAdd(&stats[TILING_STAT_DROPPED], lost);
    }
}

// Subtracts `n` from stats field `field`, stopping at 0: records and stats of different
// frames (a caller's mistake) could otherwise wrap the count. Corrupt frames only.
fn tiling_stat_sub_saturating(field: u32, n: u32) {
    var old = atomicLoad(&stats[field]);
    loop {
        if (old == 0u) {
            break;
        }
        let r = atomicCompareExchangeWeak(&stats[field], old, old - min(old, n));
        if (r.exchanged) {
            break;
        }
        old = r.old_value;
    }
}

// The scatter's workgroups: a 16x16 workgroup per TILING_BLOCK_SIZE block of the vis buffer.
fn tiling_scatter_groups() -> vec2<u32> {
    return vec2<u32>((params.width + TILING_BLOCK_SIZE - 1u) / TILING_BLOCK_SIZE, (params.height + TILING_BLOCK_SIZE - 1u) / TILING_BLOCK_SIZE);
}

var<workgroup> tiling_wg_pass_waves: array<atomic<u32>, TILING_ENTRY_BLOCK>;
var<workgroup> tiling_wg_pass_items: array<atomic<u32>, TILING_ENTRY_BLOCK>;

// Per pass-major entry (one invocation each, TILING_ENTRY_BLOCK per workgroup): clamps its
// counters' final counts to their room and sums their waves; per workgroup the block's
// sum and, per pass, its waves and commands. The last workgroup to finish turns the block
// sums into the blocks' first waves (every cross-workgroup value an atomic, ordered by
// storageBarrier's device-scope fences).
// Workgroup `block` of `blocks` (the entry blocks of the frame).
fn tiling_entry_waves(block: u32, blocks: u32, li: u32) {
    atomicStore(&tiling_wg_pass_waves[li], 0u);
    atomicStore(&tiling_wg_pass_items[li], 0u);
    workgroupBarrier();
    let tiles = params.tiles_x * params.tiles_y;
    let n = min(tiling_entry_count(), arrayLength(&masks));
    let q = block * TILING_ENTRY_BLOCK + li;
    let first_pass = block * TILING_ENTRY_BLOCK / max(tiles, 1u);
    var waves = 0u;
    if (q < n && tiles != 0u) {
        let e = tiling_entry_of(q);
        var bits = masks[e];
        var c = counter_offsets[e];
        var items = 0u;
        while (bits != 0u) {
            bits &= bits - 1u;
            if (tiling_counter_in_buffers(c)) {
                // scatter_commands writes every counted command and keeps no final counts.
                var f = counts[c];
                if (tiling_has_validity()) {
                    f = min(atomicLoad(&final_counts[c]), f);
                }
                atomicStore(&final_counts[c], f);
                waves += tiling_waves_of(f);
                items += f;
            }
            c += 1u;
        }
        let local = q / tiles - first_pass;
        if (waves != 0u) {
            atomicAdd(&tiling_wg_pass_waves[local], waves);
        }
        if (items != 0u) {
            atomicAdd(&tiling_wg_pass_items[local], items);
        }
    }
    // Each entry's first wave within its block (write_waves adds the block's first wave).
    let in_block = tiling_wg_scan(li, waves);
    if (q < n && tiles != 0u) {
        tiling_scratch_store(TILING_SCRATCH_ENTRIES + q, in_block.x);
    }
    if (li == 0u) {
        tiling_scratch_store(tiling_scratch_blocks() + block, in_block.y);
    }
    let my_pass = first_pass + li;
    if (my_pass < params.pass_count) {
        tiling_scratch_add(tiling_scratch_pass_waves() + my_pass, atomicLoad(&tiling_wg_pass_waves[li]));
        tiling_scratch_add(tiling_scratch_pass_items() + my_pass, atomicLoad(&tiling_wg_pass_items[li]));
    }
    // The last workgroup turns the block sums into the blocks' first waves.
    _ = tiling_scan_blocks(li, blocks, (n + TILING_ENTRY_BLOCK - 1u) / TILING_ENTRY_BLOCK);
}

// The pass dispatches and totals.wave_count from entry_waves' pass sums (write_waves'
// first workgroup: in entry_waves' last workgroup this scan lengthened the pass before
// the scatter). Contains barriers: call from uniform control flow.
fn tiling_pass_dispatches(li: u32) {
    var pass_waves = 0u;
    if (li < params.pass_count) {
        pass_waves = tiling_scratch_load(tiling_scratch_pass_waves() + li);
    }
    let scan = tiling_wg_scan(li, pass_waves);
    if (li < params.pass_count && li < arrayLength(&passes)) {
        passes[li] = tiling_dispatch(scan.x, pass_waves, tiling_scratch_load(tiling_scratch_pass_items() + li));
    }
    if (li == 0u) {
        totals.wave_count = scan.y;
    }
}

// Workgroups of `per` (tile, pass) entries each over the frame's entries.
fn tiling_entry_groups(per: u32) -> u32 {
    return (min(tiling_entry_count(), arrayLength(&masks)) + per - 1u) / per;
}

// The entry blocks of the frame: ceil(entries / TILING_ENTRY_BLOCK).
fn tiling_entry_blocks() -> u32 {
    return tiling_entry_groups(TILING_ENTRY_BLOCK);
}

// With a validity mask, after write_commands: a workgroup per block of entries.
@compute @workgroup_size(256)
fn entry_waves(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
) {
    tiling_entry_waves(wid.y * groups.x + wid.x, groups.x * groups.y * groups.z, li);
}

// Without a validity mask the final counts are mid classify's counts, so the entries' waves
// need not wait for the commands: pixel_offsets_pass' workgroup (first: it takes longest)
// and entry_waves' in one dispatch, and the stats are mid classify's (no index reads in
// this phase; scatter_write_waves moves the commands that find no room to dropped).
// Workgroups in rows (Dispatch::Items).
@compute @workgroup_size(256)
fn pixel_offsets_entry_waves(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
) {
    let g = wid.y * groups.x + wid.x;
    if (g == 0u) {
        tiling_pixel_offsets(li);
        if (li < TILING_STAT_COUNT) {
            atomicStore(&stats[li], select(mid_stats[li], 0u, li == TILING_STAT_BAD_INDICES));
        }
    } else if (g - 1u < tiling_entry_blocks()) {
        tiling_entry_waves(g - 1u, tiling_entry_blocks(), li);
    }
}

// write_waves' entries per workgroup of 256 (TILING_WAVE_ENTRY_LANES each). A workgroup per
// entry launched 84 us of mostly empty workgroups at 163 passes on the H200.
const TILING_WAVE_ENTRIES: u32 = 256u / TILING_WAVE_ENTRY_LANES;

// TILING_WAVE_ENTRY_LANES lanes per pass-major entry: its counters' wave offsets and wave
// commands, the lanes striding over each counter's waves. Workgroup `workgroup` of
// write_waves'.
fn tiling_write_waves(workgroup: u32, li: u32) {
    if (workgroup == 0u) {
        tiling_pass_dispatches(li);
    }
    let tiles = params.tiles_x * params.tiles_y;
    let sub = li / TILING_WAVE_ENTRY_LANES;
    let lane = li % TILING_WAVE_ENTRY_LANES;
    let q = workgroup * TILING_WAVE_ENTRIES + sub;
    var bits = 0u;
    var e = 0u;
    if (q < min(tiling_entry_count(), arrayLength(&masks))) {
        e = tiling_entry_of(q);
        bits = masks[e];
    }
    if (bits == 0u) {
        return;
    }
    // The entry's first wave: its block's plus its own within the block (entry_waves).
    var first = tiling_scratch_load(TILING_SCRATCH_ENTRIES + q) + tiling_scratch_load(tiling_scratch_blocks() + q / TILING_ENTRY_BLOCK);
    let t = q % tiles;
    let p = q / tiles;
    let tile = (t % params.tiles_x) | ((t / params.tiles_x) << TILING_WAVE_TILE_Y_SHIFT);
    var c = counter_offsets[e];
    while (bits != 0u) {
        let g = firstTrailingBit(bits);
        bits &= bits - 1u;
        if (tiling_counter_in_buffers(c)) {
            let f = atomicLoad(&final_counts[c]);
            if (lane == 0u && c < arrayLength(&wave_offsets)) {
                wave_offsets[c] = first;
            }
            let n = tiling_waves_of(f);
            for (var w = lane; w < n; w += TILING_WAVE_ENTRY_LANES) {
                if (first + w < arrayLength(&waves)) {
                    let k = w * params.wave_width;
                    waves[first + w] = TilingWaveCommand(
                        tile,
                        p | (g << TILING_WAVE_GROUP_SHIFT),
                        pixel_offsets[c] + k,
                        min(params.wave_width, f - k),
                    );
                }
            }
            first += n;
        }
        c += 1u;
    }
}

// write_waves' workgroups: one per TILING_WAVE_ENTRIES entries.
fn tiling_write_waves_groups() -> u32 {
    return tiling_entry_groups(TILING_WAVE_ENTRIES);
}

// With a validity mask, after entry_waves. Workgroups in rows (Dispatch::Items).
@compute @workgroup_size(256)
fn write_waves(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
) {
    tiling_write_waves(wid.y * groups.x + wid.x, li);
}

// Without a validity mask, after pixel_offsets_entry_waves: write_waves' workgroups, then
// (one per TILING_BLOCK_SIZE block) each pixel's command at the slot mid classify recorded: neither
// needs the other, so one dispatch, one pass fewer. Workgroups in rows (Dispatch::Items).
@compute @workgroup_size(256)
fn scatter_write_waves(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
) {
    let g = wid.y * groups.x + wid.x;
    let wave_groups = tiling_write_waves_groups();
    let scatter = tiling_scatter_groups();
    if (g < wave_groups) {
        tiling_write_waves(g, li);
    } else if (g - wave_groups < scatter.x * scatter.y) {
        let s = g - wave_groups;
        let w = vec3<u32>(s % scatter.x, s / scatter.x, 0u);
        let quads = TILING_BLOCK_SIZE / 2u;
        tiling_scatter_commands(vec3<u32>(w.x * quads + li % quads, w.y * quads + li / quads, 0u), w);
    }
}
