//! The frame: every pass's pipelines ([`Pipelines`]), the groups over the renderer's
//! targets ([`TargetGroups`](crate::resources::groups::TargetGroups)), a scene's groups made
//! at prepare ([`prepare`]), and the order a frame records its passes in
//! ([`Pipelines::record`]). Data flows one way: `resources` -> `passes` -> `frame` ->
//! `renderer`.

use shader::StageCounts;

use crate::context::{ActivePaths, PrimitiveIdPath};
use crate::error::Result;
use crate::passes::context::FrameContext;
use crate::passes::{
    baseline, classify, compute_laydown, conditional, laydown, light_volumes, lighting, lights,
    pixel_pull, regular, resolve, static_place, vertex_ring, vis_copy, water,
};
use crate::resources::groups::TargetGroups;
use crate::resources::targets::Targets;
use crate::timing::GpuTimer;

pub(crate) mod prepare;

/// What the most demanding pass binds per stage: the device limits the renderer needs.
/// What the most demanding pass binds per stage: the device limits the renderer needs.
pub(crate) fn stage_counts() -> StageCounts {
    let mut c = StageCounts::default();
    for counts in [
        laydown::pass(PrimitiveIdPath::Builtin).stage_counts(),
        baseline::BASELINE.stage_counts(),
        regular::REGULAR.stage_counts(),
        pixel_pull::PIXEL_PULL.stage_counts(),
        vis_copy::VIS_COPY.stage_counts(),
        compute_laydown::COMPUTE_LAYDOWN.stage_counts(),
        compute_laydown::COMPUTE_LAYDOWN_HYBRID.stage_counts(),
        compute_laydown::LAYDOWN_TARGET.stage_counts(),
        compute_laydown::LAYDOWN_UNPACK.stage_counts(),
        classify::ZERO.stage_counts(),
        resolve::RESOLVE.stage_counts(),
        lighting::LIGHTING.stage_counts(),
        light_volumes::LIGHT_VOLUMES.stage_counts(),
        conditional::CONDITIONAL.stage_counts(),
        crate::passes::depth_reductions::TILE_DEPTH.stage_counts(),
        deferred::pass::LIGHT_CULL_PASS.stage_counts(),
        static_place::STATIC_PLACE.stage_counts(),
        vertex_ring::VERTEX_RING.stage_counts(),
        tiling::wgsl::VERTEX_WAVES.stage_counts(),
        water::visibility::VISIBILITY.stage_counts(),
        water::position::POSITION.stage_counts(),
        water::displacement::DISPLACEMENT.stage_counts(),
        water::tiles::TILES.stage_counts(),
        water::tessellation::TESSELLATION.stage_counts(),
        water::normals::NORMALS.stage_counts(),
        water::foam::FOAM.stage_counts(),
        water::composite::COMPOSITE.stage_counts(),
        lighting::LIGHTING_WATER.stage_counts(),
    ]
    .into_iter()
    .chain(
        tiling::wgsl::CLASSIFICATION
            .iter()
            .map(|p| p.stage_counts()),
    ) {
        c = c.max(counts);
    }
    c
}

/// Every pass's pipelines on one device.
pub(crate) struct Pipelines {
    pub laydown: laydown::Laydown,
    /// With [`Laydown::Compute`](crate::Laydown) on a device with
    /// [`crate::resources::vis64::COMPUTE_LAYDOWN_FEATURES`].
    pub compute_laydown: Option<compute_laydown::ComputeLaydown>,
    pub vis_copy: vis_copy::VisCopy,
    pub classify: classify::Classify,
    pub resolve: resolve::Resolve,
    pub baseline: baseline::Baseline,
    /// HFW's mixed frame's regular geometry pass, with
    /// [`RendererConfig::geometry.mixed_frame`](crate::config::GeometryConfig::mixed_frame).
    pub regular: Option<regular::Regular>,
    pub pixel_pull: pixel_pull::PixelPull,
    pub lighting: lighting::Lighting,
    pub lights: lights::LocalLights,
    /// With a light path that has volumes.
    pub light_volumes: Option<light_volumes::LightVolumes>,
    /// With volumes and [`RendererConfig::lighting.conditional_volumes`](crate::config::LightingConfig::conditional_volumes)
    /// on a device with `INDIRECT_FIRST_INSTANCE`.
    pub conditional: Option<conditional::Conditional>,
    pub static_place: static_place::StaticPlace,
    /// HFW's vertex side: vertex wave commands and the transform into the ring.
    pub vertex_ring: vertex_ring::VertexRing,
}

