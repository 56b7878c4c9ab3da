//! The complete wgpu renderer of the workspace: HFW's visibility-buffer laydown (hardware
//! or in compute), GPU classification into loose-tile wave commands and compute material
//! resolve into a G-buffer; KZ2's deferred lighting, shadows and render-memory allocator;
//! HZD's static-scene query and depth-equal baseline; FC5's water. Every format and
//! algorithm comes from the small crates; this crate owns devices, buffers, pipelines and
//! passes.
//!
//! # On your device
//!
//! Start from the recommended configuration for your adapter, create the device with the
//! renderer's optional features and required limits, prepare a [`Scene`] once (the
//! [`scene`] crate's description: meshes, materials, batches of instances) and render a
//! [`FrameInput`] (camera, time, sun and local lights) each frame. Read-backs and the
//! talks' statistics are apart, behind [`Renderer::inspect`].
//!
//! ```no_run
//! use gpu::glam::Vec3;
//! use gpu::{Camera, FrameInput, RenderPath, Renderer, RendererConfig, Scene};
//!
//! let instance = wgpu::Instance::default();
//! let adapter =
//!     pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default()))?;
//! // Laydown::Auto (the compute laydown where it measures faster), HFW's vertex ring, the
//! // tiled light lists, the sun's cascades and spot maps.
//! let mut config = RendererConfig::recommended(&adapter, 1920, 1080);
//! // Grouped by concern: image, geometry (the laydown), lighting, frames (pacing, uploads).
//! config.lighting.light_paths = gpu::config::LightPaths::Classified;
//! let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
//!     required_features: adapter.features() & Renderer::optional_features(),
//!     required_limits: Renderer::required_limits(&config),
//!     ..Default::default()
//! }))?;
//! let mut renderer = Renderer::new(&device, &queue, config)?;
//! let prepared = renderer.prepare(&Scene::default())?; // your scene
//! let frame = FrameInput::new(Camera::look_at(Vec3::new(0.0, 2.0, 10.0), Vec3::ZERO));
//! let out = renderer.render(&prepared, &frame, RenderPath::Deferred)?;
//! // `renderer.output_view()` now holds the image (sRGB-encoded `Rgba8Unorm`) for your own
//! // passes; `out.gpu` the passes' GPU times; `out.laydown` the laydown this frame ran.
//! println!("{:?} {:?}", out.laydown, renderer.laydown_choice().reason);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # What it draws
//!
//! Lighting: KZ2's sun slices as stable cascaded shadow maps with a baked sun term; point
//! and spot lights through 16x16 tiles or stencil light volumes ([`LightPaths`](config::LightPaths)) with KZ2's
//! light-shader permutations; shadow-casting spots ([`SpotShadowConfig`](config::SpotShadowConfig)) whose maps and
//! shading the GPU skips when their volume covers no pixel
//! ([`RendererConfig::lighting.conditional_volumes`](crate::config::LightingConfig::conditional_volumes)); the octahedral or KZ2's G-buffer; HZD's
//! depth-equal baseline (single-sample, or 4x MSAA lit with KZ2's tricks:
//! [`MsaaLighting`](config::MsaaLighting)). Every per-frame upload is sub-allocated from `framealloc`'s pool, so
//! frames can be submitted without waiting ([`Renderer::submit`]).
//!
//! Beside the scene the renderer draws Far Cry 5's water ([`Renderer::set_water`] with a
//! [`WaterScene`]: a baked `water::world::WaterWorld`, its materials, the flow atlas and
//! shore field for foam, decal textures) after lighting; the water writes a second depth
//! buffer ([`water_scene`]'s docs say which passes read which).
//!
//! # A complete example
//!
//! Headless ([`headless`] makes the device), writing a PNG:
//!
//! ```no_run
//! use gpu::glam::{Affine3A, Vec2, Vec3, Vec4};
//! use gpu::scene::{AlbedoLayer, MaterialId, MeshId, ShaderKind};
//! use gpu::{
//!     Batch, Camera, FrameInput, Material, Mesh, RenderPath, Renderer, RendererConfig, Scene,
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
//!     data_layers: vec![],
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
//!         ..Default::default()
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
//! let mut config = RendererConfig::default();
//! (config.image.width, config.image.height) = (640, 360);
//! let mut renderer = Renderer::new(&ctx.device, &ctx.queue, config)?;
//! let prepared = renderer.prepare(&scene)?;
//! let frame = FrameInput::new(Camera::look_at(Vec3::new(0.0, 1.0, 8.0), Vec3::ZERO));
//! renderer.render(&prepared, &frame, RenderPath::Deferred)?;
//! renderer.read_output()?.write_png(std::path::Path::new("quads.png"))?;
//! # Ok::<(), gpu::Error>(())
//! ```

pub mod config;
mod context;
mod error;
mod frame;
mod gbuffer;
mod image;
pub mod inspect;
mod passes;
mod renderer;
mod resources;
mod shaders;
mod shadows;
mod spot_shadows;
pub mod statics;
mod stats;
mod timing;
pub mod water_scene;

// The embedder's names: the device set-up, the renderer and its frame, the scene
// description's common types and errors. Configuration details live in [`config`], the
// static query in [`statics`], the water in [`water_scene`], read-backs, statistics and
// test hooks in [`inspect`].
pub use config::{Laydown, RenderPath, RendererConfig};
pub use context::{GpuContext, HeadlessOptions, OPTIONAL_FEATURES, adapter_line, headless};
/// The `deferred` version this crate's API uses (G-buffer layouts, lights, cascades).
pub use deferred;
pub use error::{Error, FrameError, Result, SceneError, WaterError};
/// The `framealloc` version this crate's API uses (the upload pool's layout).
pub use framealloc;
pub use glam;
pub use image::Rgba8Image;
pub use renderer::{FrameOutput, Renderer};
pub use resources::PreparedScene;
/// The scene, frame input and water scene descriptions this crate's API takes (the common
/// names below are re-exported from it).
pub use scene;
pub use scene::{
    Batch, Camera, FrameInput, Lighting, Material, Mesh, PointLight, Scene, SpotLight,
};
/// The static-scene crate whose tiles and views [`statics::StaticQuery`] takes.
pub use staticscene;
pub use timing::Timing;
/// The `water` version this crate's API uses (worlds, materials, flow atlases, decals).
pub use water;
pub use water_scene::{WaterOptions, WaterScene};
