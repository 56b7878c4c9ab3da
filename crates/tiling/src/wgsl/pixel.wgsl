// tiling: the per-pixel part shared by the three classification passes: their first four
// bindings and the pixel decode (Rust: tiling::classify, "Which pixels are shaded").

#import visbuf::id
#import tiling::common

@group(0) @binding(0) var<uniform> params: TilingParams;
// width * height vis words, row-major.
@group(0) @binding(1) var<storage, read> vis: array<u32>;
// Validity bitmask, bit i % 32 of word i / 32 for pixel i (read only with TILING_FLAG_VALIDITY;
// bind any non-empty buffer otherwise).
@group(0) @binding(2) var<storage, read> valid: array<u32>;
// The MicroBatchInfoTable, indexed by micro-batch ID.
@group(0) @binding(3) var<storage, read> table: array<TilingMicroBatchInfo>;

// The pixel phases' workgroups: 16x16 invocations, each a 2x2 quad of pixels, so a
// workgroup covers a 32x32 block of one 128x128 tile. Four pixels an invocation keep four
// vis loads in flight and cut the workgroups (and their barriers) by four: the phases are
// bound by latency, not bandwidth.
const TILING_BLOCK_SIZE: u32 = 32u;

// The tile of the block that workgroup `wid` covers.
fn tiling_block_tile(wid: vec3<u32>) -> u32 {
    return (wid.y * TILING_BLOCK_SIZE / TILING_TILE_SIZE) * params.tiles_x + wid.x * TILING_BLOCK_SIZE / TILING_TILE_SIZE;
}

// Pixel k (0..4: x = k % 2, y = k / 2) of invocation `gid`'s quad.
fn tiling_quad_pixel(gid: vec3<u32>, k: u32) -> vec2<u32> {
    return vec2<u32>(2u * gid.x + (k & 1u), 2u * gid.y + (k >> 1u));
}

// The row-major index of invocation `gid`'s quad among ceil(width / 2) x ceil(height / 2)
// (TILING_NONE past them).
fn tiling_quad_index(gid: vec3<u32>) -> u32 {
    let quads = vec2<u32>((params.width + 1u) / 2u, (params.height + 1u) / 2u);
    if (gid.x >= quads.x || gid.y >= quads.y) {
        return TILING_NONE;
    }
    return gid.y * quads.x + gid.x;
}

// The vis word of pixel k of invocation `gid`'s quad (VISBUF_NONE outside the image).
fn tiling_quad_word(gid: vec3<u32>, k: u32) -> u32 {
    let p = tiling_quad_pixel(gid, k);
    if (p.x >= params.width || p.y >= params.height) {
        return VISBUF_NONE;
    }
    return tiling_word(p.y * params.width + p.x);
}

// The vis words of invocation `gid`'s quad, loaded together before any is decoded. The
// quad's four pixels are spelled out here and in the passes, never indexed by a loop
// variable: a dynamically indexed vector lives in local memory on the H200 (the passes
// measured up to 1.7x slower).
fn tiling_quad_words(gid: vec3<u32>) -> vec4<u32> {
    return vec4<u32>(tiling_quad_word(gid, 0u), tiling_quad_word(gid, 1u), tiling_quad_word(gid, 2u), tiling_quad_word(gid, 3u));
}

// count_pixels' record of each pixel (the `slots` buffer, a vec4 per quad), which classify output's
// scatter_commands turns into a command without decoding the vis word again (frames
// without a validity mask, where the two phases classify alike). With a command: bit 31,
// the slot within its counter (bits 0-13: a counter holds at most 128 * 128 pixels), the
// counter's index within its tile's (bits 14-26), the sample mask (bits 27-30). Without
// one: the pixel's TILING_PX_* kind (bits 0-1) and TILING_RECORD_DROPPED.
const TILING_RECORD_COMMAND: u32 = 1u << 31u;
const TILING_RECORD_DROPPED: u32 = 4u;
const TILING_RECORD_COUNTER_SHIFT: u32 = 14u;
const TILING_RECORD_SLOT_MASK: u32 = (1u << TILING_RECORD_COUNTER_SHIFT) - 1u;
const TILING_RECORD_MASK_SHIFT: u32 = 27u;
const TILING_RECORD_COUNTER_MASK: u32 = (1u << (TILING_RECORD_MASK_SHIFT - TILING_RECORD_COUNTER_SHIFT)) - 1u;

const TILING_PX_EMPTY: u32 = 0u;
const TILING_PX_UNKNOWN: u32 = 1u;
const TILING_PX_OUT_OF_RANGE: u32 = 2u;
const TILING_PX_VALID: u32 = 3u;

struct TilingPixel {
    // TILING_PX_*.
    kind: u32,
    // pass * 32 + batch group.
    pg: u32,
    // Micro-batch ID (table row).
    mb: u32,
    // Instance within the micro batch.
    instance: u32,
    // Primitive within the geometry.
    prim: u32,
}

fn tiling_valid_bit(i: u32) -> bool {
    if ((params.flags & TILING_FLAG_VALIDITY) == 0u) {
        return true;
    }
    let w = i >> 5u;
    if (w >= arrayLength(&valid)) {
        return false;
    }
    return ((valid[w] >> (i & 31u)) & 1u) == 1u;
}