impl Pipelines {
    /// Creates every pass's pipelines for `paths` (primitive-ID path, subgroups, wave
    /// width), `light_paths`, the G-buffer layout and whether KZ2's conditional rendering
    /// is emulated (`conditional`: asked for and possible), and with `compute_laydown` the
    /// compute laydown's over that target, and with `mixed` the mixed frame's regular
    /// geometry pass.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        device: &wgpu::Device,
        paths: &ActivePaths,
        wave_width: u32,
        light_paths: crate::config::LightPaths,
        gbuffer: deferred::GBufferLayout,
        msaa: Option<crate::config::MsaaLighting>,
        conditional: bool,
        compute_laydown: Option<crate::resources::vis64::LaydownTarget>,
        compute_laydown_max_extent: f32,
        mixed: bool,
        vrs: bool,
    ) -> Result<Self> {
        Ok(Self {
            laydown: laydown::Laydown::new(device, paths.primitive_id, msaa.is_some())?,
            compute_laydown: match compute_laydown {
                Some(kind) => Some(compute_laydown::ComputeLaydown::new(
                    device,
                    kind,
                    paths.subgroup_size.is_some(),
                    compute_laydown_max_extent,
                )?),
                None => None,
            },
            vis_copy: vis_copy::VisCopy::new(device)?,
            classify: classify::Classify::new(device, paths.subgroup_size.is_some())?,
            resolve: resolve::Resolve::new(device, wave_width, gbuffer, vrs)?,
            baseline: baseline::Baseline::new(device, gbuffer, msaa.is_some())?,
            pixel_pull: pixel_pull::PixelPull::new(
                device,
                gbuffer,
                paths.primitive_id,
                paths.barycentrics,
            )?,
            regular: mixed
                .then(|| regular::Regular::new(device, gbuffer))
                .transpose()?,
            lighting: lighting::Lighting::new(
                device,
                light_paths,
                gbuffer,
                msaa,
                paths.subgroup_size.is_some(),
            )?,
            lights: lights::LocalLights::new(device, msaa.is_some())?,
            light_volumes: if light_paths.volumes() {
                Some(light_volumes::LightVolumes::new(device, gbuffer)?)
            } else {
                None
            },
            static_place: static_place::StaticPlace::new(device)?,
            vertex_ring: vertex_ring::VertexRing::new(device)?,
            conditional: if light_paths.volumes() && conditional {
                Some(conditional::Conditional::new(device)?)
            } else {
                None
            },
        })
    }
}

/// What a command buffer records.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Recording {
    /// HFW's frame: laydown, vis copy, classification, resolve by wave commands, lighting
    /// (the mixed frame: the regular geometry pass between mid classify and classify
    /// output).
    Deferred,
    /// Diagnostic: laydown, the resolve of every pixel (no classification), lighting.
    DeferredFullScreen,
    /// HZD's frame on the same scene: depth prepass with alpha test, depth-equal
    /// geometry pass into the G-buffer, lighting.
    Baseline,
    /// Seed 004's frame: depth prepass with alpha test, depth-equal pass pulling vertices
    /// in the fragment stage into the G-buffer, lighting.
    PixelPull,
    /// The laydown alone (tests read the vis and depth buffers after it).
    Laydown,
    /// The classification alone, over whatever the vis words hold (how tests feed random
    /// vis buffers to it).
    Classification,
}

impl Recording {
    /// What a frame of `path` records.
    pub(crate) fn of(path: crate::RenderPath) -> Self {
        match path {
            crate::RenderPath::Deferred => Recording::Deferred,
            crate::RenderPath::Baseline => Recording::Baseline,
            crate::RenderPath::DeferredFullScreen => Recording::DeferredFullScreen,
            crate::RenderPath::PixelPull => Recording::PixelPull,
        }
    }

    /// Whether it lays down depth and the vis buffer (the deferred paths and the laydown
    /// alone; the baseline and pixel pull have a depth prepass instead).
    pub(crate) fn lays_down(self) -> bool {
        matches!(
            self,
            Recording::Deferred | Recording::DeferredFullScreen | Recording::Laydown
        )
    }

