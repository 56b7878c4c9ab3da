//! The signed distance transform against brute force on random masks, exact to the bit,
//! and the parallel version against the sequential one.

use std::ops::ControlFlow;

use proptest::prelude::*;
use water::edt::{brute_signed_squared_edt, signed_edt, signed_squared_edt};

/// Masks with structure: random blobs (runs of both classes) plus noise.
fn mask(w: usize, h: usize, seed: u32, blobs: u32, noise: u32) -> Vec<u8> {
    let centres: Vec<(f32, f32, f32)> = (0..blobs)
        .map(|k| {
            let r = |s| water::hash::unit(water::hash::hash3(k, seed, s));
            (r(1) * w as f32, r(2) * h as f32, 1.0 + r(3) * 8.0)
        })
        .collect();
    (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f32, (i / w) as f32);
            let blob = centres
                .iter()
                .any(|&(cx, cy, r)| (x - cx).powi(2) + (y - cy).powi(2) < r * r);
            let flip = water::hash::hash3(i as u32, seed, 9) % 100 < noise;
            u8::from(blob != flip) * (1 + (i % 3) as u8) // any non-zero byte is solid
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(40))]

    #[test]
    fn exact_against_brute_force(w in 1usize..48, h in 1usize..40, seed in any::<u32>(), blobs in 0u32..6, noise in 0u32..20) {
        let m = mask(w, h, seed, blobs, noise);
        let got = signed_squared_edt(&m, w as u32, h as u32).unwrap();
        prop_assert_eq!(&got, &brute_signed_squared_edt(&m, w, h));
        let f = signed_edt(&m, w as u32, h as u32, &mut water::no_progress).unwrap();
        for (v, d) in f.values().iter().zip(&got) {
            let want = if d.unsigned_abs() == i32::MAX as u32 { f32::INFINITY } else { (d.unsigned_abs() as f32).sqrt() };
            prop_assert_eq!(v.abs(), want);
            prop_assert_eq!(*v < 0.0, *d < 0);
        }
    }
}

#[test]
fn progress_reports_every_stage_and_can_cancel() {
    let m = mask(300, 600, 1, 20, 2);
    let mut seen = Vec::new();
    signed_edt(&m, 300, 600, &mut |p: water::Progress| {
        seen.push((p.stage, p.done, p.total));
        ControlFlow::Continue(())
    })
    .unwrap();
    assert_eq!(seen[0], (water::Stage::DistanceColumns, 1, 1));
    assert_eq!(
        *seen.last().unwrap(),
        (water::Stage::DistanceRows, 600, 600)
    );
    assert!(
        seen.windows(2)
            .all(|w| w[0].1 <= w[1].1 || w[0].0 != w[1].0)
    );
    let mut calls = 0;
    let r = signed_edt(&m, 300, 600, &mut |_| {
        calls += 1;
        if calls == 2 {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    });
    assert_eq!(r.unwrap_err(), water::Error::Cancelled);
}

#[cfg(feature = "parallel")]
#[test]
fn parallel_equals_sequential_bit_for_bit() {
    for (w, h, seed) in [
        (517usize, 389usize, 3u32),
        (1, 700, 4),
        (900, 1, 5),
        (640, 640, 6),
    ] {
        let m = mask(w, h, seed, 40, 1);
        let a = signed_edt(&m, w as u32, h as u32, &mut water::no_progress).unwrap();
        let mut reports = 0;
        let b = water::parallel::signed_edt(&m, w as u32, h as u32, &mut |_| {
            reports += 1;
            ControlFlow::Continue(())
        })
        .unwrap();
        assert_eq!(a, b, "{w}x{h}");
        assert!(reports >= 2);
    }
}
