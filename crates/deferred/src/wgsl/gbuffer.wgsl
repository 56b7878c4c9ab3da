// deferred: G-buffer pack/unpack for both layouts (Killzone 2's 4xRGBA8 preset and the
// octahedral layout) and the normal codecs. Binding-free; the Rust crate `deferred` is the
// reference (gbuffer.rs, normal.rs) and its unit tests tie every constant below to it.
//
// Write the fields of a `DeferredKz2Targets` / `DeferredOctTargets` to RT0..RT3 (storage
// textures with `textureStore`, or fragment outputs @location(0..3)); read them back with
// `textureLoad` and pass the four values to the unpack function.
//
//   KZ2   RT0 rgba8unorm  lighting rgb, glow       RT1 rgba8unorm  view normal x, y as f16 bytes
//         RT2 rgba8unorm  motion xy, spec power, spec intensity    RT3 rgba8unorm  albedo (linear), sun shadow
//   Oct   RT0 rgba16float lighting rgb (HDR), 0    RT1 rgba8uint   normal code (24 bits), roughness
//         RT2 rgba16float motion xy (px), specular, metallic       RT3 rgba8unorm  albedo (sRGB), sun shadow

const DEFERRED_OCT_BITS: u32 = 12u;
const DEFERRED_OCT_AXIS_MASK: u32 = 4095u;
const DEFERRED_OCT_CENTER: u32 = 2047u;
const DEFERRED_OCT_CODE_MAX: u32 = 4094u;
const DEFERRED_KZ2_GLOW_RANGE: f32 = 8.0;
const DEFERRED_GLOW_SLACK: f32 = 0.017647059;
const DEFERRED_KZ2_MOTION_STEP_PX: f32 = 0.25;
const DEFERRED_KZ2_SPEC_POWER_MAX: f32 = 8191.0;
const DEFERRED_KZ2_SPEC_LOG_RANGE: f32 = 13.0;
const DEFERRED_F16_MAX: f32 = 65504.0;
const DEFERRED_LUMINANCE_R: f32 = 0.2126;
const DEFERRED_LUMINANCE_G: f32 = 0.7152;
const DEFERRED_LUMINANCE_B: f32 = 0.0722;

// Rust: deferred::Surface. `normal` is in the layout's space: view space for KZ2
// (right-handed, camera looking down -z), world space for the octahedral layout.
struct DeferredSurface {
    // linear HDR radiance, >= 0 (indirect + emissive terms of the geometry pass)
    lighting: vec3<f32>,
    // linear, [0, 1]
    albedo: vec3<f32>,
    // unit
    normal: vec3<f32>,
    // perceptual, GGX alpha = roughness^2
    roughness: f32,
    // scales a dielectric's lobe (Fresnel from 0.04)
    specular: f32,
    // [0, 1]; Fresnel mix(specular * F(0.04), F(albedo), metallic), diffuse albedo * (1 - metallic)
    metallic: f32,
    sun_shadow: f32,
    // pixels, current minus previous, +y down
    motion: vec2<f32>,
}

// Target values of the KZ2 layout: all four targets are rgba8unorm.
struct DeferredKz2Targets {
    rt0: vec4<f32>,
    rt1: vec4<f32>,
    rt2: vec4<f32>,
    rt3: vec4<f32>,
}

// Target values of the octahedral layout: rt0 and rt2 are rgba16float, rt1 rgba8uint.
struct DeferredOctTargets {
    rt0: vec4<f32>,
    rt1: vec4<u32>,
    rt2: vec4<f32>,
    rt3: vec4<f32>,
}

// ---- scalar helpers (NaN sanitised the way the Rust side does) ----

fn deferred_is_nan(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7fffffffu) > 0x7f800000u;
}

fn deferred_is_finite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

// saturate with NaN -> 0.
fn deferred_saturate(x: f32) -> f32 {
    if x > 0.0 {
        return min(x, 1.0);
    }
    return 0.0;
}

// [0, 1] -> 8-bit code, round to nearest even (NaN -> 0).
fn deferred_unorm8_code(x: f32) -> u32 {
    return u32(round(deferred_saturate(x) * 255.0));
}

// The value to store to a unorm8 channel so that it holds exactly deferred_unorm8_code(x).
fn deferred_unorm8(x: f32) -> f32 {
    return f32(deferred_unorm8_code(x)) / 255.0;
}

fn deferred_srgb_encode(x: f32) -> f32 {
    let v = deferred_saturate(x);
    if v <= 0.0031308 {
        return v * 12.92;
    }
    return 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}

