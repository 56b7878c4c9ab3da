// tiling: phase 3, classify output (Rust twin: tiling::classify_output). Three entry
// points, in this order (dispatches and zeroed buffers: `tiling::CLASSIFY_OUTPUT`):
//   write_commands     pixel (or quad) commands
//   wave_offsets_pass  final counts, wave offsets, pass dispatches
//   write_waves        wave commands
// Bindings 0-3 are tiling::pixel's, 4 and 5 tiling::keyed's.

#import wave::append
#import tiling::keyed

// The `timing_*` features are timing experiments only (gpu's `classify_variants`; the
// output comes out wrong): a plain store instead of the packed `atomicOr`.
// Per counter: room for commands, phase 2's counts.
@group(0) @binding(6) var<storage, read> counts: array<u32>;
// Per counter: first command (phase 2).
@group(0) @binding(7) var<storage, read> pixel_offsets: array<u32>;
// Per counter: commands written (clamped to `counts` by wave_offsets_pass). Zero first.
@group(0) @binding(8) var<storage, read_write> final_counts: array<atomic<u32>>;
// The 16-bit commands, two per word (command i: bits 16 (i % 2) of word i / 2). Zero first.
@group(0) @binding(9) var<storage, read_write> commands: array<atomic<u32>>;
// Per counter: first wave command.
@group(0) @binding(10) var<storage, read_write> wave_offsets: array<u32>;
// The wave commands, pass-major.
@group(0) @binding(11) var<storage, read_write> waves: array<TilingWaveCommand>;
// Per pass: the shading dispatch.
@group(0) @binding(12) var<storage, read_write> passes: array<TilingPassDispatch>;
// wave_count (written by wave_offsets_pass).
@group(0) @binding(13) var<storage, read_write> totals: TilingTotals;
// tiling::PixelStats of write_commands. Zero first.
@group(0) @binding(14) var<storage, read_write> stats: array<atomic<u32>, 8>;

// Writes command `cmd` at `slot` of counter `c` (two 16-bit commands per word) when the
// counter has room for it, and counts it as written or dropped.
fn tiling_put_command(c: u32, slot: u32, cmd: u32) {
    if (c < arrayLength(&counts) && slot < counts[c]) {
        let at = pixel_offsets[c] + slot;
        if (at / 2u < arrayLength(&commands)) {
#if timing_store_commands
            atomicStore(&commands[at / 2u], cmd);
#else
            atomicOr(&commands[at / 2u], cmd << ((at % 2u) * 16u));
#endif
        }
        tiling_stat(TILING_STAT_COMMANDS, 1u);
    } else {
        tiling_stat(TILING_STAT_DROPPED, 1u);
    }
}

@compute @workgroup_size(16, 16)
fn write_commands(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
) {
    tiling_stats_begin(li);
    let tile = (wid.y * 16u / TILING_TILE_SIZE) * params.tiles_x + wid.x * 16u / TILING_TILE_SIZE;
    var key = TILING_NONE;
    var cmd = 0u;
    if (gid.x < params.width && gid.y < params.height) {
        let i = gid.y * params.width + gid.x;
        let word = tiling_word(i);
        let px = tiling_decode(word, i);
        tiling_stat_pixel(px);
        if (px.kind == TILING_PX_VALID) {
            let mask = tiling_sample_mask(gid.x, gid.y, word);
            if (mask != 0u) {
                let e = tile * params.pass_count + px.pg / TILING_MAX_BATCH_GROUPS;
                if (e < arrayLength(&masks) && ((masks[e] >> (px.pg % TILING_MAX_BATCH_GROUPS)) & 1u) == 1u) {
                    key = px.pg;
                    cmd = tiling_command(gid.x, gid.y, mask);
                } else {
                    tiling_stat(TILING_STAT_DROPPED, 1u);
                }
            }
        }
    }
    let range = tiling_tile_counters(tile, li);
    if (range.y <= TILING_HIST_LIMIT) {
        // Keyed histogram (keyed.wgsl): a rank within the block per command, one global
        // atomic per counter of the block for the block's first slot.
        atomicStore(&tiling_hist[li], 0u);
        workgroupBarrier();
        var rank = 0u;
        var c = 0u;
        if (key != TILING_NONE) {
            c = tiling_counter_of(tile, key);
            rank = atomicAdd(&tiling_hist[min(c - range.x, TILING_HIST_SLOTS - 1u)], 1u);
        }
        workgroupBarrier();
        if (li < range.y) {
            let v = atomicLoad(&tiling_hist[li]);
            if (v != 0u && range.x + li < arrayLength(&final_counts)) {
                tiling_hist_first[li] = atomicAdd(&final_counts[range.x + li], v);
            }
        }
        workgroupBarrier();
        if (key != TILING_NONE) {
            let slot = tiling_hist_first[min(c - range.x, TILING_HIST_SLOTS - 1u)] + rank;
            tiling_put_command(c, slot, cmd);
        }
    } else {
        // Aggregated appends, one (pass, group) of the workgroup at a time.
        var pending = key != TILING_NONE;
        loop {
            let k = tiling_smallest_pending_key(pending, key, li);
            if (k == TILING_NONE) {
                break;
            }
            let take = pending && key == k;
            let c = tiling_counter_of(tile, k);
            let a = wave_append_begin(take, li);
            var old = 0u;
            if (a.total != 0u && c < arrayLength(&final_counts)) {
                old = atomicAdd(&final_counts[c], a.total);
            }
            let slot = wave_append_end(a, old);
            if (take) {
                pending = false;
                tiling_put_command(c, slot, cmd);
            }
        }
    }
    workgroupBarrier();
    if (li < TILING_STAT_COUNT) {
        let v = atomicLoad(&tiling_wg_stats[li]);
        if (v != 0u) {
            atomicAdd(&stats[li], v);
        }
    }
}

