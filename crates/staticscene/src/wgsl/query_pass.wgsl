// staticscene::query_pass: the query compute pass (twin of src/query.rs `query_cluster`
// over the jobs of src/pass.rs `GpuQueryPlanner`). One workgroup of 64 invocations per
// wave of a cluster job (HZD's wavefront), one invocation per QueryInstance, the tests
// in the talk's order, LOD fade states updated in place, and the run-grouped batch output
// of `wave::workgroup` (batches of at most 64 instances, as HZD's).
//
// Every tile's records live in pooled buffers; a job names its tile's bases and counts,
// and every index read from a record is checked against them (an instance with an index
// outside its tile is dropped and counted as invalid, as the CPU twin does), so corrupt
// records never read outside their tile.

#import staticscene::query
#import wave::common
#import wave::workgroup
#if subgroups
#import wave::subgroup
#endif

const STATICSCENE_QUERY_WORKGROUP: u32 = 64u;
// Workgroups per row of a 2D dispatch (Rust: shader::MAX_WORKGROUPS_X).
const STATICSCENE_MAX_WORKGROUPS_X: u32 = 65535u;
// Job flags (Rust: JOB_FLAG_*).
const STATICSCENE_JOB_SNAP_FADE: u32 = 1u;
const STATICSCENE_JOB_LOD_UNLESS_LIVE: u32 = 2u;
// Words per record in a tile's record block (Rust: *_WORDS).
const STATICSCENE_OBJECT_WORDS: u32 = 16u;
const STATICSCENE_SETUP_WORDS: u32 = 8u;
const STATICSCENE_TRANSFORM_WORDS: u32 = 12u;
const STATICSCENE_BOUNDS_WORDS: u32 = 3u;
// Statistics slots of the counters block (Rust: STAT_*).
const STATICSCENE_STAT_THREADS: u32 = 0u;
const STATICSCENE_STAT_FILTER: u32 = 1u;
const STATICSCENE_STAT_LOD: u32 = 2u;
const STATICSCENE_STAT_FRUSTUM: u32 = 3u;
const STATICSCENE_STAT_SIZE: u32 = 4u;
const STATICSCENE_STAT_OCCLUSION: u32 = 5u;
const STATICSCENE_STAT_FADED_OUT: u32 = 6u;
const STATICSCENE_STAT_INVALID: u32 = 7u;
const STATICSCENE_STAT_VISIBLE: u32 = 8u;
const STATICSCENE_STAT_DROPPED: u32 = 9u;
const STATICSCENE_STAT_DRAWN_EARLY: u32 = 10u;
const STATICSCENE_STAT_COUNT: u32 = 11u;

struct StaticsceneGpuJob {
    tile: u32,
    first: u32,
    count: u32,
    flags: u32,
    instance_base: u32,
    records: u32,
    objects: u32,
    setups: u32,
    transforms: u32,
    bounds: u32,
    first_wave: u32,
    cluster: u32,
    last_run: u32,
    serial: u32,
    fade_base: u32,
    pad: u32,
}

struct StaticsceneJobList {
    count: u32,
    waves: u32,
    pad0: u32,
    pad1: u32,
    jobs: array<StaticsceneGpuJob>,
}

struct StaticsceneQueryCounters {
    instances: atomic<u32>,
    batches: atomic<u32>,
    // Two words (not a vec2, whose 8-byte alignment would pad the struct to 64 bytes).
    pad0: u32,
    pad1: u32,
    stats: array<atomic<u32>, STATICSCENE_STAT_COUNT>,
}

@group(0) @binding(0) var<uniform> params: StaticsceneQueryParams;
@group(0) @binding(1) var<storage, read> job_list: StaticsceneJobList;
// The job of each wave (GpuPlan::wave_jobs).
@group(0) @binding(2) var<storage, read> wave_jobs: array<u32>;
@group(0) @binding(3) var<storage, read> instances: array<vec4<u32>>;
@group(0) @binding(4) var<storage, read> records: array<u32>;
@group(0) @binding(5) var<storage, read> hiz: array<u32>;
// Fade state bytes (four per word) and the clusters' live serials.
@group(0) @binding(6) var<storage, read_write> state: array<atomic<u32>>;
@group(0) @binding(7) var<storage, read_write> counters: StaticsceneQueryCounters;
@group(0) @binding(8) var<storage, read_write> out_instances: array<StaticsceneDrawableSetupInstance>;
@group(0) @binding(9) var<storage, read_write> out_batches: array<StaticsceneDrawableSetupBatch>;

