//! The WGSL twins on a real device against the CPU twins, bit for bit: the three
//! classification phases (pixel commands compared after `canonical_sort`, everything else
//! as written) on both the subgroup path (where the adapter has `Features::SUBGROUP`) and
//! the workgroup fallback, the keyed histogram and the wave-append loop, both vis-word
//! layouts, with and without a validity mask (without one also over corrupt counts; with
//! one also changed since mid classify: HFW's mixed frame exactly, a grown mask in its
//! counts and stats); and
//! the vertex wave commands. The passes run through their descriptions (`tiling::wgsl`)
//! on testkit's device (lavapipe in CI); without an adapter every test fails, saying how to
//! install one.

mod common;

use common::{Rng, random_mask, random_scene, random_vis};
use testkit::device::{Data, run_pass, subgroup_variants};
use tiling::vertex::{DELTA_BLOCK, delta_block_count};
use tiling::wgsl::{CLASSIFY_OUTPUT, LAYDOWN_FINALIZE, MID_CLASSIFY, VERTEX_WAVES};
use tiling::{
    Classification, ClassifyConfig, PassDispatch, PixelStats, Plan, PlanConfig, TilingParams,
    Totals, UberChunk, VertexWaveCommand, VisBuffer, WaveCommand, canonical_sort, classify_output,
    classify_phases, laydown_finalize, mid_classify, pixel_command, unpack_pixel_command,
};
use visbuf::VisLayout;
use wave::WaveWidth;

/// The validity mask phases 1 and 2 see, against the final one classify output sees.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum MidMask {
    /// The final mask.
    Same,
    /// Every bit set: HFW's mixed frame (mid classify before the regular pass clears bits).
    AllSet,
    /// The final mask with about half its bits cleared: the mask grows after mid classify
    /// (the reverse of the talk's rule), overfilling counters.
    Sparser,
}

/// `n` zeroed elements of `T` (a whole number of words).
fn zeros<T>(n: usize) -> Data<'static> {
    const { assert!(size_of::<T>().is_multiple_of(4)) };
    Data::Zeros(size_of::<T>() / 4 * n)
}

