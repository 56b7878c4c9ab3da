// water: the water query over a baked world (`WaterWorld::words()` uploaded as an R32Uint
// texture, word i at (i % width, i / width)). Twin of `water::world`; the layout table is
// in its docs, the constants are tied to Rust by unit tests.

const WATER_WORLD_MAGIC: u32 = 1381253463u;
const WATER_WORLD_VERSION: u32 = 1u;
const WATER_NODE_INTERNAL: u32 = 4294967295u;
const WATER_TEXEL_NONE: u32 = 4294967295u;
const WATER_KIND_SHIFT: u32 = 30u;
const WATER_ITEM_LAKE_INSIDE: u32 = 0u;
const WATER_ITEM_LAKE_PARTIAL: u32 = 1u;
const WATER_ITEM_RIVER_TILE: u32 = 2u;
const WATER_BODY_LAKE: u32 = 1u;
const WATER_BODY_RIVER: u32 = 2u;
const WATER_BODY_OCEAN: u32 = 3u;
const WATER_ITEM_WORDS: u32 = 4u;
const WATER_TILE_WORDS: u32 = 6u;
const WATER_TEXEL_WORDS: u32 = 3u;
const WATER_MAX_QUADTREE_DEPTH: u32 = 20u;
const WATER_H_FLAGS: u32 = 2u;
const WATER_H_OCEAN_LEVEL: u32 = 3u;
const WATER_H_OCEAN_MATERIAL: u32 = 4u;
const WATER_H_ROOT_X: u32 = 5u;
const WATER_H_ROOT_Y: u32 = 6u;
const WATER_H_ROOT_SIZE: u32 = 7u;
const WATER_H_NODES: u32 = 8u;
const WATER_H_ITEMS: u32 = 10u;
const WATER_H_LAKES: u32 = 11u;
const WATER_H_TILES: u32 = 13u;
const WATER_H_TILE_TEXELS: u32 = 15u;
const WATER_H_EDGES: u32 = 16u;

// `WaterLevel`, with `found` = 0 for none. `body` is a `BodyId` word.
struct WaterQuery {
    found: u32,
    height: f32,
    body: u32,
    material: u32,
    depth: f32,
    flow: vec2<f32>,
}

fn water_world_word(data: texture_2d<u32>, i: u32) -> u32 {
    let w = textureDimensions(data).x;
    return textureLoad(data, vec2<u32>(i % w, i / w), 0).r;
}

fn water_world_f32(data: texture_2d<u32>, i: u32) -> f32 {
    return bitcast<f32>(water_world_word(data, i));
}

// IEEE half to f32, written out (`unpack2x16float` needs a downlevel capability).
fn water_half_to_f32(h: u32) -> f32 {
    let s = (h >> 15u) & 1u;
    let e = (h >> 10u) & 31u;
    let m = h & 1023u;
    if (e == 0u) {
        let v = f32(m) * 5.9604645e-8;
        return select(v, -v, s == 1u);
    }
    if (e == 31u) {
        return bitcast<f32>((s << 31u) | 0x7f800000u | (m << 13u));
    }
    return bitcast<f32>((s << 31u) | ((e + 112u) << 23u) | (m << 13u));
}

fn water_unpack_half2(w: u32) -> vec2<f32> {
    return vec2<f32>(water_half_to_f32(w & 0xffffu), water_half_to_f32(w >> 16u));
}

fn water_world_offer(best: ptr<function, WaterQuery>, c: WaterQuery) {
    if ((*best).found == 0u || c.height > (*best).height) {
        *best = c;
    }
}

fn water_world_crosses(x0: f32, y0: f32, x1: f32, y1: f32, p: vec2<f32>) -> bool {
    if ((y0 > p.y) != (y1 > p.y)) {
        let xc = x0 + (p.y - y0) * (x1 - x0) / (y1 - y0);
        return p.x < xc;
    }
    return false;
}

// A river tile's answer at p (found = 0 unless its nearest corner is water).
fn water_world_sample_tile(data: texture_2d<u32>, tile: u32, p: vec2<f32>) -> WaterQuery {
    var none = WaterQuery(0u, 0.0, 0u, 0u, 0.0, vec2<f32>(0.0));
    let n = water_world_word(data, WATER_H_TILE_TEXELS);
    let r = water_world_word(data, WATER_H_TILES) + tile * WATER_TILE_WORDS;
    let origin = vec2<f32>(water_world_f32(data, r), water_world_f32(data, r + 1u));
    let inv = water_world_f32(data, r + 2u);
    let base = water_world_word(data, r + 5u);
    let t = (p - origin) * inv;
    let nf = f32(n);
    if (!(t.x >= 0.0 && t.y >= 0.0 && t.x <= nf && t.y <= nf)) {
        return none;
    }
    let i = min(u32(floor(t.x)), n - 1u);
    let j = min(u32(floor(t.y)), n - 1u);
    let fx = t.x - f32(i);
    let fy = t.y - f32(j);
    let side = n + 1u;
    let near = base + ((j + select(0u, 1u, fy >= 0.5)) * side + i + select(0u, 1u, fx >= 0.5)) * WATER_TEXEL_WORDS;
    if (water_world_word(data, near) == WATER_TEXEL_NONE) {
        return none;
    }
    var sum_w = 0.0;
    var h = 0.0;
    var flow = vec2<f32>(0.0);
    var depth = 0.0;
    for (var k = 0u; k < 4u; k++) {
        let di = k & 1u;
        let dj = k >> 1u;
        let wx = select(1.0 - fx, fx, di == 1u);
        let wy = select(1.0 - fy, fy, dj == 1u);
        let wt = wx * wy;
        let a = base + ((j + dj) * side + i + di) * WATER_TEXEL_WORDS;
        let hw = water_world_word(data, a);
        if (hw != WATER_TEXEL_NONE) {
            sum_w += wt;
            h += wt * bitcast<f32>(hw);
            flow += water_unpack_half2(water_world_word(data, a + 1u)) * wt;
            depth += wt * water_unpack_half2(water_world_word(data, a + 2u)).x;
        }
    }
    let inv_w = 1.0 / sum_w;
    return WaterQuery(1u, h * inv_w, (WATER_BODY_RIVER << WATER_KIND_SHIFT) | water_world_word(data, r + 3u),
        water_world_word(data, r + 4u), depth * inv_w, flow * inv_w);
}

