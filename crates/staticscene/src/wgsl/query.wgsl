// staticscene::query: the query's records and per-thread tests (twin of src/query.rs),
// imported by staticscene::query_pass and staticscene::hiz_pass.
// Binding-free: structs, constants and functions, all prefixed staticscene_ / Staticscene.
// Constants equal the Rust constants of the same meaning (read back in unit tests).

// QueryInstance bit layout: 128 bits in a vec4<u32>, little-endian words.
const STATICSCENE_FILTER_SHIFT: u32 = 0u;
const STATICSCENE_FLAGS_SHIFT: u32 = 3u;
const STATICSCENE_SETUP_SHIFT: u32 = 5u;
const STATICSCENE_OBJECT_SHIFT: u32 = 17u;
const STATICSCENE_PARENT_BOUNDS_SHIFT: u32 = 34u;
const STATICSCENE_CHILD_BOUNDS_SHIFT: u32 = 49u;
const STATICSCENE_MATRIX_SHIFT: u32 = 64u;
const STATICSCENE_PARENT_LOD_MIN_SHIFT: u32 = 78u;
const STATICSCENE_PARENT_LOD_MAX_SHIFT: u32 = 90u;
const STATICSCENE_CHILD_LOD_MIN_SHIFT: u32 = 102u;
const STATICSCENE_CHILD_LOD_MAX_SHIFT: u32 = 114u;
const STATICSCENE_GROUP_END_SHIFT: u32 = 126u;
const STATICSCENE_INSTANCE_FLAG_NO_OCCLUSION: u32 = 1u;
const STATICSCENE_INSTANCE_FLAG_NO_FADE: u32 = 2u;
const STATICSCENE_OBJECT_FLAG_IGNORE_GLOBAL_LOD_SCALE: u32 = 65536u;
const STATICSCENE_LOD_CODE_INFINITY: u32 = 4095u;
const STATICSCENE_QUERY_FLAG_FADE: u32 = 1u;
const STATICSCENE_QUERY_FLAG_OCCLUSION: u32 = 2u;
const STATICSCENE_QUERY_FLAG_REVERSED_DEPTH: u32 = 4u;
const STATICSCENE_QUERY_FLAG_SIZE: u32 = 8u;
const STATICSCENE_QUERY_FLAG_FIRST_PASS: u32 = 16u;
const STATICSCENE_QUERY_FLAG_SECOND_PASS: u32 = 32u;
const STATICSCENE_QUERY_FLAG_SHADOW: u32 = 64u;
// Bit of an instance's camera state byte: visible in the last query that wrote it.
const STATICSCENE_CAMERA_STATE_VISIBLE: u32 = 0x80u;
const STATICSCENE_STATE_FADING: u32 = 1u;
const STATICSCENE_STATE_FADING_OUT: u32 = 2u;
const STATICSCENE_FRUSTUM_TOLERANCE: f32 = 1e-5;
const STATICSCENE_HIZ_DEPTH_EPSILON: f32 = 9.5367431640625e-7;
// The HiZ buffer of the query and HiZ passes: a header of the level count, three spare
// words and 16 levels (width, height, first texel word, 0), then texels as f32 bits.
const STATICSCENE_HIZ_MAX_LEVELS: u32 = 16u;
const STATICSCENE_HIZ_HEADER_WORDS: u32 = 68u;

struct StaticsceneQueryInstance {
    words: vec4<u32>,
}

struct StaticsceneTransform {
    rows: array<vec4<f32>, 3>,
}

struct StaticsceneQueryObject {
    object_to_snapped: StaticsceneTransform,
    snapped: vec3<i32>,
    lod: u32,
}

struct StaticsceneQuerySetup {
    bounds: array<f32, 6>,
    handle: vec2<u32>,
}

struct StaticsceneHalfAabb {
    words: array<u32, 3>,
}

struct StaticsceneInstanceState {
    fade: f32,
    flags: u32,
    tile: u32,
    instance: u32,
}

struct StaticsceneDrawableSetupInstance {
    state: StaticsceneInstanceState,
    local_to_floating: StaticsceneTransform,
}

struct StaticsceneDrawableSetupBatch {
    sort_key: vec2<u32>,
    setup: vec2<u32>,
    sphere: vec4<f32>,
    first_instance: u32,
    flags: u32,
    count: u32,
    stride: u32,
}

