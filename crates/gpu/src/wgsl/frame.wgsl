// gpu: per-frame constants and the per-instance record shared by every pass.
// Rust twins: gpu's FrameUniforms and GpuInstance (sizes checked by tests).
//
// Positions are relative to two points: instance transforms and point lights are stored
// relative to the scene origin chosen at prepare (floating origin, so f32 keeps its
// precision far from the world's zero), and every pass works camera-relative:
// camera-relative = origin-relative + `origin_offset`. `view_proj` holds only the camera's
// rotation and projection (reversed Z, infinite far plane).

struct FrameUniforms {
    // camera-relative position to clip
    view_proj: mat4x4<f32>,
    // clip to camera-relative position
    inv_view_proj: mat4x4<f32>,
    // this frame's camera-relative position to last frame's clip (motion vectors); equal to
    // `view_proj` on a first frame or a still camera
    prev_view_proj: mat4x4<f32>,
    // camera position (world, metres), w = 1
    camera_position: vec4<f32>,
    // xyz: scene origin minus camera position (metres); w: unused
    origin_offset: vec4<f32>,
    // width, height, 1/width, 1/height (pixels)
    viewport: vec4<f32>,
    // xyz: unit direction towards the sun; w: unused
    sun_direction: vec4<f32>,
    sun_color: vec4<f32>,
    ambient: vec4<f32>,
    sky: vec4<f32>,
    // local lights (point and spot) bound
    local_light_count: u32,
    // log2 scale applied to texture gradients in the resolve (mip bias)
    mip_bias: f32,
    // frames rendered since the renderer was made
    frame_index: u32,
    // seconds, from the frame input
    time: f32,
    // origin-relative position -> the baked sun map's clip (x, y in [-1, 1], depth 0
    // nearest the sun); all zero without one
    baked_sun: mat4x4<f32>,
    // camera-relative world -> view space (the camera's rotation)
    view_rotation: mat4x4<f32>,
    // the scene's wind (gpu::Wind): direction times amplitude (metres) in x (world x) and
    // y (world z), angular frequency (rad/s) in z, 1 / bend height (1/metres) in w; all
    // zero without one
    wind: vec4<f32>,
    // the previous frame's time (seconds; this frame's on a first frame)
    prev_time: f32,
    // HFW's software VRS (gpu::VrsConfig): x, y the view distances (metres) where 2x1 and
    // 2x2 begin, z, w the screen speeds (pixels per frame) that force 2x1 and 2x2; all zero:
    // off, and the vis words use the standard layout
    vrs: vec4<f32>,
}


// One instance: object-to-origin-relative 3x4 transform (rows), and where it sits in the
// vis buffer: its micro batch, instance field, the mesh's primitive bits (low 8 bits; the
// static placement packs HZD's LOD fade above them: GPU_INSTANCE_FADE_*), its material.
struct GpuInstance {
    row0: vec4<f32>,
    row1: vec4<f32>,
    row2: vec4<f32>,
    micro_batch: u32,
    instance_field: u32,
    primitive_bits: u32,
    material: u32,
}

// `primitive_bits`: the mesh's primitive bits.
const GPU_INSTANCE_PRIMITIVE_BITS_MASK: u32 = 0xffu;
// `primitive_bits`: the Bayer cells (of 16) a fading instance keeps, in bits 8-15.
const GPU_INSTANCE_FADE_CELLS_SHIFT: u32 = 8u;
// `primitive_bits`: the instance is fading (dithered by its cells).
const GPU_INSTANCE_FADING: u32 = 0x10000u;
// `primitive_bits`: it is fading out (the complementary pattern).
const GPU_INSTANCE_FADING_OUT: u32 = 0x20000u;

fn gpu_transform_point(inst: GpuInstance, p: vec3<f32>) -> vec3<f32> {
    let h = vec4<f32>(p, 1.0);
    return vec3<f32>(dot(inst.row0, h), dot(inst.row1, h), dot(inst.row2, h));
}

fn gpu_transform_direction(inst: GpuInstance, d: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(inst.row0.xyz, d), dot(inst.row1.xyz, d), dot(inst.row2.xyz, d));
}

// Normals transform with the inverse transpose; instance transforms are rotation and
// uniform scale, so the transform's linear part followed by a normalize is exact.
fn gpu_transform_normal(inst: GpuInstance, n: vec3<f32>) -> vec3<f32> {
    return normalize(gpu_transform_direction(inst, n));
}
