//! After a hardware geometry pass, what the compute passes read (`gpu::vis_copy`): the
//! vis-buffer target into the row-major word buffer the classification reads (wgpu cannot
//! view a texture as a buffer) and the depth target into [`Targets::depth_float`], which
//! the light tiles and lighting read (compute passes cannot write depth textures, so the
//! compute laydown writes that one itself). The baseline copies only the depth.

use shader::pipeline::ComputePass;
use shader::{Binding, Entry, Format, Group, Kind, Pass, Sample};

use super::context::FrameContext;
use crate::error::Result;
use crate::resources::targets::Targets;
use crate::shaders::LIBRARY;
use crate::timing::GpuTimer;

/// The copies, over the image (`[width, height]`): words and depth (`copy_vis`), or the
/// depth alone (`copy_depth`).
pub(crate) const VIS_COPY: Pass<[u32; 2]> = Pass {
    name: "vis copy",
    module: "gpu::vis_copy",
    library: LIBRARY,
    features: &[],
    groups: &[Group {
        name: "vis",
        bindings: &[
            Binding::new("vis_texture", Kind::texture_2d(Sample::Uint)),
            Binding::new("vis_words", Kind::read_write(4)),
            Binding::new("depth_texture", Kind::texture_2d(Sample::Depth)),
            Binding::new("depth_float", Kind::storage_texture_2d(Format::R32Float)),
        ],
    }],
    entries: &[
        Entry::grid("copy_vis", 16, 16, |size| *size),
        Entry::grid("copy_depth", 16, 16, |size| *size),
    ],
    zeroed: &[],
};

/// The copy's pipelines.
pub(crate) struct VisCopy {
    pass: ComputePass<[u32; 2]>,
}

impl VisCopy {
    pub(crate) fn new(device: &wgpu::Device) -> Result<Self> {
        Ok(Self {
            pass: ComputePass::new(device, &VIS_COPY, &[], &[])?,
        })
    }

    /// The bind group over the renderer's targets.
    pub(crate) fn group(&self, device: &wgpu::Device, t: &Targets) -> Result<wgpu::BindGroup> {
        Ok(self.pass.bind_group(
            device,
            "vis",
            &[
                (
                    "vis_texture",
                    wgpu::BindingResource::TextureView(&t.vis_view),
                ),
                ("vis_words", t.vis_words.as_entire_binding()),
                (
                    "depth_texture",
                    wgpu::BindingResource::TextureView(&t.depth_view),
                ),
                (
                    "depth_float",
                    wgpu::BindingResource::TextureView(&t.depth_float_view),
                ),
            ],
        )?)
    }

    /// Records the words and the depth copy (its own timed pass).
    pub(crate) fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
    ) {
        self.record_step(encoder, f, timer, "copy_vis", "vis texture -> words");
    }

    /// Records the depth copy alone (its own timed pass): the baseline's.
    pub(crate) fn record_depth(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
    ) {
        self.record_step(encoder, f, timer, "copy_depth", "depth copy");
    }

    fn record_step(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
        entry: &str,
        label: &'static str,
    ) {
        let Ok(step) = self.pass.step(entry) else {
            return;
        };
        let size = [f.targets.width, f.targets.height];
        let Some([x, y, z]) = self.pass.workgroups(step, &size) else {
            return;
        };
        let mut pass = timer.begin_compute(encoder, label);
        pass.set_bind_group(0, &f.groups.vis_copy, &[]);
        pass.set_pipeline(&step.pipeline);
        pass.dispatch_workgroups(x, y, z);
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn description_matches_its_module() {
        shadercheck::check_pass(&super::VIS_COPY, |_| shadercheck::Caps::CORE);
    }
}
