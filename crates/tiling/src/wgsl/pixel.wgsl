// tiling: the per-pixel part shared by the three classification passes: their first four
// bindings (tiling::decode's and the vis words) and the quads.

#import tiling::decode

// width * height vis words, row-major.
@group(0) @binding(1) var<storage, read> vis: array<u32>;

// The pixel phases' workgroups: 16x16 invocations, each a 2x2 quad of pixels, so a
// workgroup covers a TILING_BLOCK_SIZE block of one 128x128 tile (tiling_block_tile). Four
// pixels an invocation keep four vis loads in flight and cut the workgroups (and their
// barriers) by four: the phases are bound by latency, not bandwidth.

// Pixel k (0..4: x = k % 2, y = k / 2) of invocation `gid`'s quad.
fn tiling_quad_pixel(gid: vec3<u32>, k: u32) -> vec2<u32> {
    return vec2<u32>(2u * gid.x + (k & 1u), 2u * gid.y + (k >> 1u));
}

// The row-major index of invocation `gid`'s quad among ceil(width / 2) x ceil(height / 2)
// (TILING_NONE past them).
fn tiling_quad_index(gid: vec3<u32>) -> u32 {
    let quads = vec2<u32>((params.width + 1u) / 2u, (params.height + 1u) / 2u);
    if (gid.x >= quads.x || gid.y >= quads.y) {
        return TILING_NONE;
    }
    return gid.y * quads.x + gid.x;
}

// The vis word of pixel k of invocation `gid`'s quad (VISBUF_NONE outside the image).
fn tiling_quad_word(gid: vec3<u32>, k: u32) -> u32 {
    let p = tiling_quad_pixel(gid, k);
    if (p.x >= params.width || p.y >= params.height) {
        return VISBUF_NONE;
    }
    return tiling_word(p.y * params.width + p.x);
}

// The vis words of invocation `gid`'s quad, loaded together before any is decoded. The
// quad's four pixels are spelled out here and in the passes, never indexed by a loop
// variable: a dynamically indexed vector lives in local memory on the H200 (the passes
// measured up to 1.7x slower).
fn tiling_quad_words(gid: vec3<u32>) -> vec4<u32> {
    return vec4<u32>(tiling_quad_word(gid, 0u), tiling_quad_word(gid, 1u), tiling_quad_word(gid, 2u), tiling_quad_word(gid, 3u));
}

// count_pixels' record of each pixel (the `slots` buffer, a vec4 per quad), which classify output's
// scatter_write_waves turns into a command without decoding the vis word again (frames
// without a validity mask, where the two phases classify alike). With a command: bit 31,
// the slot within its counter (bits 0-13: a counter holds at most 128 * 128 pixels), the
// counter's index within its tile's (bits 14-26), the sample mask (bits 27-30). Without
// one: the pixel's TILING_PX_* kind (bits 0-1) and TILING_RECORD_DROPPED. Rust twin:
// tiling::wgsl::RECORD_*.
const TILING_RECORD_COMMAND: u32 = 1u << 31u;
const TILING_RECORD_DROPPED: u32 = 4u;
const TILING_RECORD_COUNTER_SHIFT: u32 = 14u;
const TILING_RECORD_SLOT_MASK: u32 = (1u << TILING_RECORD_COUNTER_SHIFT) - 1u;
const TILING_RECORD_MASK_SHIFT: u32 = 27u;
const TILING_RECORD_COUNTER_MASK: u32 = (1u << (TILING_RECORD_MASK_SHIFT - TILING_RECORD_COUNTER_SHIFT)) - 1u;

// A command record's counter index within its tile's counters.
fn tiling_record_counter(r: u32) -> u32 {
    return (r >> TILING_RECORD_COUNTER_SHIFT) & TILING_RECORD_COUNTER_MASK;
}

// A record's TILING_PX_* kind (a record without a command).
fn tiling_record_kind(r: u32) -> u32 {
    return r & 3u;
}

// A command record's 4-bit sample mask.
fn tiling_record_mask(r: u32) -> u32 {
    return (r >> TILING_RECORD_MASK_SHIFT) & 15u;
}

// The word of pixel i, or VISBUF_NONE outside the buffer.
fn tiling_word(i: u32) -> u32 {
    if (i >= arrayLength(&vis)) {
        return VISBUF_NONE;
    }
    return vis[i];
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

// Per-workgroup stats, flushed with one atomic per field. Only the rare fields are counted
// per pixel (unknown, out of range, dropped, bad indices, and with VRS the valid pixels
// whose sample an earlier pixel carries); commands once per invocation; valid and empty
// follow at the flush (tiling_stats_field): every valid pixel is a command, dropped or
// without a sample, and every pixel of the block inside the image is valid, empty,
// unknown or out of range. A workgroup atomic per pixel for its kind and another for its
// command, on the same eight words, took 15 us of count_pixels on the H200.
var<workgroup> tiling_wg_stats: array<atomic<u32>, 8>;

// Zeroes the workgroup's stats; a barrier must follow before any tiling_stat (the pixel
// phases call it right before tiling_tile_counters, whose barrier serves).
fn tiling_stats_zero(li: u32) {
    if (li < TILING_STAT_COUNT) {
        atomicStore(&tiling_wg_stats[li], 0u);
    }
}

fn tiling_stat(field: u32, n: u32) {
// Timing experiment only (gpu's `classify_variants`): no stats atomics, wrong stats.
#if !timing_omit_stats
    if (n != 0u) {
        atomicAdd(&tiling_wg_stats[field], n);
    }
#endif
}

// Counts the pixel's kind where it is a rare one (valid and empty are derived).
fn tiling_stat_kind(kind: u32) {
    if (kind == TILING_PX_UNKNOWN) {
        tiling_stat(TILING_STAT_UNKNOWN, 1u);
    } else if (kind == TILING_PX_OUT_OF_RANGE) {
        tiling_stat(TILING_STAT_OUT_OF_RANGE, 1u);
    }
}

// After every tiling_stat of the 32x32 block of workgroup `wid` and a barrier: the block's
// value of PixelStats field `field` (< TILING_STAT_COUNT), valid and empty derived.
fn tiling_stats_field(wid: vec3<u32>, field: u32) -> u32 {
    let commands = atomicLoad(&tiling_wg_stats[TILING_STAT_COMMANDS]);
    let dropped = atomicLoad(&tiling_wg_stats[TILING_STAT_DROPPED]);
    let valid = commands + dropped + atomicLoad(&tiling_wg_stats[TILING_STAT_NO_SAMPLE]);
    switch (field) {
        case TILING_STAT_VALID: { return valid; }
        case TILING_STAT_EMPTY: {
            let x0 = min(wid.x * TILING_BLOCK_SIZE, params.width);
            let y0 = min(wid.y * TILING_BLOCK_SIZE, params.height);
            let pixels = min(TILING_BLOCK_SIZE, params.width - x0) * min(TILING_BLOCK_SIZE, params.height - y0);
            let other = valid + atomicLoad(&tiling_wg_stats[TILING_STAT_UNKNOWN]) + atomicLoad(&tiling_wg_stats[TILING_STAT_OUT_OF_RANGE]);
            return pixels - min(other, pixels);
        }
        case TILING_STAT_NO_SAMPLE: { return 0u; }
        default: { return atomicLoad(&tiling_wg_stats[field]); }
    }
}
