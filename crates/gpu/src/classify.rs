//! GPU classification of the laid-down vis buffer: `tiling`'s three phases (seed 000:
//! laydown finalise, mid classify, classify output) run as compute passes with the WGSL
//! modules of [`tiling::wgsl`], over buffers this module sizes for the worst case of a
//! frame, plus the read-back that lets a test compare them with the CPU twin.
//!
//! Buffer sizes, per prepared scene, for a `width x height` image, `T` 128x128 tiles, `P`
//! passes and `G` batch groups over all passes: masks and counter offsets `T * P` words;
//! counters at most `T * G` (a counter is a (tile, pass, group) triple with pixels);
//! pixel commands at most `width * height` (two per word); wave commands at most
//! `counters + width * height / wave width`. Nothing is sized from a CPU classification.

use tiling::{
    Classification, ClassifyConfig, MicroBatchInfo, PassDispatch, PixelStats, Totals, WaveCommand,
    canonical_sort,
};
use visbuf::VisLayout;

use crate::binding;
use crate::error::Result;
use crate::readback::read_buffer;
use crate::timing::GpuTimer;
use crate::upload::storage_buffer;

/// Workgroup size of the zero fill.
const ZERO_WORKGROUP: u32 = 256;

const COPY_VIS_WGSL: &str = r"
@group(0) @binding(0) var vis_texture: texture_2d<u32>;
@group(0) @binding(1) var<storage, read_write> vis_words: array<u32>;

// The R32Uint colour target into the row-major word buffer the classification reads
// (wgpu cannot view a texture as a buffer).
@compute @workgroup_size(16, 16)
fn copy_vis(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(vis_texture);
    if id.x < size.x && id.y < size.y {
        vis_words[id.y * size.x + id.x] = textureLoad(vis_texture, vec2<i32>(id.xy), 0).x;
    }
}
";

const ZERO_WGSL: &str = r"
@group(0) @binding(0) var<storage, read_write> words: array<u32>;

// Zeroes the bound buffer; 256 words per workgroup, rows of 65535 workgroups.
@compute @workgroup_size(256)
fn zero(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.y * 65535u * 256u + id.x;
    if i < arrayLength(&words) {
        words[i] = 0u;
    }
}
";

/// The classification pipelines of a renderer (one per entry point).
pub(crate) struct ClassifyPipelines {
    copy_layout: wgpu::BindGroupLayout,
    copy: wgpu::ComputePipeline,
    zero_layout: wgpu::BindGroupLayout,
    zero: wgpu::ComputePipeline,
    phase1_layout: wgpu::BindGroupLayout,
    laydown_finalize: wgpu::ComputePipeline,
    phase2_layout: wgpu::BindGroupLayout,
    counter_offsets: wgpu::ComputePipeline,
    count_pixels: wgpu::ComputePipeline,
    pixel_offsets: wgpu::ComputePipeline,
    phase3_layout: wgpu::BindGroupLayout,
    write_commands: wgpu::ComputePipeline,
    wave_offsets: wgpu::ComputePipeline,
    write_waves: wgpu::ComputePipeline,
}

/// Binding kinds of the tiling modules, in binding order from 0.
#[derive(Clone, Copy)]
enum Kind {
    Uniform,
    Read,
    Write,
}

fn entries(kinds: &[Kind]) -> Vec<wgpu::BindGroupLayoutEntry> {
    let c = wgpu::ShaderStages::COMPUTE;
    kinds
        .iter()
        .enumerate()
        .map(|(i, k)| match k {
            Kind::Uniform => binding::uniform(i as u32, c),
            Kind::Read => binding::storage(i as u32, c, true),
            Kind::Write => binding::storage(i as u32, c, false),
        })
        .collect()
}

use Kind::{Read as R, Uniform as U, Write as W};
const PHASE1: [Kind; 5] = [U, R, R, R, W];
const PHASE2: [Kind; 12] = [U, R, R, R, R, W, W, W, W, R, W, W];
const PHASE3: [Kind; 15] = [U, R, R, R, R, R, R, R, W, W, W, W, W, W, W];

struct Module<'a> {
    device: &'a wgpu::Device,
    layout: wgpu::PipelineLayout,
    module: wgpu::ShaderModule,
    label: &'static str,
}

impl Module<'_> {
    fn pipeline(&self, entry: &str) -> wgpu::ComputePipeline {
        binding::compute_pipeline(
            self.device,
            &format!("{} {entry}", self.label),
            &self.layout,
            &self.module,
            entry,
            &[],
        )
    }
}

