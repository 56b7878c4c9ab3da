//! The scene's node hierarchy, walked: local transforms checked, world transforms of
//! every drawn primitive, and the first perspective camera.

use std::collections::HashMap;

use scene::Camera;
use scene::glam::{Affine3A, Mat3, Mat4, Quat, Vec3, Vec4};

use crate::{Error, LoadOptions};

/// A node's local transform, checked.
pub(crate) fn local_matrix(
    file: &str,
    node: &gltf::Node<'_>,
    warnings: &mut Vec<String>,
) -> Result<Mat4, Error> {
    let err = |problem: String| Error::Node {
        file: file.to_owned(),
        node: node.index(),
        name: node.name().map(str::to_owned),
        problem,
    };
    let m = match node.transform() {
        gltf::scene::Transform::Matrix { matrix } => {
            let m = Mat4::from_cols_array_2d(&matrix);
            if !m.is_finite() {
                return Err(err(format!("matrix {matrix:?} is not finite")));
            }
            if m.row(3) != Vec4::W {
                warnings.push(format!(
                    "node {}: its matrix's last row {} is not (0, 0, 0, 1); it is dropped",
                    node.index(),
                    m.row(3)
                ));
            }
            m
        }
        gltf::scene::Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => {
            let (t, s) = (Vec3::from_array(translation), Vec3::from_array(scale));
            let mut q = Quat::from_array(rotation);
            if !(t.is_finite() && s.is_finite() && q.is_finite()) {
                return Err(err(format!(
                    "translation {translation:?}, rotation {rotation:?} or scale {scale:?} is \
                     not finite"
                )));
            }
            if (q.length() - 1.0).abs() > 1e-3 {
                if q.length() < 1e-6 {
                    return Err(err(format!(
                        "rotation {rotation:?} is not a unit quaternion"
                    )));
                }
                q = q.normalize();
            }
            Mat4::from_scale_rotation_translation(s, q, t)
        }
    };
    Ok(m)
}

/// The renderer's mesh of (glTF mesh, primitive, mirrored) and what it was made from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) struct DrawKey {
    pub(crate) mesh: usize,
    pub(crate) primitive: usize,
    pub(crate) mirrored: bool,
}

/// The scene's nodes, walked: every drawn (key, world transform), the camera.
pub(crate) struct Walk {
    pub(crate) draws: Vec<(DrawKey, Vec<Affine3A>)>,
    pub(crate) camera: Option<(Camera, String)>,
    pub(crate) nodes: usize,
}

pub(crate) fn walk(
    file: &str,
    doc: &gltf::Document,
    options: &LoadOptions,
    warnings: &mut Vec<String>,
) -> Result<Walk, Error> {
    let roots: Vec<gltf::Node<'_>> = match options.scene {
        Some(i) => match doc.scenes().nth(i) {
            Some(s) => s.nodes().collect(),
            None => {
                return Err(Error::Invalid {
                    file: file.to_owned(),
                    path: "scenes".to_owned(),
                    problem: format!(
                        "LoadOptions::scene asks for scene {i}; the file has {}",
                        doc.scenes().len()
                    ),
                });
            }
        },
        None => match doc.default_scene().or_else(|| doc.scenes().next()) {
            Some(s) => s.nodes().collect(),
            None => {
                let mut child = vec![false; doc.nodes().len()];
                for n in doc.nodes() {
                    for c in n.children() {
                        child[c.index()] = true;
                    }
                }
                if doc.nodes().len() > 0 {
                    warnings.push("the file has no scene: every root node is drawn".to_owned());
                }
                doc.nodes().filter(|n| !child[n.index()]).collect()
            }
        },
    };
    let mut visited = vec![false; doc.nodes().len()];
    let mut stack: Vec<(gltf::Node<'_>, Mat4)> = roots
        .into_iter()
        .rev()
        .map(|n| (n, Mat4::IDENTITY))
        .collect();
    let mut index: HashMap<DrawKey, usize> = HashMap::new();
    let mut out = Walk {
        draws: Vec::new(),
        camera: None,
        nodes: 0,
    };
    while let Some((node, parent)) = stack.pop() {
        let err = |problem: String| Error::Node {
            file: file.to_owned(),
            node: node.index(),
            name: node.name().map(str::to_owned),
            problem,
        };
        if std::mem::replace(&mut visited[node.index()], true) {
            return Err(err(
                "it is reached twice from the scene's roots (a cycle, a node with two parents or \
                 a root listed twice): glTF's node hierarchy must be a set of disjoint trees"
                    .to_owned(),
            ));
        }
        let world = parent * local_matrix(file, &node, warnings)?;
        if !world.is_finite() {
            return Err(err(
                "its world transform (its ancestors' times its own) overflows to infinity"
                    .to_owned(),
            ));
        }
        if let Some(mesh) = node.mesh() {
            out.nodes += 1;
            if node.skin().is_some() {
                warnings.push(format!(
                    "node {}: skinning is ignored; the mesh is drawn in its bind pose with the \
                     node's transform",
                    node.index()
                ));
            }
            let mirrored = Mat3::from_mat4(world).determinant() < 0.0;
            let instance = Affine3A::from_mat4(world);
            for p in mesh.primitives() {
                let key = DrawKey {
                    mesh: mesh.index(),
                    primitive: p.index(),
                    mirrored,
                };
                let at = *index.entry(key).or_insert_with(|| {
                    out.draws.push((key, Vec::new()));
                    out.draws.len() - 1
                });
                out.draws[at].1.push(instance);
            }
        }
        if out.camera.is_none()
            && let Some(cam) = node.camera()
        {
            let label = node
                .name()
                .map_or_else(|| format!("node {}", node.index()), str::to_owned);
            match cam.projection() {
                gltf::camera::Projection::Perspective(p) => {
                    let position = world.transform_point3(Vec3::ZERO);
                    let forward = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
                    let camera = Camera {
                        position,
                        target: position + forward,
                        up: world.transform_vector3(Vec3::Y).normalize_or_zero(),
                        fov_y: p.yfov(),
                        near: p.znear(),
                    };
                    match camera.validate() {
                        Ok(()) => out.camera = Some((camera, label)),
                        Err(e) => warnings.push(format!(
                            "{label}: its camera is not usable ({e}); it is skipped"
                        )),
                    }
                }
                gltf::camera::Projection::Orthographic(_) => warnings.push(format!(
                    "{label}: orthographic cameras are not supported; it is skipped"
                )),
            }
        }
        for c in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((c, world));
        }
    }
    Ok(out)
}
