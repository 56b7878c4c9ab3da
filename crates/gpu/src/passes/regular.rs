//! HFW's mixed frame: the regular geometry pass. After the laydown (which leaves out the
//! batches of [`Material::regular`](crate::Material::regular) materials) and mid classify,
//! those batches are drawn the ordinary way, depth test `Greater` and depth writes over the
//! laydown's depth, their fragment shader writing the G-buffer (the baseline's,
//! `gpu::baseline` with feature `regular`) and clearing each drawn pixel's bit in the
//! classification's validity bitmask, so classify output and the resolve shade only the
//! vis-buffer pixels still in front. The talk's stencil bit, written by laydown finalize
//! through a UAV: wgpu has no stencil storage view, so the bit lives in a buffer
//! (`atomicAnd`), filled with ones before laydown finalize. The depth test runs before the
//! shader (`@early_depth_test(force)`, `Features::SHADER_EARLY_DEPTH_TEST`), so a fragment
//! hidden by foliage clears nothing.

use shader::pipeline::{Layouts, RasterPass};
use shader::{Binding, Entry, Group, Kind, Pass, Raster, Stage};

use super::context::FrameContext;
use super::raster::{
    DEPTH_WRITE, GEOMETRY, SCENE_GROUP, depth_attachment, gbuffer_targets, loaded_colors,
};
use crate::error::Result;
use crate::gbuffer;
pub(crate) use crate::resources::groups::RegularGroups as Groups;
use crate::shaders::LIBRARY;
use crate::timing::GpuTimer;

/// The regular geometry pass: the baseline's module with its `regular` entry and the
/// validity group.
pub(crate) const REGULAR: Pass = Pass {
    name: "regular geometry pass",
    module: "gpu::baseline",
    library: LIBRARY,
    features: &["kz2_gbuffer", "regular"],
    groups: &[
        SCENE_GROUP,
        Group {
            name: "validity",
            bindings: &[Binding::new("validity", Kind::read_write(4))],
        },
    ],
    entries: &[
        Entry::draw("vs_baseline", Stage::Vertex),
        Entry::draw("fs_baseline", Stage::Fragment),
        Entry::draw("fs_baseline_fade", Stage::Fragment),
        Entry::draw("fs_regular", Stage::Fragment),
    ],
    zeroed: &[],
};

/// The regular draws over the laydown's depth (`Greater`, writing), into the G-buffer (the
/// targets are the layout's: [`gbuffer_targets`]).
pub(crate) const REGULAR_PIPELINE: Raster<'static> = Raster::new(REGULAR.name, "vs_baseline")
    .fragment("fs_regular")
    .primitive(GEOMETRY)
    .depth(DEPTH_WRITE);

/// The device feature the pass needs (the forced early depth test).
pub(crate) const REGULAR_FEATURES: wgpu::Features = wgpu::Features::SHADER_EARLY_DEPTH_TEST;

/// The regular geometry pass's pipeline.
pub(crate) struct Regular {
    layouts: Layouts,
    pipeline: wgpu::RenderPipeline,
}

impl Regular {
    /// The pipeline writing the G-buffer of `layout`.
    pub(crate) fn new(device: &wgpu::Device, layout: deferred::GBufferLayout) -> Result<Self> {
        let mut features = gbuffer::features(layout).to_vec();
        features.push("regular");
        let raster = RasterPass::new(device, &REGULAR, &features, &[])?;
        let pipeline =
            raster.pipeline(device, &REGULAR_PIPELINE.targets(gbuffer_targets(layout)))?;
        Ok(Self {
            layouts: raster.layouts,
            pipeline,
        })
    }

    /// A prepared scene's groups: its `scene` resources by binding name and the
    /// classification's validity bitmask.
    pub(crate) fn groups(
        &self,
        device: &wgpu::Device,
        scene: &[(&str, wgpu::BindingResource<'_>)],
        validity: &wgpu::Buffer,
    ) -> Result<Groups> {
        Ok(Groups {
            scene: self.layouts.bind_group(device, "scene", scene)?,
            validity: self.layouts.bind_group(
                device,
                "validity",
                &[("validity", validity.as_entire_binding())],
            )?,
        })
    }

    /// Records the pass: the scene's regular draws over the laydown's depth, into the
    /// G-buffer (loaded: the resolve fills the rest after it).
    pub(crate) fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
    ) {
        let Some(groups) = &f.scene.regular else {
            return;
        };
        let colors = loaded_colors(&f.targets.gbuffer_views);
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(REGULAR.name),
            color_attachments: &colors,
            depth_stencil_attachment: Some(depth_attachment(&f.targets.depth_view, true)),
            timestamp_writes: timer.render(REGULAR.name),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, &groups.scene, &[]);
        pass.set_bind_group(1, &groups.validity, &[]);
        pass.set_pipeline(&self.pipeline);
        pass.set_index_buffer(f.scene.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
        for d in f
            .scene
            .draws
            .iter()
            .filter(|d| d.regular && d.instance_count > 0)
        {
            super::raster::draw(&mut pass, d);
        }
    }
}

#[cfg(test)]
mod tests {
    use shadercheck::Caps;

    #[test]
    fn description_matches_its_module_with_the_early_depth_test() {
        shadercheck::check_pass_with(&super::REGULAR, &["regular"], |_| {
            Caps::CORE.union(Caps::EARLY_DEPTH_TEST)
        });
        // The pass needs its capability.
        let src = super::REGULAR.source(&["regular"]).unwrap();
        assert!(shadercheck::validate(&src, Caps::CORE).is_err());
        for layout in deferred::GBufferLayout::ALL {
            let mut features = crate::gbuffer::features(layout).to_vec();
            features.push("regular");
            shadercheck::check_raster(
                &super::REGULAR,
                &super::REGULAR_PIPELINE.targets(super::gbuffer_targets(layout)),
                &features,
                Caps::CORE.union(Caps::EARLY_DEPTH_TEST),
            );
        }
    }
}
