//! Many waves on many threads, appending through one real shared [`AtomicU32`] (rayon).
//!
//! Each function here runs the same waves as its sequential twin ([`compact`],
//! [`compact_per_item`], [`batch_compact`]), distributed over rayon's threads. Which wave
//! gets which slots depends on scheduling, as on the GPU; what is guaranteed, and tested:
//! the multiset of outputs equals the sequential run's, each wave's writes are one
//! contiguous run in lane order, and every batch header points at its own group's
//! instances.
//!
//! The counters are taken by `&mut`: nothing else can touch them during the run, so the
//! slots they hand out are disjoint, which is what lets the threads write into one output
//! buffer. A run that could advance a counter past `u32::MAX` (where slots would repeat)
//! is refused with [`Error::CounterOverflow`] before anything is written.
//!
//! [`compact`]: crate::compact
//! [`compact_per_item`]: crate::compact_per_item
//! [`batch_compact`]: crate::batch_compact

use core::marker::PhantomData;
use core::sync::atomic::{AtomicU32, Ordering};

use rayon::prelude::*;

use crate::append::{Sink, chunk_ballot, launched};
use crate::{BatchCompaction, Compaction, Error, Wave, WaveBatch, WaveWidth};

/// An output buffer that threads holding disjoint slots write into.
struct SharedOut<'a, T> {
    ptr: *mut T,
    len: usize,
    _borrow: PhantomData<&'a mut [T]>,
}

// SAFETY: a `SharedOut` is only a `&mut [T]` split by slot: it is built from an exclusive
// borrow and each slot is written by at most one thread (see `Sink::put`), so sending or
// sharing it is sending `T`s to other threads.
unsafe impl<T: Send> Send for SharedOut<'_, T> {}
// SAFETY: as above: shared access only ever writes disjoint elements.
unsafe impl<T: Send> Sync for SharedOut<'_, T> {}

impl<'a, T> SharedOut<'a, T> {
    fn new(out: &'a mut [T]) -> Self {
        Self {
            ptr: out.as_mut_ptr(),
            len: out.len(),
            _borrow: PhantomData,
        }
    }
}

impl<T: Copy> Sink<T> for &SharedOut<'_, T> {
    fn put(&mut self, slot: u32, value: T) -> bool {
        let i = slot as usize;
        if i >= self.len {
            return false;
        }
        // SAFETY: `i < len`, so the pointer is inside the borrowed slice. Every slot comes
        // from a counter that this run holds exclusively (`&mut`) and that was checked not
        // to wrap, so no two writes share a slot and no other access to the slice exists
        // until the run returns. `T: Copy`, so overwriting without dropping is fine.
        unsafe { self.ptr.add(i).write(value) };
        true
    }
}

/// Refuses a run in which `counter` could pass `u32::MAX`.
fn check_room(counter: &mut AtomicU32, items: usize) -> Result<(), Error> {
    let start = *counter.get_mut();
    if u64::from(start) + items as u64 > 1u64 << 32 {
        return Err(Error::CounterOverflow { start, items });
    }
    Ok(())
}

/// [`compact`](crate::compact) on rayon's threads: each wave of `width` items keeps those
/// passing `keep` and appends them with one aggregated atomic on the shared `counter`.
///
/// ```
/// use std::sync::atomic::AtomicU32;
/// use wave::{WaveWidth, parallel::par_compact};
/// let items: Vec<u32> = (0..10_000).collect();
/// let mut out = vec![0; items.len()];
/// let mut counter = AtomicU32::new(0);
/// let c = par_compact(WaveWidth::W32, &items, |x| x % 3 == 0, &mut counter, &mut out).unwrap();
/// assert_eq!((c.selected, c.atomic_ops), (3334, 313));
/// let mut kept = out[..c.selected].to_vec();
/// kept.sort_unstable();
/// assert!(kept.iter().copied().eq((0..10_000).step_by(3)));
/// ```
pub fn par_compact<T, F>(
    width: WaveWidth,
    items: &[T],
    keep: F,
    counter: &mut AtomicU32,
    out: &mut [T],
) -> Result<Compaction, Error>
where
    T: Copy + Send + Sync,
    F: Fn(&T) -> bool + Sync,
{
    par_waves(
        width,
        items,
        keep,
        counter,
        out,
        |wave, chunk, counter, mut sink| {
            let r = wave.reserve(counter);
            let a = crate::append::write_reserved(&r, &mut sink, |lane| chunk[lane as usize]);
            (a, usize::from(a.count > 0))
        },
    )
}

