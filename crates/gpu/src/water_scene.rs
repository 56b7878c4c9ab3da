//! Far Cry 5's water in the frame (seed 003): what the renderer takes
//! ([`WaterScene`], given with [`Renderer::set_water`](crate::Renderer::set_water) beside
//! the prepared scene), the per-frame displacement decals ([`WaterDecal`]), the statistics
//! a frame reports ([`WaterStats`]), and the CPU side of the passes: the near bodies'
//! low-resolution meshes, the far sectors' quadtree and the material map, all built from
//! the baked [`WaterWorld`] so that the GPU draws exactly what `WaterWorld::query` answers.
//!
//! # The passes
//!
//! After the opaque frame is lit (lighting also keeps its HDR colour when water is set),
//! `passes/water/` runs, each pass timed under its own label:
//!
//! | pass | label | what |
//! | --- | --- | --- |
//! | HiZ | `water hiz` | this frame's opaque depth reduced to staticscene's HiZ layout |
//! | visibility | `water visibility` | near bodies per body (frustum, near radius, HiZ) -> an indexed indirect draw each; far water through a GPU quadtree of sectors (one workgroup, breadth first) -> one indirect draw |
//! | position | `water position` | the mini G-buffer at [`WaterOptions::resolution_scale`] and a field of view [`WaterOptions::fov_scale`] wider: data word, mesh normal, view depth |
//! | displacement | `water displacement` | FBM with the talk's octave LOD (9 near, 3 far, never 0) plus max-blended vector decals, lowered at seams between bodies |
//! | tiles | `water tiles` | 32 x 32 tiles: ballot-aggregated counts, the tile list and the draw's arguments (equal to `water::tiles`' CPU twin) |
//! | tessellation | `water tessellation` | per visible tile a 16 x 16-quad grid of 16-bit vertices (`draw_indexed_indirect`), displaced, depth-tested against the scene into the depth with water |
//! | light tiles | `water light tiles` | the frame's local lights culled into 16 x 16 tiles over the depth with water |
//! | normals | `water normals` | normals from the tessellated depth (radius growing near the camera), blended with the mesh normal |
//! | foam | `water foam` | flow atlas in two phases, shore distance field, water depth, decal foam |
//! | composite | `water composite` | light transport from the water-type table, refraction, sky / screen-space reflection, sun and local lights, specular AA, the 6 m material blend; tone mapped over the output |
//!
//! # Depth with and without water
//!
//! "Water writes depth" (the talk's first warning): the frame keeps two depth buffers.
//!
//! | depth | what it holds | read by |
//! | --- | --- | --- |
//! | the depth target ([`Inspect::read_depth`](crate::inspect::Inspect::read_depth)) | the opaque scene only | lighting, shadows' light tiles, the static query's HiZ (next frame's occlusion), the water's own HiZ, refraction and the water depth under the surface (foam, light transport), screen-space reflections |
//! | the depth with water ([`Renderer::read_water_depth`](crate::Renderer::read_water_depth)) | a copy of the opaque depth with the tessellated water drawn into it (depth-tested, writing) | the water's local light tiles; whatever draws after the water and must be hidden by it (particles, fog, transparent objects): choose this one |
//!
//! A pass that looks *through* the water (what lies under it) reads the depth target; a
//! pass that draws *over* the finished image reads the depth with water. The static query
//! keeps testing against the opaque depth, so water never occludes static instances
//! (it is not opaque).
//!
//! # Limits
//!
//! Every limit is a named `pub const` (the `scene` crate's, re-exported here); a scene over
//! one is an [`Error::WaterLimit`], never a panic.

pub use crate::renderer::{WaterGBuffer, WaterGBufferInput, WaterTiles, WaterView};
use glam::{Mat4, Vec2, Vec3};
pub use scene::{
    MAX_WATER_BODIES, MAX_WATER_BODY_CELLS, MAX_WATER_DECAL_LAYERS, MAX_WATER_DECAL_SIZE,
    MAX_WATER_DECALS, MAX_WATER_MATERIAL_MAP, MAX_WATER_MATERIALS, MAX_WATER_MESH_VERTICES,
    MAX_WATER_SECTORS_PER_SIDE, ShoreField, WATER_NO_MATERIAL, WaterDecal, WaterOptions,
    WaterScene,
};
use water::world::{BodyBounds, BodyId, WaterWorld};

use crate::error::{Error, Result};

