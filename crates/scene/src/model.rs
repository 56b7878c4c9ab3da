//! The scene a renderer prepares once: meshes, materials, albedo layers and batches of
//! instances. What changes per frame (camera, time, lights) is the
//! [`FrameInput`].
//!
//! Conventions: right-handed world space, +Y up, metres. Texture coordinates have (0, 0)
//! at the top-left of an albedo layer, v down.

use glam::{Affine3A, Vec2, Vec3, Vec4};

#[cfg(doc)]
use crate::FrameInput;
use crate::error::SceneError;
use crate::{AlbedoLayer, DataLayer};

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
    /// A stable small integer: the GPU material row's shader (the wind sways the
    /// alpha-tested). Passes are split by [`Material::shader_key`], which includes it.
    pub fn id(self) -> u32 {
        match self {
            ShaderKind::Opaque => 0,
            ShaderKind::AlphaTested => 1,
        }
    }
}

/// A material in glTF 2.0's metallic-roughness model: a base colour (an albedo layer times
/// [`Material::tint`]), metallic and roughness, and optional normal, metallic-roughness,
/// occlusion and emissive maps ([`MaterialMaps`]). Every map reads the mesh's one set of
/// texture coordinates (`Mesh::uvs`) with trilinear filtering and repeat addressing.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// A name for error messages.
    pub name: String,
    /// The shader.
    pub shader: ShaderKind,
    /// Layer of [`Scene::albedo_layers`]: the base colour (sRGB) and, for alpha-tested
    /// materials, the alpha the cutoff tests.
    pub albedo_layer: u32,
    /// Multiplies the texture's colour (linear RGB): glTF's `baseColorFactor`.
    pub tint: Vec3,
    /// Alpha-test cutoff in [0, 1] for [`ShaderKind::AlphaTested`] (texels whose alpha is
    /// below it are discarded; ignored by opaque materials, but still checked).
    pub alpha_cutoff: f32,
    /// Perceptual roughness in [0, 1] (GGX alpha = roughness²), multiplied by the
    /// metallic-roughness map's green channel where there is one.
    pub roughness: f32,
    /// Specular intensity in [0, 1]: scales a dielectric's specular lobe (Schlick's Fresnel
    /// from 0.04 at normal incidence), so 1 is glTF's dielectric.
    pub specular: f32,
    /// Metalness in [0, 1] (glTF's `metallicFactor`), multiplied by the metallic-roughness
    /// map's blue channel where there is one: the diffuse colour is `base · (1 −
    /// metallic)`, the specular lobe's Fresnel `mix(specular · F(0.04), F(base),
    /// metallic)` with Schlick's `F(f0)`.
    pub metallic: f32,
    /// Emitted radiance, linear RGB, each channel finite and ≥ 0 (glTF's `emissiveFactor`
    /// times `KHR_materials_emissive_strength`), multiplied by the emissive map where
    /// there is one; in the units of the frame's sun colour (radiance the camera sees
    /// directly, added once).
    pub emissive: Vec3,
    /// The optional texture maps.
    pub maps: MaterialMaps,
    /// HFW's mixed frame (`gpu::RendererConfig::geometry.mixed_frame`): batches
    /// of this material skip the vis buffer and are drawn by the regular geometry pass
    /// after the laydown, which writes the G-buffer from a fragment shader and clears the
    /// pixels' validity bits (the talk's stencil bit), so the classification leaves those
    /// pixels to it. Terrain and rocks in the demo scenes. Opaque materials only
    /// ([`SceneError::RegularNotOpaque`]). Every other path, and the
    /// static query's draws, ignore it.
    pub regular: bool,
}

impl Default for Material {
    /// An opaque, white, dielectric material of roughness 0.5 on albedo layer 0, with no
    /// maps.
    fn default() -> Self {
        Material {
            name: String::new(),
            shader: ShaderKind::Opaque,
            albedo_layer: 0,
            tint: Vec3::ONE,
            alpha_cutoff: 0.5,
            roughness: 0.5,
            specular: 1.0,
            metallic: 0.0,
            emissive: Vec3::ZERO,
            maps: MaterialMaps::default(),
            regular: false,
        }
    }
}

