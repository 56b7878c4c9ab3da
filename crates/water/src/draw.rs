//! What a renderer draws a baked [`WaterWorld`] from, built on the CPU so that the GPU
//! draws exactly what [`WaterWorld::query`] answers: the near bodies' low-resolution
//! meshes ([`near_meshes`]), the far sectors' quadtree ([`sector_tree`]) and the material
//! map ([`material_map`]), all in the renderer's +Y-up world ([`crate::axes`]).
//!
//! Every size has a named limit here (the `scene` and `gpu` crates re-export them); a world
//! over one is an [`Error::LimitExceeded`] naming it, never a panic.

use alloc::vec;
use alloc::vec::Vec;

use glam::{Vec2, Vec3};

use crate::Error;
use crate::axes::y_up_from_z_up;
use crate::math;
use crate::world::{BodyBounds, BodyId, WaterWorld};

/// Most water materials (the data word's 11-bit material field, less the value the
/// material map uses for "no water").
pub const MAX_WATER_MATERIALS: u32 = crate::gbuffer::MAX_MATERIALS - 1;
/// Most lakes and rivers drawn per body (the talk's heaviest scenes had 600 water bodies).
pub const MAX_WATER_BODIES: u32 = 1024;
/// Most far sectors per side of the world: Far Cry's "64 by 64 sectors in the world".
pub const MAX_WATER_SECTORS_PER_SIDE: u32 = 64;
/// Most vertices of all near bodies' meshes together.
pub const MAX_WATER_MESH_VERTICES: u32 = 1 << 22;
/// Most cells of one body's near mesh grid (its cell grows to stay under this).
pub const MAX_WATER_BODY_CELLS: u32 = 256 * 256;
/// Largest material map side, texels (the map's texel grows to stay under this).
pub const MAX_WATER_MATERIAL_MAP: u32 = 2048;
/// The material map's "no water" material.
pub const WATER_NO_MATERIAL: u32 = MAX_WATER_MATERIALS;

/// The near bodies' meshes and records, in the renderer's +Y-up world.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NearMeshes {
    /// Per vertex: position (xyz), body word (as f32 bits), normal (xyz), material (as f32
    /// bits).
    pub vertices: Vec<[f32; 8]>,
    /// Triangles, counter-clockwise seen from above, each body's a contiguous run.
    pub indices: Vec<u32>,
    /// Per body: world box min, max (+Y up), first index, index count, body word, material.
    pub bodies: Vec<(Vec3, Vec3, u32, u32, u32, u32)>,
}

/// The far sectors' quadtree, level-major (level 0 the root), each node a world box and
/// flags.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SectorTree {
    /// Per node: min (xyz, flags in w as bits), max (xyz, flat height in w).
    pub nodes: Vec<[f32; 8]>,
    /// Sectors per side of the leaf level (a power of two).
    pub sectors_per_side: u32,
    /// Levels, the root's included.
    pub levels: u32,
    /// World (x, z) of the grid's min corner, +Y up.
    pub origin: Vec2,
    /// Side of a sector, metres.
    pub sector_size: f32,
    /// Leaves holding water.
    pub water_sectors: u32,
}

/// The material map: per texel own material, the other material within half the blend
/// distance and the distance to their boundary (see [`material_map`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MaterialMap {
    /// Row-major texels, `own | other << 11 | distance << 22`.
    pub words: Vec<u32>,
    /// Texels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// Texel (0, 0)'s corner, water coordinates.
    pub origin: Vec2,
    /// Texel side, metres.
    pub texel: f32,
}

/// Node flag: the node holds water (WGSL `GPU_WATER_NODE_WATER`).
pub const NODE_WATER: u32 = 1;
/// Node flag: the node holds the ocean (WGSL `GPU_WATER_NODE_OCEAN`).
pub const NODE_OCEAN: u32 = 2;
/// Leaf flag: one body at one height (WGSL `GPU_WATER_NODE_FLAT`).
pub const NODE_FLAT: u32 = 4;
/// Leaf flag: the ocean alone, its material in the flags (WGSL `GPU_WATER_NODE_PURE`).
pub const NODE_PURE: u32 = 8;
/// A leaf's flags hold the ocean's material from this bit (WGSL
/// `GPU_WATER_NODE_MATERIAL_SHIFT`).
pub const NODE_MATERIAL_SHIFT: u32 = 8;