#[expect(
    clippy::too_many_arguments,
    reason = "one test case's knobs, each passed by the loops that cover them"
)]
fn classification_case(
    features: &[&str],
    seed: u64,
    w: u32,
    h: u32,
    layout: VisLayout,
    masked: bool,
    mid_mask: MidMask,
    keyed: bool,
    vertex_cull: bool,
) {
    let mut rng = Rng::new(seed);
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
    let mid_mask = if masked { mid_mask } else { MidMask::Same };
    let early: Vec<u32> = match mid_mask {
        MidMask::Same => mask.clone(),
        MidMask::AllSet => vec![u32::MAX; mask.len()],
        MidMask::Sparser => {
            let keep = random_mask(&mut rng, w, h, 50);
            mask.iter().zip(&keep).map(|(m, k)| m & k).collect()
        }
    };
    let cfg = ClassifyConfig {
        vertex_cull,
        ..ClassifyConfig::for_plan(plan, WaveWidth::W16)
    };
    // Seed 2 truncates the index buffer: triangles past it count as bad indices.
    let indices = if seed == 2 {
        &scene.indices[..scene.indices.len() / 2 / 12 * 12]
    } else {
        &scene.indices[..]
    };
    let cpu = if mid_mask == MidMask::Same {
        classify_phases(&vis, &plan.table, indices, &cfg).unwrap()
    } else {
        let early_vis = VisBuffer::new(&words, w, h, layout)
            .unwrap()
            .with_validity(&early)
            .unwrap();
        let (masks, _) = laydown_finalize(&early_vis, &plan.table, &cfg).unwrap();
        let mid = mid_classify(&early_vis, &plan.table, indices, &cfg, &masks).unwrap();
        let output = classify_output(&vis, &plan.table, &cfg, &masks, &mid).unwrap();
        Classification { masks, mid, output }
    };
    let params = TilingParams::new(&vis, &cfg, plan.table.len() as u32, plan.order.len() as u32);
    let tiles = vis.tile_count() as usize;
    let p = cfg.pass_count as usize;
    if seed == 4 {
        assert!(
            tiles * p > 2 * tiling::wgsl::ENTRY_BLOCK as usize,
            "{tiles} tiles x {p} passes: too few entries for several blocks"
        );
    }
    let what = format!(
        "seed {seed} {w}x{h} {layout:?} masked {masked} {mid_mask:?} {features:?} keyed {keyed} vertex cull {vertex_cull}"
    );
    // `keyed` false forces the wave-append loop that tiles with more counters than the
    // keyed histogram holds take.
    let constants: &[(&str, f64)] = if keyed {
        &[]
    } else {
        &[("TILING_HIST_LIMIT", 0.0)]
    };
    let pixel_with = |valid| {
        [
            ("params", Data::Bytes(bytemuck::bytes_of(&params))),
            ("vis", Data::Words(&words)),
            ("valid", Data::Words(valid)),
            ("table", Data::rows(&plan.table)),
        ]
    };
    let pixel = pixel_with(&mask);
    // Phases 1 and 2 see the mask mid classify ran with.
    let pixel_mid = pixel_with(&early);
    fn joined<'a>(
        a: &[(&'static str, Data<'a>)],
        b: &[(&'static str, Data<'a>)],
    ) -> Vec<(&'static str, Data<'a>)> {
        a.iter().chain(b).copied().collect()
    }

    // Phase 1.
    let p1 = run_pass(
        &LAYDOWN_FINALIZE,
        &[],
        &[],
        &params,
        &joined(&pixel_mid, &[("masks", Data::Zeros(tiles * p))]),
    );
    let masks: Vec<u32> = p1.read("masks", tiles * p);
    assert_eq!(masks, cpu.masks, "masks, {what}");

    // Phase 2. Without vertex culling the pipeline without the vertex-cull code, as `gpu`
    // takes it.
    let mut mid_constants = constants.to_vec();
    if !vertex_cull {
        mid_constants.push(("TILING_VERTEX_CULL_CODE", 0.0));
    }
    let counters = cpu.mid.counter_count as usize;
    let p2 = run_pass(
        &MID_CLASSIFY,
        features,
        &mid_constants,
        &params,
        &joined(
            &pixel_mid,
            &[
                ("masks", Data::Words(&masks)),
                ("counter_offsets", Data::Zeros(tiles * p)),
                ("counts", Data::Zeros(counters)),
                ("pixel_offsets", Data::Zeros(counters)),
                (
                    "vertex_cull",
                    Data::Zeros((cfg.chunk_count as usize).div_ceil(4)),
                ),
                ("indices", Data::Words(indices)),
                ("totals", zeros::<Totals>(1)),
                ("stats", zeros::<PixelStats>(1)),
                (
                    "slots",
                    Data::Zeros(4 * tiling::wgsl::record_quads(w, h) as usize),
                ),
                (
                    "offset_scratch",
                    Data::Zeros(tiling::wgsl::offset_scratch_words(tiles as u32, p as u32) as usize),
                ),
            ],
        ),
    );
    let slots: Vec<u32> = p2.read("slots", 4 * tiling::wgsl::record_quads(w, h) as usize);
    assert_eq!(
        p2.read::<u32>("counter_offsets", tiles * p),
        cpu.mid.counter_offsets,
        "counter offsets, {what}"
    );
    assert_eq!(
        p2.read::<u32>("counts", counters),
        cpu.mid.counts,
        "counts, {what}"
    );
    let cull: Vec<u8> = p2
        .read::<u32>("vertex_cull", cpu.mid.vertex_cull.len() / 4)
        .iter()
        .flat_map(|w| w.to_le_bytes())
        .collect();
    assert_eq!(cull, cpu.mid.vertex_cull, "vertex cull buffer, {what}");
    let totals: Vec<Totals> = p2.read("totals", 1);
    assert_eq!(totals[0].counter_count, cpu.mid.counter_count, "{what}");
    assert_eq!(
        p2.read::<PixelStats>("stats", 1)[0],
        cpu.mid.stats,
        "mid stats, {what}"
    );
    if !vertex_cull {
        assert!(cull.iter().all(|&b| b == 0), "{what}: chunks marked");
        assert_eq!(cpu.mid.stats.bad_indices, 0, "{what}");
    } else if seed == 2 {
        assert!(
            cpu.mid.stats.bad_indices > 0,
            "{what}: the truncated case has bad indices"
        );
    }

    // Phase 3.
    let commands = cpu.mid.command_count as usize;
    let p3 = run_pass(
        &CLASSIFY_OUTPUT,
        features,
        constants,
        &params,
        &joined(
            &pixel,
            &[
                ("masks", Data::Words(&masks)),
                ("counter_offsets", Data::Words(&cpu.mid.counter_offsets)),
                ("counts", Data::Words(&cpu.mid.counts)),
                ("pixel_offsets", Data::Zeros(counters)),
                ("final_counts", Data::Zeros(counters)),
                ("commands", Data::Zeros(commands.div_ceil(2))),
                ("wave_offsets", Data::Zeros(counters)),
                ("waves", zeros::<WaveCommand>(cpu.output.waves.len() + 1)),
                ("passes", zeros::<PassDispatch>(p)),
                // Phase 2's counter count.
                ("totals", Data::rows(&totals)),
                ("stats", zeros::<PixelStats>(1)),
                (
                    "wave_scratch",
                    Data::Zeros(tiling::wgsl::wave_scratch_words(tiles as u32, p as u32) as usize),
                ),
                ("slots", Data::Words(&slots)),
                ("mid_stats", Data::Bytes(bytemuck::bytes_of(&cpu.mid.stats))),
            ],
        ),
    );
    assert_eq!(
        p3.read::<u32>("pixel_offsets", counters),
        cpu.mid.pixel_offsets,
        "pixel offsets, {what}"
    );
    let finals: Vec<u32> = p3.read("final_counts", counters);
    assert_eq!(finals, cpu.output.final_counts, "final counts, {what}");
    if mid_mask == MidMask::Sparser {
        // Pixels that appeared after mid classify overfill their counters, and which of a
        // counter's commands find room follows the order of the workgroups' atomics: the
        // counts are fixed, the commands kept are not.
        assert_eq!(
            p3.read::<PixelStats>("stats", 1)[0],
            cpu.output.stats,
            "output stats, {what}"
        );
        assert!(cpu.output.stats.dropped > 0, "{what}: nothing overfilled");
        return;
    }
    let mut cmds: Vec<u16> = p3
        .read::<u32>("commands", commands.div_ceil(2))
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
        p3.read::<u32>("wave_offsets", counters),
        cpu.output.wave_offsets,
        "wave offsets, {what}"
    );
    assert_eq!(
        p3.read::<WaveCommand>("waves", cpu.output.waves.len()),
        cpu.output.waves,
        "wave commands, {what}"
    );
    assert_eq!(
        p3.read::<PassDispatch>("passes", p),
        cpu.output.passes,
        "pass dispatches, {what}"
    );
    let totals3 = p3.read::<Totals>("totals", 1)[0];
    assert_eq!(
        totals3.wave_count as usize,
        cpu.output.waves.len(),
        "{what}"
    );
    assert_eq!(totals3.command_count, cpu.mid.command_count, "{what}");
    assert_eq!(
        p3.read::<PixelStats>("stats", 1)[0],
        cpu.output.stats,
        "output stats, {what}"
    );

    if !masked {
        corrupt_counts_case(
            &what, &params, &pixel, &masks, &cpu, &totals, &slots, features, constants,
        );
    }

    // Vertex wave commands from the cull buffer.
    let vertex_waves = vertex_waves_case(&what, &params, plan, &cpu.mid.vertex_cull);
    eprintln!(
        "{what}: {} valid pixels, {} counters, {} commands, {} waves, {} vertex waves: equal",
        cpu.output.stats.valid,
        counters,
        commands,
        cpu.output.waves.len(),
        vertex_waves
    );
}

