// tiling: constants, buffer structs and helpers shared by every pass (core WGSL, no
// bindings). Every constant equals the Rust constant of the same meaning in the `tiling`
// crate (checked by its unit tests); every struct has the layout of the Rust Pod struct
// named in its comment.

const TILING_TILE_SIZE: u32 = 128u;
const TILING_TILE_SHIFT: u32 = 7u;
const TILING_PIXEL_Y_SHIFT: u32 = 7u;
const TILING_PIXEL_COORD_MASK: u32 = 127u;
const TILING_QUAD_Y_SHIFT: u32 = 6u;
const TILING_QUAD_COORD_MASK: u32 = 63u;
const TILING_QUAD_PIXELS_SHIFT: u32 = 12u;
const TILING_MAX_PASSES: u32 = 256u;
const TILING_MAX_BATCH_GROUPS: u32 = 32u;
const TILING_MAX_PRIMITIVE_BITS: u32 = 16u;
const TILING_CHUNK_SIZE: u32 = 64u;
const TILING_UBER_CHUNKS: u32 = 64u;
const TILING_PYRAMID_FANOUT: u32 = 4u;
// Deltas per workgroup of the vertex wave commands' scan (256 invocations, four each).
const TILING_DELTA_BLOCK: u32 = 1024u;
const TILING_MAX_DISPATCH_X: u32 = 65535u;
// Invocations per workgroup of every one-invocation-per-item entry point
// (`shader::Entry::items` in the descriptions of `tiling::wgsl`).
const TILING_ITEMS_WORKGROUP_SIZE: u32 = 64u;
const TILING_FLAG_VALIDITY: u32 = 1u;
const TILING_FLAG_VRS: u32 = 2u;
const TILING_FLAG_VERTEX_CULL: u32 = 4u;
const TILING_WAVE_TILE_Y_SHIFT: u32 = 16u;
const TILING_WAVE_GROUP_SHIFT: u32 = 8u;
// Bits of one pixel (or quad) command; two share a word of the command buffer.
const TILING_COMMAND_BITS: u32 = 16u;
// (tile, pass) entries a workgroup of the block scans sums (mid classify's
// counter_offsets_pass, classify output's entry_waves), and the words before the entries in
// their scratch buffers (a workgroup counter, pad).
const TILING_ENTRY_BLOCK: u32 = 256u;
const TILING_SCRATCH_ENTRIES: u32 = 4u;
// Pixels across the square block a 16x16 workgroup of the pixel phases, laydown finalise and
// gpu's unpack covers (four pixels an invocation; a block lies in one tile).
const TILING_BLOCK_SIZE: u32 = 32u;
// Invocations of classify output's write_waves per (tile, pass) entry: 16 measured best on
// the H200 beside the scatter (32 launched twice the mostly empty workgroups at 163 passes;
// 4 serialised dense entries' waves).
const TILING_WAVE_ENTRY_LANES: u32 = 16u;
// "No key / no value": larger than any valid key, index or count.
const TILING_NONE: u32 = 0xffffffffu;

// Indices into the stats buffer (Rust: tiling::PixelStats, 8 x u32).
const TILING_STAT_VALID: u32 = 0u;
const TILING_STAT_EMPTY: u32 = 1u;
const TILING_STAT_UNKNOWN: u32 = 2u;
const TILING_STAT_OUT_OF_RANGE: u32 = 3u;
const TILING_STAT_COMMANDS: u32 = 4u;
const TILING_STAT_DROPPED: u32 = 5u;
const TILING_STAT_BAD_INDICES: u32 = 6u;
// The pad field, which stays 0 in the output: the pixel phases' workgroup-only count of
// valid pixels whose VRS sample an earlier pixel carries (tiling::pixel's stats).
const TILING_STAT_NO_SAMPLE: u32 = 7u;
const TILING_STAT_COUNT: u32 = 8u;

// Rust: tiling::TilingParams, 48 bytes (uniform).
struct TilingParams {
    width: u32,
    height: u32,
    tiles_x: u32,
    tiles_y: u32,
    pass_count: u32,
    wave_width: u32,
    flags: u32,
    table_len: u32,
    micro_batch_count: u32,
    chunk_count: u32,
    uber_count: u32,
    pad: u32,
}

// Rust: tiling::MicroBatchInfo, 64 bytes, same field names except `pass_index`. One row
// per micro-batch ID.
struct TilingMicroBatchInfo {
    first_id: u32,
    id_count: u32,
    // Rust `pass` (a WGSL keyword).
    pass_index: u32,
    batch_group: u32,
    primitive_bits: u32,
    primitive_count: u32,
    vertex_count: u32,
    instance_count: u32,
    first_instance: u32,
    batch: u32,
    batch_first_instance: u32,
    first_index: u32,
    base_vertex: u32,
    first_chunk: u32,
    ring_offset: u32,
    order: u32,
}

// Rust: tiling::PassInfo, 32 bytes.
struct TilingPassInfo {
    first_micro_batch: u32,
    micro_batch_count: u32,
    vertex_count: u32,
    first_chunk: u32,
    chunk_count: u32,
    batch_group_count: u32,
    shader: u32,
    pad: u32,
}

// Rust: tiling::WaveCommand, 16 bytes.
struct TilingWaveCommand {
    tile: u32,
    pass_group: u32,
    first_command: u32,
    command_count: u32,
}

