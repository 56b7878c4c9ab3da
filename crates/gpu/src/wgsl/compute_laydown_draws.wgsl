// gpu: what the compute laydown and its hardware part share (issue 17): the draw table
// (the scene's planned draws, one row per micro batch, with the exclusive prefix of their
// items), the index buffer, the 64-bit visibility target, and the item -> triangle
// lookup. One item is one (instance, triangle) of a draw; the items of draw `d` are
// `rows[d].first_item ..` in instance-major order (consecutive invocations share an
// instance and its transform). Rust twin: gpu's GpuLaydownDraw and GpuLaydownDraws.

#import gpu::geometry

struct GpuLaydownDraw {
    // First item of this draw: the sum of `instance_count * triangles` of the rows before.
    first_item: u32,
    first_index: u32,
    base_vertex: u32,
    first_instance: u32,
    instance_count: u32,
    // Triangles of the mesh (at least 1: the table leaves out empty draws).
    triangles: u32,
    // GPU_LAYDOWN_DRAW_ALPHA_TESTED.
    flags: u32,
    pad: u32,
}

// The draw's material is alpha-tested.
const GPU_LAYDOWN_DRAW_ALPHA_TESTED: u32 = 1u;

struct GpuLaydownDraws {
    // Rows in `rows` that hold draws.
    count: u32,
    // Items of every draw: the raster dispatch's invocation count.
    items: u32,
    pad0: u32,
    pad1: u32,
    rows: array<GpuLaydownDraw>,
}

@group(1) @binding(0) var<storage, read> laydown_draws: GpuLaydownDraws;
@group(1) @binding(1) var<storage, read> laydown_indices: array<u32>;
// The 64-bit visibility target, one word a pixel: depth's f32 bits in the high 32 bits
// (reversed Z: larger is nearer, and a non-negative f32's bits order as a u32's), the vis
// word in the low 32 bits, so an atomic max keeps the nearest fragment (ties: the larger
// vis word). 0 at the start of each frame: nothing drawn (depth 0, the far plane). An
// r64uint storage texture with `texture_target` (TEXTURE_INT64_ATOMIC; reset by the
// unpack), else a row-major storage buffer (SHADER_INT64_ATOMIC_MIN_MAX; cleared).
#if texture_target
@group(1) @binding(2) var laydown_target: texture_storage_2d<r64uint, atomic>;
#else
@group(1) @binding(2) var<storage, read_write> laydown_target: array<atomic<u64>>;
#endif

// The atomic max of `value` into pixel `p` of the target (`width`: the image's); nothing
// outside it.
fn gpu_laydown_plot(p: vec2<u32>, width: u32, value: u64) {
#if texture_target
    if (all(p < textureDimensions(laydown_target))) {
        textureAtomicMax(laydown_target, p, value);
    }
#else
    let i = p.y * width + p.x;
    if (p.x < width && i < arrayLength(&laydown_target)) {
        atomicMax(&laydown_target[i], value);
    }
#endif
}

// One item's triangle: its instance, primitive (triangle of the mesh: the vis word's
// primitive field, as `primitive_index` counts it from the draw's first index), its
// three vertices (already offset by the base vertex) and the draw's flags. `valid` is
// false for an item past the table or whose indices, vertices or instance lie outside
// their buffers (nothing is drawn for it).
struct GpuLaydownTriangle {
    valid: bool,
    instance: u32,
    primitive: u32,
    vertices: vec3<u32>,
    flags: u32,
}

fn gpu_laydown_triangle(item: u32) -> GpuLaydownTriangle {
    var t: GpuLaydownTriangle;
    t.valid = false;
    let count = min(laydown_draws.count, arrayLength(&laydown_draws.rows));
    if (count == 0u || item >= laydown_draws.items) {
        return t;
    }
    // The last row whose first item is at or below `item` (rows ascend by first item).
    var lo = 0u;
    var hi = count - 1u;
    while (lo < hi) {
        let mid = (lo + hi + 1u) / 2u;
        if (laydown_draws.rows[mid].first_item <= item) {
            lo = mid;
        } else {
            hi = mid - 1u;
        }
    }
    let row = laydown_draws.rows[lo];
    let local = item - row.first_item;
    let triangles = max(row.triangles, 1u);
    let k = local / triangles;
    if (k >= row.instance_count) {
        return t;
    }
    t.primitive = local - k * triangles;
    t.instance = row.first_instance + k;
    t.flags = row.flags;
    let first = row.first_index + 3u * t.primitive;
    if (t.instance >= arrayLength(&instances) || first + 2u >= arrayLength(&laydown_indices)) {
        return t;
    }
    t.vertices = vec3<u32>(
        laydown_indices[first],
        laydown_indices[first + 1u],
        laydown_indices[first + 2u],
    ) + vec3<u32>(row.base_vertex);
    let n = arrayLength(&vertices);
    t.valid = all(t.vertices < vec3<u32>(n));
    return t;
}

// The target word of a fragment at `depth` (reversed Z, in [0, 1]) with vis word `word`.
// A negative depth (rounding past the far plane, or -0) becomes 0, which never beats the
// cleared target's far plane.
fn gpu_laydown_value(depth: f32, word: u32) -> u64 {
    var bits = bitcast<u32>(depth);
    if (bits >= 0x80000000u) {
        bits = 0u;
    }
    return (u64(bits) << 32u) | u64(word);
}
