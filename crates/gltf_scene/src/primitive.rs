//! One glTF primitive's geometry: attributes read through the accessors, checked, with
//! generated normals and tangents where the file has none.

use scene::glam::{Vec2, Vec3};

use crate::geometry::{self, Geometry};
use crate::{Error, accessor, material};

/// One primitive's geometry, before the mirror flip and the split; `None` when it draws
/// nothing (no POSITION, points or lines, no triangles).
pub(crate) fn primitive_geometry(
    data: &accessor::Data<'_>,
    mesh: &gltf::Mesh<'_>,
    prim: &gltf::Primitive<'_>,
    mat: &material::Imported,
    warnings: &mut Vec<String>,
) -> Result<Option<Geometry>, Error> {
    use gltf::Semantic;
    let label = format!("mesh {} primitive {}", mesh.index(), prim.index());
    let err = |problem: String| Error::Primitive {
        file: data.file.to_owned(),
        mesh: mesh.index(),
        name: mesh.name().map(str::to_owned),
        primitive: prim.index(),
        problem,
    };
    let Some(pos) = prim.get(&Semantic::Positions) else {
        warnings.push(format!("{label}: no POSITION attribute; it is not drawn"));
        return Ok(None);
    };
    let positions: Vec<Vec3> = data
        .floats::<3>(&pos, "POSITION")?
        .into_iter()
        .map(Vec3::from_array)
        .collect();
    let n = positions.len();
    let raw = match prim.indices() {
        Some(a) => data.indices(&a)?,
        None => {
            let n32 = u32::try_from(n).map_err(|_| err(format!("{n} vertices pass u32")))?;
            (0..n32).collect()
        }
    };
    if let Some((at, &i)) = raw.iter().enumerate().find(|&(_, &i)| i as usize >= n) {
        return Err(err(format!(
            "index {i} (entry {at} of its indices) is past its {n} vertices"
        )));
    }
    let Some(indices) = geometry::triangulate(prim.mode(), &raw) else {
        warnings.push(format!(
            "{label}: mode {:?} (points or lines) is not drawn",
            prim.mode()
        ));
        return Ok(None);
    };
    if indices.is_empty() {
        return Ok(None);
    }
    let same_length = |what: &str, len: usize| -> Result<(), Error> {
        if len == n {
            Ok(())
        } else {
            Err(err(format!("{what} has {len} elements, POSITION {n}")))
        }
    };
    for (semantic, _) in prim.attributes() {
        if let Semantic::Colors(_) = semantic {
            warnings.push("vertex colours (COLOR_n) are ignored".to_owned());
        }
    }
    if prim.morph_targets().len() > 0 {
        warnings.push(format!(
            "{label}: morph targets are ignored; the base shape is drawn"
        ));
    }
    let set = mat.uv_set;
    let mut uvs: Vec<Vec2> = match prim.get(&Semantic::TexCoords(set)) {
        Some(a) => {
            let uv: Vec<Vec2> = data
                .floats::<2>(&a, &format!("TEXCOORD_{set}"))?
                .into_iter()
                .map(Vec2::from_array)
                .collect();
            same_length(&format!("TEXCOORD_{set}"), uv.len())?;
            uv
        }
        None => {
            if mat.texture.is_some() || mat.maps != material::MapImages::default() {
                warnings.push(format!(
                    "{label}: no TEXCOORD_{set} for the textures of its material `{}` (base \
                     colour or maps); they are sampled at (0, 0)",
                    mat.material.name
                ));
            }
            vec![Vec2::ZERO; n]
        }
    };
    if let Some(t) = &mat.uv_transform {
        t.apply(&mut uvs);
        if !uvs.iter().all(|uv| uv.is_finite()) {
            return Err(err(
                "its texture coordinates overflow under the material's KHR_texture_transform"
                    .to_owned(),
            ));
        }
    }
    let mut g = match prim.get(&Semantic::Normals) {
        Some(a) => {
            let normals: Vec<Vec3> = data
                .floats::<3>(&a, "NORMAL")?
                .into_iter()
                .map(|v| Vec3::from_array(v).normalize_or(Vec3::Y))
                .map(|v| {
                    if v.is_normalized() {
                        v
                    } else {
                        v.normalize_or(Vec3::Y)
                    }
                })
                .collect();
            same_length("NORMAL", normals.len())?;
            let tangents = match prim.get(&Semantic::Tangents) {
                Some(a) => {
                    let t = data.floats::<4>(&a, "TANGENT")?;
                    same_length("TANGENT", t.len())?;
                    t.into_iter()
                        .zip(&normals)
                        .map(|(t, &nrm)| {
                            let xyz = Vec3::new(t[0], t[1], t[2])
                                .normalize_or(nrm.any_orthonormal_vector());
                            xyz.extend(if t[3] < 0.0 { -1.0 } else { 1.0 })
                        })
                        .collect()
                }
                None => Vec::new(),
            };
            Geometry {
                positions,
                normals,
                uvs,
                tangents,
                indices,
            }
        }
        None => Geometry::flat(&positions, &uvs, &indices),
    };
    if g.tangents.is_empty() {
        g.generate_tangents();
    }
    if mat.double_sided {
        g.add_back_faces();
    }
    Ok(Some(g))
}