// The water surface at horizontal position p (metres): `WaterWorld::query`.
fn water_world_query(data: texture_2d<u32>, p: vec2<f32>) -> WaterQuery {
    var best = WaterQuery(0u, 0.0, 0u, 0u, 0.0, vec2<f32>(0.0));
    if (!(abs(p.x) <= 3.4028235e38 && abs(p.y) <= 3.4028235e38)) {
        return best;
    }
    let inf = bitcast<f32>(0x7f800000u);
    if ((water_world_word(data, WATER_H_FLAGS) & 1u) != 0u) {
        water_world_offer(&best, WaterQuery(1u, water_world_f32(data, WATER_H_OCEAN_LEVEL), WATER_BODY_OCEAN << WATER_KIND_SHIFT,
            water_world_word(data, WATER_H_OCEAN_MATERIAL), inf, vec2<f32>(0.0)));
    }
    let size = water_world_f32(data, WATER_H_ROOT_SIZE);
    var bx = water_world_f32(data, WATER_H_ROOT_X);
    var by = water_world_f32(data, WATER_H_ROOT_Y);
    if (!(size > 0.0 && p.x >= bx && p.y >= by && p.x < bx + size && p.y < by + size)) {
        return best;
    }
    let nodes = water_world_word(data, WATER_H_NODES);
    var bs = size;
    var node = 0u;
    for (var level = 0u; level <= WATER_MAX_QUADTREE_DEPTH; level++) {
        let a = water_world_word(data, nodes + 2u * node);
        let b = water_world_word(data, nodes + 2u * node + 1u);
        if (b == WATER_NODE_INTERNAL) {
            let half = bs * 0.5;
            let qx = p.x >= bx + half;
            let qy = p.y >= by + half;
            if (qx) {
                bx += half;
            }
            if (qy) {
                by += half;
            }
            bs = half;
            node = a + select(0u, 1u, qx) + select(0u, 2u, qy);
            continue;
        }
        let items = water_world_word(data, WATER_H_ITEMS);
        for (var k = 0u; k < b; k++) {
            let it = items + (a + k) * WATER_ITEM_WORDS;
            let head = water_world_word(data, it);
            let kind = head >> WATER_KIND_SHIFT;
            let index = head & ((1u << WATER_KIND_SHIFT) - 1u);
            if (kind == WATER_ITEM_LAKE_INSIDE || kind == WATER_ITEM_LAKE_PARTIAL) {
                var inside = true;
                if (kind == WATER_ITEM_LAKE_PARTIAL) {
                    let e0 = water_world_word(data, WATER_H_EDGES) + water_world_word(data, it + 1u);
                    let locals = water_world_word(data, it + 2u);
                    let far = water_world_word(data, it + 3u);
                    inside = (far >> 31u) != 0u;
                    let b0 = e0 + locals * 4u;
                    for (var q = 0u; q < (far & 0x7fffffffu); q++) {
                        if (water_world_f32(data, b0 + q) <= p.y) {
                            inside = !inside;
                        }
                    }
                    for (var e = 0u; e < locals; e++) {
                        let q = e0 + e * 4u;
                        if (water_world_crosses(water_world_f32(data, q), water_world_f32(data, q + 1u),
                            water_world_f32(data, q + 2u), water_world_f32(data, q + 3u), p)) {
                            inside = !inside;
                        }
                    }
                }
                if (inside) {
                    let l = water_world_word(data, WATER_H_LAKES) + index * 2u;
                    water_world_offer(&best, WaterQuery(1u, water_world_f32(data, l), (WATER_BODY_LAKE << WATER_KIND_SHIFT) | index,
                        water_world_word(data, l + 1u), inf, vec2<f32>(0.0)));
                }
            } else if (kind == WATER_ITEM_RIVER_TILE) {
                let c = water_world_sample_tile(data, index, p);
                if (c.found != 0u) {
                    water_world_offer(&best, c);
                }
            }
        }
        break;
    }
    return best;
}
