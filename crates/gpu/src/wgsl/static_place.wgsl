// gpu: the static query's output placed in the frame, with no CPU round trip (issue 13).
// The query appends HZD's batches (DrawableSetupBatch, run-grouped by setup) and their
// instances; here each batch claims a run of its setup's reserved instance slots (one
// atomic per batch, by its first lane), its lanes write the instances' GpuInstance rows with
// the vis-word fields of their rank (tiling's reserved range: rank r -> ID first_id +
// r >> (16 - p)), then one invocation per setup with placed instances appends its indexed
// indirect draw (opaque or alpha-tested list) and bumps that list's count. With two-pass
// occlusion the placement runs twice a frame: the second run's instances take the slots
// after the first's, `emit_late_draws` rewrites the full list (every placed instance, for
// passes that draw the whole frame, like the baseline's) and writes the late list (only
// the instances placed since the first run, for the laydown's second geometry pass). Every index is
// checked: a batch naming no setup, a source past the query's buffers, or a rank past
// the setup's capacity is dropped and counted, never written.
//
// Rust twins: GpuStaticSetup, GpuStaticParams (gpu's rows.rs), STATIC_COUNTER_* (static_place.rs).

#import visbuf::id
#import gpu::frame
#import staticscene::query

// What a setup handle draws, and where its slots and IDs are.
struct GpuStaticSetup {
    first_index: u32,
    index_count: u32,
    base_vertex: u32,
    first_slot: u32,
    capacity: u32,
    first_id: u32,
    primitive_bits: u32,
    material: u32,
    // 0: opaque list, 1: alpha-tested list.
    list: u32,
    // The setup's index within its list's part of the draw buffer is not fixed (draws are
    // appended); these pad to 48 bytes.
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

struct GpuStaticParams {
    // The query's floating origin minus the scene's origin (metres, whole numbers): added
    // to every output translation so the rows share the scene's origin.
    offset: vec4<f32>,
    setup_count: u32,
    // Workgroups per dispatch row (shader::MAX_WORKGROUPS_X).
    row_width: u32,
    // First draw of the alpha-tested list in `draws` (the opaque setups' count).
    alpha_base: u32,
    // The first reserved slot: slot s's debug word is debug[s - debug_base] (0xffffffff:
    // no debug words, as for shadow views).
    debug_base: u32,
    // The slot of `instances`' first row: slot s is row s - row_base, and draws name that
    // row as their first instance (0 for the camera view, whose rows are the scene's
    // instance table; the first reserved slot for a shadow view, whose own rows hold the
    // reserved slots only, so its placement never touches the camera's rows).
    row_base: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

// counters[GPU_STATIC_COUNTER_DRAWS + list]: draws appended per list (the count buffer).
const GPU_STATIC_COUNTER_DRAWS: u32 = 0u;
// counters[GPU_STATIC_COUNTER_LATE_DRAWS + list]: the late lists' counts.
const GPU_STATIC_COUNTER_LATE_DRAWS: u32 = 2u;
// Instances dropped past their setup's capacity.
const GPU_STATIC_COUNTER_OVER_CAPACITY: u32 = 4u;
// Batches dropped: no such setup, or a source past the query's buffers.
const GPU_STATIC_COUNTER_BAD_BATCHES: u32 = 5u;
// counters[GPU_STATIC_COUNTER_PLACED + s]: instances of setup s (before the capacity clamp);
// counters[GPU_STATIC_COUNTER_PLACED + setup_count + s]: those placed by the first run.
const GPU_STATIC_COUNTER_PLACED: u32 = 6u;
// The query's counter words: visible instances, batches.
const GPU_STATIC_QUERY_BATCHES: u32 = 1u;
// Words per DrawIndexedIndirect.
const GPU_STATIC_DRAW_WORDS: u32 = 5u;
const GPU_STATIC_BATCH_LANES: u32 = 64u;

@group(0) @binding(0) var<uniform> params: GpuStaticParams;
@group(0) @binding(1) var<storage, read> setups: array<GpuStaticSetup>;
@group(0) @binding(2) var<storage, read> query_counters: array<u32>;
@group(0) @binding(3) var<storage, read> query_instances: array<StaticsceneDrawableSetupInstance>;
@group(0) @binding(4) var<storage, read> query_batches: array<StaticsceneDrawableSetupBatch>;
@group(0) @binding(5) var<storage, read_write> counters: array<atomic<u32>>;
@group(0) @binding(6) var<storage, read_write> instances: array<GpuInstance>;
@group(0) @binding(7) var<storage, read_write> place_dispatch: array<u32>;
@group(0) @binding(8) var<storage, read_write> draws: array<u32>;
// Per reserved slot, what placed it this frame (for debug views; slots not placed this
// frame keep older words, and no pixel shows them): fade opacity in bits 0-7 (0-255),
// the query's state flags in 8-15, GPU_STATIC_DEBUG_LATE for the second placement.
@group(0) @binding(9) var<storage, read_write> debug: array<u32>;

// Debug word: the state flags' first bit (the fade opacity, 0-255, below it).
const GPU_STATIC_DEBUG_FLAGS_SHIFT: u32 = 8u;
const GPU_STATIC_DEBUG_LATE: u32 = 0x10000u;

// Batches the query wrote that its buffer holds.
fn gpu_static_batch_count() -> u32 {
    return min(query_counters[GPU_STATIC_QUERY_BATCHES], arrayLength(&query_batches));
}

// The workgroups of `place`: one per batch, in rows of `row_width`.
@compute @workgroup_size(1)
fn place_args() {
    let n = gpu_static_batch_count();
    let w = max(params.row_width, 1u);
    place_dispatch[0] = min(n, w);
    place_dispatch[1] = (n + w - 1u) / w;
    place_dispatch[2] = 1u;
}

var<workgroup> gpu_static_wg_setup: u32;
var<workgroup> gpu_static_wg_count: u32;
var<workgroup> gpu_static_wg_base: u32;
var<workgroup> gpu_static_wg_source: u32;

// One workgroup per batch (a batch holds at most 64 instances); `late`: the frame's second
// placement (two-pass occlusion), recorded in the debug words.
fn gpu_static_place(wid: vec3<u32>, li: u32, late: bool) {
    let b = wid.y * params.row_width + wid.x;
    if li == 0u {
        gpu_static_wg_count = 0u;
        if b < gpu_static_batch_count() {
            let batch = query_batches[b];
            let count = min(batch.count, GPU_STATIC_BATCH_LANES);
            let n = arrayLength(&query_instances);
            let bad = batch.setup.y != 0u || batch.setup.x >= params.setup_count
                || batch.setup.x >= arrayLength(&setups) || batch.first_instance > n
                || count > n - min(batch.first_instance, n);
            if bad {
                atomicAdd(&counters[GPU_STATIC_COUNTER_BAD_BATCHES], 1u);
            } else if count > 0u {
                gpu_static_wg_setup = batch.setup.x;
                gpu_static_wg_count = count;
                gpu_static_wg_source = batch.first_instance;
                gpu_static_wg_base = atomicAdd(&counters[GPU_STATIC_COUNTER_PLACED + batch.setup.x], count);
            }
        }
    }
    let count = workgroupUniformLoad(&gpu_static_wg_count);
    if li >= count {
        return;
    }
    let s = setups[gpu_static_wg_setup];
    let rank = gpu_static_wg_base + li;
    if rank >= s.capacity {
        atomicAdd(&counters[GPU_STATIC_COUNTER_OVER_CAPACITY], 1u);
        return;
    }
    let slot = s.first_slot + rank;
    if slot < params.row_base || slot - params.row_base >= arrayLength(&instances) {
        return;
    }
    let src = query_instances[gpu_static_wg_source + li].local_to_floating.rows;
    let id = visbuf_split_instance(s.first_id, rank, s.primitive_bits);
    var out: GpuInstance;
    out.row0 = src[0] + vec4<f32>(0.0, 0.0, 0.0, params.offset.x);
    out.row1 = src[1] + vec4<f32>(0.0, 0.0, 0.0, params.offset.y);
    out.row2 = src[2] + vec4<f32>(0.0, 0.0, 0.0, params.offset.z);
    out.micro_batch = id.x;
    out.instance_field = id.y;
    out.primitive_bits = s.primitive_bits | gpu_static_fade_bits(query_instances[gpu_static_wg_source + li].state);
    out.material = s.material;
    instances[slot - params.row_base] = out;
    let d = slot - min(params.debug_base, slot);
    if slot >= params.debug_base && d < arrayLength(&debug) {
        let st = query_instances[gpu_static_wg_source + li].state;
        let fade = u32(round(clamp(st.fade, 0.0, 1.0) * 255.0));
        debug[d] = fade | ((st.flags & 0xffu) << GPU_STATIC_DEBUG_FLAGS_SHIFT) | select(0u, GPU_STATIC_DEBUG_LATE, late);
    }
}

@compute @workgroup_size(64)
fn place(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) li: u32) {
    gpu_static_place(wid, li, false);
}

@compute @workgroup_size(64)
fn place_late(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) li: u32) {
    gpu_static_place(wid, li, true);
}