var<workgroup> tiling_wg_pass_waves: array<atomic<u32>, TILING_MAX_PASSES>;
var<workgroup> tiling_wg_pass_items: array<atomic<u32>, TILING_MAX_PASSES>;
var<workgroup> tiling_wg_pass_first: array<u32, TILING_MAX_PASSES>;

// The (tile, pass) entry t * P + p of pass-major position p * T + t.
fn tiling_entry_of(pass_major: u32) -> u32 {
    let tiles = params.tiles_x * params.tiles_y;
    return (pass_major % tiles) * params.pass_count + pass_major / tiles;
}

fn tiling_waves_of(n: u32) -> u32 {
    return (n + params.wave_width - 1u) / params.wave_width;
}

@compute @workgroup_size(256)
fn wave_offsets_pass(@builtin(local_invocation_index) li: u32) {
    atomicStore(&tiling_wg_pass_waves[li], 0u);
    atomicStore(&tiling_wg_pass_items[li], 0u);
    tiling_wg_pass_first[li] = 0u;
    workgroupBarrier();
    let tiles = params.tiles_x * params.tiles_y;
    let n = min(tiles * params.pass_count, arrayLength(&masks));
    let r = tiling_wg_range(li, n);
    // Clamp each counter to its room, sum this range's waves.
    var sum = 0u;
    for (var q = r.x; q < r.y; q++) {
        let e = tiling_entry_of(q);
        var bits = masks[e];
        var c = counter_offsets[e];
        while (bits != 0u) {
            bits &= bits - 1u;
            if (c < arrayLength(&final_counts) && c < arrayLength(&counts)) {
                let f = min(atomicLoad(&final_counts[c]), counts[c]);
                atomicStore(&final_counts[c], f);
                sum += tiling_waves_of(f);
            }
            c += 1u;
        }
    }
    let scan = tiling_wg_scan(li, sum);
    var run = scan.x;
    for (var q = r.x; q < r.y; q++) {
        let e = tiling_entry_of(q);
        let p = q / tiles;
        if (q % tiles == 0u) {
            tiling_wg_pass_first[p] = run;
        }
        var bits = masks[e];
        var c = counter_offsets[e];
        while (bits != 0u) {
            bits &= bits - 1u;
            if (c < arrayLength(&final_counts) && c < arrayLength(&counts)) {
                let f = atomicLoad(&final_counts[c]);
                if (c < arrayLength(&wave_offsets)) {
                    wave_offsets[c] = run;
                }
                let w = tiling_waves_of(f);
                run += w;
                atomicAdd(&tiling_wg_pass_waves[p], w);
                atomicAdd(&tiling_wg_pass_items[p], f);
            }
            c += 1u;
        }
    }
    workgroupBarrier();
    if (li < params.pass_count && li < arrayLength(&passes)) {
        passes[li] = tiling_dispatch(
            tiling_wg_pass_first[li],
            atomicLoad(&tiling_wg_pass_waves[li]),
            atomicLoad(&tiling_wg_pass_items[li]),
        );
    }
    if (li == 0u) {
        totals.wave_count = scan.y;
    }
}

@compute @workgroup_size(TILING_ITEMS_WORKGROUP_SIZE)
fn write_waves(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    let e = tiling_item_index(gid, groups, TILING_ITEMS_WORKGROUP_SIZE);
    if (e >= params.tiles_x * params.tiles_y * params.pass_count || e >= arrayLength(&masks)) {
        return;
    }
    let t = e / params.pass_count;
    let p = e % params.pass_count;
    let tile = (t % params.tiles_x) | ((t / params.tiles_x) << TILING_WAVE_TILE_Y_SHIFT);
    var bits = masks[e];
    var c = counter_offsets[e];
    while (bits != 0u) {
        let g = firstTrailingBit(bits);
        bits &= bits - 1u;
        if (c < arrayLength(&final_counts) && c < arrayLength(&wave_offsets)) {
            let f = atomicLoad(&final_counts[c]);
            let first = wave_offsets[c];
            var k = 0u;
            var w = 0u;
            while (k < f) {
                if (first + w < arrayLength(&waves)) {
                    waves[first + w] = TilingWaveCommand(
                        tile,
                        p | (g << TILING_WAVE_GROUP_SHIFT),
                        pixel_offsets[c] + k,
                        min(params.wave_width, f - k),
                    );
                }
                k += params.wave_width;
                w += 1u;
            }
        }
        c += 1u;
    }
}
