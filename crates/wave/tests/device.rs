//! The WGSL twins run on a real device and checked against the CPU model: the subgroup
//! path (where the adapter has `Features::SUBGROUP`), the workgroup fallback, and the
//! run-grouped batch output, each called twice per dispatch so the shared scratch is
//! reused.
//!
//! Runs on whatever adapter wgpu finds (lavapipe in CI, the H100 on the device machine).
//! Without one every test fails with a message saying how to install one (lavapipe:
//! `apt-get install -y mesa-vulkan-drivers libvulkan1`); a GPU test never passes silently.

use std::collections::BTreeMap;

use wave::{
    CountedAtomicU32, LaneMask, NO_SLOT, SUBGROUP_MODULE, WORKGROUP_MODULE, Wave, WaveBatch,
    WaveWidth, module_for,
};

struct Gpu {
    device: wgpu::Device,
    queue: wgpu::Queue,
    info: wgpu::AdapterInfo,
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
        label: Some("wave device test"),
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
    Gpu {
        device,
        queue,
        info,
    }
}

impl Gpu {
    fn has_subgroups(&self) -> bool {
        self.device.features().contains(wgpu::Features::SUBGROUP)
    }

    /// Runs `main` over `workgroups` workgroups with `input` at binding 0 and zeroed
    /// `array<u32>`-sized outputs at bindings 1.., returning the outputs.
    fn run(&self, src: &str, input: &[u32], outputs: &[usize], workgroups: u32) -> Vec<Vec<u32>> {
        let d = &self.device;
        let scope = d.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("wave kernel"),
            source: wgpu::ShaderSource::Wgsl(src.into()),
        });
        let pipeline = d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("wave kernel"),
            layout: None,
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        let storage = |bytes: &[u8]| {
            let buf = d.create_buffer(&wgpu::BufferDescriptor {
                label: None,
                size: bytes.len().max(4) as u64,
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_SRC
                    | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            self.queue.write_buffer(&buf, 0, bytes);
            buf
        };
        let mut bufs = vec![storage(bytemuck::cast_slice(input))];
        for &words in outputs {
            bufs.push(storage(&vec![0u8; words.max(1) * 4]));
        }
        let entries: Vec<_> = bufs
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: b.as_entire_binding(),
            })
            .collect();
        let bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        let mut enc = d.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups(workgroups, 1, 1);
        }
        let staging: Vec<_> = bufs[1..]
            .iter()
            .map(|b| {
                let s = d.create_buffer(&wgpu::BufferDescriptor {
                    label: None,
                    size: b.size(),
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                enc.copy_buffer_to_buffer(b, 0, &s, 0, b.size());
                s
            })
            .collect();
        self.queue.submit([enc.finish()]);
        if let Some(e) = pollster::block_on(scope.pop()) {
            panic!("validation error: {e}");
        }
        staging
            .iter()
            .map(|s| {
                s.slice(..)
                    .map_async(wgpu::MapMode::Read, |r| r.expect("map"));
                d.poll(wgpu::PollType::wait_indefinitely()).expect("poll");
                let v =
                    bytemuck::pod_collect_to_vec(&s.slice(..).get_mapped_range().expect("mapped"));
                s.unmap();
                v
            })
            .collect()
    }
}

/// xorshift words.
fn words(n: usize, seed: u32) -> Vec<u32> {
    let mut s = seed | 1;
    (0..n)
        .map(|_| {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            s
        })
        .collect()
}

const N: usize = 64 * 37 + 13; // a partial last workgroup
const ROUNDS: usize = 2;

