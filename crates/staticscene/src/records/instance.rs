//! The 16-byte packed [`QueryInstance`] and its unpacked [`InstanceFields`] (bit table in
//! the [parent module's docs](super)).

use bytemuck::{Pod, Zeroable};

use super::*;
use crate::{Error, Field};

const fn mask(bits: u32) -> u128 {
    (1u128 << bits) - 1
}

/// All fields of a [`QueryInstance`], unpacked.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct InstanceFields {
    /// Filter mask, 3 bits (`FILTER_*`).
    pub filter: u8,
    /// Flags, 2 bits (`INSTANCE_FLAG_*`).
    pub flags: u8,
    /// Setup index in the tile, 12 bits.
    pub setup: u16,
    /// Object index in the tile, 17 bits.
    pub object: u32,
    /// Parent LOD bounds index in the tile, 15 bits.
    pub parent_bounds: u16,
    /// Child LOD bounds index in the tile, 15 bits.
    pub child_bounds: u16,
    /// Local-to-object matrix index in the tile, 14 bits.
    pub matrix: u16,
    /// Parent LOD bracket.
    pub parent_lod: LodRange,
    /// Child LOD bracket.
    pub child_lod: LodRange,
    /// Last instance of its setup run (batching).
    pub group_end: bool,
}

/// One instance of one DrawableSetup of one placed object: the talk's 16-byte
/// QueryInstance, one compute thread each. Layout in the [module docs](super). WGSL:
/// `array<u32, 4>` (`StaticsceneQueryInstance`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Pod, Zeroable)]
pub struct QueryInstance {
    /// The 128 bits, little-endian words.
    pub words: [u32; 4],
}

const _: () = assert!(size_of::<QueryInstance>() == 16);

fn check(field: Field, value: u64, bits: u32) -> Result<u128, Error> {
    let max = (1u64 << bits) - 1;
    if value > max {
        return Err(Error::FieldOverflow { field, value, max });
    }
    Ok(u128::from(value))
}

impl QueryInstance {
    /// Packs `f`; a field that does not fit its bits is an error naming it.
    pub fn pack(f: &InstanceFields) -> Result<QueryInstance, Error> {
        let v = check(Field::Filter, u64::from(f.filter), FILTER_BITS)? << FILTER_SHIFT
            | check(Field::Flags, u64::from(f.flags), FLAGS_BITS)? << FLAGS_SHIFT
            | check(Field::Setup, u64::from(f.setup), SETUP_BITS)? << SETUP_SHIFT
            | check(Field::Object, u64::from(f.object), OBJECT_BITS)? << OBJECT_SHIFT
            | check(Field::ParentBounds, u64::from(f.parent_bounds), BOUNDS_BITS)?
                << PARENT_BOUNDS_SHIFT
            | check(Field::ChildBounds, u64::from(f.child_bounds), BOUNDS_BITS)?
                << CHILD_BOUNDS_SHIFT
            | check(Field::Matrix, u64::from(f.matrix), MATRIX_BITS)? << MATRIX_SHIFT
            | check(Field::ParentLodMin, u64::from(f.parent_lod.min.0), LOD_BITS)?
                << PARENT_LOD_MIN_SHIFT
            | check(Field::ParentLodMax, u64::from(f.parent_lod.max.0), LOD_BITS)?
                << PARENT_LOD_MAX_SHIFT
            | check(Field::ChildLodMin, u64::from(f.child_lod.min.0), LOD_BITS)?
                << CHILD_LOD_MIN_SHIFT
            | check(Field::ChildLodMax, u64::from(f.child_lod.max.0), LOD_BITS)?
                << CHILD_LOD_MAX_SHIFT
            | u128::from(f.group_end) << GROUP_END_SHIFT;
        Ok(Self::from_u128(v))
    }

    /// The instance from its 128 bits.
    #[must_use]
    pub const fn from_u128(v: u128) -> QueryInstance {
        QueryInstance {
            words: [
                v as u32,
                (v >> 32) as u32,
                (v >> 64) as u32,
                (v >> 96) as u32,
            ],
        }
    }

