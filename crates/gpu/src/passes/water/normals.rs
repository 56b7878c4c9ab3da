//! Normals from depth (`gpu::water_normals`): over the tessellated surface at full
//! resolution, blended with the mesh normal.

use shader::pipeline::ComputePass;
use shader::{Binding, Entry, Format, Group, Kind, Pass, Sample};

use super::super::LIBRARY;
use super::{GpuWaterFrame, WaterGroups};
use crate::error::Result;
use crate::resources::rows::FrameUniforms;
use crate::timing::GpuTimer;

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

pub(crate) struct Normals {
    pub pass: ComputePass<[u32; 2]>,
}

impl Normals {
    pub(crate) fn new(device: &wgpu::Device) -> Result<Self> {
        Ok(Self {
            pass: ComputePass::new(device, &NORMALS, &[], &[])?,
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
            label: Some("water normals"),
            timestamp_writes: timer.compute("water normals"),
        });
        self.pass.record(&mut pass, &[&g.normals], &size);
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn description_matches_its_module() {
        shadercheck::check_pass(&super::NORMALS, |_| shadercheck::Caps::CORE);
    }
}
