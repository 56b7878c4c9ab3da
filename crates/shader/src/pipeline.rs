//! The wgpu side of a [`Pass`]: layouts from its groups, compute pipelines from its
//! composed module ([`ComputePass`]) and render pipelines from its [`Raster`] descriptions
//! ([`RasterPass`]), bind groups by binding name, and dispatches from its geometry. The
//! renderer and the device tests both go through here, so a pass is bound and run one way.

use std::format;
use std::string::String;
use std::vec::Vec;

use crate::compose::Error;
use crate::pass::{Dim, Entry, Format, Group, Kind, Pass, Sample, Size, Stage};
use crate::raster::{
    Blend, BlendComponent, BlendFactor, BlendOp, Compare, Depth, DepthFormat, Face, FrontFace,
    Raster, Stencil, StencilFace, StencilOp, Topology, VertexFormat,
};

/// wgpu's texture format for a storage texel format.
#[must_use]
pub fn texture_format(f: Format) -> wgpu::TextureFormat {
    match f {
        Format::Rgba8Unorm => wgpu::TextureFormat::Rgba8Unorm,
        Format::Rgba8Uint => wgpu::TextureFormat::Rgba8Uint,
        Format::Rgba16Float => wgpu::TextureFormat::Rgba16Float,
        Format::R32Uint => wgpu::TextureFormat::R32Uint,
        Format::R32Float => wgpu::TextureFormat::R32Float,
        Format::R64Uint => wgpu::TextureFormat::R64Uint,
        Format::Rgba32Float => wgpu::TextureFormat::Rgba32Float,
    }
}

fn view_dimension(d: Dim) -> wgpu::TextureViewDimension {
    match d {
        Dim::D2 | Dim::D2Multisampled => wgpu::TextureViewDimension::D2,
        Dim::D2Array => wgpu::TextureViewDimension::D2Array,
        Dim::D3 => wgpu::TextureViewDimension::D3,
    }
}

/// The stages a pass's bindings are visible to: every stage its entry points run in.
#[must_use]
pub fn visibility<P>(pass: &Pass<P>) -> wgpu::ShaderStages {
    pass.entries
        .iter()
        .fold(wgpu::ShaderStages::NONE, |acc, e| {
            acc | match e.stage {
                Stage::Vertex => wgpu::ShaderStages::VERTEX,
                Stage::Fragment => wgpu::ShaderStages::FRAGMENT,
                Stage::Compute(_) => wgpu::ShaderStages::COMPUTE,
            }
        })
}

/// The layout entries of `group`, visible to `visibility`.
#[must_use]
pub fn layout_entries(
    group: &Group,
    visibility: wgpu::ShaderStages,
) -> Vec<wgpu::BindGroupLayoutEntry> {
    group
        .bindings
        .iter()
        .enumerate()
        .map(|(i, b)| wgpu::BindGroupLayoutEntry {
            binding: i as u32,
            // A vertex stage that may write storage needs `VERTEX_WRITABLE_STORAGE`: writable
            // bindings of a render pass are its fragment stage's (a vertex stage reading one
            // fails pipeline creation, so no pass can rely on the wider visibility).
            visibility: match b.kind {
                Kind::Storage { writable: true, .. }
                | Kind::StorageTexture { .. }
                | Kind::AtomicStorageTexture { .. } => visibility - wgpu::ShaderStages::VERTEX,
                _ => visibility,
            },
            ty: match b.kind {
                Kind::Uniform { size, dynamic } => wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: dynamic,
                    min_binding_size: wgpu::BufferSize::new(u64::from(size)),
                },
                Kind::Storage { writable, size } => wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage {
                        read_only: !writable,
                    },
                    has_dynamic_offset: false,
                    min_binding_size: wgpu::BufferSize::new(u64::from(size)),
                },
                Kind::Texture { sample, dim } => wgpu::BindingType::Texture {
                    sample_type: match sample {
                        Sample::Float { filterable } => {
                            wgpu::TextureSampleType::Float { filterable }
                        }
                        Sample::Uint => wgpu::TextureSampleType::Uint,
                        Sample::Sint => wgpu::TextureSampleType::Sint,
                        Sample::Depth => wgpu::TextureSampleType::Depth,
                    },
                    view_dimension: view_dimension(dim),
                    multisampled: dim == Dim::D2Multisampled,
                },
                Kind::StorageTexture { format, dim } => wgpu::BindingType::StorageTexture {
                    access: wgpu::StorageTextureAccess::WriteOnly,
                    format: texture_format(format),
                    view_dimension: view_dimension(dim),
                },
                Kind::AtomicStorageTexture { format, dim } => wgpu::BindingType::StorageTexture {
                    access: wgpu::StorageTextureAccess::Atomic,
                    format: texture_format(format),
                    view_dimension: view_dimension(dim),
                },
                Kind::Sampler => wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
            },
            count: None,
        })
        .collect()
}