// HZD's LOD fade for the laydown's dither (GPU_INSTANCE_FADE_*): a fading instance's
// opacity as kept Bayer cells of 16 (rounded; a pair fading across each other sums to 16),
// and whether it fades out.
fn gpu_static_fade_bits(st: StaticsceneInstanceState) -> u32 {
    if ((st.flags & STATICSCENE_STATE_FADING) == 0u) {
        return 0u;
    }
    let cells = u32(round(clamp(st.fade, 0.0, 1.0) * 16.0));
    let out = select(0u, GPU_INSTANCE_FADING_OUT, (st.flags & STATICSCENE_STATE_FADING_OUT) != 0u);
    return GPU_INSTANCE_FADING | out | (cells << GPU_INSTANCE_FADE_CELLS_SHIFT);
}

// Appends setup i's draw of its instances [first, end) to list `list` of draw block
// `block` (0: full lists, 1: late lists).
fn gpu_static_append_draw(s: GpuStaticSetup, block: u32, first: u32, end: u32) {
    if first >= end || s.list > 1u || s.first_slot < params.row_base {
        return;
    }
    let d = atomicAdd(&counters[select(GPU_STATIC_COUNTER_DRAWS, GPU_STATIC_COUNTER_LATE_DRAWS, block == 1u) + s.list], 1u);
    let at = (block * params.setup_count + select(0u, params.alpha_base, s.list == 1u) + d) * GPU_STATIC_DRAW_WORDS;
    if at + GPU_STATIC_DRAW_WORDS > arrayLength(&draws) {
        return;
    }
    draws[at] = s.index_count;
    draws[at + 1u] = end - first;
    draws[at + 2u] = s.first_index;
    draws[at + 3u] = s.base_vertex;
    draws[at + 4u] = s.first_slot - params.row_base + first;
}

