//! Baking a [`WaterWorldBuilder`] into words (validation and the query over the words
//! are in `read.rs`, the helpers both share in `geom.rs`).

use alloc::collections::BTreeMap;
use alloc::vec;
use alloc::vec::Vec;

use glam::Vec2;
use half::f16;

use super::geom::{Aabb, clip, finite2, pack2x16float, point_in_polygon, signed_area};
use super::spline::{closest_on_segment, river_ranges};
use super::*;
use crate::math;
use crate::progress::{Stage, report};

/// One corner value of a river tile during the bake.
#[derive(Clone, Copy)]
struct Corner {
    /// Distance to the centre line (the nearest wins).
    dist: f32,
    height: f32,
    flow: Vec2,
    depth: f32,
    lateral: f32,
}

struct TileBuild {
    river: u32,
    material: u32,
    key: (i32, i32),
    corners: Vec<Option<Corner>>,
}

fn check_settings(s: &WorldSettings) -> Result<(), Error> {
    if !(s.texel_size > 0.0) || !s.texel_size.is_finite() {
        return Err(Error::OutOfRange {
            field: "river texel size",
            value: s.texel_size,
            min: f32::MIN_POSITIVE,
            max: f32::MAX,
        });
    }
    if s.tile_texels == 0 || s.tile_texels > 1024 {
        return Err(Error::InvalidSize {
            field: "tile texels",
            value: s.tile_texels,
            rule: "in 1..=1024",
        });
    }
    if s.max_depth > MAX_QUADTREE_DEPTH {
        return Err(Error::LimitExceeded {
            what: "quadtree max depth",
            value: u64::from(s.max_depth),
            limit: u64::from(MAX_QUADTREE_DEPTH),
            limit_name: "MAX_QUADTREE_DEPTH",
        });
    }
    Ok(())
}

/// The error of body `i` of `kind` ("lake" or "river") for a reason.
fn degenerate(kind: &'static str, i: usize) -> impl Fn(&'static str) -> Error {
    move |reason| Error::DegenerateBody {
        kind,
        index: i as u32,
        reason,
    }
}