/// A material's optional texture maps (glTF 2.0's `normalTexture`,
/// `metallicRoughnessTexture`, `occlusionTexture` and `emissiveTexture`). The data maps
/// (normal, metallic-roughness, occlusion) are layers of [`Scene::data_layers`], stored
/// and filtered linearly; the emissive map is a colour, a layer of
/// [`Scene::albedo_layers`] (sRGB).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MaterialMaps {
    /// Tangent-space normal map.
    pub normal: Option<NormalMap>,
    /// Layer of [`Scene::data_layers`] whose green channel multiplies the roughness and
    /// blue channel the metallic (glTF's packing; red and alpha are not read).
    pub metallic_roughness: Option<u32>,
    /// Ambient occlusion.
    pub occlusion: Option<OcclusionMap>,
    /// Layer of [`Scene::albedo_layers`] whose colour multiplies [`Material::emissive`].
    pub emissive: Option<u32>,
}

/// A tangent-space normal map (glTF 2.0 `normalTexture`): texel RGB in [0, 1] encodes the
/// normal `(2 r − 1, 2 g − 1, 2 b − 1)` in the basis (tangent, bitangent, normal), where the
/// bitangent is `cross(normal, tangent.xyz) · tangent.w` of the mesh's tangents
/// (`Mesh::tangents`): +X follows increasing u, +Y the bitangent, +Z points out of the
/// surface. The perturbed normal is `normalize(t · x · scale + b · y · scale + n · z)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalMap {
    /// Layer of [`Scene::data_layers`].
    pub layer: u32,
    /// Scales the map's X and Y (glTF's `normalTexture.scale`); finite, in [-16, 16].
    pub scale: f32,
}

/// An ambient occlusion map (glTF 2.0 `occlusionTexture`): its red channel `o` darkens
/// the indirect (ambient) light by `1 + strength · (o − 1)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OcclusionMap {
    /// Layer of [`Scene::data_layers`].
    pub layer: u32,
    /// In [0, 1] (glTF's `occlusionTexture.strength`).
    pub strength: f32,
}

impl Material {
    /// The key `tiling` sorts and splits passes by (HFW: one pass, and one resolve
    /// shader, per material shader): [`Material::features`]' bits, so materials of one
    /// permutation share passes and two permutations never do.
    pub fn shader_key(&self) -> u32 {
        self.features().0
    }

    /// The permutation of the material's shader: which optional features it has
    /// ([`MaterialFeatures`]).
    pub fn features(&self) -> MaterialFeatures {
        let m = &self.maps;
        let mut f = MaterialFeatures::empty();
        f.set(MaterialFeatures::NORMAL_MAP, m.normal.is_some());
        f.set(
            MaterialFeatures::METALLIC_ROUGHNESS_MAP,
            m.metallic_roughness.is_some(),
        );
        f.set(MaterialFeatures::OCCLUSION_MAP, m.occlusion.is_some());
        f.set(
            MaterialFeatures::EMISSIVE,
            m.emissive.is_some() || self.emissive != Vec3::ZERO,
        );
        f.set(
            MaterialFeatures::ALPHA_TEST,
            self.shader == ShaderKind::AlphaTested,
        );
        f
    }
}

/// The optional features of a material, as bits (HFW's material shader permutation).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct MaterialFeatures(pub u32);

impl MaterialFeatures {
    /// A tangent-space normal map.
    pub const NORMAL_MAP: Self = Self(1);
    /// A metallic-roughness map.
    pub const METALLIC_ROUGHNESS_MAP: Self = Self(2);
    /// An occlusion map.
    pub const OCCLUSION_MAP: Self = Self(4);
    /// Emission (a factor, a map or both).
    pub const EMISSIVE: Self = Self(8);
    /// The alpha test.
    pub const ALPHA_TEST: Self = Self(16);
    /// Every feature with its name, in bit order.
    pub const NAMED: [(Self, &'static str); 5] = [
        (Self::NORMAL_MAP, "normal map"),
        (Self::METALLIC_ROUGHNESS_MAP, "metallic-roughness map"),
        (Self::OCCLUSION_MAP, "occlusion map"),
        (Self::EMISSIVE, "emissive"),
        (Self::ALPHA_TEST, "alpha test"),
    ];

    /// No feature.
    pub const fn empty() -> Self {
        Self(0)
    }

    /// Whether every bit of `other` is set.
    pub const fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }

    /// Sets or clears `other`'s bits.
    pub fn set(&mut self, other: Self, on: bool) {
        if on {
            self.0 |= other.0;
        } else {
            self.0 &= !other.0;
        }
    }

