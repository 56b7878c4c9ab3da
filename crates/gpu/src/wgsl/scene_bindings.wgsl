// gpu: bind group 0 of every pass that draws or resolves the scene (laydown, baseline,
// resolve): the frame, the vertices, instances and materials, and the albedo array.

#import gpu::frame
#import gpu::scene

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var<storage, read> vertices: array<GpuVertex>;
@group(0) @binding(2) var<storage, read> instances: array<GpuInstance>;
@group(0) @binding(3) var<storage, read> materials: array<GpuMaterial>;
@group(0) @binding(4) var albedo: texture_2d_array<f32>;
@group(0) @binding(5) var albedo_sampler: sampler;
// The baked sun map (gpu::shadows::BakedSun); a 1x1 stand-in where it is the attachment.
@group(0) @binding(6) var baked_sun_map: texture_depth_2d;
// The data maps (scene::DataLayer: normal, metallic-roughness, occlusion), linear; one
// neutral 1x1 layer for a scene without them.
@group(0) @binding(7) var data_maps: texture_2d_array<f32>;

// Whether the vis words carry a shading rate (visbuf's VRS layout: RendererConfig::vrs).
fn gpu_vrs_layout() -> bool {
    return frame.vrs.y > 0.0;
}

// Camera-relative position of object-space point `p` of `inst`, unanimated.
fn gpu_camera_relative(inst: GpuInstance, p: vec3<f32>) -> vec3<f32> {
    return gpu_transform_point(inst, p) + frame.origin_offset.xyz;
}

// GpuMaterial::shader of the alpha-tested materials (ShaderKind::AlphaTested.id()): the
// foliage the wind sways.
const GPU_SHADER_ALPHA_TESTED: u32 = 1u;

// HFW's animated foliage: the wind's world displacement (metres, horizontal) of
// object-space point `p` of `inst` at `time` seconds. Bend weight per vertex from its
// object-space height, phase per instance from its origin-relative translation (so a
// gust travels across the field), zero for materials that are not alpha-tested or
// without wind. CPU reference: gpu::Wind::displacement (the same arithmetic).
fn gpu_wind(inst: GpuInstance, p: vec3<f32>, time: f32) -> vec3<f32> {
    let w = frame.wind;
    if (w.w == 0.0 || materials[inst.material].shader != GPU_SHADER_ALPHA_TESTED) {
        return vec3<f32>(0.0);
    }
    let bend = clamp(p.y * w.w, 0.0, 1.0);
    let weight = bend * bend;
    let x = 0.37 * inst.row0.w + 0.23 * inst.row2.w;
    let phase = 6.2831855 * (x - floor(x));
    let a = w.z * time;
    let sway = sin(a + phase) + 0.3 * sin(2.3 * a + 2.0 * phase);
    return vec3<f32>(w.x, 0.0, w.y) * (weight * sway);
}

// Camera-relative position of object-space point `p` of `inst` this frame, animated:
// what every pass that positions vertices uses (laydown, compute laydown, depth prepass,
// baseline, shadow maps, resolve), so their depths stay bit-identical.
fn gpu_position(inst: GpuInstance, p: vec3<f32>) -> vec3<f32> {
    return gpu_camera_relative(inst, p) + gpu_wind(inst, p, frame.time);
}

// The same point's pose at the previous frame's time, in this frame's camera-relative
// space (frame.prev_view_proj takes it to last frame's clip): motion vectors.
fn gpu_previous_position(inst: GpuInstance, p: vec3<f32>) -> vec3<f32> {
    return gpu_camera_relative(inst, p) + gpu_wind(inst, p, frame.prev_time);
}
