//! The talk's diagrams as fixed vectors (Vale, "Decima: Visibility in Horizon Zero Dawn":
//! "Aside: Aggregated atomics", "GPU compute thread: Batching", "One big batch",
//! "Batches of one"), all on the simplified eight-thread wavefront.
//!
//! The slides' pictures are not in the transcript, so the exact lanes are ours; the steps,
//! the shapes ("one batch of four", "four batches of one") and every expected number are
//! written out by hand here, not computed by the code under test.

use wave::{Batch, CountedAtomicU32, LaneMask, PerLane, Wave, WaveBatch, WaveWidth};

const W8: WaveWidth = WaveWidth::W8;

/// "Aside: Aggregated atomics": threads 1, 2, 5 and 6 of eight are active and want to
/// write; the global counter already holds 12.
#[test]
fn simplified_eight_thread_append() {
    let wave = Wave::with_active(W8, LaneMask(0b0110_0110)).unwrap();

    // ballot(true): a scalar, the same for every thread.
    let active_mask = wave.ballot(|_| true);
    assert_eq!(active_mask, LaneMask(0b0110_0110));

    // The prefix sum over the bitmask (MaskBitCnt), per thread: bits to the right.
    let prefix: Vec<u32> = (0..8).map(|lane| active_mask.count_below(lane)).collect();
    assert_eq!(prefix, [0, 0, 1, 2, 2, 2, 3, 4]);

    // popcnt: scalar again.
    assert_eq!(active_mask.count(), 4);

    // The first active thread performs the atomic.
    assert_eq!(wave.first_active_lane(), Some(1));
    assert!(wave.is_first_active_lane(1));
    assert!(!wave.is_first_active_lane(0) && !wave.is_first_active_lane(2));

    let counter = CountedAtomicU32::new(12);
    let mut out = ['.'; 20];
    let names = ['a', 'b', 'c', 'd', 'e', 'f', 'g', 'h'];
    let append = wave.aggregated_append(&counter, &mut out, |lane| names[lane as usize]);
    // Old value 12 distributed to all; each writes at 12 + prefix.
    assert_eq!((append.base, append.count, append.stored), (12, 4, 4));
    assert_eq!(out[12..16], ['b', 'c', 'f', 'g']);
    assert!(out[..12].iter().chain(&out[16..]).all(|&c| c == '.'));
    assert_eq!((counter.value(), counter.atomic_ops()), (16, 1));

    // The same through the broadcast: the old value read from the first lane's register.
    let old = PerLane::from_fn(W8, |lane| if lane == 1 { 12 } else { 999 });
    assert_eq!(wave.broadcast_first(&old), Some(12));
}

/// Runs one eight-lane batch output with the group-end bits and visibility given as
/// strings of '0'/'1' in lane order, instances 'A'..'H'.
fn run_batch(ends: &str, visible: &str) -> (Vec<u32>, String, Vec<WaveBatch>, usize, usize) {
    fn mask(s: &str) -> LaneMask {
        s.bytes()
            .enumerate()
            .filter(|&(_, b)| b == b'1')
            .map(|(i, _)| i as u32)
            .collect()
    }
    let wave = Wave::new(W8);
    let groups = wave.group_indices(mask(ends));
    let (ci, cb) = (CountedAtomicU32::new(0), CountedAtomicU32::new(0));
    let mut inst = [b'.'; 8];
    let mut hdr = [WaveBatch::default(); 8];
    let o = wave.batch_output(
        mask(ends),
        mask(visible),
        &ci,
        &mut inst,
        &cb,
        &mut hdr,
        |lane| b'A' + lane as u8,
    );
    let n = o.instances.count as usize;
    let b = o.batches.count as usize;
    assert_eq!((ci.value() as usize, cb.value() as usize), (n, b));
    (
        groups.as_slice().to_vec(),
        String::from_utf8(inst[..n].to_vec()).unwrap(),
        hdr[..b].to_vec(),
        ci.atomic_ops(),
        cb.atomic_ops(),
    )
}