    /// The names of the features set, in bit order ("none" for none).
    pub fn names(self) -> Vec<&'static str> {
        let v: Vec<_> = Self::NAMED
            .iter()
            .filter(|(f, _)| self.contains(*f))
            .map(|(_, n)| *n)
            .collect();
        if v.is_empty() { vec!["none"] } else { v }
    }
}

/// Checks that `value` lies in `[lo, hi]` (NaN never does).
pub(crate) fn check_range(
    field: impl FnOnce() -> String,
    value: f32,
    lo: f32,
    hi: f32,
    allowed: &'static str,
) -> Result<(), (String, f32, &'static str)> {
    if value >= lo && value <= hi {
        Ok(())
    } else {
        Err((field(), value, allowed))
    }
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

/// What the static query's setup handle `h` draws: `Scene::static_setups[h]` (seed 001's
/// DrawableSetup). The GPU places each frame's visible instances of the setup into
/// `capacity` reserved instance slots and draws them with one indirect draw; instances
/// past the capacity in one frame are dropped and counted
/// (`gpu::statics::StaticFrameStats::over_capacity`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StaticSetup {
    /// The geometry.
    pub mesh: MeshId,
    /// The material.
    pub material: MaterialId,
    /// Most visible instances of this setup in one frame (≥ 1): slots and micro-batch IDs
    /// are reserved for that many at `prepare`.
    pub capacity: u32,
}

/// Everything the renderer draws. An empty scene (no batches, or batches without
/// instances) is valid: it renders the sky.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Scene {
    /// Geometry.
    pub meshes: Vec<Mesh>,
    /// Materials.
    pub materials: Vec<Material>,
    /// The albedo texture array's layers (sRGB colour, linear alpha): base colours and
    /// emissive maps.
    pub albedo_layers: Vec<AlbedoLayer>,
    /// The data texture array's layers (linear): normal, metallic-roughness and occlusion
    /// maps. Empty for a scene without them.
    pub data_layers: Vec<DataLayer>,
    /// Batches of instances (drawn every frame; the CPU plans them once).
    pub batches: Vec<Batch>,
    /// What the static query's setup handles draw (index = handle); empty for a scene
    /// without static content. Frames with a static query
    /// (`gpu::Renderer::render_static`) draw its output.
    pub static_setups: Vec<StaticSetup>,
    /// HFW's animated foliage ("All our foliage is animated"): the wind that sways every
    /// [`ShaderKind::AlphaTested`] instance, `None` for a still scene (the default).
    pub wind: Option<Wind>,
}

/// A wind that sways the alpha-tested (foliage) instances in every pass that positions
/// vertices, so all paths see the same animated geometry (and bit-identical depths).
///
/// Displacement of object-space point `p` of an instance with origin-relative
/// translation `t` at time `s` (seconds), in world space (horizontal only):
///
/// ```text
/// bend  = clamp(p.y / height, 0, 1)²                   per-vertex bend weight
/// phase = 2π · fract(0.37 t.x + 0.23 t.z)              per-instance phase
/// sway  = sin(2π f s + phase) + 0.3 sin(2π 2.3 f s + 2 phase)
/// d     = amplitude · bend · sway · (direction.x, 0, direction.y)
/// ```
///
/// [`Wind::displacement`] is the CPU reference of the shader (`gpu::scene_bindings`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wind {
    /// Horizontal direction (world x, z); normalised on upload (zero: no sway).
    pub direction: Vec2,
    /// Sway at bend weight 1 (metres), in [0, 1000] (larger sways overflow positions).
    pub amplitude: f32,
    /// Main sway frequency (Hz), in [0, 1000] (larger ones make the phase infinite).
    pub frequency: f32,
    /// Object-space height at which the bend weight reaches 1 (metres), > 0.
    pub height: f32,
}

impl Default for Wind {
    /// A breeze: 8 cm of sway at 1 m and above, 0.6 Hz, along +x and a little +z.
    fn default() -> Self {
        Self {
            direction: Vec2::new(1.0, 0.35),
            amplitude: 0.08,
            frequency: 0.6,
            height: 1.0,
        }
    }
}

