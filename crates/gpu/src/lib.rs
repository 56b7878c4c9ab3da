//! The complete wgpu renderer of the workspace: visibility-buffer laydown, GPU
//! classification into loose-tile wave commands, compute material resolve into a G-buffer,
//! deferred lighting (KZ2's sun slices as stable cascaded shadow maps with a baked sun
//! term; point and spot lights through 16x16 tiles or stencil light volumes
//! ([`LightPaths`]) with KZ2's light-shader permutations (with or without specular,
//! [`PointLight::specular`], and spot shadow code), shadow-casting spots
//! ([`SpotShadowConfig`]) whose maps and shading the GPU skips when their volume covers
//! no pixel (KZ2's conditional rendering emulated with indirect draws,
//! [`RendererConfig::conditional_volumes`]); the octahedral or KZ2's G-buffer), and HZD's
//! depth-equal baseline that it replaces (single-sample, or 4x MSAA lit with KZ2's
//! tricks: [`MsaaLighting`]; the visibility-buffer path stays single-sample, one triangle
//! a pixel). Every per-frame upload is
//! sub-allocated from `framealloc`'s pool, so frames can be submitted without waiting
//! ([`Renderer::submit`]). Every format and algorithm comes from the small crates; this
//! crate owns devices, buffers, pipelines and passes.
//!
//! Beside the scene the renderer draws Far Cry 5's water ([`Renderer::set_water`] with a
//! [`WaterScene`]: a baked `water::world::WaterWorld`, its materials, the flow atlas and
//! shore field for foam, decal textures): after lighting, a HiZ-culled visibility pass, a
//! reduced-resolution mini G-buffer at a wider field of view, FBM and decal displacement,
//! 32x32 tiles, screen-space tessellation by indirect draws, normals from depth, foam and
//! a scattering composite over the lit image; the water writes a second depth buffer
//! ([`water_scene`]'s docs say which passes read which).
//!
//! A [`Scene`] (meshes, materials, albedo layers, batches of instances) is prepared once
//! ([`Renderer::prepare`]); each frame takes a [`FrameInput`] (camera, time, sun, point
//! and spot lights) and uploads its constants. The renderer runs on your device: ask for
//! [`Renderer::required_limits`] and any of [`Renderer::optional_features`] when you create
//! it, or let [`headless`] make one.
//!
//! ```no_run
//! use gpu::glam::{Affine3A, Vec2, Vec3, Vec4};
//! use gpu::{
//!     AlbedoLayer, Batch, Camera, FrameInput, Material, MaterialId, Mesh, MeshId, RenderPath,
//!     Renderer, RendererConfig, Scene, ShaderKind,
//! };
//!
//! // A unit quad facing +Z, drawn 100 times in a row, under a 2x2 checker texture.
//! let quad = Mesh {
//!     name: "quad".into(),
//!     positions: vec![Vec3::new(-0.5, -0.5, 0.0), Vec3::new(0.5, -0.5, 0.0),
//!                     Vec3::new(0.5, 0.5, 0.0), Vec3::new(-0.5, 0.5, 0.0)],
//!     normals: vec![Vec3::Z; 4],
//!     uvs: vec![Vec2::new(0.0, 1.0), Vec2::new(1.0, 1.0), Vec2::new(1.0, 0.0), Vec2::ZERO],
//!     tangents: vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 4],
//!     indices: vec![0, 1, 2, 0, 2, 3],
//! };
//! let scene = Scene {
//!     meshes: vec![quad],
//!     materials: vec![Material {
//!         name: "checker".into(),
//!         shader: ShaderKind::Opaque,
//!         albedo_layer: 0,
//!         tint: Vec3::ONE,
//!         alpha_cutoff: 0.5,
//!         roughness: 0.6,
//!         specular: 0.5,
//!         regular: false,
//!     }],
//!     albedo_layers: vec![AlbedoLayer {
//!         size: 2,
//!         texels: vec![[230, 230, 230, 255], [40, 40, 40, 255], [40, 40, 40, 255], [230, 230, 230, 255]],
//!     }],
//!     batches: vec![Batch {
//!         mesh: MeshId(0),
//!         material: MaterialId(0),
//!         instances: (0..100)
//!             .map(|i| Affine3A::from_translation(Vec3::new(i as f32 * 1.2 - 60.0, 0.0, 0.0)))
//!             .collect(),
//!     }],
//!     static_setups: vec![],
//!     wind: None,
//! };
//!
//! let ctx = gpu::headless(&gpu::HeadlessOptions::default())?;
//! let config = RendererConfig { width: 640, height: 360, ..RendererConfig::default() };
//! let mut renderer = Renderer::new(&ctx.device, &ctx.queue, config)?;
//! let prepared = renderer.prepare(&scene)?;
//! let frame = FrameInput::new(Camera::look_at(Vec3::new(0.0, 1.0, 8.0), Vec3::ZERO));
//! renderer.render(&prepared, &frame, RenderPath::Deferred)?;
//! renderer.read_output()?.write_png(std::path::Path::new("quads.png"))?;
//! # Ok::<(), gpu::Error>(())
//! ```

