//! Per-pass ID ranges: which AllocationIDs each pass of a frame uses.
//!
//! The only rule of the allocator is that IDs grow in the order the GPU consumes the blocks.
//! KZ2 met it by giving every frame a fixed budget of IDs and every pass its own range of
//! that budget ("geometry uses 1000-1100, lighting 1200-2000 and distributes it among the
//! shadow-map tasks, forward 2100-2200; the next frame starts at 2300"). Passes can then
//! allocate in any order, from any thread, and each block still frees at the right point
//! of the frame: a block tagged with the geometry pass's IDs frees as soon as the GPU is
//! past the geometry pass, even if it was allocated after a lighting block.
//!
//! A block that must outlive its pass (KZ2: skinned vertices needed until the forward pass)
//! is tagged with an ID of the last pass that reads it, e.g. [`PassIds::last`] of that pass.
//!
//! ```
//! use framealloc::{AllocId, FramePlan};
//! // Geometry: 100 IDs, lighting: 800, forward: 100.
//! let plan = FramePlan::new(&[100, 800, 100])?;
//! let frame = plan.frame(AllocId(1000));
//! assert_eq!(frame.pass(0)?.first(), AllocId(1000));
//! assert_eq!(frame.pass(1)?.first(), AllocId(1100));
//! assert_eq!(frame.last(), AllocId(1999)); // advance FreeID here when the frame is done
//! assert_eq!(frame.next().first(), AllocId(2000));
//! // Lighting hands a quarter of its range to each of 4 shadow-map tasks.
//! let shadows = frame.pass(1)?.split(2, 4)?;
//! assert_eq!((shadows.first(), shadows.len()), (AllocId(1500), 200));
//! # Ok::<(), framealloc::Error>(())
//! ```

use crate::{AllocId, Error};

/// The most passes a [`FramePlan`] may have (64).
pub const MAX_PASSES: usize = 64;

/// The most IDs one frame may span (2^24). Keeps many frames in flight well inside
/// [`crate::MAX_ID_LEAD`].
pub const MAX_FRAME_SPAN: u32 = 1 << 24;

/// A frame's layout of ID ranges: one budget (a count of IDs) per pass, in the order the
/// GPU executes the passes. `Copy`, no allocation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FramePlan {
    /// `starts[i]` is pass `i`'s first ID relative to the frame's first; `starts[count]`
    /// is the span.
    starts: [u32; MAX_PASSES + 1],
    count: u32,
}

impl FramePlan {
    /// A plan with one budget per pass, in GPU order. Each budget must be at least 1,
    /// there may be 1 ..= [`MAX_PASSES`] passes and they may sum to at most
    /// [`MAX_FRAME_SPAN`].
    pub fn new(budgets: &[u32]) -> Result<Self, Error> {
        if budgets.is_empty() || budgets.len() > MAX_PASSES {
            return Err(Error::BadPlan {
                what: "the pass count must be 1 ..= MAX_PASSES (64)",
                value: budgets.len() as u64,
            });
        }
        let mut starts = [0u32; MAX_PASSES + 1];
        let mut at = 0u64;
        for (i, &b) in budgets.iter().enumerate() {
            if b == 0 {
                return Err(Error::BadPlan {
                    what: "every pass needs a budget of at least 1 ID; this pass index has 0",
                    value: i as u64,
                });
            }
            starts[i] = at as u32;
            at += b as u64;
            if at > MAX_FRAME_SPAN as u64 {
                return Err(Error::BadPlan {
                    what: "the budgets sum past MAX_FRAME_SPAN (2^24 IDs)",
                    value: at,
                });
            }
        }
        starts[budgets.len()] = at as u32;
        Ok(FramePlan {
            starts,
            count: budgets.len() as u32,
        })
    }

    /// Passes in the plan.
    #[inline]
    #[must_use]
    pub fn pass_count(&self) -> u32 {
        self.count
    }

    /// IDs per frame: the sum of the budgets.
    #[inline]
    #[must_use]
    pub fn span(&self) -> u32 {
        self.starts[self.count as usize]
    }

    /// Pass `index`'s budget.
    pub fn budget(&self, index: u32) -> Result<u32, Error> {
        self.check(index)?;
        Ok(self.starts[index as usize + 1] - self.starts[index as usize])
    }

    fn check(&self, index: u32) -> Result<(), Error> {
        if index < self.count {
            Ok(())
        } else {
            Err(Error::NoSuchPass {
                index,
                count: self.count,
            })
        }
    }

    /// The IDs of the frame that starts at `first`.
    #[must_use]
    pub fn frame(&self, first: AllocId) -> FrameIds {
        FrameIds { plan: *self, first }
    }