    /// The 128 bits.
    #[must_use]
    #[inline]
    pub const fn to_u128(self) -> u128 {
        self.words[0] as u128
            | (self.words[1] as u128) << 32
            | (self.words[2] as u128) << 64
            | (self.words[3] as u128) << 96
    }

    /// The 16 little-endian bytes.
    #[must_use]
    pub fn to_bytes(self) -> [u8; 16] {
        self.to_u128().to_le_bytes()
    }

    /// From 16 little-endian bytes, without validation (see [`try_unpack`](Self::try_unpack)).
    #[must_use]
    pub fn from_bytes(bytes: [u8; 16]) -> QueryInstance {
        Self::from_u128(u128::from_le_bytes(bytes))
    }

    /// Unpacks every field. Fails with [`Error::SpareBitSet`] if bit 127 is set; every
    /// other pattern is a valid instance, and `pack(try_unpack(x)) == x`.
    pub fn try_unpack(self) -> Result<InstanceFields, Error> {
        let v = self.to_u128();
        if v >> SPARE_SHIFT != 0 {
            return Err(Error::SpareBitSet);
        }
        let lod = |shift: u32| LodDistance(((v >> shift) & mask(LOD_BITS)) as u16);
        Ok(InstanceFields {
            filter: self.filter(),
            flags: self.flags(),
            setup: self.setup() as u16,
            object: self.object(),
            parent_bounds: self.parent_bounds() as u16,
            child_bounds: self.child_bounds() as u16,
            matrix: self.matrix() as u16,
            parent_lod: LodRange {
                min: lod(PARENT_LOD_MIN_SHIFT),
                max: lod(PARENT_LOD_MAX_SHIFT),
            },
            child_lod: LodRange {
                min: lod(CHILD_LOD_MIN_SHIFT),
                max: lod(CHILD_LOD_MAX_SHIFT),
            },
            group_end: self.group_end(),
        })
    }

    /// Filter mask (word 0 only: the early-out loads nothing else).
    #[must_use]
    #[inline]
    pub const fn filter(self) -> u8 {
        (self.words[0] & 7) as u8
    }

    /// Flags (`INSTANCE_FLAG_*`).
    #[must_use]
    #[inline]
    pub const fn flags(self) -> u8 {
        ((self.words[0] >> FLAGS_SHIFT) & 3) as u8
    }

    /// Setup index.
    #[must_use]
    #[inline]
    pub const fn setup(self) -> u32 {
        (self.words[0] >> SETUP_SHIFT) & 0xfff
    }

    /// Object index (bits 17-33, across words 0 and 1).
    #[must_use]
    #[inline]
    pub const fn object(self) -> u32 {
        (self.words[0] >> 17) | ((self.words[1] & 3) << 15)
    }

    /// Parent bounds index.
    #[must_use]
    #[inline]
    pub const fn parent_bounds(self) -> u32 {
        (self.words[1] >> 2) & 0x7fff
    }

    /// Child bounds index.
    #[must_use]
    #[inline]
    pub const fn child_bounds(self) -> u32 {
        self.words[1] >> 17
    }

    /// Matrix index.
    #[must_use]
    #[inline]
    pub const fn matrix(self) -> u32 {
        self.words[2] & 0x3fff
    }

    /// Parent LOD (min, max) codes.
    #[must_use]
    #[inline]
    pub const fn parent_lod_codes(self) -> (u32, u32) {
        (
            (self.words[2] >> 14) & 0xfff,
            (self.words[2] >> 26) | ((self.words[3] & 0x3f) << 6),
        )
    }

    /// Child LOD (min, max) codes.
    #[must_use]
    #[inline]
    pub const fn child_lod_codes(self) -> (u32, u32) {
        ((self.words[3] >> 6) & 0xfff, (self.words[3] >> 18) & 0xfff)
    }

    /// The group-end bit.
    #[must_use]
    #[inline]
    pub const fn group_end(self) -> bool {
        (self.words[3] >> 30) & 1 != 0
    }