// Rust: tiling::PassDispatch, 24 bytes; x, y, z are dispatch_workgroups_indirect's.
struct TilingPassDispatch {
    x: u32,
    y: u32,
    z: u32,
    first: u32,
    count: u32,
    items: u32,
}

// Rust: tiling::UberChunk, 16 bytes.
struct TilingUberChunk {
    mask_lo: u32,
    mask_hi: u32,
    count: u32,
    pad: u32,
}

// Rust: tiling::VertexWaveCommand, 8 bytes.
struct TilingVertexWaveCommand {
    micro_batch: u32,
    chunk: u32,
}

// Rust: tiling::Totals, 16 bytes.
struct TilingTotals {
    counter_count: u32,
    command_count: u32,
    wave_count: u32,
    visible_chunks: u32,
}

// The indirect arguments of `count` commands from `first` (Rust: PassDispatch::new).
fn tiling_dispatch(first: u32, count: u32, items: u32) -> TilingPassDispatch {
    let x = min(count, TILING_MAX_DISPATCH_X);
    let y = (count + TILING_MAX_DISPATCH_X - 1u) / TILING_MAX_DISPATCH_X;
    return TilingPassDispatch(x, y, select(0u, 1u, count != 0u), first, count, items);
}

// The item index of an invocation of a `shader::Dispatch::Items` entry point with `size`
// invocations per workgroup; `gid` is its @builtin(global_invocation_id), `groups` its
// @builtin(num_workgroups). The dispatch is `[n, 1, 1]` up to TILING_MAX_DISPATCH_X
// workgroups (gid.y = 0) and `[TILING_MAX_DISPATCH_X, rows, 1]` past that, so this is
// `gid.y * TILING_MAX_DISPATCH_X * size + gid.x` in both shapes.
fn tiling_item_index(gid: vec3<u32>, groups: vec3<u32>, size: u32) -> u32 {
    return gid.y * groups.x * size + gid.x;
}

// Tile (x, y) of a wave command's `tile` word (Rust: WaveCommand::tile_xy).
fn tiling_wave_tile_xy(tile: u32) -> vec2<u32> {
    return vec2<u32>(tile & ((1u << TILING_WAVE_TILE_Y_SHIFT) - 1u), tile >> TILING_WAVE_TILE_Y_SHIFT);
}

// Command `i` of a command buffer, given the word that holds it: two 16-bit commands per
// word, command i in bits 16 (i % 2).. of word i / 2 (classify output's `commands`).
fn tiling_command_in_word(word: u32, i: u32) -> u32 {
    return (word >> (TILING_COMMAND_BITS * (i & 1u))) & ((1u << TILING_COMMAND_BITS) - 1u);
}

// (x, y) within its tile of a standard-layout pixel command (Rust: unpack_pixel_command).
fn tiling_unpack_pixel_command(cmd: u32) -> vec2<u32> {
    return vec2<u32>(cmd & TILING_PIXEL_COORD_MASK, (cmd >> TILING_PIXEL_Y_SHIFT) & TILING_PIXEL_COORD_MASK);
}

// a + b, or TILING_NONE when it would wrap.
fn tiling_add_sat(a: u32, b: u32) -> u32 {
    if (a > TILING_NONE - b) {
        return TILING_NONE;
    }
    return a + b;
}

// a * b, or TILING_NONE when it would wrap. Exact through 16-bit halves: a division by a
// variable costs tens of instructions on the per-pixel paths.
fn tiling_mul_sat(a: u32, b: u32) -> u32 {
    let half = 16u;
    let low = (1u << half) - 1u;
    let ah = a >> half;
    let al = a & low;
    let bh = b >> half;
    let bl = b & low;
    if (ah != 0u && bh != 0u) {
        return TILING_NONE;
    }
    // One of ah, bh is 0, so this is below 2^32.
    let cross = ah * bl + al * bh;
    if (cross > low) {
        return TILING_NONE;
    }
    return tiling_add_sat(al * bl, cross << half);
}

// A workgroup-wide exclusive prefix sum over 256 invocations (Hillis-Steele in workgroup
// memory, each step reading one half of the buffer and writing the other, so one barrier a
// step): returns (this invocation's exclusive prefix, the workgroup's total). Call from
// uniform control flow with @workgroup_size(256).
var<workgroup> tiling_scan_buf: array<u32, 512>;

fn tiling_wg_scan(li: u32, value: u32) -> vec2<u32> {
    var inclusive = value;
    var src = 0u;
    tiling_scan_buf[li] = value;
    workgroupBarrier();
    for (var d = 1u; d < 256u; d = d * 2u) {
        if (li >= d) {
            inclusive += tiling_scan_buf[src + li - d];
        }
        src = 256u - src;
        tiling_scan_buf[src + li] = inclusive;
        workgroupBarrier();
    }
    let total = tiling_scan_buf[src + 255u];
    workgroupBarrier();
    return vec2<u32>(inclusive - value, total);
}

// The half-open slice [begin, end) of `n` items that invocation `li` of 256 walks in the
// single-workgroup scans (contiguous ranges, so each thread's items are consecutive).
fn tiling_wg_range(li: u32, n: u32) -> vec2<u32> {
    let per = (n + 255u) / 256u;
    let begin = min(li * per, n);
    return vec2<u32>(begin, min(begin + per, n));
}
