//! The scene API: meshes, materials, albedo layers, batches of instances, a camera and
//! lights.
//!
//! Conventions: right-handed world space, +Y up, metres. Cameras look down their local −Z.
//! Projections use reversed Z (near plane at depth 1, far plane at depth 0, infinite far
//! plane), so `Depth32Float` keeps its precision far away; depth tests are `Greater`.
//! Texture coordinates have (0, 0) at the top-left of an albedo layer, v down.

use glam::{Affine3A, Mat4, Vec2, Vec3, Vec4};

use crate::error::SceneError;

/// The most primitives one geometry may have: 16-bit indices, and the vis-buffer ID's
/// primitive field (seed 000, "Only support 64k prims per geo").
pub const MAX_PRIMITIVES_PER_MESH: usize = 1 << 16;
/// The most vertices one geometry may have (16-bit indices).
pub const MAX_VERTICES_PER_MESH: usize = 1 << 16;

/// Index of a mesh in [`Scene::meshes`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct MeshId(pub usize);
/// Index of a material in [`Scene::materials`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct MaterialId(pub usize);

/// Indexed triangle geometry with 16-bit indices, counter-clockwise front faces.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// A name for error messages and statistics.
    pub name: String,
    /// Object-space positions (metres).
    pub positions: Vec<Vec3>,
    /// Object-space unit normals, one per position.
    pub normals: Vec<Vec3>,
    /// Texture coordinates, one per position (may exceed [0, 1]: layers wrap).
    pub uvs: Vec<Vec2>,
    /// Object-space tangents (xyz) with handedness in w (±1), one per position.
    pub tangents: Vec<Vec4>,
    /// Three indices per triangle.
    pub indices: Vec<u16>,
}

impl Mesh {
    /// Number of triangles.
    pub fn primitive_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Checks the limits and references of this mesh: attribute lengths, the 64k primitive
    /// and vertex limits, index count and range, finite floats.
    pub fn validate(&self) -> Result<(), SceneError> {
        let n = self.positions.len();
        let mesh = || self.name.clone();
        for (attribute, len) in [
            ("normals", self.normals.len()),
            ("uvs", self.uvs.len()),
            ("tangents", self.tangents.len()),
        ] {
            if len != n {
                return Err(SceneError::AttributeLength {
                    mesh: mesh(),
                    attribute,
                    len,
                    expected: n,
                });
            }
        }
        if n > MAX_VERTICES_PER_MESH {
            return Err(SceneError::TooManyVertices {
                mesh: mesh(),
                vertices: n,
                limit: MAX_VERTICES_PER_MESH,
            });
        }
        if !self.indices.len().is_multiple_of(3) {
            return Err(SceneError::IndexCountNotTriangles {
                mesh: mesh(),
                indices: self.indices.len(),
            });
        }
        if self.primitive_count() > MAX_PRIMITIVES_PER_MESH {
            return Err(SceneError::TooManyPrimitives {
                mesh: mesh(),
                primitives: self.primitive_count(),
                limit: MAX_PRIMITIVES_PER_MESH,
            });
        }
        if let Some((at, &index)) = self
            .indices
            .iter()
            .enumerate()
            .find(|&(_, &i)| usize::from(i) >= n)
        {
            return Err(SceneError::IndexOutOfRange {
                mesh: mesh(),
                at,
                index: index.into(),
                vertices: n,
            });
        }
        let finite = self.positions.iter().all(|p| p.is_finite())
            && self.normals.iter().all(|p| p.is_finite())
            && self.uvs.iter().all(|p| p.is_finite())
            && self.tangents.iter().all(|p| p.is_finite());
        if !finite {
            return Err(SceneError::NonFinite {
                what: format!("a vertex attribute of mesh `{}`", self.name),
            });
        }
        Ok(())
    }

    /// Object-space bounds (min, max); both zero for an empty mesh.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let mut it = self.positions.iter();
        let Some(&first) = it.next() else {
            return (Vec3::ZERO, Vec3::ZERO);
        };
        it.fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p)))
    }
}

