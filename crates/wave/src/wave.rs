//! The CPU model of one wave: its width, its active lanes, per-lane registers, and the
//! cross-lane operations (ballot, prefix count, first active lane, broadcast, sums).

use core::ops::{Index, IndexMut};

use crate::{Error, LaneMask, WaveWidth};

/// A per-lane register (a VGPR): one value per lane of a wave of a given width.
///
/// Lanes `width..64` exist in storage but are never read by the wave operations; they
/// hold `T::default()` when built by [`from_fn`](Self::from_fn) or
/// [`from_slice`](Self::from_slice). Indexing with a lane `>= 64` panics like a slice.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PerLane<T> {
    width: WaveWidth,
    values: [T; 64],
}

impl<T: Copy + Default> PerLane<T> {
    /// `f(lane)` for each lane `0..width`.
    pub fn from_fn(width: WaveWidth, mut f: impl FnMut(u32) -> T) -> Self {
        let mut values = [T::default(); 64];
        for lane in 0..width.lanes() {
            values[lane as usize] = f(lane);
        }
        Self { width, values }
    }

    /// The same value in every lane (a scalar broadcast to a vector register).
    pub fn splat(width: WaveWidth, value: T) -> Self {
        Self::from_fn(width, |_| value)
    }

    /// One value per lane; `values.len()` must equal the width.
    pub fn from_slice(width: WaveWidth, values: &[T]) -> Result<Self, Error> {
        if values.len() != width.len() {
            return Err(Error::LaneCount {
                width,
                values: values.len(),
            });
        }
        Ok(Self::from_fn(width, |lane| values[lane as usize]))
    }
}

impl<T> PerLane<T> {
    /// The width this register was made for.
    #[must_use]
    pub fn width(&self) -> WaveWidth {
        self.width
    }

    /// The value of `lane`, if `lane < width`.
    #[must_use]
    pub fn get(&self, lane: u32) -> Option<&T> {
        if lane < self.width.lanes() {
            self.values.get(lane as usize)
        } else {
            None
        }
    }

    /// The lanes `0..width` in order.
    #[must_use]
    pub fn as_slice(&self) -> &[T] {
        &self.values[..self.width.len()]
    }
}

impl<T> Index<u32> for PerLane<T> {
    type Output = T;
    fn index(&self, lane: u32) -> &T {
        &self.values[lane as usize]
    }
}

impl<T> IndexMut<u32> for PerLane<T> {
    fn index_mut(&mut self, lane: u32) -> &mut T {
        &mut self.values[lane as usize]
    }
}

/// One wave: a width and the lanes active at this point of the program.
///
/// Lanes are numbered `0..width`; lane `i` is bit `i` of every [`LaneMask`]. A lane that is
/// not active (past the end of the input, or on the other side of a branch) takes no part
/// in any operation: it does not vote in [`ballot`](Self::ballot), is skipped by the
/// prefix sums and cannot be broadcast from, exactly as on the GPU.
///
/// ```
/// use wave::{LaneMask, Wave, WaveWidth};
/// let wave = Wave::new(WaveWidth::W8);
/// let hits = wave.ballot(|lane| lane % 3 == 0); // lanes 0, 3, 6
/// assert_eq!(hits, LaneMask(0b0100_1001));
/// let visible = wave.restrict(hits);
/// assert_eq!(visible.first_active_lane(), Some(0));
/// assert_eq!(visible.prefix_count(6), 2); // MaskBitCnt: lanes 0 and 3 are below 6
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Wave {
    width: WaveWidth,
    active: LaneMask,
}

impl Wave {
    /// A wave with every lane active.
    #[must_use]
    pub const fn new(width: WaveWidth) -> Wave {
        Wave {
            width,
            active: width.full_mask(),
        }
    }

    /// A wave with the given active lanes, which must lie within the width.
    pub const fn with_active(width: WaveWidth, active: LaneMask) -> Result<Wave, Error> {
        if !active.is_subset_of(width.full_mask()) {
            return Err(Error::MaskOutsideWidth {
                width,
                mask: active,
            });
        }
        Ok(Wave { width, active })
    }

    /// A wave whose first `lanes` lanes are active: the last, partial wave of a dispatch
    /// over `n` items has `n % width` of them. `lanes` must not exceed the width.
    pub const fn with_lane_count(width: WaveWidth, lanes: u32) -> Result<Wave, Error> {
        if lanes > width.lanes() {
            return Err(Error::LaneCount {
                width,
                values: lanes as usize,
            });
        }
        Ok(Wave {
            width,
            active: LaneMask::first_lanes(lanes),
        })
    }

    /// The width in lanes.
    #[must_use]
    pub const fn width(&self) -> WaveWidth {
        self.width
    }

    /// The active lanes (what `ballot(true)` returns).
    #[must_use]
    pub const fn active(&self) -> LaneMask {
        self.active
    }

    /// Number of active lanes (`popcnt(ballot(true))`).
    #[must_use]
    pub const fn active_count(&self) -> u32 {
        self.active.count()
    }

    /// Whether no lane is active.
    #[must_use]
    pub const fn is_empty(&self) -> bool {
        self.active.is_empty()
    }

    /// The wave inside `if (mask bit set)`: the active lanes that are also in `mask`.
    #[must_use]
    pub const fn restrict(self, mask: LaneMask) -> Wave {
        Wave {
            width: self.width,
            active: LaneMask(self.active.0 & mask.0),
        }
    }

    /// The wave inside `if (pred(lane))`: the active lanes for which `pred` holds. `pred`
    /// is called once per active lane, lowest first.
    #[must_use]
    pub fn branch(self, pred: impl FnMut(u32) -> bool) -> Wave {
        let mask = self.ballot(pred);
        self.restrict(mask)
    }

