//! Foam (`gpu::water_foam`): the flow atlas in two phases, the shore distance field, the
//! water depth and the decals' foam, per water pixel at full resolution.

use shader::pipeline::ComputePass;
use shader::{Binding, Entry, Format, Kind, Pass, Sample};

use super::rows::{FRAME, MATERIALS, WATER, float_texture, water_group};
use crate::error::Result;
use crate::shaders::LIBRARY;

/// The pass, over the image (`[width, height]`).
pub(crate) const FOAM: Pass<[u32; 2]> = Pass {
    name: "water foam",
    module: "gpu::water_foam",
    library: LIBRARY,
    features: &[],
    groups: &[water_group(&[
        FRAME,
        WATER,
        float_texture("surface"),
        Binding::new("data", Kind::texture_2d(Sample::Uint)),
        MATERIALS,
        Binding::new("atlas", Kind::texture_2d(Sample::Uint)),
        float_texture("shore"),
        float_texture("noise"),
        float_texture("displacement"),
        Binding::new("scene_depth", Kind::texture_2d(Sample::Depth)),
        Binding::new("foam", Kind::storage_texture_2d(Format::R32Float)),
    ])],
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