struct StaticsceneQueryParams {
    clip_from_floating: mat4x4<f32>,
    hiz_clip_from_floating: mat4x4<f32>,
    planes: array<vec4<f32>, 6>,
    forward: vec4<f32>,
    lod_point: vec4<f32>,
    origin: vec4<i32>,
    prev_origin: vec4<i32>,
    viewport: vec4<f32>,
    filter_mask: u32,
    flags: u32,
    fade_frames: u32,
    hiz_scan_levels: u32,
}

struct StaticsceneAabb {
    min: vec3<f32>,
    max: vec3<f32>,
}

fn staticscene_filter(q: vec4<u32>) -> u32 {
    return q.x & 7u;
}

fn staticscene_flags(q: vec4<u32>) -> u32 {
    return (q.x >> STATICSCENE_FLAGS_SHIFT) & 3u;
}

fn staticscene_setup(q: vec4<u32>) -> u32 {
    return (q.x >> STATICSCENE_SETUP_SHIFT) & 0xfffu;
}

// Bits 17-33: across words 0 and 1.
fn staticscene_object(q: vec4<u32>) -> u32 {
    return (q.x >> 17u) | ((q.y & 3u) << 15u);
}

fn staticscene_parent_bounds(q: vec4<u32>) -> u32 {
    return (q.y >> 2u) & 0x7fffu;
}

fn staticscene_child_bounds(q: vec4<u32>) -> u32 {
    return q.y >> 17u;
}

fn staticscene_matrix(q: vec4<u32>) -> u32 {
    return q.z & 0x3fffu;
}

// (min, max) 12-bit LOD codes; the max straddles words 2 and 3.
fn staticscene_parent_lod(q: vec4<u32>) -> vec2<u32> {
    return vec2<u32>((q.z >> 14u) & 0xfffu, (q.z >> 26u) | ((q.w & 0x3fu) << 6u));
}

fn staticscene_child_lod(q: vec4<u32>) -> vec2<u32> {
    return vec2<u32>((q.w >> 6u) & 0xfffu, (q.w >> 18u) & 0xfffu);
}

fn staticscene_group_end(q: vec4<u32>) -> bool {
    return ((q.w >> 30u) & 1u) != 0u;
}

// A finite LOD code in metres, exact (the code's bits are the f32's). The infinity code
// is not decoded: staticscene_lod_selects tests it explicitly (WGSL has no reliable inf).
fn staticscene_decode_lod(code: u32) -> f32 {
    let e = code >> 8u;
    let m = code & 0xffu;
    let normal = bitcast<f32>(((e + 128u) << 23u) | (m << 15u));
    return select(normal, f32(m) * (1.0 / 64.0), e == 0u);
}

// min² s² <= d² < max² s², the max infinite for the infinity code.
fn staticscene_lod_selects(codes: vec2<u32>, d2: f32, scale2: f32) -> bool {
    let lo = staticscene_decode_lod(codes.x);
    let hi = staticscene_decode_lod(codes.y);
    let below_max = codes.y == STATICSCENE_LOD_CODE_INFINITY || d2 < hi * hi * scale2;
    return d2 >= lo * lo * scale2 && below_max;
}

// f16 bits (low 16 bits of `h`) to f32, exact for finite values, subnormals included
// (rebuilt by a multiply, so a GPU that flushes f32 subnormals still gets them right);
// written out because unpack2x16float needs a capability. The encoder never stores
// infinities or NaN.
fn staticscene_f16(h: u32) -> f32 {
    let sign = (h & 0x8000u) << 16u;
    let e = (h >> 10u) & 0x1fu;
    let m = h & 0x3ffu;
    let normal = bitcast<f32>(sign | (((h & 0x7fffu) + 0x1c000u) << 13u));
    let sub = select(1.0, -1.0, sign != 0u) * f32(m) * 5.9604644775390625e-8;
    return select(normal, sub, e == 0u);
}

fn staticscene_half_box(b: StaticsceneHalfAabb) -> StaticsceneAabb {
    let w = b.words;
    return StaticsceneAabb(
        vec3<f32>(staticscene_f16(w[0] & 0xffffu), staticscene_f16(w[0] >> 16u), staticscene_f16(w[1] & 0xffffu)),
        vec3<f32>(staticscene_f16(w[1] >> 16u), staticscene_f16(w[2] & 0xffffu), staticscene_f16(w[2] >> 16u)),
    );
}