fn module<'a>(
    device: &'a wgpu::Device,
    label: &'static str,
    source: &str,
    group: &wgpu::BindGroupLayout,
) -> Module<'a> {
    Module {
        device,
        layout: binding::pipeline_layout(device, label, &[group]),
        module: binding::module(device, label, source),
        label,
    }
}

impl ClassifyPipelines {
    /// Creates the pipelines; `subgroups` picks `wave`'s subgroup appends (the device must
    /// have `Features::SUBGROUP`) over the workgroup fallback.
    pub(crate) fn new(device: &wgpu::Device, subgroups: bool) -> Self {
        let c = wgpu::ShaderStages::COMPUTE;
        let copy_layout = binding::layout(
            device,
            "copy vis",
            &[
                binding::texture(
                    0,
                    c,
                    wgpu::TextureSampleType::Uint,
                    wgpu::TextureViewDimension::D2,
                ),
                binding::storage(1, c, false),
            ],
        );
        let copy = module(device, "copy vis", COPY_VIS_WGSL, &copy_layout).pipeline("copy_vis");
        let zero_layout = binding::layout(device, "zero", &[binding::storage(0, c, false)]);
        let zero = module(device, "zero", ZERO_WGSL, &zero_layout).pipeline("zero");
        let phase1_layout = binding::layout(device, "laydown finalize", &entries(&PHASE1));
        let features: &[&str] = if subgroups { &["subgroups"] } else { &[] };
        let source = |p: &shader::Pass<tiling::TilingParams>, f: &[&str]| {
            p.source(f).expect("tiling's passes compose (checked by its unit tests)")
        };
        let laydown_finalize = module(
            device,
            "laydown finalize",
            &source(&tiling::wgsl::LAYDOWN_FINALIZE, &[]),
            &phase1_layout,
        )
        .pipeline("laydown_finalize");
        let phase2_layout = binding::layout(device, "mid classify", &entries(&PHASE2));
        let mid = module(
            device,
            "mid classify",
            &source(&tiling::wgsl::MID_CLASSIFY, features),
            &phase2_layout,
        );
        let phase3_layout = binding::layout(device, "classify output", &entries(&PHASE3));
        let out = module(
            device,
            "classify output",
            &source(&tiling::wgsl::CLASSIFY_OUTPUT, features),
            &phase3_layout,
        );
        Self {
            copy_layout,
            copy,
            zero_layout,
            zero,
            phase1_layout,
            laydown_finalize,
            counter_offsets: mid.pipeline("counter_offsets_pass"),
            count_pixels: mid.pipeline("count_pixels"),
            pixel_offsets: mid.pipeline("pixel_offsets_pass"),
            phase2_layout,
            write_commands: out.pipeline("write_commands"),
            wave_offsets: out.pipeline("wave_offsets_pass"),
            write_waves: out.pipeline("write_waves"),
            phase3_layout,
        }
    }
}

impl ClassifyPipelines {
    /// Rebuilds the phase 2 and 3 pipelines from other sources with the same bindings
    /// (timing experiments; the layouts, and so every prepared scene's bind groups, stay).
    pub(crate) fn rebuild(&mut self, device: &wgpu::Device, mid: &str, output: &str) {
        let m = module(device, "mid classify (variant)", mid, &self.phase2_layout);
        self.counter_offsets = m.pipeline("counter_offsets_pass");
        self.count_pixels = m.pipeline("count_pixels");
        self.pixel_offsets = m.pipeline("pixel_offsets_pass");
        let o = module(
            device,
            "classify output (variant)",
            output,
            &self.phase3_layout,
        );
        self.write_commands = o.pipeline("write_commands");
        self.wave_offsets = o.pipeline("wave_offsets_pass");
        self.write_waves = o.pipeline("write_waves");
    }
}

/// Worst-case sizes of a frame's classification buffers (elements, see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ClassifySizes {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// 128x128 tiles.
    pub tiles: u32,
    /// Passes (at least 1).
    pub passes: u32,
    /// Most counters.
    pub max_counters: u32,
    /// Most pixel commands.
    pub max_commands: u32,
    /// Most wave commands.
    pub max_waves: u32,
    /// Entries of the vertex cull buffer.
    pub chunk_count: u32,
}