    /// This instance with the group-end bit set to `end`.
    #[must_use]
    pub const fn with_group_end(self, end: bool) -> QueryInstance {
        let mut w = self.words;
        w[3] = (w[3] & !(1 << 30)) | ((end as u32) << 30);
        QueryInstance { words: w }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> InstanceFields {
        InstanceFields {
            filter: 5,
            flags: 2,
            setup: 0xabc,
            object: 0x1_2345,
            parent_bounds: 0x1234,
            child_bounds: 0x5678,
            matrix: 0x2ace,
            parent_lod: LodRange {
                min: LodDistance(0x123),
                max: LodDistance(0x456),
            },
            child_lod: LodRange {
                min: LodDistance(0x789),
                max: LodDistance(0xfff),
            },
            group_end: true,
        }
    }

    #[test]
    fn instance_golden_words() {
        // Computed independently (Python big integers, fields OR-ed at the table's shifts).
        let q = QueryInstance::pack(&sample()).unwrap();
        assert_eq!(
            q.words,
            [0x468b_5795, 0xacf0_48d2, 0x5848_eace, 0x7ffd_e251]
        );
        assert_eq!(q.try_unpack().unwrap(), sample());
        assert_eq!(
            q.to_bytes()[..4],
            [0x95, 0x57, 0x8b, 0x46],
            "little-endian bytes"
        );
    }

    #[test]
    fn instance_single_fields_land_on_their_bits() {
        let zero = InstanceFields {
            filter: 0,
            flags: 0,
            setup: 0,
            object: 0,
            parent_bounds: 0,
            child_bounds: 0,
            matrix: 0,
            parent_lod: LodRange {
                min: LodDistance(0),
                max: LodDistance(0),
            },
            child_lod: LodRange {
                min: LodDistance(0),
                max: LodDistance(0),
            },
            group_end: false,
        };
        let all = |f: fn(&mut InstanceFields)| {
            let mut x = zero;
            f(&mut x);
            QueryInstance::pack(&x).unwrap().to_u128()
        };
        assert_eq!(all(|x| x.filter = 7), 0b111);
        assert_eq!(all(|x| x.flags = 3), 0b11 << 3);
        assert_eq!(all(|x| x.setup = 0xfff), 0xfff << 5);
        assert_eq!(all(|x| x.object = 0x1ffff), 0x1ffff << 17);
        assert_eq!(all(|x| x.parent_bounds = 0x7fff), 0x7fff << 34);
        assert_eq!(all(|x| x.child_bounds = 0x7fff), 0x7fff << 49);
        assert_eq!(all(|x| x.matrix = 0x3fff), 0x3fff << 64);
        assert_eq!(all(|x| x.parent_lod.min = LodDistance(0xfff)), 0xfff << 78);
        assert_eq!(all(|x| x.parent_lod.max = LodDistance(0xfff)), 0xfff << 90);
        assert_eq!(all(|x| x.child_lod.min = LodDistance(0xfff)), 0xfff << 102);
        assert_eq!(all(|x| x.child_lod.max = LodDistance(0xfff)), 0xfff << 114);
        assert_eq!(all(|x| x.group_end = true), 1 << 126);
    }

    #[test]
    fn pack_rejects_overflow_naming_the_field() {
        let mut f = sample();
        f.object = 1 << 17;
        assert_eq!(
            QueryInstance::pack(&f),
            Err(Error::FieldOverflow {
                field: Field::Object,
                value: 1 << 17,
                max: (1 << 17) - 1
            })
        );
        let mut f = sample();
        f.matrix = 1 << 14;
        assert!(matches!(
            QueryInstance::pack(&f),
            Err(Error::FieldOverflow {
                field: Field::Matrix,
                ..
            })
        ));
        let mut f = sample();
        f.filter = 8;
        assert!(matches!(
            QueryInstance::pack(&f),
            Err(Error::FieldOverflow {
                field: Field::Filter,
                ..
            })
        ));
    }

    #[test]
    fn decode_rejects_spare_bit() {
        let q = QueryInstance::from_u128(1 << 127);
        assert_eq!(q.try_unpack(), Err(Error::SpareBitSet));
    }
}