/// `tiling::wgsl::VERTEX_WAVES` over the cull buffer `cull` of `plan` against the CPU twin,
/// every output; returns the vertex waves (visible chunks).
fn vertex_waves_case(what: &str, params: &TilingParams, plan: &Plan, cull: &[u8]) -> usize {
    let v = common::plan_vertex_waves(plan, cull);
    let chunks = plan.chunk_count as usize;
    let ubers = chunks.div_ceil(64);
    let p4 = run_pass(
        &VERTEX_WAVES,
        &[],
        &[],
        params,
        &[
            ("params", Data::Bytes(bytemuck::bytes_of(params))),
            ("table", Data::rows(&plan.table)),
            ("order", Data::Words(&plan.order)),
            ("pass_infos", Data::rows(&plan.passes)),
            ("vertex_cull", Data::Bytes(cull)),
            ("ubers", zeros::<UberChunk>(ubers)),
            ("pyramid", Data::Zeros(v.pyramid.data.len())),
            ("deltas", Data::Zeros(chunks)),
            ("micro_batch_waves", Data::Zeros(plan.order.len())),
            ("vertex_commands", zeros::<VertexWaveCommand>(chunks)),
            (
                "vertex_dispatches",
                zeros::<PassDispatch>(plan.passes.len()),
            ),
            ("pass_items", Data::Zeros(plan.passes.len())),
            ("totals", zeros::<Totals>(1)),
            (
                "delta_blocks",
                Data::Zeros(delta_block_count(plan.chunk_count) as usize),
            ),
        ],
    );
    assert_eq!(
        p4.read::<UberChunk>("ubers", ubers),
        v.ubers,
        "uber chunks, {what}"
    );
    assert_eq!(
        p4.read::<u32>("pyramid", v.pyramid.data.len()),
        v.pyramid.data,
        "pyramid, {what}"
    );
    let ids: Vec<u32> = v.commands.iter().map(|c| c.micro_batch).collect();
    assert_eq!(
        p4.read::<u32>("deltas", ids.len()),
        ids,
        "scanned deltas, {what}"
    );
    assert_eq!(
        p4.read::<u32>("micro_batch_waves", plan.order.len()),
        v.micro_batch_waves,
        "micro-batch waves, {what}"
    );
    assert_eq!(
        p4.read::<VertexWaveCommand>("vertex_commands", v.commands.len()),
        v.commands,
        "vertex wave commands, {what}"
    );
    assert_eq!(
        p4.read::<PassDispatch>("vertex_dispatches", plan.passes.len()),
        v.passes,
        "vertex dispatches, {what}"
    );
    assert_eq!(
        p4.read::<Totals>("totals", 1)[0].visible_chunks as usize,
        v.commands.len(),
        "visible chunks, {what}"
    );
    v.commands.len()
}