// Whether setup i is in the table (one invocation per setup, rounded up to workgroups).
fn gpu_static_is_setup(i: u32) -> bool {
    return i < params.setup_count && i < arrayLength(&setups);
}

// Setup i's placed instances, clamped to its capacity (i a setup of the table).
fn gpu_static_placed(i: u32) -> u32 {
    return min(atomicLoad(&counters[GPU_STATIC_COUNTER_PLACED + i]), setups[i].capacity);
}

// One invocation per setup: the draw of its placed instances, appended to its full list;
// remembers how many that is for a later run's late list.
@compute @workgroup_size(64)
fn emit_draws(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if !gpu_static_is_setup(i) {
        return;
    }
    let n = gpu_static_placed(i);
    atomicStore(&counters[GPU_STATIC_COUNTER_PLACED + params.setup_count + i], n);
    gpu_static_append_draw(setups[i], 0u, 0u, n);
}

// After a second run: the full list again (every instance of the frame), and the late
// list (the instances placed since `emit_draws`).
@compute @workgroup_size(64)
fn emit_late_draws(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if !gpu_static_is_setup(i) {
        return;
    }
    let n = gpu_static_placed(i);
    let early = min(atomicLoad(&counters[GPU_STATIC_COUNTER_PLACED + params.setup_count + i]), n);
    gpu_static_append_draw(setups[i], 0u, 0u, n);
    gpu_static_append_draw(setups[i], 1u, early, n);
}
