//! The depth + visibility laydown (seed 000) and the baseline's depth prepass: one render
//! pass each, one indexed draw per micro batch, vertices pulled from storage.

use crate::binding;
use crate::context::PrimitiveIdPath;
use crate::shaders;
use crate::targets::{DEPTH_FORMAT, VIS_FORMAT};

/// One draw: a micro batch's instances of one mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Draw {
    /// First index in the index buffer.
    pub first_index: u32,
    /// Index count (3 × primitives).
    pub index_count: u32,
    /// Added to every index.
    pub base_vertex: u32,
    /// First instance in the global instance table.
    pub first_instance: u32,
    /// Instances.
    pub instance_count: u32,
    /// Whether the material is alpha-tested.
    pub alpha_tested: bool,
}

/// The laydown's pipelines for one primitive-ID path.
pub struct LaydownPipelines {
    /// Bind-group layout (see `shaders/laydown.wgsl`).
    pub layout: wgpu::BindGroupLayout,
    /// Depth + vis, opaque materials.
    pub vis_opaque: wgpu::RenderPipeline,
    /// Depth + vis, alpha-tested materials.
    pub vis_alpha: wgpu::RenderPipeline,
    /// Depth only (baseline prepass), opaque.
    pub depth_opaque: wgpu::RenderPipeline,
    /// Depth only (baseline prepass), alpha-tested.
    pub depth_alpha: wgpu::RenderPipeline,
}

/// The bind-group layout entries of the laydown (and of the baseline's geometry pass, which
/// reads the same resources): frame, vertices, instances, materials, payloads, albedo,
/// sampler.
pub fn scene_layout_entries() -> Vec<wgpu::BindGroupLayoutEntry> {
    use wgpu::ShaderStages as S;
    let vf = S::VERTEX | S::FRAGMENT;
    vec![
        binding::uniform(0, vf),
        binding::storage(1, vf, true),
        binding::storage(2, vf, true),
        binding::storage(3, vf, true),
        binding::storage(4, vf, true),
        binding::texture(
            5,
            S::FRAGMENT,
            wgpu::TextureSampleType::Float { filterable: true },
            wgpu::TextureViewDimension::D2Array,
        ),
        binding::sampler(6, S::FRAGMENT),
    ]
}

/// Primitive state shared by every geometry pipeline: triangle lists, counter-clockwise
/// front faces, back faces culled (foliage cards carry both faces as geometry).
pub fn primitive_state() -> wgpu::PrimitiveState {
    wgpu::PrimitiveState {
        topology: wgpu::PrimitiveTopology::TriangleList,
        strip_index_format: None,
        front_face: wgpu::FrontFace::Ccw,
        cull_mode: Some(wgpu::Face::Back),
        unclipped_depth: false,
        polygon_mode: wgpu::PolygonMode::Fill,
        conservative: false,
    }
}

/// Reversed-Z depth state: `Greater`, writing.
pub fn depth_write_state() -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: DEPTH_FORMAT,
        depth_write_enabled: Some(true),
        depth_compare: Some(wgpu::CompareFunction::Greater),
        stencil: wgpu::StencilState::default(),
        bias: wgpu::DepthBiasState::default(),
    }
}

impl LaydownPipelines {
    /// Builds the pipelines of `path`.
    pub fn new(device: &wgpu::Device, path: PrimitiveIdPath) -> Self {
        let layout = binding::layout(device, "laydown", &scene_layout_entries());
        let pl = binding::pipeline_layout(device, "laydown", &[&layout]);
        let module = binding::module(device, "laydown", &shaders::laydown(path));
        let (fs_opaque, fs_alpha) = shaders::laydown_entry_points(path);
        let vs = if path == PrimitiveIdPath::Builtin {
            "vs_main"
        } else {
            "vs_payload"
        };
        let make = |label: &str, vs: &str, fs: Option<&str>, vis: bool| {
            let targets = [Some(wgpu::ColorTargetState {
                format: VIS_FORMAT,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })];
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&pl),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some(vs),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: primitive_state(),
                depth_stencil: Some(depth_write_state()),
                multisample: wgpu::MultisampleState::default(),
                fragment: fs.map(|entry| wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    targets: if vis { &targets } else { &[] },
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        Self {
            vis_opaque: make("laydown vis opaque", vs, Some(fs_opaque), true),
            vis_alpha: make("laydown vis alpha", vs, Some(fs_alpha), true),
            depth_opaque: make("prepass depth opaque", "vs_main", None, false),
            depth_alpha: make(
                "prepass depth alpha",
                "vs_main",
                Some("fs_depth_alpha"),
                false,
            ),
            layout,
        }
    }
}

/// Records `draws` into `pass` with the opaque or alpha-tested pipeline as each needs,
/// opaque draws first (they fill depth that early-Z then uses against the foliage).
pub fn record_draws(
    pass: &mut wgpu::RenderPass<'_>,
    draws: &[Draw],
    opaque: &wgpu::RenderPipeline,
    alpha: &wgpu::RenderPipeline,
    bind_group: &wgpu::BindGroup,
    index_buffer: &wgpu::Buffer,
) {
    pass.set_bind_group(0, bind_group, &[]);
    pass.set_index_buffer(index_buffer.slice(..), wgpu::IndexFormat::Uint32);
    for alpha_pass in [false, true] {
        pass.set_pipeline(if alpha_pass { alpha } else { opaque });
        for d in draws
            .iter()
            .filter(|d| d.alpha_tested == alpha_pass && d.instance_count > 0)
        {
            pass.draw_indexed(
                d.first_index..d.first_index + d.index_count,
                d.base_vertex as i32,
                d.first_instance..d.first_instance + d.instance_count,
            );
        }
    }
}
