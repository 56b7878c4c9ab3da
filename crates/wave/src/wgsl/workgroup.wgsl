// wave: the workgroup path, for adapters without `Features::SUBGROUP` (core WGSL,
// validated with `shadercheck::Caps::CORE`), and the run-grouped batch output.
//
// The "wave" here is the whole workgroup: invocation `local_invocation_index` is lane
// `local_index`, at most WAVE_WG_INVOCATIONS_MAX of them. A workgroup ballot is built
// with workgroup-shared `atomicOr`, so appends stay in local-index order (the same order
// as the CPU model and the subgroup path) with one global atomic per workgroup.
//
// Every function here contains workgroup barriers: call it from uniform control flow,
// from every invocation of the workgroup (pass predicates as arguments), and pair each
// `*_begin` with its `*_end`. The functions may be called any number of times per
// dispatch: the shared scratch is reset as it is consumed. Workgroup memory used:
// 2 x 32 bytes of ballot, 8 bytes of scalars, and 2 KiB for the batch output (only the
// variables an entry point reaches count).

#import wave::common

// Largest workgroup the ballot covers (wgpu's default `max_compute_invocations_per_workgroup`).
// Rust: `wave::WG_INVOCATIONS_MAX`.
const WAVE_WG_INVOCATIONS_MAX: u32 = 256u;
// 32-bit words in a workgroup ballot. Rust: `wave::WG_BALLOT_WORDS`.
const WAVE_WG_BALLOT_WORDS: u32 = 8u;

// Votes being collected.
var<workgroup> wave_wg_votes: array<atomic<u32>, WAVE_WG_BALLOT_WORDS>;
// The last completed ballot, written by local index 0 between two barriers.
var<workgroup> wave_wg_ballot_words: array<u32, WAVE_WG_BALLOT_WORDS>;
// Sum of the variable-amount append.
var<workgroup> wave_wg_sum: atomic<u32>;
// The broadcast value.
var<workgroup> wave_wg_scalar: u32;
// Per-group scratch of the batch output (the talk's LDS arrays): visible-lane count, and
// the first visible lane stored as its bitwise complement (0 = none yet, max wins).
var<workgroup> wave_wg_batch_count: array<atomic<u32>, WAVE_WG_INVOCATIONS_MAX>;
var<workgroup> wave_wg_batch_first: array<atomic<u32>, WAVE_WG_INVOCATIONS_MAX>;

// A workgroup-wide ballot: bit `i` of the result is set when invocation `i` passed `pred`.
// Two barriers.
fn wave_wg_ballot(pred: bool, local_index: u32) -> array<u32, WAVE_WG_BALLOT_WORDS> {
    if (pred) {
        atomicOr(&wave_wg_votes[local_index / 32u], 1u << (local_index % 32u));
    }
    workgroupBarrier();
    if (local_index == 0u) {
        // Read and clear in one step, so the next ballot starts from zero.
        for (var w = 0u; w < WAVE_WG_BALLOT_WORDS; w++) {
            wave_wg_ballot_words[w] = atomicExchange(&wave_wg_votes[w], 0u);
        }
    }
    workgroupBarrier();
    // Everyone copies the result before the next ballot's first barrier, after which
    // local index 0 may overwrite it.
    return wave_wg_ballot_words;
}

// popcount of a workgroup ballot.
fn wave_wg_ballot_count(mask: array<u32, WAVE_WG_BALLOT_WORDS>) -> u32 {
    var m = mask;
    var n = 0u;
    for (var w = 0u; w < WAVE_WG_BALLOT_WORDS; w++) {
        n += countOneBits(m[w]);
    }
    return n;
}

// The set bits of a workgroup ballot strictly below `lane` (MaskBitCnt).
fn wave_wg_ballot_count_below(mask: array<u32, WAVE_WG_BALLOT_WORDS>, lane: u32) -> u32 {
    var m = mask;
    var n = 0u;
    for (var w = 0u; w < WAVE_WG_BALLOT_WORDS; w++) {
        n += wave_word_count_below(m[w], w * 32u, lane);
    }
    return n;
}

// The leader's `value` in every invocation. Two barriers.
fn wave_wg_broadcast_leader(value: u32, leader: bool) -> u32 {
    if (leader) {
        wave_wg_scalar = value;
    }
    let v = workgroupUniformLoad(&wave_wg_scalar);
    // Keep the next broadcast's write after every invocation's read of this one.
    workgroupBarrier();
    return v;
}

// Aggregated append of one item per invocation with `want`, in local-index order. The
// leader is local index 0; it adds `total` to the caller's counter (skip the atomic when
// `total` is 0) and passes the old value to `wave_wg_append_end`. Two barriers.
fn wave_wg_append_begin(want: bool, local_index: u32) -> WaveAppend {
    let mask = wave_wg_ballot(want, local_index);
    let leader = local_index == 0u;
    let total = select(0u, wave_wg_ballot_count(mask), leader);
    return WaveAppend(total, wave_wg_ballot_count_below(mask, local_index), select(0u, 1u, want), leader);
}

