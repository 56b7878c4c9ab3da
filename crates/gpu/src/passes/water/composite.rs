//! The composite (`gpu::water_composite`): light transport, refraction, reflection, sun
//! and local lights, specular AA and the material blend, tone mapped over the output;
//! feature `f16` for half precision where the device has `SHADER_F16`.

use shader::pipeline::ComputePass;
use shader::{Binding, Entry, Format, Group, Kind, Pass, Sample};

use super::super::LIBRARY;
use super::super::lighting::GpuLocalLights;
use super::{GpuWaterFrame, WaterGroups};
use crate::error::Result;
use crate::resources::rows::FrameUniforms;
use crate::timing::GpuTimer;

/// The pass, over the image (`[width, height]`).
pub(crate) const COMPOSITE: Pass<[u32; 2]> = Pass {
    name: "water composite",
    module: "gpu::water_composite",
    library: LIBRARY,
    features: &["f16"],
    groups: &[Group {
        name: "water",
        bindings: &[
            Binding::new("frame", Kind::uniform(size_of::<FrameUniforms>())),
            Binding::new("water", Kind::uniform(size_of::<GpuWaterFrame>())),
            Binding::new("local", Kind::uniform(size_of::<GpuLocalLights>())),
            Binding::new("lights", Kind::read(size_of::<deferred::DeferredLight>())),
            Binding::new("light_counts", Kind::read(4)),
            Binding::new("light_indices", Kind::read(4)),
            Binding::new(
                "surface",
                Kind::texture_2d(Sample::Float { filterable: false }),
            ),
            Binding::new(
                "normals",
                Kind::texture_2d(Sample::Float { filterable: false }),
            ),
            Binding::new(
                "foam",
                Kind::texture_2d(Sample::Float { filterable: false }),
            ),
            Binding::new("data", Kind::texture_2d(Sample::Uint)),
            Binding::new(
                "materials",
                Kind::read(size_of::<water::material::WaterMaterialGpu>()),
            ),
            Binding::new("material_map", Kind::texture_2d(Sample::Uint)),
            Binding::new(
                "scene_hdr",
                Kind::texture_2d(Sample::Float { filterable: false }),
            ),
            Binding::new("scene_depth", Kind::texture_2d(Sample::Depth)),
            Binding::new("output", Kind::storage_texture_2d(Format::Rgba8Unorm)),
        ],
    }],
    entries: &[Entry::grid("composite", 8, 8, |s| *s)],
    zeroed: &[],
};

pub(crate) struct Composite {
    pub pass: ComputePass<[u32; 2]>,
}

impl Composite {
    /// With `half`, the `f16` variant (the device must have `SHADER_F16`).
    pub(crate) fn new(device: &wgpu::Device, half: bool) -> Result<Self> {
        let features: &[&str] = if half { &["f16"] } else { &[] };
        Ok(Self {
            pass: ComputePass::new(device, &COMPOSITE, features, &[])?,
        })
    }

    pub(crate) fn record(
        &self,
        e: &mut wgpu::CommandEncoder,
        g: &WaterGroups,
        size: [u32; 2],
        timer: &mut GpuTimer,
    ) {
        let mut pass = e.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("water composite"),
            timestamp_writes: timer.compute("water composite"),
        });
        self.pass.record(&mut pass, &[&g.composite], &size);
    }
}

#[cfg(test)]
mod tests {
    use shadercheck::Caps;

    #[test]
    fn description_matches_its_module_in_both_precisions() {
        shadercheck::check_pass(&super::COMPOSITE, |f| {
            if f.contains(&"f16") {
                Caps::F16
            } else {
                Caps::CORE
            }
        });
    }
}