/// Classify output without a validity mask over corrupt counts (every third counter's
/// halved after phase 2): the commands mid classify recorded past their counter's count
/// find no room and move from commands to dropped, nothing is written past a counter's
/// commands, and the rest stand: each counter holds its own commands (a sub-multiset of
/// the CPU twin's), the offsets and final counts follow the corrupt counts. The reference
/// is the records themselves (`tiling::wgsl::RECORD_*`), read independently of the scatter.
/// Run twice: with this frame's mid stats, and with another frame's that counted fewer
/// commands than get lost, where commands stop at 0 instead of wrapping.
#[expect(
    clippy::too_many_arguments,
    reason = "the case's phase-2 results, passed on as they are"
)]
fn corrupt_counts_case(
    what: &str,
    params: &TilingParams,
    pixel: &[(&'static str, Data<'_>)],
    masks: &[u32],
    cpu: &Classification,
    totals: &[Totals],
    slots: &[u32],
    features: &[&str],
    constants: &[(&str, f64)],
) {
    use tiling::wgsl::{
        RECORD_COMMAND, RECORD_COUNTER_MASK, RECORD_COUNTER_SHIFT, RECORD_SLOT_MASK,
    };
    let counts: Vec<u32> = (cpu.mid.counts.iter().enumerate())
        .map(|(i, &n)| if i % 3 == 0 { n / 2 } else { n })
        .collect();
    let p = params.pass_count as usize;
    // The reference: each recorded command's counter and slot.
    let quads_x = params.width.div_ceil(2) as usize;
    let mut lost = 0u32;
    for (i, &r) in slots.iter().enumerate() {
        if r & RECORD_COMMAND == 0 {
            continue;
        }
        let (q, k) = (i / 4, i % 4);
        let x = 2 * (q % quads_x) + k % 2;
        let y = 2 * (q / quads_x) + k / 2;
        let tile = y / 128 * params.tiles_x as usize + x / 128;
        let c = cpu.mid.counter_offsets[tile * p] as usize
            + ((r >> RECORD_COUNTER_SHIFT) & RECORD_COUNTER_MASK) as usize;
        if r & RECORD_SLOT_MASK >= counts[c] {
            lost += 1;
        }
    }
    assert!(lost > 0, "{what}: the halved counts lose commands");
    // Mid stats as this frame's count_pixels wrote them, then stale ones (another frame's)
    // that counted fewer commands than get lost: the count stops at 0 instead of wrapping.
    let stale = PixelStats {
        commands: lost / 2,
        ..cpu.mid.stats
    };
    let counters = counts.len();
    let tiles = (params.tiles_x * params.tiles_y) as usize;
    let offsets: Vec<u32> = counts
        .iter()
        .scan(0u32, |run, &n| {
            let o = *run;
            *run += n;
            Some(o)
        })
        .collect();
    let commands: usize = counts.iter().map(|&n| n as usize).sum();
    let waves: u32 = counts.iter().map(|n| n.div_ceil(params.wave_width)).sum();
    // One guard word past the commands and one guard wave past the waves.
    let words = commands.div_ceil(2) + 1;
    for mid in [cpu.mid.stats, stale] {
        let p3 = run_pass(
            &CLASSIFY_OUTPUT,
            features,
            constants,
            params,
            &pixel
                .iter()
                .copied()
                .chain([
                    ("masks", Data::Words(masks)),
                    ("counter_offsets", Data::Words(&cpu.mid.counter_offsets)),
                    ("counts", Data::Words(&counts)),
                    ("pixel_offsets", Data::Zeros(counters)),
                    ("final_counts", Data::Zeros(counters)),
                    ("commands", Data::Zeros(words)),
                    ("wave_offsets", Data::Zeros(counters)),
                    ("waves", zeros::<WaveCommand>(waves as usize + 1)),
                    ("passes", zeros::<PassDispatch>(p)),
                    ("totals", Data::rows(totals)),
                    ("stats", zeros::<PixelStats>(1)),
                    (
                        "wave_scratch",
                        Data::Zeros(
                            tiling::wgsl::wave_scratch_words(tiles as u32, p as u32) as usize
                        ),
                    ),
                    ("slots", Data::Words(slots)),
                    ("mid_stats", Data::Bytes(bytemuck::bytes_of(&mid))),
                ])
                .collect::<Vec<_>>(),
        );
        assert_eq!(p3.read::<u32>("pixel_offsets", counters), offsets, "{what}");
        assert_eq!(p3.read::<u32>("final_counts", counters), counts, "{what}");
        let written: Vec<u32> = p3.read("commands", words);
        assert_eq!(written[words - 1], 0, "{what}: a command past the last one");
        let got: Vec<u16> = written
            .iter()
            .flat_map(|w| [*w as u16, (*w >> 16) as u16])
            .collect();
        for c in 0..counters {
            let mut mine: Vec<u16> = got[offsets[c] as usize..][..counts[c] as usize].to_vec();
            let o = cpu.mid.pixel_offsets[c] as usize;
            let mut all: Vec<u16> = cpu.output.commands[o..][..cpu.mid.counts[c] as usize].to_vec();
            mine.sort_unstable();
            all.sort_unstable();
            // `mine` within `all`, as multisets (both sorted).
            let mut rest = all.iter();
            for m in &mine {
                assert!(
                    rest.any(|a| a == m),
                    "{what}: counter {c} holds a command that is not its own: {m:#x}"
                );
            }
        }
        let stats = p3.read::<PixelStats>("stats", 1)[0];
        assert_eq!(
            stats,
            PixelStats {
                commands: mid.commands.saturating_sub(lost),
                dropped: mid.dropped + lost,
                bad_indices: 0,
                ..mid
            },
            "{what}: {lost} lost, mid classify counted {} commands",
            mid.commands
        );
        let totals3 = p3.read::<Totals>("totals", 1)[0];
        assert_eq!(totals3.wave_count, waves, "{what}");
        assert_eq!(totals3.command_count as usize, commands, "{what}");
        assert_eq!(
            p3.read::<WaveCommand>("waves", waves as usize + 1)[waves as usize],
            WaveCommand::default(),
            "{what}: a wave past the last one"
        );
    }
}

