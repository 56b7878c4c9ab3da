//! Mesh resources and their flattening to two LOD levels ("Input constraints").
//!
//! A [`MeshNode`] tree is what a placed object draws: LOD-switch nodes select one branch
//! by distance, multi-mesh nodes place branches relative to their parent, static-mesh
//! leaves are the DrawableSetups. The query needs every leaf as a flat record with exactly
//! two LOD levels, parent and child, each a bounding box plus a `[min, max)` distance
//! bracket; a leaf is visible iff both levels are selected. A path with fewer LOD nodes is
//! padded with always-on levels (`[0, inf)`, so no special cases); a tree with a path of
//! three or more LOD nodes, a skinned leaf, or a value that does not fit the packed
//! records does not fit, and goes to the dynamic list with its [`DynamicReason`].
//!
//! Spaces: each node's transform maps its local space to its parent's; the root's space
//! is object space. A LOD node's `bounds` are in its own local space (they are the
//! LodMeshResource's bounds, which every branch fits inside); a leaf's `bounds` are the
//! accurate vertex bounds of its geometry in its local (mesh) space. Distances are metres.

use alloc::vec::Vec;

use glam::{Affine3A, Vec3};

use crate::{
    Error, FILTER_ALL, Field, HalfAabb, LodRange, QuerySetup, Transform4x3, records::check_aabb,
};

/// An axis-aligned box, f32, in the space named where it is used.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Minimum corner.
    pub min: Vec3,
    /// Maximum corner.
    pub max: Vec3,
}

impl Aabb {
    /// The box `[min, max]`.
    #[must_use]
    pub const fn new(min: Vec3, max: Vec3) -> Aabb {
        Aabb { min, max }
    }

    /// The empty box (min = +inf, max = -inf), the identity of [`union`](Self::union).
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    /// The smallest box containing both.
    #[must_use]
    #[inline]
    pub fn union(self, o: Aabb) -> Aabb {
        Aabb {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    /// Whether `min <= max` on every axis.
    #[must_use]
    pub fn is_valid(&self) -> bool {
        self.min.cmple(self.max).all()
    }

    /// The centre.
    #[must_use]
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// The box enclosing this one transformed by `t`.
    #[must_use]
    pub fn transformed(&self, t: &Transform4x3) -> Aabb {
        let (min, max) = t.transform_aabb(self.min, self.max);
        Aabb { min, max }
    }
}

/// One branch of a [`MeshNode::Lod`] switch: drawn while the distance to the node's
/// bounds is in `[min, max)` metres (`max` may be `f32::INFINITY`).
#[derive(Clone, Debug, PartialEq)]
pub struct LodLevel {
    /// Start of the bracket, metres.
    pub min: f32,
    /// End of the bracket (exclusive), metres.
    pub max: f32,
    /// What this level draws.
    pub node: MeshNode,
}

/// One part of a [`MeshNode::Multi`]: a branch placed relative to the parent.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshPart {
    /// The part's local space to its parent's.
    pub local_to_parent: Affine3A,
    /// What the part draws.
    pub node: MeshNode,
}

/// A static-mesh leaf: one DrawableSetup.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StaticMesh {
    /// The renderer's handle for the DrawableSetup (geometry + shaders), opaque here.
    pub setup: u64,
    /// Accurate vertex bounds in the mesh's local space.
    pub bounds: Aabb,
    /// Filter bits (`FILTER_*`): which views draw it.
    pub filter: u8,
    /// Instance flags (`INSTANCE_FLAG_*`).
    pub flags: u8,
}

/// A node of a mesh-resource tree.
#[derive(Clone, Debug, PartialEq)]
pub enum MeshNode {
    /// A LOD switch: `bounds` (local space) and one branch per distance bracket.
    Lod {
        /// The switch's bounds, local space.
        bounds: Aabb,
        /// The branches.
        levels: Vec<LodLevel>,
    },
    /// A multi-mesh: several parts, each with its own transform.
    Multi(Vec<MeshPart>),
    /// A static-mesh leaf.
    Static(StaticMesh),
    /// A skinned-mesh leaf: not static content, so the tree goes to the dynamic list.
    Skinned {
        /// The renderer's handle.
        setup: u64,
    },
}

impl MeshNode {
    /// A LOD switch over `bounds` (local space), one branch per `(min, max, node)`
    /// distance bracket.
    #[must_use]
    pub fn lod(bounds: Aabb, levels: impl IntoIterator<Item = (f32, f32, MeshNode)>) -> Self {
        MeshNode::Lod {
            bounds,
            levels: levels
                .into_iter()
                .map(|(min, max, node)| LodLevel { min, max, node })
                .collect(),
        }
    }
}

