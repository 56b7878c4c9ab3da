//! Mesh preprocessing so the laydown's pixel shader can recover its triangle's primitive
//! ID without `@builtin(primitive_index)` (seed 000, "Visibility Buffer").
//!
//! The GPU has three ways to learn the primitive ID, chosen by adapter features:
//!
//! 1. `@builtin(primitive_index)` (`Features::PRIMITIVE_INDEX`): no preprocessing.
//! 2. **Provoking vertex** ([`encode_provoking`]): every triangle's first vertex carries the
//!    triangle's ID as a flat (`@interpolate(flat)`, first-vertex) payload. Each triangle
//!    needs a vertex of its own to be first; triangles are rotated (winding kept) so one
//!    of their vertices that no other triangle claimed leads, and a vertex is duplicated
//!    only when all three are taken.
//! 3. **XOR** ([`encode_xor`]), HFW's scheme: each vertex carries a 16-bit payload and a
//!    triangle's ID is the XOR of its three vertices' payloads, read with per-vertex
//!    attributes (`Features::SHADER_PER_VERTEX`). The order of the vertices no longer
//!    matters, so the hardware may rotate triangles freely; a vertex is duplicated only
//!    when all three of a triangle's payloads are already fixed and do not XOR to its ID.
//!
//! Both encoders take 16-bit-indexable triangle lists (at most
//! [`MAX_VERTICES_PER_GEOMETRY`] vertices and
//! [`MAX_PRIMITIVES_PER_GEOMETRY`] triangles) and
//! return a [`PrimitiveIdMesh`]: the new index buffer (triangle `t` is still primitive
//! `t`), a remap from output vertices to source vertices (the first `vertex_count` output
//! vertices are the source vertices in order, added ones follow) and one payload per
//! output vertex. A renderer either duplicates vertex data through [`PrimitiveIdMesh::remap`]
//! or, as HFW did, keeps the vertex buffer and uses [`PrimitiveIdMesh::packed_indices`]:
//! 32-bit indices whose top 16 bits are the payload and low 16 bits the source vertex.
//!
//! # Strategies
//!
//! Each scheme has the talk's greedy pass and a better one; all four give valid meshes.
//!
//! | function | method | vertices added |
//! |---|---|---|
//! | [`encode_provoking_greedy`] | in triangle order, first corner still free leads | baseline |
//! | [`encode_provoking`] | maximum bipartite matching of triangles to vertices (Hopcroft-Karp) | the minimum possible |
//! | [`encode_xor_greedy`] | the talk's: in triangle order, fix the free corners, add a vertex on a mismatch | baseline |
//! | [`encode_xor`] | peeling (solve triangles last-to-first from vertices used once), duplicating a least-used vertex when stuck, then merging duplicates with equal payloads | close to the provoking minimum |
//!
//! Every closed mesh has about twice as many triangles as vertices, so each scheme must add
//! at least `triangles - vertices` vertices there (a triangle needs one vertex, or one
//! payload degree of freedom, of its own). BENCHMARKS.md has the measured growth.
//!
//! ```
//! // Two triangles sharing an edge: 4 vertices are enough for both schemes.
//! let quad = [0u32, 1, 2, 2, 1, 3];
//! let p = visbuf::encode_provoking(&quad, 4)?;
//! assert_eq!(p.added_vertices(), 0);
//! for t in 0..2 {
//!     assert_eq!(p.payloads[p.indices[3 * t] as usize], t as u32); // first vertex carries t
//! }
//! let x = visbuf::encode_xor(&quad, 4)?;
//! for t in 0..2 {
//!     let c = &x.indices[3 * t..3 * t + 3];
//!     let id = x.payloads[c[0] as usize] ^ x.payloads[c[1] as usize] ^ x.payloads[c[2] as usize];
//!     assert_eq!(id, t as u32);
//! }
//! # Ok::<(), visbuf::Error>(())
//! ```

use alloc::collections::VecDeque;
use alloc::vec;
use alloc::vec::Vec;

use crate::{Error, MAX_PRIMITIVES_PER_GEOMETRY};

/// Most vertices a geometry may have: 16-bit indices.
pub const MAX_VERTICES_PER_GEOMETRY: u32 = 1 << 16;
/// Vertex count limit of [`PrimitiveIdMesh::packed_indices`] (16-bit vertex field).
pub const MAX_PACKED_VERTICES: u32 = 1 << 16;