fn staticscene_setup_box(s: StaticsceneQuerySetup) -> StaticsceneAabb {
    return StaticsceneAabb(
        vec3<f32>(s.bounds[0], s.bounds[1], s.bounds[2]),
        vec3<f32>(s.bounds[3], s.bounds[4], s.bounds[5]),
    );
}

fn staticscene_lod_scale(o: StaticsceneQueryObject) -> f32 {
    return staticscene_f16(o.lod & 0xffffu);
}

fn staticscene_ignores_global_lod_scale(o: StaticsceneQueryObject) -> bool {
    return (o.lod & STATICSCENE_OBJECT_FLAG_IGNORE_GLOBAL_LOD_SCALE) != 0u;
}

// Object space to the floating space of the snapped origin `origin`.
fn staticscene_object_to_floating(o: StaticsceneQueryObject, origin: vec3<i32>) -> StaticsceneTransform {
    let d = vec3<f32>(o.snapped - origin);
    var t = o.object_to_snapped;
    t.rows[0].w += d.x;
    t.rows[1].w += d.y;
    t.rows[2].w += d.z;
    return t;
}

fn staticscene_transform_point(t: StaticsceneTransform, p: vec3<f32>) -> vec3<f32> {
    let h = vec4<f32>(p, 1.0);
    return vec3<f32>(dot(t.rows[0], h), dot(t.rows[1], h), dot(t.rows[2], h));
}

// a ∘ b: b first.
fn staticscene_mul(a: StaticsceneTransform, b: StaticsceneTransform) -> StaticsceneTransform {
    var out: StaticsceneTransform;
    for (var i = 0u; i < 3u; i++) {
        let r = a.rows[i];
        out.rows[i] = r.x * b.rows[0] + r.y * b.rows[1] + r.z * b.rows[2] + vec4<f32>(0.0, 0.0, 0.0, r.w);
    }
    return out;
}

// The box enclosing the transformed box (centre and absolute extent).
fn staticscene_transform_aabb(t: StaticsceneTransform, b: StaticsceneAabb) -> StaticsceneAabb {
    let c = (b.min + b.max) * 0.5;
    let e = (b.max - b.min) * 0.5;
    let tc = staticscene_transform_point(t, c);
    let te = vec3<f32>(
        dot(abs(t.rows[0].xyz), e),
        dot(abs(t.rows[1].xyz), e),
        dot(abs(t.rows[2].xyz), e),
    );
    return StaticsceneAabb(tc - te, tc + te);
}

fn staticscene_dist2(p: vec3<f32>, b: StaticsceneAabb) -> f32 {
    let d = max(max(b.min - p, p - b.max), vec3<f32>(0.0));
    return dot(d, d);
}

// Conservative: outside only beyond the tolerance of the magnitudes involved.
fn staticscene_box_outside_frustum(planes: array<vec4<f32>, 6>, b: StaticsceneAabb) -> bool {
    for (var i = 0u; i < 6u; i++) {
        let p = planes[i];
        let v = select(b.min, b.max, p.xyz >= vec3<f32>(0.0));
        let t = p.xyz * v;
        let d = t.x + t.y + t.z + p.w;
        let mag = abs(t.x) + abs(t.y) + abs(t.z) + abs(p.w);
        if (d < -STATICSCENE_FRUSTUM_TOLERANCE * mag) {
            return true;
        }
    }
    return false;
}

// The LOD fade step: `prev` in 0..=n; outside the frustum it snaps.
fn staticscene_fade_step(prev: u32, n: u32, lod_selected: bool, in_frustum: bool) -> u32 {
    if (!in_frustum) {
        return select(0u, n, lod_selected);
    }
    if (lod_selected) {
        return min(prev + 1u, n);
    }
    return select(prev - 1u, 0u, prev == 0u);
}

// The batch sort key: setup handle's low word, then the nearest depth's bits.
fn staticscene_sort_key(setup: vec2<u32>, nearest_depth: f32) -> vec2<u32> {
    return vec2<u32>(select(0u, bitcast<u32>(nearest_depth), nearest_depth > 0.0), setup.x);
}