/// The limit error for `what`.
fn limit(what: &'static str, value: u64, limit: u64, limit_name: &'static str) -> Error {
    Error::LimitExceeded {
        what,
        value,
        limit,
        limit_name,
    }
}

/// The water (+Z up) point `(x, y)` at height `h` in the renderer's +Y up.
fn y_up(p: Vec2, h: f32) -> Vec3 {
    y_up_from_z_up(p.extend(h))
}

/// Builds every lake's and river's low-resolution mesh: a grid over the body's bounds
/// (`cell` metres, grown to stay under [`MAX_WATER_BODY_CELLS`]) keeping the cells where
/// the body has water (at the corners or the centre, whichever body's surface is highest
/// there: `WaterWorld::candidates`) and their neighbours, each
/// vertex at the body's surface there (the nearest found height where the body is not),
/// normals from the heights; triangles counter-clockwise seen from above.
pub fn near_meshes(
    world: &WaterWorld,
    bodies: &[BodyBounds],
    cell: f32,
) -> Result<NearMeshes, Error> {
    if bodies.len() as u64 > u64::from(MAX_WATER_BODIES) {
        return Err(limit(
            "lakes and rivers",
            bodies.len() as u64,
            u64::from(MAX_WATER_BODIES),
            "MAX_WATER_BODIES",
        ));
    }
    let mut out = NearMeshes::default();
    for b in bodies {
        let extent = (b.max - b.min).max(Vec2::splat(1e-3));
        let mut c = cell;
        while math::ceil(extent.x / c) * math::ceil(extent.y / c) > MAX_WATER_BODY_CELLS as f32 {
            c *= 1.5;
        }
        let nx = (math::ceil(extent.x / c) as u32).max(1);
        let ny = (math::ceil(extent.y / c) as u32).max(1);
        let at = |i: u32, j: u32| b.min + Vec2::new(i as f32, j as f32) * c;
        // The body's own water, whether or not another body's surface is higher there:
        // wherever the body wins the query, its mesh must be drawn.
        let own = |p: Vec2| {
            world
                .candidates(p)
                .into_iter()
                .find(|q| q.body == b.body)
                .map(|q| q.height)
        };
        // Heights at the grid's vertices where the body is.
        let (vw, vh) = (nx + 1, ny + 1);
        let mut heights: Vec<Option<f32>> = Vec::with_capacity((vw * vh) as usize);
        for j in 0..vh {
            for i in 0..vw {
                heights.push(own(at(i, j)));
            }
        }
        let mut keep = vec![false; (nx * ny) as usize];
        for j in 0..ny {
            for i in 0..nx {
                let corner = |di: u32, dj: u32| heights[((j + dj) * vw + i + di) as usize];
                keep[(j * nx + i) as usize] = corner(0, 0).is_some()
                    || corner(1, 0).is_some()
                    || corner(0, 1).is_some()
                    || corner(1, 1).is_some()
                    || own(at(i, j) + Vec2::splat(c * 0.5)).is_some();
            }
        }
        // One cell of dilation: the shore lies within half a world texel of a water corner.
        let mut grown = keep.clone();
        for j in 0..ny as i64 {
            for i in 0..nx as i64 {
                if !keep[(j * nx as i64 + i) as usize] {
                    continue;
                }
                for dj in -1..=1 {
                    for di in -1..=1 {
                        let (x, y) = (i + di, j + dj);
                        if x >= 0 && y >= 0 && x < nx as i64 && y < ny as i64 {
                            grown[(y * nx as i64 + x) as usize] = true;
                        }
                    }
                }
            }
        }
        // Fill the heights of vertices off the body from the nearest found ones.
        let fallback = b.height.0;
        let mut filled: Vec<f32> = heights.iter().map(|h| h.unwrap_or(f32::NAN)).collect();
        for _ in 0..4 {
            let prev = filled.clone();
            for j in 0..vh as i64 {
                for i in 0..vw as i64 {
                    let k = (j * vw as i64 + i) as usize;
                    if !prev[k].is_nan() {
                        continue;
                    }
                    let (mut sum, mut n) = (0.0, 0);
                    for (di, dj) in [
                        (-1, 0),
                        (1, 0),
                        (0, -1),
                        (0, 1),
                        (-1, -1),
                        (1, 1),
                        (-1, 1),
                        (1, -1),
                    ] {
                        let (x, y) = (i + di, j + dj);
                        if x >= 0 && y >= 0 && x < vw as i64 && y < vh as i64 {
                            let h = prev[(y * vw as i64 + x) as usize];
                            if !h.is_nan() {
                                sum += h;
                                n += 1;
                            }
                        }
                    }
                    if n > 0 {
                        filled[k] = sum / n as f32;
                    }
                }
            }
        }
        for h in &mut filled {
            if h.is_nan() {
                *h = fallback;
            }
        }
        let first_index = out.indices.len() as u32;
        let mut index_of = vec![u32::MAX; (vw * vh) as usize];
        let material = b.material;
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        let mut vertex = |out: &mut NearMeshes, i: u32, j: u32| -> Result<u32, Error> {
            let k = (j * vw + i) as usize;
            if index_of[k] != u32::MAX {
                return Ok(index_of[k]);
            }
            if out.vertices.len() as u64 >= u64::from(MAX_WATER_MESH_VERTICES) {
                return Err(limit(
                    "near water mesh vertices",
                    out.vertices.len() as u64 + 1,
                    u64::from(MAX_WATER_MESH_VERTICES),
                    "MAX_WATER_MESH_VERTICES",
                ));
            }
            let h = |i: i64, j: i64| {
                filled[(j.clamp(0, vh as i64 - 1) * vw as i64 + i.clamp(0, vw as i64 - 1)) as usize]
            };
            let (ii, jj) = (i64::from(i), i64::from(j));
            let hx = (h(ii + 1, jj) - h(ii - 1, jj)) / (2.0 * c);
            let hy = (h(ii, jj + 1) - h(ii, jj - 1)) / (2.0 * c);
            // The water normal (-hx, -hy, 1) in +Y up.
            let n = Vec3::new(-hx, 1.0, hy).normalize_or(Vec3::Y);
            let p = y_up(at(i, j), filled[k]);
            lo = lo.min(p);
            hi = hi.max(p);
            let index = out.vertices.len() as u32;
            out.vertices.push([
                p.x,
                p.y,
                p.z,
                f32::from_bits(b.body.0),
                n.x,
                n.y,
                n.z,
                f32::from_bits(material),
            ]);
            index_of[k] = index;
            Ok(index)
        };
        for j in 0..ny {
            for i in 0..nx {
                if !grown[(j * nx + i) as usize] {
                    continue;
                }
                let a = vertex(&mut out, i, j)?;
                let bx = vertex(&mut out, i + 1, j)?;
                let cc = vertex(&mut out, i + 1, j + 1)?;
                let d = vertex(&mut out, i, j + 1)?;
                // Counter-clockwise seen from above in +Y up (the test checks it).
                out.indices.extend_from_slice(&[a, bx, cc, a, cc, d]);
            }
        }
        let count = out.indices.len() as u32 - first_index;
        // The surface between the vertices reaches the body's whole height range.
        lo.y = lo.y.min(b.height.0);
        hi.y = hi.y.max(b.height.1);
        if count > 0 {
            out.bodies
                .push((lo, hi, first_index, count, b.body.0, material));
        }
    }
    Ok(out)
}

