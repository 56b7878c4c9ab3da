// gpu::hiz_depth: level 0 of staticscene's HiZ buffer from the frame's depth target,
// texel for texel (the buffer's layout: staticscene pass::hiz_header, written by the
// CPU when the size changes; staticscene::hiz_pass then reduces level after level).
// Word 4, 5: level 0's width and height; word 6: its first texel word.

@group(0) @binding(0) var depth: texture_depth_2d;
@group(0) @binding(1) var<storage, read_write> hiz: array<u32>;

@compute @workgroup_size(8, 8)
fn depth_to_hiz(@builtin(global_invocation_id) id: vec3<u32>) {
    let w = hiz[4];
    let h = hiz[5];
    let size = textureDimensions(depth);
    if (id.x >= w || id.y >= h || id.x >= size.x || id.y >= size.y) {
        return;
    }
    let at = hiz[6] + id.y * w + id.x;
    if (at < arrayLength(&hiz)) {
        hiz[at] = bitcast<u32>(textureLoad(depth, vec2<i32>(id.xy), 0));
    }
}
