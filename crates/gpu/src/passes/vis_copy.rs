//! The vis-buffer target into the row-major word buffer the classification reads
//! (`gpu::vis_copy`; wgpu cannot view a texture as a buffer).

use shader::pipeline::ComputePass;
use shader::{Binding, Entry, Group, Kind, Pass, Sample};

use super::{FrameContext, LIBRARY};
use crate::error::Result;
use crate::resources::targets::Targets;
use crate::timing::GpuTimer;

/// The copy, over the image (`[width, height]`).
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
        ],
    }],
    entries: &[Entry::grid("copy_vis", 16, 16, |size| *size)],
    zeroed: &[],
};

/// The copy's pipeline.
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
            ],
        )?)
    }

    /// Records the copy (its own timed pass).
    pub(crate) fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("vis copy"),
            timestamp_writes: timer.compute("vis texture -> words"),
        });
        self.pass.record(
            &mut pass,
            &[&f.groups.vis_copy],
            &[f.targets.width, f.targets.height],
        );
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn description_matches_its_module() {
        shadercheck::check_pass(&super::VIS_COPY, |_| shadercheck::Caps::CORE);
    }
}