/// Which shader a material uses. Batches are sorted into passes per shader.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ShaderKind {
    /// Opaque: no alpha test.
    Opaque,
    /// Alpha-tested (foliage cards, grass): the laydown discards texels under the cutoff.
    AlphaTested,
}

impl ShaderKind {
    /// A stable small integer, used as the shader hash in batch sorting.
    pub fn id(self) -> u32 {
        match self {
            ShaderKind::Opaque => 0,
            ShaderKind::AlphaTested => 1,
        }
    }
}

/// A material: an albedo layer of the scene's texture array and a few constants.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// A name for error messages.
    pub name: String,
    /// The shader.
    pub shader: ShaderKind,
    /// Layer of [`Scene::albedo_layers`].
    pub albedo_layer: u32,
    /// Multiplies the texture's colour (linear RGB).
    pub tint: Vec3,
    /// Alpha-test cutoff in [0, 1] for [`ShaderKind::AlphaTested`].
    pub alpha_cutoff: f32,
    /// Perceptual roughness in [0, 1].
    pub roughness: f32,
    /// Specular intensity in [0, 1].
    pub specular: f32,
}

/// One albedo layer: RGBA8, sRGB colour with linear alpha, `size` × `size` texels, row
/// major from the top-left. All layers of a scene share one size (a power of two).
#[derive(Clone, Debug, PartialEq)]
pub struct AlbedoLayer {
    /// Width and height in texels.
    pub size: u32,
    /// `size * size` texels.
    pub texels: Vec<[u8; 4]>,
}

/// A batch: one mesh with one material, drawn for many instances (what the scene query
/// hands to the renderer; `tiling` splits it into micro batches).
#[derive(Clone, Debug, PartialEq)]
pub struct Batch {
    /// The geometry.
    pub mesh: MeshId,
    /// The material.
    pub material: MaterialId,
    /// Object-to-world transforms, one per instance.
    pub instances: Vec<Affine3A>,
}

/// A perspective camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position (world, metres).
    pub position: Vec3,
    /// The point looked at.
    pub target: Vec3,
    /// Vertical field of view (radians).
    pub fov_y: f32,
    /// Near plane distance (metres); the far plane is at infinity (reversed Z).
    pub near: f32,
}

impl Camera {
    /// World-to-view matrix (right-handed, looking down −Z).
    pub fn view(&self) -> Mat4 {
        Mat4::look_at_rh(self.position, self.target, Vec3::Y)
    }

    /// View-to-clip matrix for `aspect` = width / height: reversed Z, infinite far plane.
    pub fn projection(&self, aspect: f32) -> Mat4 {
        Mat4::perspective_infinite_reverse_rh(self.fov_y, aspect, self.near)
    }

    /// World-to-clip.
    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        self.projection(aspect) * self.view()
    }
}

/// A point light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLight {
    /// World position (metres).
    pub position: Vec3,
    /// Linear RGB intensity (arbitrary units; 1 lights a white surface at 1 m to 1).
    pub color: Vec3,
    /// Distance at which the light fades to zero (metres).
    pub radius: f32,
}

/// Lighting of the scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Lighting {
    /// Unit direction *towards* the sun (world).
    pub sun_direction: Vec3,
    /// Sun colour (linear RGB).
    pub sun_color: Vec3,
    /// Constant ambient term (linear RGB).
    pub ambient: Vec3,
    /// Sky colour behind everything (linear RGB).
    pub sky: Vec3,
    /// Point lights.
    pub point_lights: Vec<PointLight>,
}

impl Default for Lighting {
    fn default() -> Self {
        Self {
            sun_direction: Vec3::new(0.4, 0.8, 0.3).normalize(),
            sun_color: Vec3::new(2.6, 2.4, 2.1),
            ambient: Vec3::new(0.18, 0.22, 0.28),
            sky: Vec3::new(0.45, 0.62, 0.9),
            point_lights: Vec::new(),
        }
    }
}

