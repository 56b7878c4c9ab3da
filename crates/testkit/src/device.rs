//! The one headless device of a test binary, and everything the GPU tests run through it.

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::OnceLock;

use gpu::inspect::{diff_image, diff_metrics};
use gpu::{GpuContext, HeadlessOptions, Rgba8Image};
use shader::pipeline::ComputePass;
use shader::{Kind, Pass};

/// The device every GPU test of this test binary uses: the high-performance adapter, else
/// any (lavapipe in CI), with every optional feature it has. A machine without a Vulkan
/// driver fails here, with the command that installs one.
pub fn ctx() -> &'static GpuContext {
    static CTX: OnceLock<GpuContext> = OnceLock::new();
    CTX.get_or_init(|| {
        let c = gpu::headless(&HeadlessOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        eprintln!("test device: {}", c.adapter_line());
        c
    })
}

/// Whether the test device has subgroup operations (`Features::SUBGROUP`).
pub fn has_subgroups() -> bool {
    ctx().device.features().contains(wgpu::Features::SUBGROUP)
}

/// The feature sets a test of a pass with a `subgroups` variant runs: both where the device
/// has subgroups, the fallback alone otherwise (said on stderr, never silently).
pub fn subgroup_variants() -> Vec<&'static [&'static str]> {
    if has_subgroups() {
        vec![&["subgroups"], &[]]
    } else {
        eprintln!(
            "{} has no subgroups: the workgroup fallback only",
            ctx().adapter_line()
        );
        vec![&[]]
    }
}

/// Runs `f` in validation and out-of-memory error scopes, panicking with what they caught
/// and `what` (a kernel's source, a pass's name).
fn scoped<T>(what: &str, f: impl FnOnce() -> T) -> T {
    let device = &ctx().device;
    let out = gpu::inspect::scoped(device, || Ok(f()))
        .unwrap_or_else(|e| panic!("{e}\n--- in ---\n{what}"));
    gpu::inspect::wait_idle(device).unwrap_or_else(|e| panic!("{e}"));
    out
}

fn buffer(bytes: &[u8], min: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
    let c = ctx();
    let size = (bytes.len() as u64).max(min).max(4).next_multiple_of(4);
    let b = c.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("test buffer"),
        size,
        usage: usage | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    if !bytes.is_empty() {
        let mut padded = bytes.to_vec();
        padded.resize(bytes.len().next_multiple_of(4), 0);
        c.queue.write_buffer(&b, 0, &padded);
    }
    b
}

/// The whole of `b` (which needs `COPY_SRC`), after the GPU finished its work.
pub fn read_bytes(b: &wgpu::Buffer) -> Vec<u8> {
    let c = ctx();
    gpu::inspect::read_buffer(&c.device, &c.queue, b, 0, b.size()).unwrap_or_else(|e| panic!("{e}"))
}

