//! Screen-space tessellation (`gpu::water_tessellation`): per visible tile one instance of
//! the 16x16-quad grid, whose 16-bit vertex words are the index buffer, drawn with one
//! `draw_indexed_indirect` into the depth with water.

use shader::pipeline::{Layouts, RasterPass};
use shader::{Binding, Entry, Format, Kind, Pass, Raster, Stage, Target};

use super::super::raster::{DEPTH_WRITE, GEOMETRY};
use super::groups::WaterGroups;
use super::rows::{FRAME, WATER, water_group};
use super::targets::WaterTargets;
use crate::error::Result;
use crate::resources::targets::cleared_color;
use crate::shaders::LIBRARY;
use crate::timing::GpuTimer;

/// The pass: the grid's vertex and fragment stages.
pub(crate) const TESSELLATION: Pass = Pass {
    name: "water tessellation",
    module: "gpu::water_tessellation",
    library: LIBRARY,
    features: &[],
    groups: &[water_group(&[
        FRAME,
        WATER,
        Binding::new("vertices", Kind::read(16)),
        Binding::new("tile_list", Kind::read(4)),
    ])],
    entries: &[
        Entry::draw("vs_grid", Stage::Vertex),
        Entry::draw("fs_grid", Stage::Fragment),
    ],
    zeroed: &[],
};

/// The grid into the surface target (view depth, mini G-buffer UV) and the depth with
/// water, reversed-Z depth written. Both faces: displacement may fold a triangle over.
pub(crate) const GRID: Raster<'static> = Raster::new("water tessellation", "vs_grid")
    .fragment("fs_grid")
    .targets(&[Target::replace(Format::Rgba32Float)])
    .primitive(GEOMETRY)
    .cull(None)
    .depth(DEPTH_WRITE);

pub(crate) struct Tessellation {
    pub layouts: Layouts,
    pipeline: wgpu::RenderPipeline,
}

impl Tessellation {
    pub(crate) fn new(device: &wgpu::Device) -> Result<Self> {
        let raster = RasterPass::new(device, &TESSELLATION, &[], &[])?;
        Ok(Self {
            pipeline: raster.pipeline(device, &GRID)?,
            layouts: raster.layouts,
        })
    }

    pub(crate) fn record(
        &self,
        e: &mut wgpu::CommandEncoder,
        t: &WaterTargets,
        g: &WaterGroups,
        timer: &mut GpuTimer,
    ) {
        let mut pass = e.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("water tessellation"),
            color_attachments: &[cleared_color(&t.surface.1)],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &t.depth_water.1,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: timer.render("water tessellation"),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &g.tessellation, &[]);
        pass.set_index_buffer(t.grid.slice(..), wgpu::IndexFormat::Uint16);
        pass.draw_indexed_indirect(&t.tile_args, 0);
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn description_matches_its_module() {
        shadercheck::check_pass(&super::TESSELLATION, |_| shadercheck::Caps::CORE);
        shadercheck::check_raster(
            &super::TESSELLATION,
            &super::GRID,
            &[],
            shadercheck::Caps::CORE,
        );
    }
}
