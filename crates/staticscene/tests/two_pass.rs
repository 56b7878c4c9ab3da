//! Two-pass occlusion against single-pass queries on clones of the same scene, over a
//! walk through the demo city with fading on:
//! - the first pass outputs exactly the instances that a query without occlusion outputs
//!   and that the single-pass query (same HiZ) saw as visible the frame before;
//! - the second pass outputs exactly the single-pass query's visible set minus the first
//!   pass's output, and counts the rest of that set as drawn early;
//! - both passes together draw everything the single pass draws (nothing is lost);
//! - the camera states (fade and visibility) after the second pass equal the single pass's.

mod common;

use std::collections::BTreeSet;

use glam::DVec3;
use staticscene::demo::{CityConfig, box_hiz, city, street_camera};
use staticscene::{
    CAMERA_STATE_VISIBLE, DrawableSetupInstance, HiZ, OcclusionPass, QueryOptions, QueryOutput,
    QueryParams, Scene, ViewDesc,
};

fn visible_set(out: &QueryOutput<DrawableSetupInstance>) -> BTreeSet<(u32, u32)> {
    out.instances
        .iter()
        .map(|d| (d.state.tile, d.state.instance))
        .collect()
}

fn run(
    scene: &mut Scene,
    view: &ViewDesc,
    hiz: Option<&HiZ>,
) -> QueryOutput<DrawableSetupInstance> {
    let mut out = QueryOutput::new();
    scene
        .query(
            &QueryParams::new(view).unwrap(),
            hiz,
            &QueryOptions::default(),
            &mut out,
        )
        .unwrap();
    out
}

#[test]
fn two_passes_draw_the_single_pass_set_split_by_last_frames_visibility() {
    let cfg = CityConfig::with_instances(20_000);
    let c = city(&cfg);
    let mut two = common::scene(&c.resources, &c.groups, staticscene::BuildConfig::default());
    let mut single = two.clone();
    let mut open = two.clone();
    let start = street_camera(&cfg);
    let (w, h) = (320u32, 180u32);
    let (mut early_total, mut late_total) = (0usize, 0usize);
    for frame in 0..16 {
        // Slow enough for frame-to-frame coherence, turning enough for disocclusion.
        let mut cam = start;
        cam.position += DVec3::new(0.0, 0.0, -2.0 * frame as f64);
        cam.rotation *= glam::DQuat::from_rotation_y(0.2 * (frame as f64 * 0.4).sin());
        let hiz = box_hiz(&c.building_boxes, &cam, &cam, w, h, false).unwrap();
        // Visible when last queried (clusters the pre-cull skipped keep their bits).
        let last_visible: BTreeSet<(u32, u32)> = single
            .tiles()
            .iter()
            .flat_map(|t| {
                let s = &single;
                (0..t.instances().len()).filter_map(move |i| {
                    let state = s.camera_state(t.id(), i).unwrap();
                    (state & CAMERA_STATE_VISIBLE != 0).then_some((t.id().0, i as u32))
                })
            })
            .collect();
        let mut view = ViewDesc::camera(cam, [w, h]);
        view.fade_frames = 4;
        view.lod_scale = 0.35;
        // The references: no occlusion, and one pass against this frame's HiZ.
        let unoccluded = visible_set(&run(&mut open, &view, None));
        view.occlusion_camera = Some(cam);
        let single_out = run(&mut single, &view, Some(&hiz));
        let visible = visible_set(&single_out);

        view.occlusion_pass = OcclusionPass::First;
        let first = visible_set(&run(&mut two, &view, None));
        view.occlusion_pass = OcclusionPass::Second;
        let second_out = run(&mut two, &view, Some(&hiz));
        let second = visible_set(&second_out);

        let want_first: BTreeSet<_> = unoccluded.intersection(&last_visible).copied().collect();
        assert_eq!(first, want_first, "frame {frame}: first pass");
        let want_second: BTreeSet<_> = visible.difference(&first).copied().collect();
        assert_eq!(second, want_second, "frame {frame}: second pass");
        assert_eq!(
            second_out.stats.drawn_early,
            visible.intersection(&first).count() as u64,
            "frame {frame}: drawn early"
        );
        let drawn: BTreeSet<_> = first.union(&second).copied().collect();
        assert!(drawn.is_superset(&visible), "frame {frame}: lost instances");
        for t in two.tiles() {
            for i in 0..t.instances().len() {
                assert_eq!(
                    two.camera_state(t.id(), i),
                    single.camera_state(t.id(), i),
                    "frame {frame}: camera state of {:?} {i}",
                    t.id()
                );
            }
        }
        early_total += first.len();
        late_total += second.len();
    }
    // Both passes do real work on this walk.
    assert!(
        early_total > 1000 && late_total > 100,
        "{early_total} early, {late_total} late"
    );
}
