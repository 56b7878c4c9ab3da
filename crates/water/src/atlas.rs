//! The world flow map and its atlas of high-resolution tiles, in one self-contained
//! texture.
//!
//! Far Cry 5 bakes "a flow map texture atlas" in two variations: "a high resolution
//! texture, and one is a world flow map"; the high-resolution tiles near the player are
//! streamed in, the world map (8 m per texel) is baked once. "Based on a sector ID, we can
//! figure out a UV remap table, which is stored in the texture itself ... This is a
//! self-contained texture, so any feature that needs the flow map could actually read this
//! simply based on the world position" (seed 003).
//!
//! [`FlowAtlas`] is that texture: one `R32Uint` image holding a header, the sector table,
//! the world map and the tile slots. [`FlowAtlas::sample`] (and `water_flow_atlas_sample`
//! in [`wgsl::ATLAS`](crate::wgsl::ATLAS), the same arithmetic) reads flow at a world
//! position: the sector's tile if one is resident, else the world map.
//!
//! # Layout
//!
//! Texel `(x, y)` is word `y * width + x`.
//!
//! | where | what |
//! | --- | --- |
//! | words 0..24 | header: magic `FLOW`, version, width, height, origin `x, y` (f32), sector size (f32), sectors `x, y`, world texel (f32), world map width, height and top row, tile resolution, max speed (f32), table start, slots per row, slot rows, first slot row, slot count, 3 reserved |
//! | words 24.. | the sector table, `sectors_x * sectors_y` words, row-major: a tile slot index or `0xffffffff` (no tile: use the world map) |
//! | rows `world_top..` | the world map, `world_w x world_h` texels, texel `(i, j)` centred at `origin + (i + 0.5, j + 0.5) * world_texel` |
//! | rows `slot_top..` | tile slots of `(res + 2)^2` texels: a one-texel gutter around `res x res`; tile texel `(i, j)` (`i, j` in `-1..=res`) centred at `sector_min + (i + 0.5, j + 0.5) * sector_size / res`, so bilinear sampling never needs a neighbouring tile |
//!
//! A flow texel is `pack2x16snorm(flow / max_speed)`, flow in m/s along world +x and +y.

use alloc::vec;
use alloc::vec::Vec;
use core::ops::ControlFlow;

use glam::{UVec2, Vec2};

use crate::Error;
use crate::flowbake::FlowField;
use crate::math;
use crate::progress::{Progress, Stage, report};

/// `"FLOW"` as a little-endian word.
pub const ATLAS_MAGIC: u32 = u32::from_le_bytes(*b"FLOW");
/// Version of the layout.
pub const ATLAS_VERSION: u32 = 1;
/// Header words before the sector table.
pub const ATLAS_HEADER_WORDS: u32 = 24;
/// The talk's world map resolution, metres per texel.
pub const WORLD_MAP_TEXEL: f32 = 8.0;
/// A table entry meaning "no tile resident".
pub const SECTOR_NONE: u32 = u32::MAX;
/// Largest atlas side (the core wgpu 2D texture limit).
pub const MAX_ATLAS_SIZE: u32 = 8192;

/// Header word indices.
pub mod header {
    /// Magic.
    pub const MAGIC: usize = 0;
    /// Version.
    pub const VERSION: usize = 1;
    /// Texture width.
    pub const WIDTH: usize = 2;
    /// Texture height.
    pub const HEIGHT: usize = 3;
    /// World origin x (f32).
    pub const ORIGIN_X: usize = 4;
    /// World origin y (f32).
    pub const ORIGIN_Y: usize = 5;
    /// Sector size (f32).
    pub const SECTOR_SIZE: usize = 6;
    /// Sectors along x.
    pub const SECTORS_X: usize = 7;
    /// Sectors along y.
    pub const SECTORS_Y: usize = 8;
    /// World map texel size (f32).
    pub const WORLD_TEXEL: usize = 9;
    /// World map width.
    pub const WORLD_W: usize = 10;
    /// World map height.
    pub const WORLD_H: usize = 11;
    /// World map's first row.
    pub const WORLD_TOP: usize = 12;
    /// Tile resolution (texels per sector side, without the gutter).
    pub const TILE_RES: usize = 13;
    /// Max speed (f32): flow = unpack2x16snorm(texel) * max speed.
    pub const MAX_SPEED: usize = 14;
    /// First word of the sector table.
    pub const TABLE: usize = 15;
    /// Slots per slot row.
    pub const SLOTS_X: usize = 16;
    /// Slot rows.
    pub const SLOTS_Y: usize = 17;
    /// First texel row of the slots.
    pub const SLOT_TOP: usize = 18;
    /// Slots in use.
    pub const SLOTS_USED: usize = 19;
}

