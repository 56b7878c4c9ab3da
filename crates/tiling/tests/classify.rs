//! The classification against the naive reference (tests/common), on random plans and
//! vis buffers: every phase's every output, both layouts, with and without a validity
//! mask, with garbage words. Plus the invariants stated in the issue, checked directly.

mod common;

use common::{NaiveInput, Rng, naive_classify, random_mask, random_scene, random_vis};
use proptest::prelude::*;
use tiling::{
    ClassifyConfig, Error, PlanConfig, VisBuffer, classify, classify_output, laydown_finalize,
    mid_classify, unpack_pixel_command,
};
use visbuf::VisLayout;
use wave::WaveWidth;

fn layout_of(vrs: bool) -> VisLayout {
    if vrs {
        VisLayout::Vrs
    } else {
        VisLayout::Standard
    }
}

/// Every valid pixel (by the naive decode) appears in exactly one command of its own
/// tile, pass and group; no wave mixes tiles, passes or groups.
fn check_invariants(input: &NaiveInput<'_>, c: &tiling::Classification) {
    let NaiveInput {
        words,
        valid,
        w,
        h,
        layout,
        table,
        passes,
        ..
    } = *input;
    let tiles_x = w.div_ceil(128);
    let mut seen = vec![0u8; words.len()];
    for wc in &c.output.waves {
        let (tx, ty) = wc.tile_xy();
        for k in 0..wc.command_count {
            let cmd = c.output.commands[(wc.first_command + k) as usize];
            let pixels: Vec<(u32, u32)> = if layout == VisLayout::Standard {
                vec![unpack_pixel_command(cmd)]
            } else {
                let (qx, qy, m) = tiling::unpack_quad_command(cmd);
                (0..4)
                    .filter(|b| (m >> b) & 1 == 1)
                    .map(|b| (2 * qx + (b & 1), 2 * qy + (b >> 1)))
                    .collect()
            };
            for (x, y) in pixels {
                let (gx, gy) = (tx * 128 + x, ty * 128 + y);
                assert!(gx < w && gy < h, "command outside the image");
                let i = (gy * w + gx) as usize;
                let mask_ok = valid.is_none_or(|m| (m[i / 32] >> (i % 32)) & 1 == 1);
                let (kind, hit) = common::naive_decode(words[i], mask_ok, layout, table, passes);
                assert_eq!(kind, 3, "command for a pixel that is not valid");
                let hit = hit.unwrap();
                assert_eq!(
                    (hit.pass, hit.group),
                    (wc.pass(), wc.batch_group()),
                    "wave mixes passes or groups"
                );
                seen[i] += 1;
            }
        }
        let _ = tiles_x;
    }
    for (i, &word) in words.iter().enumerate() {
        let mask_ok = valid.is_none_or(|m| (m[i / 32] >> (i % 32)) & 1 == 1);
        let (kind, _) = common::naive_decode(word, mask_ok, layout, table, passes);
        assert_eq!(
            seen[i],
            u8::from(kind == 3),
            "pixel {i} covered {} times",
            seen[i]
        );
    }
}

/// One random frame to classify.
struct Case {
    seed: u64,
    w: u32,
    h: u32,
    vrs: bool,
    with_mask: bool,
    wave: WaveWidth,
    /// Small plan limits: many passes and batch groups.
    small_limits: bool,
    /// At least this many batches (30 more at most, at random).
    min_batches: usize,
}

