// tiling: vertex wave commands from the vertex cull buffer (Rust twin:
// tiling::vertex_wave_commands). Entry points, in this order (dispatches and zeroed
// buffers: `tiling::VERTEX_WAVES`): uber_chunks, build_pyramid, micro_batch_deltas,
// delta_block_sums, scan_delta_blocks, scan_deltas, write_vertex_commands, pass_args.

#import tiling::common

@group(0) @binding(0) var<uniform> params: TilingParams;
// The MicroBatchInfoTable, indexed by micro-batch ID.
@group(0) @binding(1) var<storage, read> table: array<TilingMicroBatchInfo>;
// The micro-batch order buffer: first micro-batch ID of each micro batch, in order.
@group(0) @binding(2) var<storage, read> order: array<u32>;
// The passes (tiling::PassInfo).
@group(0) @binding(3) var<storage, read> pass_infos: array<TilingPassInfo>;
// One byte per 64-vertex chunk, four per word (mid classify's output).
@group(0) @binding(4) var<storage, read> vertex_cull: array<u32>;
// One per 64 chunks.
@group(0) @binding(5) var<storage, read_write> ubers: array<TilingUberChunk>;
// The histogram pyramid, levels bottom first (tiling::vertex::pyramid_levels).
@group(0) @binding(6) var<storage, read_write> pyramid: array<u32>;
// Per visible chunk: micro-batch-ID deltas, then (after scan_deltas) the IDs. Zero first;
// at least as long as the visible chunks (chunk_count is always enough).
@group(0) @binding(7) var<storage, read_write> deltas: array<atomic<u32>>;
// Per order entry: its vertex waves.
@group(0) @binding(8) var<storage, read_write> micro_batch_waves: array<u32>;
// One per visible chunk.
@group(0) @binding(9) var<storage, read_write> vertex_commands: array<TilingVertexWaveCommand>;
// Per pass: the vertex-transform dispatch.
@group(0) @binding(10) var<storage, read_write> vertex_dispatches: array<TilingPassDispatch>;
// Per pass: vertices in visible chunks. Zero first.
@group(0) @binding(11) var<storage, read_write> pass_items: array<atomic<u32>>;
// visible_chunks (written by build_pyramid).
@group(0) @binding(12) var<storage, read_write> totals: TilingTotals;
// Per TILING_DELTA_BLOCK deltas: their sum (delta_block_sums), then the sum of the blocks
// before it (scan_delta_blocks).
@group(0) @binding(13) var<storage, read_write> delta_blocks: array<u32>;

// Levels of the pyramid over `uber_count` entries (at least one level of length 1).
fn tiling_level_count() -> u32 {
    var len = max(params.uber_count, 1u);
    var n = 1u;
    while (len > 1u) {
        len = (len + TILING_PYRAMID_FANOUT - 1u) / TILING_PYRAMID_FANOUT;
        n += 1u;
    }
    return n;
}

// (offset, length) of level k.
fn tiling_level(k: u32) -> vec2<u32> {
    var len = max(params.uber_count, 1u);
    var offset = 0u;
    for (var i = 0u; i < k; i++) {
        offset += len;
        len = (len + TILING_PYRAMID_FANOUT - 1u) / TILING_PYRAMID_FANOUT;
    }
    return vec2<u32>(offset, len);
}

fn tiling_pyramid(i: u32) -> u32 {
    if (i >= arrayLength(&pyramid)) {
        return 0u;
    }
    return pyramid[i];
}

// Visible chunks in all.
fn tiling_total() -> u32 {
    return tiling_pyramid(tiling_level(tiling_level_count() - 1u).x);
}

// Sum of the counts of uber chunks 0..u.
fn tiling_prefix(u: u32) -> u32 {
    var sum = 0u;
    var idx = u;
    let levels = tiling_level_count();
    for (var k = 0u; k < levels; k++) {
        let l = tiling_level(k);
        for (var j = idx / TILING_PYRAMID_FANOUT * TILING_PYRAMID_FANOUT; j < min(idx, l.y); j++) {
            sum += tiling_pyramid(l.x + j);
        }
        idx /= TILING_PYRAMID_FANOUT;
    }
    return sum;
}

