//! Displacement (`gpu::water_displacement`): FBM with octave LOD and the vector
//! displacement decals into the displacement texture, at the mini G-buffer's resolution.

use shader::pipeline::ComputePass;
use shader::{Binding, Dim, Entry, Format, Kind, Pass, Sample};

use super::rows::GpuWaterDecal;
use super::rows::{FRAME, MATERIALS, WATER, float_texture, water_group};
use crate::error::Result;
use crate::shaders::LIBRARY;

/// The pass, over the mini G-buffer (`[width, height]`).
pub(crate) const DISPLACEMENT: Pass<[u32; 2]> = Pass {
    name: "water displacement",
    module: "gpu::water_displacement",
    library: LIBRARY,
    features: &[],
    groups: &[water_group(&[
        FRAME,
        WATER,
        Binding::new("data", Kind::texture_2d(Sample::Uint)),
        float_texture("depth"),
        MATERIALS,
        float_texture("noise"),
        Binding::new("decals", Kind::read(size_of::<GpuWaterDecal>())),
        Binding::new(
            "decal_texels",
            Kind::Texture {
                sample: Sample::Float { filterable: false },
                dim: Dim::D2Array,
            },
        ),
        Binding::new(
            "displacement",
            Kind::storage_texture_2d(Format::Rgba32Float),
        ),
        Binding::new("vertices", Kind::read_write(16)),
    ])],
    entries: &[Entry::grid("displace", 8, 8, |s| *s)],
    zeroed: &[],
};

/// The pass's pipelines, recorded by the water's `record_grid`.
pub(crate) fn new(device: &wgpu::Device) -> Result<ComputePass<[u32; 2]>> {
    Ok(ComputePass::new(device, &DISPLACEMENT, &[], &[])?)
}

#[cfg(test)]
mod tests {
    #[test]
    fn description_matches_its_module() {
        shadercheck::check_pass(&super::DISPLACEMENT, |_| shadercheck::Caps::CORE);
    }
}
