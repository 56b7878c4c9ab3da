//! Aggregated atomic append: one atomic per wave instead of one per lane.
//!
//! The pattern of the talk's "Aside: Aggregated atomics" (Vale, HZD, after Adinetz 2014):
//! `ballot(true)` gives the appending lanes, the first of them adds the mask's popcount to
//! the shared counter and broadcasts the old value, and each lane writes at that base plus
//! its `MaskBitCnt`. Writes are contiguous and in lane order within the wave.

use crate::{Counter, Error, LaneMask, PerLane, Wave, WaveWidth};

/// The slots one wave reserved with one atomic: `count` consecutive slots from `base`,
/// handed out to the reserving lanes in lane order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Reservation {
    /// The counter's value before the wave's add (the broadcast `wavefront_old_value`).
    pub base: u32,
    /// The lanes that reserved a slot.
    pub lanes: LaneMask,
}

impl Reservation {
    /// Number of slots reserved (the popcount of [`lanes`](Self::lanes)).
    #[must_use]
    pub const fn count(&self) -> u32 {
        self.lanes.count()
    }

    /// `lane`'s slot, `base + MaskBitCnt(lanes)`; `None` if `lane` did not reserve, or if
    /// the slot would wrap past `u32::MAX` (a counter that ran away).
    #[must_use]
    pub const fn slot(&self, lane: u32) -> Option<u32> {
        if !self.lanes.contains(lane) {
            return None;
        }
        self.base.checked_add(self.lanes.count_below(lane))
    }
}

/// What an append did: how many items the wave appended and how many fitted the output.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Append {
    /// First slot (the counter's value before the wave's atomic).
    pub base: u32,
    /// Items the wave appended: the counter advanced by this much.
    pub count: u32,
    /// Items actually written: those whose slot was inside the output buffer. Slots past
    /// the end are dropped, as a GPU with robust buffer access drops them; the counter
    /// still counts them, so the caller sees the overflow as `counter > capacity`.
    pub stored: u32,
}

impl Append {
    /// Items that did not fit the output.
    #[must_use]
    pub const fn dropped(&self) -> u32 {
        self.count - self.stored
    }
}

/// The slot ranges one wave reserved with one atomic when each lane appends its own number
/// of items (`amounts`): lane `l` owns `base + offsets[l] .. base + offsets[l] + amounts[l]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct RangeReservation {
    /// The counter's value before the wave's add.
    pub base: u32,
    /// Sum of the active lanes' amounts (what the atomic added).
    pub total: u32,
    /// Each active lane's exclusive prefix sum of amounts (0 in inactive lanes).
    pub offsets: PerLane<u32>,
}

impl Wave {
    /// The aggregated atomic: if any lane is active, the first active lane adds
    /// `popcount(active)` to `counter` (one atomic), and every active lane gets
    /// `old + MaskBitCnt(active)` through [`Reservation::slot`]. A wave with no active lane
    /// performs no atomic.
    ///
    /// ```
    /// use wave::{CountedAtomicU32, LaneMask, Wave, WaveWidth};
    /// let counter = CountedAtomicU32::new(100);
    /// let wave = Wave::with_active(WaveWidth::W8, LaneMask(0b0110_0101)).unwrap();
    /// let r = wave.reserve(&counter);
    /// assert_eq!((r.base, r.count()), (100, 4));
    /// assert_eq!([r.slot(0), r.slot(1), r.slot(2), r.slot(5), r.slot(6)],
    ///            [Some(100), None, Some(101), Some(102), Some(103)]);
    /// assert_eq!((counter.value(), counter.atomic_ops()), (104, 1));
    /// ```
    pub fn reserve<C: Counter + ?Sized>(&self, counter: &C) -> Reservation {
        let lanes = self.active();
        // Only the first active lane touches memory; the others receive its result.
        let base = match lanes.first() {
            Some(_) => counter.atomic_add(lanes.count()),
            None => 0,
        };
        Reservation { base, lanes }
    }

    /// [`reserve`](Self::reserve), then each active lane writes `value(lane)` to its slot
    /// in `out`, in lane order. `value` is called once per active lane, lowest first; slots
    /// outside `out` are dropped and counted in [`Append::dropped`].
    ///
    /// ```
    /// use wave::{CountedAtomicU32, Wave, WaveWidth};
    /// let items = [10u32, 11, 12, 13, 14, 15, 16, 17];
    /// let counter = CountedAtomicU32::new(0);
    /// let mut out = [0u32; 8];
    /// let visible = Wave::new(WaveWidth::W8).branch(|lane| items[lane as usize] % 2 == 1);
    /// let a = visible.aggregated_append(&counter, &mut out, |lane| items[lane as usize]);
    /// assert_eq!((a.base, a.count, a.stored), (0, 4, 4));
    /// assert_eq!(out[..4], [11, 13, 15, 17]);
    /// assert_eq!(counter.atomic_ops(), 1);
    /// ```
    pub fn aggregated_append<T, C: Counter + ?Sized>(
        &self,
        counter: &C,
        out: &mut [T],
        value: impl FnMut(u32) -> T,
    ) -> Append {
        let r = self.reserve(counter);
        write_reserved(&r, &mut { out }, value)
    }