/// Atlas settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlowAtlasSettings {
    /// Sector side, metres.
    pub sector_size: f32,
    /// Tile texels per sector side.
    pub tile_res: u32,
    /// World map texel, metres (the talk: 8).
    pub world_texel: f32,
    /// Texture width in texels.
    pub width: u32,
    /// Flow speed encoded as full scale, m/s (faster flow is clamped).
    pub max_speed: f32,
    /// Tile slots to reserve (at least the tiles built; more leave room to stream).
    pub slots: u32,
}

impl Default for FlowAtlasSettings {
    /// 64 m sectors of 64 texels (1 m), the 8 m world map, 4096 wide, 16 m/s, 256 slots.
    fn default() -> Self {
        Self {
            sector_size: 64.0,
            tile_res: 64,
            world_texel: WORLD_MAP_TEXEL,
            width: 4096,
            max_speed: 16.0,
            slots: 256,
        }
    }
}

/// `pack2x16snorm`, as WGSL defines it.
#[must_use]
pub fn pack2x16snorm(v: Vec2) -> u32 {
    let e = |x: f32| {
        let c = if x.is_nan() { 0.0 } else { x.clamp(-1.0, 1.0) };
        (math::floor(c * 32767.0 + 0.5) as i32 as i16) as u16
    };
    u32::from(e(v.x)) | u32::from(e(v.y)) << 16
}

/// `unpack2x16snorm`, as WGSL defines it.
#[must_use]
pub fn unpack2x16snorm(w: u32) -> Vec2 {
    let d = |h: u16| (f32::from(h as i16) / 32767.0).max(-1.0);
    Vec2::new(d(w as u16), d((w >> 16) as u16))
}

/// The self-contained flow texture. See the module docs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FlowAtlas {
    texels: Vec<u32>,
}

fn bad(reason: &'static str) -> Error {
    Error::InvalidData {
        what: "flow atlas",
        reason,
    }
}

