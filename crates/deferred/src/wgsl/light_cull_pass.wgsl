// deferred::light_cull_pass: pass 2 of tiled light culling (twin of lights.rs
// `cull_tiles`). One workgroup of 64 invocations per tile: the lights are tested 64 at a
// time against the tile's frustum (deferred_light_in_tile) and the passing indices
// appended in ascending order, up to DEFERRED_MAX_LIGHTS_PER_TILE; a tile that finds more
// keeps the first ones and counts as overflowed. Tiles without geometry get an empty
// list. Every index and length is checked against its buffer.

#import deferred::lights

const DEFERRED_CULL_WORKGROUP: u32 = 64u;
// Workgroups per row of a 2D dispatch (Rust: shader::MAX_WORKGROUPS_X).
const DEFERRED_MAX_WORKGROUPS_X: u32 = 65535u;
// Most lights one pass takes (Rust: MAX_LIGHTS).
const DEFERRED_MAX_LIGHTS: u32 = 65536u;

// Rust: deferred::pass::LightCullParams (48 bytes).
struct DeferredLightCullParams {
    projection: DeferredProjection,
    // tiles across and down (lights::tile_counts of the viewport)
    tiles: vec2<u32>,
    light_count: u32,
    pad: u32,
}

// Rust: deferred::pass::LightCullCounters (16 bytes), zeroed before the pass.
struct DeferredLightCullCounters {
    tiles_with_geometry: atomic<u32>,
    pairs: atomic<u32>,
    overflowed_tiles: atomic<u32>,
    pad: u32,
}

@group(0) @binding(0) var<uniform> params: DeferredLightCullParams;
@group(0) @binding(1) var<storage, read> tile_depths: array<DeferredTileDepth>;
@group(0) @binding(2) var<storage, read> lights: array<DeferredLight>;
// Per tile: its light count.
@group(0) @binding(3) var<storage, read_write> counts: array<u32>;
// Per tile: DEFERRED_MAX_LIGHTS_PER_TILE slots of light indices.
@group(0) @binding(4) var<storage, read_write> indices: array<u32>;
@group(0) @binding(5) var<storage, read_write> counters: DeferredLightCullCounters;

// The chunk's passing lanes, one bit each.
var<workgroup> deferred_wg_mask: array<atomic<u32>, 2>;
var<workgroup> deferred_wg_mask_copy: vec2<u32>;

@compute @workgroup_size(64)
fn cull_lights(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) li: u32) {
    let tile = wid.y * DEFERRED_MAX_WORKGROUPS_X + wid.x;
    let tx = params.tiles.x;
    let tile_count = tx * params.tiles.y;
    if (tile >= tile_count || tile >= arrayLength(&tile_depths) || tile >= arrayLength(&counts)) {
        return;
    }
    let depth = tile_depths[tile];
    let reversed = params.projection.beta > 0.0;
    let far_depth = select(1.0, 0.0, reversed);
    if (deferred_tile_is_empty(depth, far_depth)) {
        if (li == 0u) {
            counts[tile] = 0u;
        }
        return;
    }
    let f = deferred_tile_frustum(params.projection, vec2<u32>(tile % tx, tile / tx), depth);
    let n = min(min(params.light_count, arrayLength(&lights)), DEFERRED_MAX_LIGHTS);
    let slot = tile * DEFERRED_MAX_LIGHTS_PER_TILE;
    var count = 0u;
    var overflow = false;
    for (var base = 0u; base < n; base += DEFERRED_CULL_WORKGROUP) {
        if (li < 2u) {
            atomicStore(&deferred_wg_mask[li], 0u);
        }
        workgroupBarrier();
        let i = base + li;
        let visible = i < n && deferred_light_in_tile(f, lights[i]);
        if (visible) {
            atomicOr(&deferred_wg_mask[li / 32u], 1u << (li % 32u));
        }
        workgroupBarrier();
        if (li == 0u) {
            deferred_wg_mask_copy = vec2<u32>(atomicLoad(&deferred_wg_mask[0]), atomicLoad(&deferred_wg_mask[1]));
        }
        let mask = workgroupUniformLoad(&deferred_wg_mask_copy);
        // Rank among the chunk's passing lanes (ascending light index).
        var below = countOneBits(mask.x & ((1u << min(li, 31u)) - 1u));
        if (li >= 32u) {
            below = countOneBits(mask.x) + countOneBits(mask.y & ((1u << (li - 32u)) - 1u));
        }
        let at = count + below;
        if (visible && at < DEFERRED_MAX_LIGHTS_PER_TILE && slot + at < arrayLength(&indices)) {
            indices[slot + at] = i;
        }
        let total = countOneBits(mask.x) + countOneBits(mask.y);
        if (count + total > DEFERRED_MAX_LIGHTS_PER_TILE) {
            count = DEFERRED_MAX_LIGHTS_PER_TILE;
            overflow = true;
            break;
        }
        count += total;
    }
    if (li == 0u) {
        counts[tile] = count;
        atomicAdd(&counters.tiles_with_geometry, 1u);
        atomicAdd(&counters.pairs, count);
        if (overflow) {
            atomicAdd(&counters.overflowed_tiles, 1u);
        }
    }
}
