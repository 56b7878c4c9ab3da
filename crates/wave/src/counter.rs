//! The shared counter that appends go through: the GPU's `atomicAdd` on a storage `u32`.

use core::sync::atomic::{AtomicU32, AtomicUsize, Ordering};

/// A shared append counter: `atomic_add` adds `value` and returns the value before the add,
/// wrapping at `u32::MAX` like WGSL's `atomicAdd` on an `atomic<u32>`.
///
/// Implemented for [`AtomicU32`] (a plain counter), [`core::cell::Cell<u32>`] (single
/// thread) and [`CountedAtomicU32`] (which also counts the atomic operations, so tests
/// and benches can assert how many were issued).
/// Implement it for your own type to model another memory (for example a per-tile counter
/// in an array).
pub trait Counter {
    /// Atomically adds `value`, returning the previous value (wrapping on overflow).
    fn atomic_add(&self, value: u32) -> u32;
}

impl Counter for AtomicU32 {
    fn atomic_add(&self, value: u32) -> u32 {
        // Relaxed: the counter only hands out disjoint slots; the writes into them are
        // published by whatever joins the threads (rayon's join, a GPU pass boundary).
        self.fetch_add(value, Ordering::Relaxed)
    }
}

/// A single-threaded counter (a CPU twin that runs its waves one after another needs no
/// atomic). Wraps like the others.
impl Counter for core::cell::Cell<u32> {
    fn atomic_add(&self, value: u32) -> u32 {
        let old = self.get();
        self.set(old.wrapping_add(value));
        old
    }
}

impl<C: Counter + ?Sized> Counter for &C {
    fn atomic_add(&self, value: u32) -> u32 {
        (**self).atomic_add(value)
    }
}

/// An [`AtomicU32`] append counter that also counts the atomic operations performed on it,
/// so a test can assert "exactly one atomic per wave that had an active lane" and a bench
/// can report atomics per item.
///
/// ```
/// use wave::{Counter, CountedAtomicU32};
/// let c = CountedAtomicU32::new(10);
/// assert_eq!(c.atomic_add(3), 10);
/// assert_eq!(c.atomic_add(0), 13);
/// assert_eq!((c.value(), c.atomic_ops()), (13, 2));
/// ```
#[derive(Debug, Default)]
pub struct CountedAtomicU32 {
    value: AtomicU32,
    ops: AtomicUsize,
}

impl CountedAtomicU32 {
    /// A counter starting at `value`, with no operations counted yet.
    #[must_use]
    pub const fn new(value: u32) -> Self {
        Self {
            value: AtomicU32::new(value),
            ops: AtomicUsize::new(0),
        }
    }

    /// The current value (the number of items appended so far, plus the start value).
    #[must_use]
    pub fn value(&self) -> u32 {
        self.value.load(Ordering::Relaxed)
    }

    /// Number of [`atomic_add`](Counter::atomic_add) calls so far.
    #[must_use]
    pub fn atomic_ops(&self) -> usize {
        self.ops.load(Ordering::Relaxed)
    }

    /// Sets the value and clears the operation count (like clearing a GPU counter
    /// between passes). Takes `&mut self`, so no append can be in flight.
    pub fn reset(&mut self, value: u32) {
        *self.value.get_mut() = value;
        *self.ops.get_mut() = 0;
    }
}

impl Counter for CountedAtomicU32 {
    fn atomic_add(&self, value: u32) -> u32 {
        self.ops.fetch_add(1, Ordering::Relaxed);
        self.value.fetch_add(value, Ordering::Relaxed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::cell::Cell;

    #[test]
    fn every_counter_returns_the_old_value_and_wraps() {
        fn check(c: &impl Counter) {
            assert_eq!(c.atomic_add(5), u32::MAX - 2);
            assert_eq!(c.atomic_add(1), 2);
            assert_eq!(c.atomic_add(0), 3);
        }
        check(&AtomicU32::new(u32::MAX - 2));
        check(&Cell::new(u32::MAX - 2));
        let counted = CountedAtomicU32::new(u32::MAX - 2);
        check(&counted);
        check(&&AtomicU32::new(u32::MAX - 2));
        assert_eq!(counted.atomic_ops(), 3);
        let mut counted = counted;
        counted.reset(9);
        assert_eq!((counted.value(), counted.atomic_ops()), (9, 0));
    }
}
