//! MSAA: the PCF tap split (disjoint, complete, balanced, interleaved; interior pixels get
//! the full kernel) and the edge classifier against a direct comparison.

use deferred::msaa::*;
use glam::Vec2;
use proptest::prelude::*;

fn check_partition(kernel: &[(Vec2, f32)], split: &TapSplit, samples: SampleCount) {
    // Union is the kernel, each tap exactly once.
    let mut seen = vec![false; kernel.len()];
    for s in 0..samples.get() {
        let taps = split.sample_taps(s);
        assert!(!taps.is_empty(), "sample {s} got no taps");
        let wsum: f32 = taps.iter().map(|t| t.weight).sum();
        assert!(
            (wsum - 1.0).abs() < 1e-5,
            "sample {s} weights sum to {wsum}"
        );
        for t in taps {
            assert_eq!(t.sample, s);
            let i = kernel
                .iter()
                .enumerate()
                .position(|(i, (o, _))| !seen[i] && *o == Vec2::from(t.offset))
                .expect("tap from the kernel");
            seen[i] = true;
        }
    }
    assert!(seen.iter().all(|&s| s), "every tap used");
    assert_eq!(split.taps().len(), kernel.len());
}

/// The interior-pixel result: the mean over samples of each sample's filtered value,
/// against the full kernel, for a shadow test `lit(offset)`.
fn interior_vs_full(
    kernel: &[(Vec2, f32)],
    split: &TapSplit,
    lit: impl Fn(Vec2) -> f32,
) -> (f32, f32) {
    let total: f32 = kernel.iter().map(|k| k.1).sum();
    let full = kernel.iter().map(|(o, w)| w * lit(*o)).sum::<f32>() / total;
    let k = split.ranges().len() as u32;
    let pixel = (0..k)
        .map(|s| {
            split
                .sample_taps(s)
                .iter()
                .map(|t| t.weight * lit(Vec2::from(t.offset)))
                .sum::<f32>()
        })
        .sum::<f32>()
        / k as f32;
    (pixel, full)
}

#[test]
fn box_kernels_split_evenly_and_interleave() {
    for size in [2u32, 3, 4, 5, 6, 8] {
        let kernel: Vec<_> = box_kernel(size).collect();
        for samples in [SampleCount::X2, SampleCount::X4] {
            let split = split_taps(&kernel, samples).unwrap();
            check_partition(&kernel, &split, samples);
            let counts: Vec<_> = split.ranges().iter().map(|r| r.1).collect();
            let (lo, hi) = (*counts.iter().min().unwrap(), *counts.iter().max().unwrap());
            assert!(hi - lo <= 1, "{size}x{size} {samples:?}: {counts:?}");
            // Each subset spans the kernel: its bounding box is at least the kernel's less
            // one texel per side.
            for s in 0..samples.get() {
                let t = split.sample_taps(s);
                let min = t
                    .iter()
                    .map(|t| Vec2::from(t.offset))
                    .fold(Vec2::INFINITY, Vec2::min);
                let max = t
                    .iter()
                    .map(|t| Vec2::from(t.offset))
                    .fold(Vec2::NEG_INFINITY, Vec2::max);
                let c = (size as f32 - 1.0) * 0.5;
                if size >= 3 {
                    assert!(
                        min.cmple(Vec2::splat(-c + 1.0)).all()
                            && max.cmpge(Vec2::splat(c - 1.0)).all(),
                        "{size} {samples:?} sample {s}: {min} {max}"
                    );
                }
            }
            if (size * size) % samples.get() == 0 {
                assert!(split.imbalance() < 1e-6);
                // Interior pixel: the full kernel, exactly, for any shadow pattern.
                let (pixel, full) = interior_vs_full(&kernel, &split, |o| {
                    if o.x + 0.3 * o.y > 0.2 { 1.0 } else { 0.0 }
                });
                assert!((pixel - full).abs() < 1e-6, "{pixel} vs {full}");
            }
        }
    }
    // 4x4 in two samples: a checkerboard.
    let kernel: Vec<_> = box_kernel(4).collect();
    let split = split_taps(&kernel, SampleCount::X2).unwrap();
    for t in split.taps() {
        let parity = ((t.offset[0] + 1.5) as u32 + (t.offset[1] + 1.5) as u32) % 2;
        assert_eq!(parity, t.sample, "{t:?}");
    }
}

