//! The errors of a scene, a frame input and a water scene that cannot be rendered as
//! given: each names the item, the value and the limit or range it breaks.

use std::fmt;

/// A scene that cannot be rendered as given.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum SceneError {
    /// A static tile cannot be activated on the GPU.
    StaticTile {
        /// The tile's id.
        tile: u32,
        /// Why.
        problem: &'static str,
    },
    /// A static setup refers to a missing mesh or material, or its capacity is out of
    /// range.
    StaticSetup {
        /// Index in `Scene::static_setups` (the setup handle).
        setup: usize,
        /// What is wrong.
        problem: String,
    },
    /// A mesh has more primitives than 16-bit indices and the vis-buffer ID allow.
    TooManyPrimitives {
        /// The mesh's name.
        mesh: String,
        /// Its primitive count.
        primitives: usize,
        /// The limit (65 536).
        limit: usize,
    },
    /// A mesh has more vertices than 16-bit indices can address.
    TooManyVertices {
        /// The mesh's name.
        mesh: String,
        /// Its vertex count.
        vertices: usize,
        /// The limit (65 536).
        limit: usize,
    },
    /// A mesh's index count is not a multiple of three.
    IndexCountNotTriangles {
        /// The mesh's name.
        mesh: String,
        /// Its index count.
        indices: usize,
    },
    /// An index refers past the mesh's vertices.
    IndexOutOfRange {
        /// The mesh's name.
        mesh: String,
        /// Position in the index array.
        at: usize,
        /// The index found.
        index: u32,
        /// The mesh's vertex count.
        vertices: usize,
    },
    /// Attribute arrays of a mesh differ in length.
    AttributeLength {
        /// The mesh's name.
        mesh: String,
        /// Which attribute.
        attribute: &'static str,
        /// Its length.
        len: usize,
        /// The position count.
        expected: usize,
    },
    /// A float in the scene is NaN or infinite.
    NonFinite {
        /// Where it was found.
        what: String,
    },
    /// A batch refers to a mesh or material that does not exist.
    UnknownReference {
        /// The batch's index.
        batch: usize,
        /// "mesh" or "material".
        kind: &'static str,
        /// The id it used.
        id: usize,
    },
    /// A material uses a texture layer that does not exist.
    UnknownTextureLayer {
        /// The material's name.
        material: String,
        /// Which of its fields (`albedo_layer`, `maps.normal`, ...).
        field: &'static str,
        /// The layer it used.
        layer: u32,
        /// How many layers the scene has.
        layers: usize,
    },
    /// Texture layers differ in size, or a layer's pixel count does not match its size.
    TextureSize {
        /// Which array: `albedo_layers` or `data_layers`.
        array: &'static str,
        /// The layer.
        layer: usize,
        /// What is wrong.
        detail: String,
    },
    /// The micro-batch / pass builder refused the scene (a limit from the talk).
    Tiling(String),
    /// A primitive-ID encoder refused a mesh.
    Encoding(String),
    /// A material drawn by the mixed frame's regular geometry pass
    /// ([`Material::regular`](crate::Material::regular)) that is not
    /// [`ShaderKind::Opaque`](crate::ShaderKind::Opaque): that pass tests depth before its
    /// fragment shader runs (it clears the validity bit as a side effect), so it cannot
    /// discard.
    RegularNotOpaque {
        /// The material's name.
        material: String,
    },
    /// A value outside its allowed range (NaN and infinities included).
    OutOfRange {
        /// Which value (`material \`bark\`: roughness`).
        field: String,
        /// What it was.
        value: f32,
        /// What is allowed.
        allowed: &'static str,
    },
}

/// A frame input that cannot be rendered as given.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum FrameError {
    /// A value outside its allowed range (NaN and infinities included).
    OutOfRange {
        /// Which value (`camera.fov_y`, `lighting.point_lights[3].radius`).
        field: String,
        /// What it was.
        value: f32,
        /// What is allowed.
        allowed: &'static str,
    },
    /// The camera has no well-defined orientation.
    CameraBasis {
        /// What is wrong.
        detail: &'static str,
    },
    /// More local lights (point and spot together) than the light culling takes.
    TooManyLocalLights {
        /// How many were given.
        count: usize,
        /// [`MAX_LOCAL_LIGHTS`](crate::MAX_LOCAL_LIGHTS).
        limit: usize,
    },
}

