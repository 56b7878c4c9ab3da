// tiling: phase 1, laydown finalise (Rust twin: tiling::laydown_finalize) over the vis
// words. Bindings 0-3 are tiling::pixel's, 4 tiling::finalize's; entry point and dispatch:
// `tiling::LAYDOWN_FINALIZE`.

#import tiling::pixel
#import tiling::finalize

@compute @workgroup_size(16, 16)
fn laydown_finalize(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
) {
    tiling_finalize_begin(li);
    let words = tiling_quad_words(gid);
    workgroupBarrier();
#if timing_load_only
    atomicOr(&tiling_wg_masks[0], (words.x ^ words.y ^ words.z ^ words.w) & 1u);
#else
    // The quad decoded first, then the atomics (which would order the next table read).
    let keys = vec4<u32>(
        tiling_finalize_key(tiling_quad_pixel(gid, 0u), words.x),
        tiling_finalize_key(tiling_quad_pixel(gid, 1u), words.y),
        tiling_finalize_key(tiling_quad_pixel(gid, 2u), words.z),
        tiling_finalize_key(tiling_quad_pixel(gid, 3u), words.w),
    );
    tiling_finalize_mark(keys.x);
    tiling_finalize_mark(keys.y);
    tiling_finalize_mark(keys.z);
    tiling_finalize_mark(keys.w);
#endif
    workgroupBarrier();
    tiling_finalize_flush(li, tiling_block_tile(wid));
}
