// water: screen tiles and the tessellated grid. Twin of `water::tiles`.

const WATER_TILE_SIZE: u32 = 32u;
const WATER_COUNT_GROUP_SIZE: u32 = 8u;
const WATER_MAX_GRID_QUADS: u32 = 64u;
const WATER_GRID_CELL_BITS: u32 = 6u;
const WATER_GRID_HALF_SHIFT: u32 = 12u;
const WATER_GRID_CORNER_SHIFT: u32 = 13u;

// Where a killed triangle's vertices go: one point behind the near plane.
const WATER_COLLAPSED_CLIP: vec4<f32> = vec4<f32>(0.0, 0.0, -1.0, 1.0);

struct WaterGridVertex {
    cell: vec2<u32>,
    triangle: u32,
    corner: u32,
}

// `GridVertex::unpack` of a 16-bit word (in the low half of `w`).
fn water_grid_vertex(w: u32) -> WaterGridVertex {
    let m = (1u << WATER_GRID_CELL_BITS) - 1u;
    return WaterGridVertex(
        vec2<u32>(w & m, (w >> WATER_GRID_CELL_BITS) & m),
        (w >> WATER_GRID_HALF_SHIFT) & 1u,
        min((w >> WATER_GRID_CORNER_SHIFT) & 3u, 2u),
    );
}

// Corner `k` (0..2) of triangle `triangle` of a cell: `GRID_CORNERS`.
fn water_grid_corner_offset(triangle: u32, k: u32) -> vec2<u32> {
    if (k == 0u) {
        return vec2<u32>(0u, 0u);
    }
    if (k == 1u) {
        return select(vec2<u32>(1u, 1u), vec2<u32>(1u, 0u), triangle == 0u);
    }
    return select(vec2<u32>(0u, 1u), vec2<u32>(1u, 1u), triangle == 0u);
}

// The vertex's own position in grid units.
fn water_grid_position(v: WaterGridVertex) -> vec2<u32> {
    return v.cell + water_grid_corner_offset(v.triangle, v.corner);
}

// Grid units to water-buffer pixels for a tile: origin + p * tile_size / quads.
fn water_grid_to_pixel(tile_origin: vec2<u32>, p: vec2<u32>, tile_size: u32, quads: u32) -> vec2<u32> {
    return tile_origin + p * tile_size / quads;
}

// The pixel each of the triangle's corners tests (clamped to the buffer).
fn water_grid_corner_pixel(v: WaterGridVertex, k: u32, tile_origin: vec2<u32>, tile_size: u32, quads: u32, buffer: vec2<u32>) -> vec2<u32> {
    let p = water_grid_to_pixel(tile_origin, v.cell + water_grid_corner_offset(v.triangle, k), tile_size, quads);
    return min(p, buffer - vec2<u32>(1u));
}

// Tile `id`'s top-left pixel.
fn water_tile_origin(id: u32, tiles_x: u32, tile_size: u32) -> vec2<u32> {
    return vec2<u32>(id % tiles_x, id / tiles_x) * tile_size;
}

// The tile holding a pixel.
fn water_tile_of(p: vec2<u32>, tiles_x: u32, tile_size: u32) -> u32 {
    return (p.y / tile_size) * tiles_x + p.x / tile_size;
}
