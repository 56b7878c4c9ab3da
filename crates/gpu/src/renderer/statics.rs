//! HZD's static query in the frame: the query and its placement recorded before the
//! geometry (and, with two-pass occlusion, again after its first half), the sun slices'
//! shadow views, and the statistics read back after the frame.

use super::*;

/// A frame's static query as recorded: the prepared view, whether its second pass
/// (two-pass occlusion) is still to record after the first geometry pass, and the shadow
/// views of the sun slices (slice, texels per side, view).
pub(super) struct StaticFrame {
    pub(super) view: PreparedView,
    pub(super) two_pass: bool,
    pub(super) shadows: Vec<(u32, u32, PreparedView)>,
}

/// The static query's state from frame to frame.
#[derive(Default)]
pub(super) struct StaticState {
    /// The scene and the camera of the static view the depth target was last rendered
    /// for (`None` after a frame without a static query):
    /// [`StaticOcclusion::PreviousFrame`]'s HiZ, for frames of the same scene.
    pub(super) depth_camera: Option<(u64, staticscene::Camera)>,
    /// Per sun slice: whether this frame's static query placed the slice's own static
    /// casters (its shadow view).
    pub(super) slices: Vec<bool>,
    /// The last bake's static shadow view, until a frame's statistics report it.
    pub(super) bake_stats: Option<StaticShadowStats>,
}

/// Labels of the static shadow views' passes (timed together, all views summed).
const STATIC_SHADOW_QUERY: &str = "static shadow query";
const STATIC_SHADOW_PLACEMENT: &str = "static shadow placement";

impl Renderer {
    /// Renders one frame as [`Renderer::render`] does, with HZD's static query in front:
    /// the CPU pre-culls `statics.view` on `statics.scene`, then one command buffer runs
    /// the query, places its batches into the scene's reserved instance slots and indirect
    /// draw lists (no CPU round trip), and draws them with the scene's batches in the
    /// laydown (or the baseline's passes). Reads the query's and the placement's counters
    /// back after the frame ([`FrameOutput::statics`]).
    ///
    /// # Errors
    /// As [`Renderer::render`]; a scene without static setups ([`Error::Config`]); a view
    /// the query rejects ([`Error::StaticScene`]).
    pub fn render_static(
        &mut self,
        scene: &PreparedScene,
        frame: &FrameInput,
        path: RenderPath,
        statics: &mut StaticView<'_>,
    ) -> Result<FrameOutput> {
        let what = Recording::of(path);
        self.run(scene, frame, path.name(), what, Some(statics), true)
    }

    /// The scene's static buffers, or the error for a scene without static setups.
    pub(super) fn static_buffers(scene: &PreparedScene) -> Result<&StaticBuffers> {
        scene.statics.as_ref().ok_or_else(|| {
            Error::Scene(crate::error::SceneError::StaticSetup {
                setup: 0,
                problem: "the prepared scene has none; render_static draws static setups".into(),
            })
        })
    }

