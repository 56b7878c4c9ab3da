//! Normals from depth (`gpu::water_normals`): over the tessellated surface at full
//! resolution, blended with the mesh normal.

use shader::pipeline::ComputePass;
use shader::{Binding, Entry, Format, Kind, Pass, Sample};

use super::rows::{FRAME, MATERIALS, WATER, float_texture, water_group};
use crate::error::Result;
use crate::shaders::LIBRARY;

/// The pass, over the image (`[width, height]`).
pub(crate) const NORMALS: Pass<[u32; 2]> = Pass {
    name: "water normals",
    module: "gpu::water_normals",
    library: LIBRARY,
    features: &[],
    groups: &[water_group(&[
        FRAME,
        WATER,
        float_texture("surface"),
        Binding::new("data", Kind::texture_2d(Sample::Uint)),
        float_texture("mesh_normal"),
        MATERIALS,
        Binding::new("normals", Kind::storage_texture_2d(Format::Rgba16Float)),
    ])],
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
