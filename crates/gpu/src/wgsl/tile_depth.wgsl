// gpu::tile_depth: pass 1 of tiled light culling (twin of deferred::lights
// `tile_depth_ranges`) over the depth target. One 16x16 workgroup per
// DEFERRED_TILE_SIZE^2 tile: each invocation loads its pixel's depth and folds it into the
// tile's nearest and farthest through workgroup atomics on order-preserving words (so any
// float orders as on the CPU); pixels at the far plane's depth and NaN are skipped.

#import deferred::lights

// Rust: passes::lights::GpuTileDepthParams (16 bytes).
struct GpuTileDepthParams {
    // viewport width, height in pixels
    size: vec2<u32>,
    // tiles across
    tiles_x: u32,
    // non-zero for reversed depth (far plane at 0)
    reversed: u32,
}

@group(0) @binding(0) var<uniform> params: GpuTileDepthParams;
@group(0) @binding(1) var depth_texture: texture_depth_2d;
@group(0) @binding(2) var<storage, read_write> tile_depths: array<DeferredTileDepth>;

// The tile's nearest and farthest so far, as order-preserving words.
var<workgroup> gpu_tile_near: atomic<u32>;
var<workgroup> gpu_tile_far: atomic<u32>;

// f32 to a u32 with the same order.
fn gpu_ordered(f: f32) -> u32 {
    let b = bitcast<u32>(f);
    return select(b | 0x80000000u, ~b, (b & 0x80000000u) != 0u);
}

fn gpu_unordered(u: u32) -> f32 {
    return bitcast<f32>(select(~u, u & 0x7fffffffu, (u & 0x80000000u) != 0u));
}

@compute @workgroup_size(16, 16)
fn tile_depth(@builtin(workgroup_id) wid: vec3<u32>, @builtin(global_invocation_id) id: vec3<u32>, @builtin(local_invocation_index) li: u32) {
    let reversed = params.reversed != 0u;
    let far = select(1.0, 0.0, reversed);
    let empty = DeferredTileDepth(far, select(0.0, 1.0, reversed));
    if (li == 0u) {
        // Reversed: nearest is a maximum (from far = 0), farthest a minimum (from 1).
        // Standard: the other way round. Kept as maximum words: minima complemented.
        atomicStore(&gpu_tile_near, select(~gpu_ordered(empty.nearest), gpu_ordered(empty.nearest), reversed));
        atomicStore(&gpu_tile_far, select(gpu_ordered(empty.farthest), ~gpu_ordered(empty.farthest), reversed));
    }
    workgroupBarrier();
    let size = min(params.size, vec2<u32>(textureDimensions(depth_texture)));
    if (all(id.xy < size)) {
        let d = textureLoad(depth_texture, vec2<i32>(id.xy), 0);
        let nan = (bitcast<u32>(d) & 0x7fffffffu) > 0x7f800000u;
        if (d != far && !nan) {
            let o = gpu_ordered(d);
            if (reversed) {
                atomicMax(&gpu_tile_near, o);
                atomicMax(&gpu_tile_far, ~o);
            } else {
                atomicMax(&gpu_tile_near, ~o);
                atomicMax(&gpu_tile_far, o);
            }
        }
    }
    workgroupBarrier();
    let tile = wid.y * params.tiles_x + wid.x;
    if (li == 0u && wid.x < params.tiles_x && tile < arrayLength(&tile_depths)) {
        let n = atomicLoad(&gpu_tile_near);
        let f = atomicLoad(&gpu_tile_far);
        tile_depths[tile] = DeferredTileDepth(
            gpu_unordered(select(~n, n, reversed)),
            gpu_unordered(select(f, ~f, reversed)),
        );
    }
}