    /// Whether it ends with the sun's shadow maps, the light tiles and lighting.
    pub(crate) fn lights(self) -> bool {
        matches!(
            self,
            Recording::Deferred
                | Recording::DeferredFullScreen
                | Recording::Baseline
                | Recording::PixelPull
        )
    }
}

impl Pipelines {
    /// Records `what` into `encoder`, each pass in its own timing scope: the frame's order.
    pub(crate) fn record(
        &self,
        what: Recording,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        water: Option<&water::WaterState>,
        timer: &mut GpuTimer,
    ) {
        self.record_geometry(what, encoder, f, timer, false);
        self.record_after_geometry(what, encoder, f, water, timer);
    }

    /// The frame's geometry pass: the laydown, or the baseline's depth prepass. `late`:
    /// its second half under two-pass occlusion, the late static draws over what the
    /// first half left.
    pub(crate) fn record_geometry(
        &self,
        what: Recording,
        e: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
        late: bool,
    ) {
        match what {
            Recording::Deferred | Recording::DeferredFullScreen | Recording::Laydown => {
                // The compute laydown's unpack finalises the laydown into the masks, which
                // the classification's zero fill clears beside its raster (after the large
                // triangles, in their pass).
                let classifies = what == Recording::Deferred;
                let compute = f.compute_laydown
                    && !late
                    && self.compute_laydown.as_ref().is_some_and(|c| {
                        c.record(e, f, timer, self.needs_depth_target(what, f), |pass| {
                            if classifies {
                                self.classify.record_zero_in(pass, f);
                            }
                        })
                    });
                if !compute {
                    self.laydown.record_vis(e, f, timer, late);
                }
            }
            Recording::Baseline | Recording::PixelPull => {
                self.laydown.record_depth(e, f, timer, late);
            }
            Recording::Classification => {}
        }
    }

    /// Whether this frame's laydown was the compute one (the same test `record_geometry`
    /// made).
    pub(crate) fn laid_down_in_compute(&self, f: &FrameContext<'_>) -> bool {
        f.compute_laydown
            && self.compute_laydown.is_some()
            && f.scene.compute_laydown.is_some()
            && f.targets.vis64.is_some()
            && f.groups.laydown_target.is_some()
    }

    /// Whether a frame recording `what` has raster passes after its geometry that test
    /// against the depth target, which the compute laydown then writes too (the stencil
    /// light volumes and their conditional tests, the mixed frame's regular geometry pass,
    /// the water's HiZ, depth copy and tessellation;
    /// the laydown alone, whose depth tests read). Compute passes read the float depth.
    fn needs_depth_target(&self, what: Recording, f: &FrameContext<'_>) -> bool {
        what == Recording::Laydown
            || f.water_hdr.is_some()
            || (what.lights() && self.light_volumes.is_some())
            || (matches!(what, Recording::Deferred | Recording::DeferredFullScreen)
                && self.regular.is_some())
    }

