//! `tiling::parallel` equals the sequential passes exactly, phase by phase, on random
//! frames of both layouts, with and without validity masks, including a multi-thread run
//! on a 4K-sized frame.

mod common;

use common::{Rng, random_mask, random_scene, random_vis};
use tiling::{ClassifyConfig, PlanConfig, VisBuffer};
use visbuf::VisLayout;
use wave::WaveWidth;

fn check(seed: u64, w: u32, h: u32, layout: VisLayout, masked: bool) {
    let mut rng = Rng::new(seed);
    let config = PlanConfig {
        layout,
        max_batch_groups: 4,
        max_micro_batch_vertices: 4000,
        ..PlanConfig::default()
    };
    let scene = random_scene(&mut rng, 30, &config);
    let words = random_vis(&mut rng, &scene.plan, w, h, layout, 5);
    let mask = random_mask(&mut rng, w, h, 85);
    let mut vis = VisBuffer::new(&words, w, h, layout).unwrap();
    if masked {
        vis = vis.with_validity(&mask).unwrap();
    }
    let cfg = ClassifyConfig::for_plan(&scene.plan, WaveWidth::W32);
    let table = &scene.plan.table;
    let (m_seq, s_seq) = tiling::laydown_finalize(&vis, table, &cfg).unwrap();
    let (m_par, s_par) = tiling::parallel::laydown_finalize(&vis, table, &cfg).unwrap();
    assert_eq!((&m_seq, s_seq), (&m_par, s_par));
    let mid_seq = tiling::mid_classify(&vis, table, &scene.indices, &cfg, &m_seq).unwrap();
    let mid_par =
        tiling::parallel::mid_classify(&vis, table, &scene.indices, &cfg, &m_seq).unwrap();
    assert_eq!(mid_seq, mid_par);
    let out_seq = tiling::classify_output(&vis, table, &cfg, &m_seq, &mid_seq).unwrap();
    let out_par = tiling::parallel::classify_output(&vis, table, &cfg, &m_seq, &mid_seq).unwrap();
    assert_eq!(out_seq, out_par);
    let fused = tiling::classify(&vis, table, &scene.indices, &cfg).unwrap();
    assert_eq!(
        fused,
        tiling::parallel::classify(&vis, table, &scene.indices, &cfg).unwrap()
    );
    assert_eq!(
        fused,
        tiling::parallel::classify_phases(&vis, table, &scene.indices, &cfg).unwrap()
    );
    assert_eq!(fused.mid, mid_seq);
    assert_eq!(fused.output, out_seq);
}

#[test]
fn parallel_equals_sequential_on_random_frames() {
    for seed in 0..12u64 {
        let layout = if seed % 2 == 0 {
            VisLayout::Standard
        } else {
            VisLayout::Vrs
        };
        check(
            seed,
            100 + 37 * seed as u32,
            80 + 53 * seed as u32,
            layout,
            seed % 3 == 0,
        );
    }
}

#[test]
fn parallel_equals_sequential_at_4k() {
    check(1234, 3840, 2160, VisLayout::Standard, false);
}