/// The point count every body checks: at least `min` (else `bad(too_few)`), at most
/// [`MAX_POINTS_PER_BODY`] (`what` names the points in the error).
fn check_count(
    len: usize,
    (min, too_few): (usize, &'static str),
    bad: &impl Fn(&'static str) -> Error,
    what: &'static str,
) -> Result<(), Error> {
    if len < min {
        return Err(bad(too_few));
    }
    if len > MAX_POINTS_PER_BODY as usize {
        return Err(Error::LimitExceeded {
            what,
            value: len as u64,
            limit: u64::from(MAX_POINTS_PER_BODY),
            limit_name: "MAX_POINTS_PER_BODY",
        });
    }
    Ok(())
}

fn check_lake(i: usize, lake: &Lake) -> Result<Aabb, Error> {
    let bad = degenerate("lake", i);
    let few = (3, "fewer than 3 points");
    check_count(lake.polygon.len(), few, &bad, "lake polygon points")?;
    if !lake.height.is_finite() || lake.height.abs() > MAX_COORDINATE {
        return Err(bad("height is not finite or beyond MAX_COORDINATE"));
    }
    let mut b = Aabb::empty();
    for &p in &lake.polygon {
        if !finite2(p) {
            return Err(bad("a point is not finite or beyond MAX_COORDINATE"));
        }
        b.add(p);
    }
    if signed_area(&lake.polygon).abs() < 1e-6 {
        return Err(bad("zero area"));
    }
    Ok(b)
}

fn check_river(i: usize, river: &River) -> Result<(), Error> {
    let bad = degenerate("river", i);
    let few = (2, "fewer than 2 points");
    check_count(river.points.len(), few, &bad, "river points")?;
    for p in &river.points {
        let ok = finite2(p.position.truncate())
            && p.position.z.is_finite()
            && p.position.z.abs() <= MAX_COORDINATE
            && p.width.is_finite()
            && p.width >= 0.0
            && p.width <= MAX_COORDINATE
            && p.depth.is_finite()
            && p.depth >= 0.0
            && p.speed.is_finite()
            // The flow is stored as f16 (`pack2x16float`).
            && p.speed.abs() <= f16::MAX.to_f32_const();
        if !ok {
            return Err(bad(
                "a point has a non-finite or out-of-range position, width, depth or speed",
            ));
        }
    }
    Ok(())
}

/// Rasterises one river into tiles.
fn bake_river(
    index: u32,
    river: &River,
    s: &WorldSettings,
    tiles: &mut BTreeMap<(u32, i32, i32), TileBuild>,
) -> Result<(), Error> {
    let texel = s.texel_size;
    let n = s.tile_texels as i64;
    let max_tiles = MAX_WORLD_WORDS / ((n as u64 + 1).pow(2) * u64::from(TEXEL_WORDS));
    let side = (n + 1) as usize;
    // The texel range under each segment's capsule, refused above MAX_RIVER_TEXELS before
    // any work; world texels sit on the grid's corners (no half-texel shift).
    let (samples, ranges) = river_ranges(&river.points, texel, Vec2::ZERO, 0.0, None)?;
    for (seg, &(x0, y0, x1, y1)) in samples.windows(2).zip(&ranges) {
        let (a, b) = (seg[0], seg[1]);
        let (a2, b2) = (a.position.truncate(), b.position.truncate());
        let dir = (b2 - a2).normalize_or_zero();
        for gy in y0..=y1 {
            for gx in x0..=x1 {
                let p = Vec2::new(gx as f32 * texel, gy as f32 * texel);
                let (t, d) = closest_on_segment(a2, b2, p);
                let hw = math::mix(a.width, b.width, t) * 0.5;
                if !(d <= hw) {
                    continue;
                }
                let sl = if hw > 0.0 { d / hw } else { 0.0 };
                let profile = 1.0 - sl * sl;
                let c = Corner {
                    dist: d,
                    height: math::mix(a.position.z, b.position.z, t),
                    flow: dir * (math::mix(a.speed, b.speed, t) * profile),
                    depth: math::mix(a.depth, b.depth, t) * profile,
                    lateral: sl,
                };
                // The corner belongs to every tile whose (n + 1)^2 corners include it.
                let (tx, ty) = (gx.div_euclid(n), gy.div_euclid(n));
                let (lx, ly) = (gx.rem_euclid(n), gy.rem_euclid(n));
                for (ox, oy) in [(0i64, 0i64), (1, 0), (0, 1), (1, 1)] {
                    if (ox == 1 && lx != 0) || (oy == 1 && ly != 0) {
                        continue;
                    }
                    let (ktx, kty) = (tx - ox, ty - oy);
                    let (clx, cly) = (lx + ox * n, ly + oy * n);
                    let key = (index, ktx as i32, kty as i32);
                    if !tiles.contains_key(&key) && tiles.len() as u64 >= max_tiles {
                        return Err(Error::LimitExceeded {
                            what: "river tiles",
                            value: max_tiles + 1,
                            limit: max_tiles,
                            limit_name: "MAX_WORLD_WORDS / texel words per tile",
                        });
                    }
                    let tile = tiles.entry(key).or_insert_with(|| TileBuild {
                        river: index,
                        material: river.material,
                        key: (ktx as i32, kty as i32),
                        corners: vec![None; side * side],
                    });
                    let slot = &mut tile.corners[cly as usize * side + clx as usize];
                    if slot.is_none_or(|old| c.dist < old.dist) {
                        *slot = Some(c);
                    }
                }
            }
        }
    }
    Ok(())
}

struct QuadBuild<'a> {
    lakes: &'a [Lake],
    lake_boxes: &'a [Aabb],
    tile_boxes: &'a [Aabb],
    settings: &'a WorldSettings,
    nodes: Vec<[u32; 2]>,
    items: Vec<[u32; 4]>,
    /// Per partial item: its local edges (4 words each), then its breakpoints.
    edge_words: Vec<f32>,
    depth: u32,
}

/// What a partial lake stores in a leaf.
struct Partial {
    lake: u32,
    local: Vec<[f32; 4]>,
    breakpoints: Vec<f32>,
    base: bool,
}

impl QuadBuild<'_> {
    /// Splits lake `l`'s edges for `node` (expanded by `margin`): edges whose box overlaps
    /// the node are *local* (tested exactly by the query); edges entirely to the right
    /// that overlap the node's band in y are *far*: for a query point inside the node they
    /// cross its +x ray exactly when `lo <= p.y < hi`, which depends on `p.y` only and is
    /// stored as a base parity at the band's bottom plus the sorted breakpoints `lo`, `hi`
    /// that fall inside the band. `candidates` are the edges that were local or far for the
    /// parent (no other edge can be either for a child); the ones that still are get
    /// pushed to `keep`. Returns `None` when no edge is local (the node is entirely inside
    /// or outside).
    fn partial(
        &self,
        l: u32,
        candidates: &[u32],
        node: &Aabb,
        margin: f32,
        keep: &mut Vec<u32>,
    ) -> Option<Partial> {
        let poly = &self.lakes[l as usize].polygon;
        let n = poly.len();
        let (bmin, bmax) = (node.min.y - margin, node.max.y + margin);
        let mut local = Vec::new();
        let mut breakpoints = Vec::new();
        let mut base = false;
        let (x0, x1) = (
            f64::from(node.min.x - margin),
            f64::from(node.max.x + margin),
        );
        let (y0, y1) = (f64::from(bmin), f64::from(bmax));
        for &i in candidates {
            let i = i as usize;
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            // The part of the edge inside the band row y in [bmin, bmax].
            let Some((ta, tb)) = clip(a.y, b.y, y0, y1, 0.0, 1.0) else {
                continue;
            };
            // ... and inside the node's x range too: then it is local.
            if clip(a.x, b.x, x0, x1, ta, tb).is_some() {
                local.push([a.x, a.y, b.x, b.y]);
                keep.push(i as u32);
                continue;
            }
            // Otherwise the band part lies wholly left or right of the node.
            let tm = 0.5 * (ta + tb);
            let xm = f64::from(a.x) + (f64::from(b.x) - f64::from(a.x)) * tm;
            let (lo, hi) = (a.y.min(b.y), a.y.max(b.y));
            if xm < x1 || lo == hi {
                continue;
            }
            keep.push(i as u32);
            // [lo <= y] xor [hi <= y] for y in [bmin, bmax].
            for t in [lo, hi] {
                if t <= bmin {
                    base = !base;
                } else if t <= bmax {
                    breakpoints.push(t);
                }
            }
        }
        if local.is_empty() {
            return None;
        }
        breakpoints.sort_by(f32::total_cmp);
        Some(Partial {
            lake: l,
            local,
            breakpoints,
            base,
        })
    }

    /// Builds node `node_index` covering `b` from the lakes (each with its candidate edges)
    /// and tiles that may overlap it.
    fn build(
        &mut self,
        node_index: usize,
        b: Aabb,
        depth: u32,
        lakes: &[(u32, Vec<u32>)],
        tiles: &[u32],
    ) {
        self.depth = self.depth.max(depth);
        let size = b.max.x - b.min.x;
        let margin = size * 1e-3;
        let mut here_lakes = Vec::new();
        let mut partial: Vec<Partial> = Vec::new();
        let mut inside = Vec::new();
        for (l, candidates) in lakes {
            let l = *l;
            if !self.lake_boxes[l as usize].overlaps(&b, margin) {
                continue;
            }
            let mut keep = Vec::new();
            match self.partial(l, candidates, &b, margin, &mut keep) {
                Some(p) => {
                    here_lakes.push((l, keep));
                    partial.push(p);
                }
                None => {
                    if point_in_polygon(&self.lakes[l as usize].polygon, (b.min + b.max) * 0.5) {
                        // No edge can reach the children either.
                        here_lakes.push((l, Vec::new()));
                        inside.push(l);
                    }
                }
            }
        }
        let here_tiles: Vec<u32> = tiles
            .iter()
            .copied()
            .filter(|&t| self.tile_boxes[t as usize].overlaps(&b, margin))
            .collect();
        let items = inside.len() + partial.len() + here_tiles.len();
        let too_many_edges = partial
            .iter()
            .any(|p| p.local.len() + p.breakpoints.len() > self.settings.max_leaf_edges as usize);
        let split = depth < self.settings.max_depth
            && (items > self.settings.max_leaf_items as usize || too_many_edges);
        if split {
            let first = self.nodes.len() as u32;
            self.nodes[node_index] = [first, NODE_INTERNAL];
            self.nodes.extend([[0, 0]; 4]);
            let half = size * 0.5;
            let mid = Vec2::new(b.min.x + half, b.min.y + half);
            for q in 0..4u32 {
                let (qx, qy) = (q & 1 != 0, q & 2 != 0);
                let min = Vec2::new(
                    if qx { mid.x } else { b.min.x },
                    if qy { mid.y } else { b.min.y },
                );
                let child = Aabb {
                    min,
                    max: min + half,
                };
                self.build(
                    (first + q) as usize,
                    child,
                    depth + 1,
                    &here_lakes,
                    &here_tiles,
                );
            }
            return;
        }
        let first_item = self.items.len() as u32;
        for l in inside {
            self.items
                .push([ITEM_LAKE_INSIDE << KIND_SHIFT | l, 0, 0, 0]);
        }
        for p in partial {
            let start = self.edge_words.len() as u32;
            self.items.push([
                ITEM_LAKE_PARTIAL << KIND_SHIFT | p.lake,
                start,
                p.local.len() as u32,
                p.breakpoints.len() as u32 | u32::from(p.base) << 31,
            ]);
            for e in &p.local {
                self.edge_words.extend_from_slice(e);
            }
            self.edge_words.extend_from_slice(&p.breakpoints);
        }
        for t in here_tiles {
            self.items
                .push([ITEM_RIVER_TILE << KIND_SHIFT | t, 0, 0, 0]);
        }
        self.nodes[node_index] = [first_item, self.items.len() as u32 - first_item];
    }
}