    /// Everything after the geometry pass: classification, resolve or the baseline's
    /// geometry pass, lighting.
    /// `water`: FC5's water, recorded after lighting (its HDR group is `f.water_hdr`).
    pub(crate) fn record_after_geometry(
        &self,
        what: Recording,
        e: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        water: Option<&water::WaterState>,
        timer: &mut GpuTimer,
    ) {
        match what {
            Recording::Deferred => {
                // The compute laydown unpacked its words and depth itself, and finalised
                // the laydown (the zero fill came before it).
                let finalized = self.laid_down_in_compute(f);
                if !finalized {
                    self.vis_copy.record(e, f, timer);
                    self.classify.record_zero(e, f, timer);
                }
                // The talk's order: mid classify is recorded before the geometry pass (its
                // counts conservative), classify output after it (the final validity).
                self.classify.record_mid(e, f, timer, finalized);
                if let Some(r) = &self.regular {
                    r.record(e, f, timer);
                    // Its depth is the frame's: what the light tiles and lighting read.
                    self.vis_copy.record_depth(e, f, timer);
                }
                self.classify.record_output(e, f, timer);
                // HFW's vertex side (RendererConfig::geometry.vertex_ring): the vertex wave
                // commands from the cull buffer, then each pass's transform into the ring.
                // With the resolve reading the ring, each pass's transform is recorded
                // right before its resolve; else all of them here (measured alone).
                if let Some(b) = &f.scene.vertex_ring {
                    self.vertex_ring.record_waves(e, b, timer);
                    if !f.scene.resolve.reads_ring {
                        self.vertex_ring.record_transforms(e, f, timer);
                    }
                }
                self.resolve.record_waves(e, f, timer, |e, b, p, timer| {
                    self.vertex_ring.record_transform_timed(e, b, p, timer)
                });
            }
            Recording::DeferredFullScreen => {
                if !self.laid_down_in_compute(f) {
                    self.vis_copy.record_depth(e, f, timer);
                }
                self.resolve.record_full_screen(e, f, timer);
                // The mixed frame's regular batches, drawn over whatever the resolve wrote
                // (no classification here: the depth test alone decides).
                if let Some(r) = &self.regular {
                    r.record(e, f, timer);
                    self.vis_copy.record_depth(e, f, timer);
                }
            }
            Recording::Baseline => {
                if !f.msaa {
                    self.vis_copy.record_depth(e, f, timer);
                }
                self.baseline.record(e, f, timer);
            }
            Recording::PixelPull => {
                self.vis_copy.record_depth(e, f, timer);
                self.pixel_pull.record(e, f, timer);
            }
            Recording::Laydown => return,
            Recording::Classification => return self.classify.record(e, f, timer),
        }
        self.laydown.record_shadows(e, f, timer);
        // KZ2's conditional rendering: the shadowed volume lights' pixel counts first, as
        // indirect arguments of their maps and shading.
        if let (Some(v), Some(c)) = (&self.light_volumes, &self.conditional) {
            v.record_tests(e, f, timer);
            c.record(e, f, timer);
        }
        self.laydown.record_spot_shadows(e, f, timer);
        if let Some(v) = &self.light_volumes {
            v.record(e, f, timer);
        }
        // The compute laydown's unpack reduced the depth to the light tiles' ranges; a
        // regular pass drew depth after it, and the baseline has its own.
        let unpacked = matches!(what, Recording::Deferred | Recording::DeferredFullScreen)
            && self.laid_down_in_compute(f)
            && self.regular.is_none();
        self.lights.record(e, f, timer, unpacked);
        self.lighting.record(e, f, timer);
        if let Some(w) = water {
            w.record(e, f, timer);
        }
    }
}

impl TargetGroups {
    /// The groups over the renderer's targets, its frame and local-light uniforms
    /// (`frame`, `local`) and its light buffers.
    pub(crate) fn new(
        device: &wgpu::Device,
        p: &Pipelines,
        targets: &Targets,
        frame: &wgpu::Buffer,
        local: &wgpu::Buffer,
        lights: &crate::resources::lights::LightBuffers,
    ) -> Result<Self> {
        let mut groups = Self {
            vis_copy: p.vis_copy.group(device, targets)?,
            laydown_target: match (&p.compute_laydown, &targets.vis64) {
                (Some(c), Some(t)) => {
                    Some(c.target_groups(device, targets, t, &lights.tile_depths)?)
                }
                _ => None,
            },
            gbuffer_store: p.resolve.gbuffer_group(device, &targets.gbuffer_views)?,
            lighting: p.lighting.groups(device, targets, frame, local, lights)?,
            lights: p.lights.groups(device, targets, lights)?,
            light_volumes: None,
        };
        groups.refresh_lights(device, p, targets, frame, local, lights)?;
        Ok(groups)
    }

    /// Makes the groups that bind the light buffers again, over `lights` (after they grew;
    /// the per-tile buffers the compute laydown's unpack binds are kept when they grow).
    pub(crate) fn refresh_lights(
        &mut self,
        device: &wgpu::Device,
        p: &Pipelines,
        targets: &Targets,
        frame: &wgpu::Buffer,
        local: &wgpu::Buffer,
        lights: &crate::resources::lights::LightBuffers,
    ) -> Result<()> {
        self.lighting = p.lighting.groups(device, targets, frame, local, lights)?;
        self.lights = p.lights.groups(device, targets, lights)?;
        self.light_volumes = p
            .light_volumes
            .as_ref()
            .map(|v| {
                v.groups(
                    device,
                    targets,
                    frame,
                    local,
                    &lights.lights,
                    &lights.volumes,
                )
            })
            .transpose()?;
        Ok(())
    }
}