// Aggregated append of `amount` items per invocation through a workgroup-shared atomic:
// ranges are contiguous per workgroup, but their order within the workgroup is whatever
// order the shared atomics ran in. Keep the workgroup's sum below 2^32. Two barriers.
fn wave_wg_append_n_begin(amount: u32, local_index: u32) -> WaveAppend {
    var prefix = 0u;
    if (amount != 0u) {
        prefix = atomicAdd(&wave_wg_sum, amount);
    }
    workgroupBarrier();
    let leader = local_index == 0u;
    var total = 0u;
    if (leader) {
        total = atomicExchange(&wave_wg_sum, 0u);
    }
    // The next append may add to the sum only after the leader has taken it.
    workgroupBarrier();
    return WaveAppend(total, prefix, amount, leader);
}

// Broadcasts the leader's old counter value and returns this invocation's first slot,
// or WAVE_NO_SLOT. Two barriers.
fn wave_wg_append_end(a: WaveAppend, old: u32) -> u32 {
    return wave_slot(a, wave_wg_broadcast_leader(old, a.leader));
}

// One invocation's part in the run-grouped batch output.
struct WaveBatchLane {
    // The group index: group-end bits set in the invocations below this one. Index the
    // caller's own per-group workgroup arrays (bounds, flags) with it.
    group: u32,
    // The instance append (amount 1 when visible).
    instance: WaveAppend,
}

// The batch-header half of the batch output.
struct WaveBatchHeader {
    // The header append: amount 1 in the first visible invocation of each group.
    append: WaveAppend,
    // Visible instances in this invocation's group (valid in header writers).
    instance_count: u32,
}

// HZD's batching in the query, workgroup-wide (batches of at most the workgroup size).
// `group_end`: this invocation's instance is the last of its DrawableSetup run;
// `visible`: it passed the visibility test. Invocations without an instance pass false
// for both. Then, at the call site:
//
//   let lane = wave_wg_batch_begin(end, vis, li);
//   var old = 0u;
//   if (lane.instance.total != 0u) { old = atomicAdd(&instance_counter, lane.instance.total); }
//   let slot = wave_wg_append_end(lane.instance, old);
//   if (slot < arrayLength(&instances)) { instances[slot] = ...; }
//   // optional: fold this lane into your own var<workgroup> arrays at [lane.group]
//   let hdr = wave_wg_batch_headers_begin(lane, li);
//   var old_b = 0u;
//   if (hdr.append.total != 0u) { old_b = atomicAdd(&batch_counter, hdr.append.total); }
//   let b = wave_wg_append_end(hdr.append, old_b);
//   if (b < arrayLength(&batches)) { batches[b] = WaveBatch(slot, hdr.instance_count); }
//   // optional: header writers (b != WAVE_NO_SLOT... or hdr.append.amount != 0u) read and
//   // then reset your own arrays at [lane.group]
//
// Four barriers here plus two per `wave_wg_append_end`.
fn wave_wg_batch_begin(group_end: bool, visible: bool, local_index: u32) -> WaveBatchLane {
    let ends = wave_wg_ballot(group_end, local_index);
    let group = wave_wg_ballot_count_below(ends, local_index);
    if (visible) {
        atomicAdd(&wave_wg_batch_count[group], 1u);
        atomicMax(&wave_wg_batch_first[group], ~local_index);
    }
    // The barriers inside make the accumulation above visible to the header step.
    let instance = wave_wg_append_begin(visible, local_index);
    return WaveBatchLane(group, instance);
}

// Elects the first visible invocation of each group, reads the group's count and starts
// the header append (in group order). Three barriers.
fn wave_wg_batch_headers_begin(lane: WaveBatchLane, local_index: u32) -> WaveBatchHeader {
    // The caller's own accumulations into its per-group arrays are complete after this.
    workgroupBarrier();
    let visible = lane.instance.amount != 0u;
    let first = ~atomicLoad(&wave_wg_batch_first[lane.group]);
    let writes_header = visible && first == local_index;
    var count = 0u;
    if (writes_header) {
        count = atomicLoad(&wave_wg_batch_count[lane.group]);
    }
    // Every read of the scratch above happens before this ballot's barriers...
    let append = wave_wg_append_begin(writes_header, local_index);
    // ...so the group's writer can clear its slot for the next batch output.
    if (writes_header) {
        atomicStore(&wave_wg_batch_count[lane.group], 0u);
        atomicStore(&wave_wg_batch_first[lane.group], 0u);
    }
    return WaveBatchHeader(append, count);
}