fn deferred_srgb_decode(x: f32) -> f32 {
    let v = deferred_saturate(x);
    if v <= 0.04045 {
        return v * (1.0 / 12.92);
    }
    return pow((v + 0.055) * (1.0 / 1.055), 2.4);
}

// IEEE binary16 bits -> f32, exactly (written out: needs no capability, matches the CPU).
fn deferred_unpack_half(bits: u32) -> f32 {
    let sign = (bits & 0x8000u) << 16u;
    let e = (bits >> 10u) & 0x1fu;
    let m = bits & 0x3ffu;
    if e == 0u {
        let mag = f32(m) * (1.0 / 16777216.0);
        return select(mag, -mag, sign != 0u);
    }
    if e == 31u {
        return bitcast<f32>(sign | 0x7f800000u | (m << 13u));
    }
    return bitcast<f32>(sign | ((e + 112u) << 23u) | (m << 13u));
}

// f32 -> binary16 bits, round to nearest even (as the Rust `half` crate); NaN stays NaN,
// magnitudes from 65520 up become infinity.
fn deferred_pack_half(x: f32) -> u32 {
    let b = bitcast<u32>(x);
    let sign = (b >> 16u) & 0x8000u;
    let a = b & 0x7fffffffu;
    if a > 0x7f800000u {
        return sign | 0x7e00u | ((a >> 13u) & 0x3ffu);
    }
    if a >= 0x477ff000u {
        return sign | 0x7c00u;
    }
    if a < 0x38800000u {
        // Subnormal or zero: |x| * 2^24 is exact in f32 for these magnitudes; round half even.
        let s = bitcast<f32>(a) * 16777216.0;
        return sign | u32(round(s));
    }
    // Normal: drop 13 mantissa bits, round to nearest even (a carry into the exponent is right).
    let r = a + 0xfffu + ((a >> 13u) & 1u);
    return sign | ((r - 0x38000000u) >> 13u);
}

// binary16 bits -> finite f32 (NaN -> 0, infinities -> +-65504), as the Rust `half_value` (deferred::gbuffer).
fn deferred_half_value(bits: u32) -> f32 {
    let v = deferred_unpack_half(bits & 0xffffu);
    if deferred_is_nan(v) {
        return 0.0;
    }
    return clamp(v, -DEFERRED_F16_MAX, DEFERRED_F16_MAX);
}

// f32 rounded to the binary16 value a rgba16float channel will hold (NaN -> 0, clamped to
// +-65504): store this and the conversion the hardware does is exact.
fn deferred_f16_round(x: f32) -> f32 {
    var v = x;
    if deferred_is_nan(v) {
        v = 0.0;
    }
    return deferred_unpack_half(deferred_pack_half(clamp(v, -DEFERRED_F16_MAX, DEFERRED_F16_MAX)));
}

// ---- octahedral normal, 12+12 bits ----

fn deferred_sign_not_zero(v: vec2<f32>) -> vec2<f32> {
    return select(vec2<f32>(-1.0), vec2<f32>(1.0), v >= vec2<f32>(0.0));
}

// Direction -> folded octahedron square [-1, 1]^2 (zero / non-finite input -> centre).
fn deferred_oct_project(n: vec3<f32>) -> vec2<f32> {
    let l1 = abs(n.x) + abs(n.y) + abs(n.z);
    if !(l1 > 0.0) || !deferred_is_finite(l1) {
        return vec2<f32>(0.0);
    }
    let p = n.xy / l1;
    if n.z < 0.0 {
        return (vec2<f32>(1.0) - abs(p.yx)) * deferred_sign_not_zero(p);
    }
    return p;
}

// The unfolded point on the octahedron |x| + |y| + |z| = 1, before normalising.
fn deferred_oct_unproject_raw(q: vec2<f32>) -> vec3<f32> {
    let p = clamp(q, vec2<f32>(-1.0), vec2<f32>(1.0));
    let z = 1.0 - abs(p.x) - abs(p.y);
    let t = max(-z, 0.0);
    let xy = p + select(vec2<f32>(t), vec2<f32>(-t), p >= vec2<f32>(0.0));
    return vec3<f32>(xy, z);
}

fn deferred_oct_unproject(q: vec2<f32>) -> vec3<f32> {
    let v = deferred_oct_unproject_raw(q);
    return v * (1.0 / sqrt(dot(v, v)));
}

fn deferred_oct_axis_value(code: u32) -> f32 {
    let c = min(code, DEFERRED_OCT_CODE_MAX);
    return (f32(c) - f32(DEFERRED_OCT_CENTER)) * (1.0 / f32(DEFERRED_OCT_CENTER));
}