/// Two compaction rounds per invocation (predicates `(x >> r) % 3 == 0`), each through
/// counter `2r` with the atomics it issued counted in `2r + 1`. `info` gets, per round and
/// invocation: slot, wave key (which subgroup or workgroup), lane.
fn compaction_kernel(module: &str, path: &str, key: &str, lane: &str, builtins: &str) -> String {
    format!(
        "{module}
@group(0) @binding(0) var<storage, read> input: array<u32>;
@group(0) @binding(1) var<storage, read_write> counters: array<atomic<u32>>;
@group(0) @binding(2) var<storage, read_write> items: array<u32>;
@group(0) @binding(3) var<storage, read_write> info: array<u32>;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>, {builtins}) {{
    let n = arrayLength(&input);
    let i = gid.x;
    var x = 0u;
    if (i < n) {{ x = input[i]; }}
    for (var r = 0u; r < {ROUNDS}u; r++) {{
        let keep = i < n && ((x >> r) % 3u) == 0u;
        let a = wave_{path}_append_begin(keep, {lane});
        var old = 0u;
        if (a.total != 0u) {{
            old = atomicAdd(&counters[2u * r], a.total);
            atomicAdd(&counters[2u * r + 1u], 1u);
        }}
        let slot = wave_{path}_append_end(a, old);
        if (slot < n) {{ items[r * n + slot] = x; }}
        if (i < n) {{
            let o = 3u * (r * n + i);
            info[o] = slot;
            info[o + 1u] = {key};
            info[o + 2u] = {lane};
        }}
    }}
}}"
    )
}

fn check_compaction(gpu: &Gpu, src: &str, wave_width_of: impl Fn(u32) -> WaveWidth) {
    let input = words(N, 12345);
    let groups = N.div_ceil(64) as u32;
    let out = gpu.run(
        src,
        &input,
        &[4 * ROUNDS, ROUNDS * N, 3 * ROUNDS * N],
        groups,
    );
    let (counters, items, info) = (&out[0], &out[1], &out[2]);
    for r in 0..ROUNDS {
        let keep = |x: u32| (x >> r).is_multiple_of(3);
        let total = input.iter().filter(|&&x| keep(x)).count();
        assert_eq!(counters[2 * r] as usize, total, "round {r}: total");
        // Lanes of each wave (subgroup or workgroup), by key.
        let mut waves: BTreeMap<u32, Vec<(u32, usize)>> = BTreeMap::new();
        for i in 0..N {
            let o = 3 * (r * N + i);
            waves.entry(info[o + 1]).or_default().push((info[o + 2], i));
        }
        let mut atomics = 0;
        for (key, mut lanes) in waves {
            lanes.sort_unstable();
            let width = wave_width_of(key);
            let active: LaneMask = lanes.iter().map(|&(l, _)| l).collect();
            let wave = Wave::with_active(width, active).expect("lanes within the width");
            let kept = wave.restrict(
                lanes
                    .iter()
                    .filter(|&&(_, i)| keep(input[i]))
                    .map(|&(l, _)| l)
                    .collect(),
            );
            // The CPU model, started where the device's atomic started for this wave.
            let base = lanes
                .iter()
                .map(|&(_, i)| info[3 * (r * N + i)])
                .min()
                .unwrap_or(NO_SLOT);
            let cpu = CountedAtomicU32::new(if kept.is_empty() { 0 } else { base });
            let reservation = kept.reserve(&cpu);
            atomics += cpu.atomic_ops();
            for &(lane, i) in &lanes {
                let slot = info[3 * (r * N + i)];
                assert_eq!(
                    reservation.slot(lane).unwrap_or(NO_SLOT),
                    slot,
                    "round {r}, wave {key}, lane {lane}"
                );
                if slot != NO_SLOT {
                    assert_eq!(items[r * N + slot as usize], input[i]);
                }
            }
        }
        assert_eq!(
            counters[2 * r + 1] as usize,
            atomics,
            "round {r}: one atomic per wave with a kept lane"
        );
    }
}