    /// The IDs of frame number `n` of a sequence whose frame 0 starts at `first` (wrapping).
    #[must_use]
    pub fn nth_frame(&self, first: AllocId, n: u64) -> FrameIds {
        let offset = (n.wrapping_mul(self.span() as u64)) as u32;
        self.frame(first.add(offset))
    }
}

/// One frame's IDs under a [`FramePlan`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameIds {
    plan: FramePlan,
    first: AllocId,
}

impl FrameIds {
    /// The frame's first ID (its first pass's first ID).
    #[inline]
    #[must_use]
    pub fn first(&self) -> AllocId {
        self.first
    }

    /// The frame's last ID: advance FreeID to it once the GPU has finished the frame.
    #[inline]
    #[must_use]
    pub fn last(&self) -> AllocId {
        self.first.add(self.plan.span() - 1)
    }

    /// The plan this frame follows.
    #[inline]
    #[must_use]
    pub fn plan(&self) -> &FramePlan {
        &self.plan
    }

    /// Pass `index`'s range.
    pub fn pass(&self, index: u32) -> Result<PassIds, Error> {
        self.plan.check(index)?;
        let i = index as usize;
        Ok(PassIds {
            first: self.first.add(self.plan.starts[i]),
            len: self.plan.starts[i + 1] - self.plan.starts[i],
        })
    }

    /// The next frame, starting right after this one's last ID.
    #[must_use]
    pub fn next(&self) -> FrameIds {
        FrameIds {
            plan: self.plan,
            first: self.first.add(self.plan.span()),
        }
    }
}

/// A contiguous range of `len` IDs starting at `first` (wrapping), owned by one pass or one
/// task of a pass. Hand its IDs out in GPU order with [`PassIds::cursor`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PassIds {
    first: AllocId,
    len: u32,
}

impl PassIds {
    /// A range of `len` IDs from `first`. [`Error::BadPlan`] when `len` is 0 or more than
    /// [`MAX_FRAME_SPAN`].
    pub fn new(first: AllocId, len: u32) -> Result<Self, Error> {
        if len == 0 || len > MAX_FRAME_SPAN {
            return Err(Error::BadPlan {
                what: "a range needs 1 ..= MAX_FRAME_SPAN (2^24) IDs",
                value: len as u64,
            });
        }
        Ok(PassIds { first, len })
    }

    /// The first ID.
    #[inline]
    #[must_use]
    pub fn first(&self) -> AllocId {
        self.first
    }

    /// The last ID: a block tagged with it frees only once the GPU is past the whole range.
    #[inline]
    #[must_use]
    pub fn last(&self) -> AllocId {
        self.first.add(self.len - 1)
    }

    /// IDs in the range (at least 1).
    #[inline]
    #[must_use]
    #[allow(clippy::len_without_is_empty)] // a range is never empty
    pub fn len(&self) -> u32 {
        self.len
    }

    /// The `k`-th ID of the range, if `k < len`.
    #[must_use]
    pub fn get(&self, k: u32) -> Option<AllocId> {
        (k < self.len).then(|| self.first.add(k))
    }

    /// Whether `id` lies in the range.
    #[must_use]
    pub fn contains(&self, id: AllocId) -> bool {
        id.distance_from(self.first) < self.len
    }

    /// Part `part` of `parts` near-equal consecutive sub-ranges, in order (the first
    /// `len % parts` parts get one extra ID). Part `i` comes entirely before part `i + 1`,
    /// so tasks consumed in part order may each allocate from their own part.
    /// [`Error::NoSuchPass`] when `part >= parts`, [`Error::BadPlan`] when `parts` is 0 or
    /// exceeds `len`.
    pub fn split(&self, part: u32, parts: u32) -> Result<PassIds, Error> {
        if parts == 0 || parts > self.len {
            return Err(Error::BadPlan {
                what: "a range splits into 1 ..= len parts",
                value: parts as u64,
            });
        }
        if part >= parts {
            return Err(Error::NoSuchPass {
                index: part,
                count: parts,
            });
        }
        let (q, r) = (self.len / parts, self.len % parts);
        let start = part * q + part.min(r);
        let len = q + u32::from(part < r);
        Ok(PassIds {
            first: self.first.add(start),
            len,
        })
    }

    /// A cursor handing out the range's IDs in order.
    #[must_use]
    pub fn cursor(&self) -> IdCursor {
        IdCursor {
            range: *self,
            used: 0,
        }
    }
}

/// Hands out a [`PassIds`] range's IDs in order, one call at a time (single-threaded; give
/// each thread its own sub-range with [`PassIds::split`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct IdCursor {
    range: PassIds,
    used: u32,
}