// 24-bit code (u in bits 0..12, v in 12..24; higher bits ignored) -> unit direction.
fn deferred_oct_decode(word: u32) -> vec3<f32> {
    return deferred_oct_unproject(vec2<f32>(
        deferred_oct_axis_value(word & DEFERRED_OCT_AXIS_MASK),
        deferred_oct_axis_value((word >> DEFERRED_OCT_BITS) & DEFERRED_OCT_AXIS_MASK)));
}

// Nearest-code encoder.
fn deferred_oct_encode_fast(n: vec3<f32>) -> u32 {
    let p = deferred_oct_project(n);
    let s = (clamp(p, vec2<f32>(-1.0), vec2<f32>(1.0)) + 1.0) * f32(DEFERRED_OCT_CENTER);
    let c = min(vec2<u32>(round(s)), vec2<u32>(DEFERRED_OCT_CODE_MAX));
    return c.x | (c.y << DEFERRED_OCT_BITS);
}

// Precise encoder: of the four codes around the projected point, the one whose decoded
// direction makes the smallest angle with n, compared as |a x n|^2 / |a|^2 on the
// unnormalised decode a (f32 dot products of unit vectors cannot separate these angles);
// ties keep the lower code.
fn deferred_oct_encode(n: vec3<f32>) -> u32 {
    let p = deferred_oct_project(n);
    var dir = vec3<f32>(0.0, 0.0, 1.0);
    let len2 = dot(n, n);
    if len2 > 0.0 && deferred_is_finite(len2) {
        dir = n * (1.0 / sqrt(len2));
    }
    let s = (clamp(p, vec2<f32>(-1.0), vec2<f32>(1.0)) + 1.0) * f32(DEFERRED_OCT_CENTER);
    let c0 = min(vec2<u32>(floor(s)), vec2<u32>(DEFERRED_OCT_CODE_MAX));
    var best = c0.x | (c0.y << DEFERRED_OCT_BITS);
    var best_err = 3.0e38;
    for (var dv = 0u; dv < 2u; dv++) {
        for (var du = 0u; du < 2u; du++) {
            let u = min(c0.x + du, DEFERRED_OCT_CODE_MAX);
            let v = min(c0.y + dv, DEFERRED_OCT_CODE_MAX);
            let a = deferred_oct_unproject_raw(vec2<f32>(deferred_oct_axis_value(u), deferred_oct_axis_value(v)));
            let c = cross(a, dir);
            let err = dot(c, c) / dot(a, a);
            if err < best_err {
                best_err = err;
                best = u | (v << DEFERRED_OCT_BITS);
            }
        }
    }
    return best;
}

// ---- Killzone 2 view-space normal: x, y as two f16 ----

fn deferred_kz2_normal_encode(n: vec3<f32>) -> u32 {
    var xy = vec2<f32>(0.0);
    let l2 = dot(n, n);
    if deferred_is_finite(n.x) && deferred_is_finite(n.y) && deferred_is_finite(n.z) && l2 > 0.0 {
        xy = n.xy / sqrt(l2);
    }
    return deferred_pack_half(xy.x) | (deferred_pack_half(xy.y) << 16u);
}

fn deferred_kz2_reconstruct(x: f32, y: f32) -> vec3<f32> {
    if !(deferred_is_finite(x) && deferred_is_finite(y)) {
        return vec3<f32>(0.0, 0.0, 1.0);
    }
    let r2 = x * x + y * y;
    if r2 > 1.0 {
        let r = sqrt(r2);
        return vec3<f32>(x / r, y / r, 0.0);
    }
    return vec3<f32>(x, y, sqrt(1.0 - r2));
}

// z = sqrt(1 - x^2 - y^2) >= 0: the sign of z is lost.
fn deferred_kz2_normal_decode(word: u32) -> vec3<f32> {
    return deferred_kz2_reconstruct(deferred_unpack_half(word & 0xffffu), deferred_unpack_half(word >> 16u));
}

// ---- shared channels ----

fn deferred_luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(DEFERRED_LUMINANCE_R, DEFERRED_LUMINANCE_G, DEFERRED_LUMINANCE_B));
}

fn deferred_sanitize_hdr(c: vec3<f32>) -> vec3<f32> {
    var o = vec3<f32>(0.0);
    for (var i = 0u; i < 3u; i++) {
        if c[i] > 0.0 {
            o[i] = min(c[i], DEFERRED_F16_MAX);
        }
    }
    return o;
}

fn deferred_sanitize_normal(n: vec3<f32>) -> vec3<f32> {
    let l2 = dot(n, n);
    if deferred_is_finite(n.x) && deferred_is_finite(n.y) && deferred_is_finite(n.z) && l2 > 0.0 {
        return n;
    }
    return vec3<f32>(0.0, 0.0, 1.0);
}