    /// `ballot(pred)`: the mask of active lanes for which `pred(lane)` holds. `pred` is
    /// called once per active lane, lowest first; inactive lanes do not vote.
    pub fn ballot(&self, mut pred: impl FnMut(u32) -> bool) -> LaneMask {
        let mut bits = 0u64;
        for lane in self.active {
            if pred(lane) {
                bits |= 1 << lane;
            }
        }
        LaneMask(bits)
    }

    /// `ballot(values[lane])` over a per-lane boolean register.
    #[must_use]
    pub fn ballot_lanes(&self, values: &PerLane<bool>) -> LaneMask {
        self.ballot(|lane| values[lane])
    }

    /// The talk's `MaskBitCnt(active_mask)` for `lane`: how many active lanes are below it.
    /// This is the lane's offset in an aggregated append.
    #[must_use]
    pub const fn prefix_count(&self, lane: u32) -> u32 {
        self.active.count_below(lane)
    }

    /// The lowest active lane (the one `ReadFirstLane` reads, and the elected leader).
    #[must_use]
    pub const fn first_active_lane(&self) -> Option<u32> {
        self.active.first()
    }

    /// Whether `lane` is the elected leader: `ReadFirstLane(lane_id) == lane_id`.
    #[must_use]
    pub const fn is_first_active_lane(&self, lane: u32) -> bool {
        match self.active.first() {
            Some(first) => first == lane,
            None => false,
        }
    }

    /// `lane`'s value in `values`, as every lane sees it after a broadcast; `None` if
    /// `lane` is not active (reading an inactive lane is undefined on the GPU).
    #[must_use]
    pub fn broadcast<T: Copy>(&self, values: &PerLane<T>, lane: u32) -> Option<T> {
        if self.active.contains(lane) {
            values.get(lane).copied()
        } else {
            None
        }
    }

    /// `ReadFirstLane(values)` / `subgroupBroadcastFirst`: the first active lane's value,
    /// `None` when no lane is active.
    #[must_use]
    pub fn broadcast_first<T: Copy>(&self, values: &PerLane<T>) -> Option<T> {
        self.broadcast(values, self.first_active_lane()?)
    }

    /// `subgroupExclusiveAdd(values)`: for each active lane, the wrapping sum of `values`
    /// over the active lanes below it. Inactive lanes get 0.
    #[must_use]
    pub fn exclusive_add(&self, values: &PerLane<u32>) -> PerLane<u32> {
        let mut out = PerLane::splat(self.width, 0u32);
        let mut sum = 0u32;
        for lane in self.active {
            out[lane] = sum;
            sum = sum.wrapping_add(values[lane]);
        }
        out
    }

    /// `subgroupAdd(values)`: the wrapping sum over the active lanes.
    #[must_use]
    pub fn sum(&self, values: &PerLane<u32>) -> u32 {
        self.active
            .iter()
            .fold(0u32, |acc, lane| acc.wrapping_add(values[lane]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn construction_checks_the_width() {
        assert!(Wave::with_active(WaveWidth::W8, LaneMask(0x1ff)).is_err());
        assert_eq!(
            Wave::with_active(WaveWidth::W8, LaneMask(0xff)),
            Ok(Wave::new(WaveWidth::W8))
        );
        assert_eq!(
            Wave::with_lane_count(WaveWidth::W16, 5).unwrap().active(),
            LaneMask(0b11111)
        );
        assert!(Wave::with_lane_count(WaveWidth::W16, 17).is_err());
        assert_eq!(Wave::new(WaveWidth::W64).active_count(), 64);
        assert!(PerLane::from_slice(WaveWidth::W8, &[0u32; 7]).is_err());
    }

    #[test]
    fn inactive_lanes_do_not_vote_or_broadcast() {
        let wave = Wave::with_active(WaveWidth::W8, LaneMask(0b1011_0100)).unwrap();
        let mut asked = std::vec::Vec::new();
        let m = wave.ballot(|lane| {
            asked.push(lane);
            true
        });
        assert_eq!(asked, [2, 4, 5, 7]);
        assert_eq!(m, wave.active());
        let v = PerLane::from_fn(WaveWidth::W8, |lane| lane * 10);
        assert_eq!(wave.broadcast(&v, 3), None);
        assert_eq!(wave.broadcast(&v, 4), Some(40));
        assert_eq!(wave.broadcast_first(&v), Some(20));
        assert!(wave.is_first_active_lane(2));
        assert!(!wave.is_first_active_lane(0));
        let empty = wave.restrict(LaneMask::EMPTY);
        assert_eq!(empty.broadcast_first(&v), None);
        assert!(!empty.is_first_active_lane(0));
    }

    #[test]
    fn scans_against_a_running_total() {
        let wave = Wave::with_active(WaveWidth::W16, LaneMask(0b0110_1101_0011_1010)).unwrap();
        let v = PerLane::from_fn(WaveWidth::W16, |lane| lane * lane + 1);
        let ex = wave.exclusive_add(&v);
        for lane in 0..16 {
            let expect: u32 = (0..lane)
                .filter(|&l| wave.active().contains(l))
                .map(|l| l * l + 1)
                .sum();
            let got = ex[lane];
            if wave.active().contains(lane) {
                assert_eq!(got, expect, "lane {lane}");
            } else {
                assert_eq!(got, 0);
            }
        }
        let total: u32 = wave.active().iter().map(|l| l * l + 1).sum();
        assert_eq!(wave.sum(&v), total);
    }
}