impl ClassifySizes {
    /// The sizes for a plan whose passes hold `batch_groups` groups in all.
    pub fn new(width: u32, height: u32, config: &ClassifyConfig, batch_groups: u32) -> Self {
        let tiles = width.div_ceil(tiling::TILE_SIZE) * height.div_ceil(tiling::TILE_SIZE);
        let pixels = width * height;
        let max_counters = tiles * batch_groups.max(1);
        Self {
            width,
            height,
            tiles,
            passes: config.pass_count.max(1),
            max_counters,
            max_commands: pixels,
            max_waves: max_counters + pixels.div_ceil(config.wave_width.lanes()),
            chunk_count: config.chunk_count,
        }
    }
}

/// A frame's classification buffers and bind groups.
pub struct ClassifyBuffers {
    /// The sizes they were made for.
    pub sizes: ClassifySizes,
    /// The configuration (pass count, wave width, chunk count).
    pub config: ClassifyConfig,
    pub(crate) layout: VisLayout,
    pub(crate) vis_words: wgpu::Buffer,
    pub(crate) masks: wgpu::Buffer,
    pub(crate) counter_offsets: wgpu::Buffer,
    pub(crate) counts: wgpu::Buffer,
    pub(crate) pixel_offsets: wgpu::Buffer,
    pub(crate) vertex_cull: wgpu::Buffer,
    pub(crate) totals: wgpu::Buffer,
    pub(crate) stats_mid: wgpu::Buffer,
    pub(crate) final_counts: wgpu::Buffer,
    pub(crate) commands: wgpu::Buffer,
    pub(crate) wave_offsets: wgpu::Buffer,
    pub(crate) waves: wgpu::Buffer,
    pub(crate) pass_dispatch: wgpu::Buffer,
    pub(crate) stats_out: wgpu::Buffer,
    _params: wgpu::Buffer,
    _valid: wgpu::Buffer,
    _table: wgpu::Buffer,
    copy_group: wgpu::BindGroup,
    zero_groups: Vec<(wgpu::BindGroup, u32)>,
    phase1_group: wgpu::BindGroup,
    phase2_group: wgpu::BindGroup,
    phase3_group: wgpu::BindGroup,
}

/// Words (`u32`) that `n` elements of `T` take.
fn words_of<T>(n: u32) -> u32 {
    const { assert!(size_of::<T>().is_multiple_of(4)) };
    n * (size_of::<T>() / 4) as u32
}

fn zeroed(
    device: &wgpu::Device,
    label: &str,
    words: u32,
    extra: wgpu::BufferUsages,
) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: u64::from(words.max(1)) * 4,
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC
            | extra,
        mapped_at_creation: false,
    })
}

