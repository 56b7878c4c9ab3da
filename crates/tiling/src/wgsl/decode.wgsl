// tiling: the pixel decode every classification pass shares (Rust: tiling::classify,
// "Which pixels are shaded"): bindings 0, 2 and 3 (tiling::pixel adds the vis words at 1),
// so a pass that has the word in hand (gpu's compute laydown unpack) decodes without them.

#import visbuf::id
#import tiling::common

@group(0) @binding(0) var<uniform> params: TilingParams;
// Validity bitmask, bit i % 32 of word i / 32 for pixel i (read only with TILING_FLAG_VALIDITY;
// bind any non-empty buffer otherwise).
@group(0) @binding(2) var<storage, read> valid: array<u32>;
// The MicroBatchInfoTable, indexed by micro-batch ID.
@group(0) @binding(3) var<storage, read> table: array<TilingMicroBatchInfo>;

// The tile of the TILING_BLOCK_SIZE block that workgroup `wid` covers (the pixel phases'
// and laydown finalise's workgroups: a block lies in one tile).
fn tiling_block_tile(wid: vec3<u32>) -> u32 {
    return (wid.y * TILING_BLOCK_SIZE / TILING_TILE_SIZE) * params.tiles_x + wid.x * TILING_BLOCK_SIZE / TILING_TILE_SIZE;
}

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
    // The row's fields one by one: a whole-row load fetches its 64 bytes, these 28.
    let first_id = table[mb].first_id;
    let id_count = table[mb].id_count;
    let pass_index = table[mb].pass_index;
    let batch_group = table[mb].batch_group;
    let primitive_bits = table[mb].primitive_bits;
    let primitive_count = table[mb].primitive_count;
    let instance_count = table[mb].instance_count;
    if (mb < first_id || mb - first_id >= id_count || pass_index >= params.pass_count
        || batch_group >= TILING_MAX_BATCH_GROUPS || primitive_bits > TILING_MAX_PRIMITIVE_BITS) {
        return px;
    }
    let field = visbuf_instance_field(word, primitive_bits);
    let prim = visbuf_primitive(word, primitive_bits);
    let instance = visbuf_instance_index(mb, first_id, field, primitive_bits);
    px.kind = TILING_PX_OUT_OF_RANGE;
    if (instance >= instance_count || prim >= primitive_count) {
        return px;
    }
    return TilingPixel(TILING_PX_VALID, pass_index * TILING_MAX_BATCH_GROUPS + batch_group, mb, instance, prim);
}
