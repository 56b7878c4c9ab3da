//! The multi-threaded runs against the sequential ones: same multiset of outputs, each
//! wave's writes contiguous and in lane order, batch headers pointing at their own group.

use std::collections::HashMap;
use std::sync::atomic::AtomicU32;

use wave::parallel::{par_batch_compact, par_compact, par_compact_per_item};
use wave::{CountedAtomicU32, Error, WaveBatch, WaveWidth, batch_compact, compact};

/// `n` random items (testkit's generator, deterministic).
fn items(n: usize, seed: u64) -> Vec<u64> {
    let mut rng = testkit::Rng::new(seed);
    (0..n).map(|_| rng.next_u64()).collect()
}

/// Item `i` carries its index in the low 32 bits so its wave and lane can be recovered.
fn tagged(n: usize, seed: u64) -> Vec<u64> {
    items(n, seed)
        .into_iter()
        .enumerate()
        .map(|(i, r)| (r << 32) | i as u64)
        .collect()
}

fn keep(x: &u64) -> bool {
    (x >> 32).is_multiple_of(3)
}

/// Each wave's kept items must sit consecutively, in lane order, somewhere in `out`.
fn assert_waves_contiguous(
    width: WaveWidth,
    all: &[u64],
    out: &[u64],
    keep: impl Fn(&u64) -> bool,
) {
    let pos: HashMap<u64, usize> = out.iter().enumerate().map(|(p, &x)| (x, p)).collect();
    for (w, chunk) in all.chunks(width.len()).enumerate() {
        let kept: Vec<usize> = chunk.iter().filter(|x| keep(x)).map(|x| pos[x]).collect();
        for pair in kept.windows(2) {
            assert_eq!(pair[1], pair[0] + 1, "wave {w} not contiguous and ordered");
        }
    }
}

#[test]
fn par_compact_equals_the_sequential_run() {
    let all = tagged(100_003, 7);
    for width in WaveWidth::ALL {
        let seq_counter = CountedAtomicU32::new(0);
        let mut seq = vec![0u64; all.len()];
        let s = compact(width, &all, keep, &seq_counter, &mut seq);

        let mut counter = AtomicU32::new(0);
        let mut par = vec![0u64; all.len()];
        let p = par_compact(width, &all, keep, &mut counter, &mut par).unwrap();
        assert_eq!(p, s);
        assert_eq!(counter.into_inner() as usize, s.selected);
        assert_eq!(p.atomic_ops, seq_counter.atomic_ops());
        assert_waves_contiguous(width, &all, &par[..p.selected], keep);
        let (mut a, mut b) = (seq[..s.selected].to_vec(), par[..p.selected].to_vec());
        a.sort_unstable();
        b.sort_unstable();
        assert_eq!(a, b);

        let mut counter = AtomicU32::new(0);
        let mut base = vec![0u64; all.len()];
        let q = par_compact_per_item(width, &all, keep, &mut counter, &mut base).unwrap();
        assert_eq!(
            (q.selected, q.stored, q.waves),
            (s.selected, s.stored, s.waves)
        );
        assert_eq!(q.atomic_ops, s.selected);
        let mut c = base[..q.selected].to_vec();
        c.sort_unstable();
        assert_eq!(a, c);
    }
}

#[test]
fn par_compact_drops_what_does_not_fit_and_refuses_a_wrapping_counter() {
    let all = tagged(10_000, 3);
    let mut counter = AtomicU32::new(0);
    let mut small = vec![0u64; 1000];
    let p = par_compact(WaveWidth::W32, &all, keep, &mut counter, &mut small).unwrap();
    assert!(p.selected > 1000);
    assert_eq!(p.stored, 1000);
    assert_eq!(counter.into_inner() as usize, p.selected);

    let mut near_end = AtomicU32::new(u32::MAX - 100);
    assert_eq!(
        par_compact(WaveWidth::W32, &all, keep, &mut near_end, &mut small),
        Err(Error::CounterOverflow {
            start: u32::MAX - 100,
            items: all.len()
        })
    );
    assert_eq!(near_end.into_inner(), u32::MAX - 100, "nothing appended");
}

#[test]
fn par_batch_compact_equals_the_sequential_run() {
    // Setup ids in sorted runs of random length; group end where the setup changes.
    let raw = items(50_000, 11);
    let mut setup = 0u64;
    let all: Vec<u64> = raw
        .iter()
        .enumerate()
        .map(|(i, r)| {
            if r % 5 == 0 {
                setup += 1;
            }
            (setup << 40) | ((r >> 20) & 1) << 32 | i as u64
        })
        .collect();
    let setup_of = |x: &u64| x >> 40;
    let visible = |x: &u64| (x >> 32) & 1 == 1;
    let index = |x: &u64| (x & 0xffff_ffff) as usize;
    let ends = |x: &u64| {
        let i = index(x);
        i + 1 == all.len() || setup_of(&all[i]) != setup_of(&all[i + 1])
    };
    for width in WaveWidth::ALL {
        let (ci, cb) = (CountedAtomicU32::new(0), CountedAtomicU32::new(0));
        let mut inst = vec![0u64; all.len()];
        let mut hdr = vec![WaveBatch::default(); all.len()];
        let s = batch_compact(width, &all, ends, visible, &ci, &mut inst, &cb, &mut hdr);

        let (mut pci, mut pcb) = (AtomicU32::new(0), AtomicU32::new(0));
        let mut pinst = vec![0u64; all.len()];
        let mut phdr = vec![WaveBatch::default(); all.len()];
        let p = par_batch_compact(
            width, &all, ends, visible, &mut pci, &mut pinst, &mut pcb, &mut phdr,
        )
        .unwrap();
        assert_eq!(p, s);
        assert_eq!(
            (pci.into_inner() as usize, pcb.into_inner() as usize),
            (s.instances, s.batches)
        );
        assert_waves_contiguous(width, &all, &pinst[..p.instances], visible);

        // Same batches, as sets of instances: each header's run is one setup within one wave.
        let runs = |inst: &[u64], hdr: &[WaveBatch]| {
            let mut v: Vec<Vec<u64>> = hdr
                .iter()
                .map(|b| {
                    inst[b.first_instance as usize..(b.first_instance + b.instance_count) as usize]
                        .to_vec()
                })
                .collect();
            for run in &v {
                assert!(run.iter().all(|x| setup_of(x) == setup_of(&run[0])));
                assert!(
                    run.iter()
                        .all(|x| index(x) / width.len() == index(&run[0]) / width.len())
                );
                assert!(run.len() <= width.len());
            }
            v.sort();
            v
        };
        assert_eq!(
            runs(&inst, &hdr[..s.batches]),
            runs(&pinst, &phdr[..p.batches])
        );
    }
}
