// water: the mini G-buffer's data word. Twin of `water::gbuffer` (layout table there).

const WATER_SHADER_ID_MASK: u32 = 255u;
const WATER_FLAGS_SHIFT: u32 = 8u;
const WATER_FLAG_VALID: u32 = 1u;
const WATER_FLAG_FRONT_FACE: u32 = 2u;
const WATER_FLAG_LIT: u32 = 4u;
const WATER_FOAM_MIP_SHIFT: u32 = 11u;
const WATER_ALGAE_MIP_SHIFT: u32 = 16u;
const WATER_MIP_BITS: u32 = 5u;
const WATER_MIP_MASK: u32 = 31u;
const WATER_MIP_STEPS_PER_LEVEL: u32 = 2u;
const WATER_MATERIAL_SHIFT: u32 = 21u;
const WATER_MAX_MATERIALS: u32 = 2048u;
const WATER_DATA_NONE: u32 = 0u;

struct WaterData {
    shader_id: u32,
    flags: u32,
    material: u32,
    foam_mip: f32,
    algae_mip: f32,
}

// Nearest half level, clamped to [0, 15.5]; negative or NaN gives 0.
fn water_quantize_mip(level: f32) -> u32 {
    let q = level * f32(WATER_MIP_STEPS_PER_LEVEL) + 0.5;
    if (!(q > 0.0)) {
        return 0u;
    }
    return u32(min(q, f32(WATER_MIP_MASK)));
}

// Fields are masked to their widths (the CPU's `DataWord::pack` rejects wide ones).
fn water_pack_data(shader_id: u32, flags: u32, material: u32, foam_mip: f32, algae_mip: f32) -> u32 {
    return (shader_id & WATER_SHADER_ID_MASK)
        | ((flags & 7u) << WATER_FLAGS_SHIFT)
        | (water_quantize_mip(foam_mip) << WATER_FOAM_MIP_SHIFT)
        | (water_quantize_mip(algae_mip) << WATER_ALGAE_MIP_SHIFT)
        | ((material & (WATER_MAX_MATERIALS - 1u)) << WATER_MATERIAL_SHIFT);
}

fn water_unpack_data(w: u32) -> WaterData {
    return WaterData(
        w & WATER_SHADER_ID_MASK,
        (w >> WATER_FLAGS_SHIFT) & 7u,
        w >> WATER_MATERIAL_SHIFT,
        f32((w >> WATER_FOAM_MIP_SHIFT) & WATER_MIP_MASK) * 0.5,
        f32((w >> WATER_ALGAE_MIP_SHIFT) & WATER_MIP_MASK) * 0.5,
    );
}

fn water_data_is_valid(w: u32) -> bool {
    return ((w >> WATER_FLAGS_SHIFT) & WATER_FLAG_VALID) != 0u;
}

// Isotropic mip level from UV derivatives: `mip_level`.
fn water_mip_level(duv_dx: vec2<f32>, duv_dy: vec2<f32>, texture_size: vec2<f32>) -> f32 {
    let a = dot(duv_dx * texture_size, duv_dx * texture_size);
    let b = dot(duv_dy * texture_size, duv_dy * texture_size);
    let m = max(a, b);
    if (!(m > 1.0) || !(m < 3.0e38)) {
        return 0.0;
    }
    return 0.5 * log2(m);
}
