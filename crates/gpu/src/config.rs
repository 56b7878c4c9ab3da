//! [`RendererConfig`](crate::RendererConfig)'s groups (image, geometry, lighting, frames) and
//! what they choose beyond the defaults: the
//! laydown and how `Laydown::Auto` chose, the light paths, MSAA, VRS, shadows, the vertex
//! ring's sizes, the compute laydown's limits and the device paths the renderer found.

pub use crate::context::{ActivePaths, PrimitiveIdPath};
pub use crate::passes::compute_laydown::{
    COMPUTE_LAYDOWN_EXTENT_LIMIT, COMPUTE_LAYDOWN_MAX_EXTENT,
};
pub use crate::renderer::{
    AUTO_LAYDOWN_FRAMES, FrameConfig, GeometryConfig, ImageConfig, LaydownChoice, LaydownReason,
    LightPaths, LightingConfig, MSAA_SAMPLES, MsaaLighting, VrsConfig,
};
pub use crate::resources::vis64::{
    COMPUTE_LAYDOWN_FEATURES, LAYDOWN_TEXTURE_FEATURES, LaydownTarget,
};
pub use crate::shadows::ShadowConfig;
pub use crate::spot_shadows::{MAX_SPOT_SHADOW_MAPS, SpotShadowConfig};
/// The talk's vertex ring sizes (PS4 12 MiB, PS5 24 MiB), for `RendererConfig::geometry.vertex_ring`.
pub use tiling::{RING_BYTES_PS4, RING_BYTES_PS5};