const NIL: u32 = u32::MAX;

/// A mesh preprocessed for one primitive-ID scheme. See the [module docs](self).
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct PrimitiveIdMesh {
    /// Triangle list over output vertices, triangle `t` being primitive `t` (provoking:
    /// rotated so its first vertex carries `t`; XOR: corners in the source order).
    pub indices: Vec<u32>,
    /// For each output vertex, the source vertex whose data it copies. The first
    /// `source_vertex_count` entries are `0, 1, 2, ...`.
    pub remap: Vec<u32>,
    /// For each output vertex, its payload (below 65 536). Vertices whose payload no
    /// triangle needs hold 0.
    pub payloads: Vec<u32>,
    /// Vertices in the source mesh.
    pub source_vertex_count: u32,
}

impl PrimitiveIdMesh {
    /// Output vertices: source vertices plus added ones.
    #[must_use]
    pub fn vertex_count(&self) -> u32 {
        self.remap.len() as u32
    }

    /// Vertices the encoding added.
    #[must_use]
    pub fn added_vertices(&self) -> u32 {
        self.vertex_count() - self.source_vertex_count
    }

    /// Triangles (= primitives).
    #[must_use]
    pub fn triangle_count(&self) -> u32 {
        (self.indices.len() / 3) as u32
    }

    /// The primitive ID the provoking-vertex scheme reads for triangle `t`: the payload
    /// of its first vertex. `None` past the last triangle.
    #[must_use]
    pub fn provoking_id(&self, t: u32) -> Option<u32> {
        let i = *self.indices.get(3 * t as usize)?;
        self.payloads.get(i as usize).copied()
    }

    /// The primitive ID the XOR scheme reads for triangle `t`. `None` past the last
    /// triangle.
    #[must_use]
    pub fn xor_id(&self, t: u32) -> Option<u32> {
        let c = self.indices.get(3 * t as usize..3 * t as usize + 3)?;
        let p = |i: u32| self.payloads.get(i as usize).copied();
        Some(p(c[0])? ^ p(c[1])? ^ p(c[2])?)
    }

    /// HFW's form: one 32-bit index per corner, `payload << 16 | source vertex`, over the
    /// unchanged source vertex buffer (the vertex stage fetches with the low 16 bits and
    /// passes the high 16 on). Always fits: source meshes have at most
    /// [`MAX_PACKED_VERTICES`] vertices and payloads are below 65 536.
    #[must_use]
    pub fn packed_indices(&self) -> Vec<u32> {
        self.indices
            .iter()
            .map(|&i| (self.payloads[i as usize] << 16) | self.remap[i as usize])
            .collect()
    }

    /// Vertex data for the output vertices, copied from the source through
    /// [`remap`](Self::remap). Errors when `source` has fewer than `source_vertex_count`
    /// entries.
    pub fn remap_vertices<T: Copy>(&self, source: &[T]) -> Result<Vec<T>, Error> {
        if source.len() < self.source_vertex_count as usize {
            return Err(Error::VertexDataTooShort {
                len: source.len(),
                needed: self.source_vertex_count,
            });
        }
        Ok(self.remap.iter().map(|&r| source[r as usize]).collect())
    }
}

/// Checks a triangle list against the limits; returns the triangle count.
fn validate<I: Copy + Into<u32>>(indices: &[I], vertex_count: u32) -> Result<u32, Error> {
    if vertex_count > MAX_VERTICES_PER_GEOMETRY {
        return Err(Error::TooManyVertices {
            count: vertex_count,
            limit: MAX_VERTICES_PER_GEOMETRY,
        });
    }
    if !indices.len().is_multiple_of(3) {
        return Err(Error::IndexCountNotMultipleOf3 { len: indices.len() });
    }
    let triangles = indices.len() / 3;
    if triangles > MAX_PRIMITIVES_PER_GEOMETRY as usize {
        return Err(Error::TooManyPrimitives {
            count: triangles as u64,
            limit: MAX_PRIMITIVES_PER_GEOMETRY,
        });
    }
    for (k, &i) in indices.iter().enumerate() {
        let i: u32 = i.into();
        if i >= vertex_count {
            return Err(Error::IndexOutOfRange {
                triangle: (k / 3) as u32,
                index: i,
                vertex_count,
            });
        }
    }
    Ok(triangles as u32)
}

