//! The renderer's error type.

use std::fmt;

/// Everything the renderer can fail with. Device loss and out-of-memory are errors here,
/// never panics; so are scene limits from the talks (each names the limit and the item).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// No adapter was found. The message says how to get one.
    NoAdapter {
        /// What wgpu said.
        reason: String,
    },
    /// The adapter refused the device request.
    RequestDevice(String),
    /// The device lacks a feature a requested path needs.
    MissingFeature {
        /// The wgpu feature.
        feature: &'static str,
        /// What needs it.
        needed_by: &'static str,
    },
    /// wgpu reported a validation error: a bug in the renderer, or a scene that breaks a
    /// device limit the renderer did not check.
    Validation(String),
    /// The device ran out of memory.
    OutOfMemory(String),
    /// The device was lost (driver reset, GPU removed).
    DeviceLost(String),
    /// Waiting for the GPU failed or timed out.
    Poll(String),
    /// Reading a buffer back failed.
    Map(String),
    /// The scene breaks a limit, refers to something that does not exist, or holds a
    /// value outside its range.
    Scene(SceneError),
    /// A frame input holds a value outside its range.
    Frame(FrameError),
    /// A slice given to the renderer has the wrong length.
    Length {
        /// What was given.
        what: &'static str,
        /// Its length.
        got: usize,
        /// The length it must have.
        expected: usize,
    },
    /// A shader failed to compose (a bug in the renderer's WGSL modules).
    Shader(shader::Error),
    /// A prepared scene was given to a renderer other than the one that prepared it.
    ForeignScene,
    /// A device limit is too small for the request.
    DeviceLimit {
        /// The wgpu limit's name.
        limit: &'static str,
        /// What the request needs.
        needed: u64,
        /// What the device has.
        available: u64,
    },
    /// Writing an image failed.
    Image(String),
    /// The static scene refused a value (a HiZ size, a view).
    StaticScene(staticscene::Error),
    /// A frame's uploads found the upload pool full even after waiting for the device:
    /// the pool is smaller than a frame's uploads, or the GPU has not finished the frames
    /// holding it. Nothing was overwritten; the frame was not submitted.
    UploadPoolExhausted {
        /// Bytes in the pool (`RendererConfig::upload_pool`).
        pool_bytes: u64,
        /// Blocks in the pool, all live.
        blocks: u32,
        /// Bytes the frame tried to upload.
        frame_bytes: u64,
    },
    /// The upload allocator refused a request (a bug: every upload is sized to fit).
    Upload(String),
    /// The water crate refused the water scene (a world, an atlas, a noise texture, FBM
    /// parameters: each names the limit or the field).
    Water(water::Error),
    /// The water scene breaks one of the renderer's water limits (named `pub const`s of
    /// this crate, from the talk where it gives one: `MAX_WATER_SECTORS_PER_SIDE` is Far
    /// Cry's 64 x 64 sectors).
    WaterLimit {
        /// What exceeded it.
        what: &'static str,
        /// The value.
        value: u64,
        /// The limit.
        limit: u64,
        /// The limit's name.
        limit_name: &'static str,
    },
    /// A [`RendererConfig`](crate::RendererConfig) value outside its range.
    Config {
        /// Which value (`RendererConfig::width`).
        field: &'static str,
        /// What it was.
        value: f64,
        /// What is allowed.
        allowed: &'static str,
    },
}

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
        /// The layer it used.
        layer: u32,
        /// How many layers the scene has.
        layers: usize,
    },
    /// Texture layers differ in size, or a layer's pixel count does not match its size.
    TextureSize {
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

impl Error {
    /// `Err(Error::Config { .. })`: a configuration value outside what it allows.
    pub(crate) fn config<T>(field: &'static str, value: f64, allowed: &'static str) -> Result<T> {
        Err(Error::Config {
            field,
            value,
            allowed,
        })
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::NoAdapter { reason } => write!(
                f,
                "no GPU adapter found ({reason}). The renderer runs on any Vulkan driver; \
                 without a GPU install Mesa's software driver: \
                 `apt-get install -y mesa-vulkan-drivers libvulkan1` (Debian/Ubuntu, lavapipe). \
                 On NVIDIA, install the driver's Vulkan ICD or set VK_DRIVER_FILES to nvidia_icd.json"
            ),
            Error::RequestDevice(s) => write!(f, "the adapter refused the device request: {s}"),
            Error::MissingFeature { feature, needed_by } => write!(
                f,
                "{needed_by} needs the device feature {feature}, which this device does not have"
            ),
            Error::Validation(s) => write!(f, "wgpu validation error: {s}"),
            Error::OutOfMemory(s) => write!(f, "the GPU ran out of memory: {s}"),
            Error::DeviceLost(s) => write!(f, "the GPU device was lost: {s}"),
            Error::Poll(s) => write!(f, "waiting for the GPU failed: {s}"),
            Error::Map(s) => write!(f, "reading a GPU buffer back failed: {s}"),
            Error::Scene(e) => write!(f, "scene error: {e}"),
            Error::Frame(e) => write!(f, "frame input error: {e}"),
            Error::Length {
                what,
                got,
                expected,
            } => write!(f, "{what}: {got} given, {expected} expected"),
            Error::Shader(e) => write!(f, "renderer shader: {e}"),
            Error::ForeignScene => write!(
                f,
                "the scene was prepared by another renderer: prepare it with this one"
            ),
            Error::UploadPoolExhausted {
                pool_bytes,
                blocks,
                frame_bytes,
            } => write!(
                f,
                "the upload pool ({pool_bytes} bytes in {blocks} blocks, \
                 RendererConfig::upload_pool) is full: the frame's {frame_bytes} bytes of \
                 uploads wait for frames the GPU has not finished; raise the pool size or \
                 wait for the device"
            ),
            Error::Upload(e) => write!(f, "upload allocator: {e}"),
            Error::DeviceLimit {
                limit,
                needed,
                available,
            } => write!(
                f,
                "the device limit `{limit}` is {available}, but the request needs {needed}"
            ),
            Error::Image(s) => write!(f, "writing an image failed: {s}"),
            Error::StaticScene(e) => write!(f, "static scene: {e}"),
            Error::Config {
                field,
                value,
                allowed,
            } => write!(f, "{field} is {value}, allowed: {allowed}"),
            Error::Water(e) => write!(f, "water: {e}"),
            Error::WaterLimit {
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
                layer,
                layers,
            } => write!(
                f,
                "material `{material}` uses albedo layer {layer}, but the scene has {layers} layers"
            ),
            SceneError::TextureSize { layer, detail } => {
                write!(f, "albedo layer {layer}: {detail}")
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

impl std::error::Error for Error {}
impl std::error::Error for SceneError {}
impl std::error::Error for FrameError {}

impl From<FrameError> for Error {
    fn from(e: FrameError) -> Self {
        Error::Frame(e)
    }
}

impl From<staticscene::Error> for Error {
    fn from(e: staticscene::Error) -> Self {
        Error::StaticScene(e)
    }
}

impl From<shader::Error> for Error {
    fn from(e: shader::Error) -> Self {
        Error::Shader(e)
    }
}

impl From<water::Error> for Error {
    fn from(e: water::Error) -> Self {
        Error::Water(e)
    }
}

impl From<SceneError> for Error {
    fn from(e: SceneError) -> Self {
        Error::Scene(e)
    }
}

/// Shorthand for the renderer's results.
pub type Result<T, E = Error> = std::result::Result<T, E>;