    /// The baseline the aggregated append replaces: every active lane does its own atomic
    /// add of 1 (here in lane order) and writes at the value it got back. Returns the slot
    /// of each active lane (`None` in inactive lanes).
    pub fn reserve_per_lane<C: Counter + ?Sized>(&self, counter: &C) -> PerLane<Option<u32>> {
        let mut slots = PerLane::splat(self.width(), None);
        for lane in self.active() {
            slots[lane] = Some(counter.atomic_add(1));
        }
        slots
    }

    /// The baseline append: one atomic per active lane, then a write at the returned slot.
    /// `Append::base` is the first lane's slot; the others follow only if nothing else
    /// touches the counter meanwhile.
    pub fn per_lane_append<T, C: Counter + ?Sized>(
        &self,
        counter: &C,
        out: &mut [T],
        mut value: impl FnMut(u32) -> T,
    ) -> Append {
        let mut a = Append::default();
        for lane in self.active() {
            let slot = counter.atomic_add(1);
            if a.count == 0 {
                a.base = slot;
            }
            a.count += 1;
            let item = value(lane);
            if let Some(dst) = out.get_mut(slot as usize) {
                *dst = item;
                a.stored += 1;
            }
        }
        a
    }

    /// The aggregated atomic for variable amounts (an append of several items per lane, or
    /// FC5's per-tile pixel count): one atomic adds the sum of the active lanes' `amounts`
    /// (`subgroupAdd`), and each lane's range starts at the old value plus its exclusive
    /// prefix sum (`subgroupExclusiveAdd`). No atomic when no lane is active.
    ///
    /// Fails with [`Error::AppendTooLarge`] (and touches nothing) if the sum does not
    /// fit a `u32`.
    pub fn reserve_ranges<C: Counter + ?Sized>(
        &self,
        counter: &C,
        amounts: &PerLane<u32>,
    ) -> Result<RangeReservation, Error> {
        let total: u64 = self.active().iter().map(|l| u64::from(amounts[l])).sum();
        let total = u32::try_from(total).map_err(|_| Error::AppendTooLarge { total })?;
        let offsets = self.exclusive_add(amounts);
        let base = if self.is_empty() {
            0
        } else {
            counter.atomic_add(total)
        };
        Ok(RangeReservation {
            base,
            total,
            offsets,
        })
    }
}

/// Where appended items go: a slice, or (under `parallel`) a buffer shared by threads that
/// hold disjoint slots.
pub(crate) trait Sink<T> {
    /// Writes `value` at `slot`; false (and nothing written) if `slot` is outside.
    fn put(&mut self, slot: u32, value: T) -> bool;
}

impl<T> Sink<T> for &mut [T] {
    fn put(&mut self, slot: u32, value: T) -> bool {
        match self.get_mut(slot as usize) {
            Some(dst) => {
                *dst = value;
                true
            }
            None => false,
        }
    }
}

impl<T, S: Sink<T>> Sink<T> for &mut S {
    fn put(&mut self, slot: u32, value: T) -> bool {
        (**self).put(slot, value)
    }
}

/// Writes `value(lane)` to each reserved lane's slot, lowest lane first, counting those
/// that fit.
pub(crate) fn write_reserved<T>(
    r: &Reservation,
    out: &mut impl Sink<T>,
    mut value: impl FnMut(u32) -> T,
) -> Append {
    let mut stored = 0;
    // Lane k of the mask (in lane order) writes at base + k: MaskBitCnt, incrementally.
    for (k, lane) in r.lanes.iter().enumerate() {
        let item = value(lane);
        if let Some(slot) = r.base.checked_add(k as u32)
            && out.put(slot, item)
        {
            stored += 1;
        }
    }
    Append {
        base: r.base,
        count: r.count(),
        stored,
    }
}

