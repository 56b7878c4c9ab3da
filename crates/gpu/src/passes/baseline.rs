//! HZD's method, the baseline the deferred path replaces: after the depth prepass (with
//! alpha test, in [`laydown`](super::laydown)), every batch is drawn again with depth test
//! `Equal` and no alpha test, writing the G-buffer from a fragment shader (`gpu::baseline`).

use shader::pipeline::Layouts;
use shader::{Entry, Pass, Stage};

use super::laydown::{SCENE_GROUP, depth_write_state, primitive_state, record_draws};
use super::{FrameContext, LIBRARY};
use crate::error::Result;
use crate::gbuffer;
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

/// The baseline's geometry pipelines: planned instances, and static ones (which may fade:
/// the laydown's dither first).
pub(crate) struct Baseline {
    layouts: Layouts,
    pipeline: wgpu::RenderPipeline,
    fade_pipeline: wgpu::RenderPipeline,
    /// Both at [`crate::MSAA_SAMPLES`] samples, with MSAA on.
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
        let layouts = Layouts::new(device, &BASELINE);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(BASELINE.name),
            source: wgpu::ShaderSource::Wgsl(BASELINE.source(gbuffer::features(layout))?.into()),
        });
        let targets = gbuffer::color_targets(layout);
        let make = |fragment: &str, count: u32| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(BASELINE.name),
                layout: Some(layouts.pipeline_layout()),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_baseline"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: primitive_state(),
                depth_stencil: Some(wgpu::DepthStencilState {
                    depth_write_enabled: Some(false),
                    depth_compare: Some(wgpu::CompareFunction::Equal),
                    ..depth_write_state()
                }),
                // MSAA: the fragment shader runs once a pixel per triangle and its output
                // goes to every covered sample, so a pixel inside one triangle has equal
                // samples (what lighting's edge test relies on).
                multisample: wgpu::MultisampleState {
                    count,
                    ..Default::default()
                },
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(fragment),
                    compilation_options: Default::default(),
                    targets: &targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let pipeline = make("fs_baseline", 1);
        let fade_pipeline = make("fs_baseline_fade", 1);
        let msaa = msaa.then(|| {
            (
                make("fs_baseline", crate::MSAA_SAMPLES),
                make("fs_baseline_fade", crate::MSAA_SAMPLES),
            )
        });
        Ok(Self {
            layouts,
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
        let colors: Vec<Option<wgpu::RenderPassColorAttachment<'_>>> = views
            .iter()
            .map(|v| {
                Some(wgpu::RenderPassColorAttachment {
                    view: v,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    },
                })
            })
            .collect();
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("baseline depth-equal geometry pass"),
            color_attachments: &colors,
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
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
}
