//! Wave widths and lane masks: the scalar values a `ballot()` returns.

use core::fmt;
use core::ops::{BitAnd, BitAndAssign, BitOr, BitOrAssign, BitXor, Not};

use crate::Error;

/// The lanes of the widest supported wave (PS4's wavefront).
pub const WAVE_WIDTH_MAX: u32 = 64;

/// A wave (wavefront, warp, subgroup) width in lanes.
///
/// The talk's diagrams use 8 lanes, NVIDIA's warps (the H100) 32, the PS4's wavefronts 64;
/// some mobile and software adapters (lavapipe) run 8 or 16.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(u8)]
pub enum WaveWidth {
    /// 8 lanes: the talk's simplified diagrams, lavapipe.
    W8 = 8,
    /// 16 lanes.
    W16 = 16,
    /// 32 lanes: NVIDIA warps, RDNA wave32.
    W32 = 32,
    /// 64 lanes: GCN wavefronts (PS4).
    W64 = 64,
}

impl WaveWidth {
    /// Every supported width, narrowest first.
    pub const ALL: [WaveWidth; 4] = [Self::W8, Self::W16, Self::W32, Self::W64];

    /// The width for a lane count, if it is one of 8, 16, 32 or 64.
    pub const fn from_lanes(lanes: u32) -> Result<WaveWidth, Error> {
        match lanes {
            8 => Ok(Self::W8),
            16 => Ok(Self::W16),
            32 => Ok(Self::W32),
            64 => Ok(Self::W64),
            _ => Err(Error::UnsupportedWidth { lanes }),
        }
    }

    /// Number of lanes.
    #[must_use]
    pub const fn lanes(self) -> u32 {
        self as u32
    }

    /// Number of lanes, as a slice length.
    #[must_use]
    pub const fn len(self) -> usize {
        self as usize
    }

    /// Always false: a wave has at least 8 lanes (for clippy's `len` without `is_empty`).
    #[must_use]
    pub const fn is_empty(self) -> bool {
        false
    }

    /// The mask with every lane of this width set.
    #[must_use]
    pub const fn full_mask(self) -> LaneMask {
        LaneMask::first_lanes(self.lanes())
    }
}

impl TryFrom<u32> for WaveWidth {
    type Error = Error;
    fn try_from(lanes: u32) -> Result<Self, Error> {
        Self::from_lanes(lanes)
    }
}

impl fmt::Display for WaveWidth {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} lanes", self.lanes())
    }
}

/// One bit per lane: bit `i` is lane `i` (lane 0 is the least significant bit), as
/// `ballot()` returns it on GCN and as WGSL's `subgroupBallot` returns it in `.x` (lanes
/// 0-31) and `.y` (lanes 32-63).
///
/// | bits | lanes |
/// | --- | --- |
/// | 0 | lane 0 |
/// | i | lane i |
/// | 63 | lane 63 |
///
/// Methods that take a lane accept any `u32`: lanes 64 and above are simply never set.
#[derive(Clone, Copy, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct LaneMask(pub u64);

impl LaneMask {
    /// No lane set.
    pub const EMPTY: LaneMask = LaneMask(0);

    /// Lanes `0..n` set (all 64 for `n >= 64`).
    #[must_use]
    pub const fn first_lanes(n: u32) -> LaneMask {
        if n >= 64 {
            LaneMask(u64::MAX)
        } else {
            LaneMask((1u64 << n) - 1)
        }
    }

    /// Only `lane` set (empty for `lane >= 64`).
    #[must_use]
    pub const fn lane(lane: u32) -> LaneMask {
        if lane >= 64 {
            LaneMask(0)
        } else {
            LaneMask(1u64 << lane)
        }
    }

    /// The raw bits.
    #[must_use]
    pub const fn bits(self) -> u64 {
        self.0
    }

    /// The mask as WGSL's `subgroupBallot` result: `vec4<u32>` with lanes 0-31 in `x`,
    /// 32-63 in `y`, and `z = w = 0`.
    #[must_use]
    pub const fn to_ballot_vec4(self) -> [u32; 4] {
        [self.0 as u32, (self.0 >> 32) as u32, 0, 0]
    }

    /// Whether `lane` is set.
    #[must_use]
    pub const fn contains(self, lane: u32) -> bool {
        lane < 64 && (self.0 >> lane) & 1 == 1
    }

    /// Whether no lane is set.
    #[must_use]
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// Number of set lanes: the talk's `popcnt(active_mask)`.
    #[must_use]
    pub const fn count(self) -> u32 {
        self.0.count_ones()
    }

    /// Number of set lanes strictly below `lane`: the talk's `MaskBitCnt`, the exclusive
    /// prefix count that gives each appending lane its offset. For `lane >= 64` it is
    /// [`count`](Self::count).
    #[must_use]
    pub const fn count_below(self, lane: u32) -> u32 {
        (self.0 & LaneMask::first_lanes(lane).0).count_ones()
    }

    /// The lowest set lane (`ReadFirstLane`'s source), if any.
    #[must_use]
    pub const fn first(self) -> Option<u32> {
        if self.0 == 0 {
            None
        } else {
            Some(self.0.trailing_zeros())
        }
    }

    /// The highest set lane, if any.
    #[must_use]
    pub const fn last(self) -> Option<u32> {
        if self.0 == 0 {
            None
        } else {
            Some(63 - self.0.leading_zeros())
        }
    }

