//! Seed 004's geometry pipeline, [`RenderPath::PixelPull`](crate::RenderPath): after the
//! baseline's depth prepass (alpha-tested, in [`laydown`](super::laydown)), every batch is
//! drawn again with depth test `Equal` by a position-only vertex stage, and the fragment
//! stage pulls its triangle's vertices from storage by the primitive ID and interpolates
//! them with barycentrics (`gpu::pixel_pull`): hardware barycentrics where the device has
//! `SHADER_BARYCENTRICS`, else the pixel's camera ray against the triangle
//! (`visbuf::ray`). The primitive ID comes the laydown's way (`PrimitiveIdPath`).

use shader::pipeline::{Layouts, RasterPass};
use shader::{Binding, Entry, Group, Kind, Pass, Raster, Stage};

use super::context::FrameContext;
use super::raster::record_draws;
use super::raster::{
    DEPTH_EQUAL, GEOMETRY, SCENE_GROUP, depth_attachment, gbuffer_targets, loaded_colors,
};
use crate::context::PrimitiveIdPath;
use crate::error::Result;
use crate::gbuffer;
pub(crate) use crate::resources::groups::PixelPullGroups as Groups;
use crate::resources::rows::{GpuMesh, GpuMicroBatch};
use crate::shaders::LIBRARY;
use crate::timing::GpuTimer;

/// The pixel-pull depth-equal pass. Features: the G-buffer layout's, the primitive-ID path
/// (`primitive_builtin`, `primitive_xor`, neither: the provoking vertex) and
/// `barycentrics` (hardware; else the ray fallback).
pub(crate) const PIXEL_PULL: Pass = Pass {
    name: "pixel-pull depth-equal pass",
    module: "gpu::pixel_pull",
    library: LIBRARY,
    features: &[
        "kz2_gbuffer",
        "primitive_builtin",
        "primitive_xor",
        "barycentrics",
    ],
    groups: &[
        SCENE_GROUP,
        Group {
            name: "pull",
            bindings: &[
                Binding::new("payloads", Kind::read(4)),
                Binding::new("indices", Kind::read(4)),
                Binding::new("meshes", Kind::read(size_of::<GpuMesh>())),
                Binding::new("micro_batches", Kind::read(size_of::<GpuMicroBatch>())),
            ],
        },
    ],
    entries: &[
        Entry::draw("vs_pull", Stage::Vertex),
        Entry::draw("fs_pull", Stage::Fragment),
        Entry::draw("fs_pull_fade", Stage::Fragment),
    ],
    zeroed: &[],
};

/// The pass's planned instances over the prepass's depth (`Equal`), into the G-buffer (the
/// targets are the layout's: [`gbuffer_targets`]).
pub(crate) const PULL_PIPELINE: Raster<'static> = Raster::new(PIXEL_PULL.name, "vs_pull")
    .fragment("fs_pull")
    .primitive(GEOMETRY)
    .depth(DEPTH_EQUAL);

/// Its static instances (which may fade).
pub(crate) const PULL_FADE: Raster<'static> = PULL_PIPELINE.fragment("fs_pull_fade");

/// The composer features of the pass for a G-buffer layout, a primitive-ID path and
/// whether hardware barycentrics are used.
pub(crate) fn features(
    layout: deferred::GBufferLayout,
    path: PrimitiveIdPath,
    barycentrics: bool,
) -> Vec<&'static str> {
    let mut f = gbuffer::features(layout).to_vec();
    match path {
        PrimitiveIdPath::Builtin => f.push("primitive_builtin"),
        PrimitiveIdPath::PerVertexXor => f.push("primitive_xor"),
        PrimitiveIdPath::ProvokingVertex => {}
    }
    if barycentrics {
        f.push("barycentrics");
    }
    f
}

/// The pass's pipelines: planned instances, and static ones (which may fade).
pub(crate) struct PixelPull {
    layouts: Layouts,
    pipeline: wgpu::RenderPipeline,
    fade_pipeline: wgpu::RenderPipeline,
}

impl PixelPull {
    /// The pipelines writing the G-buffer of `layout`, primitive IDs by `path`, hardware
    /// `barycentrics` or the ray fallback.
    pub(crate) fn new(
        device: &wgpu::Device,
        layout: deferred::GBufferLayout,
        path: PrimitiveIdPath,
        barycentrics: bool,
    ) -> Result<Self> {
        let features = features(layout, path, barycentrics);
        let raster = RasterPass::new(device, &PIXEL_PULL, &features, &[])?;
        let make =
            |r: Raster<'static>| raster.pipeline(device, &r.targets(gbuffer_targets(layout)));
        Ok(Self {
            pipeline: make(PULL_PIPELINE)?,
            fade_pipeline: make(PULL_FADE)?,
            layouts: raster.layouts,
        })
    }