fn run_case(case: &Case) -> (tiling::PixelStats, u32) {
    let Case {
        seed,
        w,
        h,
        vrs,
        with_mask,
        wave,
        small_limits,
        min_batches,
    } = *case;
    let mut rng = Rng::new(seed);
    let layout = layout_of(vrs);
    let mut config = PlanConfig {
        layout,
        ..PlanConfig::default()
    };
    if small_limits {
        // Many passes and groups: split hard.
        config.max_micro_batch_vertices = 2000;
        config.max_batch_groups = 3;
        config.ring_bytes = 32 * 2 * 3000;
    }
    let batches = min_batches + rng.below(30) as usize;
    let scene = random_scene(&mut rng, batches, &config);
    let words = random_vis(&mut rng, &scene.plan, w, h, layout, 10);
    let mask = with_mask.then(|| random_mask(&mut rng, w, h, 80));
    let mut vis = VisBuffer::new(&words, w, h, layout).unwrap();
    if let Some(m) = &mask {
        vis = vis.with_validity(m).unwrap();
    }
    let cfg = ClassifyConfig::for_plan(&scene.plan, wave);
    let got = classify(&vis, &scene.plan.table, &scene.indices, &cfg).unwrap();
    let input = NaiveInput {
        words: &words,
        valid: mask.as_deref(),
        w,
        h,
        layout,
        table: &scene.plan.table,
        indices: &scene.indices,
        passes: cfg.pass_count,
        wave: wave.lanes(),
        chunk_count: cfg.chunk_count,
    };
    let want = naive_classify(&input);
    assert_eq!(got.masks, want.masks, "laydown finalise masks");
    assert_eq!(got.mid.counter_offsets, want.mid.counter_offsets);
    assert_eq!(got.mid.counts, want.mid.counts);
    assert_eq!(got.mid.pixel_offsets, want.mid.pixel_offsets);
    assert_eq!(
        got.mid.vertex_cull, want.mid.vertex_cull,
        "vertex cull buffer"
    );
    assert_eq!(got.mid.stats, want.mid.stats);
    assert_eq!(got.output.final_counts, want.output.final_counts);
    assert_eq!(got.output.commands, want.output.commands, "commands");
    assert_eq!(got.output.waves, want.output.waves, "wave commands");
    assert_eq!(got.output.wave_offsets, want.output.wave_offsets);
    assert_eq!(got.output.passes, want.output.passes);
    assert_eq!(got.output.stats, want.output.stats);
    assert_eq!(got, want);
    // The phases run one after another (as the GPU runs them) give the same.
    let phases = tiling::classify_phases(&vis, &scene.plan.table, &scene.indices, &cfg).unwrap();
    assert_eq!(phases, want, "classify_phases");
    assert_eq!(got.output.stats.pixels(), u64::from(w * h));
    check_invariants(&input, &got);
    (got.output.stats, cfg.pass_count)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn classification_equals_naive(
        seed: u64,
        w in 1u32..300,
        h in 1u32..300,
        vrs: bool,
        with_mask: bool,
        wave in 0usize..4,
        small_limits: bool,
    ) {
        let _ = run_case(&Case {
            seed,
            w,
            h,
            vrs,
            with_mask,
            wave: WaveWidth::ALL[wave],
            small_limits,
            min_batches: 1,
        });
    }
}

#[test]
fn multi_tile_frames_with_many_passes() {
    for seed in 0..4 {
        let vrs = seed % 2 == 1;
        let (stats, passes) = run_case(&Case {
            seed,
            w: 513,
            h: 260,
            vrs,
            with_mask: seed >= 2,
            wave: WaveWidth::W32,
            small_limits: true,
            min_batches: 40,
        });
        // The cases exercise what they claim: many passes, every kind of pixel, and VRS
        // samples shared between pixels.
        assert!(passes >= 5, "{passes} passes");
        assert!(
            stats.valid > 1000 && stats.empty > 1000 && stats.unknown > 0 && stats.out_of_range > 0,
            "{stats:?}"
        );
        if vrs {
            assert!(stats.commands < stats.valid, "{stats:?}");
        } else {
            assert_eq!(stats.commands, stats.valid);
        }
    }
}

#[test]
fn mid_counts_may_overestimate_and_output_uses_the_final_validity() {
    // Mid classify before the "geometry pass" (all pixels valid), output after it (half of
    // them cleared): counts stay as counted, final counts shrink, nothing is dropped.
    let mut rng = Rng::new(7);
    let scene = random_scene(&mut rng, 12, &PlanConfig::default());
    let (w, h) = (200, 150);
    let words = random_vis(&mut rng, &scene.plan, w, h, VisLayout::Standard, 0);
    let all = VisBuffer::new(&words, w, h, VisLayout::Standard).unwrap();
    let late_mask = random_mask(&mut rng, w, h, 50);
    let late = all.with_validity(&late_mask).unwrap();
    let cfg = ClassifyConfig::for_plan(&scene.plan, WaveWidth::W16);
    let (masks, _) = laydown_finalize(&all, &scene.plan.table, &cfg).unwrap();
    let mid = mid_classify(&all, &scene.plan.table, &scene.indices, &cfg, &masks).unwrap();
    let out = classify_output(&late, &scene.plan.table, &cfg, &masks, &mid).unwrap();
    assert_eq!(out.stats.dropped, 0);
    assert!(
        out.final_counts
            .iter()
            .zip(&mid.counts)
            .all(|(f, c)| f <= c)
    );
    assert!(out.stats.commands < mid.stats.commands);
    // The late classification by itself finds the same pixels in each counter.
    let alone = classify(&late, &scene.plan.table, &scene.indices, &cfg).unwrap();
    assert_eq!(out.stats.commands, alone.output.stats.commands);
    // Waves cover exactly the final counts.
    let covered: u32 = out.waves.iter().map(|w| w.command_count).sum();
    assert_eq!(covered, out.stats.commands);
}

