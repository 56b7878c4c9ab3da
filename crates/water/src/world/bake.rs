//! Baking a [`WaterWorldBuilder`] into words, validating words, and the query over them.

use alloc::collections::BTreeMap;
use alloc::vec;
use alloc::vec::Vec;
use core::ops::ControlFlow;

use glam::Vec2;
use half::f16;

use super::spline::{SplineSample, closest_on_segment, flatten_bounded};
use super::*;
use crate::math;
use crate::progress::{Stage, report};

fn f(w: u32) -> f32 {
    f32::from_bits(w)
}

/// `pack2x16float` as WGSL does it (round to nearest even, low half first).
pub(crate) fn pack2x16float(a: f32, b: f32) -> u32 {
    u32::from(f16::from_f32(a).to_bits()) | u32::from(f16::from_f32(b).to_bits()) << 16
}

/// `unpack2x16float`.
pub(crate) fn unpack2x16float(w: u32) -> Vec2 {
    Vec2::new(
        f16::from_bits(w as u16).to_f32(),
        f16::from_bits((w >> 16) as u16).to_f32(),
    )
}

fn finite2(p: Vec2) -> bool {
    p.x.is_finite() && p.y.is_finite() && p.x.abs() <= MAX_COORDINATE && p.y.abs() <= MAX_COORDINATE
}

/// Axis-aligned box `[min, max]`.
#[derive(Clone, Copy, Debug)]
struct Aabb {
    min: Vec2,
    max: Vec2,
}

impl Aabb {
    fn empty() -> Self {
        Self {
            min: Vec2::splat(f32::INFINITY),
            max: Vec2::splat(f32::NEG_INFINITY),
        }
    }
    fn add(&mut self, p: Vec2) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }
    fn union(&mut self, o: &Aabb) {
        self.min = self.min.min(o.min);
        self.max = self.max.max(o.max);
    }
    fn overlaps(&self, o: &Aabb, margin: f32) -> bool {
        self.min.x <= o.max.x + margin
            && o.min.x <= self.max.x + margin
            && self.min.y <= o.max.y + margin
            && o.min.y <= self.max.y + margin
    }
    fn is_empty(&self) -> bool {
        !(self.min.x <= self.max.x)
    }
}

/// Even-odd test against a whole polygon (the build's classification; queries use
/// the same [`crosses`] on a leaf's edges).
fn point_in_polygon(poly: &[Vec2], p: Vec2) -> bool {
    let mut inside = false;
    let n = poly.len();
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        if crosses(a.x, a.y, b.x, b.y, p) {
            inside = !inside;
        }
    }
    inside
}

/// Whether the ray from `p` towards +x crosses edge `(x0, y0) -> (x1, y1)` (half-open in y).
#[inline]
fn crosses(x0: f32, y0: f32, x1: f32, y1: f32, p: Vec2) -> bool {
    if (y0 > p.y) != (y1 > p.y) {
        let xc = x0 + (p.y - y0) * (x1 - x0) / (y1 - y0);
        p.x < xc
    } else {
        false
    }
}

fn signed_area(poly: &[Vec2]) -> f64 {
    let n = poly.len();
    let mut a = 0.0f64;
    for i in 0..n {
        let (p, q) = (poly[i], poly[(i + 1) % n]);
        a += f64::from(p.x) * f64::from(q.y) - f64::from(q.x) * f64::from(p.y);
    }
    a * 0.5
}

/// Liang–Barsky along one axis: the sub-range of `t in [t0, t1]` where `a + (b - a) t`
/// lies in `[lo, hi]` (f64), or `None`.
fn clip(a: f32, b: f32, lo: f64, hi: f64, t0: f64, t1: f64) -> Option<(f64, f64)> {
    let (a, d) = (f64::from(a), f64::from(b) - f64::from(a));
    let (mut t0, mut t1) = (t0, t1);
    if d == 0.0 {
        return (a >= lo && a <= hi).then_some((t0, t1));
    }
    let (mut ta, mut tb) = ((lo - a) / d, (hi - a) / d);
    if ta > tb {
        core::mem::swap(&mut ta, &mut tb);
    }
    t0 = t0.max(ta);
    t1 = t1.min(tb);
    (t0 <= t1).then_some((t0, t1))
}

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

