// gpu: zeroes the bound buffer, one word per invocation, in rows of TILING_MAX_DISPATCH_X
// workgroups (shader's MAX_WORKGROUPS_X; the `Dispatch::Items` layout of its description).

#import tiling::common

@group(0) @binding(0) var<storage, read_write> words: array<u32>;

@compute @workgroup_size(256)
fn zero(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.y * TILING_MAX_DISPATCH_X * 256u + id.x;
    if i < arrayLength(&words) {
        words[i] = 0u;
    }
}