/// A pass's bind-group layouts and pipeline layout (cloning shares them: bind groups made
/// from one serve the pipelines of every clone).
#[derive(Clone, Debug)]
pub struct Layouts {
    pass: &'static str,
    groups: Vec<(&'static Group, wgpu::BindGroupLayout)>,
    pipeline: wgpu::PipelineLayout,
}

impl Layouts {
    /// The layouts of `pass` on `device`.
    pub fn new<P>(device: &wgpu::Device, pass: &Pass<P>) -> Self {
        let vis = visibility(pass);
        let groups: Vec<(&'static Group, wgpu::BindGroupLayout)> = pass
            .groups
            .iter()
            .map(|g| {
                let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some(&format!("{}: {}", pass.name, g.name)),
                    entries: &layout_entries(g, vis),
                });
                (g, layout)
            })
            .collect();
        let refs: Vec<Option<&wgpu::BindGroupLayout>> =
            groups.iter().map(|(_, l)| Some(l)).collect();
        let pipeline = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(pass.name),
            bind_group_layouts: &refs,
            immediate_size: 0,
        });
        Self {
            pass: pass.name,
            groups,
            pipeline,
        }
    }

    /// The pipeline layout.
    #[must_use]
    pub fn pipeline_layout(&self) -> &wgpu::PipelineLayout {
        &self.pipeline
    }

    /// The description and layout of the group named `group`.
    fn find(&self, group: &str) -> Result<&(&'static Group, wgpu::BindGroupLayout), Error> {
        self.groups
            .iter()
            .find(|(g, _)| g.name == group)
            .ok_or_else(|| Error::UnknownName {
                pass: self.pass,
                what: "group",
                name: group.into(),
            })
    }

    /// The layout of the group named `group`.
    ///
    /// # Errors
    /// [`Error::UnknownName`].
    pub fn group(&self, group: &str) -> Result<&wgpu::BindGroupLayout, Error> {
        Ok(&self.find(group)?.1)
    }

    /// A bind group of the group named `group`, each binding given by its WGSL name.
    ///
    /// # Errors
    /// An unknown group or resource name, or a binding given no resource.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        group: &str,
        resources: &[(&str, wgpu::BindingResource<'_>)],
    ) -> Result<wgpu::BindGroup, Error> {
        let (desc, layout) = self.find(group)?;
        if let Some((name, _)) = resources
            .iter()
            .find(|(n, _)| !desc.bindings.iter().any(|b| b.name == *n))
        {
            return Err(Error::UnknownName {
                pass: self.pass,
                what: "binding",
                name: (*name).into(),
            });
        }
        let entries =
            desc.bindings
                .iter()
                .enumerate()
                .map(|(i, b)| {
                    let (_, r) = resources.iter().find(|(n, _)| *n == b.name).ok_or(
                        Error::MissingResource {
                            pass: self.pass,
                            group: desc.name,
                            binding: b.name,
                        },
                    )?;
                    Ok(wgpu::BindGroupEntry {
                        binding: i as u32,
                        resource: r.clone(),
                    })
                })
                .collect::<Result<Vec<_>, Error>>()?;
        Ok(device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(&format!("{}: {}", self.pass, desc.name)),
            layout,
            entries: &entries,
        }))
    }
}