#[test]
fn gpu_passes_equal_the_cpu_twins() {
    for (seed, (w, h)) in [(1u64, (300u32, 200u32)), (2, (129, 257)), (3, (64, 48))] {
        for layout in [VisLayout::Standard, VisLayout::Vrs] {
            for masked in [false, true] {
                for keyed in [true, false] {
                    for features in subgroup_variants() {
                        classification_case(
                            features,
                            seed,
                            w,
                            h,
                            layout,
                            masked,
                            MidMask::Same,
                            keyed,
                            true,
                        );
                    }
                }
            }
        }
    }
    // More (tile, pass) entries than one workgroup of classify output's entry_waves sums
    // (tiling::wgsl::ENTRY_BLOCK): the blocks' first waves come from its last workgroup.
    for features in subgroup_variants() {
        // With a validity mask entry_waves alone, without one entry_waves' blocks after
        // pixel_offsets_pass' workgroup in pixel_offsets_entry_waves.
        for masked in [true, false] {
            classification_case(
                features,
                4,
                1700,
                1300,
                VisLayout::Standard,
                masked,
                MidMask::Same,
                true,
                true,
            );
        }
    }
    // Without vertex culling (no index reads): the cull buffer stays zero and no bad
    // indices are counted, though seed 2's index buffer is truncated.
    for features in subgroup_variants() {
        for layout in [VisLayout::Standard, VisLayout::Vrs] {
            classification_case(
                features,
                2,
                129,
                257,
                layout,
                false,
                MidMask::Same,
                true,
                false,
            );
        }
    }
    // The mask changes between mid classify and classify output: HFW's mixed frame (every
    // bit set at mid classify; classify output's write_commands then takes phase 2's
    // records where it can) and a mask that grows (pixels without a record).
    for features in subgroup_variants() {
        for (seed, (w, h)) in [(1u64, (300u32, 200u32)), (3, (64, 48))] {
            for layout in [VisLayout::Standard, VisLayout::Vrs] {
                for mid_mask in [MidMask::AllSet, MidMask::Sparser] {
                    for keyed in [true, false] {
                        classification_case(
                            features, seed, w, h, layout, true, mid_mask, keyed, true,
                        );
                    }
                }
            }
        }
    }
}