#[test]
fn a_growing_validity_drops_what_has_no_room() {
    // The reverse of the talk's rule (validity only shrinks): pixels that appear after
    // mid classify have no counter room and are dropped and counted, never written past
    // their counter.
    let mut rng = Rng::new(11);
    let scene = random_scene(&mut rng, 8, &PlanConfig::default());
    let (w, h) = (130, 140);
    let words = random_vis(&mut rng, &scene.plan, w, h, VisLayout::Standard, 0);
    let early_mask = random_mask(&mut rng, w, h, 40);
    let early = VisBuffer::new(&words, w, h, VisLayout::Standard)
        .unwrap()
        .with_validity(&early_mask)
        .unwrap();
    let late = VisBuffer::new(&words, w, h, VisLayout::Standard).unwrap();
    let cfg = ClassifyConfig::for_plan(&scene.plan, WaveWidth::W8);
    let (masks, _) = laydown_finalize(&early, &scene.plan.table, &cfg).unwrap();
    let mid = mid_classify(&early, &scene.plan.table, &scene.indices, &cfg, &masks).unwrap();
    let out = classify_output(&late, &scene.plan.table, &cfg, &masks, &mid).unwrap();
    assert!(out.stats.dropped > 0);
    assert_eq!(out.stats.commands + out.stats.dropped, out.stats.valid);
    assert_eq!(out.final_counts, mid.counts);
}

#[test]
fn mismatched_inputs_are_errors() {
    let mut rng = Rng::new(3);
    let scene = random_scene(&mut rng, 5, &PlanConfig::default());
    let words = random_vis(&mut rng, &scene.plan, 64, 64, VisLayout::Standard, 0);
    let vis = VisBuffer::new(&words, 64, 64, VisLayout::Standard).unwrap();
    let cfg = ClassifyConfig::for_plan(&scene.plan, WaveWidth::W32);
    let c = classify(&vis, &scene.plan.table, &scene.indices, &cfg).unwrap();
    // Wrong sizes.
    assert!(matches!(
        VisBuffer::new(&words, 63, 64, VisLayout::Standard),
        Err(Error::BufferSize { .. })
    ));
    assert!(matches!(
        VisBuffer::new(&words, 0, 64, VisLayout::Standard),
        Err(Error::InvalidConfig { what: "width", .. })
    ));
    assert!(matches!(
        vis.with_validity(&[0; 3]),
        Err(Error::BufferSize {
            what: "validity mask",
            ..
        })
    ));
    let bad_passes = ClassifyConfig {
        pass_count: 257,
        ..cfg
    };
    assert!(matches!(
        laydown_finalize(&vis, &scene.plan.table, &bad_passes),
        Err(Error::InvalidConfig {
            what: "pass_count",
            ..
        })
    ));
    assert!(matches!(
        mid_classify(&vis, &scene.plan.table, &scene.indices, &cfg, &c.masks[1..]),
        Err(Error::BufferSize { .. })
    ));
    // Tampered phase outputs.
    let mut mid = c.mid.clone();
    if let Some(o) = mid.pixel_offsets.last_mut() {
        *o += 1;
        assert!(matches!(
            classify_output(&vis, &scene.plan.table, &cfg, &c.masks, &mid),
            Err(Error::MismatchedPhase { .. })
        ));
    }
    let mut masks = c.masks.clone();
    masks[0] ^= 1;
    assert!(matches!(
        classify_output(&vis, &scene.plan.table, &cfg, &masks, &c.mid),
        Err(Error::MismatchedPhase { .. })
    ));
}