fn check_lake(i: usize, lake: &Lake) -> Result<Aabb, Error> {
    let index = i as u32;
    let bad = |reason| Error::DegenerateBody {
        kind: "lake",
        index,
        reason,
    };
    if lake.polygon.len() < 3 {
        return Err(bad("fewer than 3 points"));
    }
    if lake.polygon.len() > MAX_POINTS_PER_BODY as usize {
        return Err(Error::LimitExceeded {
            what: "lake polygon points",
            value: lake.polygon.len() as u64,
            limit: u64::from(MAX_POINTS_PER_BODY),
            limit_name: "MAX_POINTS_PER_BODY",
        });
    }
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
    let index = i as u32;
    let bad = |reason| Error::DegenerateBody {
        kind: "river",
        index,
        reason,
    };
    if river.points.len() < 2 {
        return Err(bad("fewer than 2 points"));
    }
    if river.points.len() > MAX_POINTS_PER_BODY as usize {
        return Err(Error::LimitExceeded {
            what: "river points",
            value: river.points.len() as u64,
            limit: u64::from(MAX_POINTS_PER_BODY),
            limit_name: "MAX_POINTS_PER_BODY",
        });
    }
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
    let too_big = |value: u64| Error::LimitExceeded {
        what: "texels a river's segments cover",
        value,
        limit: MAX_RIVER_TEXELS,
        limit_name: "MAX_RIVER_TEXELS",
    };
    let samples: Vec<SplineSample> =
        flatten_bounded(&river.points, texel * 0.5, MAX_RIVER_TEXELS as usize)
            .ok_or(too_big(MAX_RIVER_TEXELS + 1))?;
    // The texel range under each segment's capsule, and the total, before any work.
    let ranges: Vec<(i64, i64, i64, i64)> = samples
        .windows(2)
        .map(|seg| {
            let (a2, b2) = (seg[0].position.truncate(), seg[1].position.truncate());
            let r = seg[0].width.max(seg[1].width) * 0.5;
            let lo = (a2.min(b2) - r) / texel;
            let hi = (a2.max(b2) + r) / texel;
            (
                math::ceil(lo.x) as i64,
                math::ceil(lo.y) as i64,
                math::floor(hi.x) as i64,
                math::floor(hi.y) as i64,
            )
        })
        .collect();
    let total: u64 = ranges
        .iter()
        .map(|&(x0, y0, x1, y1)| {
            ((x1 - x0 + 1).max(0) as u64).saturating_mul((y1 - y0 + 1).max(0) as u64)
        })
        .fold(0u64, u64::saturating_add);
    if total > MAX_RIVER_TEXELS {
        return Err(too_big(total));
    }
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

fn invalid(reason: &'static str) -> Error {
    Error::InvalidData {
        what: "water world",
        reason,
    }
}

/// Checks that a word array is a world whose queries stay in bounds.
pub(crate) fn validate(w: &[u32]) -> Result<(), Error> {
    if w.len() < WORLD_HEADER_WORDS as usize {
        return Err(invalid("shorter than the header"));
    }
    if w[header::MAGIC] != WORLD_MAGIC || w[header::VERSION] != WORLD_VERSION {
        return Err(invalid("bad magic or version"));
    }
    if w[header::TOTAL] as usize != w.len() {
        return Err(invalid("total word count does not match the length"));
    }
    let len = w.len() as u64;
    let span = |off: usize, count: u64, words: u32| -> Result<(), Error> {
        let end = u64::from(w[off]) + count * u64::from(words);
        if end > len {
            Err(invalid("a section runs past the end"))
        } else {
            Ok(())
        }
    };
    let nodes = u64::from(w[header::NODE_COUNT]);
    if nodes == 0 {
        return Err(invalid("no root node"));
    }
    span(header::NODES, nodes, NODE_WORDS)?;
    span(header::LAKES, u64::from(w[header::LAKE_COUNT]), LAKE_WORDS)?;
    span(header::TILES, u64::from(w[header::TILE_COUNT]), TILE_WORDS)?;
    let n = w[header::TILE_TEXELS];
    if n == 0 || n > 1024 {
        return Err(invalid("tile texels outside 1..=1024"));
    }
    if w[header::DEPTH] > MAX_QUADTREE_DEPTH {
        return Err(invalid("quadtree deeper than MAX_QUADTREE_DEPTH"));
    }
    let side = u64::from(n) + 1;
    let o_nodes = w[header::NODES] as usize;
    let o_items = u64::from(w[header::ITEMS]);
    let o_edges = u64::from(w[header::EDGES]);
    for i in 0..nodes as usize {
        let (a, b) = (w[o_nodes + 2 * i], w[o_nodes + 2 * i + 1]);
        if b == NODE_INTERNAL {
            if u64::from(a) + 4 > nodes || a as usize <= i {
                return Err(invalid(
                    "a child index is out of range or not after its parent",
                ));
            }
        } else {
            let end = o_items + (u64::from(a) + u64::from(b)) * u64::from(ITEM_WORDS);
            if end > len {
                return Err(invalid("a leaf's items run past the end"));
            }
            for k in 0..u64::from(b) {
                let at = (o_items + (u64::from(a) + k) * u64::from(ITEM_WORDS)) as usize;
                let (kind, index) = (w[at] >> KIND_SHIFT, w[at] & (MAX_BODIES - 1));
                match kind {
                    ITEM_LAKE_INSIDE | ITEM_LAKE_PARTIAL => {
                        if index >= w[header::LAKE_COUNT] {
                            return Err(invalid("an item names a missing lake"));
                        }
                        let end = o_edges
                            + u64::from(w[at + 1])
                            + u64::from(w[at + 2]) * u64::from(EDGE_WORDS)
                            + u64::from(w[at + 3] & !(1 << 31));
                        if kind == ITEM_LAKE_PARTIAL && end > len {
                            return Err(invalid("a lake's edges run past the end"));
                        }
                    }
                    ITEM_RIVER_TILE => {
                        if index >= w[header::TILE_COUNT] {
                            return Err(invalid("an item names a missing tile"));
                        }
                    }
                    _ => return Err(invalid("an item of unknown kind")),
                }
            }
        }
    }
    let o_tiles = w[header::TILES] as usize;
    for t in 0..w[header::TILE_COUNT] as usize {
        let data = u64::from(w[o_tiles + t * TILE_WORDS as usize + 5]);
        if data + side * side * u64::from(TEXEL_WORDS) > len {
            return Err(invalid("a tile's texels run past the end"));
        }
    }
    Ok(())
}

/// The best candidate so far.
struct Best {
    level: Option<WaterLevel>,
}

impl Best {
    fn offer(&mut self, l: WaterLevel) {
        if self.level.is_none_or(|b| l.height > b.height) {
            self.level = Some(l);
        }
    }
}

/// A river tile's answer at `p`, if its nearest corner is water.
fn sample_tile(w: &[u32], tile: usize, p: Vec2) -> Option<WaterLevel> {
    let n = w[header::TILE_TEXELS];
    let r = w[header::TILES] as usize + tile * TILE_WORDS as usize;
    let origin = Vec2::new(f(w[r]), f(w[r + 1]));
    let inv = f(w[r + 2]);
    let data = w[r + 5] as usize;
    let t = (p - origin) * inv;
    let nf = n as f32;
    if !(t.x >= 0.0 && t.y >= 0.0 && t.x <= nf && t.y <= nf) {
        return None;
    }
    let i = (math::floor(t.x) as u32).min(n - 1);
    let j = (math::floor(t.y) as u32).min(n - 1);
    let (fx, fy) = (t.x - i as f32, t.y - j as f32);
    let side = n as usize + 1;
    let at = |di: u32, dj: u32| data + ((j + dj) as usize * side + (i + di) as usize) * 3;
    let near = at(u32::from(fx >= 0.5), u32::from(fy >= 0.5));
    if w[near] == TEXEL_NONE {
        return None;
    }
    let mut sum_w = 0.0;
    let (mut h, mut flow, mut depth) = (0.0, Vec2::ZERO, 0.0);
    for (di, dj, wt) in [
        (0, 0, (1.0 - fx) * (1.0 - fy)),
        (1, 0, fx * (1.0 - fy)),
        (0, 1, (1.0 - fx) * fy),
        (1, 1, fx * fy),
    ] {
        let a = at(di, dj);
        if w[a] != TEXEL_NONE {
            sum_w += wt;
            h += wt * f(w[a]);
            flow += unpack2x16float(w[a + 1]) * wt;
            depth += wt * unpack2x16float(w[a + 2]).x;
        }
    }
    // The nearest corner is water and has the largest weight, so sum_w >= 1/4.
    let inv_w = 1.0 / sum_w;
    Some(WaterLevel {
        height: h * inv_w,
        body: BodyId::river(w[r + 3]),
        material: w[r + 4],
        depth: depth * inv_w,
        flow: flow * inv_w,
    })
}

/// The query over validated words.
pub(crate) fn query(w: &[u32], p: Vec2) -> Option<WaterLevel> {
    let mut best = Best { level: None };
    visit(w, p, |l| best.offer(l));
    best.level
}

/// Every body whose water covers `p` over validated words, in the query's order (the
/// ocean first, then the quadtree leaf's items).
pub(crate) fn visit(w: &[u32], p: Vec2, mut offer: impl FnMut(WaterLevel)) {
    if !(p.x.is_finite() && p.y.is_finite()) {
        return;
    }
    if w[header::FLAGS] & 1 != 0 {
        offer(WaterLevel {
            height: f(w[header::OCEAN_LEVEL]),
            body: BodyId::OCEAN,
            material: w[header::OCEAN_MATERIAL],
            depth: f32::INFINITY,
            flow: Vec2::ZERO,
        });
    }
    let size = f(w[header::ROOT_SIZE]);
    let (mut bx, mut by) = (f(w[header::ROOT_X]), f(w[header::ROOT_Y]));
    if !(size > 0.0 && p.x >= bx && p.y >= by && p.x < bx + size && p.y < by + size) {
        return;
    }
    let nodes = w[header::NODES] as usize;
    let mut bs = size;
    let mut node = 0usize;
    // Validated words have children after parents, so this descends at most node-count
    // times; the depth bound keeps it short.
    for _ in 0..=MAX_QUADTREE_DEPTH {
        let (a, b) = (w[nodes + 2 * node], w[nodes + 2 * node + 1]);
        if b == NODE_INTERNAL {
            let half = bs * 0.5;
            let qx = p.x >= bx + half;
            let qy = p.y >= by + half;
            if qx {
                bx += half;
            }
            if qy {
                by += half;
            }
            bs = half;
            node = a as usize + usize::from(qx) + 2 * usize::from(qy);
            continue;
        }
        let items = w[header::ITEMS] as usize;
        for k in 0..b as usize {
            let it = items + (a as usize + k) * ITEM_WORDS as usize;
            let (kind, index) = (w[it] >> KIND_SHIFT, w[it] & (MAX_BODIES - 1));
            match kind {
                ITEM_LAKE_INSIDE | ITEM_LAKE_PARTIAL => {
                    let inside = kind == ITEM_LAKE_INSIDE || {
                        // Far edges: the base parity and the breakpoints at or below p.y.
                        let e0 = w[header::EDGES] as usize + w[it + 1] as usize;
                        let locals = w[it + 2] as usize;
                        let mut inside = w[it + 3] >> 31 != 0;
                        let b0 = e0 + locals * 4;
                        for k in 0..(w[it + 3] & !(1 << 31)) as usize {
                            if f(w[b0 + k]) <= p.y {
                                inside = !inside;
                            }
                        }
                        // Local edges: the crossing test.
                        for e in 0..locals {
                            let q = e0 + e * 4;
                            if crosses(f(w[q]), f(w[q + 1]), f(w[q + 2]), f(w[q + 3]), p) {
                                inside = !inside;
                            }
                        }
                        inside
                    };
                    if inside {
                        let l = w[header::LAKES] as usize + index as usize * 2;
                        offer(WaterLevel {
                            height: f(w[l]),
                            body: BodyId::lake(index),
                            material: w[l + 1],
                            depth: f32::INFINITY,
                            flow: Vec2::ZERO,
                        });
                    }
                }
                ITEM_RIVER_TILE => {
                    if let Some(l) = sample_tile(w, index as usize, p) {
                        offer(l);
                    }
                }
                _ => {}
            }
        }
        break;
    }
}

/// Every lake's and river's horizontal bounds, material and height range over validated
/// words: lakes from the quadtree leaves that hold them (clamped to the leaf), rivers from
/// their tiles (water texels only). Lakes first, by index, then rivers, by index.
pub(crate) fn bodies(w: &[u32]) -> Vec<BodyBounds> {
    let lakes = w[header::LAKE_COUNT] as usize;
    let mut lake_boxes = vec![Aabb::empty(); lakes];
    let size = f(w[header::ROOT_SIZE]);
    if size > 0.0 {
        let nodes = w[header::NODES] as usize;
        let items = w[header::ITEMS] as usize;
        let node_count = w[header::NODE_COUNT] as usize;
        // Validated words have children after parents: the walk ends.
        let mut stack = vec![(0usize, f(w[header::ROOT_X]), f(w[header::ROOT_Y]), size)];
        while let Some((node, bx, by, bs)) = stack.pop() {
            if node >= node_count {
                continue;
            }
            let (a, b) = (w[nodes + 2 * node], w[nodes + 2 * node + 1]);
            if b == NODE_INTERNAL {
                let half = bs * 0.5;
                for (k, (dx, dy)) in [(0.0, 0.0), (half, 0.0), (0.0, half), (half, half)]
                    .into_iter()
                    .enumerate()
                {
                    stack.push((a as usize + k, bx + dx, by + dy, half));
                }
                continue;
            }
            for k in 0..b as usize {
                let it = items + (a as usize + k) * ITEM_WORDS as usize;
                let (kind, index) = (w[it] >> KIND_SHIFT, (w[it] & (MAX_BODIES - 1)) as usize);
                if matches!(kind, ITEM_LAKE_INSIDE | ITEM_LAKE_PARTIAL) && index < lakes {
                    lake_boxes[index].add(Vec2::new(bx, by));
                    lake_boxes[index].add(Vec2::new(bx + bs, by + bs));
                }
            }
        }
    }
    let mut out = Vec::new();
    for (i, b) in lake_boxes.iter().enumerate() {
        if b.is_empty() {
            continue;
        }
        let l = w[header::LAKES] as usize + i * LAKE_WORDS as usize;
        let h = f(w[l]);
        out.push(BodyBounds {
            body: BodyId::lake(i as u32),
            material: w[l + 1],
            min: b.min,
            max: b.max,
            height: (h, h),
        });
    }
    let n = w[header::TILE_TEXELS] as usize;
    let side = n + 1;
    let mut rivers: BTreeMap<u32, BodyBounds> = BTreeMap::new();
    for t in 0..w[header::TILE_COUNT] as usize {
        let r = w[header::TILES] as usize + t * TILE_WORDS as usize;
        let origin = Vec2::new(f(w[r]), f(w[r + 1]));
        let inv = f(w[r + 2]);
        let (river, material, data) = (w[r + 3], w[r + 4], w[r + 5] as usize);
        let mut lo = f32::INFINITY;
        let mut hi = f32::NEG_INFINITY;
        for k in 0..side * side {
            let h = w[data + k * TEXEL_WORDS as usize];
            if h != TEXEL_NONE {
                lo = lo.min(f(h));
                hi = hi.max(f(h));
            }
        }
        if !(lo <= hi) || !(inv > 0.0) {
            continue;
        }
        let far = origin + Vec2::splat(n as f32 / inv);
        let e = rivers.entry(river).or_insert(BodyBounds {
            body: BodyId::river(river),
            material,
            min: origin,
            max: far,
            height: (lo, hi),
        });
        e.min = e.min.min(origin);
        e.max = e.max.max(far);
        e.height = (e.height.0.min(lo), e.height.1.max(hi));
    }
    out.extend(rivers.into_values());
    out
}
