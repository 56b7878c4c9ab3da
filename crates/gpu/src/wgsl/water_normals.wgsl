// gpu: FC5's normals from depth (seed 003: "we need to generate a screen space normal map
// without ddx, ddy, which we use position from depth to do"), over the tessellated
// surface's view depth at full resolution: water::normals' 9-tap reconstruction (the side
// that continues the surface, the central difference where both do), its radius growing
// as the camera nears the water, blended with the low-resolution mesh normal from the mini
// G-buffer by the material's detail weight. Output: the world normal (+Y up), 0 where
// there is no water.

#import gpu::frame
#import gpu::water_frame
#import water::gbuffer
#import water::material

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var<uniform> water: GpuWaterFrame;
// The tessellation's target: view depth (0: no water), mini G-buffer UV.
@group(0) @binding(2) var surface: texture_2d<f32>;
@group(0) @binding(3) var data: texture_2d<u32>;
@group(0) @binding(4) var mesh_normal: texture_2d<f32>;
@group(0) @binding(5) var<storage, read> materials: array<WaterMaterialGpu>;
@group(0) @binding(6) var normals: texture_storage_2d<rgba16float, write>;

// The mini G-buffer pixel a surface UV names, clamped.
fn gpu_water_gbuffer_pixel(uv: vec2<f32>) -> vec2<u32> {
    let size = max(min(textureDimensions(data), textureDimensions(mesh_normal)), vec2<u32>(1u));
    let p = clamp(uv * vec2<f32>(size), vec2<f32>(0.0), vec2<f32>(size - vec2<u32>(1u)));
    return select(vec2<u32>(0u), vec2<u32>(p), p == p);
}

@compute @workgroup_size(8, 8)
fn normals_from_depth(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(surface);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let s = textureLoad(surface, id.xy, 0);
    if (!gpu_water_depth_ok(s.r)) {
        textureStore(normals, id.xy, vec4<f32>(0.0));
        return;
    }
    let g = gpu_water_gbuffer_pixel(s.gb);
    let word = textureLoad(data, g, 0).r;
    let count = max(min(water.counts.x, arrayLength(&materials)), 1u);
    let m = materials[min(word >> WATER_MATERIAL_SHIFT, count - 1u)];
    var mesh = textureLoad(mesh_normal, g, 0).xyz;
    if (!(dot(mesh, mesh) > 1e-8) || !(dot(mesh, mesh) < 1e8)) {
        mesh = vec3<f32>(0.0, 1.0, 0.0);
    }
    mesh = normalize(mesh);
    let radius = water_normal_radius(s.r, water.normals.x, u32(clamp(water.normals.y, 1.0, 16.0)));
    let nv = water_normal_from_depth(surface, vec2<i32>(id.xy), radius, WATER_TAPS_NINE, water.tan_half.xy);
    var n = mesh;
    if (dot(nv, nv) > 0.5) {
        let detail = (water.inv_rotation * vec4<f32>(nv, 0.0)).xyz;
        n = water_blend_normals(mesh, detail, m.detail_weight);
    }
    textureStore(normals, id.xy, vec4<f32>(n, 1.0));
}
