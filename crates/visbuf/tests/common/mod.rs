//! Test meshes and independent decoders, shared by the integration tests and the benches
//! (`#[path]`-included there).
#![allow(dead_code)]

/// A regular grid of `n x n` quads, two triangles each: `(n + 1)^2` vertices, `2 n^2`
/// triangles, counter-clockwise seen from +z.
pub fn grid(n: u32) -> (Vec<u32>, u32) {
    let mut idx = Vec::with_capacity((6 * n * n) as usize);
    let w = n + 1;
    for y in 0..n {
        for x in 0..n {
            let a = y * w + x;
            let (b, c, d) = (a + 1, a + w, a + w + 1);
            idx.extend_from_slice(&[a, b, d, a, d, c]);
        }
    }
    (idx, w * w)
}

/// Vertex positions of [`grid`] on the unit square, z = 0.
pub fn grid_positions(n: u32) -> Vec<[f32; 3]> {
    let w = n + 1;
    (0..w * w)
        .map(|i| [(i % w) as f32 / n as f32, (i / w) as f32 / n as f32, 0.0])
        .collect()
}

/// A closed UV sphere: `stacks` rings of latitude (poles included as single vertices) and
/// `slices` of longitude: `(stacks - 1) * slices + 2` vertices, `2 * slices * (stacks - 1)`
/// triangles.
pub fn uv_sphere(stacks: u32, slices: u32) -> (Vec<u32>, u32) {
    let ring = |s: u32, j: u32| 1 + (s - 1) * slices + (j % slices);
    let south = 1 + (stacks - 1) * slices;
    let mut idx = Vec::new();
    for j in 0..slices {
        idx.extend_from_slice(&[0, ring(1, j + 1), ring(1, j)]);
    }
    for s in 1..stacks - 1 {
        for j in 0..slices {
            let (a, b, c, d) = (
                ring(s, j),
                ring(s, j + 1),
                ring(s + 1, j),
                ring(s + 1, j + 1),
            );
            idx.extend_from_slice(&[a, b, d, a, d, c]);
        }
    }
    for j in 0..slices {
        idx.extend_from_slice(&[south, ring(stacks - 1, j), ring(stacks - 1, j + 1)]);
    }
    (idx, south + 1)
}

/// A random triangle soup: `triangles` triangles of three distinct vertices drawn uniformly
/// from `vertices` (`testkit::Rng` seeded with `seed`).
pub fn soup(triangles: u32, vertices: u32, seed: u64) -> (Vec<u32>, u32) {
    let mut rng = testkit::Rng::new(seed);
    let mut pick = || rng.below(u64::from(vertices)) as u32;
    let mut idx = Vec::with_capacity(3 * triangles as usize);
    for _ in 0..triangles {
        let a = pick();
        let mut b = a;
        while b == a {
            b = pick();
        }
        let mut c = a;
        while c == a || c == b {
            c = pick();
        }
        idx.extend_from_slice(&[a, b, c]);
    }
    (idx, vertices)
}

/// Parses the `v` and `f` lines of an OBJ (triangles only, 1-based, `a/b/c` forms ok).
pub fn parse_obj(src: &str) -> (Vec<[f32; 3]>, Vec<u32>) {
    let mut pos = Vec::new();
    let mut idx = Vec::new();
    for line in src.lines() {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let v: Vec<f32> = it.take(3).map(|x| x.parse().unwrap()).collect();
                pos.push([v[0], v[1], v[2]]);
            }
            Some("f") => {
                for c in it.take(3) {
                    let i: u32 = c.split('/').next().unwrap().parse().unwrap();
                    idx.push(i - 1);
                }
            }
            _ => {}
        }
    }
    (pos, idx)
}

/// The Stanford bunny (low-resolution version, 1 839 vertices, 3 674 triangles).
pub fn bunny() -> (Vec<[f32; 3]>, Vec<u32>) {
    parse_obj(include_str!("../data/bunny.obj"))
}

/// Independent check of a provoking-vertex encoding: every triangle's first vertex carries
/// its index, the corners are a rotation (same winding) of the source triangle, the first
/// `vertex_count` output vertices are the source vertices, payloads fit 16 bits.
pub fn check_provoking(src: &[u32], vertex_count: u32, m: &visbuf::PrimitiveIdMesh) {
    check_common(src, vertex_count, m);
    for (t, (s, o)) in src.chunks(3).zip(m.indices.chunks(3)).enumerate() {
        assert_eq!(
            m.payloads[o[0] as usize], t as u32,
            "triangle {t}: first vertex payload"
        );
        let mapped = [
            m.remap[o[0] as usize],
            m.remap[o[1] as usize],
            m.remap[o[2] as usize],
        ];
        let rotations = [[s[0], s[1], s[2]], [s[1], s[2], s[0]], [s[2], s[0], s[1]]];
        assert!(
            rotations.contains(&mapped),
            "triangle {t}: {mapped:?} not a rotation of {s:?}"
        );
    }
}

/// Independent check of an XOR encoding: every triangle's three payloads XOR to its index
/// and its corners copy the source corners in order.
pub fn check_xor(src: &[u32], vertex_count: u32, m: &visbuf::PrimitiveIdMesh) {
    check_common(src, vertex_count, m);
    for (t, (s, o)) in src.chunks(3).zip(m.indices.chunks(3)).enumerate() {
        let x = o.iter().fold(0, |acc, &v| acc ^ m.payloads[v as usize]);
        assert_eq!(x, t as u32, "triangle {t}: XOR of payloads");
        let mapped = [
            m.remap[o[0] as usize],
            m.remap[o[1] as usize],
            m.remap[o[2] as usize],
        ];
        assert_eq!(mapped, [s[0], s[1], s[2]], "triangle {t}: corners");
    }
}

fn check_common(src: &[u32], vertex_count: u32, m: &visbuf::PrimitiveIdMesh) {
    assert_eq!(m.indices.len(), src.len());
    assert_eq!(m.source_vertex_count, vertex_count);
    assert_eq!(m.remap.len(), m.payloads.len());
    for v in 0..vertex_count {
        assert_eq!(m.remap[v as usize], v);
    }
    assert!(m.remap.iter().all(|&r| r < vertex_count));
    assert!(m.payloads.iter().all(|&p| p < 65536));
    assert!(m.indices.iter().all(|&i| (i as usize) < m.remap.len()));
    // Packed form decodes to the same source vertices and payloads.
    for (k, p) in m.packed_indices().into_iter().enumerate() {
        let o = m.indices[k] as usize;
        assert_eq!((p >> 16, p & 0xffff), (m.payloads[o], m.remap[o]));
    }
}

/// Maximum matching of triangles to distinct vertices by Kuhn's simple augmenting paths
/// (recursive, small meshes only): the reference for the provoking encoder's optimality.
pub fn kuhn_matching(src: &[u32], vertex_count: u32) -> u32 {
    fn try_tri(t: usize, src: &[u32], seen: &mut [bool], owner: &mut [Option<usize>]) -> bool {
        for &v in &src[3 * t..3 * t + 3] {
            if seen[v as usize] {
                continue;
            }
            seen[v as usize] = true;
            if owner[v as usize].is_none_or(|o| try_tri(o, src, seen, owner)) {
                owner[v as usize] = Some(t);
                return true;
            }
        }
        false
    }
    let mut owner = vec![None; vertex_count as usize];
    let mut n = 0;
    for t in 0..src.len() / 3 {
        let mut seen = vec![false; vertex_count as usize];
        if try_tri(t, src, &mut seen, &mut owner) {
            n += 1;
        }
    }
    n
}