// Lighting accumulation + glow (RT0 of both layouts).
fn deferred_pack_lighting(lighting: vec3<f32>) -> vec4<f32> {
    let l = deferred_sanitize_hdr(lighting);
    return vec4<f32>(deferred_unorm8(l.x), deferred_unorm8(l.y), deferred_unorm8(l.z),
                     deferred_unorm8(deferred_luminance(l) * (1.0 / DEFERRED_KZ2_GLOW_RANGE)));
}

// KZ2's HDR reconstruction: where a channel was clamped (reads 1) and the glow luminance
// is brighter by more than DEFERRED_GLOW_SLACK, rgb scaled up to it; other values read
// back as stored.
fn deferred_unpack_lighting(rt0: vec4<f32>) -> vec3<f32> {
    let rgb = rt0.rgb;
    let lum = deferred_luminance(rgb);
    let target_lum = deferred_saturate(rt0.a) * DEFERRED_KZ2_GLOW_RANGE;
    if max(rgb.r, max(rgb.g, rgb.b)) >= 1.0 && lum > 0.0 && target_lum > lum + DEFERRED_GLOW_SLACK {
        return rgb * (target_lum / lum);
    }
    return rgb;
}

// Blinn-Phong power of perceptual roughness r: 2 / r^4 - 2, clamped to [0, 8191].
fn deferred_spec_power_from_roughness(r: f32) -> f32 {
    let rr = deferred_saturate(r);
    let a2 = rr * rr * rr * rr;
    if a2 <= 2.0 / (DEFERRED_KZ2_SPEC_POWER_MAX + 2.0) {
        return DEFERRED_KZ2_SPEC_POWER_MAX;
    }
    return clamp(2.0 / a2 - 2.0, 0.0, DEFERRED_KZ2_SPEC_POWER_MAX);
}

fn deferred_roughness_from_spec_power(power: f32) -> f32 {
    var p = 0.0;
    if power > 0.0 {
        p = min(power, DEFERRED_KZ2_SPEC_POWER_MAX);
    }
    return sqrt(sqrt(2.0 / (p + 2.0)));
}

// KZ2 motion code of one axis: 128 + round(m / 0.25), clamped to 1..=255 (NaN -> 128).
fn deferred_kz2_motion_code(m: f32) -> u32 {
    var v = m;
    if deferred_is_nan(v) {
        v = 0.0;
    }
    return u32(128.0 + round(clamp(v * (1.0 / DEFERRED_KZ2_MOTION_STEP_PX), -127.0, 127.0)));
}

fn deferred_kz2_motion_value(code: u32) -> f32 {
    return (f32(max(code, 1u)) - 128.0) * DEFERRED_KZ2_MOTION_STEP_PX;
}

// rgba8unorm channel value -> its 8-bit code.
fn deferred_unorm8_read(x: f32) -> u32 {
    return u32(round(deferred_saturate(x) * 255.0));
}

// ---- the KZ2 layout ----

fn deferred_gbuffer_kz2_pack(s: DeferredSurface) -> DeferredKz2Targets {
    var t: DeferredKz2Targets;
    t.rt0 = deferred_pack_lighting(s.lighting);
    let n = deferred_kz2_normal_encode(deferred_sanitize_normal(s.normal));
    // Cg's unpack_4ubyte(pack_2half(n.xy)): the f16 bits as four unorm8 bytes.
    t.rt1 = unpack4x8unorm(n);
    let power = deferred_spec_power_from_roughness(s.roughness);
    let power_code = deferred_unorm8_code(log2(1.0 + power) * (1.0 / DEFERRED_KZ2_SPEC_LOG_RANGE));
    t.rt2 = vec4<f32>(f32(deferred_kz2_motion_code(s.motion.x)) / 255.0,
                      f32(deferred_kz2_motion_code(s.motion.y)) / 255.0,
                      f32(power_code) / 255.0,
                      deferred_unorm8(s.specular));
    // No metallic channel: the diffuse colour is stored (metals lose their reflection).
    let diffuse = s.albedo * (1.0 - deferred_saturate(s.metallic));
    t.rt3 = vec4<f32>(deferred_unorm8(diffuse.x), deferred_unorm8(diffuse.y),
                      deferred_unorm8(diffuse.z), deferred_unorm8(s.sun_shadow));
    return t;
}

