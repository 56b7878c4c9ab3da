//! Deferred lighting in compute (`gpu::lighting`): KZ2's sun, ambient and point lights over
//! the G-buffer, tone mapped into the sRGB-encoded output image. The same pass ends both
//! the deferred and the baseline frames.

use shader::pipeline::ComputePass;
use shader::{Binding, Dim, Entry, Format, Group, Kind, Pass, Sample};

use super::{FrameContext, LIBRARY};
use crate::error::Result;
use crate::gbuffer::LOAD_BINDINGS;
use crate::resources::rows::{FrameUniforms, GpuPointLight};
use crate::resources::targets::Targets;
use crate::timing::GpuTimer;

/// Lighting, over the image (`[width, height]`).
pub(crate) const LIGHTING: Pass<[u32; 2]> = Pass {
    name: "lighting",
    module: "gpu::lighting",
    library: LIBRARY,
    features: &[],
    groups: &[
        Group {
            name: "frame",
            bindings: &[
                Binding::new("frame", Kind::uniform(size_of::<FrameUniforms>())),
                Binding::new(
                    "depth_texture",
                    Kind::Texture {
                        sample: Sample::Depth,
                        dim: Dim::D2,
                    },
                ),
                Binding::new("point_lights", Kind::read(size_of::<GpuPointLight>())),
                Binding::new("output", Kind::storage_texture_2d(Format::Rgba8Unorm)),
            ],
        },
        Group {
            name: "gbuffer",
            bindings: &LOAD_BINDINGS,
        },
    ],
    entries: &[Entry::grid("main", 8, 8, |size| *size)],
    zeroed: &[],
};

/// The lighting pipeline.
pub(crate) struct Lighting {
    pass: ComputePass<[u32; 2]>,
}

/// The renderer's bind groups for lighting (they change only when the light buffer grows).
pub(crate) struct Groups {
    pub frame: wgpu::BindGroup,
    pub gbuffer: wgpu::BindGroup,
}

impl Lighting {
    pub(crate) fn new(device: &wgpu::Device) -> Result<Self> {
        Ok(Self {
            pass: ComputePass::new(device, &LIGHTING, &[], &[])?,
        })
    }

    /// The groups over the renderer's targets, frame uniforms and point-light buffer.
    pub(crate) fn groups(
        &self,
        device: &wgpu::Device,
        targets: &Targets,
        frame: &wgpu::Buffer,
        point_lights: &wgpu::Buffer,
    ) -> Result<Groups> {
        Ok(Groups {
            frame: self.pass.bind_group(
                device,
                "frame",
                &[
                    ("frame", frame.as_entire_binding()),
                    (
                        "depth_texture",
                        wgpu::BindingResource::TextureView(&targets.depth_view),
                    ),
                    ("point_lights", point_lights.as_entire_binding()),
                    (
                        "output",
                        wgpu::BindingResource::TextureView(&targets.output_view),
                    ),
                ],
            )?,
            gbuffer: self.pass.bind_group(
                device,
                "gbuffer",
                &crate::gbuffer::resources(&LOAD_BINDINGS, &targets.gbuffer_views),
            )?,
        })
    }

    /// Records lighting and tone mapping into the output image.
    pub(crate) fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("lighting"),
            timestamp_writes: timer.compute("lighting"),
        });
        let g = &f.groups.lighting;
        self.pass.record(
            &mut pass,
            &[&g.frame, &g.gbuffer],
            &[f.targets.width, f.targets.height],
        );
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn description_matches_its_module() {
        shadercheck::check_pass(&super::LIGHTING, |_| shadercheck::Caps::CORE);
    }
}
