//! GPU stream compaction of `2^--log2-items` items (16M by default) at 1/3 density through
//! this crate's WGSL: one atomic per thread, one per subgroup (the subgroup path), one per
//! workgroup (the fallback), and a floor without any atomic, timed with timestamp queries. Prints the adapter, the
//! median time per dispatch, ns per item, and atomics per item (counted in a separate run).
//!
//! `cargo run --release -p wave --example gpu_append_timing`
//!
//! This is the measurement REFERENCES.md asks for ("whether NVIDIA's Vulkan driver
//! aggregates per-thread atomics is undocumented: measure per-thread vs per-wave vs
//! per-workgroup"); the `gpu` crate owns the renderer's own passes and their timings.

use clap::Parser;
use testkit::device::read_bytes;

/// Times stream compaction through wave's WGSL on the workspace's headless device.
#[derive(Debug, Parser)]
#[command()]
struct Args {
    /// log2 of the items compacted (20 to 26: 1M to 64M words).
    #[arg(long, default_value_t = 24, value_parser = clap::value_parser!(u32).range(20..=26))]
    log2_items: u32,
    /// Timed dispatches per variant (the median is reported).
    #[arg(long, default_value_t = 30, value_parser = clap::value_parser!(u32).range(1..=1000))]
    reps: u32,
}

struct Variant {
    name: &'static str,
    module: &'static str,
    workgroup: u32,
    builtins: &'static str,
    body: &'static str,
    needs_subgroups: bool,
}

/// The workgroup-aggregated append's body, the same at every workgroup size.
const WORKGROUP_AGGREGATED: &str = "let a = wave_wg_append_begin(keep, li);
    var old = 0u;
    if (a.total != 0u) { old = atomicAdd(&counters[0], a.total); if (COUNT) { atomicAdd(&counters[1], 1u); } }
    let s = wave_wg_append_end(a, old);
    if (s != WAVE_NO_SLOT) { items[s] = x; }";

const VARIANTS: &[Variant] = &[
    Variant {
        name: "per_thread_atomic",
        module: "",
        workgroup: 64,
        builtins: "",
        body: "if (keep) { let s = atomicAdd(&counters[0], 1u); if (COUNT) { atomicAdd(&counters[1], 1u); } items[s] = x; }",
        needs_subgroups: false,
    },
    Variant {
        // The same, with the counter's index unknown to the compiler (always 0 at run
        // time): a driver that aggregates only provably uniform addresses cannot here.
        name: "per_thread_atomic_dynamic_index",
        module: "",
        workgroup: 64,
        builtins: "",
        body: "let k = min(arrayLength(&input) >> 30u, 1u);
    if (keep) { let s = atomicAdd(&counters[k], 1u); if (COUNT) { atomicAdd(&counters[2], 1u); } items[s] = x; }",
        needs_subgroups: false,
    },
    Variant {
        name: "subgroup_aggregated",
        module: "#import wave::subgroup",
        workgroup: 64,
        builtins: ", @builtin(subgroup_invocation_id) sg_lane: u32",
        body: "let a = wave_sg_append_begin(keep, sg_lane);
    var old = 0u;
    if (a.total != 0u) { old = atomicAdd(&counters[0], a.total); if (COUNT) { atomicAdd(&counters[1], 1u); } }
    let s = wave_sg_append_end(a, old);
    if (s != WAVE_NO_SLOT) { items[s] = x; }",
        needs_subgroups: true,
    },
    Variant {
        name: "workgroup_aggregated_64",
        module: "#import wave::workgroup",
        workgroup: 64,
        builtins: "",
        body: WORKGROUP_AGGREGATED,
        needs_subgroups: false,
    },
    Variant {
        name: "workgroup_aggregated_256",
        module: "#import wave::workgroup",
        workgroup: 256,
        builtins: "",
        body: WORKGROUP_AGGREGATED,
        needs_subgroups: false,
    },
    Variant {
        name: "floor_no_atomic_uncompacted",
        module: "",
        workgroup: 64,
        builtins: "",
        // Touches the counter once per dispatch so the bindings match the other variants.
        body: "if (keep) { items[i] = x; } if (i == 0u) { atomicAdd(&counters[1], 0u); }",
        needs_subgroups: false,
    },
];

fn source(v: &Variant, count: bool) -> String {
    let src = format!(
        "{module}
const COUNT: bool = {count};
@group(0) @binding(0) var<storage, read> input: array<u32>;
@group(0) @binding(1) var<storage, read_write> counters: array<atomic<u32>>;
@group(0) @binding(2) var<storage, read_write> items: array<u32>;
@compute @workgroup_size({wg})
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
        @builtin(local_invocation_index) li: u32{builtins}) {{
    let i = (wid.y * nwg.x + wid.x) * {wg}u + li;
    let x = input[i];
    let keep = x % 3u == 0u;
    {body}
}}",
        module = v.module,
        wg = v.workgroup,
        builtins = v.builtins,
        body = v.body,
    );
    shader::compose_source(&[wave::wgsl::MODULES], v.name, &src, &[])
        .unwrap_or_else(|e| panic!("{e}"))
}