#[test]
fn garbage_words_and_tables_are_counted_never_read_out_of_bounds() {
    let mut rng = Rng::new(99);
    let scene = random_scene(&mut rng, 6, &PlanConfig::default());
    let (w, h) = (100, 90);
    let words: Vec<u32> = (0..w * h).map(|_| rng.next_u64() as u32).collect();
    let vis = VisBuffer::new(&words, w, h, VisLayout::Standard).unwrap();
    // A table with broken rows: bad pass, bad group, ID outside its own range.
    let mut table = scene.plan.table.clone();
    for (k, row) in table.iter_mut().enumerate() {
        match k % 4 {
            0 => row.pass = 1000,
            1 => row.batch_group = 40,
            2 => row.first_id = row.first_id.wrapping_add(7),
            _ => {}
        }
    }
    let cfg = ClassifyConfig::for_plan(&scene.plan, WaveWidth::W64);
    let got = classify(
        &vis,
        &table,
        &scene.indices[..scene.indices.len() / 2],
        &cfg,
    )
    .unwrap();
    let want = naive_classify(&NaiveInput {
        words: &words,
        valid: None,
        w,
        h,
        layout: VisLayout::Standard,
        table: &table,
        indices: &scene.indices[..scene.indices.len() / 2],
        passes: cfg.pass_count,
        wave: 64,
        chunk_count: cfg.chunk_count,
    });
    assert_eq!(got, want);
    assert!(got.output.stats.unknown > 0);
}

#[test]
fn bad_indices_count_run_starts_as_the_naive_reference_does() {
    let mut rng = Rng::new(4242);
    let scene = random_scene(&mut rng, 12, &PlanConfig::default());
    let (w, h) = (300, 170);
    // Runs of equal words (random_vis's runs), half of them past a truncated index buffer.
    let words = random_vis(&mut rng, &scene.plan, w, h, VisLayout::Standard, 12);
    let indices = &scene.indices[..scene.indices.len() / 2];
    for masked in [false, true] {
        let mask = masked.then(|| random_mask(&mut rng, w, h, 70));
        let mut vis = VisBuffer::new(&words, w, h, VisLayout::Standard).unwrap();
        if let Some(m) = &mask {
            vis = vis.with_validity(m).unwrap();
        }
        let cfg = ClassifyConfig::for_plan(&scene.plan, WaveWidth::W32);
        let got = classify(&vis, &scene.plan.table, indices, &cfg).unwrap();
        let phases = tiling::classify_phases(&vis, &scene.plan.table, indices, &cfg).unwrap();
        let want = naive_classify(&NaiveInput {
            words: &words,
            valid: mask.as_deref(),
            w,
            h,
            layout: VisLayout::Standard,
            table: &scene.plan.table,
            indices,
            passes: cfg.pass_count,
            wave: 32,
            chunk_count: cfg.chunk_count,
        });
        assert_eq!(got, want, "fused, masked {masked}");
        assert_eq!(phases, want, "phases, masked {masked}");
        // Without vertex culling: the same but for the marks and the bad indices.
        let off = ClassifyConfig {
            vertex_cull: false,
            ..cfg
        };
        let mut unmarked = want.clone();
        unmarked.mid.vertex_cull.fill(0);
        unmarked.mid.stats.bad_indices = 0;
        let got = classify(&vis, &scene.plan.table, indices, &off).unwrap();
        assert_eq!(got, unmarked, "fused without culling, masked {masked}");
        let phases = tiling::classify_phases(&vis, &scene.plan.table, indices, &off).unwrap();
        assert_eq!(phases, unmarked, "phases without culling, masked {masked}");
        #[cfg(feature = "parallel")]
        {
            let par = tiling::parallel::classify(&vis, &scene.plan.table, indices, &off).unwrap();
            assert_eq!(par, unmarked, "parallel without culling, masked {masked}");
        }
        let bad = want.mid.stats.bad_indices;
        assert!(
            bad > 0 && bad < want.mid.stats.valid / 2,
            "runs make run starts rarer than bad pixels: {bad} of {} valid",
            want.mid.stats.valid
        );
    }
}
