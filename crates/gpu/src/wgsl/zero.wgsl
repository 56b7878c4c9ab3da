// gpu: zeroes the bound buffer, one word per invocation, in rows of 65 535 workgroups.

@group(0) @binding(0) var<storage, read_write> words: array<u32>;

@compute @workgroup_size(256)
fn zero(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.y * 65535u * 256u + id.x;
    if i < arrayLength(&words) {
        words[i] = 0u;
    }
}