/// One compute entry point's pipeline.
#[derive(Debug)]
pub struct ComputeStep<P: 'static> {
    /// Its description.
    pub entry: &'static Entry<P>,
    /// Its pipeline.
    pub pipeline: wgpu::ComputePipeline,
}

/// A compute pass built from its description: layouts and one pipeline per entry point,
/// in order.
#[derive(Debug)]
pub struct ComputePass<P: 'static> {
    /// The description.
    pub pass: &'static Pass<P>,
    /// Its layouts.
    pub layouts: Layouts,
    /// One pipeline per entry point, in the description's order.
    pub steps: Vec<ComputeStep<P>>,
    /// The values of the `override`s that size workgroups (by the description's names).
    size_overrides: Vec<(&'static str, f64)>,
    /// The module the pipelines were made from (for [`ComputePass::variant`]).
    module: wgpu::ShaderModule,
}

/// `pass`'s WGSL composed with `features`, as a shader module.
fn module<P>(
    device: &wgpu::Device,
    pass: &'static Pass<P>,
    features: &[&str],
) -> Result<wgpu::ShaderModule, Error> {
    let source = pass.source(features)?;
    Ok(device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(pass.name),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    }))
}

impl<P> ComputePass<P> {
    /// Composes `pass` with `features`, creates its module and a pipeline per entry point
    /// with the `override` values `constants`. Device errors (validation) are wgpu's; run
    /// inside an error scope to catch them.
    ///
    /// # Errors
    /// A composition error or an undeclared feature.
    pub fn new(
        device: &wgpu::Device,
        pass: &'static Pass<P>,
        features: &[&str],
        constants: &[(&str, f64)],
    ) -> Result<Self, Error> {
        let module = module(device, pass, features)?;
        let layouts = Layouts::new(device, pass);
        let steps = pass
            .entries
            .iter()
            .filter(|e| matches!(e.stage, Stage::Compute(_)))
            .map(|entry| ComputeStep {
                entry,
                pipeline: device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(&format!("{} {}", pass.name, entry.name)),
                    layout: Some(layouts.pipeline_layout()),
                    module: &module,
                    entry_point: Some(entry.name),
                    compilation_options: wgpu::PipelineCompilationOptions {
                        constants,
                        ..Default::default()
                    },
                    cache: None,
                }),
            })
            .collect();
        let size_overrides = pass
            .entries
            .iter()
            .filter_map(|e| match e.stage {
                Stage::Compute(size) => Some(size),
                _ => None,
            })
            .flatten()
            .filter_map(|s| match s {
                Size::Override(name) => constants
                    .iter()
                    .find(|(k, _)| *k == name)
                    .map(|&(_, v)| (name, v)),
                Size::Fixed(_) => None,
            })
            .collect();
        Ok(Self {
            pass,
            layouts,
            steps,
            size_overrides,
            module,
        })
    }

    /// Another pipeline of the entry point `name`, on this pass's module and layout with
    /// the `override` values `constants` (a specialisation: the pass's bind groups serve
    /// it). `constants` must give the workgroup-size overrides the values [`ComputePass::new`]
    /// had, or the pass's dispatch sizes are wrong for it.
    ///
    /// # Errors
    /// [`Error::UnknownName`] for an entry point the pass does not have.
    pub fn variant(
        &self,
        device: &wgpu::Device,
        name: &str,
        constants: &[(&str, f64)],
    ) -> Result<wgpu::ComputePipeline, Error> {
        let entry = self.step(name)?.entry;
        Ok(
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(&format!("{} {} (variant)", self.pass.name, entry.name)),
                layout: Some(self.layouts.pipeline_layout()),
                module: &self.module,
                entry_point: Some(entry.name),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants,
                    ..Default::default()
                },
                cache: None,
            }),
        )
    }

    /// A bind group of the group named `group` (see [`Layouts::bind_group`]).
    ///
    /// # Errors
    /// An unknown group or resource name, or a binding given no resource.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        group: &str,
        resources: &[(&str, wgpu::BindingResource<'_>)],
    ) -> Result<wgpu::BindGroup, Error> {
        self.layouts.bind_group(device, group, resources)
    }

    /// The step of the entry point named `name`.
    ///
    /// # Errors
    /// [`Error::UnknownName`].
    pub fn step(&self, name: &str) -> Result<&ComputeStep<P>, Error> {
        Ok(&self.steps[self.step_index(name)?])
    }

    /// The workgroup counts of `step` with `params` (`None` for indirect entry points).
    pub fn workgroups(&self, step: &ComputeStep<P>, params: &P) -> Option<[u32; 3]> {
        step.entry.workgroups(params, &self.size_overrides)
    }

    /// The index in [`ComputePass::steps`] of the entry point named `name`.
    ///
    /// # Errors
    /// [`Error::UnknownName`].
    pub fn step_index(&self, name: &str) -> Result<usize, Error> {
        self.steps
            .iter()
            .position(|s| s.entry.name == name)
            .ok_or_else(|| Error::UnknownName {
                pass: self.pass.name,
                what: "entry point",
                name: name.into(),
            })
    }

    /// Records every directly dispatched entry point, in order, with `groups[i]` bound as
    /// group `i`. Indirect entry points are the caller's to dispatch.
    pub fn record(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        groups: &[&wgpu::BindGroup],
        params: &P,
    ) {
        for (i, g) in groups.iter().enumerate() {
            pass.set_bind_group(i as u32, *g, &[]);
        }
        for step in &self.steps {
            if let Some([x, y, z]) = self.workgroups(step, params) {
                pass.set_pipeline(&step.pipeline);
                pass.dispatch_workgroups(x, y, z);
            }
        }
    }
}

