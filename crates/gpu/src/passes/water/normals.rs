//! Normals from depth (`gpu::water_normals`): over the tessellated surface at full
//! resolution, blended with the mesh normal.

use shader::pipeline::ComputePass;
use shader::{Binding, Entry, Format, Group, Kind, Pass, Sample};

use super::super::LIBRARY;
use super::GpuWaterFrame;
use crate::error::Result;
use crate::resources::rows::FrameUniforms;

/// The pass, over the image (`[width, height]`).
pub(crate) const NORMALS: Pass<[u32; 2]> = Pass {
    name: "water normals",
    module: "gpu::water_normals",
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
                "mesh_normal",
                Kind::texture_2d(Sample::Float { filterable: false }),
            ),
            Binding::new(
                "materials",
                Kind::read(size_of::<water::material::WaterMaterialGpu>()),
            ),
            Binding::new("normals", Kind::storage_texture_2d(Format::Rgba16Float)),
        ],
    }],
    entries: &[Entry::grid("normals_from_depth", 8, 8, |s| *s)],
    zeroed: &[],
};

/// The pass's pipelines, recorded by the water's `record_grid`.
pub(crate) fn new(device: &wgpu::Device) -> Result<ComputePass<[u32; 2]>> {
    Ok(ComputePass::new(device, &NORMALS, &[], &[])?)
}

#[cfg(test)]
mod tests {
    #[test]
    fn description_matches_its_module() {
        shadercheck::check_pass(&super::NORMALS, |_| shadercheck::Caps::CORE);
    }
}