impl IdCursor {
    /// The next ID, or [`Error::RangeExhausted`] once all are handed out.
    #[allow(clippy::should_implement_trait)] // fallible, unlike Iterator::next
    pub fn next(&mut self) -> Result<AllocId, Error> {
        let id = self.peek()?;
        self.used += 1;
        Ok(id)
    }

    /// The ID [`IdCursor::next`] would return, without taking it.
    pub fn peek(&self) -> Result<AllocId, Error> {
        self.range.get(self.used).ok_or(Error::RangeExhausted {
            first: self.range.first,
            len: self.range.len,
        })
    }

    /// IDs not yet handed out.
    #[must_use]
    pub fn remaining(&self) -> u32 {
        self.range.len - self.used
    }

    /// The range being handed out.
    #[must_use]
    pub fn range(&self) -> PassIds {
        self.range
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kz2_example_frame() {
        // The talk's numbers, with its gaps folded into the budgets.
        let plan = FramePlan::new(&[200, 900, 200]).unwrap();
        assert_eq!(plan.span(), 1300);
        assert_eq!(plan.budget(1), Ok(900));
        let f = plan.frame(AllocId(1000));
        let passes: [PassIds; 3] = core::array::from_fn(|i| f.pass(i as u32).unwrap());
        assert_eq!(passes.map(|p| p.first().0), [1000, 1200, 2100]);
        assert_eq!(passes.map(|p| p.last().0), [1199, 2099, 2299]);
        assert_eq!(f.next().first(), AllocId(2300));
        assert_eq!(plan.nth_frame(AllocId(1000), 1), f.next());
        assert_eq!(f.pass(3), Err(Error::NoSuchPass { index: 3, count: 3 }));
    }

    #[test]
    fn ranges_wrap_and_stay_ordered() {
        let plan = FramePlan::new(&[3, 5]).unwrap();
        let f = plan.nth_frame(AllocId(u32::MAX - 20), 3); // frame 3 straddles the wrap
        let (a, b) = (f.pass(0).unwrap(), f.pass(1).unwrap());
        assert!(a.last().precedes(b.first()));
        assert_eq!(b.first(), a.last().next());
        assert_eq!(f.last(), b.last());
        assert!(f.last().precedes(f.next().first()));
        assert!(b.contains(b.first()) && b.contains(b.last()) && !b.contains(a.last()));
    }

    #[test]
    fn split_partitions_the_range_in_order() {
        for len in 1..40u32 {
            let r = PassIds::new(AllocId(u32::MAX - 7), len).unwrap();
            for parts in 1..=len {
                let mut expect = r.first();
                for p in 0..parts {
                    let s = r.split(p, parts).unwrap();
                    assert_eq!(s.first(), expect, "len {len} parts {parts} part {p}");
                    assert!(s.len() == len / parts || s.len() == len / parts + 1);
                    expect = s.last().next();
                }
                assert_eq!(expect, r.last().next());
            }
            assert!(r.split(0, len + 1).is_err());
            assert!(r.split(0, 0).is_err());
        }
    }

    #[test]
    fn cursor_hands_out_each_id_once() {
        let r = PassIds::new(AllocId(10), 3).unwrap();
        let mut c = r.cursor();
        assert_eq!(c.peek(), Ok(AllocId(10)));
        assert_eq!(
            [c.next(), c.next(), c.next()],
            [Ok(AllocId(10)), Ok(AllocId(11)), Ok(AllocId(12))]
        );
        assert_eq!(c.remaining(), 0);
        assert_eq!(
            c.next(),
            Err(Error::RangeExhausted {
                first: AllocId(10),
                len: 3
            })
        );
    }

    #[test]
    fn bad_plans_are_rejected() {
        assert!(matches!(FramePlan::new(&[]), Err(Error::BadPlan { .. })));
        assert!(matches!(
            FramePlan::new(&[1, 0]),
            Err(Error::BadPlan { value: 1, .. })
        ));
        assert!(FramePlan::new(&[1; MAX_PASSES]).is_ok());
        assert!(FramePlan::new(&[1; MAX_PASSES + 1]).is_err());
        assert!(FramePlan::new(&[MAX_FRAME_SPAN]).is_ok());
        assert!(FramePlan::new(&[MAX_FRAME_SPAN, 1]).is_err());
        assert!(FramePlan::new(&[u32::MAX, u32::MAX]).is_err());
        assert!(PassIds::new(AllocId(0), 0).is_err());
        assert!(FramePlan::new(&[1]).unwrap().budget(1).is_err());
    }
}