impl Wind {
    /// Checks every field (finite, non-negative amplitude and frequency, positive height).
    ///
    /// # Errors
    /// [`SceneError::OutOfRange`] naming the field.
    pub fn validate(&self) -> Result<(), SceneError> {
        let field = |f: &'static str| move || format!("wind.{f}");
        check_range(
            field("direction.x"),
            self.direction.x,
            f32::MIN,
            f32::MAX,
            "finite",
        )
        .and(check_range(
            field("direction.y"),
            self.direction.y,
            f32::MIN,
            f32::MAX,
            "finite",
        ))
        .and(check_range(
            field("amplitude"),
            self.amplitude,
            0.0,
            1000.0,
            "[0, 1000] metres",
        ))
        .and(check_range(
            field("frequency"),
            self.frequency,
            0.0,
            1000.0,
            "[0, 1000] Hz",
        ))
        .and(check_range(
            field("height"),
            self.height,
            f32::MIN_POSITIVE,
            f32::MAX,
            "finite, > 0 metres",
        ))
        .map_err(|(field, value, allowed)| SceneError::OutOfRange {
            field,
            value,
            allowed,
        })
    }

    /// The four constants the shaders read (`gpu`'s `FrameUniforms::wind`): direction
    /// times amplitude (x, z), angular frequency (rad/s), 1 / height.
    #[must_use]
    pub fn uniform(&self) -> [f32; 4] {
        let d = self.direction.normalize_or_zero() * self.amplitude;
        [
            d.x,
            d.y,
            std::f32::consts::TAU * self.frequency,
            1.0 / self.height,
        ]
    }

    /// CPU reference of the shader's displacement (world metres, added to the transformed
    /// position) of object-space point `p` of an instance whose origin-relative
    /// translation is `translation`, at `time` seconds. The same f32 arithmetic as the
    /// WGSL (`sin` may differ in its last bits).
    #[must_use]
    pub fn displacement(&self, translation: Vec3, p: Vec3, time: f32) -> Vec3 {
        wind_displacement(self.uniform(), translation, p, time)
    }
}

/// `Wind::displacement` from the uploaded constants (all zero: none).
fn wind_displacement(w: [f32; 4], t: Vec3, p: Vec3, time: f32) -> Vec3 {
    let bend = (p.y * w[3]).clamp(0.0, 1.0);
    let weight = bend * bend;
    let phase = std::f32::consts::TAU * {
        let x = 0.37 * t.x + 0.23 * t.z;
        x - x.floor()
    };
    let a = w[2] * time;
    let sway = (a + phase).sin() + 0.3 * (2.3 * a + 2.0 * phase).sin();
    Vec3::new(w[0], 0.0, w[1]) * (weight * sway)
}