var<workgroup> staticscene_wg_live_serial: u32;
// Whether any invocation has a visible instance (most waves have none: the batch output
// and its barriers are skipped for them, uniformly).
var<workgroup> staticscene_wg_any_visible: atomic<u32>;
var<workgroup> staticscene_wg_any_visible_copy: u32;
var<workgroup> staticscene_wg_stats: array<atomic<u32>, STATICSCENE_STAT_COUNT>;
// The batch accumulation (the talk's LDS arrays), per group: bounds and nearest depth as
// order-preserving words (the minima complemented, so zero-initialised memory is neutral
// for atomicMax), OR of flags.
var<workgroup> staticscene_wg_bmin: array<atomic<u32>, 192>;
var<workgroup> staticscene_wg_bmax: array<atomic<u32>, 192>;
var<workgroup> staticscene_wg_bdepth: array<atomic<u32>, 64>;
var<workgroup> staticscene_wg_bflags: array<atomic<u32>, 64>;

fn staticscene_is_nan(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7fffffffu) > 0x7f800000u;
}

fn staticscene_word_f32(i: u32) -> f32 {
    return bitcast<f32>(records[i]);
}

fn staticscene_load_transform(at: u32) -> StaticsceneTransform {
    var t: StaticsceneTransform;
    for (var r = 0u; r < 3u; r++) {
        let b = at + r * 4u;
        t.rows[r] = vec4<f32>(staticscene_word_f32(b), staticscene_word_f32(b + 1u), staticscene_word_f32(b + 2u), staticscene_word_f32(b + 3u));
    }
    return t;
}

fn staticscene_load_object(job: StaticsceneGpuJob, i: u32) -> StaticsceneQueryObject {
    let at = job.records + i * STATICSCENE_OBJECT_WORDS;
    var o: StaticsceneQueryObject;
    o.object_to_snapped = staticscene_load_transform(at);
    o.snapped = vec3<i32>(bitcast<i32>(records[at + 12u]), bitcast<i32>(records[at + 13u]), bitcast<i32>(records[at + 14u]));
    o.lod = records[at + 15u];
    return o;
}

fn staticscene_setups_at(job: StaticsceneGpuJob) -> u32 {
    return job.records + job.objects * STATICSCENE_OBJECT_WORDS;
}

fn staticscene_transforms_at(job: StaticsceneGpuJob) -> u32 {
    return staticscene_setups_at(job) + job.setups * STATICSCENE_SETUP_WORDS;
}

fn staticscene_bounds_at(job: StaticsceneGpuJob) -> u32 {
    return staticscene_transforms_at(job) + job.transforms * STATICSCENE_TRANSFORM_WORDS;
}

fn staticscene_load_setup(job: StaticsceneGpuJob, i: u32) -> StaticsceneQuerySetup {
    let at = staticscene_setups_at(job) + i * STATICSCENE_SETUP_WORDS;
    var s: StaticsceneQuerySetup;
    for (var k = 0u; k < 6u; k++) {
        s.bounds[k] = staticscene_word_f32(at + k);
    }
    s.handle = vec2<u32>(records[at + 6u], records[at + 7u]);
    return s;
}

fn staticscene_load_bounds(job: StaticsceneGpuJob, i: u32) -> StaticsceneAabb {
    let at = staticscene_bounds_at(job) + i * STATICSCENE_BOUNDS_WORDS;
    var b: StaticsceneHalfAabb;
    b.words = array<u32, 3>(records[at], records[at + 1u], records[at + 2u]);
    return staticscene_half_box(b);
}

// Whether the job's record block lies inside the records buffer.
fn staticscene_job_records_fit(job: StaticsceneGpuJob) -> bool {
    let n = arrayLength(&records);
    // Each count is below its index space (17 bits at most), so no term overflows.
    let limits = job.objects <= 131072u && job.setups <= 4096u && job.transforms <= 16384u && job.bounds <= 32768u;
    let end = staticscene_bounds_at(job) + job.bounds * STATICSCENE_BOUNDS_WORDS;
    return limits && job.records <= n && end <= n && end >= job.records;
}

