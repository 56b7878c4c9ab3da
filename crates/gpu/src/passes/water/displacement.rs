//! Displacement (`gpu::water_displacement`): FBM with octave LOD and the vector
//! displacement decals into the displacement texture, at the mini G-buffer's resolution.

use shader::pipeline::ComputePass;
use shader::{Binding, Dim, Entry, Format, Group, Kind, Pass, Sample};

use super::super::LIBRARY;
use super::{GpuWaterDecal, GpuWaterFrame};
use crate::error::Result;
use crate::resources::rows::FrameUniforms;

/// The pass, over the mini G-buffer (`[width, height]`).
pub(crate) const DISPLACEMENT: Pass<[u32; 2]> = Pass {
    name: "water displacement",
    module: "gpu::water_displacement",
    library: LIBRARY,
    features: &[],
    groups: &[Group {
        name: "water",
        bindings: &[
            Binding::new("frame", Kind::uniform(size_of::<FrameUniforms>())),
            Binding::new("water", Kind::uniform(size_of::<GpuWaterFrame>())),
            Binding::new("data", Kind::texture_2d(Sample::Uint)),
            Binding::new(
                "depth",
                Kind::texture_2d(Sample::Float { filterable: false }),
            ),
            Binding::new(
                "materials",
                Kind::read(size_of::<water::material::WaterMaterialGpu>()),
            ),
            Binding::new(
                "noise",
                Kind::texture_2d(Sample::Float { filterable: false }),
            ),
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
        ],
    }],
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
