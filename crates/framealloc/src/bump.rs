//! The double-ended bump allocator inside one block (KZ2's push-buffer trick).
//!
//! Commands grow from the front of the block, the data they use grows down from the back,
//! and the block is full when the two meet. Data generated just in time for a command then
//! lives in the same block and frees with it.
//!
//! ```text
//!  0                front                  back               bytes
//!  | commands ...  -> |      free gap       | <- ... data       |
//! ```
//!
//! Offsets are bytes from the start of the block. Every alignment must be a power of two
//! that divides the block size, so an offset aligned in the block is aligned in the pool
//! too (blocks start at multiples of the block size).

use core::ops::Range;

use crate::Error;

/// A double-ended bump allocator over one block of `capacity` bytes.
///
/// ```
/// use framealloc::{BlockBump, Error};
/// let mut b = BlockBump::new(1024);
/// assert_eq!(b.push_front(100, 4)?, 0);      // a command at the front
/// assert_eq!(b.push_back(256, 256)?, 768);   // its data at the back, 256-aligned
/// assert_eq!(b.push_front(8, 16)?, 112);     // the next command, padded to 16
/// assert_eq!(b.free(), 768 - 120);
/// assert!(matches!(b.push_back(700, 4), Err(Error::BlockFull { .. })));
/// # Ok::<(), Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BlockBump {
    capacity: u32,
    /// First byte after the commands.
    front: u32,
    /// First byte of the data.
    back: u32,
}

impl BlockBump {
    /// An empty block of `capacity` bytes.
    #[must_use]
    pub const fn new(capacity: u32) -> Self {
        BlockBump {
            capacity,
            front: 0,
            back: capacity,
        }
    }

    /// Bytes in the block.
    #[inline]
    #[must_use]
    pub fn capacity(&self) -> u32 {
        self.capacity
    }

    /// Bytes still free between the commands and the data.
    #[inline]
    #[must_use]
    pub fn free(&self) -> u32 {
        self.back - self.front
    }

    /// The bytes the commands occupy (padding included): `0 .. front`.
    #[inline]
    #[must_use]
    pub fn front_range(&self) -> Range<u32> {
        0..self.front
    }

    /// The bytes the data occupies (padding included): `back .. capacity`.
    #[inline]
    #[must_use]
    pub fn back_range(&self) -> Range<u32> {
        self.back..self.capacity
    }

    /// Forgets every allocation: the whole block is free again.
    pub fn reset(&mut self) {
        self.front = 0;
        self.back = self.capacity;
    }

    pub(crate) fn check(&self, bytes: u32, align: u32) -> Result<(), Error> {
        if align == 0 || !align.is_power_of_two() || !self.capacity.is_multiple_of(align) {
            return Err(Error::BadAlignment {
                align,
                block_bytes: self.capacity,
            });
        }
        if bytes > self.capacity {
            return Err(Error::TooLarge {
                bytes,
                block_bytes: self.capacity,
            });
        }
        Ok(())
    }

    fn full(&self, bytes: u32, align: u32) -> Error {
        Error::BlockFull {
            bytes,
            align,
            free: self.free(),
        }
    }

    /// Where a front allocation would start, if it fits.
    fn front_fit(&self, bytes: u32, align: u32) -> Option<u32> {
        let start = (self.front as u64).next_multiple_of(align as u64);
        (start + bytes as u64 <= self.back as u64).then_some(start as u32)
    }

    /// Where a back allocation would start, if it fits.
    fn back_fit(&self, bytes: u32, align: u32) -> Option<u32> {
        let start = self.back.checked_sub(bytes)? & !(align - 1);
        (start >= self.front).then_some(start)
    }

    /// Allocates `bytes` at the front (commands), aligned to `align`; returns the offset in
    /// the block. Zero bytes are allowed (an aligned position, consuming only padding).
    /// [`Error::BlockFull`] when it would cross the data, [`Error::TooLarge`] when it could
    /// never fit, [`Error::BadAlignment`] for an alignment that is not a power of two
    /// dividing the capacity. A failed call changes nothing.
    pub fn push_front(&mut self, bytes: u32, align: u32) -> Result<u32, Error> {
        self.check(bytes, align)?;
        let start = self
            .front_fit(bytes, align)
            .ok_or(self.full(bytes, align))?;
        self.front = start + bytes;
        Ok(start)
    }

    /// Allocates `bytes` at the back (data), aligned to `align`; returns the offset in the
    /// block. Errors as [`BlockBump::push_front`].
    pub fn push_back(&mut self, bytes: u32, align: u32) -> Result<u32, Error> {
        self.check(bytes, align)?;
        let start = self.back_fit(bytes, align).ok_or(self.full(bytes, align))?;
        self.back = start;
        Ok(start)
    }

