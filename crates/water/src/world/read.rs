//! Reading validated world words: the validation itself, the point query, the visit of
//! every covering body, and the bodies' bounds.

use alloc::collections::BTreeMap;
use alloc::vec;
use alloc::vec::Vec;

use glam::Vec2;

use super::geom::{Aabb, crosses, f, unpack2x16float};
use super::*;
use crate::math;

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