/// What a stream compaction did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Compaction {
    /// Items that passed the predicate (the counter advanced by this much).
    pub selected: usize,
    /// Items written: those whose slot fell inside the output.
    pub stored: usize,
    /// Waves run (`ceil(items / width)`).
    pub waves: usize,
    /// Atomic operations issued on the counter: one per wave with a selected item for the
    /// aggregated append, one per selected item for the baseline.
    pub atomic_ops: usize,
}

impl Compaction {
    /// Adds one wave's append.
    pub(crate) fn add_wave(&mut self, a: &Append, atomic_ops: usize) {
        self.selected += a.count as usize;
        self.stored += a.stored as usize;
        self.waves += 1;
        self.atomic_ops += atomic_ops;
    }

    /// Sums two runs (for parallel reductions).
    #[must_use]
    pub fn merge(self, other: Compaction) -> Compaction {
        Compaction {
            selected: self.selected + other.selected,
            stored: self.stored + other.stored,
            waves: self.waves + other.waves,
            atomic_ops: self.atomic_ops + other.atomic_ops,
        }
    }
}

/// Stream compaction as a compute dispatch would do it, sequentially: the items are cut
/// into waves of `width` lanes (the last one partial), each lane tests `keep`, and each
/// wave appends its kept items with one [aggregated atomic](Wave::aggregated_append) on
/// `counter`. Output order: waves in order, lanes in order.
///
/// ```
/// use wave::{compact, CountedAtomicU32, WaveWidth};
/// let items: Vec<u32> = (0..100).collect();
/// let mut out = vec![0; 100];
/// let counter = CountedAtomicU32::new(0);
/// let c = compact(WaveWidth::W32, &items, |&x| x % 3 == 0, &counter, &mut out);
/// assert_eq!((c.selected, c.stored, c.waves, c.atomic_ops), (34, 34, 4, 4));
/// assert_eq!(counter.atomic_ops(), 4);
/// assert!(out[..34].iter().copied().eq((0..100).step_by(3)));
/// ```
pub fn compact<T: Copy, C: Counter + ?Sized>(
    width: WaveWidth,
    items: &[T],
    keep: impl FnMut(&T) -> bool,
    counter: &C,
    out: &mut [T],
) -> Compaction {
    waves(width, items, keep, |wave, chunk| {
        let a = wave.aggregated_append(counter, out, |lane| chunk[lane as usize]);
        (a, usize::from(a.count > 0))
    })
}

/// [`compact`]'s baseline: the same waves, but each kept item does its own atomic.
pub fn compact_per_item<T: Copy, C: Counter + ?Sized>(
    width: WaveWidth,
    items: &[T],
    keep: impl FnMut(&T) -> bool,
    counter: &C,
    out: &mut [T],
) -> Compaction {
    waves(width, items, keep, |wave, chunk| {
        let a = wave.per_lane_append(counter, out, |lane| chunk[lane as usize]);
        (a, a.count as usize)
    })
}

/// The frame both compactions share: cuts `items` into waves of `width` lanes (the last one
/// partial), keeps the lanes passing `keep`, and lets `append(wave, chunk)` append the
/// wave's kept items, returning its [`Append`] and its atomic operations; sums the waves.
fn waves<T>(
    width: WaveWidth,
    items: &[T],
    mut keep: impl FnMut(&T) -> bool,
    mut append: impl FnMut(Wave, &[T]) -> (Append, usize),
) -> Compaction {
    let mut c = Compaction::default();
    for chunk in items.chunks(width.len()) {
        let wave = launched(width, chunk.len()).restrict(chunk_ballot(chunk, &mut keep));
        let (a, atomic_ops) = append(wave, chunk);
        c.add_wave(&a, atomic_ops);
    }
    c
}

/// The wave that runs a chunk of `len <= width` items.
pub(crate) fn launched(width: WaveWidth, len: usize) -> Wave {
    // `len <= width` by construction (chunks of `width`), so this cannot fail.
    Wave::new(width).restrict(LaneMask::first_lanes(len as u32))
}