fn main() {
    let args = Args::parse();
    let n: u32 = 1 << args.log2_items;
    let reps = args.reps;
    // The workspace's one headless device (every optional feature the adapter has).
    let ctx = testkit::device::ctx();
    let (device, queue) = (&ctx.device, &ctx.queue);
    let features = device.features();
    if !features.contains(wgpu::Features::TIMESTAMP_QUERY) {
        eprintln!(
            "adapter {} lacks wgpu::Features::TIMESTAMP_QUERY, which the timings need",
            ctx.adapter_line()
        );
        std::process::exit(1);
    }
    let info = &ctx.info;
    println!(
        "adapter: {}, subgroup sizes {}..{}",
        ctx.adapter_line(),
        info.subgroup_min_size,
        info.subgroup_max_size
    );

    // `n` pseudo-random words; a third pass `x % 3 == 0`.
    let input = testkit::Rng::new(0x2545_f491).words(n as usize);
    let kept = input.iter().filter(|&&x| x % 3 == 0).count() as u32;
    println!(
        "{n} items, {kept} kept (density {:.4})",
        f64::from(kept) / f64::from(n)
    );

    let usage =
        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC;
    let buf = |size: u64| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size,
            usage,
            mapped_at_creation: false,
        })
    };
    let input_buf = buf(u64::from(n) * 4);
    queue.write_buffer(&input_buf, 0, bytemuck::cast_slice(&input));
    let counters = buf(16);
    let items = buf(u64::from(n) * 4);
    let queries = device.create_query_set(&wgpu::QuerySetDescriptor {
        label: None,
        ty: wgpu::QueryType::Timestamp,
        count: 2 * reps,
    });
    let resolve = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: u64::from(2 * reps) * 8,
        usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let period = f64::from(queue.get_timestamp_period());

    println!("| variant | workgroup | median ms | min ms | max ms | ns/item | atomics/item |");
    println!("| --- | --- | --- | --- | --- | --- | --- |");
    for v in VARIANTS {
        if v.needs_subgroups && !features.contains(wgpu::Features::SUBGROUP) {
            println!("| {} | - | no SUBGROUP on this adapter | | |", v.name);
            continue;
        }
        let groups = n / v.workgroup;
        let (gx, gy) = (4096, groups / 4096);
        let pipeline = |count: bool| {
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(v.name),
                source: wgpu::ShaderSource::Wgsl(source(v, count).into()),
            });
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(v.name),
                layout: None,
                module: &module,
                entry_point: Some("main"),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let run = |p: &wgpu::ComputePipeline, reps: u32, timed: bool| {
            let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: None,
                layout: &p.get_bind_group_layout(0),
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: input_buf.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: counters.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: items.as_entire_binding(),
                    },
                ],
            });
            let mut enc = device.create_command_encoder(&Default::default());
            for r in 0..reps {
                enc.clear_buffer(&counters, 0, None);
                let tw = wgpu::ComputePassTimestampWrites {
                    query_set: &queries,
                    beginning_of_pass_write_index: Some(2 * r),
                    end_of_pass_write_index: Some(2 * r + 1),
                };
                let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: None,
                    timestamp_writes: timed.then_some(tw),
                });
                pass.set_pipeline(p);
                pass.set_bind_group(0, &bind, &[]);
                pass.dispatch_workgroups(gx, gy, 1);
            }
            if timed {
                enc.resolve_query_set(&queries, 0..2 * reps, &resolve, 0);
            }
            queue.submit([enc.finish()]);
            device
                .poll(wgpu::PollType::wait_indefinitely())
                .expect("poll");
        };
        // Count the atomics once, then check the counter of a timed run.
        let counting = pipeline(true);
        run(&counting, 1, false);
        let c: Vec<u32> = bytemuck::pod_collect_to_vec(&read_bytes(&counters));
        let atomics = if v.name.ends_with("dynamic_index") {
            c[2]
        } else {
            c[1]
        };
        let timed = pipeline(false);
        run(&timed, 2, false); // warm-up
        run(&timed, reps, true);
        let c: Vec<u32> = bytemuck::pod_collect_to_vec(&read_bytes(&counters));
        if v.name.starts_with("floor") {
            assert_eq!(c[0], 0);
        } else {
            assert_eq!(c[0], kept, "{}: every kept item appended", v.name);
        }
        let ts: Vec<u64> = bytemuck::pod_collect_to_vec(&read_bytes(&resolve));
        let mut ms: Vec<f64> = ts
            .chunks(2)
            .map(|p| (p[1].wrapping_sub(p[0])) as f64 * period / 1e6)
            .collect();
        ms.sort_by(f64::total_cmp);
        let median = ms[ms.len() / 2];
        println!(
            "| {} | {} | {:.4} | {:.4} | {:.4} | {:.4} | {:.5} |",
            v.name,
            v.workgroup,
            median,
            ms[0],
            ms[ms.len() - 1],
            median * 1e6 / f64::from(n),
            f64::from(atomics) / f64::from(n)
        );
    }
}
