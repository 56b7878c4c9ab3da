//! The renderer's error type.

use std::fmt;

pub use scene::{FrameError, SceneError, WaterError};

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
        /// Bytes in the pool (`RendererConfig::frames.upload_pool`).
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
        /// Which value (`RendererConfig::image.width`).
        field: &'static str,
        /// What it was.
        value: f64,
        /// What is allowed.
        allowed: &'static str,
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
                 RendererConfig::frames.upload_pool) is full: the frame's {frame_bytes} bytes of \
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

impl std::error::Error for Error {}

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

impl From<WaterError> for Error {
    /// The water crate's refusals stay [`Error::Water`], the renderer's limits
    /// [`Error::WaterLimit`] (the variants `set_water` always returned).
    fn from(e: WaterError) -> Self {
        match e {
            WaterError::Water(e) => Error::Water(e),
            WaterError::Limit {
                what,
                value,
                limit,
                limit_name,
            } => Error::WaterLimit {
                what,
                value,
                limit,
                limit_name,
            },
        }
    }
}

impl From<SceneError> for Error {
    fn from(e: SceneError) -> Self {
        Error::Scene(e)
    }
}

/// Shorthand for the renderer's results.
pub type Result<T, E = Error> = std::result::Result<T, E>;
