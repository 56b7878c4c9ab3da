// gpu: the R32Uint vis-buffer target into the row-major word buffer the classification
// reads (wgpu cannot view a texture as a buffer).

@group(0) @binding(0) var vis_texture: texture_2d<u32>;
@group(0) @binding(1) var<storage, read_write> vis_words: array<u32>;

@compute @workgroup_size(16, 16)
fn copy_vis(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(vis_texture);
    if id.x < size.x && id.y < size.y {
        vis_words[id.y * size.x + id.x] = textureLoad(vis_texture, vec2<i32>(id.xy), 0).x;
    }
}
