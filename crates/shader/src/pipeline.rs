//! The wgpu side of a [`Pass`]: layouts from its groups, pipelines from its composed
//! module, bind groups by binding name, and dispatches from its geometry. The renderer and
//! the device tests both go through here, so a pass is bound and run one way.

use std::format;
use std::vec::Vec;

use crate::compose::Error;
use crate::pass::{Dim, Entry, Format, Group, Kind, Pass, Sample, Size, Stage};

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

/// A pass's bind-group layouts and pipeline layout.
#[derive(Debug)]
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
        let source = pass.source(features)?;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(pass.name),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
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
        })
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