/// What a test puts in one buffer binding of a described pass.
#[derive(Clone, Copy, Debug)]
pub enum Data<'a> {
    /// These words.
    Words(&'a [u32]),
    /// These bytes (a uniform struct, Pod rows).
    Bytes(&'a [u8]),
    /// This many zero words.
    Zeros(usize),
}

impl<'a> Data<'a> {
    /// Pod rows.
    pub fn rows<T: bytemuck::Pod>(rows: &'a [T]) -> Self {
        Data::Bytes(bytemuck::cast_slice(rows))
    }
}

/// The buffers of a pass after it ran, by binding name.
pub struct PassBuffers {
    pass: &'static str,
    buffers: BTreeMap<&'static str, wgpu::Buffer>,
}

impl PassBuffers {
    /// The first `len` elements of the binding named `name`.
    pub fn read<T: bytemuck::Pod>(&self, name: &str, len: usize) -> Vec<T> {
        let b = self
            .buffers
            .get(name)
            .unwrap_or_else(|| panic!("pass `{}` has no buffer `{name}`", self.pass));
        let bytes = read_bytes(b);
        let n = len * size_of::<T>();
        assert!(
            n <= bytes.len(),
            "`{name}` holds {} bytes, {n} asked for",
            bytes.len()
        );
        bytemuck::pod_collect_to_vec(&bytes[..n])
    }
}

/// Runs every directly dispatched entry point of `pass`, in order, with `features` and the
/// `override` values `constants`, dispatched from `params` as the description says. Every
/// buffer binding of every group is given by name in `data` (uniforms from
/// [`Data::Bytes`]); a missing one is a panic naming it. Returns the buffers to read.
pub fn run_pass<P>(
    pass: &'static Pass<P>,
    features: &[&str],
    constants: &[(&str, f64)],
    params: &P,
    data: &[(&str, Data<'_>)],
) -> PassBuffers {
    let c = ctx();
    let what = format!("pass `{}` with {features:?} {constants:?}", pass.name);
    scoped(&what, || {
        let compute = ComputePass::new(&c.device, pass, features, constants)
            .unwrap_or_else(|e| panic!("{e}"));
        let mut buffers = BTreeMap::new();
        let mut groups = Vec::new();
        for g in pass.groups {
            let mut resources = Vec::new();
            for b in g.bindings {
                let (bytes, zeros): (&[u8], usize) =
                    match data.iter().find(|(n, _)| *n == b.name).map(|(_, d)| *d) {
                        Some(Data::Words(w)) => (bytemuck::cast_slice(w), 0),
                        Some(Data::Bytes(bytes)) => (bytes, 0),
                        Some(Data::Zeros(n)) => (&[], n * 4),
                        None => panic!("{what}: no data for binding `{}`", b.name),
                    };
                let usage = match b.kind {
                    Kind::Uniform { .. } => wgpu::BufferUsages::UNIFORM,
                    Kind::Storage { .. } => {
                        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT
                    }
                    other => panic!("{what}: `{}` is {other:?}, not a buffer", b.name),
                };
                let min = u64::from(b.kind.buffer_size().unwrap_or(4)).max(zeros as u64);
                buffers.insert(b.name, buffer(bytes, min, usage));
            }
            for b in g.bindings {
                resources.push((b.name, buffers[b.name].as_entire_binding()));
            }
            groups.push(
                compute
                    .bind_group(&c.device, g.name, &resources)
                    .unwrap_or_else(|e| panic!("{e}")),
            );
        }
        let refs: Vec<&wgpu::BindGroup> = groups.iter().collect();
        let mut encoder = c.device.create_command_encoder(&Default::default());
        {
            let mut cpass = encoder.begin_compute_pass(&Default::default());
            compute.record(&mut cpass, &refs, params);
        }
        c.queue.submit([encoder.finish()]);
        PassBuffers {
            pass: pass.name,
            buffers,
        }
    })
}

/// One binding of an ad-hoc kernel, in binding order from 0 of group 0.
#[derive(Clone, Copy, Debug)]
pub enum Resource<'a> {
    /// A storage buffer holding these words (read back after the run).
    Words(&'a [u32]),
    /// A zeroed storage buffer of this many words (read back after the run).
    Zeros(usize),
    /// A uniform buffer holding these bytes.
    Uniform(&'a [u8]),
    /// A 2D texture of `format`, `width` x `height` texels, tightly packed rows.
    Texture {
        /// Texel format.
        format: wgpu::TextureFormat,
        /// Width in texels.
        width: u32,
        /// Height in texels.
        height: u32,
        /// The texels.
        texels: &'a [u8],
    },
    /// A repeating sampler with linear filtering.
    LinearSampler,
}

/// Runs entry point `entry` of `source` (plain WGSL, composed already) over `workgroups`
/// with `resources` at bindings 0.. of group 0, and returns every storage buffer read back
/// after the run, in binding order. The pipeline layout is derived from the shader, so
/// every binding must be used by the entry point.
pub fn run_kernel(
    source: &str,
    entry: &str,
    resources: &[Resource<'_>],
    workgroups: [u32; 3],
) -> Vec<Vec<u32>> {
    let c = ctx();
    let d = &c.device;
    let buffers = scoped(source, || {
        let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("test kernel"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let pipeline = d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("test kernel"),
            layout: None,
            module: &module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        });
        enum Held {
            Buffer(wgpu::Buffer, bool),
            View(wgpu::TextureView),
            Sampler(wgpu::Sampler),
        }
        let held: Vec<Held> = resources
            .iter()
            .map(|r| match *r {
                Resource::Words(w) => Held::Buffer(
                    buffer(bytemuck::cast_slice(w), 4, wgpu::BufferUsages::STORAGE),
                    true,
                ),
                Resource::Zeros(n) => {
                    Held::Buffer(buffer(&[], n as u64 * 4, wgpu::BufferUsages::STORAGE), true)
                }
                Resource::Uniform(bytes) => {
                    Held::Buffer(buffer(bytes, 16, wgpu::BufferUsages::UNIFORM), false)
                }
                Resource::Texture {
                    format,
                    width,
                    height,
                    texels,
                } => {
                    let size = wgpu::Extent3d {
                        width,
                        height,
                        depth_or_array_layers: 1,
                    };
                    let t = d.create_texture(&wgpu::TextureDescriptor {
                        label: Some("test texture"),
                        size,
                        mip_level_count: 1,
                        sample_count: 1,
                        dimension: wgpu::TextureDimension::D2,
                        format,
                        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                        view_formats: &[],
                    });
                    let texel = format.block_copy_size(None).unwrap_or(4);
                    c.queue.write_texture(
                        t.as_image_copy(),
                        texels,
                        wgpu::TexelCopyBufferLayout {
                            offset: 0,
                            bytes_per_row: Some(width * texel),
                            rows_per_image: Some(height),
                        },
                        size,
                    );
                    Held::View(t.create_view(&Default::default()))
                }
                Resource::LinearSampler => {
                    Held::Sampler(d.create_sampler(&wgpu::SamplerDescriptor {
                        address_mode_u: wgpu::AddressMode::Repeat,
                        address_mode_v: wgpu::AddressMode::Repeat,
                        mag_filter: wgpu::FilterMode::Linear,
                        min_filter: wgpu::FilterMode::Linear,
                        ..Default::default()
                    }))
                }
            })
            .collect();
        let entries: Vec<wgpu::BindGroupEntry<'_>> = held
            .iter()
            .enumerate()
            .map(|(i, h)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: match h {
                    Held::Buffer(b, _) => b.as_entire_binding(),
                    Held::View(v) => wgpu::BindingResource::TextureView(v),
                    Held::Sampler(s) => wgpu::BindingResource::Sampler(s),
                },
            })
            .collect();
        let bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("test kernel"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        let mut encoder = d.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups(workgroups[0], workgroups[1], workgroups[2]);
        }
        c.queue.submit([encoder.finish()]);
        held.into_iter()
            .filter_map(|h| match h {
                Held::Buffer(b, true) => Some(b),
                _ => None,
            })
            .collect::<Vec<_>>()
    });
    buffers
        .iter()
        .map(|b| bytemuck::pod_collect_to_vec(&read_bytes(b)))
        .collect()
}

/// Runs `body` once per item `i` in `0..items` with `input: array<u32>` at binding 0 and
/// `output: array<u32>` (`items * out_stride` zeroed words) at binding 1; `prelude` comes
/// first (its `#import` lines are resolved from `library`, and it may declare `extra`
/// bindings from 2 on). Returns `output`. How a crate's WGSL functions are checked
/// against their CPU twins.
pub fn run_words(
    library: &[&[shader::Module]],
    prelude: &str,
    body: &str,
    input: &[u32],
    items: u32,
    out_stride: usize,
    extra: &[Resource<'_>],
) -> Vec<u32> {
    let groups = items.div_ceil(64);
    let rows = groups.div_ceil(shader::MAX_WORKGROUPS_X).max(1);
    let source = format!(
        "{prelude}
@group(0) @binding(0) var<storage, read> input: array<u32>;
@group(0) @binding(1) var<storage, read_write> output: array<u32>;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {{
    let i = gid.y * {stride}u + gid.x;
    if i >= {items}u {{ return; }}
    {body}
}}",
        stride = shader::MAX_WORKGROUPS_X * 64,
    );
    let source = shader::compose_source(library, "test kernel", &source, &[])
        .unwrap_or_else(|e| panic!("{e}"));
    let mut resources = vec![
        Resource::Words(input),
        Resource::Zeros(items as usize * out_stride),
    ];
    resources.extend_from_slice(extra);
    let x = groups.clamp(1, shader::MAX_WORKGROUPS_X);
    run_kernel(&source, "main", &resources, [x, rows, 1]).swap_remove(1)
}

/// Bounds of a golden-image comparison: mean absolute RGB error (0-255) and the largest
/// per-pixel error at the 99th percentile.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GoldenBounds {
    /// Largest mean absolute error.
    pub mean: f64,
    /// Largest 99th-percentile error.
    pub p99: u8,
}

impl GoldenBounds {
    /// The bounds for golden images blessed on llvmpipe (the CI driver): tight on a CPU
    /// adapter. Other drivers rasterise alpha-tested foliage edges and filter textures
    /// differently; on the H100 (NVIDIA 580.159.04, Vulkan) the forest measured mean 1.456
    /// and p99 53, so other adapters get looser bounds.
    pub fn blessed_on_llvmpipe() -> Self {
        if ctx().info.device_type == wgpu::DeviceType::Cpu {
            GoldenBounds { mean: 0.5, p99: 16 }
        } else {
            GoldenBounds { mean: 3.0, p99: 96 }
        }
    }
}

/// Compares `image` with the PNG at `file`. With `GPU_BLESS=1` in the environment it
/// writes `image` there instead (commit it, naming the adapter that made it). On a
/// mismatch it writes `<file>-actual.png` and `<file>-diff.png` beside it and panics with
/// the figures and the adapter.
pub fn check_golden(file: &Path, image: &Rgba8Image, bounds: GoldenBounds) {
    if std::env::var("GPU_BLESS").as_deref() == Ok("1") {
        image.write_png(file).unwrap_or_else(|e| panic!("{e}"));
        eprintln!("blessed {} on {}", file.display(), ctx().adapter_line());
        return;
    }
    let golden = Rgba8Image::read_png(file).unwrap_or_else(|e| {
        panic!(
            "{}: {e}; run with GPU_BLESS=1 to write it from this device",
            file.display()
        )
    });
    let metrics = diff_metrics(image, &golden, 0.5).zip(diff_metrics(image, &golden, 0.99));
    let Some(((mean, _), (_, p99))) = metrics else {
        panic!(
            "{}: {}x{} against a {}x{} golden image",
            file.display(),
            image.width,
            image.height,
            golden.width,
            golden.height
        );
    };
    if mean > bounds.mean || p99 > bounds.p99 {
        let stem = file.with_extension("");
        let actual = stem.with_file_name(format!(
            "{}-actual.png",
            stem.file_name().and_then(|s| s.to_str()).unwrap_or("image")
        ));
        let diff = actual.with_file_name(actual.to_string_lossy().replace("-actual", "-diff"));
        image.write_png(&actual).ok();
        diff_image(image, &golden).write_png(&diff).ok();
        panic!(
            "{} on {}: mean {mean:.3} (max {}), p99 {p99} (max {}); wrote {} and {}; \
             if the change is intended, GPU_BLESS=1 rewrites the golden image",
            file.display(),
            ctx().adapter_line(),
            bounds.mean,
            bounds.p99,
            actual.display(),
            diff.display()
        );
    }
    eprintln!("{}: golden mean {mean:.3}, p99 {p99}", file.display());
}
