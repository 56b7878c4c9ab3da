// water: flow from the self-contained flow atlas (`FlowAtlas::texels()` uploaded as an
// R32Uint texture). Twin of `water::atlas`; the layout table is in its docs.

const WATER_ATLAS_MAGIC: u32 = 1464814662u;
const WATER_SECTOR_NONE: u32 = 4294967295u;
const WATER_A_ORIGIN_X: u32 = 4u;
const WATER_A_ORIGIN_Y: u32 = 5u;
const WATER_A_SECTOR_SIZE: u32 = 6u;
const WATER_A_SECTORS_X: u32 = 7u;
const WATER_A_SECTORS_Y: u32 = 8u;
const WATER_A_WORLD_TEXEL: u32 = 9u;
const WATER_A_WORLD_W: u32 = 10u;
const WATER_A_WORLD_H: u32 = 11u;
const WATER_A_WORLD_TOP: u32 = 12u;
const WATER_A_TILE_RES: u32 = 13u;
const WATER_A_MAX_SPEED: u32 = 14u;
const WATER_A_TABLE: u32 = 15u;
const WATER_A_SLOTS_X: u32 = 16u;
const WATER_A_SLOT_TOP: u32 = 18u;

fn water_atlas_word(atlas: texture_2d<u32>, i: u32) -> u32 {
    let w = textureDimensions(atlas).x;
    return textureLoad(atlas, vec2<u32>(i % w, i / w), 0).r;
}

fn water_atlas_f32(atlas: texture_2d<u32>, i: u32) -> f32 {
    return bitcast<f32>(water_atlas_word(atlas, i));
}

fn water_atlas_texel(atlas: texture_2d<u32>, x: u32, y: u32) -> vec2<f32> {
    return unpack2x16snorm(textureLoad(atlas, vec2<u32>(x, y), 0).r);
}

// Flow (m/s) at world position p in .xy, and 1.0 in .z where p is inside the atlas
// (0 outside or for non-finite p): `FlowAtlas::sample`.
fn water_flow_atlas_sample(atlas: texture_2d<u32>, p: vec2<f32>) -> vec3<f32> {
    let origin = vec2<f32>(water_atlas_f32(atlas, WATER_A_ORIGIN_X), water_atlas_f32(atlas, WATER_A_ORIGIN_Y));
    let ns = vec2<u32>(water_atlas_word(atlas, WATER_A_SECTORS_X), water_atlas_word(atlas, WATER_A_SECTORS_Y));
    let rel = (p - origin) / water_atlas_f32(atlas, WATER_A_SECTOR_SIZE);
    if (!(rel.x >= 0.0 && rel.y >= 0.0 && rel.x < f32(ns.x) && rel.y < f32(ns.y))) {
        return vec3<f32>(0.0);
    }
    let sector = min(vec2<u32>(rel), ns - vec2<u32>(1u));
    let max_speed = water_atlas_f32(atlas, WATER_A_MAX_SPEED);
    let entry = water_atlas_word(atlas, water_atlas_word(atlas, WATER_A_TABLE) + sector.y * ns.x + sector.x);
    if (entry != WATER_SECTOR_NONE) {
        let res_u = water_atlas_word(atlas, WATER_A_TILE_RES);
        let res = f32(res_u);
        let stride = res_u + 2u;
        let sx = water_atlas_word(atlas, WATER_A_SLOTS_X);
        let o = vec2<u32>((entry % sx) * stride, water_atlas_word(atlas, WATER_A_SLOT_TOP) + (entry / sx) * stride);
        let l = (rel - vec2<f32>(sector)) * res - 0.5;
        let fl = clamp(floor(l), vec2<f32>(-1.0), vec2<f32>(res - 1.0));
        let f = clamp(l - fl, vec2<f32>(0.0), vec2<f32>(1.0));
        let x = o.x + u32(fl.x + 1.0);
        let y = o.y + u32(fl.y + 1.0);
        let a = water_atlas_texel(atlas, x, y) + (water_atlas_texel(atlas, x + 1u, y) - water_atlas_texel(atlas, x, y)) * f.x;
        let b = water_atlas_texel(atlas, x, y + 1u) + (water_atlas_texel(atlas, x + 1u, y + 1u) - water_atlas_texel(atlas, x, y + 1u)) * f.x;
        return vec3<f32>((a + (b - a) * f.y) * max_speed, 1.0);
    }
    let ww = water_atlas_word(atlas, WATER_A_WORLD_W);
    let wh = water_atlas_word(atlas, WATER_A_WORLD_H);
    let top = water_atlas_word(atlas, WATER_A_WORLD_TOP);
    let u = clamp((p - origin) / water_atlas_f32(atlas, WATER_A_WORLD_TEXEL) - 0.5, vec2<f32>(0.0), vec2<f32>(f32(ww - 1u), f32(wh - 1u)));
    let fl = floor(u);
    let f = u - fl;
    let x0 = u32(fl.x);
    let y0 = u32(fl.y);
    let x1 = min(x0 + 1u, ww - 1u);
    let y1 = min(y0 + 1u, wh - 1u);
    let a = water_atlas_texel(atlas, x0, top + y0) + (water_atlas_texel(atlas, x1, top + y0) - water_atlas_texel(atlas, x0, top + y0)) * f.x;
    let b = water_atlas_texel(atlas, x0, top + y1) + (water_atlas_texel(atlas, x1, top + y1) - water_atlas_texel(atlas, x0, top + y1)) * f.x;
    return vec3<f32>((a + (b - a) * f.y) * max_speed, 1.0);
}
