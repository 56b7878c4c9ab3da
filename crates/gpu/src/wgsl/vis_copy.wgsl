// gpu: after a hardware geometry pass, what the compute passes read: the R32Uint vis
// target into the row-major word buffer the classification reads (wgpu cannot view a
// texture as a buffer), and the depth target into the float depth the light tiles and
// lighting read (compute passes cannot write depth textures, so the compute laydown
// writes that one directly and the hardware paths copy it here). `copy_depth` alone ends
// the baseline's geometry.

@group(0) @binding(0) var vis_texture: texture_2d<u32>;
@group(0) @binding(1) var<storage, read_write> vis_words: array<u32>;
@group(0) @binding(2) var depth_texture: texture_depth_2d;
@group(0) @binding(3) var depth_float: texture_storage_2d<r32float, write>;

@compute @workgroup_size(16, 16)
fn copy_vis(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(vis_texture);
    if id.x < size.x && id.y < size.y {
        let i = id.y * size.x + id.x;
        if i < arrayLength(&vis_words) {
            vis_words[i] = textureLoad(vis_texture, vec2<i32>(id.xy), 0).x;
        }
        let d = textureLoad(depth_texture, vec2<i32>(id.xy), 0);
        textureStore(depth_float, id.xy, vec4<f32>(d, 0.0, 0.0, 0.0));
    }
}

@compute @workgroup_size(16, 16)
fn copy_depth(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(depth_float);
    if id.x < size.x && id.y < size.y {
        let d = textureLoad(depth_texture, vec2<i32>(id.xy), 0);
        textureStore(depth_float, id.xy, vec4<f32>(d, 0.0, 0.0, 0.0));
    }
}
