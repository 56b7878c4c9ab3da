// gpu: KZ2's conditional rendering, emulated with indirect draws. KZ2 ran a pixel query
// during a shadow-casting light's stencil pass and let the GPU skip the light's shadow map
// and its shading when no pixel passed. wgpu has no conditional rendering: the light
// volumes' test pass (passes::light_volumes) counts, per tested light, the pixels its
// shading would cover (an occlusion query, resolved into `queries`), and this pass turns
// the counts into the indirect arguments of that light's spot-map caster draws and of its
// volume draws: the same draws where the count is non-zero, none where it is zero. One
// invocation per tested light and per caster draw; every index is bounded, so corrupt rows
// draw nothing rather than read or write out of bounds.

// Rust: passes::conditional::GpuConditionalParams (16 bytes).
struct GpuConditionalParams {
    // tested lights (rows of `tests`, queries)
    tests: u32,
    // caster draw rows
    casters: u32,
    // indices of the unit volume mesh (every volume draw's index_count)
    volume_indices: u32,
    pad: u32,
}

// Rust: passes::conditional::GpuConditionalTest (16 bytes): one tested light.
struct GpuConditionalTest {
    // its GpuLightVolume row (the volume draw's first_instance)
    volume: u32,
    // its map's opaque and alpha-tested caster draws (the count words' values)
    opaque: u32,
    alpha: u32,
    pad: u32,
}

// Rust: passes::conditional::GpuCasterDraw (32 bytes): a spot-map caster draw as the CPU
// culled it, and the test that decides it.
struct GpuCasterDraw {
    index_count: u32,
    instance_count: u32,
    first_index: u32,
    base_vertex: i32,
    first_instance: u32,
    test: u32,
    pad: vec2<u32>,
}

// Rust: passes::conditional::DRAW_WORDS: words of one DrawIndexedIndirect.
const GPU_CONDITIONAL_DRAW_WORDS: u32 = 5u;
// Rust: passes::conditional::COUNT_WORDS: count words per tested light.
const GPU_CONDITIONAL_COUNT_WORDS: u32 = 4u;

@group(0) @binding(0) var<uniform> params: GpuConditionalParams;
// Per test: the occlusion query's 64-bit sample count (low word, high word).
@group(0) @binding(1) var<storage, read> queries: array<vec2<u32>>;
@group(0) @binding(2) var<storage, read> tests: array<GpuConditionalTest>;
@group(0) @binding(3) var<storage, read> caster_rows: array<GpuCasterDraw>;
// The static query's full draw lists' counts this frame (opaque, alpha-tested; zeros in a
// frame without one), copied from the placement's counters.
@group(0) @binding(4) var<storage, read> static_counts: array<u32>;
// Outputs: DrawIndexedIndirect per caster row, per tested light's volume, and per tested
// light GPU_CONDITIONAL_COUNT_WORDS counts for multi_draw_indexed_indirect_count: its
// map's opaque and alpha-tested caster rows, and the static lists' opaque and
// alpha-tested draws.
@group(0) @binding(5) var<storage, read_write> caster_args: array<u32>;
@group(0) @binding(6) var<storage, read_write> volume_args: array<u32>;
@group(0) @binding(7) var<storage, read_write> counts: array<u32>;

fn conditional_test_count() -> u32 {
    return min(params.tests, min(arrayLength(&queries), arrayLength(&tests)));
}

// Whether test `t` counted a pixel; false for a test that does not exist.
fn conditional_visible(t: u32) -> bool {
    if (t >= conditional_test_count()) {
        return false;
    }
    let q = queries[t];
    return (q.x | q.y) != 0u;
}

@compute @workgroup_size(64)
fn conditional_args(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    let w = GPU_CONDITIONAL_DRAW_WORDS;
    if (i < conditional_test_count()) {
        let visible = conditional_visible(i);
        let t = tests[i];
        if ((i + 1u) * w <= arrayLength(&volume_args)) {
            volume_args[i * w] = params.volume_indices;
            volume_args[i * w + 1u] = select(0u, 1u, visible);
            volume_args[i * w + 2u] = 0u;
            volume_args[i * w + 3u] = 0u;
            volume_args[i * w + 4u] = t.volume;
        }
        let c = GPU_CONDITIONAL_COUNT_WORDS;
        if ((i + 1u) * c <= arrayLength(&counts)) {
            counts[i * c] = select(0u, t.opaque, visible);
            counts[i * c + 1u] = select(0u, t.alpha, visible);
            // The draw calls bound these by the lists' capacities.
            let n = arrayLength(&static_counts);
            counts[i * c + 2u] = select(0u, static_counts[0u], visible && n >= 1u);
            counts[i * c + 3u] = select(0u, static_counts[min(1u, n - 1u)], visible && n >= 2u);
        }
    }
    let casters = min(params.casters, min(arrayLength(&caster_rows), arrayLength(&caster_args) / w));
    if (i < casters) {
        let d = caster_rows[i];
        // Zeroed instances as well as zero counts: the draws are skipped with or without
        // a count buffer.
        caster_args[i * w] = d.index_count;
        caster_args[i * w + 1u] = select(0u, d.instance_count, conditional_visible(d.test));
        caster_args[i * w + 2u] = d.first_index;
        caster_args[i * w + 3u] = bitcast<u32>(d.base_vertex);
        caster_args[i * w + 4u] = d.first_instance;
    }
}
