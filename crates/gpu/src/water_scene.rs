//! Far Cry 5's water in the frame (seed 003): what the renderer takes
//! ([`WaterScene`], given with [`Renderer::set_water`](crate::Renderer::set_water) beside
//! the prepared scene), the per-frame displacement decals ([`WaterDecal`]), the statistics
//! a frame reports ([`WaterStats`]). The CPU side of the passes (the near bodies'
//! low-resolution meshes, the far sectors' quadtree and the material map, built from the
//! baked `WaterWorld` so that the GPU draws exactly what `WaterWorld::query` answers) is
//! `water::draw`; this module keeps what turns into the renderer's errors and records.
//!
//! # The passes
//!
//! After the opaque frame is lit (lighting also keeps its HDR colour when water is set),
//! `passes/water/` runs, each pass timed under its own label:
//!
//! | pass | label | what |
//! | --- | --- | --- |
//! | HiZ | `water hiz` | this frame's opaque depth reduced to staticscene's HiZ layout |
//! | visibility | `water visibility` | near bodies per body (frustum, near radius, HiZ) -> an indexed indirect draw each; far water through a GPU quadtree of sectors (one workgroup, breadth first) -> one indirect draw |
//! | position | `water position` | the mini G-buffer at [`WaterOptions::resolution_scale`] and a field of view [`WaterOptions::fov_scale`] wider: data word, mesh normal, view depth |
//! | displacement | `water displacement` | FBM with the talk's octave LOD (9 near, 3 far, never 0) plus max-blended vector decals, lowered at seams between bodies |
//! | tiles | `water tiles` | 32 x 32 tiles: ballot-aggregated counts, the tile list and the draw's arguments (equal to `water::tiles`' CPU twin) |
//! | tessellation | `water tessellation` | per visible tile a 16 x 16-quad grid of 16-bit vertices (`draw_indexed_indirect`), displaced, depth-tested against the scene into the depth with water |
//! | light tiles | `water light tiles` | the frame's local lights culled into 16 x 16 tiles over the depth with water |
//! | normals | `water normals` | normals from the tessellated depth (radius growing near the camera), blended with the mesh normal |
//! | foam | `water foam` | flow atlas in two phases, shore distance field, water depth, decal foam |
//! | composite | `water composite` | light transport from the water-type table, refraction, sky / screen-space reflection, sun and local lights, specular AA, the 6 m material blend; tone mapped over the output |
//!
//! # Depth with and without water
//!
//! "Water writes depth" (the talk's first warning): the frame keeps two depth buffers.
//!
//! | depth | what it holds | read by |
//! | --- | --- | --- |
//! | the depth target ([`Inspect::read_depth`](crate::inspect::Inspect::read_depth)) | the opaque scene only | lighting, shadows' light tiles, the static query's HiZ (next frame's occlusion), the water's own HiZ, refraction and the water depth under the surface (foam, light transport), screen-space reflections |
//! | the depth with water ([`Inspect::read_water_depth`](crate::inspect::Inspect::read_water_depth)) | a copy of the opaque depth with the tessellated water drawn into it (depth-tested, writing) | the water's local light tiles; whatever draws after the water and must be hidden by it (particles, fog, transparent objects): choose this one |
//!
//! A pass that looks *through* the water (what lies under it) reads the depth target; a
//! pass that draws *over* the finished image reads the depth with water. The static query
//! keeps testing against the opaque depth, so water never occludes static instances
//! (it is not opaque).
//!
//! # Limits
//!
//! Every limit is a named `pub const` (the `scene` crate's, re-exported here); a scene over
//! one is an [`Error::WaterLimit`], never a panic.

pub use crate::renderer::{WaterGBuffer, WaterGBufferInput, WaterTiles, WaterView};
use glam::Mat4;
pub use scene::{
    MAX_WATER_BODIES, MAX_WATER_BODY_CELLS, MAX_WATER_DECAL_LAYERS, MAX_WATER_DECAL_SIZE,
    MAX_WATER_DECALS, MAX_WATER_MATERIAL_MAP, MAX_WATER_MATERIALS, MAX_WATER_MESH_VERTICES,
    MAX_WATER_SECTORS_PER_SIDE, ShoreField, WATER_NO_MATERIAL, WaterDecal, WaterOptions,
    WaterScene,
};
use water::world::BodyBounds;

