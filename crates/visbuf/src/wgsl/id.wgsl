// visbuf: the 32-bit vis-buffer ID (Horizon Forbidden West). Binding-free; every constant is
// checked against the Rust crate `visbuf` by its unit tests.
//
//   standard: [31..16 micro batch | 15..p instance field | p-1..0 primitive]
//   VRS:      [31..30 rate | 29..16 micro batch | 15..p instance field | p-1..0 primitive]
// p = primitive bits = ceil(log2(primitive count)), stored per micro batch, not in the word.

const VISBUF_NONE: u32 = 0xffffffffu;
const VISBUF_MICRO_BATCH_SHIFT: u32 = 16u;
const VISBUF_MICRO_BATCH_MASK: u32 = 0xffffu;
const VISBUF_MICRO_BATCH_MASK_VRS: u32 = 0x3fffu;
const VISBUF_RATE_SHIFT: u32 = 30u;
const VISBUF_RATE_MASK: u32 = 3u;
// ShadingRate codes of the VRS layout's rate field.
const VISBUF_RATE_2X1: u32 = 2u;
const VISBUF_RATE_2X2: u32 = 3u;
const VISBUF_INSTANCE_PRIMITIVE_BITS: u32 = 16u;
const VISBUF_INSTANCE_PRIMITIVE_MASK: u32 = 0xffffu;
const VISBUF_MAX_PRIMITIVE_BITS: u32 = 16u;
const VISBUF_MICRO_BATCH_IDS: u32 = 65536u;
const VISBUF_MICRO_BATCH_IDS_VRS: u32 = 16384u;

// One batch's micro-batch-ID range (Rust: visbuf::VisbufIdRange, 16 bytes).
struct VisbufIdRange {
    first_id: u32,
    id_count: u32,
    instance_count: u32,
    primitive_count: u32,
}

fn visbuf_is_none(word: u32) -> bool {
    return word == VISBUF_NONE;
}

// Micro-batch ID, standard layout (16 bits).
fn visbuf_micro_batch(word: u32) -> u32 {
    return (word >> VISBUF_MICRO_BATCH_SHIFT) & VISBUF_MICRO_BATCH_MASK;
}

// Micro-batch ID, VRS layout (14 bits).
fn visbuf_micro_batch_vrs(word: u32) -> u32 {
    return (word >> VISBUF_MICRO_BATCH_SHIFT) & VISBUF_MICRO_BATCH_MASK_VRS;
}

// Shading-rate code, VRS layout: 0 = 1x1, 1 = 1x2, 2 = 2x1, 3 = 2x2 (width x height);
// bit 0 = log2(height), bit 1 = log2(width).
fn visbuf_shading_rate_vrs(word: u32) -> u32 {
    return (word >> VISBUF_RATE_SHIFT) & VISBUF_RATE_MASK;
}

// Block size (width, height) in pixels of a rate code.
fn visbuf_rate_size(rate: u32) -> vec2<u32> {
    return vec2<u32>(1u + ((rate >> 1u) & 1u), 1u + (rate & 1u));
}

// Instance field: bits 15..p. primitive_bits must be 0..=16.
fn visbuf_instance_field(word: u32, primitive_bits: u32) -> u32 {
    return (word & VISBUF_INSTANCE_PRIMITIVE_MASK) >> primitive_bits;
}

// Primitive index: bits p-1..0. primitive_bits must be 0..=16.
fn visbuf_primitive(word: u32, primitive_bits: u32) -> u32 {
    return word & ((1u << primitive_bits) - 1u);
}

// ceil(log2(n)) for n in 1..=65536 (0 for n = 1); clamped to 16 above, 0 for n = 0.
fn visbuf_primitive_bits(primitive_count: u32) -> u32 {
    if (primitive_count <= 1u) {
        return 0u;
    }
    return min(32u - countLeadingZeros(primitive_count - 1u), VISBUF_MAX_PRIMITIVE_BITS);
}

// Standard-layout word; each field is masked to its width.
fn visbuf_pack_id(micro_batch: u32, instance_field: u32, primitive: u32, primitive_bits: u32) -> u32 {
    let low = ((instance_field << primitive_bits) | (primitive & ((1u << primitive_bits) - 1u)))
        & VISBUF_INSTANCE_PRIMITIVE_MASK;
    return ((micro_batch & VISBUF_MICRO_BATCH_MASK) << VISBUF_MICRO_BATCH_SHIFT) | low;
}

// VRS-layout word; each field is masked to its width.
fn visbuf_pack_id_vrs(rate: u32, micro_batch: u32, instance_field: u32, primitive: u32, primitive_bits: u32) -> u32 {
    let low = ((instance_field << primitive_bits) | (primitive & ((1u << primitive_bits) - 1u)))
        & VISBUF_INSTANCE_PRIMITIVE_MASK;
    return ((rate & VISBUF_RATE_MASK) << VISBUF_RATE_SHIFT)
        | ((micro_batch & VISBUF_MICRO_BATCH_MASK_VRS) << VISBUF_MICRO_BATCH_SHIFT) | low;
}

// Instance index within its batch: (micro_batch - first) * 2^(16 - p) + field (wrapping).
fn visbuf_instance_index(micro_batch: u32, first_micro_batch: u32, instance_field: u32, primitive_bits: u32) -> u32 {
    return ((micro_batch - first_micro_batch) << (VISBUF_INSTANCE_PRIMITIVE_BITS - primitive_bits)) | instance_field;
}

// The (micro batch, instance field) that instance `instance` of a batch starting at
// `first_micro_batch` is written with.
fn visbuf_split_instance(first_micro_batch: u32, instance: u32, primitive_bits: u32) -> vec2<u32> {
    let ibits = VISBUF_INSTANCE_PRIMITIVE_BITS - primitive_bits;
    return vec2<u32>(first_micro_batch + (instance >> ibits), instance & ((1u << ibits) - 1u));
}