/// The vertex wave commands of a scene with hundreds of thousands of chunks against the
/// CPU twin: the deltas' prefix sum runs over many blocks (`tiling::vertex::DELTA_BLOCK`),
/// more than one per invocation of its block scan, with visible chunks dense, sparse and
/// absent over whole micro batches (their deltas share the next one's position).
#[test]
fn vertex_waves_over_many_blocks() {
    let mut rng = Rng::new(17);
    let config = PlanConfig {
        ring_bytes: 32 * 2 * 1_000_000,
        ..PlanConfig::default()
    };
    let scene = random_scene(&mut rng, 1500, &config);
    let plan = &scene.plan;
    let cfg = ClassifyConfig::for_plan(plan, WaveWidth::W16);
    let params = TilingParams::for_frame(
        (64, 64),
        VisLayout::Standard,
        false,
        &cfg,
        plan.table.len() as u32,
        plan.order.len() as u32,
    );
    // Per micro batch a density: none visible, a few, most, all.
    let mut cull = vec![0u8; plan.chunk_count as usize];
    for row in &plan.table {
        let percent = [0, 3, 60, 100][rng.below(4) as usize];
        let first = row.first_chunk as usize;
        let end = (first + row.chunk_count() as usize).min(cull.len());
        for c in &mut cull[first..end] {
            *c = u8::from(rng.chance(percent));
        }
    }
    let visible = vertex_waves_case("many blocks", &params, plan, &cull);
    let blocks = visible.div_ceil(DELTA_BLOCK as usize);
    assert!(
        blocks > 256,
        "{visible} visible chunks of {}: {blocks} blocks, too few to cover the block scan",
        plan.chunk_count
    );
    eprintln!(
        "{visible} visible chunks of {} in {blocks} blocks: equal",
        plan.chunk_count
    );
}