/// Everything the renderer draws.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Geometry.
    pub meshes: Vec<Mesh>,
    /// Materials.
    pub materials: Vec<Material>,
    /// The albedo texture array's layers.
    pub albedo_layers: Vec<AlbedoLayer>,
    /// Batches of instances.
    pub batches: Vec<Batch>,
    /// The camera.
    pub camera: Camera,
    /// Sun, ambient and point lights.
    pub lighting: Lighting,
}

impl Scene {
    /// Validates every mesh, material, texture layer and batch reference.
    pub fn validate(&self) -> Result<(), SceneError> {
        for m in &self.meshes {
            m.validate()?;
        }
        let size = self.albedo_layers.first().map_or(1, |l| l.size);
        for (i, l) in self.albedo_layers.iter().enumerate() {
            if l.size != size || !l.size.is_power_of_two() {
                return Err(SceneError::TextureSize {
                    layer: i,
                    detail: format!(
                        "size {} differs from layer 0's {size} or is not a power of two",
                        l.size
                    ),
                });
            }
            if l.texels.len() != (l.size as usize).pow(2) {
                return Err(SceneError::TextureSize {
                    layer: i,
                    detail: format!(
                        "{} texels for a {}x{} layer",
                        l.texels.len(),
                        l.size,
                        l.size
                    ),
                });
            }
        }
        for m in &self.materials {
            if m.albedo_layer as usize >= self.albedo_layers.len() {
                return Err(SceneError::UnknownTextureLayer {
                    material: m.name.clone(),
                    layer: m.albedo_layer,
                    layers: self.albedo_layers.len(),
                });
            }
            if !(m.tint.is_finite()
                && m.alpha_cutoff.is_finite()
                && m.roughness.is_finite()
                && m.specular.is_finite())
            {
                return Err(SceneError::NonFinite {
                    what: format!("a constant of material `{}`", m.name),
                });
            }
        }
        for (b, batch) in self.batches.iter().enumerate() {
            if batch.mesh.0 >= self.meshes.len() {
                return Err(SceneError::UnknownReference {
                    batch: b,
                    kind: "mesh",
                    id: batch.mesh.0,
                });
            }
            if batch.material.0 >= self.materials.len() {
                return Err(SceneError::UnknownReference {
                    batch: b,
                    kind: "material",
                    id: batch.material.0,
                });
            }
            if let Some(i) = batch.instances.iter().position(|t| !t.is_finite()) {
                return Err(SceneError::NonFinite {
                    what: format!("instance {i} of batch {b}"),
                });
            }
        }
        let c = &self.camera;
        if !(c.position.is_finite()
            && c.target.is_finite()
            && c.fov_y.is_finite()
            && c.near.is_finite())
            || c.near <= 0.0
            || c.fov_y <= 0.0
            || c.position == c.target
        {
            return Err(SceneError::NonFinite {
                what: "the camera (or a zero near plane, field of view or view direction)".into(),
            });
        }
        Ok(())
    }

    /// Total instances over all batches.
    pub fn instance_count(&self) -> usize {
        self.batches.iter().map(|b| b.instances.len()).sum()
    }

    /// Total triangles drawn (instances × their mesh's primitives).
    pub fn triangle_count(&self) -> u64 {
        self.batches
            .iter()
            .map(|b| {
                b.instances.len() as u64
                    * self
                        .meshes
                        .get(b.mesh.0)
                        .map_or(0, |m| m.primitive_count() as u64)
            })
            .sum()
    }

    /// Total vertices of all instances (the "vertices in the scene" of seed 000's table).
    pub fn vertex_count(&self) -> u64 {
        self.batches
            .iter()
            .map(|b| {
                b.instances.len() as u64
                    * self
                        .meshes
                        .get(b.mesh.0)
                        .map_or(0, |m| m.positions.len() as u64)
            })
            .sum()
    }
}