/// A render pass built from its description: its layouts and its module composed once
/// with one feature combination; [`RasterPass::pipeline`] builds a [`Raster`] description
/// of it.
#[derive(Debug)]
pub struct RasterPass<P: 'static = ()> {
    /// The description.
    pub pass: &'static Pass<P>,
    /// Its layouts.
    pub layouts: Layouts,
    module: wgpu::ShaderModule,
    constants: Vec<(String, f64)>,
}

impl<P> RasterPass<P> {
    /// Composes `pass` with `features` and creates its module and layouts; pipelines take
    /// the `override` values `constants`. Device errors (validation) are wgpu's; run inside
    /// an error scope to catch them.
    ///
    /// # Errors
    /// A composition error or an undeclared feature.
    pub fn new(
        device: &wgpu::Device,
        pass: &'static Pass<P>,
        features: &[&str],
        constants: &[(&str, f64)],
    ) -> Result<Self, Error> {
        let layouts = Layouts::new(device, pass);
        Self::with_layouts(device, pass, layouts, features, constants)
    }

    /// The same pass composed with other `features`, sharing these layouts (a bind group
    /// serves the pipelines of both): a pass's permutations.
    ///
    /// # Errors
    /// A composition error or an undeclared feature.
    pub fn variant(&self, device: &wgpu::Device, features: &[&str]) -> Result<Self, Error> {
        let constants: Vec<(&str, f64)> = self
            .constants
            .iter()
            .map(|(k, v)| (k.as_str(), *v))
            .collect();
        Self::with_layouts(
            device,
            self.pass,
            self.layouts.clone(),
            features,
            &constants,
        )
    }

    fn with_layouts(
        device: &wgpu::Device,
        pass: &'static Pass<P>,
        layouts: Layouts,
        features: &[&str],
        constants: &[(&str, f64)],
    ) -> Result<Self, Error> {
        let module = module(device, pass, features)?;
        Ok(Self {
            pass,
            layouts,
            module,
            constants: constants.iter().map(|&(k, v)| (k.into(), v)).collect(),
        })
    }