fn identity_mesh<I: Copy + Into<u32>>(indices: &[I], vertex_count: u32) -> PrimitiveIdMesh {
    PrimitiveIdMesh {
        indices: indices.iter().map(|&i| i.into()).collect(),
        remap: (0..vertex_count).collect(),
        payloads: vec![0; vertex_count as usize],
        source_vertex_count: vertex_count,
    }
}

impl PrimitiveIdMesh {
    /// Adds a copy of source vertex `of` with `payload`; returns its output index.
    fn add_vertex(&mut self, of: u32, payload: u32) -> u32 {
        let id = self.remap.len() as u32;
        self.remap.push(of);
        self.payloads.push(payload);
        id
    }
}

/// Rotates triangle `t` of `indices` left by `k` corners (winding kept).
fn rotate(indices: &mut [u32], t: usize, k: usize) {
    indices[3 * t..3 * t + 3].rotate_left(k);
}

/// The provoking-vertex encoding with the fewest added vertices: a maximum matching of
/// triangles to distinct vertices (Hopcroft-Karp, `O(E sqrt(V))`); each matched triangle
/// is rotated so its vertex leads, each unmatched one gets a copy of its first vertex.
pub fn encode_provoking<I: Copy + Into<u32>>(
    indices: &[I],
    vertex_count: u32,
) -> Result<PrimitiveIdMesh, Error> {
    let triangles = validate(indices, vertex_count)?;
    let mut mesh = identity_mesh(indices, vertex_count);
    let matched = max_matching(&mesh.indices, triangles, vertex_count);
    for (t, &v) in matched.iter().enumerate() {
        if v == NIL {
            let first = mesh.indices[3 * t];
            mesh.indices[3 * t] = mesh.add_vertex(first, t as u32);
        } else {
            let k = (0..3).find(|&k| mesh.indices[3 * t + k] == v).unwrap_or(0);
            rotate(&mut mesh.indices, t, k);
            mesh.payloads[v as usize] = t as u32;
        }
    }
    Ok(mesh)
}

/// The talk's provoking-vertex pass, the baseline: in triangle order, the first corner no
/// earlier triangle claimed is rotated to lead; if all three are claimed the first corner
/// is duplicated.
pub fn encode_provoking_greedy<I: Copy + Into<u32>>(
    indices: &[I],
    vertex_count: u32,
) -> Result<PrimitiveIdMesh, Error> {
    let triangles = validate(indices, vertex_count)?;
    let mut mesh = identity_mesh(indices, vertex_count);
    let mut claimed = vec![false; vertex_count as usize];
    for t in 0..triangles as usize {
        match (0..3).find(|&k| !claimed[mesh.indices[3 * t + k] as usize]) {
            Some(k) => {
                let v = mesh.indices[3 * t + k];
                claimed[v as usize] = true;
                mesh.payloads[v as usize] = t as u32;
                rotate(&mut mesh.indices, t, k);
            }
            None => {
                let first = mesh.indices[3 * t];
                mesh.indices[3 * t] = mesh.add_vertex(first, t as u32);
            }
        }
    }
    Ok(mesh)
}

/// Compressed adjacency: for each vertex, the triangles using it (once per triangle).
struct Incidence {
    start: Vec<u32>,
    tris: Vec<u32>,
}

