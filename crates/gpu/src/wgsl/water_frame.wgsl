// gpu: what every pass of FC5's water (passes/water/) shares: the per-frame water
// constants, the near bodies' records and vertices, the far sectors' quadtree nodes, the
// displacement decals, and the conversions between the renderer's +Y-up world and the
// `water` crate's +Z-up one ((x, y, z) there is (x, z, -y) here). Rust twins in
// passes/water/mod.rs (layouts checked by its tests).
//
// Views: the camera (FrameUniforms) and the water view, the camera's position and
// rotation with a wider field of view (`tan_half.zw` = `tan_half.xy` times
// WaterOptions::fov_scale) at the mini G-buffer's reduced resolution (`size.zw`). Both
// share the rotation, so a view-space depth is the same in both and later passes
// reproject between them by scaling NDC.

#import water::noise
#import water::flow
#import water::foam
#import water::normals

// Rust: passes::water::GpuWaterFrame.
struct GpuWaterFrame {
    // camera-relative position -> the water view's clip space (reversed Z)
    view_proj: mat4x4<f32>,
    // view space -> camera-relative world (the camera's rotation, inverted)
    inv_rotation: mat4x4<f32>,
    // the water view's frustum planes, camera-relative (inside: dot(p, n) + d >= 0)
    planes: array<vec4<f32>, 6>,
    // xyz: camera position (world); w: near plane (metres)
    camera: vec4<f32>,
    // tan of the half fields of view: camera x, y; water view x, y
    tan_half: vec4<f32>,
    // screen width, height; mini G-buffer width, height (pixels)
    size: vec4<u32>,
    // tiles across, down; quads per tile side; near bodies
    grid: vec4<u32>,
    // far sectors per side; quadtree levels; quads per far sector side; decals
    far: vec4<u32>,
    // materials; GPU_WATER_FLAG_*; material map width, height
    counts: vec4<u32>,
    // far sector grid origin (world x, z of its min corner); sector side; near radius
    sectors: vec4<f32>,
    // shore field: origin (water x, y), texel (metres); largest displacement (metres)
    shore: vec4<f32>,
    // material map: origin (water x, y), texel (metres), blend distance (metres)
    material_map: vec4<f32>,
    // time (s), refraction strength, foam noise frequency (periods per metre), SSR steps
    misc: vec4<f32>,
    // normals: radius at 1 m (pixels), largest radius, specular AA kappa; the noise
    // texture's side (texels)
    normals: vec4<f32>,
    fbm: WaterFbmParams,
    flow: WaterFlowParams,
    foam: WaterFoamParams,
    // shore field width, height; 0; 0
    shore_size: vec4<u32>,
}

// Rust: passes::water::GpuWaterBody (48 bytes). A near body: its world box (xyz), its
// index range in the near mesh, its body word (water::world::BodyId) and material.
struct GpuWaterBody {
    min: vec4<f32>,
    max: vec4<f32>,
    first_index: u32,
    index_count: u32,
    body: u32,
    material: u32,
}

// Rust: passes::water::GpuWaterVertex (32 bytes). A near mesh vertex: world position,
// its body word, world normal, material.
struct GpuWaterVertex {
    position: vec3<f32>,
    body: u32,
    normal: vec3<f32>,
    material: u32,
}

// Rust: passes::water::GpuWaterNode (32 bytes). A node of the far sectors' quadtree:
// world box; `min.w` holds GPU_WATER_NODE_* flags (bitcast), `max.w` the flat height.
struct GpuWaterNode {
    min: vec4<f32>,
    max: vec4<f32>,
}

// Rust: passes::water::GpuWaterDecal (160 bytes). A displacement decal in the water
// crate's +Z-up world: world -> box-local [-1, 1]^3, box -> world (its linear part maps
// texel vectors), strength, animation frame, fade; its texture's first layer, frames,
// width, height.
struct GpuWaterDecal {
    world_to_box: mat4x4<f32>,
    box_to_world: mat4x4<f32>,
    params: vec4<f32>,
    texture: vec4<u32>,
}

// GpuWaterFrame::counts.y.
const GPU_WATER_FLAG_FLOW: u32 = 1u;
const GPU_WATER_FLAG_SHORE: u32 = 2u;
const GPU_WATER_FLAG_SSR: u32 = 4u;
const GPU_WATER_FLAG_MATERIAL_MAP: u32 = 8u;

// GpuWaterNode flags.
const GPU_WATER_NODE_WATER: u32 = 1u;
const GPU_WATER_NODE_OCEAN: u32 = 2u;
const GPU_WATER_NODE_FLAT: u32 = 4u;
// A leaf of ocean alone (no other body's bounds reach it): its fragments skip the query.
const GPU_WATER_NODE_PURE: u32 = 8u;
// A leaf's flags hold the ocean's material from this bit.
const GPU_WATER_NODE_MATERIAL_SHIFT: u32 = 8u;

// The body word the far draw's vertices carry (no near body).
const GPU_WATER_FAR_BODY: u32 = 4294967295u;
// The body word of the ocean (water::world::BodyId::OCEAN).
const GPU_WATER_OCEAN_BODY: u32 = 3221225472u;
// A material map texel's "no water" material.
const GPU_WATER_NO_MATERIAL: u32 = 2047u;

// Horizontal water coordinates of a +Y-up world position.
fn gpu_water_xy(p: vec3<f32>) -> vec2<f32> {
    return vec2<f32>(p.x, -p.z);
}

// A +Z-up water vector in the renderer's +Y up.
fn gpu_water_y_up(v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(v.x, v.z, -v.y);
}

// A +Y-up vector in the water crate's +Z up.
fn gpu_water_z_up(v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(v.x, -v.z, v.y);
}

// The camera-relative position of image point `xy` (pixels of an image of `size` seen
// with `tan_half`) at view depth `depth`.
fn gpu_water_relative(w: GpuWaterFrame, xy: vec2<f32>, depth: f32, size: vec2<u32>, tan_half: vec2<f32>) -> vec3<f32> {
    let v = water_view_position(xy, depth, size, tan_half);
    return (w.inv_rotation * vec4<f32>(v, 0.0)).xyz;
}

// Whether a view depth is one (positive and finite).
fn gpu_water_depth_ok(d: f32) -> bool {
    return d > 0.0 && d < 3.0e38;
}

// The view depth (metres along the view axis) of a camera-relative position.
fn gpu_water_view_depth(w: GpuWaterFrame, rel: vec3<f32>) -> f32 {
    // inv_rotation's columns are the view axes in world space; view z is column 2.
    return -dot(w.inv_rotation[2].xyz, rel);
}

// The slope variance per axis that the FBM's octave LOD drops at `distance`
// (`Fbm::sample`'s `dropped_variance`, without sampling), times `scale^2` (the material's
// amplitude).
fn gpu_water_dropped_variance(prm: WaterFbmParams, distance: f32, scale: f32) -> f32 {
    let c = water_fbm_octave_count(distance, prm);
    var v = 0.0;
    var a = prm.amplitude * scale;
    var f = prm.frequency;
    let n = min(prm.octaves_near, WATER_MAX_OCTAVES);
    for (var k = 0u; k < n; k++) {
        let wk = saturate(c - f32(k));
        let af = a * f;
        v += (1.0 - wk * wk) * af * af * prm.slope_variance;
        a *= prm.gain;
        f *= 2.0;
    }
    return v;
}