    /// Whether [`BlockBump::push_front`] would succeed.
    #[must_use]
    pub fn fits_front(&self, bytes: u32, align: u32) -> bool {
        self.check(bytes, align).is_ok() && self.front_fit(bytes, align).is_some()
    }

    /// Whether [`BlockBump::push_back`] would succeed.
    #[must_use]
    pub fn fits_back(&self, bytes: u32, align: u32) -> bool {
        self.check(bytes, align).is_ok() && self.back_fit(bytes, align).is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::vec::Vec;

    #[test]
    fn meets_in_the_middle() {
        let mut b = BlockBump::new(256);
        assert_eq!(b.push_front(100, 1), Ok(0));
        assert_eq!(b.push_back(100, 1), Ok(156));
        assert_eq!(b.free(), 56);
        assert_eq!(b.push_front(56, 1), Ok(100));
        assert_eq!(b.free(), 0);
        assert_eq!(
            b.push_back(1, 1),
            Err(Error::BlockFull {
                bytes: 1,
                align: 1,
                free: 0
            })
        );
        assert_eq!(b.push_front(0, 1), Ok(156));
        assert_eq!(b.push_back(0, 1), Ok(156));
        b.reset();
        assert_eq!(b.free(), 256);
    }

    #[test]
    fn alignment_pads_outward_from_each_end() {
        let mut b = BlockBump::new(1024);
        assert_eq!(b.push_front(3, 1), Ok(0));
        assert_eq!(b.push_front(4, 64), Ok(64));
        assert_eq!(b.front_range(), 0..68);
        assert_eq!(b.push_back(3, 1), Ok(1021));
        assert_eq!(b.push_back(10, 256), Ok(768));
        assert_eq!(b.back_range(), 768..1024);
        // Only the aligned gap counts: 68..768 has 700 bytes, but a 256-aligned
        // 600-byte allocation from the back would start at 0.
        assert!(!b.fits_back(600, 256));
        assert!(b.fits_back(500, 256) && b.fits_back(700, 4) && !b.fits_back(701, 1));
    }

    #[test]
    fn bad_requests_are_errors_and_change_nothing() {
        let mut b = BlockBump::new(512);
        let before = b;
        for align in [0, 3, 1024] {
            assert_eq!(
                b.push_front(1, align),
                Err(Error::BadAlignment {
                    align,
                    block_bytes: 512
                })
            );
        }
        assert_eq!(
            b.push_back(513, 1),
            Err(Error::TooLarge {
                bytes: 513,
                block_bytes: 512
            })
        );
        assert_eq!(b, before);
        let mut odd = BlockBump::new(u32::MAX);
        assert_eq!(odd.push_front(u32::MAX, 1), Ok(0));
        assert!(odd.push_back(1, 1).is_err());
    }

    /// Random sequences against a brute-force byte map: no two allocations overlap,
    /// each is aligned and in bounds, and a failure happens exactly when no aligned gap
    /// of the right side remains.
    #[test]
    fn never_overlaps_against_a_byte_map() {
        let mut rng = testkit::Rng::new(0x1234_5678_9abc_def0);
        let mut rnd = |m: u64| rng.below(m);
        for _ in 0..200 {
            let cap = 64 << rnd(4);
            let mut b = BlockBump::new(cap as u32);
            let mut used = Vec::from_iter((0..cap).map(|_| false));
            // The reference tracks the ends itself.
            let (mut lo, mut hi) = (0u64, cap);
            for _ in 0..40 {
                let bytes = rnd(40) as u32;
                let align = 1u32 << rnd(6);
                let front = rnd(2) == 0;
                let want = if front {
                    let s = lo.div_ceil(align as u64) * align as u64;
                    (s + bytes as u64 <= hi).then_some(s)
                } else {
                    let s = (hi.checked_sub(bytes as u64)).map(|s| s / align as u64 * align as u64);
                    s.filter(|&s| s >= lo)
                };
                let got = if front {
                    b.push_front(bytes, align)
                } else {
                    b.push_back(bytes, align)
                };
                match (want, got) {
                    (Some(s), Ok(o)) => {
                        assert_eq!(s, o as u64);
                        assert_eq!(o % align, 0);
                        for k in o..o + bytes {
                            assert!(!used[k as usize], "byte {k} handed out twice");
                            used[k as usize] = true;
                        }
                        if front {
                            lo = s + bytes as u64;
                        } else {
                            hi = s;
                        }
                    }
                    (None, Err(Error::BlockFull { .. })) => {}
                    (w, g) => panic!("reference {w:?}, got {g:?}"),
                }
                assert_eq!(b.free() as u64, hi - lo);
            }
        }
    }
}
