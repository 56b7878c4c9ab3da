//! Mesh preprocessing for the active primitive-ID path and the concatenated geometry
//! buffers: one vertex array, one payload array and one 32-bit index array for all meshes.
//!
//! The encoders are `visbuf`'s: the provoking-vertex path rotates triangles (and copies a
//! vertex where it must) so the first corner carries the primitive ID; the XOR path gives
//! every vertex a payload so the XOR of a triangle's three is its ID. Indices are 32-bit
//! because an encoded mesh may grow past 65 536 vertices (the source mesh may not).

use super::rows::{GpuMesh, GpuVertex};
use crate::context::PrimitiveIdPath;
use crate::error::SceneError;
use crate::scene::Mesh;

/// All meshes of a scene, encoded for one primitive-ID path.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Geometry {
    /// The path the payloads are for.
    pub path: Option<PrimitiveIdPath>,
    /// Vertices of every mesh, mesh after mesh.
    pub vertices: Vec<GpuVertex>,
    /// One payload per vertex (zero for the builtin path).
    pub payloads: Vec<u32>,
    /// Triangle lists, local to each mesh's first vertex.
    pub indices: Vec<u32>,
    /// One record per scene mesh.
    pub meshes: Vec<GpuMesh>,
    /// Vertices the encoder added, per mesh.
    pub added_vertices: Vec<u32>,
}

impl Geometry {
    /// Encodes every mesh of `meshes` (validated already: [`Scene::validate`](crate::Scene::validate))
    /// for `path`.
    pub(crate) fn build(meshes: &[Mesh], path: PrimitiveIdPath) -> Result<Self, SceneError> {
        let mut g = Geometry {
            path: Some(path),
            ..Geometry::default()
        };
        for mesh in meshes {
            let vertex_count = mesh.positions.len() as u32;
            let encoded = match path {
                PrimitiveIdPath::Builtin => None,
                PrimitiveIdPath::ProvokingVertex => Some(visbuf::encode::encode_provoking(
                    &mesh.indices,
                    vertex_count,
                )),
                PrimitiveIdPath::PerVertexXor => {
                    Some(visbuf::encode::encode_xor(&mesh.indices, vertex_count))
                }
            }
            .transpose()
            .map_err(|e| SceneError::Encoding(format!("mesh `{}`: {e}", mesh.name)))?;
            let source: Vec<GpuVertex> = (0..mesh.positions.len())
                .map(|i| GpuVertex {
                    position: mesh.positions[i].to_array(),
                    u: mesh.uvs[i].x,
                    normal: mesh.normals[i].to_array(),
                    v: mesh.uvs[i].y,
                    tangent: mesh.tangents[i].to_array(),
                })
                .collect();
            let base_vertex = g.vertices.len() as u32;
            let first_index = g.indices.len() as u32;
            match encoded {
                None => {
                    g.vertices.extend_from_slice(&source);
                    g.payloads.extend(std::iter::repeat_n(0, source.len()));
                    g.indices.extend(mesh.indices.iter().map(|&i| u32::from(i)));
                    g.added_vertices.push(0);
                }
                Some(e) => {
                    let remapped = e.remap_vertices(&source).map_err(|err| {
                        SceneError::Encoding(format!("mesh `{}`: {err}", mesh.name))
                    })?;
                    g.vertices.extend_from_slice(&remapped);
                    g.payloads.extend_from_slice(&e.payloads);
                    g.indices.extend_from_slice(&e.indices);
                    g.added_vertices.push(e.added_vertices());
                }
            }
            g.meshes.push(GpuMesh {
                first_index,
                primitive_count: mesh.primitive_count() as u32,
                base_vertex,
                vertex_count: g.vertices.len() as u32 - base_vertex,
            });
        }
        Ok(g)
    }

    /// The primitive ID the laydown sees for triangle `t` of mesh `m` on this path,
    /// decoded independently of the encoder (builtin: `t`; provoking: the first corner's
    /// payload; XOR: the XOR of the three payloads).
    #[cfg(test)]
    pub(crate) fn decoded_primitive(&self, m: usize, t: u32) -> Option<u32> {
        let mesh = self.meshes.get(m)?;
        if t >= mesh.primitive_count {
            return None;
        }
        let at = (mesh.first_index + 3 * t) as usize;
        let corner = |k: usize| {
            self.payloads
                .get((mesh.base_vertex + self.indices[at + k]) as usize)
                .copied()
        };
        match self.path? {
            PrimitiveIdPath::Builtin => Some(t),
            PrimitiveIdPath::ProvokingVertex => corner(0),
            PrimitiveIdPath::PerVertexXor => Some(corner(0)? ^ corner(1)? ^ corner(2)?),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_path_decodes_every_triangle_and_keeps_its_corners() {
        let (scene, _) = demo::build(&demo::DemoOptions {
            density: 0.01,
            ..Default::default()
        });
        for path in PrimitiveIdPath::ALL {
            let g = Geometry::build(&scene.meshes, path).unwrap();
            for (m, mesh) in scene.meshes.iter().enumerate() {
                let rec = g.meshes[m];
                for t in 0..mesh.primitive_count() as u32 {
                    assert_eq!(
                        g.decoded_primitive(m, t),
                        Some(t),
                        "{} mesh {m} tri {t}",
                        path.name()
                    );
                    // The encoded triangle has the same corner positions, in the same winding.
                    let src: Vec<[f32; 3]> = (0..3)
                        .map(|k| {
                            mesh.positions[mesh.indices[3 * t as usize + k] as usize].to_array()
                        })
                        .collect();
                    let enc: Vec<[f32; 3]> = (0..3)
                        .map(|k| {
                            let i = g.indices[(rec.first_index + 3 * t) as usize + k];
                            g.vertices[(rec.base_vertex + i) as usize].position
                        })
                        .collect();
                    let rotations = [[0, 1, 2], [1, 2, 0], [2, 0, 1]];
                    assert!(
                        rotations
                            .iter()
                            .any(|r| (0..3).all(|k| enc[k] == src[r[k]])),
                        "{} mesh {m} tri {t}: corners or winding changed",
                        path.name()
                    );
                }
            }
        }
    }
}