impl ClassifyBuffers {
    /// Creates the buffers for `table` (the MicroBatchInfoTable), reading the laid-down
    /// vis buffer from `vis_view` and triangle indices from `indices`.
    #[allow(
        clippy::too_many_arguments,
        reason = "one call site, every argument distinct"
    )]
    pub(crate) fn new(
        device: &wgpu::Device,
        pipelines: &ClassifyPipelines,
        sizes: ClassifySizes,
        config: ClassifyConfig,
        table: &[MicroBatchInfo],
        micro_batch_count: u32,
        vis_view: &wgpu::TextureView,
        indices: &wgpu::Buffer,
    ) -> Self {
        let layout = VisLayout::Standard;
        let params = tiling::TilingParams {
            width: sizes.width,
            height: sizes.height,
            tiles_x: sizes.width.div_ceil(tiling::TILE_SIZE),
            tiles_y: sizes.height.div_ceil(tiling::TILE_SIZE),
            pass_count: sizes.passes,
            wave_width: config.wave_width.lanes(),
            flags: 0,
            table_len: table.len() as u32,
            micro_batch_count,
            chunk_count: config.chunk_count,
            uber_count: config.chunk_count.div_ceil(64),
            pad: 0,
        };
        let params_buffer = wgpu::util::DeviceExt::create_buffer_init(
            device,
            &wgpu::util::BufferInitDescriptor {
                label: Some("tiling params"),
                contents: bytemuck::bytes_of(&params),
                usage: wgpu::BufferUsages::UNIFORM,
            },
        );
        let none = wgpu::BufferUsages::empty();
        let s = sizes;
        let tp = s.tiles * s.passes;
        let vis_words = zeroed(device, "vis words", s.width * s.height, none);
        let valid = zeroed(device, "validity (unused: no stencil bit)", 1, none);
        let table_buffer = storage_buffer(
            device,
            "MicroBatchInfoTable",
            bytemuck::cast_slice(table),
            none,
        );
        let masks = zeroed(device, "batch-group masks", tp, none);
        let counter_offsets = zeroed(device, "counter offsets", tp, none);
        let counts = zeroed(device, "counts", s.max_counters, none);
        let pixel_offsets = zeroed(device, "pixel offsets", s.max_counters, none);
        let vertex_cull = zeroed(device, "vertex cull", s.chunk_count.div_ceil(4), none);
        let totals = zeroed(device, "totals", words_of::<Totals>(1), none);
        let stats_mid = zeroed(device, "mid stats", words_of::<PixelStats>(1), none);
        let final_counts = zeroed(device, "final counts", s.max_counters, none);
        let commands = zeroed(device, "pixel commands", s.max_commands.div_ceil(2), none);
        let wave_offsets = zeroed(device, "wave offsets", s.max_counters, none);
        let waves = zeroed(
            device,
            "wave commands",
            words_of::<WaveCommand>(s.max_waves),
            none,
        );
        let pass_dispatch = zeroed(
            device,
            "pass dispatches",
            words_of::<PassDispatch>(s.passes),
            wgpu::BufferUsages::INDIRECT,
        );
        let stats_out = zeroed(device, "output stats", words_of::<PixelStats>(1), none);

        let copy_group = binding::group(
            device,
            "copy vis",
            &pipelines.copy_layout,
            &[
                wgpu::BindingResource::TextureView(vis_view),
                vis_words.as_entire_binding(),
            ],
        );
        let zero_groups = [
            &masks,
            &counts,
            &vertex_cull,
            &totals,
            &stats_mid,
            &final_counts,
            &commands,
            &stats_out,
        ]
        .iter()
        .map(|b| {
            (
                binding::group(
                    device,
                    "zero",
                    &pipelines.zero_layout,
                    &[b.as_entire_binding()],
                ),
                (b.size() / 4) as u32,
            )
        })
        .collect();
        let common = [
            params_buffer.as_entire_binding(),
            vis_words.as_entire_binding(),
            valid.as_entire_binding(),
            table_buffer.as_entire_binding(),
        ];
        let mut p1 = common.to_vec();
        p1.push(masks.as_entire_binding());
        let phase1_group =
            binding::group(device, "laydown finalize", &pipelines.phase1_layout, &p1);
        let mut p2 = common.to_vec();
        p2.extend([
            masks.as_entire_binding(),
            counter_offsets.as_entire_binding(),
            counts.as_entire_binding(),
            pixel_offsets.as_entire_binding(),
            vertex_cull.as_entire_binding(),
            indices.as_entire_binding(),
            totals.as_entire_binding(),
            stats_mid.as_entire_binding(),
        ]);
        let phase2_group = binding::group(device, "mid classify", &pipelines.phase2_layout, &p2);
        let mut p3 = common.to_vec();
        p3.extend([
            masks.as_entire_binding(),
            counter_offsets.as_entire_binding(),
            counts.as_entire_binding(),
            pixel_offsets.as_entire_binding(),
            final_counts.as_entire_binding(),
            commands.as_entire_binding(),
            wave_offsets.as_entire_binding(),
            waves.as_entire_binding(),
            pass_dispatch.as_entire_binding(),
            totals.as_entire_binding(),
            stats_out.as_entire_binding(),
        ]);
        let phase3_group = binding::group(device, "classify output", &pipelines.phase3_layout, &p3);
        Self {
            sizes,
            config,
            layout,
            vis_words,
            masks,
            counter_offsets,
            counts,
            pixel_offsets,
            vertex_cull,
            totals,
            stats_mid,
            final_counts,
            commands,
            wave_offsets,
            waves,
            pass_dispatch,
            stats_out,
            _params: params_buffer,
            _valid: valid,
            _table: table_buffer,
            copy_group,
            zero_groups,
            phase1_group,
            phase2_group,
            phase3_group,
        }
    }

    /// Records the copy of the vis texture into the word buffer (its own timed pass).
    pub(crate) fn record_copy(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipelines: &ClassifyPipelines,
        timer: &mut GpuTimer,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("vis copy"),
            timestamp_writes: timer.compute("vis texture -> words"),
        });
        pass.set_pipeline(&pipelines.copy);
        pass.set_bind_group(0, &self.copy_group, &[]);
        pass.dispatch_workgroups(
            self.sizes.width.div_ceil(16),
            self.sizes.height.div_ceil(16),
            1,
        );
    }

    /// Records the three phases (and the zeroing they need first), each a timed pass.
    pub(crate) fn record_classification(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipelines: &ClassifyPipelines,
        timer: &mut GpuTimer,
    ) {
        let s = self.sizes;
        let groups16 = (s.width.div_ceil(16), s.height.div_ceil(16));
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("classify: zero"),
                timestamp_writes: timer.compute("classify 0: zero buffers"),
            });
            pass.set_pipeline(&pipelines.zero);
            for (group, words) in &self.zero_groups {
                let groups = words.div_ceil(ZERO_WORKGROUP);
                pass.set_bind_group(0, group, &[]);
                pass.dispatch_workgroups(groups.min(65_535), groups.div_ceil(65_535), 1);
            }
        }
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("classify: laydown finalize"),
                timestamp_writes: timer.compute("classify 1: laydown finalize"),
            });
            pass.set_pipeline(&pipelines.laydown_finalize);
            pass.set_bind_group(0, &self.phase1_group, &[]);
            pass.dispatch_workgroups(groups16.0, groups16.1, 1);
        }
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("classify: mid"),
                timestamp_writes: timer.compute("classify 2: mid classify"),
            });
            pass.set_bind_group(0, &self.phase2_group, &[]);
            pass.set_pipeline(&pipelines.counter_offsets);
            pass.dispatch_workgroups(1, 1, 1);
            pass.set_pipeline(&pipelines.count_pixels);
            pass.dispatch_workgroups(groups16.0, groups16.1, 1);
            pass.set_pipeline(&pipelines.pixel_offsets);
            pass.dispatch_workgroups(1, 1, 1);
        }
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("classify: output"),
                timestamp_writes: timer.compute("classify 3: output"),
            });
            pass.set_bind_group(0, &self.phase3_group, &[]);
            pass.set_pipeline(&pipelines.write_commands);
            pass.dispatch_workgroups(groups16.0, groups16.1, 1);
            pass.set_pipeline(&pipelines.wave_offsets);
            pass.dispatch_workgroups(1, 1, 1);
            pass.set_pipeline(&pipelines.write_waves);
            pass.dispatch_workgroups((s.tiles * s.passes).div_ceil(64), 1, 1);
        }
    }

    /// Reads every output of the last classification back (waits for the GPU). Pixel
    /// commands are put in [`canonical_sort`] order, the only order the GPU's atomics
    /// leave undetermined.
    pub fn read(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<GpuClassification> {
        let words = |b: &wgpu::Buffer, n: u32| -> Result<Vec<u32>> {
            let bytes = read_buffer(device, queue, b, 0, u64::from(n) * 4)?;
            Ok(bytemuck::pod_collect_to_vec(&bytes))
        };
        let s = self.sizes;
        let tp = s.tiles * s.passes;
        let totals: Totals = bytemuck::pod_read_unaligned(&read_buffer(
            device,
            queue,
            &self.totals,
            0,
            size_of::<Totals>() as u64,
        )?);
        let counters = totals.counter_count.min(s.max_counters);
        let commands = totals.command_count.min(s.max_commands);
        let waves = totals.wave_count.min(s.max_waves);
        let pixel_offsets = words(&self.pixel_offsets, counters)?;
        let final_counts = words(&self.final_counts, counters)?;
        let mut cmds: Vec<u16> = words(&self.commands, commands.div_ceil(2))?
            .iter()
            .flat_map(|w| [*w as u16, (*w >> 16) as u16])
            .take(commands as usize)
            .collect();
        canonical_sort(&mut cmds, &pixel_offsets, &final_counts, self.layout);
        let cull_bytes = read_buffer(device, queue, &self.vertex_cull, 0, self.vertex_cull.size())?;
        let stats = |b: &wgpu::Buffer| -> Result<PixelStats> {
            Ok(bytemuck::pod_read_unaligned(&read_buffer(
                device,
                queue,
                b,
                0,
                size_of::<PixelStats>() as u64,
            )?))
        };
        Ok(GpuClassification {
            masks: words(&self.masks, tp)?,
            counter_offsets: words(&self.counter_offsets, tp)?,
            counts: words(&self.counts, counters)?,
            pixel_offsets,
            vertex_cull: cull_bytes[..s.chunk_count.next_multiple_of(4) as usize].to_vec(),
            totals,
            mid_stats: stats(&self.stats_mid)?,
            final_counts,
            commands: cmds,
            wave_offsets: words(&self.wave_offsets, counters)?,
            waves: bytemuck::pod_collect_to_vec(&read_buffer(
                device,
                queue,
                &self.waves,
                0,
                u64::from(waves) * size_of::<WaveCommand>() as u64,
            )?),
            passes: bytemuck::pod_collect_to_vec(&read_buffer(
                device,
                queue,
                &self.pass_dispatch,
                0,
                u64::from(s.passes) * size_of::<PassDispatch>() as u64,
            )?),
            output_stats: stats(&self.stats_out)?,
            vis: words(&self.vis_words, s.width * s.height)?,
        })
    }
}