use crate::error::{Error, Result};

/// What the last frame's water passes did ([`Inspect::water_stats`](crate::inspect::Inspect::water_stats)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WaterStats {
    /// The mini G-buffer's size.
    pub buffer: [u32; 2],
    /// Whether the composite ran in half precision.
    pub half_precision: bool,
    /// Near bodies drawn (of [`WaterSummary::bodies`]).
    pub near_bodies: u32,
    /// Far sectors drawn (one draw).
    pub far_sectors: u32,
    /// Quadtree nodes the far pass tested.
    pub nodes_tested: u32,
    /// Mini G-buffer pixels with water.
    pub water_pixels: u64,
    /// Tiles with water (instances of the tessellated grid), of `tiles_total`.
    pub tiles: u32,
    /// Tiles of the mini G-buffer.
    pub tiles_total: u32,
    /// Triangles submitted: `tiles` times the grid's (2 x 16 x 16 at the talk's density).
    pub triangles: u64,
}

/// What [`Renderer::set_water`](crate::Renderer::set_water) built.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WaterSummary {
    /// Lakes and rivers drawn per body.
    pub bodies: u32,
    /// Triangles of their low-resolution meshes.
    pub mesh_triangles: u64,
    /// Far sectors per side and the quadtree's levels.
    pub sectors_per_side: u32,
    /// Levels of the far quadtree (a leaf level of `sectors_per_side^2` sectors).
    pub quadtree_levels: u32,
    /// Far sectors holding water.
    pub water_sectors: u32,
    /// Material map texels per side and texel size (metres).
    pub material_map: [u32; 2],
    /// Words of the baked world.
    pub world_words: u64,
    /// CPU time of the build (ms).
    pub build_ms: f64,
}

/// The limit error for `what`.
pub(crate) fn limit(what: &'static str, value: u64, limit: u64, limit_name: &'static str) -> Error {
    Error::WaterLimit {
        what,
        value,
        limit,
        limit_name,
    }
}

/// Checks the options' ranges ([`WaterOptions::validate`]).
pub(crate) fn check_options(o: &WaterOptions) -> Result<()> {
    Ok(o.validate()?)
}

/// Checks the materials against the world's `bodies` ([`WaterScene::check_materials`]).
pub(crate) fn check_materials(scene: &WaterScene, bodies: &[BodyBounds]) -> Result<()> {
    Ok(scene.check_materials(bodies)?)
}

/// `water::draw`'s limit refusals as the renderer's [`Error::WaterLimit`] (what
/// `set_water` always returned for them), anything else as [`Error::Water`].
pub(crate) fn draw_error(e: water::Error) -> Error {
    match e {
        water::Error::LimitExceeded {
            what,
            value,
            limit: max,
            limit_name,
        } => limit(what, value, max, limit_name),
        e => Error::Water(e),
    }
}

/// A decal's GPU record: world-to-box and box-to-world (water coordinates), strength,
/// frame, fade, and its texture's `[first layer, frames, width, height]` from `textures`
/// (one per decal texture of the scene).
pub(crate) fn decal_record(
    d: &WaterDecal,
    textures: &[[u32; 4]],
) -> Result<crate::passes::water::rows::GpuWaterDecal> {
    let Some(&texture) = textures.get(d.texture as usize) else {
        return Err(limit(
            "a decal's texture index",
            u64::from(d.texture),
            textures.len().saturating_sub(1) as u64,
            "WaterScene::decal_textures.len() - 1",
        ));
    };
    let m = Mat4::from(d.box_to_world);
    let det = m.determinant();
    let finite = m.is_finite()
        && d.strength.is_finite()
        && d.frame.is_finite()
        && d.fade.is_finite()
        && det.is_finite()
        && det.abs() > 1e-12;
    if !finite {
        return Err(Error::Water(water::Error::NonFinite {
            field: "water decal (box, strength, frame or fade; the box must be invertible)",
        }));
    }
    Ok(crate::passes::water::rows::GpuWaterDecal {
        world_to_box: m.inverse().to_cols_array_2d(),
        box_to_world: m.to_cols_array_2d(),
        params: [d.strength, d.frame, d.fade, 0.0],
        texture,
    })
}