/// A water scene that breaks a limit or holds a value outside its range. Exhaustive: the
/// renderer maps each variant onto its own error's.
#[derive(Debug, Clone, PartialEq)]
pub enum WaterError {
    /// The water crate refused a value (a world, an atlas, a noise texture, FBM
    /// parameters, an option's range: each names the field).
    Water(water::Error),
    /// The water scene breaks one of the renderer's water limits (the `MAX_WATER_*`
    /// constants, from the talk where it gives one: [`MAX_WATER_SECTORS_PER_SIDE`] is Far
    /// Cry's 64 x 64 sectors).
    ///
    /// [`MAX_WATER_SECTORS_PER_SIDE`]: crate::MAX_WATER_SECTORS_PER_SIDE
    Limit {
        /// What exceeded it.
        what: &'static str,
        /// The value.
        value: u64,
        /// The limit.
        limit: u64,
        /// The limit's name.
        limit_name: &'static str,
    },
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneError::StaticTile { tile, problem } => {
                write!(f, "static tile {tile} not activated: {problem}")
            }
            SceneError::StaticSetup { setup, problem } => {
                write!(f, "static setup {setup}: {problem}")
            }
            SceneError::TooManyPrimitives {
                mesh,
                primitives,
                limit,
            } => write!(
                f,
                "mesh `{mesh}` has {primitives} primitives, over the limit of {limit} per geometry \
                 (16-bit indices; the vis-buffer primitive field); split it"
            ),
            SceneError::TooManyVertices {
                mesh,
                vertices,
                limit,
            } => write!(
                f,
                "mesh `{mesh}` has {vertices} vertices, over the {limit} that 16-bit indices address; split it"
            ),
            SceneError::IndexCountNotTriangles { mesh, indices } => {
                write!(
                    f,
                    "mesh `{mesh}` has {indices} indices, not a multiple of 3"
                )
            }
            SceneError::RegularNotOpaque { material } => write!(
                f,
                "material `{material}`: `regular` needs ShaderKind::Opaque (the regular \
                 geometry pass tests depth before shading and cannot discard)"
            ),
            SceneError::IndexOutOfRange {
                mesh,
                at,
                index,
                vertices,
            } => write!(
                f,
                "mesh `{mesh}`: index {index} at position {at} is out of range ({vertices} vertices)"
            ),
            SceneError::AttributeLength {
                mesh,
                attribute,
                len,
                expected,
            } => write!(
                f,
                "mesh `{mesh}`: {attribute} has {len} entries, expected {expected} (one per position)"
            ),
            SceneError::NonFinite { what } => write!(f, "{what} is NaN or infinite"),
            SceneError::UnknownReference { batch, kind, id } => {
                write!(
                    f,
                    "batch {batch} refers to {kind} {id}, which does not exist"
                )
            }
            SceneError::UnknownTextureLayer {
                material,
                field,
                layer,
                layers,
            } => write!(
                f,
                "material `{material}`: {field} is layer {layer}, but its array has {layers} layers"
            ),
            SceneError::TextureSize {
                array,
                layer,
                detail,
            } => {
                write!(f, "{array}[{layer}]: {detail}")
            }
            SceneError::Tiling(s) => write!(f, "micro batches and passes: {s}"),
            SceneError::Encoding(s) => write!(f, "primitive-ID encoding: {s}"),
            SceneError::OutOfRange {
                field,
                value,
                allowed,
            } => write!(f, "{field} is {value}, allowed: {allowed}"),
        }
    }
}

impl fmt::Display for FrameError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FrameError::OutOfRange {
                field,
                value,
                allowed,
            } => write!(f, "{field} is {value}, allowed: {allowed}"),
            FrameError::CameraBasis { detail } => write!(f, "{detail}"),
            FrameError::TooManyLocalLights { count, limit } => write!(
                f,
                "{count} point and spot lights, over the limit of {limit}"
            ),
        }
    }
}

impl fmt::Display for WaterError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            WaterError::Water(e) => write!(f, "water: {e}"),
            WaterError::Limit {
                what,
                value,
                limit,
                limit_name,
            } => write!(
                f,
                "water: {what} is {value}, over the limit {limit_name} = {limit}"
            ),
        }
    }
}

impl std::error::Error for SceneError {}
impl std::error::Error for FrameError {}
impl std::error::Error for WaterError {}

impl From<water::Error> for WaterError {
    fn from(e: water::Error) -> Self {
        WaterError::Water(e)
    }
}
