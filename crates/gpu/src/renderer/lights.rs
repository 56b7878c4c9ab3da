//! Local lights in the frame: the lights uploaded in view space and split between the
//! tiles and the stencil volumes, and KZ2's conditional rendering planned.

use super::*;

/// How the last frame's local lights were drawn ([`Inspect::light_path_counts`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LightPathCounts {
    /// Lights in the tiles' lists (or, under [`LightPaths::EveryPixel`], tested at every
    /// pixel).
    pub tiled: u32,
    /// Lights drawn as stencil volumes (those wholly behind the near plane are not).
    pub volumes: u32,
    /// Of `volumes`, those drawn from inside (the eye in the mesh or the mesh reaching the
    /// near plane): back faces alone, no stencil.
    pub volumes_from_inside: u32,
    /// Spot lights that rendered a shadow map (shadow-casting, not faded out, among the
    /// largest [`SpotShadowConfig::maps`](crate::config::SpotShadowConfig::maps)), or had one to
    /// render: see the next two.
    pub spot_shadow_maps: u32,
    /// Of `volumes`, those tested for KZ2's conditional rendering
    /// ([`RendererConfig::lighting.conditional_volumes`](crate::config::LightingConfig::conditional_volumes)): lights with a spot map, whose map and
    /// shading the GPU skips if their test counts no pixel.
    pub volumes_tested: u32,
    /// Of `spot_shadow_maps`, those the CPU skipped under
    /// [`RendererConfig::lighting.conditional_volumes`](crate::config::LightingConfig::conditional_volumes): their light takes the volume path but has
    /// no volume draw (wholly behind the near plane).
    pub spot_shadow_maps_skipped: u32,
}

/// The frame's local lights as the renderer keeps them between uploads.
pub(super) struct LightState {
    /// Lighting's view rotation and tile counts (`GpuLocalLights`).
    pub(super) local: wgpu::Buffer,
    /// The lights in view space and the light tiles.
    pub(super) buffers: LightBuffers,
    /// This frame's lights on the tiled path (the tiles' indices point into it), in the
    /// light buffer's order.
    pub(super) tiled: Vec<deferred::DeferredLight>,
    /// This frame's stencil volume draws.
    pub(super) volume_draws: Vec<crate::resources::lights::VolumeDraw>,
    /// This frame's spot-map slots of the lights on the volume path (drawn or not).
    pub(super) volume_map_slots: Vec<u32>,
    /// This frame's lights on the volume path (`GpuLightVolume` order).
    pub(super) volume_rows: Vec<deferred::DeferredLight>,
    /// KZ2's conditional rendering emulated: buffers and this frame's plan.
    pub(super) conditional: Option<crate::resources::conditional::ConditionalBuffers>,
}

impl LightState {
    /// No lights yet, over the renderer's buffers.
    pub(super) fn new(
        local: wgpu::Buffer,
        buffers: LightBuffers,
        conditional: Option<crate::resources::conditional::ConditionalBuffers>,
    ) -> Self {
        Self {
            local,
            buffers,
            tiled: Vec::new(),
            volume_draws: Vec::new(),
            volume_map_slots: Vec::new(),
            volume_rows: Vec::new(),
            conditional,
        }
    }
}

