// wave: the subgroup path (needs wgpu `Features::SUBGROUP`; validated with
// `shadercheck::Caps::SUBGROUP`).

#import wave::common
//
// Call these from every invocation of the subgroup that is still running (they are
// subgroup operations): pass the append predicate as an argument instead of branching
// around the call. `lane_id` is any id unique within the subgroup: the
// `@builtin(subgroup_invocation_id)`, or the `@builtin(local_invocation_index)` (which
// lets one pass source serve both paths, see `wave_append_begin`).

// The elected invocation: the first active one. naga has no subgroupElect; this is its
// equivalent, ReadFirstLane(id) == id.
fn wave_sg_is_leader(lane_id: u32) -> bool {
    return subgroupBroadcastFirst(lane_id) == lane_id;
}

// Aggregated append of one item per invocation with `want`: ballot, popcount in the
// leader, exclusive prefix in every lane. Then the caller's leader adds `total` to its
// counter (skip the atomic when `total` is 0) and passes the old value to
// `wave_sg_append_end`.
fn wave_sg_append_begin(want: bool, lane_id: u32) -> WaveAppend {
    let mask = subgroupBallot(want);
    let one = select(0u, 1u, want);
    let prefix = subgroupExclusiveAdd(one);
    let leader = wave_sg_is_leader(lane_id);
    return WaveAppend(select(0u, wave_ballot_count(mask), leader), prefix, one, leader);
}

// Aggregated append of `amount` items per invocation (0 for none), or an aggregated
// count (FC5's per-tile pixel count): subgroupAdd in the leader, subgroupExclusiveAdd in
// every lane. The caller must keep the subgroup's sum below 2^32.
fn wave_sg_append_n_begin(amount: u32, lane_id: u32) -> WaveAppend {
    let total = subgroupAdd(amount);
    let prefix = subgroupExclusiveAdd(amount);
    let leader = wave_sg_is_leader(lane_id);
    return WaveAppend(select(0u, total, leader), prefix, amount, leader);
}

// Broadcasts the leader's old counter value (`old` is ignored in the other invocations)
// and returns this invocation's first slot, or WAVE_NO_SLOT.
fn wave_sg_append_end(a: WaveAppend, old: u32) -> u32 {
    return wave_slot(a, subgroupBroadcastFirst(old));
}
