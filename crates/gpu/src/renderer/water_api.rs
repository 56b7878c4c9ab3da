//! The renderer's water API: [`Renderer::set_water`] and what reads the water passes back.

use std::time::Instant;

use glam::{UVec2, Vec2, Vec3};

use super::Renderer;
use crate::context::scoped;
use crate::error::{Error, Result};
use crate::passes::water::{
    Built, Shared, WaterData, WaterGroups, WaterPasses, WaterState, WaterTargets,
};
use crate::resources::uniforms::Camera;

use crate::passes::water::targets::buffer_size;
use crate::water_scene::{
    WaterDecal, WaterScene, WaterSummary, check_materials, check_options, draw_error,
};
use water::draw::{material_map, near_meshes, sector_tree};

/// The mini G-buffer of the last frame ([`Inspect::read_water_gbuffer`](crate::inspect::Inspect::read_water_gbuffer)), row-major.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WaterGBuffer {
    /// Its size (the image's times [`WaterOptions::resolution_scale`](crate::WaterOptions)).
    pub size: [u32; 2],
    /// The data words (`water::gbuffer`; invalid where there is no water).
    pub data: Vec<u32>,
    /// View depth, metres (0 where there is no water).
    pub depth: Vec<f32>,
}

/// The last frame's 32x32 tiles ([`Inspect::read_water_tiles`](crate::inspect::Inspect::read_water_tiles)).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct WaterTiles {
    /// Tiles across and down.
    pub tiles: [u32; 2],
    /// Water pixels per tile, row-major.
    pub counts: Vec<u32>,
    /// The tiles with water, in the GPU's order (a set).
    pub list: Vec<u32>,
    /// The draw's index count (`6 * 16 * 16`) and instance count (the list's length).
    pub index_count: u32,
    /// Instances.
    pub instance_count: u32,
}

/// A mini G-buffer given instead of the position pass's ([`Renderer::set_water_gbuffer`]):
/// data words, view depths, mesh normals as half-float bit patterns.
#[doc(hidden)]
pub type WaterGBufferInput<'a> = (&'a [u32], &'a [f32], &'a [[u16; 4]]);

/// How the water view sees: for reconstructing what the mini G-buffer holds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WaterView {
    /// The mini G-buffer's size.
    pub size: [u32; 2],
    /// `tan` of the water view's half field of view, x and y.
    pub tan_half: Vec2,
}

impl WaterView {
    /// The world position (+Y up) of mini G-buffer pixel `pixel`'s centre at view depth
    /// `depth`, seen by `camera`: the passes' own arithmetic.
    #[must_use]
    pub fn world_position(&self, camera: &Camera, pixel: UVec2, depth: f32) -> Vec3 {
        let p = pixel.as_vec2() + 0.5;
        let ndc = Vec2::new(
            p.x / self.size[0] as f32 * 2.0 - 1.0,
            1.0 - p.y / self.size[1] as f32 * 2.0,
        );
        let v = Vec3::new(
            ndc.x * self.tan_half.x * depth,
            ndc.y * self.tan_half.y * depth,
            -depth,
        );
        camera.view_rotation().transpose().transform_vector3(v) + camera.position
    }
}