#[test]
fn subgroup_append_matches_the_cpu_model() {
    let gpu = gpu();
    if !gpu.has_subgroups() {
        eprintln!("adapter has no SUBGROUP; the subgroup path is not run");
        return;
    }
    let src = compaction_kernel(
        SUBGROUP_MODULE,
        "sg",
        "subgroupBroadcastFirst(gid.x)",
        "sg_lane",
        "@builtin(subgroup_invocation_id) sg_lane: u32, @builtin(subgroup_size) sg_size: u32",
    );
    let (lo, hi) = (gpu.info.subgroup_min_size, gpu.info.subgroup_max_size);
    eprintln!("subgroup sizes {lo}..{hi}");
    // Keys are the first invocation of each subgroup; the width is the subgroup size. With
    // varying sizes take the widest, which only loosens the width check.
    let width = WaveWidth::from_lanes(hi.clamp(8, 64)).expect("8, 16, 32 or 64 lanes");
    check_compaction(&gpu, &src, |_| width);
}

#[test]
fn workgroup_fallback_append_matches_the_cpu_model() {
    let gpu = gpu();
    let src = compaction_kernel(
        WORKGROUP_MODULE,
        "wg",
        "wid.x",
        "li",
        "@builtin(local_invocation_index) li: u32",
    );
    check_compaction(&gpu, &src, |_| WaveWidth::W64);
}

/// One pass source, written against the path-neutral `wave_append_*`, on both paths.
#[test]
fn one_pass_source_runs_on_both_paths() {
    let gpu = gpu();
    let pass = "
@group(0) @binding(0) var<storage, read> input: array<u32>;
@group(0) @binding(1) var<storage, read_write> counters: array<atomic<u32>>;
@group(0) @binding(2) var<storage, read_write> items: array<u32>;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) li: u32) {
    let n = arrayLength(&input);
    var x = 0u;
    if (gid.x < n) { x = input[gid.x]; }
    let a = wave_append_begin(gid.x < n && x % 3u == 0u, li);
    var old = 0u;
    if (a.total != 0u) { old = atomicAdd(&counters[0], a.total); atomicAdd(&counters[1], 1u); }
    let slot = wave_append_end(a, old);
    if (slot < n) { items[slot] = x; }
}";
    let input = words(N, 4242);
    let mut kept: Vec<u32> = input
        .iter()
        .copied()
        .filter(|x| x.is_multiple_of(3))
        .collect();
    kept.sort_unstable();
    let workgroups_with_hits = input
        .chunks(64)
        .filter(|c| c.iter().any(|x| x.is_multiple_of(3)))
        .count();
    for subgroups in [false, true] {
        if subgroups && !gpu.has_subgroups() {
            continue;
        }
        let src = format!("{}\n{pass}", module_for(subgroups));
        let out = gpu.run(&src, &input, &[2, N], N.div_ceil(64) as u32);
        assert_eq!(out[0][0] as usize, kept.len(), "subgroups {subgroups}");
        let mut got = out[1][..kept.len()].to_vec();
        got.sort_unstable();
        assert_eq!(got, kept, "subgroups {subgroups}");
        let atomics = out[0][1] as usize;
        if subgroups {
            let widest = gpu.info.subgroup_min_size.max(1) as usize;
            assert!(atomics >= workgroups_with_hits && atomics <= N.div_ceil(widest.min(64)));
        } else {
            assert_eq!(atomics, workgroups_with_hits);
        }
    }
}