fn too_big(words: u64) -> Error {
    Error::LimitExceeded {
        what: "baked world words",
        value: words,
        limit: MAX_WORLD_WORDS,
        limit_name: "MAX_WORLD_WORDS",
    }
}

pub(crate) fn bake(
    builder: &WaterWorldBuilder,
    progress: &mut impl FnMut(Progress) -> ControlFlow<()>,
) -> Result<Vec<u32>, Error> {
    let s = &builder.settings;
    check_settings(s)?;
    if builder.lakes.len() >= MAX_BODIES as usize || builder.rivers.len() >= MAX_BODIES as usize {
        return Err(Error::LimitExceeded {
            what: "lakes or rivers",
            value: builder.lakes.len().max(builder.rivers.len()) as u64,
            limit: u64::from(MAX_BODIES),
            limit_name: "MAX_BODIES",
        });
    }
    if let Some(o) = builder.ocean
        && (!o.level.is_finite() || o.level.abs() > MAX_COORDINATE)
    {
        return Err(Error::NonFinite {
            field: "ocean level",
        });
    }
    let lake_boxes: Vec<Aabb> = builder
        .lakes
        .iter()
        .enumerate()
        .map(|(i, l)| check_lake(i, l))
        .collect::<Result<_, _>>()?;
    for (i, r) in builder.rivers.iter().enumerate() {
        check_river(i, r)?;
    }

    // Rivers to tiles.
    let mut tiles = BTreeMap::new();
    let rivers = builder.rivers.len() as u64;
    for (i, r) in builder.rivers.iter().enumerate() {
        bake_river(i as u32, r, s, &mut tiles)?;
        report(progress, Stage::RiverTiles, i as u64 + 1, rivers)?;
    }
    let tiles: Vec<TileBuild> = tiles.into_values().collect();
    let n = s.tile_texels;
    let side = u64::from(n + 1);
    let tile_span = n as f32 * s.texel_size;
    let tile_boxes: Vec<Aabb> = tiles
        .iter()
        .map(|t| {
            let min = Vec2::new(t.key.0 as f32, t.key.1 as f32) * tile_span;
            Aabb {
                min,
                max: min + tile_span,
            }
        })
        .collect();
    let texel_words = tiles.len() as u64 * side * side * u64::from(TEXEL_WORDS);
    if texel_words > MAX_WORLD_WORDS {
        return Err(too_big(texel_words));
    }

    // The quadtree over lakes and tiles, on a square root box.
    let mut all = Aabb::empty();
    for b in lake_boxes.iter().chain(&tile_boxes) {
        all.union(b);
    }
    let (root, root_size) = if all.is_empty() {
        (Vec2::ZERO, 0.0)
    } else {
        let ext = (all.max - all.min).max_element().max(s.texel_size);
        // A little larger than the content so nothing sits on the far boundary.
        let size = ext * (1.0 + 1.0 / 1024.0) + s.texel_size;
        (all.min - s.texel_size * 0.5, size)
    };
    let mut q = QuadBuild {
        lakes: &builder.lakes,
        lake_boxes: &lake_boxes,
        tile_boxes: &tile_boxes,
        settings: s,
        nodes: vec![[0, 0]],
        items: Vec::new(),
        edge_words: Vec::new(),
        depth: 0,
    };
    if root_size > 0.0 {
        let lakes: Vec<(u32, Vec<u32>)> = builder
            .lakes
            .iter()
            .enumerate()
            .map(|(i, l)| (i as u32, (0..l.polygon.len() as u32).collect()))
            .collect();
        let tiles_idx: Vec<u32> = (0..tiles.len() as u32).collect();
        let b = Aabb {
            min: root,
            max: root + root_size,
        };
        q.build(0, b, 0, &lakes, &tiles_idx);
    }
    report(progress, Stage::Quadtree, 1, 1)?;

    // Lay out the words.
    let h = WORLD_HEADER_WORDS as u64;
    let nodes = q.nodes.len() as u64 * u64::from(NODE_WORDS);
    let items = q.items.len() as u64 * u64::from(ITEM_WORDS);
    let lakes = builder.lakes.len() as u64 * u64::from(LAKE_WORDS);
    let edges = q.edge_words.len() as u64;
    let tile_recs = tiles.len() as u64 * u64::from(TILE_WORDS);
    let total = h + nodes + items + lakes + edges + tile_recs + texel_words;
    if total > MAX_WORLD_WORDS {
        return Err(too_big(total));
    }
    let o_nodes = h;
    let o_items = o_nodes + nodes;
    let o_lakes = o_items + items;
    let o_edges = o_lakes + lakes;
    let o_tiles = o_edges + edges;
    let o_texels = o_tiles + tile_recs;
    let mut w = vec![0u32; total as usize];
    let ocean = builder.ocean;
    w[header::MAGIC] = WORLD_MAGIC;
    w[header::VERSION] = WORLD_VERSION;
    w[header::FLAGS] = u32::from(ocean.is_some());
    w[header::OCEAN_LEVEL] = ocean.map_or(0.0, |o| o.level).to_bits();
    w[header::OCEAN_MATERIAL] = ocean.map_or(0, |o| o.material);
    w[header::ROOT_X] = root.x.to_bits();
    w[header::ROOT_Y] = root.y.to_bits();
    w[header::ROOT_SIZE] = root_size.to_bits();
    w[header::NODES] = o_nodes as u32;
    w[header::NODE_COUNT] = q.nodes.len() as u32;
    w[header::ITEMS] = o_items as u32;
    w[header::LAKES] = o_lakes as u32;
    w[header::LAKE_COUNT] = builder.lakes.len() as u32;
    w[header::TILES] = o_tiles as u32;
    w[header::TILE_COUNT] = tiles.len() as u32;
    w[header::TILE_TEXELS] = n;
    w[header::EDGES] = o_edges as u32;
    w[header::RIVER_COUNT] = builder.rivers.len() as u32;
    w[header::DEPTH] = q.depth;
    w[header::TOTAL] = total as u32;
    let mut at = o_nodes as usize;
    for node in &q.nodes {
        w[at..at + 2].copy_from_slice(node);
        at += 2;
    }
    for item in &q.items {
        w[at..at + 4].copy_from_slice(item);
        at += 4;
    }
    for lake in &builder.lakes {
        w[at] = lake.height.to_bits();
        w[at + 1] = lake.material;
        at += 2;
    }
    for v in &q.edge_words {
        w[at] = v.to_bits();
        at += 1;
    }
    let per_tile = (side * side) as usize * TEXEL_WORDS as usize;
    for (i, t) in tiles.iter().enumerate() {
        let origin = tile_boxes[i].min;
        let data = o_texels as usize + i * per_tile;
        w[at] = origin.x.to_bits();
        w[at + 1] = origin.y.to_bits();
        w[at + 2] = (1.0 / s.texel_size).to_bits();
        w[at + 3] = t.river;
        w[at + 4] = t.material;
        w[at + 5] = data as u32;
        at += TILE_WORDS as usize;
        for (k, c) in t.corners.iter().enumerate() {
            let d = data + k * TEXEL_WORDS as usize;
            match c {
                Some(c) => {
                    w[d] = c.height.to_bits();
                    w[d + 1] = pack2x16float(c.flow.x, c.flow.y);
                    w[d + 2] = pack2x16float(c.depth, c.lateral);
                }
                None => {
                    w[d] = TEXEL_NONE;
                    w[d + 1] = 0;
                    w[d + 2] = 0;
                }
            }
        }
    }
    Ok(w)
}