impl Scene {
    /// Validates every mesh, material, texture layer and batch reference.
    pub fn validate(&self) -> Result<(), SceneError> {
        for m in &self.meshes {
            m.validate()?;
        }
        if let Some(w) = &self.wind {
            w.validate()?;
        }
        check_layers(
            "albedo_layers",
            self.albedo_layers.iter().map(|l| (l.size, l.texels.len())),
        )?;
        check_layers(
            "data_layers",
            self.data_layers.iter().map(|l| (l.size, l.texels.len())),
        )?;
        for m in &self.materials {
            let (albedo, data) = (self.albedo_layers.len(), self.data_layers.len());
            let maps = &m.maps;
            let references = [
                ("albedo_layer", Some(m.albedo_layer), albedo),
                ("maps.normal", maps.normal.map(|n| n.layer), data),
                ("maps.metallic_roughness", maps.metallic_roughness, data),
                ("maps.occlusion", maps.occlusion.map(|o| o.layer), data),
                ("maps.emissive", maps.emissive, albedo),
            ];
            for (field, layer, layers) in references {
                if let Some(layer) = layer
                    && layer as usize >= layers
                {
                    return Err(SceneError::UnknownTextureLayer {
                        material: m.name.clone(),
                        field,
                        layer,
                        layers,
                    });
                }
            }
            if m.regular && m.shader != ShaderKind::Opaque {
                return Err(SceneError::RegularNotOpaque {
                    material: m.name.clone(),
                });
            }
            let field = |f: &'static str| move || format!("material `{}`: {f}", m.name);
            let unit = |f: &'static str, v: f32| check_range(field(f), v, 0.0, 1.0, "[0, 1]");
            let colour =
                |f: &'static str, v: f32| check_range(field(f), v, 0.0, f32::MAX, "finite, >= 0");
            unit("alpha_cutoff", m.alpha_cutoff)
                .and(unit("roughness", m.roughness))
                .and(unit("specular", m.specular))
                .and(unit("metallic", m.metallic))
                .and(colour("tint.r", m.tint.x))
                .and(colour("tint.g", m.tint.y))
                .and(colour("tint.b", m.tint.z))
                .and(colour("emissive.r", m.emissive.x))
                .and(colour("emissive.g", m.emissive.y))
                .and(colour("emissive.b", m.emissive.z))
                .and(maps.normal.map_or(Ok(()), |n| {
                    check_range(
                        field("maps.normal.scale"),
                        n.scale,
                        -16.0,
                        16.0,
                        "[-16, 16]",
                    )
                }))
                .and(
                    maps.occlusion
                        .map_or(Ok(()), |o| unit("maps.occlusion.strength", o.strength)),
                )
                .map_err(|(field, value, allowed)| SceneError::OutOfRange {
                    field,
                    value,
                    allowed,
                })?;
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
        let mut slots = 0u64;
        for (i, st) in self.static_setups.iter().enumerate() {
            let problem = if st.mesh.0 >= self.meshes.len() {
                Some(format!("mesh {} of {}", st.mesh.0, self.meshes.len()))
            } else if st.material.0 >= self.materials.len() {
                Some(format!(
                    "material {} of {}",
                    st.material.0,
                    self.materials.len()
                ))
            } else if st.capacity == 0 {
                Some("capacity 0 (at least 1)".to_owned())
            } else {
                None
            };
            if let Some(problem) = problem {
                return Err(SceneError::StaticSetup { setup: i, problem });
            }
            slots += u64::from(st.capacity);
        }
        if slots + self.instance_count() as u64 > u64::from(u32::MAX) {
            return Err(SceneError::StaticSetup {
                setup: self.static_setups.len().saturating_sub(1),
                problem: format!(
                    "{slots} reserved slots and {} instances pass u32 instance indices",
                    self.instance_count()
                ),
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
        self.per_instance(|m| m.primitive_count() as u64)
    }

    /// Total vertices of all instances (the "vertices in the scene" of seed 000's table).
    pub fn vertex_count(&self) -> u64 {
        self.per_instance(|m| m.positions.len() as u64)
    }

    /// The sum over instances of `f` of their mesh (0 for an unknown mesh).
    fn per_instance(&self, f: impl Fn(&Mesh) -> u64) -> u64 {
        self.batches
            .iter()
            .map(|b| b.instances.len() as u64 * self.meshes.get(b.mesh.0).map_or(0, &f))
            .sum()
    }

    /// Every batch's instance positions (world, metres): what `tiling` sorts batches by.
    #[must_use]
    pub fn instance_positions(&self) -> Vec<Vec<[f32; 3]>> {
        self.batches
            .iter()
            .map(|b| {
                b.instances
                    .iter()
                    .map(|t| t.translation.to_array())
                    .collect()
            })
            .collect()
    }

    /// The batches as `tiling` plans them: shader and material as the sort keys, the
    /// geometry of mesh `m` from `geometry(m)`, `positions` from
    /// [`Scene::instance_positions`]. A batch whose material does not exist (a scene that
    /// fails [`Scene::validate`]) sorts as [`ShaderKind::Opaque`].
    pub fn tiling_batches<'a>(
        &self,
        positions: &'a [Vec<[f32; 3]>],
        geometry: impl Fn(usize) -> tiling::Geometry,
    ) -> Vec<tiling::Batch<'a>> {
        self.batches
            .iter()
            .zip(positions)
            .map(|(b, pos)| tiling::Batch {
                shader: self
                    .materials
                    .get(b.material.0)
                    .map_or(0, Material::shader_key),
                batch_data: b.material.0 as u64,
                geometry: geometry(b.mesh.0),
                instances: pos,
            })
            .collect()
    }
}

/// Checks that the layers of one texture array (`(size, texel count)` each) share one
/// power-of-two size and hold `size²` texels each.
fn check_layers(
    array: &'static str,
    layers: impl Iterator<Item = (u32, usize)>,
) -> Result<(), SceneError> {
    let mut first = None;
    for (i, (size, texels)) in layers.enumerate() {
        let size0 = *first.get_or_insert(size);
        if size != size0 || !size.is_power_of_two() {
            return Err(SceneError::TextureSize {
                array,
                layer: i,
                detail: format!(
                    "size {size} differs from layer 0's {size0} or is not a power of two"
                ),
            });
        }
        if texels != (size as usize).pow(2) {
            return Err(SceneError::TextureSize {
                array,
                layer: i,
                detail: format!("{texels} texels for a {size}x{size} layer"),
            });
        }
    }
    Ok(())
}