/// Builds the far sectors' quadtree: a square of `sectors^2` sectors (a power of two per
/// side, at most [`MAX_WATER_SECTORS_PER_SIDE`]) over the ocean extent around the world's
/// centre (or, without an ocean, over the bodies), each leaf sampled on a 9 x 9 grid of
/// water queries (water, ocean, heights, flat), the nodes above their children's union.
pub fn sector_tree(
    world: &WaterWorld,
    bodies: &[BodyBounds],
    sector_size: f32,
    ocean_extent: f32,
) -> Result<SectorTree, Error> {
    let (mut lo, mut hi) = (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY));
    for b in bodies {
        lo = lo.min(b.min);
        hi = hi.max(b.max);
    }
    let ocean = world.ocean();
    let (centre, side) = if ocean.is_some() {
        let c = if lo.x <= hi.x {
            (lo + hi) * 0.5
        } else {
            Vec2::ZERO
        };
        (c, ocean_extent.max((hi - lo).max_element()))
    } else if lo.x <= hi.x {
        ((lo + hi) * 0.5, (hi - lo).max_element().max(sector_size))
    } else {
        return Ok(SectorTree::default());
    };
    let needed = math::ceil(side / sector_size).max(1.0);
    if needed > MAX_WATER_SECTORS_PER_SIDE as f32 {
        return Err(limit(
            "far water sectors per side",
            needed as u64,
            u64::from(MAX_WATER_SECTORS_PER_SIDE),
            "MAX_WATER_SECTORS_PER_SIDE",
        ));
    }
    let sectors = (needed as u32).next_power_of_two();
    let levels = sectors.trailing_zeros() + 1;
    let size = sector_size;
    let span = size * sectors as f32;
    // Water (x, y) of the grid's min corner; sector (i, j) covers
    // [x0 + i size, x0 + (i + 1) size] x [y0 + j size, ...].
    let w0 = centre - Vec2::splat(span * 0.5);
    let mut leaves = vec![[0.0f32; 8]; (sectors * sectors) as usize];
    let samples = 8u32;
    let mut water_sectors = 0;
    for j in 0..sectors {
        for i in 0..sectors {
            let s0 = w0 + Vec2::new(i as f32, j as f32) * size;
            let (mut hmin, mut hmax) = (f32::INFINITY, f32::NEG_INFINITY);
            let (mut found, mut has_ocean, mut bodies_seen) = (false, false, 0u32);
            let mut first = None;
            for v in 0..=samples {
                for u in 0..=samples {
                    let p = s0 + Vec2::new(u as f32, v as f32) * (size / samples as f32);
                    if let Some(q) = world.query(p) {
                        found = true;
                        has_ocean |= q.body == BodyId::OCEAN;
                        hmin = hmin.min(q.height);
                        hmax = hmax.max(q.height);
                        if first != Some(q.body) {
                            bodies_seen += 1;
                            first = Some(q.body);
                        }
                    }
                }
            }
            // Bodies narrower than the sampling still count through their bounds.
            for b in bodies {
                let (bmin, bmax) = (b.min, b.max);
                if bmin.x <= s0.x + size
                    && bmax.x >= s0.x
                    && bmin.y <= s0.y + size
                    && bmax.y >= s0.y
                {
                    found = true;
                    hmin = hmin.min(b.height.0);
                    hmax = hmax.max(b.height.1);
                    bodies_seen += 2;
                }
            }
            let mut flags = 0;
            if found {
                flags |= NODE_WATER;
                water_sectors += 1;
            }
            if has_ocean {
                flags |= NODE_OCEAN;
            }
            if found && hmin == hmax && bodies_seen <= 1 {
                flags |= NODE_FLAT;
                // Ocean alone: every fragment is the ocean's (its material in the flags).
                if let (true, Some(o)) = (has_ocean, ocean) {
                    flags |=
                        NODE_PURE | o.material.min(WATER_NO_MATERIAL - 1) << NODE_MATERIAL_SHIFT;
                }
            }
            if !found {
                hmin = 0.0;
                hmax = 0.0;
            }
            let a = y_up(s0, hmin);
            let b = y_up(s0 + Vec2::splat(size), hmax);
            leaves[(j * sectors + i) as usize] = [
                a.x.min(b.x),
                hmin,
                a.z.min(b.z),
                f32::from_bits(flags),
                a.x.max(b.x),
                hmax,
                a.z.max(b.z),
                hmin,
            ];
        }
    }
    // Levels, root first: level l has 4^l nodes, node (i, j) at offset + j 2^l + i.
    let mut levels_data: Vec<Vec<[f32; 8]>> = vec![leaves];
    let mut s = sectors;
    while s > 1 {
        let child = levels_data.last().expect("a level");
        let half = s / 2;
        let mut up = vec![[0.0f32; 8]; (half * half) as usize];
        for j in 0..half {
            for i in 0..half {
                let mut n = [
                    f32::INFINITY,
                    f32::INFINITY,
                    f32::INFINITY,
                    f32::from_bits(0),
                    f32::NEG_INFINITY,
                    f32::NEG_INFINITY,
                    f32::NEG_INFINITY,
                    0.0,
                ];
                let mut flags = 0;
                for (di, dj) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let c = child[((2 * j + dj) * s + 2 * i + di) as usize];
                    for k in 0..3 {
                        n[k] = n[k].min(c[k]);
                        n[4 + k] = n[4 + k].max(c[4 + k]);
                    }
                    flags |= c[3].to_bits() & (NODE_WATER | NODE_OCEAN);
                }
                n[3] = f32::from_bits(flags);
                n[7] = n[1];
                up[(j * half + i) as usize] = n;
            }
        }
        levels_data.push(up);
        s = half;
    }
    let nodes = levels_data.into_iter().rev().flatten().collect();
    let origin = {
        let a = y_up(w0, 0.0);
        let b = y_up(w0 + Vec2::splat(span), 0.0);
        Vec2::new(a.x.min(b.x), a.z.min(b.z))
    };
    Ok(SectorTree {
        nodes,
        sectors_per_side: sectors,
        levels,
        origin,
        sector_size: size,
        water_sectors,
    })
}