/// `ballot(pred(item))` over a chunk of `len <= width` items, one lane per item, `pred`
/// called once per item in lane order: the same mask as
/// `launched(width, len).ballot(..)`, built without iterating set bits.
pub(crate) fn chunk_ballot<T>(chunk: &[T], mut pred: impl FnMut(&T) -> bool) -> LaneMask {
    let mut bits = 0u64;
    for (lane, item) in chunk.iter().enumerate().take(64) {
        bits |= u64::from(pred(item)) << lane;
    }
    LaneMask(bits)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::CountedAtomicU32;
    use std::vec;
    use std::vec::Vec;

    #[test]
    fn empty_wave_does_no_atomic() {
        let c = CountedAtomicU32::new(7);
        let w = Wave::new(WaveWidth::W32).restrict(LaneMask::EMPTY);
        let r = w.reserve(&c);
        assert_eq!(r.count(), 0);
        let a = w.aggregated_append(&c, &mut [0u8; 4], |_| 1);
        assert_eq!(
            a,
            Append {
                base: 0,
                count: 0,
                stored: 0
            }
        );
        assert!(
            w.reserve_ranges(&c, &PerLane::splat(WaveWidth::W32, 5))
                .is_ok()
        );
        assert_eq!((c.value(), c.atomic_ops()), (7, 0));
    }

    #[test]
    fn overflow_is_dropped_and_reported() {
        let c = CountedAtomicU32::new(3);
        let mut out = [0u32; 5];
        let a = Wave::new(WaveWidth::W8).aggregated_append(&c, &mut out, |l| l + 1);
        assert_eq!(
            a,
            Append {
                base: 3,
                count: 8,
                stored: 2
            }
        );
        assert_eq!(a.dropped(), 6);
        assert_eq!(out, [0, 0, 0, 1, 2]);
        assert_eq!(c.value(), 11);
    }

    #[test]
    fn wrapping_counter_never_writes_a_wrapped_slot() {
        let c = CountedAtomicU32::new(u32::MAX - 1);
        let r = Wave::new(WaveWidth::W8).reserve(&c);
        assert_eq!(r.slot(0), Some(u32::MAX - 1));
        assert_eq!(r.slot(1), Some(u32::MAX));
        assert_eq!(r.slot(2), None);
    }

    #[test]
    fn per_lane_baseline_counts_one_atomic_per_lane() {
        let c = CountedAtomicU32::new(0);
        let w = Wave::with_active(WaveWidth::W16, LaneMask(0b1001_0000_0110)).unwrap();
        let slots = w.reserve_per_lane(&c);
        assert_eq!(c.atomic_ops(), 4);
        let got: Vec<_> = (0..16).filter_map(|l| slots[l].map(|s| (l, s))).collect();
        assert_eq!(got, [(1, 0), (2, 1), (8, 2), (11, 3)]);
    }

    #[test]
    fn ranges_match_a_running_sum() {
        let c = CountedAtomicU32::new(50);
        let w = Wave::with_active(WaveWidth::W8, LaneMask(0b1101_0110)).unwrap();
        let amounts = PerLane::from_slice(WaveWidth::W8, &[9, 1, 2, 9, 3, 9, 0, 4]).unwrap();
        let r = w.reserve_ranges(&c, &amounts).unwrap();
        assert_eq!((r.base, r.total), (50, 10));
        assert_eq!(
            [
                r.offsets[1],
                r.offsets[2],
                r.offsets[4],
                r.offsets[6],
                r.offsets[7]
            ],
            [0, 1, 3, 6, 6]
        );
        assert_eq!((c.value(), c.atomic_ops()), (60, 1));
        let huge = PerLane::splat(WaveWidth::W8, u32::MAX);
        assert_eq!(
            w.reserve_ranges(&c, &huge),
            Err(Error::AppendTooLarge {
                total: 5 * u64::from(u32::MAX)
            })
        );
        assert_eq!(c.atomic_ops(), 1);
    }

    #[test]
    fn compaction_equals_a_filter_and_counts_waves() {
        let items: Vec<u32> = (0..1000).map(|i| i * 7 % 13).collect();
        for width in WaveWidth::ALL {
            let expect: Vec<u32> = items.iter().copied().filter(|x| x % 3 == 1).collect();
            let c = CountedAtomicU32::new(0);
            let mut out = vec![u32::MAX; items.len()];
            let r = compact(width, &items, |x| x % 3 == 1, &c, &mut out);
            assert_eq!(&out[..expect.len()], &expect[..]);
            assert_eq!(r.selected, expect.len());
            let waves_with_hits = items
                .chunks(width.len())
                .filter(|ch| ch.iter().any(|x| x % 3 == 1))
                .count();
            assert_eq!(c.atomic_ops(), waves_with_hits);
            let c2 = CountedAtomicU32::new(0);
            let mut out2 = vec![u32::MAX; items.len()];
            let r2 = compact_per_item(width, &items, |x| x % 3 == 1, &c2, &mut out2);
            assert_eq!(out, out2);
            assert_eq!(
                (r.selected, r.stored, r.waves),
                (r2.selected, r2.stored, r2.waves)
            );
            assert_eq!(
                (r.atomic_ops, r2.atomic_ops),
                (waves_with_hits, expect.len())
            );
            assert_eq!(c2.atomic_ops(), expect.len());
        }
    }
}
