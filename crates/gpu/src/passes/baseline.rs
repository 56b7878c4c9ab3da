//! HZD's method, the baseline the deferred path replaces: after the depth prepass (with
//! alpha test, in [`laydown`](super::laydown)), every batch is drawn again with depth test
//! `Equal` and no alpha test, writing the G-buffer from a fragment shader (`gpu::baseline`).

use shader::pipeline::{Layouts, RasterPass};
use shader::{Entry, Pass, Raster, Stage};

use super::context::FrameContext;
use super::raster::record_draws;
use super::raster::{
    DEPTH_EQUAL, GEOMETRY, SCENE_GROUP, depth_attachment, gbuffer_targets, loaded_colors,
};
use crate::error::Result;
use crate::gbuffer;
use crate::shaders::LIBRARY;
use crate::timing::GpuTimer;

/// The depth-equal geometry pass.
pub(crate) const BASELINE: Pass = Pass {
    name: "baseline depth-equal geometry pass",
    module: "gpu::baseline",
    library: LIBRARY,
    features: &["kz2_gbuffer"],
    groups: &[SCENE_GROUP],
    entries: &[
        Entry::draw("vs_baseline", Stage::Vertex),
        Entry::draw("fs_baseline", Stage::Fragment),
        Entry::draw("fs_baseline_fade", Stage::Fragment),
    ],
    zeroed: &[],
};

/// The depth-equal pass's planned instances over the prepass's depth, into the G-buffer
/// (the targets are the layout's: [`gbuffer_targets`]). MSAA: the fragment shader runs
/// once a pixel per triangle and its output goes to every covered sample, so a pixel
/// inside one triangle has equal samples (what lighting's edge test relies on).
pub(crate) const BASELINE_PIPELINE: Raster<'static> = Raster::new(BASELINE.name, "vs_baseline")
    .fragment("fs_baseline")
    .primitive(GEOMETRY)
    .depth(DEPTH_EQUAL);

/// Its static instances (which may fade).
pub(crate) const BASELINE_FADE: Raster<'static> = BASELINE_PIPELINE.fragment("fs_baseline_fade");

/// The baseline's geometry pipelines: planned instances, and static ones (which may fade:
/// the laydown's dither first).
pub(crate) struct Baseline {
    layouts: Layouts,
    pipeline: wgpu::RenderPipeline,
    fade_pipeline: wgpu::RenderPipeline,
    /// Both at [`crate::config::MSAA_SAMPLES`] samples, with MSAA on.
    msaa: Option<(wgpu::RenderPipeline, wgpu::RenderPipeline)>,
}

impl Baseline {
    /// The pipelines writing the G-buffer of `layout`; with `msaa`, the multisampled ones
    /// too.
    pub(crate) fn new(
        device: &wgpu::Device,
        layout: deferred::GBufferLayout,
        msaa: bool,
    ) -> Result<Self> {
        let raster = RasterPass::new(device, &BASELINE, gbuffer::features(layout), &[])?;
        let targets = gbuffer_targets(layout);
        let make = |r: Raster<'static>, samples: u32| {
            raster.pipeline(device, &r.targets(targets).samples(samples))
        };
        let pipeline = make(BASELINE_PIPELINE, 1)?;
        let fade_pipeline = make(BASELINE_FADE, 1)?;
        let msaa = if msaa {
            Some((
                make(BASELINE_PIPELINE, crate::config::MSAA_SAMPLES)?,
                make(BASELINE_FADE, crate::config::MSAA_SAMPLES)?,
            ))
        } else {
            None
        };
        Ok(Self {
            layouts: raster.layouts,
            pipeline,
            fade_pipeline,
            msaa,
        })
    }

    /// A prepared scene's bind group (its `scene` resources by binding name).
    pub(crate) fn group(
        &self,
        device: &wgpu::Device,
        scene: &[(&str, wgpu::BindingResource<'_>)],
    ) -> Result<wgpu::BindGroup> {
        Ok(self.layouts.bind_group(device, "scene", scene)?)
    }

    /// Records the depth-equal geometry pass over the prepass's depth.
    pub(crate) fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
    ) {
        // The baseline's MSAA frame: the multisampled targets and pipelines.
        let (views, depth, pipeline, fade) = match (f.msaa, &f.targets.msaa, &self.msaa) {
            (true, Some(t), Some((p, fade))) => (&t.gbuffer_views, &t.depth_view, p, fade),
            _ => (
                &f.targets.gbuffer_views,
                &f.targets.depth_view,
                &self.pipeline,
                &self.fade_pipeline,
            ),
        };
        let colors = loaded_colors(views);
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("baseline depth-equal geometry pass"),
            color_attachments: &colors,
            depth_stencil_attachment: Some(depth_attachment(depth, true)),
            timestamp_writes: timer.render("depth-equal geometry pass"),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, &f.scene.baseline, &[]);
        // No alpha test here: the prepass decided coverage, depth-equal keeps the survivors.
        record_draws(&mut pass, f, pipeline, pipeline, fade, false);
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn description_matches_its_module() {
        shadercheck::check_pass(&super::BASELINE, |_| shadercheck::Caps::CORE);
    }

    #[test]
    fn pipelines_match_their_module_for_every_layout() {
        for layout in deferred::GBufferLayout::ALL {
            for r in [super::BASELINE_PIPELINE, super::BASELINE_FADE] {
                shadercheck::check_raster(
                    &super::BASELINE,
                    &r.targets(super::gbuffer_targets(layout)),
                    crate::gbuffer::features(layout),
                    shadercheck::Caps::CORE,
                );
            }
        }
    }
}