    /// A prepared scene's groups: its `scene` resources by binding name, and its payloads,
    /// index buffer, meshes and micro batches.
    pub(crate) fn groups(
        &self,
        device: &wgpu::Device,
        scene: &[(&str, wgpu::BindingResource<'_>)],
        [payloads, indices, meshes, micro_batches]: [&wgpu::Buffer; 4],
    ) -> Result<Groups> {
        Ok(Groups {
            scene: self.layouts.bind_group(device, "scene", scene)?,
            pull: self.layouts.bind_group(
                device,
                "pull",
                &[
                    ("payloads", payloads.as_entire_binding()),
                    ("indices", indices.as_entire_binding()),
                    ("meshes", meshes.as_entire_binding()),
                    ("micro_batches", micro_batches.as_entire_binding()),
                ],
            )?,
        })
    }

    /// Records the depth-equal pass over the prepass's depth (single-sample).
    pub(crate) fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
    ) {
        let colors = loaded_colors(&f.targets.gbuffer_views);
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(PIXEL_PULL.name),
            color_attachments: &colors,
            depth_stencil_attachment: Some(depth_attachment(&f.targets.depth_view, true)),
            timestamp_writes: timer.render("pixel-pull depth-equal pass"),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, &f.scene.pixel_pull.scene, &[]);
        pass.set_bind_group(1, &f.scene.pixel_pull.pull, &[]);
        // No alpha test: the prepass decided coverage, depth-equal keeps the survivors.
        let p = &self.pipeline;
        record_draws(&mut pass, f, p, p, &self.fade_pipeline, false);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shadercheck::Caps;

    fn caps(features: &[&str]) -> Caps {
        let mut c = Caps::CORE;
        if features.contains(&"primitive_builtin") {
            c = c.union(Caps::PRIMITIVE_INDEX);
        } else if features.contains(&"primitive_xor") {
            c = c.union(Caps::PER_VERTEX);
        }
        if features.contains(&"barycentrics") {
            c = c.union(Caps::BARYCENTRICS);
        }
        c
    }

    /// Every combination, the hardware-barycentric ones included (composed and validated
    /// by naga without a device that has them).
    #[test]
    fn description_matches_its_module_on_every_path() {
        let modules = shadercheck::check_pass(&PIXEL_PULL, caps);
        assert_eq!(modules.len(), 16);
    }

    #[test]
    fn pipelines_match_their_module_for_every_layout() {
        for layout in deferred::GBufferLayout::ALL {
            let f = features(layout, PrimitiveIdPath::ProvokingVertex, false);
            for r in [PULL_PIPELINE, PULL_FADE] {
                let r = r.targets(gbuffer_targets(layout));
                shadercheck::check_raster(&PIXEL_PULL, &r, &f, caps(&f));
            }
        }
    }

    #[test]
    fn each_variant_needs_exactly_its_capabilities() {
        for path in PrimitiveIdPath::ALL {
            for bary in [false, true] {
                let f = features(deferred::GBufferLayout::Octahedral, path, bary);
                let src = PIXEL_PULL.source(&f).unwrap();
                shadercheck::validate(&src, caps(&f)).unwrap();
                if bary {
                    let without: Vec<&str> =
                        f.iter().copied().filter(|x| *x != "barycentrics").collect();
                    assert!(
                        shadercheck::validate(&src, caps(&without)).is_err(),
                        "{path:?}: hardware barycentrics need their capability"
                    );
                    assert!(src.contains("@builtin(barycentric)"));
                } else {
                    assert!(src.contains("visbuf_intersect_watertight(vec3<f32>(0.0)"));
                }
            }
        }
    }

    /// The hardware-barycentric variant down to SPIR-V (what Vulkan devices with the
    /// feature, the H200's, are given): naga writes `BaryCoordKHR` under
    /// `SPV_KHR_fragment_shader_barycentric`.
    #[test]
    fn the_hardware_barycentric_variant_writes_spirv() {
        let f = features(
            deferred::GBufferLayout::Octahedral,
            PrimitiveIdPath::Builtin,
            true,
        );
        let src = PIXEL_PULL.source(&f).unwrap();
        let module = shadercheck::validate(&src, caps(&f)).unwrap();
        let info = naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::all(),
        )
        .validate(&module)
        .unwrap();
        // The overrides (the material's MATERIAL_FEATURES) at their defaults, as a
        // pipeline that sets none has them.
        let (module, info) = naga::back::pipeline_constants::process_overrides(
            &module,
            &info,
            None,
            &naga::back::PipelineConstants::default(),
        )
        .unwrap();
        let words = naga::back::spv::write_vec(
            &module,
            &info,
            &naga::back::spv::Options::default(),
            Some(&naga::back::spv::PipelineOptions {
                shader_stage: naga::ShaderStage::Fragment,
                entry_point: "fs_pull".into(),
            }),
        )
        .unwrap();
        // SpvBuiltInBaryCoordKHR = 5286, decorated on an input.
        assert!(words.windows(2).any(|w| w == [11, 5286]), "BaryCoordKHR");
    }
}
