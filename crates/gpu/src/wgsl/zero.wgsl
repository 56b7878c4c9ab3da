// gpu: fills the bound buffer with ZERO_FILL (zeroes by default; all ones for the mixed
// frame's validity bitmask), one word per invocation, in rows of TILING_MAX_DISPATCH_X
// workgroups (shader's MAX_WORKGROUPS_X; the `Dispatch::Items` layout of its description,
// indexed by tiling_item_index).

#import tiling::common

// Invocations per workgroup (the `Entry::items` size of its description).
const ZERO_WORKGROUP_SIZE: u32 = 256u;

// The word written.
override ZERO_FILL: u32 = 0u;

@group(0) @binding(0) var<storage, read_write> words: array<u32>;

@compute @workgroup_size(ZERO_WORKGROUP_SIZE)
fn zero(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = tiling_item_index(id, groups, ZERO_WORKGROUP_SIZE);
    if i < arrayLength(&words) {
        words[i] = ZERO_FILL;
    }
}