// The LOD test of one level: the level's bounds through object-to-floating, the squared
// distance from the LOD point against the bracket ("always" codes pass without a test).
fn staticscene_level_selected(codes: vec2<u32>, b: StaticsceneAabb, o2f: StaticsceneTransform, scale2: f32) -> bool {
    let bx = staticscene_transform_aabb(o2f, b);
    let always = codes.x == 0u && codes.y == STATICSCENE_LOD_CODE_INFINITY;
    return always || staticscene_lod_selects(codes, staticscene_dist2(params.lod_point.xyz, bx), scale2);
}

fn staticscene_hiz_texel(at: u32) -> f32 {
    if (at >= arrayLength(&hiz)) {
        // Outside the buffer: the far side of everything (never occludes).
        return select(1.0e30, -1.0e30, (params.flags & STATICSCENE_QUERY_FLAG_REVERSED_DEPTH) != 0u);
    }
    return bitcast<f32>(hiz[at]);
}

// The HiZ occlusion test (twin of HiZ::occluded): the box's eight corners through the
// HiZ frame's matrix, its pixel rectangle and nearest depth, the level where the
// rectangle spans 2x2 texels (or a scan some levels finer), occluded only if behind every
// texel read.
fn staticscene_occluded(bmin: vec3<f32>, bmax: vec3<f32>) -> bool {
    let level_count = min(hiz[0], STATICSCENE_HIZ_MAX_LEVELS);
    if (level_count == 0u) {
        return false;
    }
    let reversed = (params.flags & STATICSCENE_QUERY_FLAG_REVERSED_DEPTH) != 0u;
    let m = params.hiz_clip_from_floating;
    let base = m * vec4<f32>(bmin, 1.0);
    let e = bmax - bmin;
    let cx = m[0] * e.x;
    let cy = m[1] * e.y;
    let cz = m[2] * e.z;
    var lo = vec3<f32>(3.0e38);
    var hi = vec3<f32>(-3.0e38);
    for (var i = 0u; i < 8u; i++) {
        var c = base;
        if ((i & 1u) != 0u) {
            c += cx;
        }
        if ((i & 2u) != 0u) {
            c += cy;
        }
        if ((i & 4u) != 0u) {
            c += cz;
        }
        if (staticscene_is_nan(c.w) || c.w <= 1e-6) {
            return false;
        }
        let inv = 1.0 / c.w;
        let p = vec3<f32>(c.x * inv, c.y * inv, c.z * inv);
        lo = min(lo, p);
        hi = max(hi, p);
    }
    let size = vec2<u32>(hiz[4], hiz[5]);
    if (size.x == 0u || size.y == 0u) {
        return false;
    }
    let w = f32(size.x);
    let h = f32(size.y);
    let margin = 1.0 / 64.0;
    let px0 = (lo.x * 0.5 + 0.5) * w - margin;
    let px1 = (hi.x * 0.5 + 0.5) * w + margin;
    let py0 = (0.5 - hi.y * 0.5) * h - margin;
    let py1 = (0.5 - lo.y * 0.5) * h + margin;
    if (!(px1 >= 0.0 && py1 >= 0.0 && px0 < w && py0 < h)) {
        return false;
    }
    let x0 = select(min(u32(floor(px0)), size.x - 1u), 0u, px0 <= 0.0);
    let y0 = select(min(u32(floor(py0)), size.y - 1u), 0u, py0 <= 0.0);
    let x1 = select(min(u32(floor(px1)), size.x - 1u), 0u, px1 <= 0.0);
    let y1 = select(min(u32(floor(py1)), size.y - 1u), 0u, py1 <= 0.0);
    let depth = select(lo.z, hi.z, reversed);
    var l = 0u;
    while (((x1 >> l) - (x0 >> l)) > 1u || ((y1 >> l) - (y0 >> l)) > 1u) {
        l += 1u;
    }
    l = min(l, level_count - 1u);
    // The 2x2 texels of level l first: each is the farthest of the finer texels under it,
    // so behind all of them is behind everything the finer scan reads (the same verdict,
    // in at most four reads instead of up to a scan's 9x9).
    if (staticscene_behind_texels(l, x0, y0, x1, y1, depth, reversed)) {
        return true;
    }
    let scan = params.hiz_scan_levels;
    if (scan == 0u || l <= scan) {
        return false;
    }
    return staticscene_behind_texels(l - scan, x0, y0, x1, y1, depth, reversed);
}