/// Why a placed tree did not fit the static scene and went to the dynamic list.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DynamicReason {
    /// A root-to-leaf path crosses more than two LOD switches.
    TooManyLodLevels {
        /// LOD switches on the deepest path.
        depth: u32,
    },
    /// The tree has a skinned (non-static) leaf.
    NotStatic,
    /// The tree draws nothing (no static leaf).
    NoMeshes,
    /// A value does not fit the packed records (a LOD distance, a bound beyond the f16
    /// range, a filter wider than 3 bits...): the error names the field.
    Encoding(Error),
    /// The object's placement is invalid (position outside the world, non-finite
    /// transform, LOD scale): the error names the field.
    Placement(Error),
    /// One object alone needs more entries than a tile can index.
    TooLargeForTile {
        /// The index space ([`Field::Setup`], [`Field::Matrix`], [`Field::ParentBounds`]).
        field: Field,
        /// Entries the object needs.
        needed: usize,
        /// The tile's limit.
        limit: usize,
    },
}

/// One LOD level of a flattened leaf: bounds in object space and the distance bracket.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct FlatLod {
    /// The LOD switch's bounds in object space (conservative half box).
    pub bounds: HalfAabb,
    /// The bracket.
    pub range: LodRange,
}

/// A leaf of a flattened tree: one future QueryInstance per placement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlatLeaf {
    /// The setup (accurate local bounds, handle).
    pub setup: QuerySetup,
    /// Filter bits.
    pub filter: u8,
    /// Instance flags.
    pub flags: u8,
    /// The leaf's local space to object space.
    pub local_to_object: Transform4x3,
    /// Parent level.
    pub parent: FlatLod,
    /// Child level.
    pub child: FlatLod,
}

/// A flattened resource: its leaves, and how many distinct entries one placement needs in
/// a tile's index spaces.
#[derive(Clone, Debug, PartialEq)]
pub struct FlatResource {
    /// The leaves, in tree order.
    pub leaves: Vec<FlatLeaf>,
    /// Distinct setups.
    pub setups: usize,
    /// Distinct local-to-object matrices.
    pub matrices: usize,
    /// Distinct LOD bounds.
    pub bounds: usize,
    /// Union of the leaves' accurate bounds, object space.
    pub object_bounds: Aabb,
}

struct Level {
    bounds: Aabb,
    range: LodRange,
}

/// Flattens a tree whose root space is object space.
pub fn flatten(root: &MeshNode) -> Result<FlatResource, DynamicReason> {
    let depth = lod_depth(root);
    if depth > 2 {
        return Err(DynamicReason::TooManyLodLevels { depth });
    }
    let mut leaves = Vec::new();
    let mut levels: Vec<Level> = Vec::new();
    walk(root, &Affine3A::IDENTITY, &mut levels, &mut leaves)?;
    if leaves.is_empty() {
        return Err(DynamicReason::NoMeshes);
    }
    let setups = count_distinct(leaves.iter().map(|l| bytemuck::bytes_of(&l.setup).to_vec()));
    let matrices = count_distinct(
        leaves
            .iter()
            .map(|l| bytemuck::bytes_of(&l.local_to_object).to_vec()),
    );
    let bounds = count_distinct(leaves.iter().flat_map(|l| {
        [
            bytemuck::bytes_of(&l.parent.bounds).to_vec(),
            bytemuck::bytes_of(&l.child.bounds).to_vec(),
        ]
    }));
    let object_bounds = leaves.iter().fold(Aabb::EMPTY, |b, l| {
        b.union(Aabb::new(l.setup.min(), l.setup.max()).transformed(&l.local_to_object))
    });
    if !(object_bounds.min.is_finite() && object_bounds.max.is_finite()) {
        return Err(DynamicReason::Encoding(Error::FloatOutOfRange {
            field: Field::Bounds,
            value: f64::INFINITY,
            max: f64::from(f32::MAX),
        }));
    }
    Ok(FlatResource {
        leaves,
        setups,
        matrices,
        bounds,
        object_bounds,
    })
}

fn count_distinct(items: impl Iterator<Item = Vec<u8>>) -> usize {
    let mut v: Vec<Vec<u8>> = items.collect();
    v.sort_unstable();
    v.dedup();
    v.len()
}