impl Renderer {
    /// Uploads the frame's local lights in view space and the light passes' uniforms (the
    /// lights move in view space with the camera, so every frame), growing the light
    /// buffers when they are short. Splits the lights between the tiles and the stencil
    /// volumes as [`RendererConfig::lighting.light_paths`](crate::config::LightingConfig::light_paths) says: the tiled ones first in the light
    /// buffer (their count is returned, for the frame uniforms), the volumes' after them.
    pub(super) fn upload_lights(
        &mut self,
        frame: &FrameInput,
        uniforms: &FrameUniforms,
    ) -> Result<u32> {
        use crate::resources::lights::{GpuLightVolume, VolumeDraw};
        use deferred::lights::{LightClassifier, LightPath};
        let (width, height) = (self.config.image.width, self.config.image.height);
        let camera = &frame.camera;
        let projection = deferred::Perspective::try_new(
            camera.fov_y,
            width as f32 / height as f32,
            camera.near,
            None,
            deferred::DepthMode::Reversed,
        )
        .map_err(|e| {
            Error::Frame(crate::error::FrameError::OutOfRange {
                field: "camera".into(),
                value: camera.fov_y,
                allowed: if matches!(e, deferred::Error::InvalidParameter { name: "near", .. }) {
                    "a near plane > 0"
                } else {
                    "a field of view in (0, π)"
                },
            })
        })?
        .gpu(glam::Vec2::new(width as f32, height as f32));
        let mut all = local_light_rows(&frame.lighting, camera);
        let classifier = LightClassifier::default();
        self.upload_spot_shadows(&mut all, &projection, uniforms);
        let volume = |l: &deferred::DeferredLight| match self.config.lighting.light_paths {
            LightPaths::Tiled | LightPaths::EveryPixel => false,
            LightPaths::Volumes => true,
            // A light the classifier culls stays with the tiles, whose own test decides.
            LightPaths::Classified => classifier.classify(&projection, l).path == LightPath::Volume,
        };
        let (volume_lights, tiled): (Vec<_>, Vec<_>) = all.into_iter().partition(volume);
        let count = tiled.len() as u32;
        let reach = self
            .pipelines
            .light_volumes
            .as_ref()
            .map_or(1.0, |v| v.reach);
        let mut volumes = Vec::with_capacity(volume_lights.len().max(1));
        self.light.volume_draws.clear();
        self.light.volume_map_slots.clear();
        for (k, l) in volume_lights.iter().enumerate() {
            let map = (l.flags >> crate::spot_shadows::LIGHT_SHADOW_SLOT_SHIFT).checked_sub(1);
            self.light.volume_map_slots.extend(map);
            let (c, r) = l.bounding_sphere();
            volumes.push(GpuLightVolume {
                sphere: [c.x, c.y, c.z, r],
                light: count + k as u32,
                pad: [0; 3],
            });
            // View depths of the mesh's bounding sphere. All of it nearer than the near
            // plane (or behind the eye): it lights no visible point, no draw. Reaching the
            // near plane (as it does with the eye inside): its front faces may be clipped,
            // so it is drawn from inside.
            let (nearest, farthest) = (-c.z - r * reach, -c.z + r * reach);
            if farthest < camera.near {
                continue;
            }
            self.light.volume_draws.push(VolumeDraw {
                volume: k as u32,
                inside: nearest <= camera.near * 1.001,
                map,
                specular: l.has_specular(),
            });
        }
        let mut rows = tiled.clone();
        rows.extend_from_slice(&volume_lights);
        self.light.volume_rows = volume_lights;
        self.light.tiled = tiled;
        if rows.is_empty() {
            // A binding holds at least one light; the counts say none are real.
            rows.push(deferred::DeferredLight::default());
        }
        if volumes.is_empty() {
            volumes.push(GpuLightVolume::default());
        }
        if rows.len() > self.light.buffers.capacity {
            self.light.buffers = self
                .light
                .buffers
                .with_capacity(&self.device, rows.len().next_power_of_two())?;
            self.groups.refresh_lights(
                &self.device,
                &self.pipelines,
                &self.targets,
                &self.frame,
                &self.light.local,
                &self.light.buffers,
            )?;
            self.refresh_water_groups()?;
        }
        let b = &self.light.buffers;
        self.uploads
            .write(&b.lights, 0, bytemuck::cast_slice(&rows));
        self.uploads
            .write(&b.volumes, 0, bytemuck::cast_slice(&volumes));
        self.uploads.write(
            &b.cull_params,
            0,
            bytemuck::bytes_of(&deferred::pass::LightCullParams::new(projection, count)),
        );
        self.uploads.write(
            &b.tile_params,
            0,
            bytemuck::bytes_of(&GpuTileDepthParams {
                size: [width, height],
                tiles_x: b.tiles[0],
                reversed: 1,
            }),
        );
        self.uploads.write(
            &self.light.local,
            0,
            bytemuck::bytes_of(&GpuLocalLights {
                view_rotation: camera.view_rotation().to_cols_array_2d(),
                tiles: b.tiles,
                pad: [0; 2],
            }),
        );
        Ok(count)
    }

