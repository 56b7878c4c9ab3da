// gpu: FC5's screen-space tessellation (seed 003). Per visible 32x32 tile, one instance
// of a grid of 16x16 quads (2x2 mini G-buffer pixels a quad: "constant density
// tessellation"), drawn with one draw_indexed_indirect: the index buffer holds the grid's
// 16-bit vertex words themselves (water::tiles: cell, triangle, corner), so the vertex
// index is the word and no vertex buffer exists. Each vertex finds its tile in the list,
// tests its triangle's three pixels for water (all three vertices take the same
// decision), samples the mini G-buffer's depth and the displacement at its own pixel,
// builds the world position in the wide water view and projects it with the camera's.
// WGSL clips nothing on NaN, so a killed triangle's vertices all go to one point behind
// the near plane (WATER_COLLAPSED_CLIP): zero area, culled. Drawn depth-tested against the
// scene into the depth with water; writes the view depth and the mini G-buffer UV of the
// surface it shows ("we have to write out the UVs").

#import gpu::frame
#import gpu::water_frame
#import water::gbuffer
#import water::tiles

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var<uniform> water: GpuWaterFrame;
@group(0) @binding(2) var data: texture_2d<u32>;
@group(0) @binding(3) var depth: texture_2d<f32>;
@group(0) @binding(4) var displacement: texture_2d<f32>;
@group(0) @binding(5) var<storage, read> tile_list: array<u32>;

struct GpuWaterSurfaceVarying {
    @builtin(position) clip: vec4<f32>,
    // view depth, then the mini G-buffer UV
    @location(0) surface: vec3<f32>,
}

// Whether the mini G-buffer has water at pixel `p` (inside the buffer).
fn gpu_water_pixel_ok(p: vec2<u32>) -> bool {
    return water_data_is_valid(textureLoad(data, p, 0).r) && gpu_water_depth_ok(textureLoad(depth, p, 0).r);
}

@vertex
fn vs_grid(@builtin(vertex_index) word: u32, @builtin(instance_index) instance: u32) -> GpuWaterSurfaceVarying {
    var out = GpuWaterSurfaceVarying(WATER_COLLAPSED_CLIP, vec3<f32>(0.0));
    let size = min(min(water.size.zw, textureDimensions(data)), min(textureDimensions(depth), textureDimensions(displacement)));
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
    for (var k = 0u; k < 3u; k++) {
        if (!gpu_water_pixel_ok(water_grid_corner_pixel(v, k, origin, WATER_TILE_SIZE, quads, size))) {
            return out;
        }
    }
    let p = min(water_grid_to_pixel(origin, water_grid_position(v), WATER_TILE_SIZE, quads), size - vec2<u32>(1u));
    let d = textureLoad(depth, p, 0).r;
    var rel = gpu_water_relative(water, vec2<f32>(p) + 0.5, d, water.size.zw, water.tan_half.zw);
    let disp = textureLoad(displacement, p, 0).xyz;
    let limit = vec3<f32>(max(water.shore.w, 0.0));
    rel += select(vec3<f32>(0.0), clamp(disp, -limit, limit), disp == disp);
    out.clip = frame.view_proj * vec4<f32>(rel, 1.0);
    out.surface = vec3<f32>(gpu_water_view_depth(water, rel), (vec2<f32>(p) + 0.5) / vec2<f32>(water.size.zw));
    return out;
}

@fragment
fn fs_grid(in: GpuWaterSurfaceVarying) -> @location(0) vec4<f32> {
    return vec4<f32>(in.surface, 1.0);
}
