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

// Per-workgroup stats, flushed with one atomic per field.
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
