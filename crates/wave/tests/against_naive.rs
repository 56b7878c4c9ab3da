//! Property tests: the wave model against independent naive references (a filter, a
//! group-by over the visible instances), for random widths, masks and group bits.

use proptest::prelude::*;
use wave::{
    Batch, CountedAtomicU32, LaneMask, PerLane, Wave, WaveBatch, WaveWidth, batch_compact, compact,
};

fn width() -> impl Strategy<Value = WaveWidth> {
    prop::sample::select(WaveWidth::ALL.to_vec())
}

/// A wave with a random active mask, plus two more random masks.
fn wave_and_masks() -> impl Strategy<Value = (Wave, LaneMask, LaneMask)> {
    (width(), any::<u64>(), any::<u64>(), any::<u64>(), 0u32..4).prop_map(
        |(w, active, a, b, density)| {
            // Bias some cases towards sparse and dense masks.
            let active = match density {
                0 => active & (active >> 1),
                1 => active | (active >> 1),
                _ => active,
            };
            let wave = Wave::new(w).restrict(LaneMask(active));
            (wave, LaneMask(a), LaneMask(b))
        },
    )
}

/// The naive group-by: walk the lanes, give each active lane the number of group ends seen
/// so far among active lanes, keep the visible ones, and cut the kept list where the group
/// changes. Returns (instance lanes, batches as (group, first position, count)).
fn naive_group_by(
    width: u32,
    active: u64,
    ends: u64,
    visible: u64,
) -> (Vec<u32>, Vec<(u32, usize, usize)>) {
    let mut group = 0u32;
    let mut kept: Vec<(u32, u32)> = Vec::new(); // (lane, group)
    for lane in 0..width {
        let is_active = active >> lane & 1 == 1;
        if !is_active {
            continue;
        }
        if visible >> lane & 1 == 1 {
            kept.push((lane, group));
        }
        if ends >> lane & 1 == 1 {
            group += 1;
        }
    }
    let mut batches: Vec<(u32, usize, usize)> = Vec::new();
    for (pos, &(_, g)) in kept.iter().enumerate() {
        match batches.last_mut() {
            Some(b) if b.0 == g => b.2 += 1,
            _ => batches.push((g, pos, 1)),
        }
    }
    (kept.into_iter().map(|(l, _)| l).collect(), batches)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    #[test]
    fn aggregated_append_equals_a_filter((wave, _, _) in wave_and_masks(), start in 0u32..1000) {
        let counter = CountedAtomicU32::new(start);
        let mut out = vec![u32::MAX; start as usize + 64];
        let a = wave.aggregated_append(&counter, &mut out, |lane| lane * 3 + 1);
        let expect: Vec<u32> = (0..wave.width().lanes())
            .filter(|l| wave.active().0 >> l & 1 == 1)
            .map(|l| l * 3 + 1)
            .collect();
        prop_assert_eq!(&out[start as usize..start as usize + expect.len()], &expect[..]);
        prop_assert!(out[..start as usize].iter().all(|&x| x == u32::MAX));
        prop_assert!(out[start as usize + expect.len()..].iter().all(|&x| x == u32::MAX));
        prop_assert_eq!(a.count as usize, expect.len());
        prop_assert_eq!(counter.value(), start + expect.len() as u32);
        prop_assert_eq!(counter.atomic_ops(), usize::from(!expect.is_empty()));
    }

    #[test]
    fn lane_operations_match_loops((wave, m, _) in wave_and_masks(), seed in any::<u32>()) {
        let w = wave.width().lanes();
        let active = wave.active().0;
        // ballot: only active lanes vote
        let b = wave.ballot(|l| m.0 >> l & 1 == 1);
        prop_assert_eq!(b.0, m.0 & active);
        // MaskBitCnt, first active, broadcast
        let vals = PerLane::from_fn(wave.width(), |l| seed.wrapping_mul(l + 1));
        let first = (0..w).find(|l| active >> l & 1 == 1);
        prop_assert_eq!(wave.first_active_lane(), first);
        prop_assert_eq!(wave.broadcast_first(&vals), first.map(|l| seed.wrapping_mul(l + 1)));
        let ex = wave.exclusive_add(&vals);
        let mut run = 0u32;
        let mut count = 0u32;
        for l in 0..w {
            if active >> l & 1 == 1 {
                prop_assert_eq!(wave.prefix_count(l), count);
                prop_assert_eq!(ex[l], run);
                prop_assert_eq!(wave.broadcast(&vals, l), Some(vals[l]));
                run = run.wrapping_add(vals[l]);
                count += 1;
            } else {
                prop_assert_eq!(wave.broadcast(&vals, l), None);
            }
        }
        prop_assert_eq!(wave.sum(&vals), run);
        prop_assert_eq!(wave.active_count(), count);
    }

    #[test]
    fn batch_output_equals_a_naive_group_by(
        (wave, ends, visible) in wave_and_masks(),
        start_i in 0u32..500,
        start_b in 0u32..500,
    ) {
        let w = wave.width().lanes();
        let (lanes, batches) = naive_group_by(w, wave.active().0, ends.0, visible.0);
        let (ci, cb) = (CountedAtomicU32::new(start_i), CountedAtomicU32::new(start_b));
        let mut inst = vec![u32::MAX; 600];
        let mut hdr = vec![(0u32, 0u32, 0u32, 0u64); 600];
        let o = wave.batch_output_with(
            ends, visible, &ci, &mut inst, &cb, &mut hdr,
            |lane| lane,
            |acc: &mut u64, lane| *acc |= 1 << lane,
            |b: &Batch<u64>| (b.group, b.first_instance, b.instance_count, b.acc),
        );
        let si = start_i as usize;
        let sb = start_b as usize;
        prop_assert_eq!(&inst[si..si + lanes.len()], &lanes[..]);
        prop_assert_eq!(o.instances.count as usize, lanes.len());
        prop_assert_eq!(o.batches.count as usize, batches.len());
        for (k, &(g, pos, n)) in batches.iter().enumerate() {
            let members: u64 = lanes[pos..pos + n].iter().map(|l| 1u64 << l).sum();
            prop_assert_eq!(hdr[sb + k], (g, start_i + pos as u32, n as u32, members));
        }
        prop_assert!(batches.iter().all(|b| b.2 <= w as usize));
        let any = !lanes.is_empty();
        prop_assert_eq!((ci.atomic_ops(), cb.atomic_ops()), (usize::from(any), usize::from(any)));
        // The simple form writes the same headers.
        let (ci2, cb2) = (CountedAtomicU32::new(start_i), CountedAtomicU32::new(start_b));
        let mut inst2 = vec![u32::MAX; 600];
        let mut hdr2 = vec![WaveBatch::default(); 600];
        wave.batch_output(ends, visible, &ci2, &mut inst2, &cb2, &mut hdr2, |lane| lane);
        prop_assert_eq!(&inst, &inst2);
        for k in 0..batches.len() {
            prop_assert_eq!(hdr2[sb + k], WaveBatch { first_instance: hdr[sb + k].1, instance_count: hdr[sb + k].2 });
        }
    }

    #[test]
    fn stream_compaction_equals_a_filter(
        w in width(),
        items in prop::collection::vec(any::<u16>(), 0..700),
        modulus in 1u16..5,
        cap in 0usize..800,
    ) {
        let expect: Vec<u16> = items.iter().copied().filter(|x| x % modulus == 0).collect();
        let counter = CountedAtomicU32::new(0);
        let mut out = vec![0u16; cap];
        let c = compact(w, &items, |x| x % modulus == 0, &counter, &mut out);
        let stored = expect.len().min(cap);
        prop_assert_eq!(&out[..stored], &expect[..stored]);
        prop_assert_eq!((c.selected, c.stored), (expect.len(), stored));
        prop_assert_eq!(c.waves, items.len().div_ceil(w.len()));
        let hits = items.chunks(w.len()).filter(|ch| ch.iter().any(|x| x % modulus == 0)).count();
        prop_assert_eq!((c.atomic_ops, counter.atomic_ops()), (hits, hits));
    }

    #[test]
    fn stream_batches_equal_a_naive_group_by_per_wave(
        w in width(),
        // (setup id, visible); sorted by setup so runs are contiguous
        mut items in prop::collection::vec((0u8..12, any::<bool>()), 0..400),
    ) {
        items.sort_by_key(|t| t.0);
        let tagged: Vec<(usize, u8, bool)> =
            items.iter().enumerate().map(|(i, &(s, v))| (i, s, v)).collect();
        let ends = |i: usize| i + 1 == items.len() || items[i].0 != items[i + 1].0;
        let (ci, cb) = (CountedAtomicU32::new(0), CountedAtomicU32::new(0));
        let mut inst = vec![(0usize, 0u8, false); items.len()];
        let mut hdr = vec![WaveBatch::default(); items.len()];
        let r = batch_compact(w, &tagged, |t| ends(t.0), |t| t.2, &ci, &mut inst, &cb, &mut hdr);
        // Naive: per wave, group the visible items by (setup) run.
        let mut exp_inst = Vec::new();
        let mut exp_hdr = Vec::new();
        for chunk in tagged.chunks(w.len()) {
            let mut last_setup = None;
            for &t in chunk.iter().filter(|t| t.2) {
                if last_setup != Some(t.1) {
                    exp_hdr.push(WaveBatch { first_instance: exp_inst.len() as u32, instance_count: 0 });
                    last_setup = Some(t.1);
                }
                exp_hdr.last_mut().unwrap().instance_count += 1;
                exp_inst.push(t);
            }
        }
        prop_assert_eq!(&inst[..exp_inst.len()], &exp_inst[..]);
        prop_assert_eq!(&hdr[..exp_hdr.len()], &exp_hdr[..]);
        prop_assert_eq!((r.instances, r.batches), (exp_inst.len(), exp_hdr.len()));
        // Every batch is one setup.
        for b in &exp_hdr {
            let s = &inst[b.first_instance as usize..(b.first_instance + b.instance_count) as usize];
            prop_assert!(s.iter().all(|t| t.1 == s[0].1));
        }
    }
}
