//! The sun's shadows in the frame: KZ2's pre-rendered sun map (baked when the scene or the
//! sun moves), the stable cascades fitted and uploaded every frame, and the spot lights'
//! maps chosen by KZ2's fade.

use super::*;

/// The sun's cascades and the shadow views' caster culling, kept from frame to frame.
#[derive(Default)]
pub(super) struct ShadowState {
    /// The sun's cascades of the last frame (f64), with shadows on.
    pub(super) cascades: Option<deferred::cascades::StableCascades>,
    /// This frame's shadow views' caster culling.
    pub(super) casters: crate::shadows::CasterCulls,
}

impl Renderer {
    /// KZ2's pre-rendered sun shadow: the baked map of `scene`'s batches, and in a frame
    /// with a static query of its static casters, for this frame's sun, rendered (in a
    /// submission of its own) when the scene, the sun direction or the set of active
    /// static tiles changed, its matrix put into `uniforms`. Off
    /// (`RendererConfig::lighting.baked_sun`), or for a scene with nothing to cast, the matrix stays
    /// zero: no baked shadow.
    ///
    /// The static casters come from the static query's shadow view over the bake's
    /// orthographic box (the size threshold in the bake's texels), placed into slice 0's
    /// rows and lists before the frame's own work reuses them. Not every static instance
    /// drawn: the reserved slots hold a frame's visible instances (each setup's capacity),
    /// not the whole world, and every LOD level of every instance would overlap; the query
    /// picks one LOD per instance (from the camera's LOD point at bake time: the map keeps
    /// those LODs until it is re-baked, a texel-sized difference at its resolution) and
    /// drops what is too small for its texels.
    pub(super) fn bake_sun(
        &mut self,
        scene: &PreparedScene,
        frame: &FrameInput,
        uniforms: &mut FrameUniforms,
        mut statics: Option<&mut StaticView<'_>>,
    ) -> Result<()> {
        if !self.config.lighting.baked_sun {
            return Ok(());
        }
        // The static casters' bounds (origin-relative) and which tiles they came from.
        let origin = scene.summary.origin.as_dvec3();
        let static_part = statics
            .as_deref()
            .filter(|_| !scene.static_shadows.is_empty())
            .map(|v| {
                let mut bounds: Option<(glam::Vec3, glam::Vec3)> = None;
                let mut ids = std::collections::hash_map::DefaultHasher::new();
                for t in v.scene.tiles() {
                    std::hash::Hash::hash(&t.id().0, &mut ids);
                    let cull = t.cull();
                    if cull.filter & staticscene::FILTER_SUN_SHADOW == 0
                        || !(cull.bounds.min.cmple(cull.bounds.max).all())
                    {
                        continue;
                    }
                    let anchor = t.anchor().as_dvec3() - origin;
                    let lo = (anchor + cull.bounds.min.as_dvec3()).as_vec3();
                    let hi = (anchor + cull.bounds.max.as_dvec3()).as_vec3();
                    bounds = Some(match bounds {
                        Some((a, b)) => (a.min(lo), b.max(hi)),
                        None => (lo, hi),
                    });
                }
                (bounds, std::hash::Hasher::finish(&ids))
            });
        let static_bounds = static_part.and_then(|(b, _)| b);
        let bounds = match (scene.bounds, static_bounds) {
            (Some((a, b)), Some((c, d))) => (a.min(c), b.max(d)),
            (Some(b), None) | (None, Some(b)) => b,
            (None, None) => return Ok(()),
        };
        let sun = frame.lighting.sun_direction.normalize_or(glam::Vec3::Y);
        let matrix = crate::shadows::baked_sun_matrix(bounds, sun);
        uniforms.baked_sun = matrix.to_cols_array_2d();
        let key = (
            scene.id,
            sun.to_array().map(f32::to_bits),
            static_part.map(|(_, tiles)| tiles),
        );
        if self.targets.shadows.baked_for == Some(key) {
            return Ok(());
        }
        let mut bake = *uniforms;
        bake.view_proj = matrix.to_cols_array_2d();
        bake.origin_offset = [0.0; 4];
        bake.baked_sun = [[0.0; 4]; 4];
        self.queue.write_buffer(
            &self.targets.shadows.baked_frame,
            0,
            bytemuck::bytes_of(&bake),
        );
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("baked sun map"),
            });
        // The static casters' shadow view: uploads straight to the queue (they land before
        // this submission, which runs before the frame's uploads overwrite set 0).
        let mut placed = None;
        if let (Some(v), Some(set)) = (statics.as_deref_mut(), scene.static_shadows.first())
            && static_part.is_some()
            && let Some(group) = &set.bake_group
        {
            // World to the bake's clip space, f64: the matrix takes origin-relative points.
            let world_to_clip = matrix.as_dmat4() * glam::DMat4::from_translation(-origin);
            let centre = origin + ((bounds.0 + bounds.1) * 0.5).as_dvec3();
            let camera = crate::shadows::sun_query_camera(world_to_clip, centre, sun.as_dvec3());
            let threshold = self
                .config
                .lighting
                .shadows
                .unwrap_or_default()
                .static_size_threshold;
            let view = crate::shadows::sun_query_view(
                camera,
                crate::shadows::BAKED_SUN_RESOLUTION,
                v.view.lod_position,
                v.view.lod_scale,
                threshold,
            );
            let params = staticscene::QueryParams::new(&view)?;
            let mut queue = self.queue.clone();
            let mut views = v.query.prepare_shadow_views(
                &self.device,
                &mut queue,
                v.scene,
                std::slice::from_ref(&params),
                &v.options,
            )?;
            let prepared = views.pop().ok_or(Error::Length {
                what: "static shadow views prepared for the bake",
                got: 0,
                expected: 1,
            })?;
            let offset = Self::query_offset(scene, &params);
            self.queue.write_buffer(
                &set.buffers.params,
                0,
                bytemuck::bytes_of(&set.buffers.params(offset)),
            );
            // Untimed: the bake is its own submission, outside the frame's timings.
            Self::record_view_and_place(
                &self.device,
                &self.pipelines,
                &mut GpuTimer::inert(),
                &mut encoder,
                v.query,
                &prepared,
                (&set.buffers, &set.instances),
                ("baked sun static query", "baked sun static placement"),
            )?;
            placed = Some((prepared, &set.buffers, group));
        }
        self.pipelines.laydown.record_bake(
            &mut encoder,
            scene,
            &self.targets.shadows.baked_view,
            placed.as_ref().map(|(_, b, g)| (*b, *g)),
        );
        self.queue.submit([encoder.finish()]);
        self.targets.shadows.baked_for = Some(key);
        if let (Some((view, b, _)), Some(v)) = (&placed, statics.as_deref()) {
            self.statics.bake_stats = Some(self.read_shadow_stats(
                scene,
                v.query,
                view,
                b,
                (0, crate::shadows::BAKED_SUN_RESOLUTION),
            )?);
        }
        Ok(())
    }

    /// Fits the sun's cascades to this frame's camera and uploads each cascade's frame
    /// uniforms (`uniforms` with the cascade's camera-relative matrix as `view_proj`) and
    /// what lighting reads; with shadows off, a zero cascade count.
    pub(super) fn upload_shadows(
        &mut self,
        scene_id: u64,
        static_frame: bool,
        frame: &FrameInput,
        uniforms: &FrameUniforms,
    ) -> Result<()> {
        let maps = &mut self.targets.shadows;
        let Some(config) = maps.config else {
            self.uploads.write(
                &maps.sun,
                0,
                bytemuck::bytes_of(&crate::shadows::GpuSunShadow::default()),
            );
            return Ok(());
        };
        let aspect = self.config.image.width as f32 / self.config.image.height as f32;
        let cascades = config.fit(&frame.camera, aspect, frame.lighting.sun_direction)?;
        let origin = frame.camera.position.as_dvec3();
        self.shadow.casters.slices.clear();
        for (i, c) in cascades.cascades().iter().enumerate() {
            let planes = shadow_view(
                &mut self.uploads,
                &maps.frames,
                i,
                uniforms,
                c.relative_matrix(origin),
            );
            if self.config.lighting.cull_shadow_casters {
                self.shadow.casters.slices.push(planes);
            }
        }
        self.uploads.write(
            &maps.sun,
            0,
            bytemuck::bytes_of(&crate::shadows::GpuSunShadow::new(
                &cascades, origin, &config,
            )),
        );
        let keys = cascades
            .cascades()
            .iter()
            .map(|c| (scene_id, c.world_to_clip.to_cols_array().map(f64::to_bits)))
            .collect();
        maps.plan(keys, static_frame);
        self.shadow.cascades = Some(cascades);
        Ok(())
    }

    /// KZ2's shadowed spots: picks this frame's maps (fade by coverage, largest first),
    /// writes each chosen light's slot into its row, and uploads each map's frame uniforms
    /// (`uniforms` drawn from the light) and the rows lighting reads.
    pub(super) fn upload_spot_shadows(
        &mut self,
        rows: &mut [deferred::DeferredLight],
        projection: &deferred::DeferredProjection,
        uniforms: &FrameUniforms,
    ) {
        use crate::spot_shadows::{GpuSpotShadow, assign_maps};
        let maps = &mut self.targets.spot_shadows;
        let Some(config) = maps.config else {
            maps.active = 0;
            return;
        };
        let classifier = deferred::lights::LightClassifier {
            fade: config.fade,
            ..deferred::lights::LightClassifier::default()
        };
        let chosen = assign_maps(rows, &config, |l| {
            let c = classifier.classify(projection, l);
            (c.coverage, c.shadow)
        });
        let view_rotation = glam::Mat4::from_cols_array_2d(&uniforms.view_rotation);
        let mut gpu_rows = Vec::with_capacity(chosen.len().max(1));
        self.shadow.casters.spots.clear();
        for (slot, map) in chosen.iter().enumerate() {
            let m = map.view_to_clip * view_rotation;
            let planes = shadow_view(&mut self.uploads, &maps.frames, slot, uniforms, m);
            if self.config.lighting.cull_shadow_casters {
                self.shadow.casters.spots.push(planes);
            }
            gpu_rows.push(GpuSpotShadow::new(map, config.resolution));
        }
        if !gpu_rows.is_empty() {
            self.uploads
                .write(&maps.rows, 0, bytemuck::cast_slice(&gpu_rows));
        }
        maps.active = chosen.len() as u32;
    }
}

/// Uploads the frame uniforms of shadow view `index` (`uniforms` drawn through `m`, a
/// camera-relative matrix) into `frames` and returns the view's clip planes.
pub(super) fn shadow_view(
    uploads: &mut Uploads,
    frames: &wgpu::Buffer,
    index: usize,
    uniforms: &FrameUniforms,
    m: glam::Mat4,
) -> [glam::Vec4; 6] {
    let mut u = *uniforms;
    u.view_proj = m.to_cols_array_2d();
    uploads.write(
        frames,
        index as u64 * crate::shadows::CASCADE_FRAME_STRIDE,
        bytemuck::bytes_of(&u),
    );
    crate::shadows::clip_planes(m)
}