    /// The pipeline `raster` describes, over this pass's module and layouts.
    ///
    /// # Errors
    /// [`Error::UnknownName`] when `raster`'s vertex or fragment entry point is not one of
    /// the pass's entry points of that stage.
    pub fn pipeline(
        &self,
        device: &wgpu::Device,
        raster: &Raster<'_>,
    ) -> Result<wgpu::RenderPipeline, Error> {
        let stage_entry = |name: &str, stage: Stage, what: &'static str| match self.pass.entry(name)
        {
            Ok(e) if e.stage == stage => Ok(()),
            _ => Err(Error::UnknownName {
                pass: self.pass.name,
                what,
                name: name.into(),
            }),
        };
        stage_entry(raster.vertex, Stage::Vertex, "vertex entry point")?;
        if let Some(f) = raster.fragment {
            stage_entry(f, Stage::Fragment, "fragment entry point")?;
        }
        let constants: Vec<(&str, f64)> = self
            .constants
            .iter()
            .map(|(k, v)| (k.as_str(), *v))
            .collect();
        let options = || wgpu::PipelineCompilationOptions {
            constants: &constants,
            ..Default::default()
        };
        let attributes: Vec<Vec<wgpu::VertexAttribute>> = raster
            .buffers
            .iter()
            .map(|b| {
                b.attributes
                    .iter()
                    .map(|a| wgpu::VertexAttribute {
                        format: vertex_format(a.format),
                        offset: a.offset,
                        shader_location: a.location,
                    })
                    .collect()
            })
            .collect();
        let buffers: Vec<Option<wgpu::VertexBufferLayout<'_>>> = raster
            .buffers
            .iter()
            .zip(&attributes)
            .map(|(b, attributes)| {
                Some(wgpu::VertexBufferLayout {
                    array_stride: b.stride,
                    step_mode: if b.per_instance {
                        wgpu::VertexStepMode::Instance
                    } else {
                        wgpu::VertexStepMode::Vertex
                    },
                    attributes,
                })
            })
            .collect();
        let targets: Vec<Option<wgpu::ColorTargetState>> = raster
            .targets
            .iter()
            .map(|t| {
                Some(wgpu::ColorTargetState {
                    format: texture_format(t.format),
                    blend: t.blend.map(blend),
                    write_mask: wgpu::ColorWrites::from_bits_truncate(u32::from(t.write_mask)),
                })
            })
            .collect();
        Ok(
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(raster.name),
                layout: Some(self.layouts.pipeline_layout()),
                vertex: wgpu::VertexState {
                    module: &self.module,
                    entry_point: Some(raster.vertex),
                    compilation_options: options(),
                    buffers: &buffers,
                },
                primitive: wgpu::PrimitiveState {
                    topology: match raster.primitive.topology {
                        Topology::TriangleList => wgpu::PrimitiveTopology::TriangleList,
                        Topology::TriangleStrip => wgpu::PrimitiveTopology::TriangleStrip,
                        Topology::LineList => wgpu::PrimitiveTopology::LineList,
                        Topology::LineStrip => wgpu::PrimitiveTopology::LineStrip,
                        Topology::PointList => wgpu::PrimitiveTopology::PointList,
                    },
                    strip_index_format: None,
                    front_face: match raster.primitive.front_face {
                        FrontFace::Ccw => wgpu::FrontFace::Ccw,
                        FrontFace::Cw => wgpu::FrontFace::Cw,
                    },
                    cull_mode: raster.primitive.cull.map(|f| match f {
                        Face::Front => wgpu::Face::Front,
                        Face::Back => wgpu::Face::Back,
                    }),
                    unclipped_depth: false,
                    polygon_mode: wgpu::PolygonMode::Fill,
                    conservative: false,
                },
                depth_stencil: raster.depth.map(depth_stencil),
                multisample: wgpu::MultisampleState {
                    count: raster.samples,
                    ..Default::default()
                },
                fragment: raster.fragment.map(|entry| wgpu::FragmentState {
                    module: &self.module,
                    entry_point: Some(entry),
                    compilation_options: options(),
                    targets: &targets,
                }),
                multiview_mask: None,
                cache: None,
            }),
        )
    }

    /// A bind group of the group named `group` (see [`Layouts::bind_group`]).
    ///
    /// # Errors
    /// An unknown group or resource name, or a binding given no resource.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        group: &str,
        resources: &[(&str, wgpu::BindingResource<'_>)],
    ) -> Result<wgpu::BindGroup, Error> {
        self.layouts.bind_group(device, group, resources)
    }
}