#[test]
fn rejects_bad_kernels() {
    assert!(split_taps(&[], SampleCount::X2).is_err());
    let one = [(Vec2::ZERO, 1.0)];
    assert!(
        split_taps(&one, SampleCount::X2)
            .unwrap_err()
            .to_string()
            .contains("1 taps")
    );
    let big: Vec<_> = box_kernel(9).collect();
    assert!(split_taps(&big, SampleCount::X4).is_err());
    let bad = [(Vec2::ZERO, 1.0), (Vec2::X, -1.0)];
    assert!(
        split_taps(&bad, SampleCount::X2)
            .unwrap_err()
            .to_string()
            .contains("tap 1")
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// Any positive kernel: a partition, weights balanced to within the heaviest tap.
    #[test]
    fn any_kernel_partitions(taps in prop::collection::vec(((-4.0f32..4.0, -4.0f32..4.0), 0.01f32..1.0), 4..64), four in any::<bool>()) {
        let kernel: Vec<_> = taps.iter().map(|&((x, y), w)| (Vec2::new(x, y), w)).collect();
        let samples = if four { SampleCount::X4 } else { SampleCount::X2 };
        let split = split_taps(&kernel, samples).unwrap();
        check_partition(&kernel, &split, samples);
        let total: f32 = kernel.iter().map(|k| k.1).sum();
        let heaviest = kernel.iter().map(|k| k.1).fold(0.0, f32::max);
        prop_assert!(split.imbalance() <= heaviest / total + 1e-5, "{}", split.imbalance());
        // The interior pixel differs from the full kernel by at most the imbalance per
        // sample (shadow values in [0, 1]).
        let (pixel, full) = interior_vs_full(&kernel, &split, |o| (o.x.sin() * 0.5 + 0.5).clamp(0.0, 1.0));
        let k = samples.get() as f32;
        prop_assert!((pixel - full).abs() <= split.imbalance() * k + 1e-5, "{pixel} vs {full}");
    }

    /// The classifier against a direct definition.
    #[test]
    fn edges_match_a_direct_comparison(
        px in prop::collection::vec((prop::array::uniform4(0u32..3), prop::array::uniform4(0.5f32..0.52)), 1..40),
        four in any::<bool>(),
    ) {
        let samples = if four { SampleCount::X4 } else { SampleCount::X2 };
        let k = samples.get() as usize;
        let words_per_sample = 2;
        let mut words = vec![];
        let mut depth = vec![];
        for (w, d) in &px {
            for s in 0..k {
                words.extend([w[s], 7]);
                depth.push(d[s]);
            }
        }
        let mut edges = vec![0; px.len()];
        let n = classify_edges(&words, words_per_sample, &depth, samples, px.len(), 0.02, &mut edges).unwrap();
        let expect: Vec<u32> = px.iter().enumerate().filter(|(_, (w, d))| {
            (1..k).any(|s| w[s] != w[0] || (d[s] - d[0]).abs() > 0.02 * d[0].max(d[s]))
        }).map(|(i, _)| i as u32).collect();
        prop_assert_eq!(&edges[..n], &expect[..]);
        // Unique samples: interior pixels light one sample, edges one per distinct value.
        for (i, (w, _)) in px.iter().enumerate() {
            let mask = unique_samples(&words[i * k * 2..(i + 1) * k * 2], 2, k as u32);
            let distinct = (0..k).filter(|&s| (0..s).all(|e| w[e] != w[s])).count();
            prop_assert_eq!(mask.count_ones() as usize, distinct);
            prop_assert!(mask & 1 == 1);
        }
    }
}

#[test]
fn classifier_reports_short_buffers() {
    let mut edges = [0u32; 1];
    let words = [1, 2, 1, 2, 3, 4, 5, 6];
    let depth = [0.5; 8];
    // Two edge pixels, room for one.
    let e = classify_edges(&words, 1, &depth, SampleCount::X2, 4, 0.01, &mut edges).unwrap_err();
    assert!(e.to_string().contains("edges"), "{e}");
    assert!(classify_edges(&words, 2, &depth, SampleCount::X4, 2, 0.01, &mut edges).is_err());
    // Depth within tolerance on a slanted triangle is interior; beyond it, an edge.
    assert!(!is_edge(&[9, 9], 1, &[0.500, 0.504], 0.01));
    assert!(is_edge(&[9, 9], 1, &[0.500, 0.52], 0.01));
    assert!(is_edge(&[9, 9], 1, &[0.5, f32::NAN], 0.01));
}