fn batch(first_instance: u32, instance_count: u32) -> WaveBatch {
    WaveBatch {
        first_instance,
        instance_count,
    }
}

/// "GPU compute thread: One big batch": every instance uses the same DrawableSetup, so
/// every group index is zero and the four visible instances form one batch.
#[test]
fn one_big_batch() {
    let (groups, inst, hdr, iops, bops) = run_batch("00000001", "10110100");
    assert_eq!(groups, [0; 8]);
    assert_eq!(inst, "ACDF");
    assert_eq!(hdr, [batch(0, 4)]);
    assert_eq!((iops, bops), (1, 1));
}

/// "GPU compute thread: Batches of one": every DrawableSetup differs (all group-end bits
/// set), so group indices equal lane indices and four visible lanes give four batches of
/// one.
#[test]
fn batches_of_one() {
    let (groups, inst, hdr, iops, bops) = run_batch("11111111", "10110100");
    assert_eq!(groups, [0, 1, 2, 3, 4, 5, 6, 7]);
    assert_eq!(inst, "ACDF");
    assert_eq!(hdr, [batch(0, 1), batch(1, 1), batch(2, 1), batch(3, 1)]);
    assert_eq!((iops, bops), (1, 1));
}

/// "GPU compute thread: Batching": groups AAA | BB | C | DD by colour, with invisible
/// lanes: group B's first lane and all of group C fail the test. C writes no batch; B's
/// header is written by its second lane, which wrote B's first instance.
#[test]
fn mixed_groups_with_invisible_lanes() {
    //                                ends        visible
    let (groups, inst, hdr, iops, bops) = run_batch("00101101", "11001011");
    assert_eq!(groups, [0, 0, 0, 1, 1, 2, 3, 3]);
    assert_eq!(inst, "ABEGH");
    assert_eq!(hdr, [batch(0, 2), batch(2, 1), batch(3, 2)]);
    assert_eq!((iops, bops), (1, 1));
}

/// A wave where nothing is visible performs no atomic at all.
#[test]
fn nothing_visible_no_atomics() {
    let (_, inst, hdr, iops, bops) = run_batch("01010101", "00000000");
    assert!(inst.is_empty() && hdr.is_empty());
    assert_eq!((iops, bops), (0, 0));
}

/// The per-group accumulation (the LDS arrays): bounds as min/max of a per-lane value,
/// and the header's view of its group.
#[test]
fn accumulated_bounds_reach_the_header() {
    let wave = Wave::new(W8);
    let x = [5u32, 9, 1, 7, 3, 8, 2, 6];
    let (ci, cb) = (CountedAtomicU32::new(100), CountedAtomicU32::new(0));
    let mut inst = [0u32; 256];
    let mut hdr = [(0u32, 0u32, 0u32, 0u32); 8];
    //                 lanes:      76543210
    let ends = LaneMask(0b1010_0100); // groups {0,1,2} {3,4,5} {6,7}
    let vis = LaneMask(0b1101_1011); // lanes 0 1 3 4 6 7
    #[derive(Clone, Copy)]
    struct MinMax(u32, u32);
    impl Default for MinMax {
        fn default() -> Self {
            MinMax(u32::MAX, 0)
        }
    }
    let o = wave.batch_output_with(
        ends,
        vis,
        &ci,
        &mut inst,
        &cb,
        &mut hdr,
        |lane| x[lane as usize],
        |acc: &mut MinMax, lane| {
            acc.0 = acc.0.min(x[lane as usize]);
            acc.1 = acc.1.max(x[lane as usize]);
        },
        |b: &Batch<MinMax>| {
            assert_eq!(b.first_lane(), b.lanes.first().unwrap());
            (b.first_instance, b.instance_count, b.acc.0, b.acc.1)
        },
    );
    assert_eq!(o.instances.base, 100);
    assert_eq!(inst[100..106], [5, 9, 7, 3, 2, 6]);
    assert_eq!(hdr[..3], [(100, 2, 5, 9), (102, 2, 3, 7), (104, 2, 2, 6)]);
}