// Whether `depth` is behind every texel of `level` under the level-0 rectangle
// [x0, x1] x [y0, y1].
fn staticscene_behind_texels(level: u32, x0: u32, y0: u32, x1: u32, y1: u32, depth: f32, reversed: bool) -> bool {
    let lw = hiz[4u + level * 4u];
    let lh = hiz[5u + level * 4u];
    let offset = hiz[6u + level * 4u];
    if (lw == 0u || lh == 0u) {
        return false;
    }
    let xe = min(x1 >> level, lw - 1u);
    let d = vec4<f32>(depth);
    let e = vec4<f32>(STATICSCENE_HIZ_DEPTH_EPSILON);
    for (var y = y0 >> level; y <= min(y1 >> level, lh - 1u); y++) {
        let row = offset + y * lw;
        // Four texels per step, all loads issued before any test (a scan row is up to
        // nine texels; one dependent load per texel was the scan's cost: H200 aerial view,
        // 71.5 -> 66.7 us; eight loads per step gained nothing and raised the register
        // count of the whole pass). Lanes past the row's end re-read its last texel: the
        // verdict is unchanged.
        for (var x = x0 >> level; x <= xe; x += 4u) {
            let t = vec4<f32>(
                staticscene_hiz_texel(row + x),
                staticscene_hiz_texel(row + min(x + 1u, xe)),
                staticscene_hiz_texel(row + min(x + 2u, xe)),
                staticscene_hiz_texel(row + min(x + 3u, xe)),
            );
            if (!all(select(d > t + e, d < t - e, reversed))) {
                return false;
            }
        }
    }
    return true;
}

// What one invocation found: its outcome (a STAT_* slot, or STAT_COUNT for no instance)
// and, when visible, its output.
struct StaticsceneLane {
    outcome: u32,
    live: bool,
    l2f: StaticsceneTransform,
    bmin: vec3<f32>,
    bmax: vec3<f32>,
    depth: f32,
    fade: f32,
    flags: u32,
    handle: vec2<u32>,
}

// The fade state byte `index` (of the state buffer), or 0 outside it.
fn staticscene_fade_load(index: u32) -> u32 {
    if ((index >> 2u) >= arrayLength(&state)) {
        return 0u;
    }
    return (atomicLoad(&state[index >> 2u]) >> ((index & 3u) * 8u)) & 0xffu;
}

fn staticscene_fade_store(index: u32, old: u32, new_state: u32) {
    if ((index >> 2u) < arrayLength(&state) && old != new_state) {
        atomicXor(&state[index >> 2u], (old ^ new_state) << ((index & 3u) * 8u));
    }
}

