//! Foam (`gpu::water_foam`): the flow atlas in two phases, the shore distance field, the
//! water depth and the decals' foam, per water pixel at full resolution.

use shader::pipeline::ComputePass;
use shader::{Binding, Entry, Format, Group, Kind, Pass, Sample};

use super::super::LIBRARY;
use super::GpuWaterFrame;
use crate::error::Result;
use crate::resources::rows::FrameUniforms;

/// The pass, over the image (`[width, height]`).
pub(crate) const FOAM: Pass<[u32; 2]> = Pass {
    name: "water foam",
    module: "gpu::water_foam",
    library: LIBRARY,
    features: &[],
    groups: &[Group {
        name: "water",
        bindings: &[
            Binding::new("frame", Kind::uniform(size_of::<FrameUniforms>())),
            Binding::new("water", Kind::uniform(size_of::<GpuWaterFrame>())),
            Binding::new(
                "surface",
                Kind::texture_2d(Sample::Float { filterable: false }),
            ),
            Binding::new("data", Kind::texture_2d(Sample::Uint)),
            Binding::new(
                "materials",
                Kind::read(size_of::<water::material::WaterMaterialGpu>()),
            ),
            Binding::new("atlas", Kind::texture_2d(Sample::Uint)),
            Binding::new(
                "shore",
                Kind::texture_2d(Sample::Float { filterable: false }),
            ),
            Binding::new(
                "noise",
                Kind::texture_2d(Sample::Float { filterable: false }),
            ),
            Binding::new(
                "displacement",
                Kind::texture_2d(Sample::Float { filterable: false }),
            ),
            Binding::new("scene_depth", Kind::texture_2d(Sample::Depth)),
            Binding::new("foam", Kind::storage_texture_2d(Format::R32Float)),
        ],
    }],
    entries: &[Entry::grid("foam_pass", 8, 8, |s| *s)],
    zeroed: &[],
};

/// The pass's pipelines, recorded by the water's `record_grid`.
pub(crate) fn new(device: &wgpu::Device) -> Result<ComputePass<[u32; 2]>> {
    Ok(ComputePass::new(device, &FOAM, &[], &[])?)
}

#[cfg(test)]
mod tests {
    #[test]
    fn description_matches_its_module() {
        shadercheck::check_pass(&super::FOAM, |_| shadercheck::Caps::CORE);
    }
}
