// gpu: fills buffers with ZERO_FILL (zeroes by default; all ones for the mixed frame's
// validity bitmask), one word per invocation, in rows of TILING_MAX_DISPATCH_X workgroups
// (shader's MAX_WORKGROUPS_X; the `Dispatch::Items` layout of its description, indexed by
// tiling_item_index). Without features: the one bound buffer. With `many`: ZERO_BINDINGS
// buffers in one dispatch over their words together, word i of buffer k after every word
// of buffers 0..k (one dispatch: the classification's nine buffers as nine dispatches
// took 16 us on the H200, most of it their launches).

#import tiling::common

// Invocations per workgroup (the `Entry::items` size of its description).
const ZERO_WORKGROUP_SIZE: u32 = 256u;

// The word written.
override ZERO_FILL: u32 = 0u;

#if many
// Words each invocation writes (the description dispatches a quarter of the words).
const ZERO_MANY_WORDS: u32 = 4u;

@group(0) @binding(0) var<storage, read_write> words0: array<u32>;
@group(0) @binding(1) var<storage, read_write> words1: array<u32>;
@group(0) @binding(2) var<storage, read_write> words2: array<u32>;
@group(0) @binding(3) var<storage, read_write> words3: array<u32>;
@group(0) @binding(4) var<storage, read_write> words4: array<u32>;
@group(0) @binding(5) var<storage, read_write> words5: array<u32>;
@group(0) @binding(6) var<storage, read_write> words6: array<u32>;
@group(0) @binding(7) var<storage, read_write> words7: array<u32>;
@group(0) @binding(8) var<storage, read_write> words8: array<u32>;
@group(0) @binding(9) var<storage, read_write> words9: array<u32>;

// Word i of the buffers taken one after another (the bindings are written out: WGSL has
// no array of differently sized buffers without binding arrays).
fn zero_word(i: u32) {
    var k = i;
    if (k < arrayLength(&words0)) { words0[k] = ZERO_FILL; return; }
    k -= arrayLength(&words0);
    if (k < arrayLength(&words1)) { words1[k] = ZERO_FILL; return; }
    k -= arrayLength(&words1);
    if (k < arrayLength(&words2)) { words2[k] = ZERO_FILL; return; }
    k -= arrayLength(&words2);
    if (k < arrayLength(&words3)) { words3[k] = ZERO_FILL; return; }
    k -= arrayLength(&words3);
    if (k < arrayLength(&words4)) { words4[k] = ZERO_FILL; return; }
    k -= arrayLength(&words4);
    if (k < arrayLength(&words5)) { words5[k] = ZERO_FILL; return; }
    k -= arrayLength(&words5);
    if (k < arrayLength(&words6)) { words6[k] = ZERO_FILL; return; }
    k -= arrayLength(&words6);
    if (k < arrayLength(&words7)) { words7[k] = ZERO_FILL; return; }
    k -= arrayLength(&words7);
    if (k < arrayLength(&words8)) { words8[k] = ZERO_FILL; return; }
    k -= arrayLength(&words8);
    if (k < arrayLength(&words9)) { words9[k] = ZERO_FILL; }
}
#else
@group(0) @binding(0) var<storage, read_write> words: array<u32>;

fn zero_word(i: u32) {
    if (i < arrayLength(&words)) {
        words[i] = ZERO_FILL;
    }
}
#endif

@compute @workgroup_size(ZERO_WORKGROUP_SIZE)
fn zero(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = tiling_item_index(id, groups, ZERO_WORKGROUP_SIZE);
#if many
    // ZERO_MANY_WORDS words per invocation, the dispatch's invocations apart (each store
    // of a subgroup contiguous): a quarter of the invocations.
    let n = groups.x * groups.y * ZERO_WORKGROUP_SIZE;
    for (var k = 0u; k < ZERO_MANY_WORDS; k++) {
        zero_word(i + k * n);
    }
#else
    zero_word(i);
#endif
}
