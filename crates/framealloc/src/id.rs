//! Allocation IDs and their wrap-around-safe comparison.
//!
//! An [`AllocId`] is a 32-bit counter that grows in the order the GPU consumes work. It
//! wraps around after 2^32 IDs, so IDs are compared with serial-number arithmetic (the
//! scheme of RFC 1982, as TCP sequence numbers are): `a` is before `b` when the wrapping
//! difference `b - a` lies in `1 ..= 2^31 - 1`. That order is only meaningful between IDs
//! less than 2^31 apart; the pool keeps every ID it compares within that window (see
//! [`MAX_ID_LEAD`], [`MAX_FREE_STEP`] and the sweep described in [`crate::pool`]).
//!
//! IDs are 32-bit on purpose: it is what a GPU can write (WGSL has `u32`, and no 64-bit
//! atomics in core), as the RSX wrote KZ2's FreeID from a push-buffer marker.

use core::cmp::Ordering;
use core::fmt;

/// The furthest an allocation's ID may be ahead of the current FreeID, in IDs (2^30).
///
/// Live blocks therefore never sit more than 2^30 IDs ahead of FreeID, half the window in
/// which wrap-around comparison is defined. At 10,000 IDs per frame and 60 frames per
/// second that is 30 minutes of frames in flight: far beyond any real pipeline.
pub const MAX_ID_LEAD: u32 = 1 << 30;

/// The furthest one [`crate::BlockPool::advance_free_id`] call may move FreeID, in IDs
/// (2^30).
pub const MAX_FREE_STEP: u32 = 1 << 30;

/// An AllocationID: the 32-bit, wrapping tag a client gives a block when it allocates it.
///
/// The block stays live until the pool's FreeID reaches this ID. IDs must grow in the order
/// the GPU consumes the blocks (see [`crate::plan`] for per-pass ranges).
///
/// `AllocId` deliberately implements neither `Ord` nor `PartialOrd`: with wrap-around there
/// is no total order. Compare with [`AllocId::precedes`], [`AllocId::is_at_or_before`] or
/// [`AllocId::serial_cmp`].
///
/// ```
/// use framealloc::AllocId;
/// let a = AllocId(u32::MAX);
/// let b = a.add(2); // wrapped to 1
/// assert_eq!(b, AllocId(1));
/// assert!(a.precedes(b));
/// assert!(!b.precedes(a));
/// assert_eq!(b.distance_from(a), 2);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct AllocId(pub u32);

impl AllocId {
    /// The ID `n` steps after this one, wrapping.
    #[inline]
    #[must_use]
    pub const fn add(self, n: u32) -> AllocId {
        AllocId(self.0.wrapping_add(n))
    }

    /// The ID right after this one, wrapping.
    #[inline]
    #[must_use]
    pub const fn next(self) -> AllocId {
        self.add(1)
    }

    /// The ID `n` steps before this one, wrapping.
    #[inline]
    #[must_use]
    pub const fn sub(self, n: u32) -> AllocId {
        AllocId(self.0.wrapping_sub(n))
    }

    /// How many steps forward from `earlier` to `self`, wrapping (`self - earlier` mod
    /// 2^32). Meaningful when `earlier` is at or before `self`.
    #[inline]
    #[must_use]
    pub const fn distance_from(self, earlier: AllocId) -> u32 {
        self.0.wrapping_sub(earlier.0)
    }

    /// True when `self` comes strictly before `other`: `other - self` (wrapping) is in
    /// `1 ..= 2^31 - 1`.
    #[inline]
    #[must_use]
    pub const fn precedes(self, other: AllocId) -> bool {
        (other.0.wrapping_sub(self.0) as i32) > 0
    }

    /// True when `self` equals `other` or comes before it: `other - self` (wrapping) is in
    /// `0 ..= 2^31 - 1`. This is KZ2's `AllocationID <= FreeID` test.
    #[inline]
    #[must_use]
    pub const fn is_at_or_before(self, other: AllocId) -> bool {
        (other.0.wrapping_sub(self.0) as i32) >= 0
    }

    /// Serial-number comparison: `Some(Less)` when `self` precedes `other`, `Some(Equal)`
    /// when equal, `Some(Greater)` when `other` precedes `self`, and `None` for the one
    /// undefined case, IDs exactly 2^31 apart.
    #[must_use]
    pub const fn serial_cmp(self, other: AllocId) -> Option<Ordering> {
        let d = other.0.wrapping_sub(self.0);
        if d == 0 {
            Some(Ordering::Equal)
        } else if d == 1 << 31 {
            None
        } else if (d as i32) > 0 {
            Some(Ordering::Less)
        } else {
            Some(Ordering::Greater)
        }
    }
}

impl fmt::Display for AllocId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "#{}", self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reference: compare in i64 after unwrapping around a known base.
    fn unwrapped(base: u64, x: u64) -> AllocId {
        AllocId((base + x) as u32)
    }

    #[test]
    fn order_holds_across_the_wrap() {
        for base in [0u64, 1, 0x7fff_fff0, 0x8000_0000, 0xffff_ff00, 0xffff_ffff] {
            for x in 0..40u64 {
                for y in 0..40u64 {
                    let (a, b) = (unwrapped(base, x), unwrapped(base, y));
                    assert_eq!(a.precedes(b), x < y, "base {base:#x} x {x} y {y}");
                    assert_eq!(a.is_at_or_before(b), x <= y);
                    assert_eq!(a.serial_cmp(b), Some(x.cmp(&y)));
                    if x <= y {
                        assert_eq!(b.distance_from(a) as u64, y - x);
                    }
                }
            }
        }
    }

    #[test]
    fn window_edges() {
        let a = AllocId(5);
        assert!(a.precedes(a.add((1 << 31) - 1)));
        assert!(!a.precedes(a.add(1 << 31)));
        assert_eq!(a.serial_cmp(a.add(1 << 31)), None);
        assert!(a.add((1 << 31) + 1).precedes(a));
        assert_eq!(a.sub(3).next(), AllocId(3));
        assert_eq!(AllocId(0).sub(1), AllocId(u32::MAX));
    }

    #[test]
    fn display() {
        extern crate alloc;
        assert_eq!(alloc::format!("{}", AllocId(42)), "#42");
    }
}
