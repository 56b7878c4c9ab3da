// wave: common part (core WGSL, no capability needed), imported by `wave::subgroup` and
// `wave::workgroup`.
//
// An aggregated append is three steps at the call site, the same for both paths
// (`li` is @builtin(local_invocation_index); `wave_append_*` are `wave::append`'s, bound
// to the subgroup or the workgroup path by the `subgroups` feature):
//
//   let a = wave_append_begin(keep, li);         // or wave_sg_append_begin / wave_wg_append_begin
//   var old = 0u;
//   if (a.total != 0u) { old = atomicAdd(&counter, a.total); }   // one atomic per wave
//   let slot = wave_append_end(a, old);          // or wave_sg_append_end / wave_wg_append_end
//   if (slot < arrayLength(&out)) { out[slot] = item; }
//
// The atomic stays at the call site because naga accepts no storage or workgroup pointer
// arguments, so the counter can be any `atomic<u32>` the pass has: a binding, an array
// element, a struct field.

// f32 to a u32 with the same order (-0 below +0), for atomicMax / atomicMin on floats
// (keep a minimum as the maximum of the complemented words: zero memory is neutral).
// Rust: wave::ordered_f32.
fn wave_ordered_f32(f: f32) -> u32 {
    let b = bitcast<u32>(f);
    return select(b | 0x80000000u, ~b, (b & 0x80000000u) != 0u);
}

// Inverse of wave_ordered_f32. Rust: wave::unordered_f32.
fn wave_unordered_f32(u: u32) -> f32 {
    return bitcast<f32>(select(~u, u & 0x7fffffffu, (u & 0x80000000u) != 0u));
}

// Returned by the `*_append_end` functions to invocations that append nothing, and to
// those whose slot would wrap past u32::MAX. Rust: `wave::NO_SLOT`.
const WAVE_NO_SLOT: u32 = 0xffffffffu;

// One invocation's part of an aggregated append, from `*_append_begin` to `*_append_end`.
struct WaveAppend {
    // What to add to the counter: the wave's (or workgroup's) sum, in the elected
    // invocation only; 0 in every other invocation and when nothing is appended.
    total: u32,
    // Items appended by the lanes below this one (MaskBitCnt, an exclusive prefix sum).
    prefix: u32,
    // Items this invocation appends (0: none; the 1-item appends use 0 or 1).
    amount: u32,
    // Whether this invocation is the elected one (first active lane / local index 0).
    leader: bool,
}

// Rust: `wave::WaveBatch`, 8 bytes. The generic part of a batch header.
struct WaveBatch {
    first_instance: u32,
    instance_count: u32,
}

// This invocation's slot given the broadcast old counter value: base + prefix, or
// WAVE_NO_SLOT when it appends nothing or the slot would wrap.
fn wave_slot(a: WaveAppend, base: u32) -> u32 {
    let slot = base + a.prefix;
    if (a.amount == 0u || slot < base) {
        return WAVE_NO_SLOT;
    }
    return slot;
}

// popcount of a subgroupBallot result (lanes 0-31 in x, 32-63 in y, ...).
fn wave_ballot_count(mask: vec4<u32>) -> u32 {
    return countOneBits(mask.x) + countOneBits(mask.y) + countOneBits(mask.z) + countOneBits(mask.w);
}

// The set bits of one ballot word, lanes `lo .. lo + 31`, strictly below `lane`: the
// per-word step of MaskBitCnt, shared by the subgroup ballot and the workgroup ballot.
fn wave_word_count_below(bits: u32, lo: u32, lane: u32) -> u32 {
    var b = bits;
    if (lane <= lo) {
        b = 0u;
    } else if (lane < lo + 32u) {
        b &= (1u << (lane - lo)) - 1u;
    }
    return countOneBits(b);
}

// The set lanes of `mask` strictly below `lane`: the talk's MaskBitCnt.
fn wave_ballot_count_below(mask: vec4<u32>, lane: u32) -> u32 {
    var n = 0u;
    for (var w = 0u; w < 4u; w++) {
        n += wave_word_count_below(mask[w], w * 32u, lane);
    }
    return n;
}

// Whether `lane` is set in a ballot mask.
fn wave_ballot_contains(mask: vec4<u32>, lane: u32) -> bool {
    if (lane >= 128u) {
        return false;
    }
    return ((mask[lane / 32u] >> (lane % 32u)) & 1u) == 1u;
}

// The lowest set lane of a ballot mask, or WAVE_NO_SLOT when it is empty.
fn wave_ballot_first(mask: vec4<u32>) -> u32 {
    for (var w = 0u; w < 4u; w++) {
        if (mask[w] != 0u) {
            return w * 32u + firstTrailingBit(mask[w]);
        }
    }
    return WAVE_NO_SLOT;
}
