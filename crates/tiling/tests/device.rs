//! The WGSL twins on a real device against the CPU twins, bit for bit: the three
//! classification phases (pixel commands compared after `canonical_sort`, everything else
//! as written) on both the subgroup path (where the adapter has `Features::SUBGROUP`) and
//! the workgroup fallback, both vis-word layouts, with and without a validity mask; and
//! the vertex wave commands.
//!
//! Runs on whatever adapter wgpu finds (lavapipe in CI, the H100 on the device machine).
//! Without one every test fails with a message saying how to install one (lavapipe:
//! `apt-get install -y mesa-vulkan-drivers libvulkan1`); a GPU test never passes silently.

mod common;

use std::collections::BTreeMap;

use common::{Rng, random_mask, random_scene, random_vis};
use tiling::wgsl::{
    CLASSIFY_OUTPUT, CLASSIFY_OUTPUT_SUBGROUP, LAYDOWN_FINALIZE, MID_CLASSIFY,
    MID_CLASSIFY_SUBGROUP, VERTEX_WAVES,
};
use tiling::{
    ClassifyConfig, PassDispatch, PixelStats, PlanConfig, TilingParams, Totals, UberChunk,
    VertexWaveCommand, VisBuffer, WaveCommand, canonical_sort, classify_phases,
    vertex_wave_commands,
};
use visbuf::VisLayout;
use wave::WaveWidth;

struct Gpu {
    device: wgpu::Device,
    queue: wgpu::Queue,
}

fn gpu() -> Gpu {
    let instance =
        wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        force_fallback_adapter: false,
        compatible_surface: None,
        apply_limit_buckets: false,
    }));
    let adapter = match adapter {
        Ok(a) => a,
        Err(e) => panic!(
            "no GPU adapter ({e}). Install a Vulkan driver: `apt-get install -y mesa-vulkan-drivers libvulkan1` (lavapipe, software), or on NVIDIA point VK_DRIVER_FILES at the NVIDIA ICD json"
        ),
    };
    let features = adapter.features() & wgpu::Features::SUBGROUP;
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("tiling device test"),
        required_features: features,
        required_limits: adapter.limits(),
        experimental_features: wgpu::ExperimentalFeatures::disabled(),
        memory_hints: wgpu::MemoryHints::Performance,
        trace: wgpu::Trace::Off,
    }))
    .expect("device");
    let info = adapter.get_info();
    eprintln!(
        "adapter: {} ({:?}, driver {}), subgroup sizes {}..{}, SUBGROUP {}",
        info.name,
        info.backend,
        info.driver,
        info.subgroup_min_size,
        info.subgroup_max_size,
        device.features().contains(wgpu::Features::SUBGROUP)
    );
    Gpu { device, queue }
}

#[derive(Clone, Copy, PartialEq)]
enum Kind {
    Uniform,
    Read,
    Write,
}

/// One module's buffers by binding, and its pipeline layout.
struct Pass<'g> {
    gpu: &'g Gpu,
    module: wgpu::ShaderModule,
    layout: wgpu::PipelineLayout,
    group_layout: wgpu::BindGroupLayout,
    buffers: BTreeMap<u32, wgpu::Buffer>,
}

