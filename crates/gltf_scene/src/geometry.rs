//! One glTF primitive's triangles on their way to the renderer's meshes: triangulated,
//! flat normals where it has none, texture transform baked, MikkTSpace tangents, the back
//! sides of double-sided materials, winding flipped for mirroring instances, and split
//! into pieces within the renderer's 64k limits.

use std::collections::HashMap;

use scene::glam::{Vec2, Vec3, Vec4};
use scene::{MAX_PRIMITIVES_PER_MESH, MAX_VERTICES_PER_MESH, Mesh};

/// Triangle geometry with 32-bit indices, before splitting.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Geometry {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub uvs: Vec<Vec2>,
    pub tangents: Vec<Vec4>,
    /// Three per triangle, counter-clockwise front faces, each below the vertex count.
    pub indices: Vec<u32>,
}

/// Triangle-list indices from a primitive's `mode` (glTF 2.0 §3.7.2.1), or `None` for
/// points and lines. Strips and fans keep the winding of their first triangle; an
/// incomplete trailing triangle of a list is dropped.
pub(crate) fn triangulate(mode: gltf::mesh::Mode, idx: &[u32]) -> Option<Vec<u32>> {
    use gltf::mesh::Mode;
    let n = idx.len();
    Some(match mode {
        Mode::Triangles => idx[..n - n % 3].to_vec(),
        Mode::TriangleStrip => (0..n.saturating_sub(2))
            .flat_map(|i| {
                if i % 2 == 0 {
                    [idx[i], idx[i + 1], idx[i + 2]]
                } else {
                    [idx[i + 1], idx[i], idx[i + 2]]
                }
            })
            .collect(),
        Mode::TriangleFan => (0..n.saturating_sub(2))
            .flat_map(|i| [idx[i + 1], idx[i + 2], idx[0]])
            .collect(),
        Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip => return None,
    })
}

/// The unit normal of the triangle `a b c` (counter-clockwise front), +Y for a degenerate
/// one.
pub(crate) fn face_normal(a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    (b - a).cross(c - a).normalize_or(Vec3::Y)
}

impl Geometry {
    /// Flat shading: every triangle gets its own three vertices, with its face normal
    /// ([`face_normal`]); `uvs` per original vertex are carried along.
    pub(crate) fn flat(positions: &[Vec3], uvs: &[Vec2], indices: &[u32]) -> Self {
        let mut g = Geometry::default();
        for t in indices.chunks_exact(3) {
            let [a, b, c] = [t[0] as usize, t[1] as usize, t[2] as usize];
            let n = face_normal(positions[a], positions[b], positions[c]);
            for i in [a, b, c] {
                g.indices.push(g.positions.len() as u32);
                g.positions.push(positions[i]);
                g.normals.push(n);
                g.uvs.push(uvs[i]);
            }
        }
        g
    }

