//! Screen-space tessellation (`gpu::water_tessellation`): per visible tile one instance of
//! the 16x16-quad grid, whose 16-bit vertex words are the index buffer, drawn with one
//! `draw_indexed_indirect` into the depth with water.

use shader::pipeline::Layouts;
use shader::{Binding, Entry, Group, Kind, Pass, Stage};

use super::super::LIBRARY;
use super::{GpuWaterFrame, WaterGroups, WaterTargets};
use crate::error::Result;
use crate::resources::rows::FrameUniforms;
use crate::timing::GpuTimer;

/// The pass: the grid's vertex and fragment stages.
pub(crate) const TESSELLATION: Pass = Pass {
    name: "water tessellation",
    module: "gpu::water_tessellation",
    library: LIBRARY,
    features: &[],
    groups: &[Group {
        name: "water",
        bindings: &[
            Binding::new("frame", Kind::uniform(size_of::<FrameUniforms>())),
            Binding::new("water", Kind::uniform(size_of::<GpuWaterFrame>())),
            Binding::new("vertices", Kind::read(16)),
            Binding::new("tile_list", Kind::read(4)),
        ],
    }],
    entries: &[
        Entry::draw("vs_grid", Stage::Vertex),
        Entry::draw("fs_grid", Stage::Fragment),
    ],
    zeroed: &[],
};

/// The surface target's format: view depth, mini G-buffer UV.
pub(crate) const SURFACE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

pub(crate) struct Tessellation {
    pub layouts: Layouts,
    pipeline: wgpu::RenderPipeline,
}

impl Tessellation {
    pub(crate) fn new(device: &wgpu::Device) -> Result<Self> {
        let layouts = Layouts::new(device, &TESSELLATION);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(TESSELLATION.name),
            source: wgpu::ShaderSource::Wgsl(TESSELLATION.source(&[])?.into()),
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("water tessellation"),
            layout: Some(layouts.pipeline_layout()),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_grid"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            // Displacement may fold a triangle over: both faces.
            primitive: wgpu::PrimitiveState {
                cull_mode: None,
                ..super::super::laydown::primitive_state()
            },
            depth_stencil: Some(super::super::laydown::depth_write_state()),
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_grid"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: SURFACE_FORMAT,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        Ok(Self { layouts, pipeline })
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
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &t.surface.1,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })],
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
    }
}