impl<'g> Pass<'g> {
    fn new(gpu: &'g Gpu, src: &str, kinds: &[(u32, Kind)]) -> Self {
        let d = &gpu.device;
        let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("tiling pass"),
            source: wgpu::ShaderSource::Wgsl(src.into()),
        });
        let entries: Vec<wgpu::BindGroupLayoutEntry> = kinds
            .iter()
            .map(|&(binding, kind)| wgpu::BindGroupLayoutEntry {
                binding,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: match kind {
                        Kind::Uniform => wgpu::BufferBindingType::Uniform,
                        Kind::Read => wgpu::BufferBindingType::Storage { read_only: true },
                        Kind::Write => wgpu::BufferBindingType::Storage { read_only: false },
                    },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            })
            .collect();
        let group_layout = d.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: None,
            entries: &entries,
        });
        let layout = d.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: None,
            bind_group_layouts: &[Some(&group_layout)],
            immediate_size: 0,
        });
        Self {
            gpu,
            module,
            layout,
            group_layout,
            buffers: BTreeMap::new(),
        }
    }

    /// Binds `bytes` (or zeros) at `binding`.
    fn set(&mut self, binding: u32, bytes: &[u8], uniform: bool) {
        let mut usage = wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
        usage |= if uniform {
            wgpu::BufferUsages::UNIFORM
        } else {
            wgpu::BufferUsages::STORAGE
        };
        let size = (bytes.len().max(4) as u64).next_multiple_of(16);
        let buf = self.gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size,
            usage,
            mapped_at_creation: false,
        });
        let mut padded = bytes.to_vec();
        padded.resize(size as usize, 0);
        self.gpu.queue.write_buffer(&buf, 0, &padded);
        self.buffers.insert(binding, buf);
    }

    fn zeros(&mut self, binding: u32, words: usize) {
        self.set(binding, &vec![0u8; words.max(1) * 4], false);
    }

    fn data<T: bytemuck::Pod>(&mut self, binding: u32, v: &[T]) {
        self.set(binding, bytemuck::cast_slice(v), false);
    }

    fn run(&self, entry: &str, groups: (u32, u32, u32)) {
        let d = &self.gpu.device;
        let scope = d.push_error_scope(wgpu::ErrorFilter::Validation);
        let pipeline = d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: Some(&self.layout),
            module: &self.module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        });
        let entries: Vec<wgpu::BindGroupEntry<'_>> = self
            .buffers
            .iter()
            .map(|(&binding, b)| wgpu::BindGroupEntry {
                binding,
                resource: b.as_entire_binding(),
            })
            .collect();
        let bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &self.group_layout,
            entries: &entries,
        });
        let mut enc = d.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups(groups.0, groups.1, groups.2);
        }
        self.gpu.queue.submit([enc.finish()]);
        if let Some(e) = pollster::block_on(scope.pop()) {
            panic!("validation error in {entry}: {e}");
        }
    }

    /// Reads back `binding` as `T`s (its first `len`).
    fn read<T: bytemuck::Pod>(&self, binding: u32, len: usize) -> Vec<T> {
        let d = &self.gpu.device;
        let b = &self.buffers[&binding];
        let s = d.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size: b.size(),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut enc = d.create_command_encoder(&Default::default());
        enc.copy_buffer_to_buffer(b, 0, &s, 0, b.size());
        self.gpu.queue.submit([enc.finish()]);
        s.slice(..)
            .map_async(wgpu::MapMode::Read, |r| r.expect("map"));
        d.poll(wgpu::PollType::wait_indefinitely()).expect("poll");
        let bytes = s.slice(..).get_mapped_range().expect("mapped").to_vec();
        s.unmap();
        let n = len * size_of::<T>();
        bytemuck::pod_collect_to_vec(&bytes[..n])
    }
}

fn pixel_kinds(extra: &[(u32, Kind)]) -> Vec<(u32, Kind)> {
    let mut k = vec![
        (0, Kind::Uniform),
        (1, Kind::Read),
        (2, Kind::Read),
        (3, Kind::Read),
    ];
    k.extend_from_slice(extra);
    k
}

