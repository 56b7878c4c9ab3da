//! Vertex wave commands against a naive list of visible chunks, the histogram pyramid's
//! two mappings against linear scans, and the measurements against plain counts.

mod common;

use common::{Rng, plan_vertex_waves, random_scene, random_vis};
use proptest::prelude::*;
use tiling::vertex::{HistogramPyramid, UberChunk, nth_set_bit, pyramid_levels, uber_chunks};
use tiling::{
    ClassifyConfig, Error, PassDispatch, PlanConfig, VisBuffer, classify, measure,
    vertex_wave_commands,
};
use visbuf::VisLayout;
use wave::WaveWidth;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn pyramid_maps_both_ways_like_a_linear_scan(counts in proptest::collection::vec(0u32..=64, 0..300)) {
        let hp = HistogramPyramid::build(&counts);
        let total: u32 = counts.iter().sum();
        prop_assert_eq!(hp.total(), total);
        // prefix(u) = sum of counts before u.
        let mut before = 0;
        for (u, &c) in counts.iter().enumerate() {
            prop_assert_eq!(hp.prefix(u as u32), before);
            before += c;
        }
        prop_assert_eq!(hp.prefix(counts.len() as u32), total);
        // locate(i) = the entry whose running range holds i.
        let mut i = 0;
        for (u, &c) in counts.iter().enumerate() {
            for r in 0..c {
                prop_assert_eq!(hp.locate(i), Some((u as u32, r)));
                i += 1;
            }
        }
        prop_assert_eq!(hp.locate(total), None);
        // Level sizes shrink by the fan-out to one.
        let levels = pyramid_levels(counts.len() as u32);
        prop_assert_eq!(levels.last().unwrap().1, 1);
        prop_assert_eq!(hp.data.len() as u32, levels.iter().map(|l| l.1).sum::<u32>());
    }

    #[test]
    fn uber_chunks_and_nth_bit(cull in proptest::collection::vec(0u8..3, 0..700), n in 0u32..70) {
        let ubers = uber_chunks(&cull, cull.len() as u32);
        prop_assert_eq!(ubers.len(), cull.len().div_ceil(64));
        for (u, uc) in ubers.iter().enumerate() {
            let set: Vec<u32> = (0..64).filter(|&j| cull.get(u * 64 + j as usize).is_some_and(|&b| b != 0)).collect();
            prop_assert_eq!(uc.count as usize, set.len());
            prop_assert_eq!(nth_set_bit(uc.mask(), n), set.get(n as usize).copied().unwrap_or(64));
        }
    }
}

/// Naive: walk the cull buffer, find each visible chunk's micro batch by a linear search.
fn naive_commands(cull: &[u8], plan: &tiling::Plan) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    for c in 0..plan.chunk_count {
        if cull[c as usize] == 0 {
            continue;
        }
        let mb = plan
            .micro_batches
            .iter()
            .find(|m| c >= m.first_chunk && c < m.first_chunk + m.chunk_count())
            .expect("every chunk belongs to a micro batch");
        out.push((mb.first_id, c - mb.first_chunk));
    }
    out
}

#[test]
fn vertex_waves_equal_a_naive_walk_of_the_cull_buffer() {
    for seed in 0..40u64 {
        let mut rng = Rng::new(seed);
        let config = PlanConfig {
            max_micro_batch_vertices: 3000,
            ring_bytes: 32 * 2 * 9000,
            ..PlanConfig::default()
        };
        let n = 1 + rng.below(25) as usize;
        let scene = random_scene(&mut rng, n, &config);
        let plan = &scene.plan;
        // A random cull buffer, sparse or dense.
        let density = rng.below(101);
        let cull: Vec<u8> = (0..plan.chunk_count)
            .map(|_| u8::from(rng.chance(density)))
            .collect();
        let v = plan_vertex_waves(plan, &cull);
        let got: Vec<(u32, u32)> = v
            .commands
            .iter()
            .map(|c| (c.micro_batch, c.chunk))
            .collect();
        let want = naive_commands(&cull, plan);
        assert_eq!(got, want, "seed {seed}");
        // Deltas: their running sum is each command's micro batch.
        let mut id = 0u32;
        for (d, c) in v.deltas.iter().zip(&v.commands) {
            id = id.wrapping_add(*d);
            assert_eq!(id, c.micro_batch);
        }
        // Per micro batch and per pass.
        for (k, mb) in plan.micro_batches.iter().enumerate() {
            let n = want.iter().filter(|c| c.0 == mb.first_id).count() as u32;
            assert_eq!(v.micro_batch_waves[k], n);
        }
        let mut first = 0;
        for (p, pass) in plan.passes.iter().enumerate() {
            let mine: Vec<&(u32, u32)> = want
                .iter()
                .filter(|c| plan.table[c.0 as usize].pass == p as u32)
                .collect();
            let items: u32 = mine
                .iter()
                .map(|c| {
                    let r = plan.table[c.0 as usize];
                    (r.instance_count * r.vertex_count - 64 * c.1).min(64)
                })
                .sum();
            let count = mine.len() as u32;
            assert_eq!(
                v.passes[p],
                PassDispatch {
                    x: count.min(65535),
                    y: count.div_ceil(65535),
                    z: u32::from(count > 0),
                    first,
                    count,
                    items
                }
            );
            let _ = pass;
            first += count;
        }
    }
}