fn tiling_uber_mask(u: u32) -> vec2<u32> {
    if (u >= arrayLength(&ubers)) {
        return vec2<u32>(0u, 0u);
    }
    return vec2<u32>(ubers[u].mask_lo, ubers[u].mask_hi);
}

// Visible chunks before global chunk `chunk`.
fn tiling_rank_of_chunk(chunk: u32) -> u32 {
    let u = chunk / TILING_UBER_CHUNKS;
    if (u >= params.uber_count) {
        return tiling_total();
    }
    let below = chunk % TILING_UBER_CHUNKS;
    let m = tiling_uber_mask(u);
    var n = 0u;
    if (below >= 32u) {
        n = countOneBits(m.x) + countOneBits(m.y & ((1u << (below - 32u)) - 1u));
    } else {
        n = countOneBits(m.x & ((1u << below) - 1u));
    }
    return tiling_prefix(u) + n;
}

// The n-th set bit of a 32-bit mask (32 if there are not that many).
fn tiling_nth_bit32(mask: u32, n: u32) -> u32 {
    var m = mask;
    for (var i = 0u; i < n; i++) {
        m &= m - 1u;
    }
    if (m == 0u) {
        return 32u;
    }
    return firstTrailingBit(m);
}

// (uber chunk, child rank) of linear work index i < total.
fn tiling_locate(i: u32) -> vec2<u32> {
    var rest = i;
    var node = 0u;
    let levels = tiling_level_count();
    for (var k = levels - 1u; k > 0u; k--) {
        let l = tiling_level(k - 1u);
        var next = node * TILING_PYRAMID_FANOUT;
        for (var c = 0u; c < TILING_PYRAMID_FANOUT; c++) {
            let child = node * TILING_PYRAMID_FANOUT + c;
            if (child >= l.y) {
                break;
            }
            next = child;
            let n = tiling_pyramid(l.x + child);
            if (rest < n) {
                break;
            }
            rest -= n;
        }
        node = next;
    }
    return vec2<u32>(node, rest);
}

// 64-vertex chunks of a micro batch, ceil(instance_count * vertex_count / 64), exactly
// (saturating past u32): with vertex_count = 64 a + b, instance_count = 64 q + r it is
// instance_count a + q b + ceil(r b / 64).
fn tiling_chunk_count(row: TilingMicroBatchInfo) -> u32 {
    let a = row.vertex_count / TILING_CHUNK_SIZE;
    let b = row.vertex_count % TILING_CHUNK_SIZE;
    let q = row.instance_count / TILING_CHUNK_SIZE;
    let r = row.instance_count % TILING_CHUNK_SIZE;
    return tiling_add_sat(tiling_add_sat(tiling_mul_sat(row.instance_count, a), q * b), (r * b + 63u) / 64u);
}

@compute @workgroup_size(TILING_ITEMS_WORKGROUP_SIZE)
fn uber_chunks(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    let u = tiling_item_index(gid, groups, TILING_ITEMS_WORKGROUP_SIZE);
    if (u >= params.uber_count) {
        return;
    }
    var lo = 0u;
    var hi = 0u;
    for (var w = 0u; w < 16u; w++) {
        let word_index = u * 16u + w;
        var word = 0u;
        if (word_index < arrayLength(&vertex_cull)) {
            word = vertex_cull[word_index];
        }
        for (var b = 0u; b < 4u; b++) {
            let j = w * 4u + b;
            let chunk = u * TILING_UBER_CHUNKS + j;
            if (chunk < params.chunk_count && ((word >> (b * 8u)) & 0xffu) != 0u) {
                if (j < 32u) {
                    lo |= 1u << j;
                } else {
                    hi |= 1u << (j - 32u);
                }
            }
        }
    }
    let count = countOneBits(lo) + countOneBits(hi);
    if (u < arrayLength(&ubers)) {
        ubers[u] = TilingUberChunk(lo, hi, count, 0u);
    }
    if (u < arrayLength(&pyramid)) {
        pyramid[u] = count;
    }
}