// One thread's tests (twin of query.rs `test_instance`).
fn staticscene_test(job: StaticsceneGpuJob, records_fit: bool, q: vec4<u32>, tile_index: u32) -> StaticsceneLane {
    var lane: StaticsceneLane;
    lane.outcome = STATICSCENE_STAT_VISIBLE;
    // 1. Filter: word 0 only.
    if ((staticscene_filter(q) & params.filter_mask) == 0u) {
        lane.outcome = STATICSCENE_STAT_FILTER;
        return lane;
    }
    let oi = staticscene_object(q);
    if (!records_fit || oi >= job.objects) {
        lane.outcome = STATICSCENE_STAT_INVALID;
        return lane;
    }
    let obj = staticscene_load_object(job, oi);
    let o2f = staticscene_object_to_floating(obj, params.origin.xyz);
    var scale = staticscene_lod_scale(obj);
    if (!staticscene_ignores_global_lod_scale(obj)) {
        scale *= params.lod_point.w;
    }
    let scale2 = scale * scale;
    // 2. Parent LOD, then 3. child LOD only if the parent is selected.
    let pbi = staticscene_parent_bounds(q);
    let cbi = staticscene_child_bounds(q);
    if (pbi >= job.bounds || cbi >= job.bounds) {
        lane.outcome = STATICSCENE_STAT_INVALID;
        return lane;
    }
    let p_sel = staticscene_level_selected(staticscene_parent_lod(q), staticscene_load_bounds(job, pbi), o2f, scale2);
    var lod_sel = false;
    if (p_sel) {
        lod_sel = staticscene_level_selected(staticscene_child_lod(q), staticscene_load_bounds(job, cbi), o2f, scale2);
    }
#if shadow_view
    // The shadow variant (the talk's fast path for shadow views, compiled separately): no
    // fade, no occlusion, no camera state; what reads or writes them compiles away.
    let fading_view = false;
    let first_pass = false;
    let second_pass = false;
    let occlusion_on = false;
#else
    let fading_view = (params.flags & STATICSCENE_QUERY_FLAG_FADE) != 0u && params.fade_frames > 0u;
    let first_pass = (params.flags & STATICSCENE_QUERY_FLAG_FIRST_PASS) != 0u;
    let second_pass = !first_pass && (params.flags & STATICSCENE_QUERY_FLAG_SECOND_PASS) != 0u;
    let occlusion_on = (params.flags & STATICSCENE_QUERY_FLAG_OCCLUSION) != 0u;
#endif
    // The camera state byte (fade state in the low 7 bits, CAMERA_STATE_VISIBLE on top):
    // read when fading or in either occlusion pass, written except in the first pass.
    let state_on = fading_view || first_pass || second_pass;
    let writes = state_on && !first_pass;
    let fade_on = fading_view && (staticscene_flags(q) & STATICSCENE_INSTANCE_FLAG_NO_FADE) == 0u;
    let n = min(params.fade_frames, 127u);
    let fade_index = job.fade_base + tile_index;
    var stored = 0u;
    if (state_on) {
        stored = staticscene_fade_load(fade_index);
    }
    let was_visible = (stored & STATICSCENE_CAMERA_STATE_VISIBLE) != 0u;
    var prev = 0u;
    if (fade_on) {
        if ((job.flags & STATICSCENE_JOB_SNAP_FADE) != 0u) {
            prev = select(0u, n, lod_sel);
        } else {
            prev = min(stored & ~STATICSCENE_CAMERA_STATE_VISIBLE, n);
        }
    }
    if (!lod_sel && prev == 0u) {
        if (writes) {
            staticscene_fade_store(fade_index, stored, 0u);
        }
        lane.outcome = STATICSCENE_STAT_LOD;
        return lane;
    }
    // 4. Accurate frustum test of the local bounds in floating space.
    let mi = staticscene_matrix(q);
    let si = staticscene_setup(q);
    if (mi >= job.transforms || si >= job.setups) {
        lane.outcome = STATICSCENE_STAT_INVALID;
        return lane;
    }
    let l2o = staticscene_load_transform(staticscene_transforms_at(job) + mi * STATICSCENE_TRANSFORM_WORDS);
    let setup = staticscene_load_setup(job, si);
    let l2f = staticscene_mul(o2f, l2o);
    let bx = staticscene_transform_aabb(l2f, staticscene_setup_box(setup));
    let in_frustum = !staticscene_box_outside_frustum(params.planes, bx);
    let centre = (bx.min + bx.max) * 0.5;
    let radius = length(bx.max - bx.min) * 0.5;
    // 5. Screen size at the sphere's nearest w.
    let m = params.clip_from_floating;
    let w_row = vec4<f32>(m[0].w, m[1].w, m[2].w, m[3].w);
    var big = true;
    if (in_frustum && (params.flags & STATICSCENE_QUERY_FLAG_SIZE) != 0u) {
        let w = dot(w_row.xyz, centre) + w_row.w - radius * length(w_row.xyz);
        big = staticscene_is_nan(w) || w <= 0.0 || 2.0 * radius * params.viewport.w >= params.viewport.z * w;
    }
    // 6. Occlusion: against the HiZ, or, in the first of two passes, last frame's
    // visibility.
    let never_occluded = (staticscene_flags(q) & STATICSCENE_INSTANCE_FLAG_NO_OCCLUSION) != 0u;
    let testable = in_frustum && big && !never_occluded;
    var occluded = false;
    if (first_pass) {
        occluded = testable && !was_visible;
    } else if (testable && occlusion_on) {
        occluded = staticscene_occluded(bx.min, bx.max);
    }
    // 7. LOD fade state.
    var shown = lod_sel;
    var opacity = 1.0;
    var flags = 0u;
    var next = 0u;
    if (fade_on) {
        if (!in_frustum) {
            next = select(0u, n, lod_sel);
        } else if (lod_sel) {
            next = min(prev + 1u, n);
        } else {
            next = select(prev - 1u, 0u, prev == 0u);
        }
        lane.live = next > 0u;
        if (next < n) {
            flags |= STATICSCENE_STATE_FADING;
        }
        if (!lod_sel) {
            flags |= STATICSCENE_STATE_FADING_OUT;
        }
        shown = next > 0u;
        opacity = f32(next) / f32(n);
    }
    if (writes) {
        let visible = in_frustum && big && !occluded && shown;
        staticscene_fade_store(fade_index, stored, next | select(0u, STATICSCENE_CAMERA_STATE_VISIBLE, visible));
    }
    if (!in_frustum) {
        lane.outcome = STATICSCENE_STAT_FRUSTUM;
    } else if (!big) {
        lane.outcome = STATICSCENE_STAT_SIZE;
    } else if (occluded) {
        lane.outcome = STATICSCENE_STAT_OCCLUSION;
    } else if (!shown) {
        lane.outcome = STATICSCENE_STAT_FADED_OUT;
    } else if (second_pass && (was_visible || never_occluded)) {
        // The first pass output it already (visible last frame or never tested, every
        // other test as here).
        lane.outcome = STATICSCENE_STAT_DRAWN_EARLY;
    }
    // 8. Output data.
    lane.l2f = l2f;
    lane.bmin = bx.min;
    lane.bmax = bx.max;
    lane.depth = dot(params.forward.xyz, centre) + params.forward.w - radius * length(params.forward.xyz);
    lane.fade = opacity;
    lane.flags = flags;
    lane.handle = setup.handle;
    return lane;
}