/// What the last frame's water passes did ([`Renderer::water_stats`](crate::Renderer::water_stats)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WaterStats {
    /// The mini G-buffer's size.
    pub buffer: [u32; 2],
    /// Whether the composite ran in half precision.
    pub half_precision: bool,
    /// Near bodies drawn (of [`WaterSummary::bodies`]).
    pub near_bodies: u32,
    /// Far sectors drawn (one draw).
    pub far_sectors: u32,
    /// Quadtree nodes the far pass tested.
    pub nodes_tested: u32,
    /// Mini G-buffer pixels with water.
    pub water_pixels: u64,
    /// Tiles with water (instances of the tessellated grid), of `tiles_total`.
    pub tiles: u32,
    /// Tiles of the mini G-buffer.
    pub tiles_total: u32,
    /// Triangles submitted: `tiles` times the grid's (2 x 16 x 16 at the talk's density).
    pub triangles: u64,
}

/// What [`Renderer::set_water`](crate::Renderer::set_water) built.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WaterSummary {
    /// Lakes and rivers drawn per body.
    pub bodies: u32,
    /// Triangles of their low-resolution meshes.
    pub mesh_triangles: u64,
    /// Far sectors per side and the quadtree's levels.
    pub sectors_per_side: u32,
    /// Levels of the far quadtree (a leaf level of `sectors_per_side^2` sectors).
    pub quadtree_levels: u32,
    /// Far sectors holding water.
    pub water_sectors: u32,
    /// Material map texels per side and texel size (metres).
    pub material_map: [u32; 2],
    /// Words of the baked world.
    pub world_words: u64,
    /// CPU time of the build (ms).
    pub build_ms: f64,
}

/// A near body's mesh and record, in the renderer's +Y-up world.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct NearMeshes {
    /// Position, body word, normal, material per vertex.
    pub vertices: Vec<[f32; 8]>,
    pub indices: Vec<u32>,
    /// Per body: world box min, max (+Y up), first index, index count, body word, material.
    pub bodies: Vec<(Vec3, Vec3, u32, u32, u32, u32)>,
}

/// The far sectors' quadtree, level-major (level 0 the root), each node a world box and
/// flags.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct SectorTree {
    /// Per node: min (xyz, flags in w as bits), max (xyz, flat height in w).
    pub nodes: Vec<[f32; 8]>,
    pub sectors_per_side: u32,
    pub levels: u32,
    /// World (x, z) of the grid's min corner, +Y up.
    pub origin: Vec2,
    pub sector_size: f32,
    pub water_sectors: u32,
}

/// Node flags (WGSL `GPU_WATER_NODE_*`).
pub(crate) const NODE_WATER: u32 = 1;
pub(crate) const NODE_OCEAN: u32 = 2;
pub(crate) const NODE_FLAT: u32 = 4;
pub(crate) const NODE_PURE: u32 = 8;
/// A leaf's flags hold the ocean's material from this bit (WGSL
/// `GPU_WATER_NODE_MATERIAL_SHIFT`).
pub(crate) const NODE_MATERIAL_SHIFT: u32 = 8;

/// The material map: per texel own material, the other material within half the blend
/// distance and the distance to their boundary (see `gpu::water_composite`).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct MaterialMap {
    pub words: Vec<u32>,
    pub width: u32,
    pub height: u32,
    /// Texel (0, 0)'s corner, water coordinates.
    pub origin: Vec2,
    pub texel: f32,
}

/// The limit error for `what`.
pub(crate) fn limit(what: &'static str, value: u64, limit: u64, limit_name: &'static str) -> Error {
    Error::WaterLimit {
        what,
        value,
        limit,
        limit_name,
    }
}

/// Checks the options' ranges ([`WaterOptions::validate`]).
pub(crate) fn check_options(o: &WaterOptions) -> Result<()> {
    Ok(o.validate()?)
}

/// Checks the materials against the world's `bodies` ([`WaterScene::check_materials`]).
pub(crate) fn check_materials(scene: &WaterScene, bodies: &[BodyBounds]) -> Result<()> {
    Ok(scene.check_materials(bodies)?)
}

/// Every margin and clamp of the passes ([`WaterScene::max_displacement`]).
pub(crate) fn max_displacement(scene: &WaterScene) -> f32 {
    scene.max_displacement()
}

/// The water (+Z up) point `(x, y)` at height `h` in the renderer's +Y up.
pub(crate) fn y_up(p: Vec2, h: f32) -> Vec3 {
    Vec3::new(p.x, h, -p.y)
}