/// Builds the material map over the bodies' bounds (texels of at least 1 m, at most
/// [`MAX_WATER_MATERIAL_MAP`] a side): per texel the material the query finds at its
/// centre, the nearest texel of another material within half the blend distance, and the
/// distance to their boundary (texel centres' distance less half a texel), packed
/// `own | other << 11 | distance << 22` (distance in 1023ths of half the blend distance).
pub fn material_map(world: &WaterWorld, bodies: &[BodyBounds], blend_distance: f32) -> MaterialMap {
    let (mut lo, mut hi) = (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY));
    for b in bodies {
        lo = lo.min(b.min);
        hi = hi.max(b.max);
    }
    if lo.x.partial_cmp(&hi.x).is_none_or(|o| o.is_gt())
        || blend_distance.is_nan()
        || blend_distance <= 0.0
    {
        return MaterialMap::default();
    }
    let reach = blend_distance * 0.5;
    lo -= Vec2::splat(reach + 1.0);
    hi += Vec2::splat(reach + 1.0);
    let extent = (hi - lo).max_element();
    // The neighbour search spans at most 16 texels each way: a wide blend distance coarsens
    // the map instead of costing (2r + 1)^2 tests per texel (10^12 at 1000 m).
    let texel = (extent / MAX_WATER_MATERIAL_MAP as f32)
        .max(reach / 16.0)
        .max(1.0);
    let width = (math::ceil((hi.x - lo.x) / texel) as u32).clamp(2, MAX_WATER_MATERIAL_MAP);
    let height = (math::ceil((hi.y - lo.y) / texel) as u32).clamp(2, MAX_WATER_MATERIAL_MAP);
    let own: Vec<u32> = (0..width * height)
        .map(|k| {
            let p = lo + (Vec2::new((k % width) as f32, (k / width) as f32) + 0.5) * texel;
            world
                .query(p)
                .map_or(WATER_NO_MATERIAL, |q| q.material.min(WATER_NO_MATERIAL - 1))
        })
        .collect();
    let r = math::ceil(reach / texel) as i64 + 1;
    let mut words = vec![0u32; own.len()];
    for y in 0..height as i64 {
        for x in 0..width as i64 {
            let m = own[(y * width as i64 + x) as usize];
            let mut best = (f32::INFINITY, WATER_NO_MATERIAL);
            if m != WATER_NO_MATERIAL {
                for dy in -r..=r {
                    for dx in -r..=r {
                        let (u, v) = (x + dx, y + dy);
                        if u < 0 || v < 0 || u >= width as i64 || v >= height as i64 {
                            continue;
                        }
                        let o = own[(v * width as i64 + u) as usize];
                        if o == m || o == WATER_NO_MATERIAL {
                            continue;
                        }
                        let d = math::sqrt((dx * dx + dy * dy) as f32) * texel;
                        if d < best.0 {
                            best = (d, o);
                        }
                    }
                }
            }
            let (d, other) = best;
            let q = if other == WATER_NO_MATERIAL {
                1023
            } else {
                (math::round((d - 0.5 * texel).max(0.0) / reach * 1023.0) as u32).min(1023)
            };
            words[(y * width as i64 + x) as usize] = m | other << 11 | q << 22;
        }
    }
    MaterialMap {
        words,
        width,
        height,
        origin: lo,
        texel,
    }
}
