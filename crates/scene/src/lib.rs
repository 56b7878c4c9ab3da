//! What the `gpu` renderer takes, without a device: the [`Scene`] it prepares once
//! (meshes, materials, albedo layers, batches of instances, static setups, wind), the
//! [`FrameInput`] of every frame (camera, time, sun, point and spot lights) and the
//! [`WaterScene`] it draws Far Cry 5's water from, each with the validation the renderer
//! runs and an error naming the item and the limit ([`SceneError`], [`FrameError`],
//! [`WaterError`]). Importers (`gltf_scene`) and generators (`demo`) build these without
//! linking wgpu; `gpu` re-exports every name here at its root.
//!
//! ```
//! use scene::glam::{Affine3A, Vec2, Vec3, Vec4};
//! use scene::{
//!     AlbedoLayer, Batch, Camera, FrameInput, Material, MaterialId, Mesh, MeshId, Scene,
//!     SceneError, ShaderKind,
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
//! let mut scene = Scene {
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
//! scene.validate()?;
//! assert_eq!((scene.instance_count(), scene.triangle_count()), (100, 200));
//! // The 2x2 layer's mips: 2x2, then 1x1.
//! assert_eq!(scene.albedo_layers[0].mip_chain().len(), 2);
//!
//! // A batch naming a material that does not exist is refused, with its index.
//! scene.batches[0].material = MaterialId(3);
//! assert!(matches!(
//!     scene.validate(),
//!     Err(SceneError::UnknownReference { batch: 0, kind: "material", id: 3 })
//! ));
//!
//! let frame = FrameInput::new(Camera::look_at(Vec3::new(0.0, 1.0, 8.0), Vec3::ZERO));
//! frame.validate()?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Conventions: right-handed world space, +Y up, metres, radians; cameras look down their
//! local −Z with a reversed-Z infinite projection. The water scene keeps the `water`
//! crate's +Z up inside ([`water::axes`] converts).

mod albedo;
mod error;
mod frame;
mod model;
mod water_scene;

pub use albedo::{AlbedoLayer, DataLayer};
/// The `deferred` version this crate uses (its sRGB conversions filter the albedo mips).
pub use deferred;
pub use error::{FrameError, SceneError, WaterError};
pub use frame::{Camera, FrameInput, Lighting, MAX_LOCAL_LIGHTS, PointLight, SpotLight};
pub use glam;
pub use model::{
    Batch, MAX_PRIMITIVES_PER_MESH, MAX_VERTICES_PER_MESH, Material, MaterialFeatures, MaterialId,
    MaterialMaps, Mesh, MeshId, NormalMap, OcclusionMap, Scene, ShaderKind, StaticSetup, Wind,
};
/// The `tiling` version [`Scene::tiling_batches`] answers in.
pub use tiling;
/// The `water` version [`WaterScene`] holds (worlds, materials, flow atlases, decals).
pub use water;
pub use water_scene::{
    MAX_WATER_BODIES, MAX_WATER_BODY_CELLS, MAX_WATER_DECAL_LAYERS, MAX_WATER_DECAL_SIZE,
    MAX_WATER_DECALS, MAX_WATER_MATERIAL_MAP, MAX_WATER_MATERIALS, MAX_WATER_MESH_VERTICES,
    MAX_WATER_SECTORS_PER_SIDE, ShoreField, WATER_NO_MATERIAL, WaterDecal, WaterOptions,
    WaterScene,
};