    /// KZ2's conditional rendering emulated: plans this frame's tests (the volume draws of
    /// lights with a spot map, at most one per map), their maps' caster draws (culled as
    /// the direct draws are) and the maps the CPU skips, and uploads the tests and the
    /// caster rows. Nothing with the emulation off.
    pub(super) fn plan_conditional(&mut self, scene: &PreparedScene) -> Result<()> {
        use crate::resources::conditional::{
            ConditionalPlan, GpuCasterDraw, GpuConditionalParams, GpuConditionalTest, MAX_TESTS,
            MapDraw,
        };
        let (Some(pass), Some(b)) = (&self.pipelines.conditional, &mut self.light.conditional)
        else {
            return Ok(());
        };
        let active = self.targets.spot_shadows.active as usize;
        let mut plan = ConditionalPlan {
            tests: Vec::new(),
            draw_test: vec![None; self.light.volume_draws.len()],
            maps: vec![MapDraw::Direct; active],
            lights: Vec::new(),
        };
        // A map of a light on the volume path is read by its volume draws alone.
        for &slot in &self.light.volume_map_slots {
            if let Some(m) = plan.maps.get_mut(slot as usize) {
                *m = MapDraw::Skipped;
            }
        }
        let mut tests = Vec::new();
        let mut rows = Vec::new();
        for (k, d) in self.light.volume_draws.iter().enumerate() {
            let Some(slot) = d.map.filter(|&s| (s as usize) < active) else {
                continue;
            };
            if tests.len() >= MAX_TESTS as usize {
                plan.maps[slot as usize] = MapDraw::Direct;
                continue;
            }
            let test = tests.len() as u32;
            let first = rows.len() as u32;
            let mut counts = [0u32; 2];
            for (kind, alpha) in [false, true].into_iter().enumerate() {
                passes::laydown::for_each_caster(
                    scene,
                    self.shadow.casters.spots.get(slot as usize),
                    self.origin_offset,
                    alpha,
                    |draw, first_instance, instance_count| {
                        rows.push(GpuCasterDraw {
                            index_count: draw.index_count,
                            instance_count,
                            first_index: draw.first_index,
                            base_vertex: draw.base_vertex as i32,
                            first_instance,
                            test,
                            pad: [0; 2],
                        });
                        counts[kind] += 1;
                    },
                );
            }
            tests.push(GpuConditionalTest {
                volume: d.volume,
                opaque: counts[0],
                alpha: counts[1],
                pad: 0,
            });
            plan.tests.push(k as u32);
            plan.draw_test[k] = Some(test);
            plan.maps[slot as usize] = MapDraw::Indirect {
                test,
                first,
                opaque: counts[0],
                alpha: counts[1],
            };
        }
        plan.lights = plan
            .tests
            .iter()
            .map(|&k| {
                let volume = self.light.volume_draws[k as usize].volume as usize;
                self.light
                    .volume_rows
                    .get(volume)
                    .copied()
                    .unwrap_or_default()
            })
            .collect();
        if rows.len() > b.capacity as usize {
            *b = pass.buffers(&self.device, (rows.len() as u32).next_power_of_two())?;
        }
        let reach = self
            .pipelines
            .light_volumes
            .as_ref()
            .map_or(0, |v| v.index_count());
        self.uploads.write(
            &b.params,
            0,
            bytemuck::bytes_of(&GpuConditionalParams {
                tests: tests.len() as u32,
                casters: rows.len() as u32,
                volume_indices: reach,
                pad: 0,
            }),
        );
        if !tests.is_empty() {
            self.uploads
                .write(&b.tests, 0, bytemuck::cast_slice(&tests));
        }
        if !rows.is_empty() {
            self.uploads
                .write(&b.caster_rows, 0, bytemuck::cast_slice(&rows));
        }
        b.casters = rows.len() as u32;
        b.plan = plan;
        Ok(())
    }
}