impl Renderer {
    /// Gives the renderer FC5's water beside the scene (`None` takes it away): checks the
    /// scene against the talk's and the renderer's limits, builds the near bodies' meshes,
    /// the far sectors' quadtree and the material map from the baked world (CPU), uploads
    /// them and the world, flow atlas, shore field, noise and decal textures, and makes
    /// the water passes' pipelines and targets (once). Every later frame of every path
    /// draws the water after lighting (see [`crate::water_scene`] for the passes and the two
    /// depth buffers). On an error the renderer has no water.
    ///
    /// # Errors
    /// A limit ([`Error::WaterLimit`]), a value the `water` crate refuses
    /// ([`Error::Water`]), MSAA on (the water passes are single-sample), or a device
    /// error.
    pub fn set_water(&mut self, water: Option<&WaterScene>) -> Result<Option<WaterSummary>> {
        let Some(scene) = water else {
            self.water = None;
            return Ok(None);
        };
        let keep = self.water.take();
        if self.config.image.msaa.is_some() {
            return Error::config(
                "RendererConfig::image.msaa",
                f64::from(crate::config::MSAA_SAMPLES),
                "off with water (its passes are single-sample)",
            );
        }
        let t0 = Instant::now();
        check_options(&scene.options)?;
        let bodies = scene.world.bodies();
        check_materials(scene, &bodies)?;
        water::noise::Fbm::new(&scene.noise, scene.fbm)?;
        let max_dim = self.device.limits().max_texture_dimension_2d;
        let mut dims = vec![(
            "water flow atlas",
            scene.flow.as_ref().map(|a| (a.width(), a.height())),
        )];
        dims.push((
            "water shore field",
            scene
                .shore
                .as_ref()
                .map(|s| (s.field.width(), s.field.height())),
        ));
        for (what, d) in dims {
            if let Some((w, h)) = d
                && w.max(h) > max_dim
            {
                return Err(crate::water_scene::limit(
                    what,
                    u64::from(w.max(h)),
                    u64::from(max_dim),
                    "the device's max_texture_dimension_2d",
                ));
            }
        }
        if let Some(s) = &scene.shore
            && !(s.texel_size > 0.0 && s.texel_size.is_finite() && s.origin.is_finite())
        {
            return Err(Error::Water(water::Error::NonFinite {
                field: "ShoreField texel size or origin (a finite texel above 0)",
            }));
        }
        let o = &scene.options;
        let built = Built {
            near: near_meshes(&scene.world, &bodies, o.near_cell).map_err(draw_error)?,
            tree: sector_tree(&scene.world, &bodies, o.sector_size, o.ocean_extent)
                .map_err(draw_error)?,
            map: material_map(&scene.world, &bodies, o.blend_distance),
            max_displacement: scene.max_displacement(),
        };
        let device = self.device.clone();
        let half = o.half_precision && self.paths.f16;
        let (width, height) = (self.config.image.width, self.config.image.height);
        let summary = WaterSummary {
            bodies: built.near.bodies.len() as u32,
            mesh_triangles: built.near.indices.len() as u64 / 3,
            sectors_per_side: built.tree.sectors_per_side,
            quadtree_levels: built.tree.levels,
            water_sectors: built.tree.water_sectors,
            material_map: [
                built.map.width.max(built.map.height),
                built.map.texel as u32,
            ],
            world_words: scene.world.words().len() as u64,
            build_ms: 0.0,
        };
        let state = scoped(&device, || {
            self.pipelines.lighting.enable_water(&device)?;
            let (passes, targets) = match keep {
                Some(w)
                    if w.half == half
                        && w.targets.size == buffer_size(width, height, o.resolution_scale) =>
                {
                    (w.passes, w.targets)
                }
                _ => (
                    WaterPasses::new(&device, self.paths.subgroup_size.is_some(), half)?,
                    WaterTargets::new(&device, width, height, o.resolution_scale)?,
                ),
            };
            let data = WaterData::new(
                &device,
                &self.queue,
                scene,
                &built,
                &targets,
                [width, height],
            )?;
            let groups = self.water_groups(&passes, &targets, &data)?;
            Ok(WaterState {
                passes,
                targets,
                data,
                groups,
                half,
                gbuffer_given: false,
            })
        })?;
        self.water = Some(state);
        Ok(Some(WaterSummary {
            build_ms: t0.elapsed().as_secs_f64() * 1e3,
            ..summary
        }))
    }

    /// Rebuilds the water's bind groups (after the light buffers grew).
    pub(super) fn refresh_water_groups(&mut self) -> Result<()> {
        let (Some(w), Some(_)) = (&self.water, self.pipelines.lighting.water_layout()) else {
            return Ok(());
        };
        let groups = self.water_groups(&w.passes, &w.targets, &w.data)?;
        if let Some(w) = &mut self.water {
            w.groups = groups;
        }
        Ok(())
    }

    /// The water's bind groups over `passes`, `targets` and `data` and the renderer's
    /// frame uniforms, depth, output, lights and lighting's water layouts.
    fn water_groups(
        &self,
        passes: &WaterPasses,
        targets: &WaterTargets,
        data: &WaterData,
    ) -> Result<WaterGroups> {
        let hdr_layout = self
            .pipelines
            .lighting
            .water_layout()
            .ok_or(Error::Validation(
                "the lighting pass has no water variant".into(),
            ))?;
        WaterState::groups(
            &self.device,
            passes,
            targets,
            data,
            &Shared {
                frame: &self.frame,
                depth: &self.targets.depth_view,
                output: &self.targets.output_view,
                local: &self.light.local,
                lights: &self.light.buffers,
                hdr_layout,
            },
        )
    }

    /// This frame's (and the next frames') displacement decals, in water coordinates; at
    /// most [`MAX_WATER_DECALS`](crate::water_scene::MAX_WATER_DECALS). Without water, nothing.
    ///
    /// # Errors
    /// Too many decals, a texture index past [`WaterScene::decal_textures`], or a box that
    /// is not finite and invertible.
    pub fn set_water_decals(&mut self, decals: &[WaterDecal]) -> Result<()> {
        match &mut self.water {
            Some(w) => w.set_decals(decals),
            None => Ok(()),
        }
    }

    /// Whether the renderer has water.
    pub fn has_water(&self) -> bool {
        self.water.is_some()
    }

    /// How the water view sees (its mini G-buffer's size and field of view), for the last
    /// frame's camera.
    pub fn water_view(&self, camera: &Camera) -> Option<WaterView> {
        let w = self.water.as_ref()?;
        let aspect = self.config.image.width as f32 / self.config.image.height as f32;
        let tan_y = (camera.fov_y * 0.5).tan() * w.data.options.fov_scale;
        Some(WaterView {
            size: w.targets.size,
            tan_half: Vec2::new(tan_y * aspect, tan_y),
        })
    }
}
