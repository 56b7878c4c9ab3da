// visbuf: the 32-byte transformed vertex (HFW's vertex ring buffer). Binding-free; checked
// against the Rust crate `visbuf` (VisbufVertex) by its unit tests.
//
//   word 0: hpos x (f16, 15..0), hpos y (f16, 31..16)    word 1: hpos w (f32)
//   word 2: uv, u16 fixed u * 8192 (u low) | slots 0, 1 word 3: RGBA8 unorm | slots 2, 3
//   word 4: normal snorm 10:10:10:2                      word 5: tangent, handedness in 31..30
//   word 6: prev hpos x, y (f16)                         word 7: prev hpos w (f16, 15..0), spare / slot 4 (31..16)

const VISBUF_UV_SCALE: f32 = 8192.0;
const VISBUF_UV_MAX: f32 = 7.99993896484375;
const VISBUF_HALF_MAX: f32 = 65504.0;
const VISBUF_SNORM10_MAX: f32 = 511.0;
const VISBUF_SNORM_W_SHIFT: u32 = 30u;
const VISBUF_VERTEX_WORDS: u32 = 8u;

// Rust: visbuf::VisbufVertex (32 bytes). An array<VisbufVertex> has a 32-byte stride.
struct VisbufVertex {
    hpos_xy: u32,
    hpos_w: f32,
    uv: u32,
    color: u32,
    normal: u32,
    tangent: u32,
    prev_hpos_xy: u32,
    prev_hpos_w_extra: u32,
}

// Everything but UV / colour / slots, decoded.
struct VisbufVertexCore {
    // Clip-space position with z recovered from w: z = z_from_w.x * w + z_from_w.y.
    clip: vec4<f32>,
    normal: vec3<f32>,
    // xyz tangent, w handedness (+1 or -1).
    tangent: vec4<f32>,
    // Previous frame's clip-space (x, y, w).
    prev_hpos: vec3<f32>,
}

// IEEE binary16 bits (low 16 bits of `bits`) to f32, exactly; written out rather than
// unpack2x16float so the module needs no downlevel capability and matches the CPU bit for bit.
fn visbuf_unpack_half(bits: u32) -> f32 {
    let sign = (bits & 0x8000u) << 16u;
    let e = (bits >> 10u) & 0x1fu;
    let m = bits & 0x3ffu;
    if (e == 0u) {
        let mag = ldexp(f32(m), -24);
        return select(mag, -mag, sign != 0u);
    }
    if (e == 31u) {
        return bitcast<f32>(sign | 0x7f800000u | (m << 13u));
    }
    return bitcast<f32>(sign | ((e + 112u) << 23u) | (m << 13u));
}

// f32 to IEEE binary16 bits, round to nearest even (as the Rust `half` crate); values of
// magnitude 65520 and above become infinity, NaN stays NaN.
fn visbuf_pack_half(x: f32) -> u32 {
    let b = bitcast<u32>(x);
    let sign = (b >> 16u) & 0x8000u;
    let a = b & 0x7fffffffu;
    if (a > 0x7f800000u) {
        return sign | 0x7e00u;
    }
    if (a >= 0x477ff000u) {
        return sign | 0x7c00u;
    }
    if (a < 0x38800000u) {
        // Subnormal (or zero): scale by 2^24, exact, then round half to even.
        return sign | u32(round(bitcast<f32>(a) * 16777216.0));
    }
    let m = a - 0x38000000u;
    return sign | ((m + 0xfffu + ((m >> 13u) & 1u)) >> 13u);
}

fn visbuf_unpack_half2(word: u32) -> vec2<f32> {
    return vec2<f32>(visbuf_unpack_half(word & 0xffffu), visbuf_unpack_half(word >> 16u));
}

fn visbuf_pack_half2(v: vec2<f32>) -> u32 {
    return visbuf_pack_half(v.x) | (visbuf_pack_half(v.y) << 16u);
}

// Clip-space (x, y, w) of words 0 and 1.
fn visbuf_vertex_hpos(hpos_xy: u32, hpos_w: f32) -> vec3<f32> {
    let xy = visbuf_unpack_half2(hpos_xy);
    return vec3<f32>(xy, hpos_w);
}

// The full clip position; z_from_w = (a, b) from visbuf::ZFromW, z = a * w + b.
fn visbuf_vertex_clip(hpos_xy: u32, hpos_w: f32, z_from_w: vec2<f32>) -> vec4<f32> {
    let xy = visbuf_unpack_half2(hpos_xy);
    return vec4<f32>(xy, z_from_w.x * hpos_w + z_from_w.y, hpos_w);
}

// Previous frame's clip-space (x, y, w) from words 6 and 7.
fn visbuf_vertex_prev_hpos(prev_hpos_xy: u32, prev_hpos_w_extra: u32) -> vec3<f32> {
    return vec3<f32>(visbuf_unpack_half2(prev_hpos_xy), visbuf_unpack_half(prev_hpos_w_extra & 0xffffu));
}

fn visbuf_unpack_uv(word: u32) -> vec2<f32> {
    return vec2<f32>(f32(word & 0xffffu), f32(word >> 16u)) / VISBUF_UV_SCALE;
}