fn tiling_vrs() -> bool {
    return (params.flags & TILING_FLAG_VRS) != 0u;
}

// The word of pixel i, or VISBUF_NONE outside the buffer.
fn tiling_word(i: u32) -> u32 {
    if (i >= arrayLength(&vis)) {
        return VISBUF_NONE;
    }
    return vis[i];
}

// Classifies the word of pixel i (the same rules as the CPU decoder).
fn tiling_decode(word: u32, i: u32) -> TilingPixel {
    var px = TilingPixel(TILING_PX_EMPTY, 0u, 0u, 0u, 0u);
    if (visbuf_is_none(word) || !tiling_valid_bit(i)) {
        return px;
    }
    var mb = visbuf_micro_batch(word);
    var reserved = VISBUF_MICRO_BATCH_IDS - 1u;
    if (tiling_vrs()) {
        mb = visbuf_micro_batch_vrs(word);
        reserved = VISBUF_MICRO_BATCH_IDS_VRS - 1u;
    }
    px.kind = TILING_PX_UNKNOWN;
    if (mb == reserved || mb >= params.table_len || mb >= arrayLength(&table)) {
        return px;
    }
    let row = table[mb];
    if (mb < row.first_id || mb - row.first_id >= row.id_count || row.pass_index >= params.pass_count
        || row.batch_group >= TILING_MAX_BATCH_GROUPS || row.primitive_bits > TILING_MAX_PRIMITIVE_BITS) {
        return px;
    }
    let field = visbuf_instance_field(word, row.primitive_bits);
    let prim = visbuf_primitive(word, row.primitive_bits);
    let instance = visbuf_instance_index(mb, row.first_id, field, row.primitive_bits);
    px.kind = TILING_PX_OUT_OF_RANGE;
    if (instance >= row.instance_count || prim >= row.primitive_count) {
        return px;
    }
    return TilingPixel(TILING_PX_VALID, row.pass_index * TILING_MAX_BATCH_GROUPS + row.batch_group, mb, instance, prim);
}

// With VRS: the pixel mask (bit 2 dy + dx of the quad) of the shading sample that valid
// pixel (x, y) with word `word` carries, or 0 when an earlier pixel of its block carries
// it. Without VRS: the pixel's own bit (never 0). Rust: tiling::vrs::sample_mask.
fn tiling_sample_mask(x: u32, y: u32, word: u32) -> u32 {
    var size = vec2<u32>(1u, 1u);
    if (tiling_vrs()) {
        size = visbuf_rate_size(visbuf_shading_rate_vrs(word));
    }
    if (size.x == 1u && size.y == 1u) {
        return 1u << (((y & 1u) << 1u) | (x & 1u));
    }
    let bx = x & ~(size.x - 1u);
    let by = y & ~(size.y - 1u);
    var mask = 0u;
    for (var py = by; py < min(by + size.y, params.height); py++) {
        for (var px = bx; px < min(bx + size.x, params.width); px++) {
            let i = py * params.width + px;
            if (tiling_word(i) != word || !tiling_valid_bit(i)) {
                continue;
            }
            if (py < y || (py == y && px < x)) {
                return 0u;
            }
            mask |= 1u << (((py & 1u) << 1u) | (px & 1u));
        }
    }
    return mask;
}

// The 16-bit command of the sample at (x, y) with pixel mask `mask`, relative to its tile:
// a pixel command (x | y << 7) or, with VRS, a quad command.
fn tiling_command(x: u32, y: u32, mask: u32) -> u32 {
    let tx = x & TILING_PIXEL_COORD_MASK;
    let ty = y & TILING_PIXEL_COORD_MASK;
    if (tiling_vrs()) {
        return ((tx >> 1u) & TILING_QUAD_COORD_MASK) | (((ty >> 1u) & TILING_QUAD_COORD_MASK) << TILING_QUAD_Y_SHIFT)
            | ((mask & 15u) << TILING_QUAD_PIXELS_SHIFT);
    }
    return tx | (ty << TILING_PIXEL_Y_SHIFT);
}

// Per-workgroup stats, flushed with one atomic per field. (Counting per invocation and
// summing per subgroup first measured slower on the H200: the passes are bound by
// instructions and latency, not by these shared atomics.)
var<workgroup> tiling_wg_stats: array<atomic<u32>, 8>;

fn tiling_stats_begin(li: u32) {
    if (li < TILING_STAT_COUNT) {
        atomicStore(&tiling_wg_stats[li], 0u);
    }
    workgroupBarrier();
}

fn tiling_stat(field: u32, n: u32) {
// Timing experiment only (gpu's `classify_variants`): no stats atomics, wrong stats.
#if !timing_omit_stats
    if (n != 0u) {
        atomicAdd(&tiling_wg_stats[field], n);
    }
#endif
}

// Counts the pixel's kind.
fn tiling_stat_pixel(px: TilingPixel) {
    switch (px.kind) {
        case 0u: { tiling_stat(TILING_STAT_EMPTY, 1u); }
        case 1u: { tiling_stat(TILING_STAT_UNKNOWN, 1u); }
        case 2u: { tiling_stat(TILING_STAT_OUT_OF_RANGE, 1u); }
        default: { tiling_stat(TILING_STAT_VALID, 1u); }
    }
}