// Folds a visible invocation into its group's accumulation (bounds, nearest depth, flags).
fn staticscene_fold(g: u32, lane: StaticsceneLane) {
    atomicMax(&staticscene_wg_bmin[g * 3u], ~wave_ordered_f32(lane.bmin.x));
    atomicMax(&staticscene_wg_bmin[g * 3u + 1u], ~wave_ordered_f32(lane.bmin.y));
    atomicMax(&staticscene_wg_bmin[g * 3u + 2u], ~wave_ordered_f32(lane.bmin.z));
    atomicMax(&staticscene_wg_bmax[g * 3u], wave_ordered_f32(lane.bmax.x));
    atomicMax(&staticscene_wg_bmax[g * 3u + 1u], wave_ordered_f32(lane.bmax.y));
    atomicMax(&staticscene_wg_bmax[g * 3u + 2u], wave_ordered_f32(lane.bmax.z));
    atomicMax(&staticscene_wg_bdepth[g], ~wave_ordered_f32(lane.depth));
    atomicOr(&staticscene_wg_bflags[g], lane.flags);
}

// Writes group g's header at `bslot` (its first instance at `slot`, `count` instances);
// returns 1 when it falls past the buffer (dropped).
fn staticscene_write_header(g: u32, lane: StaticsceneLane, slot: u32, count: u32, bslot: u32) -> u32 {
    let bmin = vec3<f32>(
        wave_unordered_f32(~atomicLoad(&staticscene_wg_bmin[g * 3u])),
        wave_unordered_f32(~atomicLoad(&staticscene_wg_bmin[g * 3u + 1u])),
        wave_unordered_f32(~atomicLoad(&staticscene_wg_bmin[g * 3u + 2u])),
    );
    let bmax = vec3<f32>(
        wave_unordered_f32(atomicLoad(&staticscene_wg_bmax[g * 3u])),
        wave_unordered_f32(atomicLoad(&staticscene_wg_bmax[g * 3u + 1u])),
        wave_unordered_f32(atomicLoad(&staticscene_wg_bmax[g * 3u + 2u])),
    );
    let depth = wave_unordered_f32(~atomicLoad(&staticscene_wg_bdepth[g]));
    if (bslot >= arrayLength(&out_batches)) {
        return 1u;
    }
    let centre = (bmin + bmax) * 0.5;
    let r = length(bmax - bmin) * 0.5;
    out_batches[bslot] = StaticsceneDrawableSetupBatch(
        staticscene_sort_key(lane.handle, depth),
        lane.handle,
        vec4<f32>(centre, r),
        slot,
        atomicLoad(&staticscene_wg_bflags[g]),
        count,
        64u,
    );
    return 0u;
}

