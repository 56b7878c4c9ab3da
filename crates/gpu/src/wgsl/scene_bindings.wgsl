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

// Camera-relative position of object-space point `p` of `inst`.
fn gpu_camera_relative(inst: GpuInstance, p: vec3<f32>) -> vec3<f32> {
    return gpu_transform_point(inst, p) + frame.origin_offset.xyz;
}