/// `tiling`'s WGSL unpack helpers (what the `gpu` resolve uses to find a wave command's
/// pixels) against the Rust definitions of the same layouts.
#[test]
fn command_and_tile_unpacking_match_the_cpu() {
    let mut rng = Rng::new(0x7469_6c65);
    let mut input = Vec::new();
    for i in 0..20_000u32 {
        // A packed pair of commands, an index choosing one, and a wave command's tile word.
        let (a, b) = if i % 3 == 0 {
            (rng.next_u32() & 0xffff, rng.next_u32() & 0xffff)
        } else {
            (
                u32::from(pixel_command(rng.next_u32() % 128, rng.next_u32() % 128)),
                u32::from(pixel_command(i % 128, (i / 128) % 128)),
            )
        };
        let tile = (rng.next_u32() % 300)
            | ((rng.next_u32() % 200) << tiling::classify::WAVE_TILE_Y_SHIFT);
        input.extend_from_slice(&[a | (b << 16), i, tile]);
    }
    let n = (input.len() / 3) as u32;
    let body = "
    let word = input[3u * i];
    let k = input[3u * i + 1u];
    let cmd = tiling_command_in_word(word, k);
    let xy = tiling_unpack_pixel_command(cmd);
    let t = tiling_wave_tile_xy(input[3u * i + 2u]);
    output[5u * i] = cmd;
    output[5u * i + 1u] = xy.x;
    output[5u * i + 2u] = xy.y;
    output[5u * i + 3u] = t.x;
    output[5u * i + 4u] = t.y;";
    let out = testkit::device::run_words(
        &[tiling::wgsl::MODULES],
        "#import tiling::common",
        body,
        &input,
        n,
        5,
        &[],
    );
    for (j, item) in input.chunks_exact(3).enumerate() {
        let (word, k, tile) = (item[0], item[1], item[2]);
        let cmd = if k % 2 == 0 {
            word as u16
        } else {
            (word >> 16) as u16
        };
        let (x, y) = unpack_pixel_command(cmd);
        let wave = WaveCommand {
            tile,
            ..WaveCommand::default()
        };
        let (tx, ty) = wave.tile_xy();
        assert_eq!(
            &out[5 * j..5 * j + 5],
            &[u32::from(cmd), x, y, tx, ty],
            "word {word:#x} index {k} tile {tile:#x}"
        );
    }
}

/// `tiling::common`'s saturating product (the chunk arithmetic of mid classify and the
/// vertex waves) against a 64-bit product, on random operands of every bit length and the
/// edges of the wrap.
#[test]
fn saturating_product_matches_a_64_bit_one() {
    let mut rng = Rng::new(0x6d75_6c73);
    let mut input = Vec::new();
    let edges = [
        0u32,
        1,
        2,
        65_535,
        65_536,
        65_537,
        0xffff_ffff,
        0x8000_0000,
        4_294_967_295 / 3,
    ];
    for &a in &edges {
        for &b in &edges {
            input.extend_from_slice(&[a, b]);
        }
    }
    for _ in 0..20_000 {
        let a = rng.next_u32() >> (rng.next_u32() % 32);
        let b = rng.next_u32() >> (rng.next_u32() % 32);
        input.extend_from_slice(&[a, b]);
    }
    // Products just below and at 2^32.
    input.extend_from_slice(&[
        65_536,
        65_535,
        65_536,
        65_536,
        4_294_967_295,
        1,
        3,
        1_431_655_765,
        3,
        1_431_655_766,
    ]);
    let n = (input.len() / 2) as u32;
    let out = testkit::device::run_words(
        &[tiling::wgsl::MODULES],
        "#import tiling::common",
        "output[i] = tiling_mul_sat(input[2u * i], input[2u * i + 1u]);",
        &input,
        n,
        1,
        &[],
    );
    for (j, pair) in input.chunks_exact(2).enumerate() {
        let p = u64::from(pair[0]) * u64::from(pair[1]);
        let want = u32::try_from(p).unwrap_or(u32::MAX);
        assert_eq!(out[j], want, "{} * {}", pair[0], pair[1]);
    }
}