impl Incidence {
    fn new(indices: &[u32], vertex_count: u32, odd_only: bool) -> Incidence {
        let n = vertex_count as usize;
        let mut start = vec![0u32; n + 1];
        let each = |f: &mut dyn FnMut(u32, u32)| {
            for (t, c) in indices.chunks_exact(3).enumerate() {
                for k in 0..3 {
                    let v = c[k];
                    if c[..k].contains(&v) {
                        continue; // count each distinct vertex once
                    }
                    let mult = c.iter().filter(|&&x| x == v).count();
                    if odd_only && mult % 2 == 0 {
                        continue;
                    }
                    f(v, t as u32);
                }
            }
        };
        each(&mut |v, _| start[v as usize + 1] += 1);
        for i in 0..n {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut tris = vec![0u32; start[n] as usize];
        each(&mut |v, t| {
            tris[fill[v as usize] as usize] = t;
            fill[v as usize] += 1;
        });
        Incidence { start, tris }
    }

    fn of(&self, v: u32) -> &[u32] {
        &self.tris[self.start[v as usize] as usize..self.start[v as usize + 1] as usize]
    }
}

/// Hopcroft-Karp: for each triangle, the vertex it is matched to, or `NIL`.
fn max_matching(indices: &[u32], triangles: u32, vertex_count: u32) -> Vec<u32> {
    let t_count = triangles as usize;
    let mut match_t = vec![NIL; t_count];
    let mut match_v = vec![NIL; vertex_count as usize];
    // Greedy start, least-shared vertex first: most triangles match here already.
    let inc = Incidence::new(indices, vertex_count, false);
    let degree = |v: u32| inc.of(v).len();
    for t in 0..t_count {
        let c = &indices[3 * t..3 * t + 3];
        if let Some(&v) = c
            .iter()
            .filter(|&&v| match_v[v as usize] == NIL)
            .min_by_key(|&&v| degree(v))
        {
            match_t[t] = v;
            match_v[v as usize] = t as u32;
        }
    }
    let mut dist = vec![u32::MAX; t_count];
    let mut queue = VecDeque::new();
    let mut stack: Vec<(u32, u8)> = Vec::new();
    loop {
        // BFS layers from the free triangles.
        queue.clear();
        for t in 0..t_count {
            if match_t[t] == NIL {
                dist[t] = 0;
                queue.push_back(t as u32);
            } else {
                dist[t] = u32::MAX;
            }
        }
        let mut found = false;
        while let Some(t) = queue.pop_front() {
            for &v in &indices[3 * t as usize..3 * t as usize + 3] {
                let t2 = match_v[v as usize];
                if t2 == NIL {
                    found = true;
                } else if dist[t2 as usize] == u32::MAX {
                    dist[t2 as usize] = dist[t as usize] + 1;
                    queue.push_back(t2);
                }
            }
        }
        if !found {
            return match_t;
        }
        // Vertex-disjoint augmenting paths along the layers, iterative DFS.
        for root in 0..t_count {
            if match_t[root] != NIL {
                continue;
            }
            stack.clear();
            stack.push((root as u32, 0));
            while let Some(&mut (t, ref mut e)) = stack.last_mut() {
                if *e >= 3 {
                    dist[t as usize] = u32::MAX; // dead end: never revisit this phase
                    stack.pop();
                    continue;
                }
                let v = indices[3 * t as usize + *e as usize];
                *e += 1;
                let t2 = match_v[v as usize];
                if t2 == NIL {
                    // Augment: each triangle on the stack takes the vertex it reached.
                    let mut take = v;
                    for &(u, _) in stack.iter().rev() {
                        let prev = match_t[u as usize];
                        match_t[u as usize] = take;
                        match_v[take as usize] = u;
                        take = prev;
                    }
                    stack.clear();
                } else if dist[t2 as usize] != u32::MAX && dist[t2 as usize] == dist[t as usize] + 1
                {
                    stack.push((t2, 0));
                }
            }
        }
    }
}

/// XOR of the payloads of triangle `t`'s corners other than `skip` (pass `NIL` for all).
fn xor_others(mesh: &PrimitiveIdMesh, t: usize, skip: u32) -> u32 {
    mesh.indices[3 * t..3 * t + 3]
        .iter()
        .filter(|&&v| v != skip)
        .fold(0, |acc, &v| acc ^ mesh.payloads[v as usize])
}

/// HFW's XOR encoding as the talk describes it, the baseline: in triangle order, a
/// triangle with corners whose payload is not yet fixed fixes them (all but one to 0, the
/// last to make the XOR right); a triangle whose corners are all fixed and XOR to another
/// ID reuses a copy of one of its vertices that has the needed payload, or adds one.
///
/// A corner that appears twice in a triangle cancels out of its XOR and is not counted as
/// free there.
pub fn encode_xor_greedy<I: Copy + Into<u32>>(
    indices: &[I],
    vertex_count: u32,
) -> Result<PrimitiveIdMesh, Error> {
    let triangles = validate(indices, vertex_count)?;
    let mut mesh = identity_mesh(indices, vertex_count);
    let mut fixed = vec![false; vertex_count as usize];
    // Copies added so far of each source vertex: (payload, output vertex), small lists.
    let mut copies: Vec<Vec<(u32, u32)>> = vec![Vec::new(); vertex_count as usize];
    for t in 0..triangles as usize {
        let c = [
            mesh.indices[3 * t],
            mesh.indices[3 * t + 1],
            mesh.indices[3 * t + 2],
        ];
        let odd = |v: u32| c.iter().filter(|&&x| x == v).count() % 2 == 1;
        let mut free: Vec<u32> = Vec::new();
        for &v in &c {
            if (v as usize) < fixed.len() && !fixed[v as usize] && odd(v) && !free.contains(&v) {
                free.push(v);
            }
        }
        if let Some((&last, rest)) = free.split_last() {
            for &v in rest {
                fixed[v as usize] = true;
                mesh.payloads[v as usize] = 0;
            }
            fixed[last as usize] = true;
            mesh.payloads[last as usize] = 0;
            mesh.payloads[last as usize] = t as u32 ^ xor_others(&mesh, t, NIL);
            continue;
        }
        if xor_others(&mesh, t, NIL) == t as u32 {
            continue;
        }
        // All fixed, mismatch: replace one corner by a copy with the payload that fits.
        // Corners that cancelled out (a vertex appearing twice) may still be free: the
        // replacement makes them count, so their current payload becomes final.
        for &v in &c {
            fixed[v as usize] = true;
        }
        let mut done = false;
        for k in 0..3 {
            let others =
                mesh.payloads[c[(k + 1) % 3] as usize] ^ mesh.payloads[c[(k + 2) % 3] as usize];
            let need = t as u32 ^ others;
            let src = mesh.remap[c[k] as usize];
            if let Some(&(_, v)) = copies[src as usize].iter().find(|&&(p, _)| p == need) {
                mesh.indices[3 * t + k] = v;
                done = true;
                break;
            }
        }
        if !done {
            let others = mesh.payloads[c[1] as usize] ^ mesh.payloads[c[2] as usize];
            let need = t as u32 ^ others;
            let src = mesh.remap[c[0] as usize];
            let v = mesh.add_vertex(src, need);
            copies[src as usize].push((need, v));
            mesh.indices[3 * t] = v;
        }
    }
    Ok(mesh)
}

/// The XOR encoding with few added vertices: peeling. A vertex used by exactly one
/// pending triangle can always make that triangle's XOR right, whatever the others hold,
/// so that triangle is set aside (solved later, in reverse order) and its other vertices
/// lose a use; when no vertex is used exactly once, the least-used vertex gets a copy in
/// one of its triangles. Payloads are then assigned in reverse, unused vertices hold 0,
/// and copies that ended with the same payload as another copy of the same source vertex
/// are merged.
pub fn encode_xor<I: Copy + Into<u32>>(
    indices: &[I],
    vertex_count: u32,
) -> Result<PrimitiveIdMesh, Error> {
    let triangles = validate(indices, vertex_count)? as usize;
    let mut mesh = identity_mesh(indices, vertex_count);
    let n = vertex_count as usize;
    // Uses per vertex: pending triangles in which it appears an odd number of times (an
    // even count cancels out of the XOR).
    let inc = Incidence::new(&mesh.indices, vertex_count, true);
    let mut uses: Vec<u32> = (0..vertex_count).map(|v| inc.of(v).len() as u32).collect();
    let mut pending = vec![true; triangles];
    let mut order: Vec<(u32, u32)> = Vec::with_capacity(triangles);
    // Vertices by use count (lazy buckets; counts only fall).
    let max_uses = uses.iter().copied().max().unwrap_or(0) as usize;
    let mut buckets: Vec<Vec<u32>> = vec![Vec::new(); max_uses + 1];
    for v in 0..vertex_count {
        buckets[uses[v as usize] as usize].push(v);
    }
    let mut lowest = 0usize;
    let mut left = triangles;

    // Removes triangle t with pivot p, updating use counts of its odd-multiplicity corners.
    let remove = |t: usize,
                  pivot: u32,
                  mesh: &PrimitiveIdMesh,
                  uses: &mut Vec<u32>,
                  pending: &mut Vec<bool>,
                  order: &mut Vec<(u32, u32)>,
                  buckets: &mut Vec<Vec<u32>>,
                  lowest: &mut usize| {
        pending[t] = false;
        order.push((t as u32, pivot));
        let c = &mesh.indices[3 * t..3 * t + 3];
        for k in 0..3 {
            let v = c[k];
            if (v as usize) >= n || c[..k].contains(&v) {
                continue;
            }
            if c.iter().filter(|&&x| x == v).count() % 2 == 1 {
                uses[v as usize] -= 1;
                let u = uses[v as usize] as usize;
                buckets[u].push(v);
                *lowest = (*lowest).min(u);
            }
        }
    };

    while left > 0 {
        // Lowest bucket with a live entry of 1 or more uses.
        while lowest < buckets.len() {
            match buckets[lowest].last() {
                Some(&v) if uses[v as usize] as usize != lowest || lowest == 0 => {
                    buckets[lowest].pop();
                }
                Some(_) => break,
                None => lowest += 1,
            }
        }
        let Some(&v) = buckets.get(lowest).and_then(|b| b.last()) else {
            break; // unreachable while triangles are pending: each has an odd corner
        };
        let t = inc
            .of(v)
            .iter()
            .copied()
            .find(|&t| pending[t as usize])
            .unwrap_or(0) as usize;
        if lowest == 1 {
            buckets[1].pop();
            remove(
                t,
                v,
                &mesh,
                &mut uses,
                &mut pending,
                &mut order,
                &mut buckets,
                &mut lowest,
            );
        } else {
            // Stuck: give t a copy of v (its only use), then peel t through the copy.
            let k = (0..3).find(|&k| mesh.indices[3 * t + k] == v).unwrap_or(0);
            let copy = mesh.add_vertex(v, 0);
            mesh.indices[3 * t + k] = copy;
            // v lost one occurrence in t: an odd count became even (it leaves t's XOR).
            uses[v as usize] -= 1;
            buckets[uses[v as usize] as usize].push(v);
            lowest = lowest.min(uses[v as usize] as usize);
            remove(
                t,
                copy,
                &mesh,
                &mut uses,
                &mut pending,
                &mut order,
                &mut buckets,
                &mut lowest,
            );
        }
        left -= 1;
    }
    // Solve in reverse: each pivot takes the value that makes its triangle right; no later
    // step touches a vertex of an already solved triangle's XOR except through its pivot.
    for &(t, pivot) in order.iter().rev() {
        let others = xor_others(&mesh, t as usize, pivot);
        mesh.payloads[pivot as usize] = t ^ others;
    }
    merge_copies(&mut mesh);
    Ok(mesh)
}

/// Merges added vertices that copy the same source vertex with the same payload as an
/// earlier output vertex, and renumbers the survivors.
fn merge_copies(mesh: &mut PrimitiveIdMesh) {
    let n = mesh.source_vertex_count as usize;
    if mesh.remap.len() == n {
        return;
    }
    // (source, payload, output vertex), sources first so they win.
    let mut keys: Vec<(u32, u32, u32)> = (0..mesh.remap.len() as u32)
        .map(|v| (mesh.remap[v as usize], mesh.payloads[v as usize], v))
        .collect();
    keys.sort_unstable();
    let mut target: Vec<u32> = (0..mesh.remap.len() as u32).collect();
    for w in keys.windows(2) {
        if w[0].0 == w[1].0 && w[0].1 == w[1].1 {
            target[w[1].2 as usize] = target[w[0].2 as usize];
        }
    }
    // Renumber the survivors (sources keep their numbers), then rewrite.
    let mut new_id = vec![NIL; mesh.remap.len()];
    let mut remap = Vec::with_capacity(mesh.remap.len());
    let mut payloads = Vec::with_capacity(mesh.remap.len());
    for v in 0..mesh.remap.len() {
        if target[v] as usize == v {
            new_id[v] = remap.len() as u32;
            remap.push(mesh.remap[v]);
            payloads.push(mesh.payloads[v]);
        }
    }
    for i in &mut mesh.indices {
        *i = new_id[target[*i as usize] as usize];
    }
    mesh.remap = remap;
    mesh.payloads = payloads;
}