// Writes a visible invocation's instance at `slot`; returns 1 when it falls past the buffer.
fn staticscene_write_instance(job: StaticsceneGpuJob, lane: StaticsceneLane, tile_index: u32, slot: u32) -> u32 {
    if (slot >= arrayLength(&out_instances)) {
        return 1u;
    }
    out_instances[slot] = StaticsceneDrawableSetupInstance(StaticsceneInstanceState(lane.fade, lane.flags, job.tile, tile_index), lane.l2f);
    return 0u;
}

#if subgroups
// Per group (subgroup base + group index): visible instances, and the complemented local
// index of the first visible one (atomicMax of ~index keeps the lowest).
var<workgroup> staticscene_wg_count: array<atomic<u32>, 64>;
var<workgroup> staticscene_wg_first: array<atomic<u32>, 64>;

// The run-grouped output of a wave with some visible invocation, HZD's per hardware wave:
// batches never span a subgroup (the CPU twin with the subgroup's width), counts and
// prefixes from ballots, one counter atomic per subgroup; `sg`: the subgroup invocation id
// and the subgroup's first local index. Two workgroup barriers (the bounds accumulation in
// workgroup memory). Returns the items dropped past the buffers.
fn staticscene_output(job: StaticsceneGpuJob, lane: StaticsceneLane, visible: bool, group_end: bool, tile_index: u32, li: u32, sg: vec2<u32>) -> u32 {
    var dropped = 0u;
    let ends = subgroupBallot(group_end);
    let g = sg.y + wave_ballot_count_below(ends, sg.x);
    let a = wave_sg_append_begin(visible, sg.x);
    var old = 0u;
    if (a.total != 0u) {
        old = atomicAdd(&counters.instances, a.total);
    }
    let slot = wave_sg_append_end(a, old);
    if (visible) {
        dropped += staticscene_write_instance(job, lane, tile_index, slot);
        staticscene_fold(g, lane);
        atomicAdd(&staticscene_wg_count[g], 1u);
        atomicMax(&staticscene_wg_first[g], ~li);
    }
    workgroupBarrier();
    let writes = visible && ~atomicLoad(&staticscene_wg_first[g]) == li;
    let h = wave_sg_append_begin(writes, sg.x);
    var old_b = 0u;
    if (h.total != 0u) {
        old_b = atomicAdd(&counters.batches, h.total);
    }
    let bslot = wave_sg_append_end(h, old_b);
    if (writes) {
        dropped += staticscene_write_header(g, lane, slot, atomicLoad(&staticscene_wg_count[g]), bslot);
    }
    return dropped;
}
#else
// The run-grouped output of a wave with some visible invocation: one instance per
// visible invocation, one header per group, workgroup-wide (batches of up to 64, the CPU
// twin's W64). Returns the items dropped past the buffers.
fn staticscene_output(job: StaticsceneGpuJob, lane: StaticsceneLane, visible: bool, group_end: bool, tile_index: u32, li: u32, sg: vec2<u32>) -> u32 {
    var dropped = 0u;
    let b = wave_wg_batch_begin(group_end, visible, li);
    var old = 0u;
    if (b.instance.total != 0u) {
        old = atomicAdd(&counters.instances, b.instance.total);
    }
    let slot = wave_wg_append_end(b.instance, old);
    if (visible) {
        dropped += staticscene_write_instance(job, lane, tile_index, slot);
        staticscene_fold(b.group, lane);
    }
    let hdr = wave_wg_batch_headers_begin(b, li);
    var old_b = 0u;
    if (hdr.append.total != 0u) {
        old_b = atomicAdd(&counters.batches, hdr.append.total);
    }
    let bslot = wave_wg_append_end(hdr.append, old_b);
    if (hdr.append.amount != 0u) {
        dropped += staticscene_write_header(b.group, lane, slot, hdr.instance_count, bslot);
    }
    return dropped;
}
#endif

