// wave: path-neutral names bound to the workgroup fallback (see select_subgroup.wgsl).

fn wave_append_begin(want: bool, local_index: u32) -> WaveAppend {
    return wave_wg_append_begin(want, local_index);
}

fn wave_append_n_begin(amount: u32, local_index: u32) -> WaveAppend {
    return wave_wg_append_n_begin(amount, local_index);
}

fn wave_append_end(a: WaveAppend, old: u32) -> u32 {
    return wave_wg_append_end(a, old);
}