    /// MikkTSpace tangents (the glTF 2.0 recommendation), one per triangle corner, then
    /// vertices re-welded: corners of one vertex with different tangents become separate
    /// vertices. MikkTSpace sees only the triangles with three distinct corner positions;
    /// the others (and all of a geometry it rejects) get tangents orthogonal to their
    /// normals (`Vec3::any_orthonormal_vector`, handedness +1).
    ///
    /// MikkTSpace's bitangent follows +v of the coordinates it is given; glTF's runs up
    /// the image (a normal map's +Y is up, glTF 2.0 §3.9.3, what Blender's exporter writes
    /// and the Khronos viewer's derivative tangents give), where glTF's v runs down: so
    /// MikkTSpace is given `(u, 1 − v)`, and `w · n × t` points up the image.
    pub(crate) fn generate_tangents(&mut self) {
        struct Faces<'a> {
            g: &'a Geometry,
            /// The triangles MikkTSpace sees (indices into `g`'s triangles).
            tris: Vec<usize>,
            out: Vec<Vec4>,
        }
        impl Faces<'_> {
            fn corner(&self, face: usize, vert: usize) -> usize {
                self.g.indices[self.tris[face] * 3 + vert] as usize
            }
        }
        impl mikktspace::Geometry for Faces<'_> {
            fn num_faces(&self) -> usize {
                self.tris.len()
            }
            fn num_vertices_of_face(&self, _face: usize) -> usize {
                3
            }
            fn position(&self, face: usize, vert: usize) -> [f32; 3] {
                self.g.positions[self.corner(face, vert)].to_array()
            }
            fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
                self.g.normals[self.corner(face, vert)].to_array()
            }
            fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
                let uv = self.g.uvs[self.corner(face, vert)];
                [uv.x, 1.0 - uv.y]
            }
            fn set_tangent_encoded(&mut self, tangent: [f32; 4], face: usize, vert: usize) {
                let at = self.tris[face] * 3 + vert;
                self.out[at] = Vec4::from_array(tangent);
            }
        }
        let fallback = |n: Vec3| n.any_orthonormal_vector().extend(1.0);
        let mut faces = Faces {
            g: self,
            tris: self.mikktspace_triangles(),
            out: vec![Vec4::ZERO; self.indices.len()],
        };
        let ok = !faces.tris.is_empty() && mikktspace::generate_tangents(&mut faces);
        let corners = faces.out;
        if !ok {
            self.tangents = self.normals.iter().map(|&n| fallback(n)).collect();
            return;
        }
        let mut welded = Geometry::default();
        let mut map: HashMap<(u32, [u32; 4]), u32> = HashMap::new();
        for (k, &v) in self.indices.iter().enumerate() {
            let vi = v as usize;
            let mut t = corners[k];
            if !t.is_finite() || t.truncate().length_squared() < 1e-12 {
                t = fallback(self.normals[vi]);
            }
            let key = (v, t.to_array().map(f32::to_bits));
            let next = welded.positions.len() as u32;
            let at = *map.entry(key).or_insert(next);
            if at == next {
                welded.positions.push(self.positions[vi]);
                welded.normals.push(self.normals[vi]);
                welded.uvs.push(self.uvs[vi]);
                welded.tangents.push(t);
            }
            welded.indices.push(at);
        }
        *self = welded;
    }

    /// The triangles mikktspace 0.3 can take: three distinct corner positions, coordinates
    /// within ±1e30. Its port has two faults these avoid: when every triangle is
    /// degenerate (two corners welded into one) it computes `0 - 1` on a `usize`, and when
    /// every vertex falls into one cell of its welding grid (a zero extent) it indexes past
    /// its table; its cell arithmetic also needs finite extents.
    fn mikktspace_triangles(&self) -> Vec<usize> {
        let ok = |p: Vec3| p.abs().max_element() <= 1e30;
        self.indices
            .chunks_exact(3)
            .enumerate()
            .filter(|(_, t)| {
                let [a, b, c] = [0, 1, 2].map(|k| self.positions[t[k] as usize]);
                ok(a) && ok(b) && ok(c) && a != b && a != c && b != c
            })
            .map(|(i, _)| i)
            .collect()
    }

    /// Appends the back side of every triangle (for a double-sided material: the renderer
    /// culls back faces): vertices `n..2n` copy `0..n` with the whole tangent frame negated
    /// (normal, tangent and handedness, so the bitangent `w · n × t` turns too and a normal
    /// map's normal on the back is the front's negated, glTF 2.0 §3.9.2), and triangle
    /// `a b c` gets the twin `n+a, n+c, n+b` after all the front triangles.
    pub(crate) fn add_back_faces(&mut self) {
        let n = self.positions.len() as u32;
        self.positions.extend_from_within(..);
        self.uvs.extend_from_within(..);
        let back_normals: Vec<Vec3> = self.normals.iter().map(|&v| -v).collect();
        self.normals.extend(back_normals);
        let back_tangents: Vec<Vec4> = self.tangents.iter().map(|&t| -t).collect();
        self.tangents.extend(back_tangents);
        let back: Vec<u32> = self
            .indices
            .chunks_exact(3)
            .flat_map(|t| [n + t[0], n + t[2], n + t[1]])
            .collect();
        self.indices.extend(back);
    }

    /// The same triangles with the opposite winding (`a b c` -> `a c b`): drawn by an
    /// instance whose transform mirrors (negative determinant), they face the same way as
    /// the unmirrored ones (glTF 2.0 §3.7.4: such a node's winding is reversed).
    pub(crate) fn flipped(&self) -> Self {
        let mut g = self.clone();
        for t in g.indices.chunks_exact_mut(3) {
            t.swap(1, 2);
        }
        // A mirroring transform turns `n × t`: the handedness turns with it, so the
        // bitangent stays the direction of the texture's +v.
        for t in &mut g.tangents {
            t.w = -t.w;
        }
        g
    }

    /// Number of triangles.
    pub(crate) fn triangles(&self) -> usize {
        self.indices.len() / 3
    }

    /// The renderer's meshes: one holding everything when it fits both 64k limits
    /// ([`MAX_VERTICES_PER_MESH`], [`MAX_PRIMITIVES_PER_MESH`]), vertex and triangle order
    /// unchanged; otherwise pieces of consecutive triangles, each as large as the limits
    /// allow, with only the vertices its triangles use (in first-use order). Triangle
    /// order and every vertex's attributes are kept.
    pub(crate) fn into_meshes(self, name: &str) -> Vec<Mesh> {
        let fits = self.positions.len() <= MAX_VERTICES_PER_MESH
            && self.triangles() <= MAX_PRIMITIVES_PER_MESH;
        if fits {
            return vec![Mesh {
                name: name.to_owned(),
                indices: self.indices.iter().map(|&i| i as u16).collect(),
                positions: self.positions,
                normals: self.normals,
                uvs: self.uvs,
                tangents: self.tangents,
            }];
        }
        let mut pieces = Vec::new();
        // local[v]: v's index in the current piece, stamped with the piece number.
        let mut local: Vec<(u32, u32)> = vec![(u32::MAX, 0); self.positions.len()];
        let mut piece = Mesh::default();
        let mut stamp = 0u32;
        for t in self.indices.chunks_exact(3) {
            let new = t
                .iter()
                .enumerate()
                .filter(|&(k, &v)| local[v as usize].0 != stamp && !t[..k].contains(&v))
                .count();
            if piece.positions.len() + new > MAX_VERTICES_PER_MESH
                || piece.primitive_count() + 1 > MAX_PRIMITIVES_PER_MESH
            {
                pieces.push(std::mem::take(&mut piece));
                stamp += 1;
            }
            for &v in t {
                let vi = v as usize;
                if local[vi].0 != stamp {
                    local[vi] = (stamp, piece.positions.len() as u32);
                    piece.positions.push(self.positions[vi]);
                    piece.normals.push(self.normals[vi]);
                    piece.uvs.push(self.uvs[vi]);
                    piece.tangents.push(self.tangents[vi]);
                }
                piece.indices.push(local[vi].1 as u16);
            }
        }
        if !piece.indices.is_empty() {
            pieces.push(piece);
        }
        let count = pieces.len();
        for (k, p) in pieces.iter_mut().enumerate() {
            p.name = format!("{name} (piece {} of {count})", k + 1);
        }
        pieces
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use gltf::mesh::Mode;

    #[test]
    fn strips_and_fans_follow_the_spec() {
        // glTF 2.0 §3.7.2.1: strip triangle i = {v_i, v_{i+(1+i%2)}, v_{i+(2-i%2)}},
        // fan triangle i = {v_{i+1}, v_{i+2}, v_0}.
        let v = [10, 11, 12, 13, 14];
        assert_eq!(
            triangulate(Mode::TriangleStrip, &v).unwrap(),
            [10, 11, 12, 12, 11, 13, 12, 13, 14]
        );
        assert_eq!(
            triangulate(Mode::TriangleFan, &v).unwrap(),
            [11, 12, 10, 12, 13, 10, 13, 14, 10]
        );
        assert_eq!(triangulate(Mode::Triangles, &v).unwrap(), [10, 11, 12]);
        assert_eq!(triangulate(Mode::Lines, &v), None);
        assert_eq!(
            triangulate(Mode::TriangleStrip, &v[..2]).unwrap(),
            Vec::<u32>::new()
        );
    }

    #[test]
    fn back_faces_mirror_the_front() {
        let mut g = Geometry {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: vec![Vec3::Z; 3],
            uvs: vec![Vec2::ZERO, Vec2::X, Vec2::Y],
            tangents: vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 3],
            indices: vec![0, 1, 2],
        };
        g.add_back_faces();
        assert_eq!(g.indices, [0, 1, 2, 3, 5, 4]);
        assert_eq!(g.normals[3..], [Vec3::NEG_Z; 3]);
        // The whole frame turns: the bitangent w · n × t, +Y in front, is -Y behind, so a
        // normal-map normal (x t + y b + z n) behind is the front's negated.
        assert_eq!(g.tangents[4], Vec4::new(-1.0, 0.0, 0.0, -1.0));
        let bitangent = |i: usize| g.normals[i].cross(g.tangents[i].truncate()) * g.tangents[i].w;
        assert_eq!(bitangent(0), Vec3::Y);
        assert_eq!(bitangent(4), Vec3::NEG_Y);
        // A mirrored copy keeps +v's direction under the mirroring transform.
        let m = g.flipped();
        let mirror = |v: Vec3| Vec3::new(-v.x, v.y, v.z);
        let b = mirror(m.normals[0]).cross(mirror(m.tangents[0].truncate())) * m.tangents[0].w;
        assert_eq!(b, mirror(bitangent(0)));
        // The back triangle's geometric normal is -Z.
        let p = |i: usize| g.positions[g.indices[i] as usize];
        assert_eq!(face_normal(p(3), p(4), p(5)), Vec3::NEG_Z);
    }

    #[test]
    fn mikktspace_on_a_quad_gives_the_uv_axes() {
        // A quad in the xy plane, u along +x and v along -y (glTF's v runs down the image).
        let mut g = Geometry {
            positions: vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            normals: vec![Vec3::Z; 4],
            uvs: vec![
                Vec2::new(0.0, 1.0),
                Vec2::new(1.0, 1.0),
                Vec2::new(1.0, 0.0),
                Vec2::new(0.0, 0.0),
            ],
            tangents: vec![],
            indices: vec![0, 1, 2, 0, 2, 3],
        };
        g.generate_tangents();
        assert_eq!(g.positions.len(), 4, "one tangent per vertex: no split");
        for t in &g.tangents {
            // Tangent along +u = +x; bitangent w·(n × t) = w·(+y) up the image (−v, +y):
            // w = +1.
            assert!((t.truncate() - Vec3::X).length() < 1e-5, "{t}");
            assert_eq!(t.w, 1.0);
        }
    }
}
