//! Fuzz bodies for the `wave` crate: arbitrary widths, masks, counter values (up to and
//! past `u32::MAX`) and output sizes through the aggregated append and the run-grouped
//! batch output, checked against naive loops. Nothing here may panic except a check.

use wave::{Batch, CountedAtomicU32, Error, LaneMask, PerLane, Wave, WaveWidth};

use crate::Input;

/// A width from any byte: 8, 16, 32, 64, or (for the error path) an unsupported one.
fn width(input: &mut Input<'_>) -> WaveWidth {
    let lanes = u32::from(input.u8());
    match WaveWidth::from_lanes(lanes) {
        Ok(w) => w,
        Err(Error::UnsupportedWidth { lanes: l }) => {
            assert_eq!(l, lanes);
            // Map the byte onto a supported width so every input exercises the model.
            WaveWidth::ALL[(lanes % 4) as usize]
        }
        Err(e) => panic!("unexpected error {e}"),
    }
}

/// Aggregated append, per-lane baseline and variable-amount reservation against loops.
pub fn wave_append(data: &[u8]) {
    let mut input = Input::new(data);
    let w = width(&mut input);
    let mask = LaneMask(input.u64());
    let start = input.u32();
    let cap = usize::from(input.u16() % 512);

    // An active mask outside the width is an error, never a panic.
    let wave = match Wave::with_active(w, mask) {
        Ok(wave) => wave,
        Err(e) => {
            assert!(!mask.is_subset_of(w.full_mask()), "{e}");
            Wave::new(w).restrict(mask)
        }
    };

    let counter = CountedAtomicU32::new(start);
    let mut out = vec![u32::MAX; cap];
    let a = wave.aggregated_append(&counter, &mut out, |lane| lane);
    let mut k = 0u32;
    let mut stored = 0u32;
    let mut expect = vec![u32::MAX; cap];
    for lane in 0..w.lanes() {
        if mask.0 >> lane & 1 == 1 {
            if let Some(slot) = start.checked_add(k)
                && (slot as usize) < cap
            {
                expect[slot as usize] = lane;
                stored += 1;
            }
            k += 1;
        }
    }
    assert_eq!(out, expect);
    assert_eq!((a.count, a.stored), (k, stored));
    assert_eq!(counter.value(), start.wrapping_add(k));
    assert_eq!(counter.atomic_ops(), usize::from(k > 0));

    // The baseline: one atomic per lane, same slots when nothing else appends.
    let base_counter = CountedAtomicU32::new(start);
    let mut base_out = vec![u32::MAX; cap];
    let b = wave.per_lane_append(&base_counter, &mut base_out, |lane| lane);
    assert_eq!(b.count, k);
    assert_eq!(base_counter.atomic_ops(), k as usize);
    if start.checked_add(k).is_some() {
        assert_eq!(base_out, expect);
    }

    // Variable amounts: one atomic, offsets are running sums, or a clean error.
    let amounts = PerLane::from_fn(w, |_| input.u32() >> (input.u8() % 33).min(31));
    let ranges = CountedAtomicU32::new(start);
    let total: u64 = wave.active().iter().map(|l| u64::from(amounts[l])).sum();
    match wave.reserve_ranges(&ranges, &amounts) {
        Ok(r) => {
            assert_eq!(u64::from(r.total), total);
            let mut run = 0u32;
            for lane in wave.active() {
                assert_eq!(r.offsets[lane], run);
                run += amounts[lane];
            }
            assert_eq!(ranges.atomic_ops(), usize::from(!wave.is_empty()));
        }
        Err(Error::AppendTooLarge { total: t }) => {
            assert_eq!(t, total);
            assert!(total > u64::from(u32::MAX));
            assert_eq!(ranges.atomic_ops(), 0);
        }
        Err(e) => panic!("unexpected error {e}"),
    }
}

/// Run-grouped batch output against a naive group-by, with arbitrary counters and sizes.
pub fn wave_batch(data: &[u8]) {
    let mut input = Input::new(data);
    let w = width(&mut input);
    let wave = Wave::new(w).restrict(LaneMask(input.u64()));
    let ends = LaneMask(input.u64());
    let visible = LaneMask(input.u64());
    let (start_i, start_b) = (input.u32(), input.u32());
    let (cap_i, cap_b) = (usize::from(input.u8()), usize::from(input.u8()));

    let (ci, cb) = (
        CountedAtomicU32::new(start_i),
        CountedAtomicU32::new(start_b),
    );
    let mut inst = vec![u32::MAX; cap_i];
    let mut hdr = vec![(0u32, 0u32, 0u32); cap_b];
    let o = wave.batch_output_with(
        ends,
        visible,
        &ci,
        &mut inst,
        &cb,
        &mut hdr,
        |lane| lane,
        |n: &mut u32, _| *n += 1,
        |b: &Batch<u32>| {
            assert_eq!(b.acc, b.instance_count);
            assert_eq!(b.lanes.count(), b.instance_count);
            (b.group, b.first_instance, b.instance_count)
        },
    );

    // Naive: visible active lanes in order, batches cut where the group index changes.
    let mut group = 0u32;
    let mut kept = Vec::new();
    let mut batches: Vec<(u32, u32, u32)> = Vec::new();
    for lane in 0..w.lanes() {
        if wave.active().contains(lane) {
            if visible.contains(lane) {
                match batches.last_mut() {
                    Some(b) if b.0 == group => b.2 += 1,
                    _ => batches.push((group, start_i.wrapping_add(kept.len() as u32), 1)),
                }
                kept.push(lane);
            }
            if ends.contains(lane) {
                group += 1;
            }
        }
    }
    assert_eq!(o.instances.count as usize, kept.len());
    assert_eq!(o.batches.count as usize, batches.len());
    for (k, lane) in kept.iter().enumerate() {
        if let Some(slot) = start_i.checked_add(k as u32)
            && (slot as usize) < cap_i
        {
            assert_eq!(inst[slot as usize], *lane);
        }
    }
    for (k, b) in batches.iter().enumerate() {
        if let Some(slot) = start_b.checked_add(k as u32)
            && (slot as usize) < cap_b
        {
            assert_eq!(hdr[slot as usize], *b);
        }
    }
    let any = usize::from(!kept.is_empty());
    assert_eq!((ci.atomic_ops(), cb.atomic_ops()), (any, any));
}