/// Builds every lake's and river's low-resolution mesh: a grid over the body's bounds
/// (`cell` metres, grown to stay under [`MAX_WATER_BODY_CELLS`]) keeping the cells where
/// the body has water (at the corners or the centre, whichever body's surface is highest
/// there: `WaterWorld::candidates`) and their neighbours, each
/// vertex at the body's surface there (the nearest found height where the body is not),
/// normals from the heights; triangles counter-clockwise seen from above.
pub(crate) fn near_meshes(
    world: &WaterWorld,
    bodies: &[BodyBounds],
    cell: f32,
) -> Result<NearMeshes> {
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
        while (extent.x / c).ceil() * (extent.y / c).ceil() > MAX_WATER_BODY_CELLS as f32 {
            c *= 1.5;
        }
        let nx = ((extent.x / c).ceil() as u32).max(1);
        let ny = ((extent.y / c).ceil() as u32).max(1);
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
        let mut vertex = |out: &mut NearMeshes, i: u32, j: u32| -> Result<u32> {
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
pub(crate) fn sector_tree(
    world: &WaterWorld,
    bodies: &[BodyBounds],
    options: &WaterOptions,
) -> Result<SectorTree> {
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
        (c, options.ocean_extent.max((hi - lo).max_element()))
    } else if lo.x <= hi.x {
        (
            (lo + hi) * 0.5,
            (hi - lo).max_element().max(options.sector_size),
        )
    } else {
        return Ok(SectorTree::default());
    };
    let needed = (side / options.sector_size).ceil().max(1.0);
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
    let size = options.sector_size;
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
pub(crate) fn material_map(
    world: &WaterWorld,
    bodies: &[BodyBounds],
    blend_distance: f32,
) -> MaterialMap {
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
    let width = (((hi.x - lo.x) / texel).ceil() as u32).clamp(2, MAX_WATER_MATERIAL_MAP);
    let height = (((hi.y - lo.y) / texel).ceil() as u32).clamp(2, MAX_WATER_MATERIAL_MAP);
    let own: Vec<u32> = (0..width * height)
        .map(|k| {
            let p = lo + (Vec2::new((k % width) as f32, (k / width) as f32) + 0.5) * texel;
            world
                .query(p)
                .map_or(WATER_NO_MATERIAL, |q| q.material.min(WATER_NO_MATERIAL - 1))
        })
        .collect();
    let r = (reach / texel).ceil() as i64 + 1;
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
                        let d = ((dx * dx + dy * dy) as f32).sqrt() * texel;
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
                (((d - 0.5 * texel).max(0.0) / reach * 1023.0).round() as u32).min(1023)
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

/// A decal's GPU record: world-to-box and box-to-world (water coordinates), strength,
/// frame, fade, and its texture's `[first layer, frames, width, height]` from `textures`
/// (one per decal texture of the scene).
pub(crate) fn decal_record(
    d: &WaterDecal,
    textures: &[[u32; 4]],
) -> Result<crate::passes::water::rows::GpuWaterDecal> {
    let Some(&texture) = textures.get(d.texture as usize) else {
        return Err(limit(
            "a decal's texture index",
            u64::from(d.texture),
            textures.len().saturating_sub(1) as u64,
            "WaterScene::decal_textures.len() - 1",
        ));
    };
    let m = Mat4::from(d.box_to_world);
    let det = m.determinant();
    let finite = m.is_finite()
        && d.strength.is_finite()
        && d.frame.is_finite()
        && d.fade.is_finite()
        && det.is_finite()
        && det.abs() > 1e-12;
    if !finite {
        return Err(Error::Water(water::Error::NonFinite {
            field: "water decal (box, strength, frame or fade; the box must be invertible)",
        }));
    }
    Ok(crate::passes::water::rows::GpuWaterDecal {
        world_to_box: m.inverse().to_cols_array_2d(),
        box_to_world: m.to_cols_array_2d(),
        params: [d.strength, d.frame, d.fade, 0.0],
        texture,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use water::world::{Lake, Ocean, River, RiverPoint, WaterWorldBuilder};

    fn world() -> WaterWorld {
        let mut b = WaterWorldBuilder::new();
        b.ocean = Some(Ocean {
            level: 0.0,
            material: 0,
        });
        b.lakes.push(Lake {
            polygon: vec![
                Vec2::new(0.0, 0.0),
                Vec2::new(60.0, 0.0),
                Vec2::new(60.0, 40.0),
                Vec2::new(0.0, 40.0),
            ],
            height: 10.0,
            material: 1,
        });
        let p = |x: f32, y: f32, z: f32| RiverPoint {
            position: Vec3::new(x, y, z),
            width: 8.0,
            depth: 1.5,
            speed: 2.0,
        };
        b.rivers.push(River {
            points: vec![
                p(30.0, 120.0, 20.0),
                p(30.0, 60.0, 14.0),
                p(30.0, 20.0, 10.0),
            ],
            material: 2,
        });
        b.build(&mut water::no_progress).unwrap()
    }

    #[test]
    fn near_meshes_cover_every_point_of_their_bodies() {
        let w = world();
        let bodies = w.bodies();
        let m = near_meshes(&w, &bodies, 2.0).unwrap();
        assert_eq!(m.bodies.len(), 2);
        // Every point a query finds a body at lies under one of that body's triangles
        // (seen from above), at the body's height there.
        for (k, b) in bodies.iter().enumerate() {
            let (lo, hi, first, count, body, _) = m.bodies[k];
            assert_eq!(body, b.body.0);
            let tris = &m.indices[first as usize..(first + count) as usize];
            for y in (0..160).map(|v| v as f32 * 0.83) {
                for x in (0..80).map(|v| v as f32 * 0.91) {
                    let p = Vec2::new(x, y);
                    let Some(q) = w.query(p).filter(|q| q.body == b.body) else {
                        continue;
                    };
                    let g = y_up(p, q.height);
                    assert!(
                        g.cmpge(lo - 1e-3).all() && g.cmple(hi + 1e-3).all(),
                        "{g} {lo} {hi} {:?}",
                        b.body
                    );
                    let covered = tris.chunks_exact(3).any(|t| {
                        let v = |i: u32| {
                            let r = m.vertices[i as usize];
                            Vec2::new(r[0], r[2])
                        };
                        let (a, bb, c) = (v(t[0]), v(t[1]), v(t[2]));
                        let g2 = Vec2::new(g.x, g.z);
                        let e = |p0: Vec2, p1: Vec2| (p1 - p0).perp_dot(g2 - p0);
                        let (e0, e1, e2) = (e(a, bb), e(bb, c), e(c, a));
                        (e0 >= -1e-4 && e1 >= -1e-4 && e2 >= -1e-4)
                            || (e0 <= 1e-4 && e1 <= 1e-4 && e2 <= 1e-4)
                    });
                    assert!(covered, "{p} of {:?} is not under its mesh", b.body);
                }
            }
            // Counter-clockwise seen from above (+Y): the face normal points up.
            for t in tris.chunks_exact(3) {
                let v = |i: u32| {
                    let r = m.vertices[i as usize];
                    Vec3::new(r[0], r[1], r[2])
                };
                let n = (v(t[1]) - v(t[0])).cross(v(t[2]) - v(t[0]));
                assert!(n.y > 0.0, "{n}");
            }
        }
    }

    #[test]
    fn sector_tree_nodes_hold_their_children_and_the_ocean() {
        let w = world();
        let bodies = w.bodies();
        let t = sector_tree(&w, &bodies, &WaterOptions::default()).unwrap();
        assert_eq!(t.sectors_per_side, 64);
        assert_eq!(t.levels, 7);
        assert_eq!(t.nodes.len(), (4usize.pow(7) - 1) / 3);
        // Every leaf has the ocean; the root's box holds every leaf's.
        let leaves = &t.nodes[(4usize.pow(6) - 1) / 3..];
        assert!(leaves.iter().all(|l| l[3].to_bits() & NODE_OCEAN != 0));
        let root = t.nodes[0];
        for l in leaves {
            for k in 0..3 {
                assert!(root[k] <= l[k] && root[4 + k] >= l[4 + k]);
            }
        }
        // Over the talk's 64 x 64 sectors: an error naming the limit.
        let big = WaterOptions {
            ocean_extent: 64.0 * 65.0,
            ..WaterOptions::default()
        };
        match sector_tree(&w, &bodies, &big) {
            Err(Error::WaterLimit { limit_name, .. }) => {
                assert_eq!(limit_name, "MAX_WATER_SECTORS_PER_SIDE")
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn material_map_blends_over_the_boundary() {
        let w = world();
        let bodies = w.bodies();
        let m = material_map(&w, &bodies, 6.0);
        assert!(m.width > 10 && m.height > 10);
        let at = |p: Vec2| {
            let t = ((p - m.origin) / m.texel).floor();
            m.words[(t.y as u32 * m.width + t.x as u32) as usize]
        };
        // Deep in the lake, away from the river: no other material.
        let w0 = at(Vec2::new(8.0, 8.0));
        assert_eq!(w0 & 0x7ff, 1);
        assert_eq!(w0 >> 22, 1023);
        // Along the river's banks inside the lake, each side sees the other within reach.
        let sees = |own: u32, other: u32| {
            m.words
                .iter()
                .filter(|&&w| w & 0x7ff == own && (w >> 11) & 0x7ff == other && w >> 22 < 300)
                .count()
        };
        assert!(
            sees(1, 2) > 10 && sees(2, 1) > 10,
            "{} {}",
            sees(1, 2),
            sees(2, 1)
        );
    }
}
