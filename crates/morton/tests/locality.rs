//! The locality metric: exact values on a full grid, and Hilbert beating Morton on random
//! points (the talk's "better locality").

use glam::{UVec2, UVec3};
use morton::locality::{Curve, curve_order2, curve_order3, measure2, measure3};

#[test]
fn hand_computed_measures() {
    let cells = [
        UVec3::ZERO,
        UVec3::new(3, 0, 0),
        UVec3::new(3, 1, 0),
        UVec3::new(0, 0, 5),
    ];
    let m = measure3(&cells, &[0, 1, 2, 3], 2);
    // Steps 3, 1, 3+1+5 = 9.
    assert_eq!(m.mean_step, 13.0 / 3.0);
    assert_eq!(m.max_step, 9);
    // Boxes: {0,1}: 4x1x1 -> 4+1+4 = 9; {2,3}: 4x2x6 -> 8+12+24 = 44.
    assert_eq!(m.mean_chunk_bounds, (9.0 + 44.0) / 2.0);
    // Out-of-range indices are skipped, empty is all zero.
    assert_eq!(measure3(&cells, &[0, 99, 1], 8).max_step, 3);
    let e = measure3(&[], &[], 0);
    assert_eq!(
        (e.mean_step, e.max_step, e.mean_chunk_bounds),
        (0.0, 0, 0.0)
    );
    let m2 = measure2(&[UVec2::ZERO, UVec2::new(2, 2)], &[1, 0], 5);
    assert_eq!(
        (m2.mean_step, m2.max_step, m2.mean_chunk_bounds),
        (4.0, 4, 9.0)
    );
}

#[test]
fn full_grid_hilbert_steps_one_cell() {
    let cells: Vec<UVec3> = (0..4096)
        .map(|i| UVec3::new(i & 15, (i >> 4) & 15, i >> 8))
        .collect();
    let h = measure3(&cells, &curve_order3(Curve::Hilbert, &cells).unwrap(), 64);
    let z = measure3(&cells, &curve_order3(Curve::Morton, &cells).unwrap(), 64);
    assert_eq!((h.mean_step, h.max_step), (1.0, 1));
    assert!(z.mean_step > 1.5, "{z:?}");
    // The jump across the middle of the cube: key 2047 = (15, 15, 7) to 2048 = (0, 0, 8).
    assert_eq!(z.max_step, 15 + 15 + 1);
    // Aligned runs of 64 are 4x4x4 blocks for both curves on a full grid.
    assert_eq!(h.mean_chunk_bounds, 48.0);
    assert_eq!(z.mean_chunk_bounds, 48.0);
}

#[test]
fn random_points_hilbert_is_more_local() {
    let mut rng = testkit::Rng::new(0x1234_5678_9abc_def0);
    let mut next = || rng.below(1024) as u32;
    let cells: Vec<UVec3> = (0..20_000)
        .map(|_| UVec3::new(next(), next(), next()))
        .collect();
    let h = measure3(&cells, &curve_order3(Curve::Hilbert, &cells).unwrap(), 256);
    let z = measure3(&cells, &curve_order3(Curve::Morton, &cells).unwrap(), 256);
    assert!(h.mean_step < z.mean_step, "{h:?} {z:?}");
    assert!(h.mean_chunk_bounds < z.mean_chunk_bounds, "{h:?} {z:?}");
    let cells2: Vec<UVec2> = cells.iter().map(|c| c.truncate()).collect();
    let h = measure2(
        &cells2,
        &curve_order2(Curve::Hilbert, &cells2).unwrap(),
        256,
    );
    let z = measure2(&cells2, &curve_order2(Curve::Morton, &cells2).unwrap(), 256);
    assert!(h.mean_step < z.mean_step, "{h:?} {z:?}");
}
