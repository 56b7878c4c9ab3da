// gpu: FC5's 32x32 screen tiles over the mini G-buffer (seed 003: "we divide the screen
// into 32 by 32 tiles"), the GPU twin of water::tiles' `count_pass` and `list_pass`.
// `count_tiles`: 8x8 workgroups (never straddling a tile), each pixel's valid bit
// aggregated by a ballot (wave::append: one atomic per subgroup, or per workgroup on the
// fallback: "reduce this from 64 atomics to a single atomic") into its tile's count.
// `list_tiles`: per tile with water, one slot of the indirect draw's instance count and
// the tile's ID in that slot of the list. The list's order is the GPU's; it is a set.

#import gpu::water_frame
#import water::gbuffer
#import water::tiles
#import wave::append

@group(0) @binding(0) var<uniform> water: GpuWaterFrame;
@group(0) @binding(1) var data: texture_2d<u32>;
@group(0) @binding(2) var<storage, read_write> counts: array<atomic<u32>>;
@group(0) @binding(3) var<storage, read_write> tile_list: array<u32>;
// wgpu's DrawIndexedIndirectArgs of the tessellated grids (5 words).
@group(0) @binding(4) var<storage, read_write> args: array<atomic<u32>>;

@compute @workgroup_size(8, 8)
fn count_tiles(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
) {
    let size = min(water.size.zw, textureDimensions(data));
    var valid = false;
    if (id.x < size.x && id.y < size.y) {
        valid = water_data_is_valid(textureLoad(data, id.xy, 0).r);
    }
    // Every invocation takes part in the ballot (uniform control flow).
    let a = wave_append_begin(valid, li);
    if (a.total != 0u) {
        let tile = water_tile_of(wid.xy * WATER_COUNT_GROUP_SIZE, water.grid.x, WATER_TILE_SIZE);
        if (tile < arrayLength(&counts)) {
            atomicAdd(&counts[tile], a.total);
        }
    }
}

@compute @workgroup_size(64)
fn list_tiles(@builtin(global_invocation_id) gid: vec3<u32>) {
    let t = gid.y * 4194240u + gid.x;
    if (t == 0u) {
        // The grid's index count (6 per quad: triangles of unshared 16-bit vertices).
        atomicStore(&args[0], 6u * water.grid.z * water.grid.z);
    }
    let tiles = min(water.grid.x * water.grid.y, arrayLength(&counts));
    if (t >= tiles) {
        return;
    }
    if (atomicLoad(&counts[t]) > 0u) {
        let slot = atomicAdd(&args[1], 1u);
        if (slot < arrayLength(&tile_list)) {
            tile_list[slot] = t;
        }
    }
}
