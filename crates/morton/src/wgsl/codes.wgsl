// morton::codes: Morton codes on the GPU, the twin of the `morton` crate's 32-bit paths.
// Binding-free: functions and constants only, all prefixed `morton_` / `MORTON_`.
// Bit layout (same as the CPU): x in bit 0, y in bit 1 (, z in bit 2), then repeating.

// Bits per axis of a 2D code in a u32 (morton::BITS2_U32).
const MORTON_BITS2_U32: u32 = 16u;
// Bits per axis of a 3D code in a u32 (morton::BITS3_U32).
const MORTON_BITS3_U32: u32 = 10u;
// Where each axis's bits sit in a 2D code (morton::MASK2_X_U32, MASK2_Y_U32).
const MORTON_MASK2_X_U32: u32 = 0x55555555u;
const MORTON_MASK2_Y_U32: u32 = 0xaaaaaaaau;
// Where each axis's bits sit in a 3D code (morton::MASK3_X_U32, ...).
const MORTON_MASK3_X_U32: u32 = 0x09249249u;
const MORTON_MASK3_Y_U32: u32 = 0x12492492u;
const MORTON_MASK3_Z_U32: u32 = 0x24924924u;

// Spreads the low 16 bits of x to the even bits.
fn morton_part1by1(v: u32) -> u32 {
    var x = v & 0x0000ffffu;
    x = (x | (x << 8u)) & 0x00ff00ffu;
    x = (x | (x << 4u)) & 0x0f0f0f0fu;
    x = (x | (x << 2u)) & 0x33333333u;
    x = (x | (x << 1u)) & 0x55555555u;
    return x;
}

// Gathers the even bits into the low 16 bits.
fn morton_compact1by1(v: u32) -> u32 {
    var x = v & 0x55555555u;
    x = (x | (x >> 1u)) & 0x33333333u;
    x = (x | (x >> 2u)) & 0x0f0f0f0fu;
    x = (x | (x >> 4u)) & 0x00ff00ffu;
    x = (x | (x >> 8u)) & 0x0000ffffu;
    return x;
}

// Spreads the low 10 bits of x to every third bit.
fn morton_part1by2(v: u32) -> u32 {
    var x = v & 0x000003ffu;
    x = (x | (x << 16u)) & 0x030000ffu;
    x = (x | (x << 8u)) & 0x0300f00fu;
    x = (x | (x << 4u)) & 0x030c30c3u;
    x = (x | (x << 2u)) & 0x09249249u;
    return x;
}

// Gathers every third bit into the low 10 bits.
fn morton_compact1by2(v: u32) -> u32 {
    var x = v & 0x09249249u;
    x = (x | (x >> 2u)) & 0x030c30c3u;
    x = (x | (x >> 4u)) & 0x0300f00fu;
    x = (x | (x >> 8u)) & 0x030000ffu;
    x = (x | (x >> 16u)) & 0x000003ffu;
    return x;
}

// 2D Morton code, 16 bits per axis (higher bits of x and y are ignored).
fn morton_encode2_u32(x: u32, y: u32) -> u32 {
    return morton_part1by1(x) | (morton_part1by1(y) << 1u);
}

// Inverse of morton_encode2_u32.
fn morton_decode2_u32(code: u32) -> vec2<u32> {
    return vec2<u32>(morton_compact1by1(code), morton_compact1by1(code >> 1u));
}

// 3D Morton code, 10 bits per axis (higher bits ignored; bits 30 and 31 of the code are 0).
fn morton_encode3_u32(x: u32, y: u32, z: u32) -> u32 {
    return morton_part1by2(x) | (morton_part1by2(y) << 1u) | (morton_part1by2(z) << 2u);
}

// Inverse of morton_encode3_u32 (bits 30 and 31 ignored).
fn morton_decode3_u32(code: u32) -> vec3<u32> {
    return vec3<u32>(
        morton_compact1by2(code),
        morton_compact1by2(code >> 1u),
        morton_compact1by2(code >> 2u),
    );
}

// The grid cell of p, as morton::Quantizer3::quantize: floor((p - box_min) * scale) clamped
// to [0, 2^bits - 1], with scale = Quantizer3::scale() (cells per world unit). NaN input is
// unspecified on the GPU (WGSL lets implementations assume no NaN); the CPU rejects it.
fn morton_quantize3(p: vec3<f32>, box_min: vec3<f32>, scale: vec3<f32>, bits: u32) -> vec3<u32> {
    let top = f32((1u << bits) - 1u);
    let t = clamp((p - box_min) * scale, vec3<f32>(0.0), vec3<f32>(top));
    return vec3<u32>(t);
}

// The 32-bit 3D Morton key of p (bits <= 10), as morton::Quantizer3::morton_u32.
fn morton_key3_u32(p: vec3<f32>, box_min: vec3<f32>, scale: vec3<f32>, bits: u32) -> u32 {
    let c = morton_quantize3(p, box_min, scale, bits);
    return morton_encode3_u32(c.x, c.y, c.z);
}
