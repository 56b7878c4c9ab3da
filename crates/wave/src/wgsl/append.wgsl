// wave: the path-neutral appends. A pass written against `wave_append_begin` /
// `wave_append_n_begin` / `wave_append_end` (with `@builtin(local_invocation_index)` as the
// id) runs unchanged on either path: composed with the `subgroups` feature they are the
// subgroup path's (one atomic per subgroup; needs `Features::SUBGROUP`), without it the
// workgroup fallback's (one atomic per workgroup; core WGSL).

#import wave::workgroup
#if subgroups
#import wave::subgroup

fn wave_append_begin(want: bool, local_index: u32) -> WaveAppend {
    return wave_sg_append_begin(want, local_index);
}

fn wave_append_n_begin(amount: u32, local_index: u32) -> WaveAppend {
    return wave_sg_append_n_begin(amount, local_index);
}

fn wave_append_end(a: WaveAppend, old: u32) -> u32 {
    return wave_sg_append_end(a, old);
}
#else

fn wave_append_begin(want: bool, local_index: u32) -> WaveAppend {
    return wave_wg_append_begin(want, local_index);
}

fn wave_append_n_begin(amount: u32, local_index: u32) -> WaveAppend {
    return wave_wg_append_n_begin(amount, local_index);
}

fn wave_append_end(a: WaveAppend, old: u32) -> u32 {
    return wave_wg_append_end(a, old);
}
#endif
