//! The composite (`gpu::water_composite`): light transport, refraction, reflection, sun
//! and local lights, specular AA and the material blend, tone mapped over the output;
//! feature `f16` for half precision where the device has `SHADER_F16`.

use shader::pipeline::ComputePass;
use shader::{Binding, Entry, Format, Kind, Pass, Sample};

use super::rows::{FRAME, MATERIALS, WATER, float_texture, water_group};
use crate::error::Result;
use crate::resources::lights::GpuLocalLights;
use crate::shaders::LIBRARY;

/// The pass, over the image (`[width, height]`).
pub(crate) const COMPOSITE: Pass<[u32; 2]> = Pass {
    name: "water composite",
    module: "gpu::water_composite",
    library: LIBRARY,
    features: &["f16"],
    groups: &[water_group(&[
        FRAME,
        WATER,
        Binding::new("local", Kind::uniform(size_of::<GpuLocalLights>())),
        Binding::new("lights", Kind::read(size_of::<deferred::DeferredLight>())),
        Binding::new("light_counts", Kind::read(4)),
        Binding::new("light_indices", Kind::read(4)),
        float_texture("surface"),
        float_texture("normals"),
        float_texture("foam"),
        Binding::new("data", Kind::texture_2d(Sample::Uint)),
        MATERIALS,
        Binding::new("material_map", Kind::texture_2d(Sample::Uint)),
        float_texture("scene_hdr"),
        Binding::new("scene_depth", Kind::texture_2d(Sample::Depth)),
        Binding::new("output", Kind::storage_texture_2d(Format::Rgba8Unorm)),
    ])],
    entries: &[Entry::grid("composite", 8, 8, |s| *s)],
    zeroed: &[],
};

/// The pass's pipelines; with `half`, the `f16` variant (the device must have
/// `SHADER_F16`). Recorded by the water's `record_grid`.
pub(crate) fn new(device: &wgpu::Device, half: bool) -> Result<ComputePass<[u32; 2]>> {
    let features: &[&str] = if half { &["f16"] } else { &[] };
    Ok(ComputePass::new(device, &COMPOSITE, features, &[])?)
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