    /// Records the static query of `v` (with [`StaticOcclusion::PreviousFrame`], the HiZ
    /// of the depth target first; with [`StaticOcclusion::TwoPass`], its first pass) and
    /// the placement of its output into `scene`'s reserved slots and draw lists.
    pub(super) fn record_static(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        scene: &PreparedScene,
        v: &mut StaticView<'_>,
        sun_shadows: bool,
        frame: &FrameInput,
    ) -> Result<StaticFrame> {
        let b = Self::static_buffers(scene)?;
        let size = (self.config.image.width, self.config.image.height);
        let mut first = v.view;
        let mut second = None;
        let depth_hiz = match v.occlusion {
            StaticOcclusion::Given => false,
            StaticOcclusion::PreviousFrame => {
                first.occlusion_pass = staticscene::OcclusionPass::Single;
                // Another scene's depth occludes nothing of this one.
                first.occlusion_camera = self
                    .statics
                    .depth_camera
                    .filter(|(id, _)| *id == scene.id)
                    .map(|(_, c)| c);
                first.occlusion_camera.is_some()
            }
            StaticOcclusion::TwoPass => {
                first.occlusion_pass = staticscene::OcclusionPass::First;
                first.occlusion_camera = None;
                let mut s = v.view;
                s.occlusion_pass = staticscene::OcclusionPass::Second;
                s.occlusion_camera = Some(v.view.camera);
                second = Some(staticscene::QueryParams::new(&s)?);
                true
            }
        };
        if depth_hiz {
            if !v.view.camera.reversed_depth {
                return Err(Error::StaticScene(staticscene::Error::Config {
                    what: "a HiZ of the depth target needs a reversed-depth camera (the renderer's depth is reversed Z)",
                }));
            }
            // Before the query's bind groups: this may grow the HiZ buffer.
            v.query
                .prepare_depth_hiz(&self.device, &self.queue, size, true)?;
        }
        let params = staticscene::QueryParams::new(&first)?;
        let view = v.query.prepare_view(
            &self.device,
            &mut self.uploads,
            v.scene,
            &params,
            second.as_ref(),
            &v.options,
        )?;
        if depth_hiz && second.is_none() {
            self.record_hiz(encoder, v.query)?;
        }
        let offset = Self::query_offset(scene, &params);
        self.uploads
            .write(&b.params, 0, bytemuck::bytes_of(&b.params(offset)));
        self.record_query_and_place(encoder, scene, v.query, &view, false)?;
        let shadows = if sun_shadows {
            self.record_static_shadows(encoder, scene, v, frame)?
        } else {
            Vec::new()
        };
        Ok(StaticFrame {
            view,
            two_pass: second.is_some(),
            shadows,
        })
    }

    /// The static query's shadow view of each sun slice this frame re-renders (KZ2's
    /// shadow query with size threshold, HZD's orthographic sun query): the slice's
    /// volume seen from the sun, LODs from the camera view's LOD point, casters below
    /// [`ShadowConfig::static_size_threshold`](crate::config::ShadowConfig) of the slice's texels
    /// dropped; each placed into the slice's own rows and draw lists, which its shadow
    /// pass draws instead of the camera's. Recorded after the camera view's placement
    /// (the views share nothing it reads), one view's query and placement after the
    /// other's (they share the query's shadow outputs).
    pub(super) fn record_static_shadows(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        scene: &PreparedScene,
        v: &mut StaticView<'_>,
        frame: &FrameInput,
    ) -> Result<Vec<(u32, u32, PreparedView)>> {
        let maps = &self.targets.shadows;
        let (Some(config), Some(cascades)) = (maps.config, &self.shadow.cascades) else {
            return Ok(Vec::new());
        };
        let to_sun = frame.lighting.sun_direction.as_dvec3();
        let mut slices = Vec::new();
        let mut params = Vec::new();
        for (k, c) in cascades.cascades().iter().enumerate() {
            if k >= scene.static_shadows.len() || !maps.dirty.get(k).copied().unwrap_or(true) {
                continue;
            }
            let texels = config.slice_resolution(k);
            let camera = crate::shadows::sun_query_camera(c.world_to_clip, c.center, to_sun);
            let view = crate::shadows::sun_query_view(
                camera,
                texels,
                v.view.lod_position,
                v.view.lod_scale,
                config.static_size_threshold,
            );
            params.push(staticscene::QueryParams::new(&view)?);
            slices.push((k as u32, texels));
        }
        if params.is_empty() {
            return Ok(Vec::new());
        }
        let views = v.query.prepare_shadow_views(
            &self.device,
            &mut self.uploads,
            v.scene,
            &params,
            &v.options,
        )?;
        self.statics.slices = vec![false; cascades.cascades().len()];
        let mut out = Vec::with_capacity(views.len());
        for ((view, p), (k, texels)) in views.into_iter().zip(&params).zip(slices) {
            let set = &scene.static_shadows[k as usize];
            let offset = Self::query_offset(scene, p);
            self.uploads.write(
                &set.buffers.params,
                0,
                bytemuck::bytes_of(&set.buffers.params(offset)),
            );
            Self::record_view_and_place(
                &self.device,
                &self.pipelines,
                &mut self.timer,
                encoder,
                v.query,
                &view,
                (&set.buffers, &set.instances),
                (STATIC_SHADOW_QUERY, STATIC_SHADOW_PLACEMENT),
            )?;
            self.statics.slices[k as usize] = true;
            out.push((k, texels, view));
        }
        Ok(out)
    }

