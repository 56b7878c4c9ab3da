//! Run-grouped batch output: Horizon Zero Dawn's batching in the visibility query
//! (Vale, "GPU compute thread: Batching", "One big batch", "Batches of one").
//!
//! Instances arrive sorted by DrawableSetup, each with a "group ends here" bit set on the
//! last instance of each run. In one wave:
//!
//! 1. The exclusive prefix count of the group-end bits gives each lane its group index.
//! 2. The visibility test leaves some lanes active ("visible").
//! 3. The visible lanes append their instances with one aggregated atomic, so each
//!    group's visible instances land contiguous and in lane order.
//! 4. Each visible lane accumulates into its group's slot of a per-wave scratch array (the
//!    talk's LDS): the instance count, and whatever else the caller folds in (bounds).
//! 5. The first visible lane of each group appends one batch header pointing at the
//!    group's first written instance; the headers go through one more aggregated atomic.
//!
//! A batch never spans waves, so the longest batch is the wave width, as in the talk; a
//! run of one DrawableSetup that crosses a wave boundary becomes one batch per wave.
//!
//! The WGSL twin, `wave_wg_batch_begin` / `wave_wg_batch_headers_begin` in
//! `wave::workgroup` ([`WORKGROUP`](crate::wgsl::WORKGROUP)), runs workgroup-wide (the workgroup
//! is the wave); with 8 to 64 invocations it equals [`Wave::batch_output`] lane for lane.

use crate::append::{Sink, write_reserved};
use crate::{Append, Counter, LaneMask, PerLane, Wave, WaveWidth};

/// The generic part of a batch header (the talk's DrawableSetupBatch "pointer to
/// instances" and "count"), as written by [`Wave::batch_output`]. WGSL struct `WaveBatch`.
///
/// | offset | field | meaning |
/// | --- | --- | --- |
/// | 0 | `first_instance` | index in the instance output of the batch's first instance |
/// | 4 | `instance_count` | instances in the batch, `1..=wave width` |
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, bytemuck::Pod, bytemuck::Zeroable)]
pub struct WaveBatch {
    /// Index in the instance output of the batch's first instance.
    pub first_instance: u32,
    /// Number of instances in the batch (at most the wave width).
    pub instance_count: u32,
}

const _: () = assert!(size_of::<WaveBatch>() == 8);

/// One group's batch, as its first visible lane sees it when it writes the header.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Batch<A> {
    /// The group's index within the wave (the prefix count of group-end bits).
    pub group: u32,
    /// The group's visible lanes; their instances were written consecutively.
    pub lanes: LaneMask,
    /// Slot in the instance output of the group's first visible instance (the slot of
    /// the lane that writes this header). Wraps only if the counter ran past `u32::MAX`.
    pub first_instance: u32,
    /// Number of visible instances in the group (`lanes.count()`), the talk's batch length.
    pub instance_count: u32,
    /// What the group's visible lanes accumulated in the scratch slot (bounds, flags).
    pub acc: A,
}

impl<A> Batch<A> {
    /// The lane that writes the header: the group's first visible lane.
    #[must_use]
    pub fn first_lane(&self) -> u32 {
        // `lanes` is never empty: a batch exists only for a group with a visible lane.
        self.lanes.first().unwrap_or(0)
    }
}

/// What a batch output did in one wave: the two appends.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct BatchOutput {
    /// The instance append (one slot per visible lane).
    pub instances: Append,
    /// The header append (one slot per group with a visible lane).
    pub batches: Append,
}

impl Wave {
    /// Each lane's group index: the number of group-end bits set in the active lanes
    /// below it (an exclusive prefix count). Bits of inactive lanes are ignored; inactive
    /// lanes get the index their position implies, which no output uses.
    #[must_use]
    pub fn group_indices(&self, group_end: LaneMask) -> PerLane<u32> {
        let ends = group_end & self.active();
        PerLane::from_fn(self.width(), |lane| ends.count_below(lane))
    }