// Takes the four rgba8unorm values as textureLoad returns them. The normal has z >= 0.
fn deferred_gbuffer_kz2_unpack(rt0: vec4<f32>, rt1: vec4<f32>, rt2: vec4<f32>, rt3: vec4<f32>) -> DeferredSurface {
    var s: DeferredSurface;
    s.lighting = deferred_unpack_lighting(rt0);
    let word = deferred_unorm8_read(rt1.x) | (deferred_unorm8_read(rt1.y) << 8u)
             | (deferred_unorm8_read(rt1.z) << 16u) | (deferred_unorm8_read(rt1.w) << 24u);
    s.normal = deferred_kz2_normal_decode(word);
    s.motion = vec2<f32>(deferred_kz2_motion_value(deferred_unorm8_read(rt2.x)),
                         deferred_kz2_motion_value(deferred_unorm8_read(rt2.y)));
    let power = exp2(f32(deferred_unorm8_read(rt2.z)) / 255.0 * DEFERRED_KZ2_SPEC_LOG_RANGE) - 1.0;
    s.roughness = deferred_roughness_from_spec_power(power);
    s.specular = f32(deferred_unorm8_read(rt2.w)) / 255.0;
    s.metallic = 0.0;
    s.albedo = vec3<f32>(f32(deferred_unorm8_read(rt3.x)), f32(deferred_unorm8_read(rt3.y)),
                         f32(deferred_unorm8_read(rt3.z))) / 255.0;
    s.sun_shadow = f32(deferred_unorm8_read(rt3.w)) / 255.0;
    return s;
}

// ---- the octahedral layout ----

fn deferred_gbuffer_oct_pack(s: DeferredSurface) -> DeferredOctTargets {
    var t: DeferredOctTargets;
    // The lighting is left to the store's f32 -> f16 conversion (the device's rounding:
    // within one f16 ulp of the CPU's round-to-nearest-even, which deferred_pack_half of
    // this value gives exactly); rounding it here cost the H200's 4K resolve 20 us.
    t.rt0 = vec4<f32>(deferred_sanitize_hdr(s.lighting), 0.0);
    let code = deferred_oct_encode(deferred_sanitize_normal(s.normal));
    t.rt1 = vec4<u32>(code & 0xffu, (code >> 8u) & 0xffu, (code >> 16u) & 0xffu,
                      deferred_unorm8_code(s.roughness));
    t.rt2 = vec4<f32>(deferred_f16_round(s.motion.x), deferred_f16_round(s.motion.y),
                      deferred_f16_round(deferred_saturate(s.specular)),
                      deferred_f16_round(deferred_saturate(s.metallic)));
    t.rt3 = vec4<f32>(deferred_unorm8(deferred_srgb_encode(s.albedo.x)),
                      deferred_unorm8(deferred_srgb_encode(s.albedo.y)),
                      deferred_unorm8(deferred_srgb_encode(s.albedo.z)),
                      deferred_unorm8(s.sun_shadow));
    return t;
}

// Takes the values as textureLoad returns them (rt1 from the rgba8uint target).
fn deferred_gbuffer_oct_unpack(rt0: vec4<f32>, rt1: vec4<u32>, rt2: vec4<f32>, rt3: vec4<f32>) -> DeferredSurface {
    var s: DeferredSurface;
    // f16 values as textureLoad returns them: NaN -> 0, clamped to [0, 65504].
    var l = rt0.rgb;
    for (var i = 0u; i < 3u; i++) {
        if deferred_is_nan(l[i]) {
            l[i] = 0.0;
        }
    }
    s.lighting = clamp(l, vec3<f32>(0.0), vec3<f32>(DEFERRED_F16_MAX));
    let b = rt1 & vec4<u32>(0xffu);
    s.normal = deferred_oct_decode(b.x | (b.y << 8u) | (b.z << 16u));
    s.roughness = f32(b.w) / 255.0;
    var m = rt2;
    for (var i = 0u; i < 4u; i++) {
        if deferred_is_nan(m[i]) {
            m[i] = 0.0;
        }
    }
    s.motion = clamp(m.xy, vec2<f32>(-DEFERRED_F16_MAX), vec2<f32>(DEFERRED_F16_MAX));
    s.specular = deferred_saturate(m.z);
    s.metallic = deferred_saturate(m.w);
    s.albedo = vec3<f32>(deferred_srgb_decode(f32(deferred_unorm8_read(rt3.x)) / 255.0),
                         deferred_srgb_decode(f32(deferred_unorm8_read(rt3.y)) / 255.0),
                         deferred_srgb_decode(f32(deferred_unorm8_read(rt3.z)) / 255.0));
    s.sun_shadow = f32(deferred_unorm8_read(rt3.w)) / 255.0;
    return s;
}