    /// Whether every lane of `self` is also in `other`.
    #[must_use]
    pub const fn is_subset_of(self, other: LaneMask) -> bool {
        self.0 & !other.0 == 0
    }

    /// The set lanes, lowest first.
    pub fn iter(self) -> Lanes {
        Lanes(self.0)
    }

    /// The mask of the lanes for which `pred` holds, among lanes `0..width`.
    pub fn from_fn(width: WaveWidth, mut pred: impl FnMut(u32) -> bool) -> LaneMask {
        let mut bits = 0u64;
        for lane in 0..width.lanes() {
            if pred(lane) {
                bits |= 1 << lane;
            }
        }
        LaneMask(bits)
    }
}

impl fmt::Debug for LaneMask {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "LaneMask({:#018x})", self.0)
    }
}

impl fmt::Binary for LaneMask {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Binary::fmt(&self.0, f)
    }
}

impl BitAnd for LaneMask {
    type Output = LaneMask;
    fn bitand(self, rhs: LaneMask) -> LaneMask {
        LaneMask(self.0 & rhs.0)
    }
}

impl BitOr for LaneMask {
    type Output = LaneMask;
    fn bitor(self, rhs: LaneMask) -> LaneMask {
        LaneMask(self.0 | rhs.0)
    }
}

impl BitXor for LaneMask {
    type Output = LaneMask;
    fn bitxor(self, rhs: LaneMask) -> LaneMask {
        LaneMask(self.0 ^ rhs.0)
    }
}

impl Not for LaneMask {
    type Output = LaneMask;
    /// All 64 bits inverted: intersect with a wave's mask to stay within its width.
    fn not(self) -> LaneMask {
        LaneMask(!self.0)
    }
}

impl BitAndAssign for LaneMask {
    fn bitand_assign(&mut self, rhs: LaneMask) {
        self.0 &= rhs.0;
    }
}

impl BitOrAssign for LaneMask {
    fn bitor_assign(&mut self, rhs: LaneMask) {
        self.0 |= rhs.0;
    }
}

impl FromIterator<u32> for LaneMask {
    /// Sets each lane below 64; larger lane numbers are ignored.
    fn from_iter<I: IntoIterator<Item = u32>>(iter: I) -> LaneMask {
        let mut m = LaneMask::EMPTY;
        for lane in iter {
            m |= LaneMask::lane(lane);
        }
        m
    }
}

impl IntoIterator for LaneMask {
    type Item = u32;
    type IntoIter = Lanes;
    fn into_iter(self) -> Lanes {
        self.iter()
    }
}

/// Iterator over the set lanes of a [`LaneMask`], lowest first.
#[derive(Clone, Debug)]
pub struct Lanes(u64);

impl Iterator for Lanes {
    type Item = u32;
    fn next(&mut self) -> Option<u32> {
        if self.0 == 0 {
            return None;
        }
        let lane = self.0.trailing_zeros();
        self.0 &= self.0 - 1;
        Some(lane)
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let n = self.0.count_ones() as usize;
        (n, Some(n))
    }
}

impl ExactSizeIterator for Lanes {}
impl core::iter::FusedIterator for Lanes {}

#[cfg(test)]
mod tests {
    use super::*;

    /// MaskBitCnt by a loop over lanes, independent of the bit trick.
    fn naive_count_below(m: u64, lane: u32) -> u32 {
        (0..lane.min(64)).filter(|&l| (m >> l) & 1 == 1).count() as u32
    }

    #[test]
    fn count_below_matches_a_loop() {
        for m in [
            0u64,
            1,
            0b1011_0110,
            u64::MAX,
            0x8000_0000_0000_0001,
            0xdead_beef_0bad_f00d,
        ] {
            for lane in 0..70 {
                assert_eq!(
                    LaneMask(m).count_below(lane),
                    naive_count_below(m, lane),
                    "{m:#x} {lane}"
                );
            }
        }
    }

    #[test]
    fn first_last_and_iter() {
        let m = LaneMask(0b1010_0100);
        assert_eq!(m.first(), Some(2));
        assert_eq!(m.last(), Some(7));
        assert_eq!(m.iter().collect::<std::vec::Vec<_>>(), [2, 5, 7]);
        assert_eq!(LaneMask::EMPTY.first(), None);
        assert_eq!(LaneMask::EMPTY.last(), None);
        assert_eq!(LaneMask(1 << 63).last(), Some(63));
        assert_eq!([2u32, 5, 7, 99].into_iter().collect::<LaneMask>(), m);
    }

    #[test]
    fn widths() {
        for w in WaveWidth::ALL {
            assert_eq!(WaveWidth::from_lanes(w.lanes()), Ok(w));
            assert_eq!(w.full_mask().count(), w.lanes());
        }
        assert_eq!(
            WaveWidth::from_lanes(48),
            Err(Error::UnsupportedWidth { lanes: 48 })
        );
        assert_eq!(
            WaveWidth::try_from(128u32).unwrap_err(),
            Error::UnsupportedWidth { lanes: 128 }
        );
    }

    #[test]
    fn ballot_vec4_layout() {
        assert_eq!(
            LaneMask(0x0000_0002_8000_0001).to_ballot_vec4(),
            [0x8000_0001, 2, 0, 0]
        );
    }
}