@compute @workgroup_size(256)
fn build_pyramid(@builtin(local_invocation_index) li: u32) {
    if (params.uber_count == 0u && li == 0u && arrayLength(&pyramid) > 0u) {
        pyramid[0] = 0u;
    }
    storageBarrier();
    workgroupBarrier();
    let levels = tiling_level_count();
    for (var k = 1u; k < levels; k++) {
        let below = tiling_level(k - 1u);
        let here = tiling_level(k);
        for (var i = li; i < here.y; i += 256u) {
            var s = 0u;
            for (var c = 0u; c < TILING_PYRAMID_FANOUT; c++) {
                let child = i * TILING_PYRAMID_FANOUT + c;
                if (child < below.y) {
                    s += tiling_pyramid(below.x + child);
                }
            }
            if (here.x + i < arrayLength(&pyramid)) {
                pyramid[here.x + i] = s;
            }
        }
        storageBarrier();
        workgroupBarrier();
    }
    if (li == 0u) {
        totals.visible_chunks = tiling_total();
    }
}

@compute @workgroup_size(TILING_ITEMS_WORKGROUP_SIZE)
fn micro_batch_deltas(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    let k = tiling_item_index(gid, groups, TILING_ITEMS_WORKGROUP_SIZE);
    if (k >= params.micro_batch_count || k >= arrayLength(&order)) {
        return;
    }
    let id = order[k];
    if (id >= params.table_len || id >= arrayLength(&table)) {
        return;
    }
    let row = table[id];
    let chunks = tiling_chunk_count(row);
    let first = row.first_chunk;
    let start = tiling_rank_of_chunk(first);
    let end = tiling_rank_of_chunk(tiling_add_sat(first, chunks));
    if (k < arrayLength(&micro_batch_waves)) {
        micro_batch_waves[k] = end - start;
    }
    var prev = 0u;
    if (k > 0u) {
        prev = order[k - 1u];
    }
    if (start < tiling_total() && start < arrayLength(&deltas)) {
        atomicAdd(&deltas[start], id - prev);
    }
    // Vertices of its visible chunks: 64 each, less what its last chunk lacks.
    var vertices = (end - start) * TILING_CHUNK_SIZE;
    if (chunks > 0u && end > start) {
        let last = first + chunks - 1u;
        let m = tiling_uber_mask(last / TILING_UBER_CHUNKS);
        let bit = last % TILING_UBER_CHUNKS;
        var visible = 0u;
        if (bit < 32u) {
            visible = (m.x >> bit) & 1u;
        } else {
            visible = (m.y >> (bit - 32u)) & 1u;
        }
        let tail = ((row.instance_count % TILING_CHUNK_SIZE) * (row.vertex_count % TILING_CHUNK_SIZE)) % TILING_CHUNK_SIZE;
        if (visible == 1u && tail != 0u) {
            vertices -= TILING_CHUNK_SIZE - tail;
        }
    }
    if (row.pass_index < arrayLength(&pass_items)) {
        atomicAdd(&pass_items[row.pass_index], vertices);
    }
}

// The deltas' inclusive prefix sum, over the GPU: each workgroup of delta_block_sums and
// scan_deltas takes a block of TILING_DELTA_BLOCK deltas, four consecutive ones an
// invocation: a single workgroup walking hundreds of thousands of deltas is a long serial
// chain per invocation.

// Deltas to scan: the visible chunks.
fn tiling_delta_count() -> u32 {
    return min(tiling_total(), arrayLength(&deltas));
}

// Blocks of the scan over `n` deltas (no overflow near 2^32).
fn tiling_delta_blocks(n: u32) -> u32 {
    return n / TILING_DELTA_BLOCK + select(0u, 1u, n % TILING_DELTA_BLOCK != 0u);
}

// Invocation li's four deltas of block `block` (zero past the n deltas) and the
// workgroup's scan of their sums (exclusive, total). Contains barriers: call from uniform
// control flow.
struct TilingDeltaBlock {
    deltas: vec4<u32>,
    scan: vec2<u32>,
}