    /// Run-grouped batch output with [`WaveBatch`] headers: see
    /// [`batch_output_with`](Self::batch_output_with) for the arguments.
    ///
    /// The talk's "batches of one": every group-end bit set, four visible lanes, four
    /// batches of one instance each.
    ///
    /// ```
    /// use wave::{CountedAtomicU32, LaneMask, Wave, WaveBatch, WaveWidth};
    /// let wave = Wave::new(WaveWidth::W8);
    /// let (ci, cb) = (CountedAtomicU32::new(0), CountedAtomicU32::new(0));
    /// let (mut inst, mut hdr) = ([0u8; 8], [WaveBatch::default(); 8]);
    /// let names = *b"ABCDEFGH";
    /// let out = wave.batch_output(LaneMask(0xff), LaneMask(0b0110_1001),
    ///     &ci, &mut inst, &cb, &mut hdr, |lane| names[lane as usize]);
    /// assert_eq!(&inst[..4], b"ADFG");
    /// assert_eq!(out.batches.count, 4);
    /// assert!(hdr[..4].iter().enumerate().all(|(i, b)| *b == WaveBatch { first_instance: i as u32, instance_count: 1 }));
    /// ```
    #[expect(
        clippy::too_many_arguments,
        reason = "pass-shaped CPU twin: the shader's bindings (instance and batch-header counter + buffer pairs) plus the wave's masks and per-lane closures"
    )]
    pub fn batch_output<T, C1: Counter + ?Sized, C2: Counter + ?Sized>(
        &self,
        group_end: LaneMask,
        visible: LaneMask,
        instance_counter: &C1,
        instances: &mut [T],
        batch_counter: &C2,
        batches: &mut [WaveBatch],
        instance: impl FnMut(u32) -> T,
    ) -> BatchOutput {
        self.batch_output_with(
            group_end,
            visible,
            instance_counter,
            instances,
            batch_counter,
            batches,
            instance,
            |_: &mut (), _| {},
            |b| WaveBatch {
                first_instance: b.first_instance,
                instance_count: b.instance_count,
            },
        )
    }

    /// Run-grouped batch output, generic over the instance record `T`, the header `B` and
    /// the per-group accumulator `A`.
    ///
    /// - `self`: the wave, active lanes are those holding an instance (a partial last wave
    ///   has fewer).
    /// - `group_end`: bit `l` set when lane `l`'s instance is the last of its run (instances
    ///   sorted by DrawableSetup). Only active lanes' bits count.
    /// - `visible`: the lanes that passed the visibility test; intersected with the active
    ///   lanes.
    /// - `instance_counter` / `instances`: the instance output and its append counter; one
    ///   aggregated atomic, in lane order.
    /// - `batch_counter` / `batches`: the header output and its counter; one aggregated
    ///   atomic, headers in group order.
    /// - `instance(lane)`: the record lane `lane` writes, called once per visible lane,
    ///   lowest first.
    /// - `accumulate(&mut acc, lane)`: folds a visible lane into its group's scratch slot
    ///   (starting from `A::default()`), lowest lane first. On the GPU the order is free,
    ///   so keep it commutative (min, max, add, or).
    /// - `header(&batch)`: the header the group's first visible lane writes, called once
    ///   per group with a visible lane, in group order.
    ///
    /// Writes past the end of either output are dropped and reported in the returned
    /// [`Append`]s, as in [`Wave::aggregated_append`]; a wave with no visible lane does no
    /// atomic at all.
    #[expect(
        clippy::too_many_arguments,
        reason = "pass-shaped CPU twin: the shader's bindings (instance and batch-header counter + buffer pairs) plus the wave's masks and per-lane closures"
    )]
    pub fn batch_output_with<T, B, A, C1, C2>(
        &self,
        group_end: LaneMask,
        visible: LaneMask,
        instance_counter: &C1,
        instances: &mut [T],
        batch_counter: &C2,
        batches: &mut [B],
        instance: impl FnMut(u32) -> T,
        accumulate: impl FnMut(&mut A, u32),
        header: impl FnMut(&Batch<A>) -> B,
    ) -> BatchOutput
    where
        A: Copy + Default,
        C1: Counter + ?Sized,
        C2: Counter + ?Sized,
    {
        self.batch_into(
            group_end,
            visible,
            instance_counter,
            instances,
            batch_counter,
            batches,
            instance,
            accumulate,
            header,
        )
    }

    /// [`batch_output_with`](Self::batch_output_with) into any [`Sink`]s.
    #[expect(
        clippy::too_many_arguments,
        reason = "pass-shaped CPU twin: the shader's bindings (instance and batch-header counter + buffer pairs) plus the wave's masks and per-lane closures"
    )]
    pub(crate) fn batch_into<T, B, A, C1, C2>(
        &self,
        group_end: LaneMask,
        visible: LaneMask,
        instance_counter: &C1,
        mut instances: impl Sink<T>,
        batch_counter: &C2,
        mut batches: impl Sink<B>,
        instance: impl FnMut(u32) -> T,
        mut accumulate: impl FnMut(&mut A, u32),
        mut header: impl FnMut(&Batch<A>) -> B,
    ) -> BatchOutput
    where
        A: Copy + Default,
        C1: Counter + ?Sized,
        C2: Counter + ?Sized,
    {
        let ends = group_end & self.active();
        let visible_wave = self.restrict(visible);
        let visible = visible_wave.active();

        // Instances: one aggregated append over the visible lanes.
        let reservation = visible_wave.reserve(instance_counter);
        let inst = write_reserved(&reservation, &mut instances, instance);

        // The per-wave scratch (the talk's LDS): one slot per group, at most one group per lane.
        let mut acc = [A::default(); 64];
        let mut lanes = [LaneMask::EMPTY; 64];
        let mut leaders = LaneMask::EMPTY;
        for lane in visible {
            let g = ends.count_below(lane) as usize;
            if lanes[g].is_empty() {
                leaders |= LaneMask::lane(lane);
            }
            lanes[g] |= LaneMask::lane(lane);
            accumulate(&mut acc[g], lane);
        }

        // Headers: the first visible lane of each group appends one, again aggregated.
        let header_reservation = self.restrict(leaders).reserve(batch_counter);
        let hdr = write_reserved(&header_reservation, &mut batches, |lane| {
            let g = ends.count_below(lane);
            let group_lanes = lanes[g as usize];
            header(&Batch {
                group: g,
                lanes: group_lanes,
                first_instance: reservation.base.wrapping_add(visible.count_below(lane)),
                instance_count: group_lanes.count(),
                acc: acc[g as usize],
            })
        });
        BatchOutput {
            instances: inst,
            batches: hdr,
        }
    }
}