@compute @workgroup_size(64)
#if subgroups
fn query(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
    @builtin(subgroup_invocation_id) sg_lane: u32,
    @builtin(subgroup_id) sg_id: u32,
    @builtin(subgroup_size) sg_size: u32,
) {
    // Subgroups are taken to tile the workgroup in local-index order (so a subgroup's
    // lanes are consecutive instances, as the CPU twin's waves).
    let sg = vec2<u32>(sg_lane, sg_id * sg_size);
#else
fn query(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) li: u32) {
    let sg = vec2<u32>(li, 0u);
#endif
    let wave = wid.y * STATICSCENE_MAX_WORKGROUPS_X + wid.x;
    let job_count = min(job_list.count, arrayLength(&job_list.jobs));
    if (wave >= job_list.waves || job_count == 0u) {
        return;
    }
    if (wave >= arrayLength(&wave_jobs)) {
        return;
    }
    // A corrupt table entry names a job whose waves do not hold this one: the wave is
    // dropped by the test below, never run against another job's records.
    let job = job_list.jobs[min(wave_jobs[wave], job_count - 1u)];
    let job_waves = (job.count + STATICSCENE_QUERY_WORKGROUP - 1u) / STATICSCENE_QUERY_WORKGROUP;
    if (wave < job.first_wave || wave - job.first_wave >= job_waves) {
        return;
    }
    // A cluster the pre-cull rejected for its LOD runs only while some instance fades
    // (the serial is read only for such jobs: a dependent load and a barrier less for the
    // others).
    if ((job.flags & STATICSCENE_JOB_LOD_UNLESS_LIVE) != 0u) {
        if (li == 0u) {
            var serial = 0u;
            if (job.cluster < arrayLength(&state)) {
                serial = atomicLoad(&state[job.cluster]);
            }
            staticscene_wg_live_serial = serial;
        }
        let live_serial = workgroupUniformLoad(&staticscene_wg_live_serial);
        // Live at its last run, or marked live by another workgroup of this run (which ran
        // because it was live at its last run).
        if (live_serial != job.last_run && live_serial != job.serial) {
            return;
        }
    }
    let local = (wave - job.first_wave) * STATICSCENE_QUERY_WORKGROUP + li;
    let tile_index = job.first + local;
    let global_index = job.instance_base + tile_index;
    let has_instance = local < job.count && global_index >= job.instance_base && global_index < arrayLength(&instances);
    var lane: StaticsceneLane;
    lane.outcome = STATICSCENE_STAT_COUNT;
    var q = vec4<u32>(0u);
    if (has_instance) {
        q = instances[global_index];
        lane = staticscene_test(job, staticscene_job_records_fit(job), q, tile_index);
    }
    let visible = lane.outcome == STATICSCENE_STAT_VISIBLE;
    if (visible) {
        atomicOr(&staticscene_wg_any_visible, 1u);
    }
    workgroupBarrier();
    if (li == 0u) {
        staticscene_wg_any_visible_copy = atomicLoad(&staticscene_wg_any_visible);
    }
    var dropped = 0u;
    if (workgroupUniformLoad(&staticscene_wg_any_visible_copy) != 0u) {
        dropped = staticscene_output(job, lane, visible, has_instance && staticscene_group_end(q), tile_index, li, sg);
    }
    // Statistics: one global atomic per counter per workgroup.
    if (has_instance) {
        atomicAdd(&staticscene_wg_stats[STATICSCENE_STAT_THREADS], 1u);
        if (lane.outcome != STATICSCENE_STAT_VISIBLE) {
            atomicAdd(&staticscene_wg_stats[lane.outcome], 1u);
        }
    }
    if (dropped != 0u) {
        atomicAdd(&staticscene_wg_stats[STATICSCENE_STAT_DROPPED], dropped);
    }
    if (lane.live && (params.flags & STATICSCENE_QUERY_FLAG_FIRST_PASS) == 0u && job.cluster < arrayLength(&state)) {
        atomicStore(&state[job.cluster], job.serial);
    }
    workgroupBarrier();
    if (li < STATICSCENE_STAT_COUNT) {
        let v = atomicLoad(&staticscene_wg_stats[li]);
        if (v != 0u) {
            atomicAdd(&counters.stats[li], v);
        }
    }
}
