// gpu: FC5's screen-space tessellation (seed 003). Per visible 32x32 tile, one instance
// of a grid of 16x16 quads (2x2 mini G-buffer pixels a quad: "constant density
// tessellation"), drawn with one draw_indexed_indirect: the index buffer holds the grid's
// 16-bit vertex words themselves (water::tiles: cell, triangle, corner), so the vertex
// index is the word and no vertex buffer exists. Each vertex finds its tile in the list,
// tests its triangle's three pixels for water (all three vertices take the same
// decision) and takes its own pixel's displaced position, which the displacement pass
// built (in the wide water view, projected with the camera's) and stored: three fetches.
// WGSL clips nothing on NaN, so a killed triangle's vertices all go to one point behind
// the near plane (WATER_COLLAPSED_CLIP): zero area, culled. Drawn depth-tested against the
// scene into the depth with water; writes the view depth and the mini G-buffer UV of the
// surface it shows ("we have to write out the UVs").

#import gpu::frame
#import gpu::water_frame
#import water::tiles

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var<uniform> water: GpuWaterFrame;
// The displacement pass's vertices (one per mini G-buffer pixel, clip space, w <= 0:
// no water).
@group(0) @binding(2) var<storage, read> vertices: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> tile_list: array<u32>;

struct GpuWaterSurfaceVarying {
    @builtin(position) clip: vec4<f32>,
    // view depth, then the mini G-buffer UV
    @location(0) surface: vec3<f32>,
}

// The vertex of mini G-buffer pixel `p` (inside the buffer).
fn gpu_water_vertex(p: vec2<u32>) -> vec4<f32> {
    let at = p.y * water.size.z + p.x;
    if (at >= arrayLength(&vertices)) {
        return vec4<f32>(0.0, 0.0, 0.0, -1.0);
    }
    return vertices[at];
}

@vertex
fn vs_grid(@builtin(vertex_index) word: u32, @builtin(instance_index) instance: u32) -> GpuWaterSurfaceVarying {
    var out = GpuWaterSurfaceVarying(WATER_COLLAPSED_CLIP, vec3<f32>(0.0));
    let size = water.size.zw;
    let tiles = water.grid.x * water.grid.y;
    let n = arrayLength(&tile_list);
    if (n == 0u || size.x == 0u || size.y == 0u) {
        return out;
    }
    let tile = tile_list[min(instance, n - 1u)];
    if (tile >= tiles) {
        return out;
    }
    let v = water_grid_vertex(word & 0xffffu);
    let quads = clamp(water.grid.z, 1u, WATER_MAX_GRID_QUADS);
    if (v.cell.x >= quads || v.cell.y >= quads) {
        return out;
    }
    let origin = water_tile_origin(tile, water.grid.x, WATER_TILE_SIZE);
    // All three vertices of a triangle test the same three pixels: killed together.
    for (var k = 0u; k < 3u; k++) {
        if (!(gpu_water_vertex(water_grid_corner_pixel(v, k, origin, WATER_TILE_SIZE, quads, size)).w > 0.0)) {
            return out;
        }
    }
    let p = min(water_grid_to_pixel(origin, water_grid_position(v), WATER_TILE_SIZE, quads), size - vec2<u32>(1u));
    out.clip = gpu_water_vertex(p);
    // Perspective: clip w is the view depth.
    out.surface = vec3<f32>(out.clip.w, (vec2<f32>(p) + 0.5) / vec2<f32>(size));
    return out;
}

@fragment
fn fs_grid(in: GpuWaterSurfaceVarying) -> @location(0) vec4<f32> {
    return vec4<f32>(in.surface, 1.0);
}