impl FlowAtlas {
    /// Builds the atlas over `field`'s extent: the world map from all of it, and a tile
    /// for every sector where `resident(sector)` says so (e.g. `|_| true`, or the sectors
    /// near the player). Fails with [`Error::AtlasFull`] if more tiles are wanted than
    /// `settings.slots`.
    pub fn build(
        field: &FlowField,
        settings: &FlowAtlasSettings,
        mut resident: impl FnMut(UVec2) -> bool,
        progress: &mut impl FnMut(Progress) -> ControlFlow<()>,
    ) -> Result<Self, Error> {
        let s = settings;
        for (field_name, v) in [
            ("sector size", s.sector_size),
            ("world texel", s.world_texel),
            ("max speed", s.max_speed),
        ] {
            if !(v > 0.0) || !v.is_finite() {
                return Err(Error::OutOfRange {
                    field: field_name,
                    value: v,
                    min: f32::MIN_POSITIVE,
                    max: f32::MAX,
                });
            }
        }
        if s.tile_res == 0 || s.tile_res + 2 > s.width || s.width > MAX_ATLAS_SIZE {
            return Err(Error::InvalidSize {
                field: "atlas width or tile resolution",
                value: s.tile_res,
                rule: "tile_res >= 1, tile_res + 2 <= width <= MAX_ATLAS_SIZE (8192)",
            });
        }
        let extent = Vec2::new(field.width() as f32, field.height() as f32) * field.texel_size();
        let sectors = (extent / s.sector_size).ceil().as_uvec2().max(UVec2::ONE);
        let world = (extent / s.world_texel).ceil().as_uvec2().max(UVec2::ONE);
        if world.x > s.width {
            return Err(Error::InvalidSize {
                field: "world map width (texels)",
                value: world.x,
                rule: "at most the atlas width",
            });
        }
        let table_words = u64::from(sectors.x) * u64::from(sectors.y);
        let w = s.width;
        let stride = s.tile_res + 2;
        let slots_x = w / stride;
        let slots_y = s.slots.div_ceil(slots_x);
        let header_rows = (u64::from(ATLAS_HEADER_WORDS) + table_words).div_ceil(u64::from(w));
        let height = header_rows + u64::from(world.y) + u64::from(slots_y) * u64::from(stride);
        if height > u64::from(MAX_ATLAS_SIZE) {
            return Err(Error::LimitExceeded {
                what: "flow atlas height (texels)",
                value: height,
                limit: u64::from(MAX_ATLAS_SIZE),
                limit_name: "MAX_ATLAS_SIZE",
            });
        }
        let height = height as u32;
        let mut t = vec![0u32; (w * height) as usize];
        let world_top = header_rows as u32;
        let slot_top = world_top + world.y;
        let hdr: [(usize, u32); 19] = [
            (header::MAGIC, ATLAS_MAGIC),
            (header::VERSION, ATLAS_VERSION),
            (header::WIDTH, w),
            (header::HEIGHT, height),
            (header::ORIGIN_X, field.origin().x.to_bits()),
            (header::ORIGIN_Y, field.origin().y.to_bits()),
            (header::SECTOR_SIZE, s.sector_size.to_bits()),
            (header::SECTORS_X, sectors.x),
            (header::SECTORS_Y, sectors.y),
            (header::WORLD_TEXEL, s.world_texel.to_bits()),
            (header::WORLD_W, world.x),
            (header::WORLD_H, world.y),
            (header::WORLD_TOP, world_top),
            (header::TILE_RES, s.tile_res),
            (header::MAX_SPEED, s.max_speed.to_bits()),
            (header::TABLE, ATLAS_HEADER_WORDS),
            (header::SLOTS_X, slots_x),
            (header::SLOTS_Y, slots_y),
            (header::SLOT_TOP, slot_top),
        ];
        for (i, v) in hdr {
            t[i] = v;
        }
        let table = ATLAS_HEADER_WORDS as usize;
        t[table..table + table_words as usize].fill(SECTOR_NONE);
        let mut atlas = FlowAtlas { texels: t };

        // The world map: the mean of the field's texels whose centres fall in each cell.
        let inv = 1.0 / s.max_speed;
        let (fw, fh) = (field.width() as usize, field.height() as usize);
        let mut sum = vec![Vec2::ZERO; (world.x * world.y) as usize];
        let mut count = vec![0u32; sum.len()];
        for y in 0..fh {
            for x in 0..fw {
                let c = (Vec2::new(x as f32, y as f32) + 0.5) * field.texel_size() / s.world_texel;
                let (cx, cy) = ((c.x as u32).min(world.x - 1), (c.y as u32).min(world.y - 1));
                let k = (cy * world.x + cx) as usize;
                sum[k] += field.flow()[y * fw + x];
                count[k] += 1;
            }
        }
        for j in 0..world.y {
            for i in 0..world.x {
                let k = (j * world.x + i) as usize;
                let v = if count[k] > 0 {
                    sum[k] / count[k] as f32
                } else {
                    Vec2::ZERO
                };
                atlas.texels[((world_top + j) * w + i) as usize] = pack2x16snorm(v * inv);
            }
        }
        report(progress, Stage::AtlasWorldMap, 1, 1)?;

        let total = u64::from(sectors.x) * u64::from(sectors.y);
        for sy in 0..sectors.y {
            for sx in 0..sectors.x {
                let sector = UVec2::new(sx, sy);
                if resident(sector) {
                    let tile = Self::tile_texels(field, settings, sector);
                    atlas.insert(sector, &tile)?;
                }
            }
            report(
                progress,
                Stage::AtlasTiles,
                u64::from(sy + 1) * u64::from(sectors.x),
                total,
            )?;
        }
        Ok(atlas)
    }

