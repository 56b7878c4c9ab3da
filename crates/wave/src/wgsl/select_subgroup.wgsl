// wave: path-neutral names bound to the subgroup path. A pass written against
// `wave_append_begin` / `wave_append_n_begin` / `wave_append_end` (with
// `@builtin(local_invocation_index)` as the id) runs unchanged on either path: prepend
// `wave::module_for(true)` or `wave::module_for(false)`.

fn wave_append_begin(want: bool, local_index: u32) -> WaveAppend {
    return wave_sg_append_begin(want, local_index);
}

fn wave_append_n_begin(amount: u32, local_index: u32) -> WaveAppend {
    return wave_sg_append_n_begin(amount, local_index);
}

fn wave_append_end(a: WaveAppend, old: u32) -> u32 {
    return wave_sg_append_end(a, old);
}