/// Variable amounts (x % 5 items per invocation): ranges disjoint and covering [0, total),
/// one atomic per wave.
fn check_ranges(gpu: &Gpu, module: &str, path: &str, lane: &str, builtins: &str) {
    let src = format!(
        "{module}
@group(0) @binding(0) var<storage, read> input: array<u32>;
@group(0) @binding(1) var<storage, read_write> counters: array<atomic<u32>>;
@group(0) @binding(2) var<storage, read_write> starts: array<u32>;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, {builtins}) {{
    let n = arrayLength(&input);
    let i = gid.x;
    var amount = 0u;
    if (i < n) {{ amount = input[i] % 5u; }}
    let a = wave_{path}_append_n_begin(amount, {lane});
    var old = 0u;
    if (a.total != 0u) {{ old = atomicAdd(&counters[0], a.total); atomicAdd(&counters[1], 1u); }}
    let first = wave_{path}_append_end(a, old);
    if (i < n) {{ starts[i] = first; }}
}}"
    );
    let input = words(N, 777);
    let out = gpu.run(&src, &input, &[2, N], N.div_ceil(64) as u32);
    let (counters, starts) = (&out[0], &out[1]);
    let total: u32 = input.iter().map(|x| x % 5).sum();
    assert_eq!(counters[0], total);
    let mut ranges: Vec<(u32, u32)> = (0..N)
        .filter(|&i| !input[i].is_multiple_of(5))
        .map(|i| (starts[i], input[i] % 5))
        .collect();
    assert!(
        (0..N)
            .filter(|&i| input[i].is_multiple_of(5))
            .all(|i| starts[i] == NO_SLOT)
    );
    ranges.sort_unstable();
    let mut next = 0;
    for (s, n) in ranges {
        assert_eq!(s, next, "ranges must tile [0, total)");
        next += n;
    }
    assert_eq!(next, total);
    assert!(
        counters[1] as usize <= N.div_ceil(8),
        "aggregated: at most one atomic per 8 lanes"
    );
}

#[test]
fn variable_amount_appends_tile_the_output() {
    let gpu = gpu();
    check_ranges(
        &gpu,
        WORKGROUP_MODULE,
        "wg",
        "li",
        "@builtin(local_invocation_index) li: u32",
    );
    if gpu.has_subgroups() {
        check_ranges(
            &gpu,
            SUBGROUP_MODULE,
            "sg",
            "sg_lane",
            "@builtin(subgroup_invocation_id) sg_lane: u32",
        );
    }
}