    /// The `(res + 2)^2` texels of `sector`'s tile sampled from `field` (gutter included),
    /// ready for [`FlowAtlas::insert`]: what a streamer loads.
    #[must_use]
    pub fn tile_texels(field: &FlowField, settings: &FlowAtlasSettings, sector: UVec2) -> Vec<u32> {
        let res = settings.tile_res;
        let side = res as usize + 2;
        let step = settings.sector_size / res as f32;
        let min = field.origin() + sector.as_vec2() * settings.sector_size;
        let inv = 1.0 / settings.max_speed;
        let mut out = Vec::with_capacity(side * side);
        for j in -1..=res as i32 {
            for i in -1..=res as i32 {
                let p = min + (Vec2::new(i as f32, j as f32) + 0.5) * step;
                out.push(pack2x16snorm(field.sample(p) * inv));
            }
        }
        out
    }

    /// Wraps texels loaded from disk, checking that every offset stays in bounds (so
    /// [`FlowAtlas::sample`] never panics on an accepted atlas).
    pub fn from_texels(texels: Vec<u32>) -> Result<Self, Error> {
        let t = &texels;
        if t.len() < ATLAS_HEADER_WORDS as usize {
            return Err(bad("shorter than the header"));
        }
        if t[header::MAGIC] != ATLAS_MAGIC || t[header::VERSION] != ATLAS_VERSION {
            return Err(bad("bad magic or version"));
        }
        let (w, h) = (u64::from(t[header::WIDTH]), u64::from(t[header::HEIGHT]));
        if w == 0
            || w > u64::from(MAX_ATLAS_SIZE)
            || h > u64::from(MAX_ATLAS_SIZE)
            || w * h != t.len() as u64
        {
            return Err(bad("width x height does not match the texel count"));
        }
        let table_end = u64::from(t[header::TABLE])
            + u64::from(t[header::SECTORS_X]) * u64::from(t[header::SECTORS_Y]);
        if t[header::TABLE] < ATLAS_HEADER_WORDS || table_end > t.len() as u64 {
            return Err(bad("the sector table runs past the end"));
        }
        let (ww, wh, top) = (
            u64::from(t[header::WORLD_W]),
            u64::from(t[header::WORLD_H]),
            u64::from(t[header::WORLD_TOP]),
        );
        if ww == 0 || wh == 0 || ww > w || top + wh > h || top * w < table_end {
            return Err(bad("the world map is empty or outside the texture"));
        }
        let res = u64::from(t[header::TILE_RES]);
        let stride = res + 2;
        let (sx, sy, stop) = (
            u64::from(t[header::SLOTS_X]),
            u64::from(t[header::SLOTS_Y]),
            u64::from(t[header::SLOT_TOP]),
        );
        // Saturating: the fields are arbitrary u32s and their product passes u64.
        if res == 0
            || sx.saturating_mul(stride) > w
            || stop.saturating_add(sy.saturating_mul(stride)) > h
            || stop < top + wh
        {
            return Err(bad("the tile slots are outside the texture"));
        }
        for &e in &t[t[header::TABLE] as usize..table_end as usize] {
            if e != SECTOR_NONE && u64::from(e) >= sx * sy {
                return Err(bad("a table entry names a slot that does not exist"));
            }
        }
        for k in [
            header::ORIGIN_X,
            header::ORIGIN_Y,
            header::SECTOR_SIZE,
            header::WORLD_TEXEL,
            header::MAX_SPEED,
        ] {
            let v = f32::from_bits(t[k]);
            if !v.is_finite() || (k != header::ORIGIN_X && k != header::ORIGIN_Y && !(v > 0.0)) {
                return Err(bad("a header float is not finite (or not positive)"));
            }
        }
        Ok(Self { texels })
    }