/// What a batched stream run did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct BatchCompaction {
    /// Visible instances appended (the instance counter advanced by this much).
    pub instances: usize,
    /// Instances written (inside the output).
    pub instances_stored: usize,
    /// Batch headers appended.
    pub batches: usize,
    /// Headers written (inside the output).
    pub batches_stored: usize,
    /// Waves run.
    pub waves: usize,
}

impl BatchCompaction {
    pub(crate) fn add(&mut self, o: &BatchOutput) {
        self.instances += o.instances.count as usize;
        self.instances_stored += o.instances.stored as usize;
        self.batches += o.batches.count as usize;
        self.batches_stored += o.batches.stored as usize;
        self.waves += 1;
    }

    /// Sums two runs (for parallel reductions).
    #[must_use]
    pub fn merge(self, o: BatchCompaction) -> BatchCompaction {
        BatchCompaction {
            instances: self.instances + o.instances,
            instances_stored: self.instances_stored + o.instances_stored,
            batches: self.batches + o.batches,
            batches_stored: self.batches_stored + o.batches_stored,
            waves: self.waves + o.waves,
        }
    }
}

/// The query's batched output over a whole stream, sequentially: `items` cut into waves
/// of `width` lanes (the last one partial), each wave running
/// [`Wave::batch_output`] with `group_end(item)` and `visible(item)`, writing the visible
/// items themselves as instances and [`WaveBatch`] headers.
///
/// ```
/// use wave::{batch_compact, CountedAtomicU32, WaveBatch, WaveWidth};
/// // (setup, visible); the last item of each setup run carries the group-end bit.
/// let items = [(0, true), (0, true), (1, false), (1, true), (2, true), (2, true)];
/// let ends = |i: usize| i + 1 == items.len() || items[i].0 != items[i + 1].0;
/// let tagged: Vec<(usize, (u32, bool))> = items.iter().copied().enumerate().collect();
/// let (ci, cb) = (CountedAtomicU32::new(0), CountedAtomicU32::new(0));
/// let (mut inst, mut hdr) = (vec![(0, (0, false)); 6], vec![WaveBatch::default(); 6]);
/// let r = batch_compact(WaveWidth::W8, &tagged, |t| ends(t.0), |t| t.1 .1, &ci, &mut inst, &cb, &mut hdr);
/// assert_eq!((r.instances, r.batches), (5, 3));
/// assert_eq!(&hdr[..3], &[
///     WaveBatch { first_instance: 0, instance_count: 2 },
///     WaveBatch { first_instance: 2, instance_count: 1 },
///     WaveBatch { first_instance: 3, instance_count: 2 },
/// ]);
/// ```
#[expect(
    clippy::too_many_arguments,
    reason = "pass-shaped CPU twin: the shader's bindings (instance and batch-header counter + buffer pairs) plus the wave's masks and per-lane closures"
)]
pub fn batch_compact<T: Copy, C1: Counter + ?Sized, C2: Counter + ?Sized>(
    width: WaveWidth,
    items: &[T],
    mut group_end: impl FnMut(&T) -> bool,
    mut visible: impl FnMut(&T) -> bool,
    instance_counter: &C1,
    instances: &mut [T],
    batch_counter: &C2,
    batches: &mut [WaveBatch],
) -> BatchCompaction {
    let mut r = BatchCompaction::default();
    for chunk in items.chunks(width.len()) {
        let wave = crate::append::launched(width, chunk.len());
        let ends = crate::append::chunk_ballot(chunk, &mut group_end);
        let vis = crate::append::chunk_ballot(chunk, &mut visible);
        let o = wave.batch_output(
            ends,
            vis,
            instance_counter,
            instances,
            batch_counter,
            batches,
            |l| chunk[l as usize],
        );
        r.add(&o);
    }
    r
}