/// Everything the GPU classification wrote for one frame, read back.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct GpuClassification {
    /// Phase 1: per (tile, pass), the batch groups used.
    pub masks: Vec<u32>,
    /// Phase 2: first counter of each (tile, pass).
    pub counter_offsets: Vec<u32>,
    /// Phase 2: pixels per counter.
    pub counts: Vec<u32>,
    /// Phase 2: first pixel command of each counter.
    pub pixel_offsets: Vec<u32>,
    /// Phase 2: the vertex cull buffer, one byte per 64-vertex chunk (padded to whole words).
    pub vertex_cull: Vec<u8>,
    /// Lengths the passes wrote.
    pub totals: Totals,
    /// Phase 2's pixel counters.
    pub mid_stats: PixelStats,
    /// Phase 3: commands written per counter.
    pub final_counts: Vec<u32>,
    /// Phase 3: pixel commands, canonically sorted within each counter.
    pub commands: Vec<u16>,
    /// Phase 3: first wave command of each counter.
    pub wave_offsets: Vec<u32>,
    /// Phase 3: the wave commands.
    pub waves: Vec<WaveCommand>,
    /// Phase 3: one indirect dispatch per pass.
    pub passes: Vec<PassDispatch>,
    /// Phase 3's pixel counters.
    pub output_stats: PixelStats,
    /// The vis words the passes read (row-major).
    pub vis: Vec<u32>,
}

