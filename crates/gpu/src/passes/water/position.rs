//! The position pass (`gpu::water_position`): the mini G-buffer at reduced resolution
//! and a wider field of view, drawn from the near bodies' meshes (one indexed indirect
//! draw per body, the visibility pass's arguments) and the far sectors (two indirect
//! draws: flat sectors a quad each, height-map sectors a grid each).

use shader::pipeline::{Layouts, RasterPass};
use shader::{Binding, Entry, Format, Kind, Pass, Raster, Sample, Stage, Target};

use super::super::raster::{DEPTH_WRITE, GEOMETRY};
use super::data::WaterData;
use super::groups::WaterGroups;
use super::rows::{FRAME, MATERIALS, WATER, water_group};
use super::targets::WaterTargets;
use crate::error::Result;
use crate::resources::targets::cleared_color;
use crate::shaders::LIBRARY;
use crate::timing::GpuTimer;

/// The pass: two vertex stages (near meshes, far sectors) and one fragment stage.
pub(crate) const POSITION: Pass = Pass {
    name: "water position",
    module: "gpu::water_position",
    library: LIBRARY,
    features: &[],
    groups: &[water_group(&[
        FRAME,
        WATER,
        Binding::new("world", Kind::texture_2d(Sample::Uint)),
        MATERIALS,
        Binding::new("vertices", Kind::read(32)),
        Binding::new("nodes", Kind::read(32)),
        Binding::new("far_list", Kind::read(4)),
        Binding::new("hiz", Kind::read(4)),
    ])],
    entries: &[
        Entry::draw("vs_near", Stage::Vertex),
        Entry::draw("vs_far_flat", Stage::Vertex),
        Entry::draw("vs_far_height", Stage::Vertex),
        Entry::draw("fs_position", Stage::Fragment),
    ],
    zeroed: &[],
};

/// The mini G-buffer's targets: data word, mesh normal, view depth.
pub(crate) const TARGETS: &[Target] = &[
    Target::replace(Format::R32Uint),
    Target::replace(Format::Rgba16Float),
    Target::replace(Format::R32Float),
];

/// The near bodies' meshes into the mini G-buffer, reversed-Z depth written. Both faces:
/// water seen from below keeps its front-face flag clear.
pub(crate) const NEAR: Raster<'static> = Raster::new("water position near", "vs_near")
    .fragment("fs_position")
    .targets(TARGETS)
    .primitive(GEOMETRY)
    .cull(None)
    .depth(DEPTH_WRITE);

/// The far flat sectors (a quad each).
pub(crate) const FAR_FLAT: Raster<'static> = Raster {
    name: "water position far flat",
    vertex: "vs_far_flat",
    ..NEAR
};

/// The far height-map sectors (a grid each).
pub(crate) const FAR_HEIGHT: Raster<'static> = Raster {
    name: "water position far height map",
    vertex: "vs_far_height",
    ..NEAR
};

/// The pass's pipelines.
pub(crate) struct Position {
    pub layouts: Layouts,
    near: wgpu::RenderPipeline,
    far_flat: wgpu::RenderPipeline,
    far_height: wgpu::RenderPipeline,
}

impl Position {
    pub(crate) fn new(device: &wgpu::Device) -> Result<Self> {
        let raster = RasterPass::new(device, &POSITION, &[], &[])?;
        Ok(Self {
            near: raster.pipeline(device, &NEAR)?,
            far_flat: raster.pipeline(device, &FAR_FLAT)?,
            far_height: raster.pipeline(device, &FAR_HEIGHT)?,
            layouts: raster.layouts,
        })
    }

    /// Records the pass: the targets cleared (no water), the near bodies, the far draw.
    pub(crate) fn record(
        &self,
        e: &mut wgpu::CommandEncoder,
        t: &WaterTargets,
        d: &WaterData,
        g: &WaterGroups,
        timer: &mut GpuTimer,
    ) {
        let mut pass = e.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("water position"),
            color_attachments: &[
                cleared_color(&t.data.1),
                cleared_color(&t.normal.1),
                cleared_color(&t.linear.1),
            ],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &t.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: timer.render("water position"),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, &g.position, &[]);
        if d.body_count > 0 {
            pass.set_pipeline(&self.near);
            pass.set_index_buffer(d.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.multi_draw_indexed_indirect(&d.near_args, 0, d.body_count);
        }
        if d.tree.levels > 0 {
            pass.set_pipeline(&self.far_flat);
            pass.draw_indirect(&d.far_args, 0);
            pass.set_pipeline(&self.far_height);
            pass.draw_indirect(&d.far_args, 16);
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn description_matches_its_module() {
        shadercheck::check_pass(&super::POSITION, |_| shadercheck::Caps::CORE);
        for r in [super::NEAR, super::FAR_FLAT, super::FAR_HEIGHT] {
            shadercheck::check_raster(&super::POSITION, &r, &[], shadercheck::Caps::CORE);
        }
    }
}
