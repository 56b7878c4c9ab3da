// gpu: the scene's records as the shaders read them. Rust twins: gpu's GpuVertex,
// GpuMaterial, GpuMesh and GpuMicroBatch (sizes checked by tests).

// One vertex, pulled from storage by every pass (no vertex buffers).
struct GpuVertex {
    position: vec3<f32>,
    u: f32,
    normal: vec3<f32>,
    v: f32,
    tangent: vec4<f32>,
}

struct GpuMaterial {
    tint: vec3<f32>,
    albedo_layer: u32,
    alpha_cutoff: f32,
    roughness: f32,
    specular: f32,
    shader: u32,
    emissive: vec3<f32>,
    metallic: f32,
    // data_maps layers, GPU_MATERIAL_NO_MAP where absent
    normal_layer: u32,
    normal_scale: f32,
    metallic_roughness_layer: u32,
    occlusion_layer: u32,
    occlusion_strength: f32,
    // albedo layer, GPU_MATERIAL_NO_MAP where absent
    emissive_layer: u32,
    // scene::MaterialFeatures bits
    features: u32,
    pad: u32,
}

// Rust: resources::rows::NO_MAP.
const GPU_MATERIAL_NO_MAP: u32 = 0xffffffffu;

// Where one mesh sits in the concatenated index and vertex arrays.
struct GpuMesh {
    first_index: u32,
    primitive_count: u32,
    base_vertex: u32,
    vertex_count: u32,
}

// What the resolve looks up per micro-batch ID.
struct GpuMicroBatch {
    first_instance: u32,
    first_id: u32,
    mesh: u32,
    primitive_bits: u32,
}