/// wgpu's texture format for a depth(-stencil) format.
#[must_use]
pub fn depth_format(f: DepthFormat) -> wgpu::TextureFormat {
    match f {
        DepthFormat::Depth32Float => wgpu::TextureFormat::Depth32Float,
        DepthFormat::Depth32FloatStencil8 => wgpu::TextureFormat::Depth32FloatStencil8,
        DepthFormat::Depth24PlusStencil8 => wgpu::TextureFormat::Depth24PlusStencil8,
    }
}

/// wgpu's comparison function for `c`.
#[must_use]
pub fn compare(c: Compare) -> wgpu::CompareFunction {
    match c {
        Compare::Never => wgpu::CompareFunction::Never,
        Compare::Less => wgpu::CompareFunction::Less,
        Compare::Equal => wgpu::CompareFunction::Equal,
        Compare::LessEqual => wgpu::CompareFunction::LessEqual,
        Compare::Greater => wgpu::CompareFunction::Greater,
        Compare::NotEqual => wgpu::CompareFunction::NotEqual,
        Compare::GreaterEqual => wgpu::CompareFunction::GreaterEqual,
        Compare::Always => wgpu::CompareFunction::Always,
    }
}

/// wgpu's depth-stencil state for `d`.
#[must_use]
pub fn depth_stencil(d: Depth) -> wgpu::DepthStencilState {
    let face = |f: StencilFace| wgpu::StencilFaceState {
        compare: compare(f.compare),
        fail_op: stencil_op(f.fail),
        depth_fail_op: stencil_op(f.depth_fail),
        pass_op: stencil_op(f.pass),
    };
    let Stencil {
        front,
        back,
        read_mask,
        write_mask,
    } = d.stencil;
    wgpu::DepthStencilState {
        format: depth_format(d.format),
        depth_write_enabled: Some(d.write),
        depth_compare: Some(compare(d.compare)),
        stencil: wgpu::StencilState {
            front: face(front),
            back: face(back),
            read_mask,
            write_mask,
        },
        bias: wgpu::DepthBiasState {
            constant: d.bias.constant,
            slope_scale: d.bias.slope_scale,
            clamp: d.bias.clamp,
        },
    }
}

fn stencil_op(op: StencilOp) -> wgpu::StencilOperation {
    match op {
        StencilOp::Keep => wgpu::StencilOperation::Keep,
        StencilOp::Zero => wgpu::StencilOperation::Zero,
        StencilOp::Replace => wgpu::StencilOperation::Replace,
        StencilOp::Invert => wgpu::StencilOperation::Invert,
        StencilOp::IncrementClamp => wgpu::StencilOperation::IncrementClamp,
        StencilOp::DecrementClamp => wgpu::StencilOperation::DecrementClamp,
        StencilOp::IncrementWrap => wgpu::StencilOperation::IncrementWrap,
        StencilOp::DecrementWrap => wgpu::StencilOperation::DecrementWrap,
    }
}