/// The most LOD switches on any root-to-leaf path.
fn lod_depth(node: &MeshNode) -> u32 {
    match node {
        MeshNode::Lod { levels, .. } => {
            1 + levels.iter().map(|l| lod_depth(&l.node)).max().unwrap_or(0)
        }
        MeshNode::Multi(parts) => parts.iter().map(|p| lod_depth(&p.node)).max().unwrap_or(0),
        MeshNode::Static(_) | MeshNode::Skinned { .. } => 0,
    }
}

fn walk(
    node: &MeshNode,
    to_object: &Affine3A,
    levels: &mut Vec<Level>,
    out: &mut Vec<FlatLeaf>,
) -> Result<(), DynamicReason> {
    let enc = DynamicReason::Encoding;
    match node {
        MeshNode::Lod {
            bounds,
            levels: branches,
        } => {
            check_aabb(bounds.min, bounds.max, Field::Bounds).map_err(enc)?;
            let t = Transform4x3::from_affine(to_object);
            let object_bounds = bounds.transformed(&t);
            for b in branches {
                let range = LodRange::new(b.min, b.max, (Field::LodDistance, Field::LodDistance))
                    .map_err(enc)?;
                levels.push(Level {
                    bounds: object_bounds,
                    range,
                });
                let r = walk(&b.node, to_object, levels, out);
                levels.pop();
                r?;
            }
        }
        MeshNode::Multi(parts) => {
            for p in parts {
                let m = *to_object * p.local_to_parent;
                if !Transform4x3::from_affine(&m).is_finite() {
                    return Err(enc(Error::FloatOutOfRange {
                        field: Field::Transform,
                        value: f64::NAN,
                        max: f64::from(f32::MAX),
                    }));
                }
                walk(&p.node, &m, levels, out)?;
            }
        }
        MeshNode::Static(mesh) => {
            if mesh.filter > FILTER_ALL {
                return Err(enc(Error::FieldOverflow {
                    field: Field::Filter,
                    value: u64::from(mesh.filter),
                    max: u64::from(FILTER_ALL),
                }));
            }
            if mesh.flags > 3 {
                return Err(enc(Error::FieldOverflow {
                    field: Field::Flags,
                    value: u64::from(mesh.flags),
                    max: 3,
                }));
            }
            let setup =
                QuerySetup::new(mesh.bounds.min, mesh.bounds.max, mesh.setup).map_err(enc)?;
            let local_to_object = Transform4x3::from_affine(to_object);
            let leaf_bounds = mesh.bounds.transformed(&local_to_object);
            let half = |b: &Aabb| HalfAabb::from_aabb(b.min, b.max).map_err(enc);
            let (parent, child) = match levels.as_slice() {
                [] => {
                    let h = half(&leaf_bounds)?;
                    let always = FlatLod {
                        bounds: h,
                        range: LodRange::ALWAYS,
                    };
                    (always, always)
                }
                [p] => {
                    let pb = half(&p.bounds)?;
                    (
                        FlatLod {
                            bounds: pb,
                            range: p.range,
                        },
                        FlatLod {
                            bounds: pb,
                            range: LodRange::ALWAYS,
                        },
                    )
                }
                [p, c] => (
                    FlatLod {
                        bounds: half(&p.bounds)?,
                        range: p.range,
                    },
                    FlatLod {
                        bounds: half(&c.bounds)?,
                        range: c.range,
                    },
                ),
                _ => {
                    return Err(DynamicReason::TooManyLodLevels {
                        depth: levels.len() as u32,
                    });
                }
            };
            out.push(FlatLeaf {
                setup,
                filter: mesh.filter,
                flags: mesh.flags,
                local_to_object,
                parent,
                child,
            });
        }
        MeshNode::Skinned { .. } => return Err(DynamicReason::NotStatic),
    }
    Ok(())
}

/// The flattened form of every resource a streaming thread places, computed once.
#[derive(Clone, Debug, Default)]
pub struct ResourceLibrary {
    flat: Vec<Result<FlatResource, DynamicReason>>,
}

impl ResourceLibrary {
    /// Flattens every resource (index = resource id).
    #[must_use]
    pub fn new(resources: &[MeshNode]) -> ResourceLibrary {
        ResourceLibrary {
            flat: resources.iter().map(flatten).collect(),
        }
    }

    /// Number of resources.
    #[must_use]
    pub fn len(&self) -> usize {
        self.flat.len()
    }

