//! The WGSL twins run on a real device and checked against the CPU model: the subgroup
//! path (where the adapter has `Features::SUBGROUP`), the workgroup fallback, and the
//! run-grouped batch output, each called twice per dispatch so the shared scratch is
//! reused.
//!
//! Runs on testkit's device (lavapipe in CI, the H200 on the device machine); without an
//! adapter every test fails, saying how to install one.

use std::collections::BTreeMap;

use testkit::device::{Resource, ctx, has_subgroups, run_kernel};
use wave::{CountedAtomicU32, LaneMask, NO_SLOT, Wave, WaveBatch, WaveWidth};

/// Composes `src` (which imports wave's modules) with `features`, runs `main` over
/// `workgroups` workgroups with `input` at binding 0 and zeroed outputs of the given word
/// counts at bindings 1.., and returns the outputs.
fn run(
    src: &str,
    features: &[&str],
    input: &[u32],
    outputs: &[usize],
    workgroups: u32,
) -> Vec<Vec<u32>> {
    let src = shader::compose_source(&[wave::wgsl::MODULES], "wave test kernel", src, features)
        .unwrap_or_else(|e| panic!("{e}"));
    let mut resources = vec![Resource::Words(input)];
    resources.extend(outputs.iter().map(|&n| Resource::Zeros(n)));
    let mut out = run_kernel(&src, "main", &resources, [workgroups, 1, 1]);
    out.remove(0);
    out
}

fn words(n: usize, seed: u64) -> Vec<u32> {
    testkit::Rng::new(seed).words(n)
}

const N: usize = 64 * 37 + 13; // a partial last workgroup
const ROUNDS: usize = 2;

/// Two compaction rounds per invocation (predicates `(x >> r) % 3 == 0`), each through
/// counter `2r` with the atomics it issued counted in `2r + 1`. `info` gets, per round and
/// invocation: slot, wave key (which subgroup or workgroup), lane.
fn compaction_kernel(module: &str, path: &str, key: &str, lane: &str, builtins: &str) -> String {
    format!(
        "#import {module}
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

fn check_compaction(src: &str, wave_width_of: impl Fn(u32) -> WaveWidth) {
    let input = words(N, 12345);
    let groups = N.div_ceil(64) as u32;
    let out = run(
        src,
        &[],
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
    if !has_subgroups() {
        eprintln!(
            "{} has no SUBGROUP: the subgroup path is not run",
            ctx().adapter_line()
        );
        return;
    }
    let src = compaction_kernel(
        "wave::subgroup",
        "sg",
        "subgroupBroadcastFirst(gid.x)",
        "sg_lane",
        "@builtin(subgroup_invocation_id) sg_lane: u32, @builtin(subgroup_size) sg_size: u32",
    );
    let (lo, hi) = (ctx().info.subgroup_min_size, ctx().info.subgroup_max_size);
    eprintln!("subgroup sizes {lo}..{hi}");
    // Keys are the first invocation of each subgroup; the width is the subgroup size. With
    // varying sizes take the widest, which only loosens the width check.
    let width = WaveWidth::from_lanes(hi.clamp(8, 64)).expect("8, 16, 32 or 64 lanes");
    check_compaction(&src, |_| width);
}

#[test]
fn workgroup_fallback_append_matches_the_cpu_model() {
    let src = compaction_kernel(
        "wave::workgroup",
        "wg",
        "wid.x",
        "li",
        "@builtin(local_invocation_index) li: u32",
    );
    check_compaction(&src, |_| WaveWidth::W64);
}

/// One pass source, written against the path-neutral `wave_append_*`, on both paths.
#[test]
fn one_pass_source_runs_on_both_paths() {
    let pass = "#import wave::append
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
    for features in testkit::device::subgroup_variants() {
        let subgroups = !features.is_empty();
        let out = run(pass, features, &input, &[2, N], N.div_ceil(64) as u32);
        assert_eq!(out[0][0] as usize, kept.len(), "subgroups {subgroups}");
        let mut got = out[1][..kept.len()].to_vec();
        got.sort_unstable();
        assert_eq!(got, kept, "subgroups {subgroups}");
        let atomics = out[0][1] as usize;
        if subgroups {
            let widest = ctx().info.subgroup_min_size.max(1) as usize;
            assert!(atomics >= workgroups_with_hits && atomics <= N.div_ceil(widest.min(64)));
        } else {
            assert_eq!(atomics, workgroups_with_hits);
        }
    }
}

/// Variable amounts (x % 5 items per invocation): ranges disjoint and covering [0, total),
/// one atomic per wave.
fn check_ranges(module: &str, path: &str, lane: &str, builtins: &str) {
    let src = format!(
        "#import {module}
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
    let out = run(&src, &[], &input, &[2, N], N.div_ceil(64) as u32);
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
    check_ranges(
        "wave::workgroup",
        "wg",
        "li",
        "@builtin(local_invocation_index) li: u32",
    );
    if has_subgroups() {
        check_ranges(
            "wave::subgroup",
            "sg",
            "sg_lane",
            "@builtin(subgroup_invocation_id) sg_lane: u32",
        );
    }
}

#[test]
fn batch_output_matches_the_cpu_model() {
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
        "#import wave::workgroup
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
    let out = run(
        &src,
        &[],
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

/// `wave_ordered_f32` / `wave_unordered_f32` equal the Rust twins on random bit patterns
/// and the special values.
#[test]
fn ordered_float_words_match_the_cpu() {
    let mut input = words(4096, 77);
    input.extend(
        [
            0.0f32,
            -0.0,
            1.0,
            -1.0,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::MIN_POSITIVE,
        ]
        .map(f32::to_bits),
    );
    let n = input.len();
    let src = format!(
        "#import wave::common
@group(0) @binding(0) var<storage, read_write> input: array<u32>;
@group(0) @binding(1) var<storage, read_write> out: array<u32>;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {{
    let i = gid.x;
    if (i >= {n}u) {{ return; }}
    let w = wave_ordered_f32(bitcast<f32>(input[i]));
    out[2u * i] = w;
    out[2u * i + 1u] = bitcast<u32>(wave_unordered_f32(input[i]));
}}"
    );
    let out = run(&src, &[], &input, &[2 * n], (n as u32).div_ceil(64));
    for (i, &x) in input.iter().enumerate() {
        let f = f32::from_bits(x);
        if f.is_nan() {
            continue; // the device may quieten a NaN it passes through a float
        }
        assert_eq!(out[0][2 * i], wave::ordered_f32(f), "word of {f:e}");
        let back = wave::unordered_f32(x);
        if !back.is_nan() {
            assert_eq!(out[0][2 * i + 1], back.to_bits(), "float of {x:#x}");
        }
    }
}