#[test]
fn inconsistent_inputs_are_errors() {
    let mut rng = Rng::new(5);
    let scene = random_scene(&mut rng, 10, &PlanConfig::default());
    let plan = &scene.plan;
    let cull = vec![1u8; plan.chunk_count as usize];
    assert!(matches!(
        vertex_wave_commands(
            &cull[..cull.len() / 2],
            plan.chunk_count,
            &plan.table,
            &plan.order,
            &plan.passes
        ),
        Err(Error::BufferSize { .. })
    ));
    if plan.order.len() > 1 {
        let mut order = plan.order.clone();
        order.reverse();
        assert!(matches!(
            vertex_wave_commands(&cull, plan.chunk_count, &plan.table, &order, &plan.passes),
            Err(Error::MismatchedPhase { .. })
        ));
    }
    let bad = vec![u32::MAX];
    assert!(matches!(
        vertex_wave_commands(&cull, plan.chunk_count, &plan.table, &bad, &plan.passes),
        Err(Error::MismatchedPhase { .. })
    ));
    // An empty frame: no chunks, no commands.
    let v = vertex_wave_commands(&[], 0, &[], &[], &[]).unwrap();
    assert!(v.commands.is_empty() && v.ubers.is_empty());
    assert_eq!(UberChunk::default().mask(), 0);
}

#[test]
fn measurements_match_plain_counts() {
    let mut rng = Rng::new(21);
    let scene = random_scene(&mut rng, 20, &PlanConfig::default());
    let plan = &scene.plan;
    let (w, h) = (257, 190);
    for layout in [VisLayout::Standard, VisLayout::Vrs] {
        let words = random_vis(&mut rng, plan, w, h, layout, 5);
        let vis = VisBuffer::new(&words, w, h, layout).unwrap();
        let config = ClassifyConfig::for_plan(plan, WaveWidth::W32);
        let c = classify(&vis, &plan.table, &scene.indices, &config).unwrap();
        let v = plan_vertex_waves(plan, &c.mid.vertex_cull);
        let m = measure(&vis, &plan.table, &config, &c, &v).unwrap();
        // Deferred side: the wave commands and their lanes.
        assert_eq!(m.deferred_waves, c.output.waves.len() as u64);
        let filled: u64 = c
            .output
            .waves
            .iter()
            .map(|w| u64::from(w.command_count))
            .sum();
        assert_eq!(m.shaded_samples, filled);
        assert!(
            (m.unfilled_lane_fraction() - (1.0 - filled as f64 / (32.0 * m.deferred_waves as f64)))
                .abs()
                < 1e-12
        );
        // Depth equal: distinct (quad, word without rate) per draw, by a set per draw.
        let mut per_batch: std::collections::BTreeMap<
            u32,
            std::collections::BTreeSet<(u32, u32, u32)>,
        > = Default::default();
        for y in 0..h {
            for x in 0..w {
                let word = words[(y * w + x) as usize];
                let (kind, hit) =
                    common::naive_decode(word, true, layout, &plan.table, config.pass_count);
                if kind == 3 {
                    let key = if layout == VisLayout::Vrs {
                        word & 0x3fff_ffff
                    } else {
                        word
                    };
                    per_batch
                        .entry(plan.table[hit.unwrap().id as usize].batch)
                        .or_default()
                        .insert((x / 2, y / 2, key));
                }
            }
        }
        let waves: u64 = per_batch
            .values()
            .map(|s| (4 * s.len() as u64).div_ceil(32))
            .sum();
        assert_eq!(m.depth_equal_waves, waves);
        // Vertices: all of them, and those in visible chunks.
        assert_eq!(m.scene_vertices, plan.vertex_count);
        let visible: u64 = (0..plan.chunk_count)
            .filter(|&c| v.ubers[(c / 64) as usize].mask() >> (c % 64) & 1 == 1)
            .map(|c| {
                let mb = plan
                    .micro_batches
                    .iter()
                    .find(|m| c >= m.first_chunk && c < m.first_chunk + m.chunk_count())
                    .unwrap();
                (mb.total_vertices() - 64 * u64::from(c - mb.first_chunk)).min(64)
            })
            .sum();
        assert_eq!(m.visible_vertices, visible);
        assert_eq!(v.visible_vertices(), visible);
        assert!(m.pixel_wave_ratio() > 0.0 && m.vertex_ratio() <= 1.0);
        if layout == VisLayout::Vrs {
            assert!(m.sample_ratio() < 1.0);
        } else {
            assert_eq!(m.sample_ratio(), 1.0);
        }
    }
}