    /// Whether there are none.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.flat.is_empty()
    }

    /// Resource `i`'s flattened leaves, or why it goes to the dynamic list; `None` past
    /// the end.
    #[must_use]
    pub fn get(&self, i: usize) -> Option<&Result<FlatResource, DynamicReason>> {
        self.flat.get(i)
    }

    /// Adds a resource, returning its id.
    pub fn push(&mut self, resource: &MeshNode) -> usize {
        self.flat.push(flatten(resource));
        self.flat.len() - 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{FILTER_VISUAL, LodDistance};
    use alloc::vec;

    fn mesh(setup: u64) -> MeshNode {
        MeshNode::Static(StaticMesh {
            setup,
            bounds: Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0)),
            filter: FILTER_VISUAL,
            flags: 0,
        })
    }

    fn lod(levels: Vec<(f32, f32, MeshNode)>) -> MeshNode {
        MeshNode::lod(Aabb::new(Vec3::splat(-10.0), Vec3::splat(10.0)), levels)
    }

    #[test]
    fn single_mesh_is_padded_with_always_on_levels() {
        let f = flatten(&mesh(7)).unwrap();
        assert_eq!(f.leaves.len(), 1);
        let l = f.leaves[0];
        assert_eq!(l.parent.range, LodRange::ALWAYS);
        assert_eq!(l.child.range, LodRange::ALWAYS);
        assert_eq!(l.parent.bounds.min(), Vec3::splat(-1.0));
    }

    #[test]
    fn hzd_shape_two_levels() {
        // Building blocks with their own LODs under the top switch, collapsed mesh far away.
        let blocks = MeshNode::Multi(vec![
            MeshPart {
                local_to_parent: Affine3A::from_translation(Vec3::new(5.0, 0.0, 0.0)),
                node: lod(vec![(0.0, 20.0, mesh(1)), (20.0, 60.0, mesh(2))]),
            },
            MeshPart {
                local_to_parent: Affine3A::from_translation(Vec3::new(-5.0, 0.0, 0.0)),
                node: mesh(3),
            },
        ]);
        let tree = lod(vec![(0.0, 60.0, blocks), (60.0, f32::INFINITY, mesh(4))]);
        let f = flatten(&tree).unwrap();
        assert_eq!(f.leaves.len(), 4);
        let by = |h: u64| f.leaves.iter().find(|l| l.setup.handle == h).unwrap();
        let r = |a: f32, b: f32| LodRange::from_metres(a, b).unwrap();
        assert_eq!(by(1).parent.range, r(0.0, 60.0));
        assert_eq!(by(1).child.range, r(0.0, 20.0));
        // The nested switch's bounds moved into object space.
        assert_eq!(by(1).child.bounds.min(), Vec3::new(-5.0, -10.0, -10.0));
        assert_eq!(by(2).child.range, r(20.0, 60.0));
        assert_eq!(by(3).child.range, LodRange::ALWAYS);
        assert_eq!(by(4).parent.range.max, LodDistance::INFINITY);
        assert_eq!(by(4).child.range, LodRange::ALWAYS);
        assert_eq!(
            by(3).local_to_object.translation(),
            Vec3::new(-5.0, 0.0, 0.0)
        );
        assert_eq!((f.setups, f.matrices), (4, 3));
    }

    #[test]
    fn misfits_name_their_reason() {
        let deep = lod(vec![(
            0.0,
            1.0,
            lod(vec![(0.0, 1.0, lod(vec![(0.0, 1.0, mesh(1))]))]),
        )]);
        assert_eq!(
            flatten(&deep),
            Err(DynamicReason::TooManyLodLevels { depth: 3 })
        );
        let skinned = MeshNode::Multi(vec![MeshPart {
            local_to_parent: Affine3A::IDENTITY,
            node: MeshNode::Skinned { setup: 1 },
        }]);
        assert_eq!(flatten(&skinned), Err(DynamicReason::NotStatic));
        assert_eq!(
            flatten(&MeshNode::Multi(vec![])),
            Err(DynamicReason::NoMeshes)
        );
        let far = lod(vec![(0.0, 500_000.0, mesh(1))]);
        assert!(matches!(
            flatten(&far),
            Err(DynamicReason::Encoding(Error::FloatOutOfRange {
                field: Field::LodDistance,
                ..
            }))
        ));
        let huge = MeshNode::Static(StaticMesh {
            setup: 1,
            bounds: Aabb::new(Vec3::ZERO, Vec3::splat(1e6)),
            filter: 1,
            flags: 0,
        });
        assert!(matches!(
            flatten(&huge),
            Err(DynamicReason::Encoding(Error::FloatOutOfRange {
                field: Field::HalfBounds,
                ..
            }))
        ));
    }
}