impl GpuClassification {
    /// The first output that differs from the CPU twin's, by name, or `None` when all are
    /// equal (pixel commands compared after the canonical sort).
    pub fn mismatch(&self, cpu: &Classification) -> Option<String> {
        fn first<T: PartialEq + std::fmt::Debug>(name: &str, a: &[T], b: &[T]) -> Option<String> {
            if a.len() != b.len() {
                return Some(format!("{name}: GPU {} entries, CPU {}", a.len(), b.len()));
            }
            let i = a.iter().zip(b).position(|(x, y)| x != y)?;
            Some(format!("{name}[{i}]: GPU {:?}, CPU {:?}", a[i], b[i]))
        }
        first("masks", &self.masks, &cpu.masks)
            .or_else(|| {
                first(
                    "counter offsets",
                    &self.counter_offsets,
                    &cpu.mid.counter_offsets,
                )
            })
            .or_else(|| first("counts", &self.counts, &cpu.mid.counts))
            .or_else(|| first("pixel offsets", &self.pixel_offsets, &cpu.mid.pixel_offsets))
            .or_else(|| first("vertex cull", &self.vertex_cull, &cpu.mid.vertex_cull))
            .or_else(|| first("mid stats", &[self.mid_stats], &[cpu.mid.stats]))
            .or_else(|| first("final counts", &self.final_counts, &cpu.output.final_counts))
            .or_else(|| first("pixel commands", &self.commands, &cpu.output.commands))
            .or_else(|| first("wave offsets", &self.wave_offsets, &cpu.output.wave_offsets))
            .or_else(|| first("wave commands", &self.waves, &cpu.output.waves))
            .or_else(|| first("pass dispatches", &self.passes, &cpu.output.passes))
            .or_else(|| first("output stats", &[self.output_stats], &[cpu.output.stats]))
    }
}

#[cfg(test)]
mod tests {
    use super::{COPY_VIS_WGSL, ZERO_WGSL, words_of};

    #[test]
    fn helper_modules_validate() {
        shadercheck::assert_valid("copy vis", COPY_VIS_WGSL, shadercheck::Caps::CORE);
        shadercheck::assert_valid("zero", ZERO_WGSL, shadercheck::Caps::CORE);
    }

    #[test]
    fn pod_rows_in_words() {
        assert_eq!(words_of::<tiling::PassDispatch>(3), 18);
        assert_eq!(words_of::<tiling::WaveCommand>(5), 20);
        assert_eq!(words_of::<tiling::PixelStats>(1), 8);
        assert_eq!(words_of::<tiling::Totals>(1), 4);
    }
}