#[test]
fn batch_output_matches_the_cpu_model() {
    let gpu = gpu();
    // Records: bit 0 group end, bit 1 visible, bits 2.. setup id. Two rounds of items.
    let rand = words(ROUNDS * N, 99);
    let mut setup = 0u32;
    let setups: Vec<u32> = rand
        .iter()
        .map(|r| {
            if r % 7 < 2 {
                setup += 1;
            }
            setup
        })
        .collect();
    let input: Vec<u32> = (0..ROUNDS * N)
        .map(|i| {
            let end = i + 1 == setups.len() || setups[i] != setups[i + 1];
            let visible = rand[i] >> 8 & 3 != 0; // 3/4 visible
            setups[i] << 2 | u32::from(visible) << 1 | u32::from(end)
        })
        .collect();
    let src = format!(
        "{WORKGROUP_MODULE}
@group(0) @binding(0) var<storage, read> input: array<u32>;
@group(0) @binding(1) var<storage, read_write> counters: array<atomic<u32>>;
@group(0) @binding(2) var<storage, read_write> instances: array<u32>;
@group(0) @binding(3) var<storage, read_write> batches: array<WaveBatch>;
@group(0) @binding(4) var<storage, read_write> info: array<u32>;
// The caller's own per-group accumulation: the largest setup id in the group.
var<workgroup> group_max: array<atomic<u32>, WAVE_WG_INVOCATIONS_MAX>;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) li: u32) {{
    let n = arrayLength(&input) / {ROUNDS}u;
    let i = gid.x;
    for (var r = 0u; r < {ROUNDS}u; r++) {{
        var rec = 0u;
        if (i < n) {{ rec = input[r * n + i]; }}
        let lane = wave_wg_batch_begin(i < n && (rec & 1u) != 0u, i < n && (rec & 2u) != 0u, li);
        var old = 0u;
        if (lane.instance.total != 0u) {{
            old = atomicAdd(&counters[4u * r], lane.instance.total);
            atomicAdd(&counters[4u * r + 1u], 1u);
        }}
        let slot = wave_wg_append_end(lane.instance, old);
        if (slot < n) {{ instances[r * n + slot] = rec; }}
        if (lane.instance.amount != 0u) {{ atomicMax(&group_max[lane.group], rec >> 2u); }}
        let hdr = wave_wg_batch_headers_begin(lane, li);
        var old_b = 0u;
        if (hdr.append.total != 0u) {{
            old_b = atomicAdd(&counters[4u * r + 2u], hdr.append.total);
            atomicAdd(&counters[4u * r + 3u], 1u);
        }}
        let b = wave_wg_append_end(hdr.append, old_b);
        if (b < n) {{
            batches[r * n + b] = WaveBatch(slot, hdr.instance_count);
            // The group's largest setup id must equal the writer's own (one setup per group).
            if (atomicLoad(&group_max[lane.group]) != (rec >> 2u)) {{ atomicAdd(&counters[8], 1u); }}
        }}
        if (hdr.append.amount != 0u) {{ atomicStore(&group_max[lane.group], 0u); }}
        if (i < n) {{ info[2u * (r * n + i)] = slot; info[2u * (r * n + i) + 1u] = b; }}
    }}
}}"
    );
    let groups = N.div_ceil(64) as u32;
    let out = gpu.run(
        &src,
        &input,
        &[9, ROUNDS * N, 2 * ROUNDS * N, 2 * ROUNDS * N],
        groups,
    );
    let (counters, instances, batches, info) = (&out[0], &out[1], &out[2], &out[3]);
    let batches: &[WaveBatch] = bytemuck::cast_slice(batches);
    assert_eq!(
        counters[8], 0,
        "per-group accumulation disagreed with the header writer"
    );
    for r in 0..ROUNDS {
        let recs = &input[r * N..(r + 1) * N];
        let (mut inst_total, mut batch_total, mut atomics) = (0, 0, 0);
        for (g, chunk) in recs.chunks(64).enumerate() {
            let wave = Wave::with_lane_count(WaveWidth::W64, chunk.len() as u32).unwrap();
            let ends = wave.ballot(|l| chunk[l as usize] & 1 != 0);
            let vis = wave.ballot(|l| chunk[l as usize] & 2 != 0);
            let lanes = || (0..chunk.len()).map(|l| (l, 2 * (r * N + g * 64 + l)));
            let base_i = lanes().map(|(_, o)| info[o]).min().unwrap();
            let base_b = lanes().map(|(_, o)| info[o + 1]).min().unwrap();
            let ci = CountedAtomicU32::new(if vis.is_empty() { 0 } else { base_i });
            let cb = CountedAtomicU32::new(if vis.is_empty() { 0 } else { base_b });
            let mut cpu_inst = vec![0u32; N];
            let mut cpu_hdr = vec![WaveBatch::default(); N];
            let o = wave.batch_output(ends, vis, &ci, &mut cpu_inst, &cb, &mut cpu_hdr, |l| {
                chunk[l as usize]
            });
            let (bi, ni) = (o.instances.base as usize, o.instances.count as usize);
            let (bb, nb) = (o.batches.base as usize, o.batches.count as usize);
            assert_eq!(
                &instances[r * N + bi..r * N + bi + ni],
                &cpu_inst[bi..bi + ni],
                "round {r} wg {g}"
            );
            assert_eq!(
                &batches[r * N + bb..r * N + bb + nb],
                &cpu_hdr[bb..bb + nb],
                "round {r} wg {g}"
            );
            inst_total += ni;
            batch_total += nb;
            atomics += ci.atomic_ops();
        }
        assert_eq!(counters[4 * r] as usize, inst_total);
        assert_eq!(counters[4 * r + 2] as usize, batch_total);
        assert_eq!(counters[4 * r + 1] as usize, atomics);
        assert_eq!(counters[4 * r + 3] as usize, atomics);
    }
}