// UV in [0, 8) to 16:16 fixed point (clamped to the range).
fn visbuf_pack_uv(uv: vec2<f32>) -> u32 {
    let q = vec2<u32>(floor(clamp(uv, vec2<f32>(0.0), vec2<f32>(65535.0 / VISBUF_UV_SCALE)) * VISBUF_UV_SCALE + 0.5));
    return q.x | (q.y << 16u);
}

fn visbuf_snorm_field(word: u32, shift: u32, bits: u32, max_code: f32) -> f32 {
    // extractBits on i32 sign-extends.
    let q = extractBits(bitcast<i32>(word), shift, bits);
    return max(f32(q) / max_code, -1.0);
}

fn visbuf_unpack_snorm_10_10_10_2(word: u32) -> vec4<f32> {
    return vec4<f32>(
        visbuf_snorm_field(word, 0u, 10u, VISBUF_SNORM10_MAX),
        visbuf_snorm_field(word, 10u, 10u, VISBUF_SNORM10_MAX),
        visbuf_snorm_field(word, 20u, 10u, VISBUF_SNORM10_MAX),
        visbuf_snorm_field(word, VISBUF_SNORM_W_SHIFT, 2u, 1.0),
    );
}

fn visbuf_pack_snorm_10_10_10_2(v: vec4<f32>) -> u32 {
    let c = clamp(v, vec4<f32>(-1.0), vec4<f32>(1.0));
    let q = vec4<i32>(floor(0.5 + c * vec4<f32>(VISBUF_SNORM10_MAX, VISBUF_SNORM10_MAX, VISBUF_SNORM10_MAX, 1.0)));
    let u = bitcast<vec4<u32>>(q) & vec4<u32>(0x3ffu, 0x3ffu, 0x3ffu, 3u);
    return u.x | (u.y << 10u) | (u.z << 20u) | (u.w << VISBUF_SNORM_W_SHIFT);
}

// Two square-rooted unorm8 channels from the low 16 bits of `bits` ("poor man's sRGB").
fn visbuf_unpack_sqrt_unorm8x2(bits: u32) -> vec2<f32> {
    let s = vec2<f32>(f32(bits & 0xffu), f32((bits >> 8u) & 0xffu)) / 255.0;
    return s * s;
}

fn visbuf_pack_sqrt_unorm8x2(c: vec2<f32>) -> u32 {
    let q = vec2<u32>(floor(0.5 + 255.0 * sqrt(clamp(c, vec2<f32>(0.0), vec2<f32>(1.0)))));
    return q.x | (q.y << 8u);
}

// The 16 bits of interpolant slot i (0..4) of the interpolant layout; 0 past slot 4.
fn visbuf_vertex_slot_bits(v: VisbufVertex, i: u32) -> u32 {
    switch i {
        case 0u: { return v.uv & 0xffffu; }
        case 1u: { return v.uv >> 16u; }
        case 2u: { return v.color & 0xffffu; }
        case 3u: { return v.color >> 16u; }
        case 4u: { return v.prev_hpos_w_extra >> 16u; }
        default: { return 0u; }
    }
}

// A slot read as a half float.
fn visbuf_slot_half(bits: u32) -> f32 {
    return visbuf_unpack_half(bits & 0xffffu);
}

fn visbuf_decode_vertex_core(v: VisbufVertex, z_from_w: vec2<f32>) -> VisbufVertexCore {
    var out: VisbufVertexCore;
    out.clip = visbuf_vertex_clip(v.hpos_xy, v.hpos_w, z_from_w);
    out.normal = visbuf_unpack_snorm_10_10_10_2(v.normal).xyz;
    out.tangent = visbuf_unpack_snorm_10_10_10_2(v.tangent);
    out.prev_hpos = visbuf_vertex_prev_hpos(v.prev_hpos_xy, v.prev_hpos_w_extra);
    return out;
}

// The vertex-transform pass's writer: standard layout. hpos and prev_hpos are clip-space
// (x, y, w); x, y and prev must stay within +-65504 (f16); uv within [0, 8) (clamped).
fn visbuf_encode_vertex(hpos: vec3<f32>, uv: vec2<f32>, color: vec4<f32>, normal: vec3<f32>,
                        tangent: vec4<f32>, prev_hpos: vec3<f32>, extra: u32) -> VisbufVertex {
    var v: VisbufVertex;
    v.hpos_xy = visbuf_pack_half2(hpos.xy);
    v.hpos_w = hpos.z;
    v.uv = visbuf_pack_uv(uv);
    v.color = pack4x8unorm(color);
    v.normal = visbuf_pack_snorm_10_10_10_2(vec4<f32>(normal, 0.0));
    v.tangent = visbuf_pack_snorm_10_10_10_2(vec4<f32>(tangent.xyz, select(1.0, -1.0, tangent.w < 0.0)));
    v.prev_hpos_xy = visbuf_pack_half2(prev_hpos.xy);
    v.prev_hpos_w_extra = visbuf_pack_half(prev_hpos.z) | (extra << 16u);
    return v;
}