fn tiling_delta_block(block: u32, li: u32, n: u32) -> TilingDeltaBlock {
    var v = vec4<u32>(0u);
    if (block < tiling_delta_blocks(n)) {
        let first = block * TILING_DELTA_BLOCK + li * 4u;
        for (var k = 0u; k < 4u; k++) {
            if (first + k < n) {
                v[k] = atomicLoad(&deltas[first + k]);
            }
        }
    }
    return TilingDeltaBlock(v, tiling_wg_scan(li, v.x + v.y + v.z + v.w));
}

// Per block: the sum of its deltas (wrapping, as the IDs' deltas are).
@compute @workgroup_size(256)
fn delta_block_sums(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
) {
    let block = wid.y * groups.x + wid.x;
    let n = tiling_delta_count();
    let sum = tiling_delta_block(block, li, n).scan.y;
    if (li == 0u && block < tiling_delta_blocks(n) && block < arrayLength(&delta_blocks)) {
        delta_blocks[block] = sum;
    }
}

// One workgroup: the block sums in place into the sums of the blocks before each.
@compute @workgroup_size(256)
fn scan_delta_blocks(@builtin(local_invocation_index) li: u32) {
    let blocks = min(tiling_delta_blocks(tiling_delta_count()), arrayLength(&delta_blocks));
    let r = tiling_wg_range(li, blocks);
    var sum = 0u;
    for (var b = r.x; b < r.y; b++) {
        sum += delta_blocks[b];
    }
    var run = tiling_wg_scan(li, sum).x;
    for (var b = r.x; b < r.y; b++) {
        let v = delta_blocks[b];
        delta_blocks[b] = run;
        run += v;
    }
}

// Per block: the deltas in place into the micro-batch IDs (the blocks before it, then the
// workgroup's exclusive scan, then the invocation's four).
@compute @workgroup_size(256)
fn scan_deltas(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
) {
    let block = wid.y * groups.x + wid.x;
    let n = tiling_delta_count();
    let d = tiling_delta_block(block, li, n);
    let v = d.deltas;
    var run = d.scan.x;
    if (block >= tiling_delta_blocks(n) || block >= arrayLength(&delta_blocks)) {
        return;
    }
    run += delta_blocks[block];
    let first = block * TILING_DELTA_BLOCK + li * 4u;
    for (var k = 0u; k < 4u; k++) {
        if (first + k < n) {
            run += v[k];
            atomicStore(&deltas[first + k], run);
        }
    }
}

@compute @workgroup_size(TILING_ITEMS_WORKGROUP_SIZE)
fn write_vertex_commands(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    let i = tiling_item_index(gid, groups, TILING_ITEMS_WORKGROUP_SIZE);
    if (i >= tiling_total() || i >= arrayLength(&deltas) || i >= arrayLength(&vertex_commands)) {
        return;
    }
    let id = atomicLoad(&deltas[i]);
    let at = tiling_locate(i);
    let m = tiling_uber_mask(at.x);
    var bit = tiling_nth_bit32(m.x, at.y);
    if (bit == 32u) {
        bit = 32u + tiling_nth_bit32(m.y, at.y - countOneBits(m.x));
    }
    let chunk = at.x * TILING_UBER_CHUNKS + bit;
    var first = 0u;
    if (id < arrayLength(&table)) {
        first = table[id].first_chunk;
    }
    vertex_commands[i] = TilingVertexWaveCommand(id, chunk - first);
}

@compute @workgroup_size(TILING_ITEMS_WORKGROUP_SIZE)
fn pass_args(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    let p = tiling_item_index(gid, groups, TILING_ITEMS_WORKGROUP_SIZE);
    if (p >= params.pass_count || p >= arrayLength(&pass_infos) || p >= arrayLength(&vertex_dispatches)) {
        return;
    }
    let info = pass_infos[p];
    let first = tiling_rank_of_chunk(info.first_chunk);
    let end = tiling_rank_of_chunk(tiling_add_sat(info.first_chunk, info.chunk_count));
    var items = 0u;
    if (p < arrayLength(&pass_items)) {
        items = atomicLoad(&pass_items[p]);
    }
    vertex_dispatches[p] = tiling_dispatch(first, end - first, items);
}