fn blend(b: Blend) -> wgpu::BlendState {
    let factor = |f: BlendFactor| match f {
        BlendFactor::Zero => wgpu::BlendFactor::Zero,
        BlendFactor::One => wgpu::BlendFactor::One,
        BlendFactor::Src => wgpu::BlendFactor::Src,
        BlendFactor::OneMinusSrc => wgpu::BlendFactor::OneMinusSrc,
        BlendFactor::SrcAlpha => wgpu::BlendFactor::SrcAlpha,
        BlendFactor::OneMinusSrcAlpha => wgpu::BlendFactor::OneMinusSrcAlpha,
        BlendFactor::Dst => wgpu::BlendFactor::Dst,
        BlendFactor::OneMinusDst => wgpu::BlendFactor::OneMinusDst,
        BlendFactor::DstAlpha => wgpu::BlendFactor::DstAlpha,
        BlendFactor::OneMinusDstAlpha => wgpu::BlendFactor::OneMinusDstAlpha,
    };
    let component = |c: BlendComponent| wgpu::BlendComponent {
        src_factor: factor(c.src),
        dst_factor: factor(c.dst),
        operation: match c.op {
            BlendOp::Add => wgpu::BlendOperation::Add,
            BlendOp::Subtract => wgpu::BlendOperation::Subtract,
            BlendOp::ReverseSubtract => wgpu::BlendOperation::ReverseSubtract,
            BlendOp::Min => wgpu::BlendOperation::Min,
            BlendOp::Max => wgpu::BlendOperation::Max,
        },
    };
    wgpu::BlendState {
        color: component(b.color),
        alpha: component(b.alpha),
    }
}

fn vertex_format(f: VertexFormat) -> wgpu::VertexFormat {
    match f {
        VertexFormat::Float32 => wgpu::VertexFormat::Float32,
        VertexFormat::Float32x2 => wgpu::VertexFormat::Float32x2,
        VertexFormat::Float32x3 => wgpu::VertexFormat::Float32x3,
        VertexFormat::Float32x4 => wgpu::VertexFormat::Float32x4,
        VertexFormat::Uint32 => wgpu::VertexFormat::Uint32,
        VertexFormat::Uint32x2 => wgpu::VertexFormat::Uint32x2,
        VertexFormat::Uint32x4 => wgpu::VertexFormat::Uint32x4,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raster::{Bias, Target};

    /// The conversions keep every field: the light volumes' shading state and a shadow
    /// bias, spelled in wgpu by hand.
    #[test]
    fn depth_and_blend_convert_field_by_field() {
        let shade = crate::raster::tests::SHADE.depth.unwrap();
        let face = wgpu::StencilFaceState {
            compare: wgpu::CompareFunction::Equal,
            fail_op: wgpu::StencilOperation::Keep,
            depth_fail_op: wgpu::StencilOperation::Zero,
            pass_op: wgpu::StencilOperation::Zero,
        };
        assert_eq!(
            depth_stencil(shade),
            wgpu::DepthStencilState {
                format: wgpu::TextureFormat::Depth24PlusStencil8,
                depth_write_enabled: Some(false),
                depth_compare: Some(wgpu::CompareFunction::GreaterEqual),
                stencil: wgpu::StencilState {
                    front: face,
                    back: face,
                    read_mask: 0xff,
                    write_mask: 0xff,
                },
                bias: wgpu::DepthBiasState::default(),
            }
        );
        let bias = Bias {
            constant: 2,
            slope_scale: 2.0,
            clamp: 0.0,
        };
        let shadow = depth_stencil(Depth::shadow(DepthFormat::Depth32Float, bias));
        assert_eq!(shadow.stencil, wgpu::StencilState::default());
        assert_eq!(shadow.depth_compare, Some(wgpu::CompareFunction::Less));
        assert_eq!(
            shadow.bias,
            wgpu::DepthBiasState {
                constant: 2,
                slope_scale: 2.0,
                clamp: 0.0,
            }
        );
        assert_eq!(
            blend(Blend::ADDITIVE),
            wgpu::BlendState {
                color: wgpu::BlendComponent {
                    src_factor: wgpu::BlendFactor::One,
                    dst_factor: wgpu::BlendFactor::One,
                    operation: wgpu::BlendOperation::Add,
                },
                alpha: wgpu::BlendComponent {
                    src_factor: wgpu::BlendFactor::One,
                    dst_factor: wgpu::BlendFactor::One,
                    operation: wgpu::BlendOperation::Add,
                },
            }
        );
        assert_eq!(
            wgpu::ColorWrites::from_bits_truncate(u32::from(Target::WRITE_ALL)),
            wgpu::ColorWrites::ALL
        );
    }
}