mod context;
pub mod debug;
mod error;
mod frame;
mod gbuffer;
mod image;
mod passes;
mod renderer;
mod resources;
mod shadows;
mod spot_shadows;
mod statics;
mod stats;
mod timing;
pub mod water_scene;

pub use context::{
    ActivePaths, GpuContext, HeadlessOptions, OPTIONAL_FEATURES, PrimitiveIdPath, adapter_line,
    headless, read_buffer, scoped, wait_idle,
};
/// The `deferred` version this crate's API uses (G-buffer layouts, lights, cascades).
pub use deferred;
pub use error::{Error, FrameError, Result, SceneError, WaterError};
pub use frame::local_light_rows;
/// The `framealloc` version this crate's API uses (the upload pool's layout).
pub use framealloc;
pub use glam;
pub use image::{Rgba8Image, diff_image, diff_metrics, heat_color, id_color};
#[doc(hidden)]
pub use passes::classify::ClassificationVariant;
pub use passes::compute_laydown::{
    COMPUTE_LAYDOWN_EXTENT_LIMIT, COMPUTE_LAYDOWN_FEATURES, COMPUTE_LAYDOWN_MAX_EXTENT,
    LAYDOWN_TEXTURE_FEATURES, LaydownStats, LaydownTarget,
};
pub use passes::query::{QueryReadback, StaticQuery, StaticQueryOutput};
pub use passes::vertex_ring::{
    RING_UV_FROM_VERTICES, RING_VERTEX_BYTES, VertexRingReadback, ring_slot,
};
#[doc(hidden)]
pub use renderer::ConditionalLight;
pub use renderer::{
    AUTO_LAYDOWN_FRAMES, FrameOutput, Hooks, Inspect, Laydown, LaydownChoice, LaydownReason,
    LightPathCounts, LightPaths, LightTiles, MSAA_SAMPLES, MsaaLighting, RenderPath, Renderer,
    RendererConfig, VrsConfig, WARM_UP, WaterGBuffer, WaterGBufferInput, WaterTiles, WaterView,
};
pub use resources::uploads::UploadStats;
pub use resources::{PreparedScene, SceneSummary};
/// The scene, frame input and water scene descriptions this crate's API takes (every name
/// below is re-exported from it).
pub use scene;
pub use scene::{
    AlbedoLayer, Batch, Camera, FrameInput, Lighting, MAX_LOCAL_LIGHTS, MAX_PRIMITIVES_PER_MESH,
    MAX_VERTICES_PER_MESH, Material, MaterialId, Mesh, MeshId, PointLight, Scene, ShaderKind,
    SpotLight, StaticSetup, Wind,
};
pub use shadows::ShadowConfig;
pub use spot_shadows::{MAX_SPOT_SHADOW_MAPS, SpotShadowConfig};
pub use statics::{
    StaticDebug, StaticFrameStats, StaticOcclusion, StaticPixel, StaticShadowStats, StaticView,
    scene_from_query, static_view_desc, stream_static_world,
};
/// The static-scene crate whose tiles and views [`StaticQuery`] takes.
pub use staticscene;
pub use stats::{ClassificationStats, GpuClassification};
/// The talk's vertex ring sizes (PS4 12 MiB, PS5 24 MiB), for `RendererConfig::vertex_ring`.
pub use tiling::{RING_BYTES_PS4, RING_BYTES_PS5};
pub use timing::Timing;
/// The `water` version this crate's API uses (worlds, materials, flow atlases, decals).
pub use water;
pub use water_scene::{
    MAX_WATER_BODIES, MAX_WATER_BODY_CELLS, MAX_WATER_DECAL_LAYERS, MAX_WATER_DECAL_SIZE,
    MAX_WATER_DECALS, MAX_WATER_MATERIAL_MAP, MAX_WATER_MATERIALS, MAX_WATER_MESH_VERTICES,
    MAX_WATER_SECTORS_PER_SIDE, ShoreField, WaterDecal, WaterOptions, WaterScene, WaterStats,
    WaterSummary,
};