#[allow(
    clippy::too_many_arguments,
    reason = "one case of the test matrix; every argument is a dimension of it"
)]
fn classification_case(
    gpu: &Gpu,
    subgroups: bool,
    seed: u64,
    w: u32,
    h: u32,
    layout: VisLayout,
    masked: bool,
    keyed: bool,
) {
    let mut rng = Rng(seed);
    let config = PlanConfig {
        layout,
        max_batch_groups: 5,
        max_micro_batch_vertices: 3000,
        ring_bytes: 32 * 2 * 6000,
        ..PlanConfig::default()
    };
    let scene = random_scene(&mut rng, 25, &config);
    let plan = &scene.plan;
    let words = random_vis(&mut rng, plan, w, h, layout, 8);
    let mask = random_mask(&mut rng, w, h, 85);
    let mut vis = VisBuffer::new(&words, w, h, layout).unwrap();
    if masked {
        vis = vis.with_validity(&mask).unwrap();
    }
    let cfg = ClassifyConfig::for_plan(plan, WaveWidth::W16);
    // Seed 2 truncates the index buffer: triangles past it count as bad indices. The
    // length stays a multiple of 4 words, so the harness's 16-byte padding adds no zero
    // indices that the shader's arrayLength would see.
    let indices = if seed == 2 {
        &scene.indices[..scene.indices.len() / 2 / 12 * 12]
    } else {
        &scene.indices[..]
    };
    let cpu = classify_phases(&vis, &plan.table, indices, &cfg).unwrap();
    let params = TilingParams::new(&vis, &cfg, plan.table.len() as u32, plan.order.len() as u32);
    let tiles = vis.tile_count() as usize;
    let p = cfg.pass_count as usize;
    let groups16 = (w.div_ceil(16), h.div_ceil(16), 1);
    let what = format!(
        "seed {seed} {w}x{h} {layout:?} masked {masked} subgroups {subgroups} keyed {keyed}"
    );
    // `keyed` false forces the wave-append loop that tiles with more counters than the
    // keyed histogram holds take.
    let path = |src: &str| {
        if keyed {
            src.to_string()
        } else {
            let limit = "const TILING_HIST_LIMIT: u32 = TILING_HIST_SLOTS;";
            assert!(src.contains(limit));
            src.replace(limit, "const TILING_HIST_LIMIT: u32 = 0u;")
        }
    };
    let setup = |pass: &mut Pass<'_>| {
        pass.set(0, bytemuck::bytes_of(&params), true);
        pass.data(1, &words);
        pass.data(2, &mask);
        pass.data(3, &plan.table);
    };

    // Phase 1.
    let mut p1 = Pass::new(gpu, LAYDOWN_FINALIZE, &pixel_kinds(&[(4, Kind::Write)]));
    setup(&mut p1);
    p1.zeros(4, tiles * p);
    p1.run("laydown_finalize", groups16);
    let masks: Vec<u32> = p1.read(4, tiles * p);
    assert_eq!(masks, cpu.masks, "masks, {what}");

    // Phase 2.
    let counters = cpu.mid.counter_count as usize;
    let mid_src = if subgroups {
        MID_CLASSIFY_SUBGROUP
    } else {
        MID_CLASSIFY
    };
    let mut p2 = Pass::new(
        gpu,
        &path(mid_src),
        &pixel_kinds(&[
            (4, Kind::Read),
            (5, Kind::Write),
            (6, Kind::Write),
            (7, Kind::Write),
            (8, Kind::Write),
            (9, Kind::Read),
            (10, Kind::Write),
            (11, Kind::Write),
        ]),
    );
    setup(&mut p2);
    p2.data(4, &masks);
    p2.zeros(5, tiles * p);
    p2.zeros(6, counters);
    p2.zeros(7, counters);
    p2.zeros(8, (cfg.chunk_count as usize).div_ceil(4));
    p2.data(9, indices);
    p2.zeros(10, 4);
    p2.zeros(11, 8);
    p2.run("counter_offsets_pass", (1, 1, 1));
    p2.run("count_pixels", groups16);
    p2.run("pixel_offsets_pass", (1, 1, 1));
    assert_eq!(
        p2.read::<u32>(5, tiles * p),
        cpu.mid.counter_offsets,
        "counter offsets, {what}"
    );
    assert_eq!(
        p2.read::<u32>(6, counters),
        cpu.mid.counts,
        "counts, {what}"
    );
    assert_eq!(
        p2.read::<u32>(7, counters),
        cpu.mid.pixel_offsets,
        "pixel offsets, {what}"
    );
    let cull: Vec<u8> = p2
        .read::<u32>(8, cpu.mid.vertex_cull.len() / 4)
        .iter()
        .flat_map(|w| w.to_le_bytes())
        .collect();
    assert_eq!(cull, cpu.mid.vertex_cull, "vertex cull buffer, {what}");
    let totals: Vec<Totals> = p2.read(10, 1);
    assert_eq!(
        (totals[0].counter_count, totals[0].command_count),
        (cpu.mid.counter_count, cpu.mid.command_count),
        "{what}"
    );
    assert_eq!(
        p2.read::<PixelStats>(11, 1)[0],
        cpu.mid.stats,
        "mid stats, {what}"
    );
    if seed == 2 {
        assert!(
            cpu.mid.stats.bad_indices > 0,
            "{what}: the truncated case has bad indices"
        );
    }

    // Phase 3.
    let commands = cpu.mid.command_count as usize;
    let out_src = if subgroups {
        CLASSIFY_OUTPUT_SUBGROUP
    } else {
        CLASSIFY_OUTPUT
    };
    let mut p3 = Pass::new(
        gpu,
        &path(out_src),
        &pixel_kinds(&[
            (4, Kind::Read),
            (5, Kind::Read),
            (6, Kind::Read),
            (7, Kind::Read),
            (8, Kind::Write),
            (9, Kind::Write),
            (10, Kind::Write),
            (11, Kind::Write),
            (12, Kind::Write),
            (13, Kind::Write),
            (14, Kind::Write),
        ]),
    );
    setup(&mut p3);
    p3.data(4, &masks);
    p3.data(5, &cpu.mid.counter_offsets);
    p3.data(6, &cpu.mid.counts);
    p3.data(7, &cpu.mid.pixel_offsets);
    p3.zeros(8, counters);
    p3.zeros(9, commands.div_ceil(2));
    p3.zeros(10, counters);
    p3.zeros(11, 4 * cpu.output.waves.len() + 4);
    p3.zeros(12, 6 * p);
    p3.zeros(13, 4);
    p3.zeros(14, 8);
    p3.run("write_commands", groups16);
    p3.run("wave_offsets_pass", (1, 1, 1));
    p3.run("write_waves", (((tiles * p) as u32).div_ceil(64), 1, 1));
    let finals: Vec<u32> = p3.read(8, counters);
    assert_eq!(finals, cpu.output.final_counts, "final counts, {what}");
    let mut cmds: Vec<u16> = p3
        .read::<u32>(9, commands.div_ceil(2))
        .iter()
        .flat_map(|w| [*w as u16, (*w >> 16) as u16])
        .take(commands)
        .collect();
    canonical_sort(&mut cmds, &cpu.mid.pixel_offsets, &finals, layout);
    assert_eq!(
        cmds, cpu.output.commands,
        "commands after the canonical sort, {what}"
    );
    assert_eq!(
        p3.read::<u32>(10, counters),
        cpu.output.wave_offsets,
        "wave offsets, {what}"
    );
    assert_eq!(
        p3.read::<WaveCommand>(11, cpu.output.waves.len()),
        cpu.output.waves,
        "wave commands, {what}"
    );
    assert_eq!(
        p3.read::<PassDispatch>(12, p),
        cpu.output.passes,
        "pass dispatches, {what}"
    );
    assert_eq!(
        p3.read::<Totals>(13, 1)[0].wave_count as usize,
        cpu.output.waves.len()
    );
    assert_eq!(
        p3.read::<PixelStats>(14, 1)[0],
        cpu.output.stats,
        "output stats, {what}"
    );

    // Vertex wave commands from the cull buffer.
    let v = vertex_wave_commands(
        &cpu.mid.vertex_cull,
        plan.chunk_count,
        &plan.table,
        &plan.order,
        &plan.passes,
    )
    .unwrap();
    let chunks = plan.chunk_count as usize;
    let ubers = chunks.div_ceil(64);
    let mut p4 = Pass::new(
        gpu,
        VERTEX_WAVES,
        &[
            (0, Kind::Uniform),
            (1, Kind::Read),
            (2, Kind::Read),
            (3, Kind::Read),
            (4, Kind::Read),
            (5, Kind::Write),
            (6, Kind::Write),
            (7, Kind::Write),
            (8, Kind::Write),
            (9, Kind::Write),
            (10, Kind::Write),
            (11, Kind::Write),
            (12, Kind::Write),
        ],
    );
    p4.set(0, bytemuck::bytes_of(&params), true);
    p4.data(1, &plan.table);
    p4.data(2, &plan.order);
    p4.data(3, &plan.passes);
    p4.data(4, &cpu.mid.vertex_cull);
    p4.zeros(5, 4 * ubers);
    p4.zeros(6, v.pyramid.data.len());
    p4.zeros(7, chunks);
    p4.zeros(8, plan.order.len());
    p4.zeros(9, 2 * chunks);
    p4.zeros(10, 6 * plan.passes.len());
    p4.zeros(11, plan.passes.len());
    p4.zeros(12, 4);
    p4.run("uber_chunks", ((ubers as u32).div_ceil(64), 1, 1));
    p4.run("build_pyramid", (1, 1, 1));
    p4.run(
        "micro_batch_deltas",
        ((plan.order.len() as u32).div_ceil(64), 1, 1),
    );
    p4.run("scan_deltas", (1, 1, 1));
    p4.run(
        "write_vertex_commands",
        ((chunks as u32).div_ceil(64).max(1), 1, 1),
    );
    p4.run(
        "pass_args",
        ((plan.passes.len() as u32).div_ceil(64).max(1), 1, 1),
    );
    assert_eq!(
        p4.read::<UberChunk>(5, ubers),
        v.ubers,
        "uber chunks, {what}"
    );
    assert_eq!(
        p4.read::<u32>(6, v.pyramid.data.len()),
        v.pyramid.data,
        "pyramid, {what}"
    );
    let ids: Vec<u32> = v.commands.iter().map(|c| c.micro_batch).collect();
    assert_eq!(p4.read::<u32>(7, ids.len()), ids, "scanned deltas, {what}");
    assert_eq!(
        p4.read::<u32>(8, plan.order.len()),
        v.micro_batch_waves,
        "micro-batch waves, {what}"
    );
    assert_eq!(
        p4.read::<VertexWaveCommand>(9, v.commands.len()),
        v.commands,
        "vertex wave commands, {what}"
    );
    assert_eq!(
        p4.read::<PassDispatch>(10, plan.passes.len()),
        v.passes,
        "vertex dispatches, {what}"
    );
    assert_eq!(
        p4.read::<Totals>(12, 1)[0].visible_chunks as usize,
        v.commands.len()
    );
    eprintln!(
        "{what}: {} valid pixels, {} counters, {} commands, {} waves, {} vertex waves: equal",
        cpu.output.stats.valid,
        counters,
        commands,
        cpu.output.waves.len(),
        v.commands.len()
    );
}

#[test]
fn gpu_passes_equal_the_cpu_twins() {
    let gpu = gpu();
    let has_subgroups = gpu.device.features().contains(wgpu::Features::SUBGROUP);
    for (seed, (w, h)) in [(1u64, (300u32, 200u32)), (2, (129, 257)), (3, (64, 48))] {
        for layout in [VisLayout::Standard, VisLayout::Vrs] {
            for masked in [false, true] {
                for keyed in [true, false] {
                    classification_case(&gpu, false, seed, w, h, layout, masked, keyed);
                    if has_subgroups {
                        classification_case(&gpu, true, seed, w, h, layout, masked, keyed);
                    }
                }
            }
        }
    }
}