    /// The texels (upload as an `R32Uint` texture of [`FlowAtlas::width`] x
    /// [`FlowAtlas::height`]).
    #[must_use]
    pub fn texels(&self) -> &[u32] {
        &self.texels
    }
    /// Texture width.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.texels[header::WIDTH]
    }
    /// Texture height.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.texels[header::HEIGHT]
    }
    /// Sectors along x and y.
    #[must_use]
    pub fn sectors(&self) -> UVec2 {
        UVec2::new(
            self.texels[header::SECTORS_X],
            self.texels[header::SECTORS_Y],
        )
    }
    /// Slots in the atlas.
    #[must_use]
    pub fn slot_capacity(&self) -> u32 {
        self.texels[header::SLOTS_X] * self.texels[header::SLOTS_Y]
    }

    fn f(&self, i: usize) -> f32 {
        f32::from_bits(self.texels[i])
    }

    /// The sector holding world position `p`, if inside the atlas.
    #[must_use]
    pub fn sector_of(&self, p: Vec2) -> Option<UVec2> {
        let origin = Vec2::new(self.f(header::ORIGIN_X), self.f(header::ORIGIN_Y));
        let rel = (p - origin) / self.f(header::SECTOR_SIZE);
        let n = self.sectors();
        if !(rel.x >= 0.0 && rel.y >= 0.0 && rel.x < n.x as f32 && rel.y < n.y as f32) {
            return None;
        }
        Some(UVec2::new(
            (rel.x as u32).min(n.x - 1),
            (rel.y as u32).min(n.y - 1),
        ))
    }

    fn table_index(&self, sector: UVec2) -> Option<usize> {
        let n = self.sectors();
        (sector.x < n.x && sector.y < n.y)
            .then(|| self.texels[header::TABLE] as usize + (sector.y * n.x + sector.x) as usize)
    }

    /// The slot holding `sector`'s tile, if resident.
    #[must_use]
    pub fn tile_slot(&self, sector: UVec2) -> Option<u32> {
        let e = self.texels[self.table_index(sector)?];
        (e != SECTOR_NONE).then_some(e)
    }

    fn slot_origin(&self, slot: u32) -> UVec2 {
        let stride = self.texels[header::TILE_RES] + 2;
        let sx = self.texels[header::SLOTS_X];
        UVec2::new(
            (slot % sx) * stride,
            self.texels[header::SLOT_TOP] + (slot / sx) * stride,
        )
    }

    /// Makes `sector`'s tile resident from `tile` (as [`FlowAtlas::tile_texels`] makes
    /// it), in the first free slot, and returns the slot. Replaces the sector's tile if it
    /// already has one.
    pub fn insert(&mut self, sector: UVec2, tile: &[u32]) -> Result<u32, Error> {
        let Some(ti) = self.table_index(sector) else {
            return Err(Error::InvalidSize {
                field: "sector",
                value: sector.x.max(sector.y),
                rule: "inside the atlas's sectors",
            });
        };
        let res = self.texels[header::TILE_RES];
        let side = (res + 2) as usize;
        if tile.len() != side * side {
            return Err(Error::LengthMismatch {
                field: "tile texels",
                len: tile.len(),
                expected: side * side,
            });
        }
        let slot = match self.tile_slot(sector) {
            Some(s) => s,
            None => {
                let capacity = self.slot_capacity();
                let n = self.sectors();
                let table = self.texels[header::TABLE] as usize;
                let used = &self.texels[table..table + (n.x * n.y) as usize];
                let mut taken = vec![false; capacity as usize];
                for &e in used {
                    if e != SECTOR_NONE {
                        taken[e as usize] = true;
                    }
                }
                let Some(free) = taken.iter().position(|&t| !t) else {
                    return Err(Error::AtlasFull { capacity });
                };
                free as u32
            }
        };
        let o = self.slot_origin(slot);
        let w = self.width() as usize;
        for j in 0..side {
            let row = (o.y as usize + j) * w + o.x as usize;
            self.texels[row..row + side].copy_from_slice(&tile[j * side..(j + 1) * side]);
        }
        self.texels[ti] = slot;
        self.texels[header::SLOTS_USED] = self.resident_count();
        Ok(slot)
    }

    /// Drops `sector`'s tile (the world map answers there again). Returns whether it had
    /// one.
    pub fn evict(&mut self, sector: UVec2) -> bool {
        let Some(ti) = self.table_index(sector) else {
            return false;
        };
        let had = self.texels[ti] != SECTOR_NONE;
        self.texels[ti] = SECTOR_NONE;
        self.texels[header::SLOTS_USED] = self.resident_count();
        had
    }

    /// Tiles resident.
    #[must_use]
    pub fn resident_count(&self) -> u32 {
        let n = self.sectors();
        let table = self.texels[header::TABLE] as usize;
        self.texels[table..table + (n.x * n.y) as usize]
            .iter()
            .filter(|&&e| e != SECTOR_NONE)
            .count() as u32
    }

    fn texel(&self, x: u32, y: u32) -> Vec2 {
        unpack2x16snorm(self.texels[(y * self.width() + x) as usize])
    }

    /// Flow (m/s) at world position `p`: bilinear in the sector's tile if resident, else in
    /// the world map (clamped at its edges). `None` outside the atlas's sectors or for a
    /// non-finite position.
    #[must_use]
    pub fn sample(&self, p: Vec2) -> Option<Vec2> {
        let sector = self.sector_of(p)?;
        let max_speed = self.f(header::MAX_SPEED);
        let origin = Vec2::new(self.f(header::ORIGIN_X), self.f(header::ORIGIN_Y));
        if let Some(slot) = self.tile_slot(sector) {
            let res = self.texels[header::TILE_RES] as f32;
            let rel = (p - origin) / self.f(header::SECTOR_SIZE) - sector.as_vec2();
            // In [-0.5, res - 0.5]; texel -1 is the gutter.
            let l = rel * res - 0.5;
            let fl = Vec2::new(math::floor(l.x), math::floor(l.y))
                .clamp(Vec2::splat(-1.0), Vec2::splat(res - 1.0));
            let f = (l - fl).clamp(Vec2::ZERO, Vec2::ONE);
            let o = self.slot_origin(slot);
            let (x, y) = (o.x + (fl.x + 1.0) as u32, o.y + (fl.y + 1.0) as u32);
            let a = math::mix2(self.texel(x, y), self.texel(x + 1, y), f.x);
            let b = math::mix2(self.texel(x, y + 1), self.texel(x + 1, y + 1), f.x);
            return Some(math::mix2(a, b, f.y) * max_speed);
        }
        let (ww, wh) = (self.texels[header::WORLD_W], self.texels[header::WORLD_H]);
        let top = self.texels[header::WORLD_TOP];
        let u = (p - origin) / self.f(header::WORLD_TEXEL) - 0.5;
        let max = Vec2::new((ww - 1) as f32, (wh - 1) as f32);
        let u = u.clamp(Vec2::ZERO, max);
        let fl = Vec2::new(math::floor(u.x), math::floor(u.y));
        let f = u - fl;
        let (x0, y0) = (fl.x as u32, fl.y as u32);
        let (x1, y1) = ((x0 + 1).min(ww - 1), (y0 + 1).min(wh - 1));
        let a = math::mix2(self.texel(x0, top + y0), self.texel(x1, top + y0), f.x);
        let b = math::mix2(self.texel(x0, top + y1), self.texel(x1, top + y1), f.x);
        Some(math::mix2(a, b, f.y) * max_speed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn snorm_matches_the_wgsl_definition() {
        assert_eq!(pack2x16snorm(Vec2::new(1.0, -1.0)), 0x8001_7fff);
        assert_eq!(unpack2x16snorm(0x8000_0000), Vec2::new(0.0, -1.0));
        assert_eq!(pack2x16snorm(Vec2::NAN), 0);
        for v in [-0.7f32, -0.1, 0.0, 0.3, 0.999] {
            let r = unpack2x16snorm(pack2x16snorm(Vec2::splat(v)));
            assert!((r.x - v).abs() <= 0.5 / 32767.0 + 1e-7);
        }
    }
}