    /// The query's floating origin minus the scene's origin (whole metres both: exact in
    /// f64, and in f32 below 2^24 m).
    pub(super) fn query_offset(
        scene: &PreparedScene,
        params: &staticscene::QueryParams,
    ) -> glam::Vec3 {
        let o = params.origin;
        let origin = glam::DVec3::new(f64::from(o[0]), f64::from(o[1]), f64::from(o[2]));
        (origin - scene.summary.origin.as_dvec3()).as_vec3()
    }

    /// Records a prepared shadow view's query and its placement into `buffers` and their
    /// rows, timed under `labels` (query, placement).
    #[expect(
        clippy::too_many_arguments,
        reason = "the renderer's parts borrowed apart, beside the encoder"
    )]
    pub(super) fn record_view_and_place(
        device: &wgpu::Device,
        pipelines: &Pipelines,
        timer: &mut GpuTimer,
        encoder: &mut wgpu::CommandEncoder,
        query: &StaticQuery,
        view: &PreparedView,
        (buffers, rows): (&StaticBuffers, &wgpu::Buffer),
        (query_label, place_label): (&'static str, &'static str),
    ) -> Result<()> {
        {
            let mut pass = timer.begin_compute(encoder, query_label);
            query.record_view(&mut pass, view, false);
        }
        let group =
            pipelines
                .static_place
                .group(device, buffers, rows, &query.view_outputs(view))?;
        pipelines
            .static_place
            .record(encoder, buffers, &group, timer, false, place_label);
        Ok(())
    }

    /// Two-pass occlusion after the first geometry pass: the HiZ of its depth, the query's
    /// second pass against it, and the placement of what it found (late draw lists).
    pub(super) fn record_static_late(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        scene: &PreparedScene,
        v: &mut StaticView<'_>,
        view: &PreparedView,
    ) -> Result<()> {
        self.record_hiz(encoder, v.query)?;
        self.record_query_and_place(encoder, scene, v.query, view, true)
    }

    /// Records the HiZ of the depth target (laid out by `prepare_depth_hiz` first).
    pub(super) fn record_hiz(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        query: &StaticQuery,
    ) -> Result<()> {
        query.record_depth_hiz(
            &self.device,
            encoder,
            &self.targets.depth_view,
            &mut self.timer,
            "hiz build",
        )
    }

    /// Records one pass of the static query (`second`: two-pass occlusion's second) and the
    /// placement of its output into `scene`'s reserved slots and draw lists.
    pub(super) fn record_query_and_place(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        scene: &PreparedScene,
        query: &StaticQuery,
        view: &PreparedView,
        second: bool,
    ) -> Result<()> {
        let b = Self::static_buffers(scene)?;
        let label = if second {
            "static query (second pass)"
        } else {
            "static query"
        };
        {
            let mut pass = self.timer.begin_compute(encoder, label);
            query.record_view(&mut pass, view, second);
        }
        let group = self.pipelines.static_place.group(
            &self.device,
            b,
            &scene.instances,
            &query.outputs(second),
        )?;
        self.pipelines.static_place.record(
            encoder,
            b,
            &group,
            &mut self.timer,
            second,
            passes::static_place::StaticPlace::camera_label(second),
        );
        Ok(())
    }

    /// Reads the query's and the placement's counters after a frame with a static query.
    pub(super) fn read_static_stats(
        &mut self,
        scene: &PreparedScene,
        v: &StaticView<'_>,
        frame: StaticFrame,
    ) -> Result<StaticFrameStats> {
        let view = frame.view;
        let shadow_slices = frame
            .shadows
            .iter()
            .map(|(k, texels, sv)| {
                let set = &scene.static_shadows[*k as usize];
                self.read_shadow_stats(scene, v.query, sv, &set.buffers, (*k, *texels))
            })
            .collect::<Result<Vec<_>>>()?;
        let counters = v.query.read_counters(&self.device, &self.queue, false)?;
        let second = if frame.two_pass {
            Some(v.query.read_counters(&self.device, &self.queue, true)?)
        } else {
            None
        };
        let Some(b) = &scene.statics else {
            return Ok(StaticFrameStats::default());
        };
        let words = self.read_static_counters(b)?;
        let w = |i: u32| words[i as usize];
        Ok(StaticFrameStats {
            query: counters.stats(&view.plan.stats),
            second_pass: second.map(|c| c.stats(&view.plan.stats)),
            threads: view.threads,
            batches: counters.batches + second.map_or(0, |c| c.batches),
            instances: counters.instances + second.map_or(0, |c| c.instances),
            placed: placed_instances(scene, b, &words),
            over_capacity: w(STATIC_COUNTER_OVER_CAPACITY),
            bad_batches: w(STATIC_COUNTER_BAD_BATCHES),
            draws: [w(STATIC_COUNTER_DRAWS), w(STATIC_COUNTER_DRAWS + 1)],
            skipped_tiles: view.plan.skipped_tiles,
            shadow_slices,
            baked: self.statics.bake_stats.take(),
        })
    }

    /// The static placement's counters (placed per setup after the fixed ones).
    pub(super) fn read_static_counters(&self, b: &StaticBuffers) -> Result<Vec<u32>> {
        self.words(
            &b.counters,
            0,
            4 * u64::from(STATIC_COUNTER_PLACED + b.setup_count),
        )
    }

    /// Reads what a static shadow view's query and placement did (after its submission).
    pub(super) fn read_shadow_stats(
        &self,
        scene: &PreparedScene,
        query: &StaticQuery,
        view: &PreparedView,
        b: &StaticBuffers,
        (slice, texels): (u32, u32),
    ) -> Result<StaticShadowStats> {
        let counters = query.read_view_counters(&self.device, &self.queue, view)?;
        let words = self.read_static_counters(b)?;
        let w = |i: u32| words[i as usize];
        Ok(StaticShadowStats {
            slice,
            texels,
            query: counters.stats(&view.plan.stats),
            threads: view.threads,
            instances: counters.instances,
            batches: counters.batches,
            placed: placed_instances(scene, b, &words),
            over_capacity: w(STATIC_COUNTER_OVER_CAPACITY),
            bad_batches: w(STATIC_COUNTER_BAD_BATCHES),
            draws: [w(STATIC_COUNTER_DRAWS), w(STATIC_COUNTER_DRAWS + 1)],
        })
    }
}

/// Instances the placement put in their setups' reserved slots, from its counters
/// (placed per setup after the fixed ones; ranks past a setup's capacity are not drawn).
pub(super) fn placed_instances(scene: &PreparedScene, b: &StaticBuffers, words: &[u32]) -> u64 {
    (0..b.setup_count)
        .map(|s| {
            let placed = words
                .get((STATIC_COUNTER_PLACED + s) as usize)
                .copied()
                .unwrap_or(0);
            let cap = scene
                .static_capacities
                .get(s as usize)
                .copied()
                .unwrap_or(0);
            u64::from(placed.min(cap))
        })
        .sum()
}