/// [`compact_per_item`](crate::compact_per_item) on rayon's threads: the baseline, one
/// atomic on the shared `counter` per kept item.
pub fn par_compact_per_item<T, F>(
    width: WaveWidth,
    items: &[T],
    keep: F,
    counter: &mut AtomicU32,
    out: &mut [T],
) -> Result<Compaction, Error>
where
    T: Copy + Send + Sync,
    F: Fn(&T) -> bool + Sync,
{
    par_waves(
        width,
        items,
        keep,
        counter,
        out,
        |wave, chunk, counter, mut sink| {
            let mut a = crate::Append::default();
            for lane in wave.active() {
                let slot = counter.fetch_add(1, Ordering::Relaxed);
                if a.count == 0 {
                    a.base = slot;
                }
                a.count += 1;
                if sink.put(slot, chunk[lane as usize]) {
                    a.stored += 1;
                }
            }
            (a, a.count as usize)
        },
    )
}

/// The frame both compactions share: refuses a run that could overflow `counter`, cuts
/// `items` into waves of `width` lanes (the last one partial) on rayon's threads, keeps the
/// lanes passing `keep`, and lets `append(wave, chunk, counter, sink)` append the wave's
/// kept items, returning the wave's [`crate::Append`] and its atomic operations; the
/// waves' counts are summed.
fn par_waves<T, F>(
    width: WaveWidth,
    items: &[T],
    keep: F,
    counter: &mut AtomicU32,
    out: &mut [T],
    append: impl Fn(Wave, &[T], &AtomicU32, &SharedOut<'_, T>) -> (crate::Append, usize) + Sync,
) -> Result<Compaction, Error>
where
    T: Copy + Send + Sync,
    F: Fn(&T) -> bool + Sync,
{
    check_room(counter, items.len())?;
    let counter: &AtomicU32 = counter;
    let shared = SharedOut::new(out);
    let shared = &shared;
    Ok(items
        .par_chunks(width.len())
        .map(|chunk| {
            let wave = launched(width, chunk.len()).restrict(chunk_ballot(chunk, &keep));
            let (a, atomic_ops) = append(wave, chunk, counter, shared);
            let mut c = Compaction::default();
            c.add_wave(&a, atomic_ops);
            c
        })
        .reduce(Compaction::default, Compaction::merge))
}

/// [`batch_compact`](crate::batch_compact) on rayon's threads: each wave runs the
/// run-grouped batch output, appending instances through `instance_counter` and
/// [`WaveBatch`] headers through `batch_counter`, one aggregated atomic each.
#[expect(
    clippy::too_many_arguments,
    reason = "pass-shaped CPU twin: the shader's bindings (instance and batch-header counter + buffer pairs) plus the wave's masks and per-lane closures"
)]
pub fn par_batch_compact<T, E, V>(
    width: WaveWidth,
    items: &[T],
    group_end: E,
    visible: V,
    instance_counter: &mut AtomicU32,
    instances: &mut [T],
    batch_counter: &mut AtomicU32,
    batches: &mut [WaveBatch],
) -> Result<BatchCompaction, Error>
where
    T: Copy + Send + Sync,
    E: Fn(&T) -> bool + Sync,
    V: Fn(&T) -> bool + Sync,
{
    check_room(instance_counter, items.len())?;
    check_room(batch_counter, items.len())?;
    let (ci, cb): (&AtomicU32, &AtomicU32) = (instance_counter, batch_counter);
    let inst = SharedOut::new(instances);
    let hdr = SharedOut::new(batches);
    let (inst, hdr) = (&inst, &hdr);
    Ok(items
        .par_chunks(width.len())
        .map(|chunk| {
            let wave = launched(width, chunk.len());
            let ends = chunk_ballot(chunk, &group_end);
            let vis = chunk_ballot(chunk, &visible);
            let o = wave.batch_into(
                ends,
                vis,
                ci,
                inst,
                cb,
                hdr,
                |l| chunk[l as usize],
                |_: &mut (), _| {},
                |b| WaveBatch {
                    first_instance: b.first_instance,
                    instance_count: b.instance_count,
                },
            );
            let mut r = BatchCompaction::default();
            r.add(&o);
            r
        })
        .reduce(BatchCompaction::default, BatchCompaction::merge))
}
