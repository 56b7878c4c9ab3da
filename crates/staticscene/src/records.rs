//! The tile's GPU records, bit for bit as the talk lists them ("Low level data:
//! QueryInstance", "QuerySetup/QueryObject"): the 16-byte [`QueryInstance`], the 64-byte
//! [`QueryObject`], the 32-byte [`QuerySetup`], the 48-byte [`Transform4x3`] and the
//! 12-byte [`HalfAabb`], plus the 12-bit [`LodDistance`] code.
//!
//! Every record is `#[repr(C)]` + `bytemuck::Pod`, little-endian, with its size asserted.
//!
//! # QueryInstance (16 bytes, one per compute thread)
//!
//! The 128 bits are one little-endian integer; word `i` of the WGSL `array<u32, 4>` holds
//! bits `32 i .. 32 i + 31`. Fields in the talk's order, from bit 0:
//!
//! | bits | field | width | meaning |
//! | --- | --- | --- | --- |
//! | 0-2 | filter | 3 | [`FILTER_VISUAL`], [`FILTER_SUN_SHADOW`], [`FILTER_LOCAL_SHADOW`]; a view rejects the instance when `filter & view.filter == 0` |
//! | 3-4 | flags | 2 | [`INSTANCE_FLAG_NO_OCCLUSION`], [`INSTANCE_FLAG_NO_FADE`] |
//! | 5-16 | setup index | 12 | into the tile's [`QuerySetup`]s ([`MAX_SETUPS_PER_TILE`]) |
//! | 17-33 | object index | 17 | into the tile's [`QueryObject`]s ([`MAX_OBJECTS_PER_TILE`]); straddles words 0 and 1 |
//! | 34-48 | parent bounds index | 15 | into the tile's [`HalfAabb`]s ([`MAX_BOUNDS_PER_TILE`]) |
//! | 49-63 | child bounds index | 15 | same |
//! | 64-77 | matrix index | 14 | into the tile's [`Transform4x3`]s, local-to-object ([`MAX_MATRICES_PER_TILE`]) |
//! | 78-89 | parent LOD min | 12 | [`LodDistance`] code |
//! | 90-101 | parent LOD max | 12 | [`LodDistance`] code; straddles words 2 and 3 |
//! | 102-113 | child LOD min | 12 | [`LodDistance`] code |
//! | 114-125 | child LOD max | 12 | [`LodDistance`] code |
//! | 126 | group end | 1 | last instance of a run of one setup (batching); the first of the talk's two spare bits |
//! | 127 | spare | 1 | zero; a decoder rejects a word with it set |
//!
//! No arrangement of these widths keeps every field inside one 32-bit word (the 14-bit
//! matrix index only fits beside 15 + 3 bits, and the five 12-bit fields then cannot fill
//! two words), so the talk's order is kept and two fields straddle a word boundary; the
//! filter, the only field the early-out reads, sits in word 0.
//!
//! # LOD distances: 12-bit unsigned minifloat
//!
//! A [`LodDistance`] code is `e << 8 | m` (4-bit exponent, 8-bit mantissa), in metres:
//!
//! | code | metres |
//! | --- | --- |
//! | `e = 0` | `m / 64`: steps of 1/64 m below 4 m |
//! | `1 <= e <= 15` | `(1 + m / 256) * 2^(e + 1)`: relative steps of 2^-8 |
//! | `0xfff` | +infinity ("always on") |
//!
//! Decoding is exact in f32 (the code's bits are the f32's exponent and top mantissa
//! bits), so the CPU and the GPU agree bit for bit. Encoding rounds to nearest: the error
//! is at most 1/128 m below 4 m and at most 2^-9 (0.195%) of the distance above. The
//! largest finite distance is [`LOD_DISTANCE_MAX`] = 130 560 m; a larger finite value is
//! an error naming the field. Equal inputs give equal codes, so a LOD level's max and the
//! next level's min stay equal after quantisation: no gap, no overlap.

use bytemuck::{Pod, Zeroable};
use glam::{Affine3A, DVec3, IVec3, Mat3, Vec3};
use half::f16;

use crate::{Error, Field};

/// Filter bit: the instance is drawn in visual (camera) passes.
pub const FILTER_VISUAL: u8 = 1;
/// Filter bit: the instance casts sun (cascade) shadows.
pub const FILTER_SUN_SHADOW: u8 = 2;
/// Filter bit: the instance casts local-light shadows.
pub const FILTER_LOCAL_SHADOW: u8 = 4;
/// All three filter bits.
pub const FILTER_ALL: u8 = 7;

/// Instance flag: never occlusion-culled (bounds that occlusion would misjudge, such as
/// geometry displaced in the vertex shader).
pub const INSTANCE_FLAG_NO_OCCLUSION: u8 = 1;
/// Instance flag: LOD switches pop instead of fading.
pub const INSTANCE_FLAG_NO_FADE: u8 = 2;

/// Bits of the QueryInstance filter field.
pub const FILTER_BITS: u32 = 3;
/// Bits of the QueryInstance flags field.
pub const FLAGS_BITS: u32 = 2;
/// Bits of the QueryInstance setup index.
pub const SETUP_BITS: u32 = 12;
/// Bits of the QueryInstance object index.
pub const OBJECT_BITS: u32 = 17;
/// Bits of each QueryInstance bounds index.
pub const BOUNDS_BITS: u32 = 15;
/// Bits of the QueryInstance matrix index.
pub const MATRIX_BITS: u32 = 14;
/// Bits of each LOD distance code.
pub const LOD_BITS: u32 = 12;

/// First bit of the filter field.
pub const FILTER_SHIFT: u32 = 0;
/// First bit of the flags field.
pub const FLAGS_SHIFT: u32 = 3;
/// First bit of the setup index.
pub const SETUP_SHIFT: u32 = 5;
/// First bit of the object index.
pub const OBJECT_SHIFT: u32 = 17;
/// First bit of the parent bounds index.
pub const PARENT_BOUNDS_SHIFT: u32 = 34;
/// First bit of the child bounds index.
pub const CHILD_BOUNDS_SHIFT: u32 = 49;
/// First bit of the matrix index.
pub const MATRIX_SHIFT: u32 = 64;
/// First bit of the parent LOD min code.
pub const PARENT_LOD_MIN_SHIFT: u32 = 78;
/// First bit of the parent LOD max code.
pub const PARENT_LOD_MAX_SHIFT: u32 = 90;
/// First bit of the child LOD min code.
pub const CHILD_LOD_MIN_SHIFT: u32 = 102;
/// First bit of the child LOD max code.
pub const CHILD_LOD_MAX_SHIFT: u32 = 114;
/// The group-end bit (batching).
pub const GROUP_END_SHIFT: u32 = 126;
/// The spare bit, always zero.
pub const SPARE_SHIFT: u32 = 127;

/// Setups one tile can index (12 bits).
pub const MAX_SETUPS_PER_TILE: usize = 1 << SETUP_BITS;
/// Objects one tile can index (17 bits).
pub const MAX_OBJECTS_PER_TILE: usize = 1 << OBJECT_BITS;
/// LOD bounds one tile can index (15 bits).
pub const MAX_BOUNDS_PER_TILE: usize = 1 << BOUNDS_BITS;
/// Local-to-object matrices one tile can index (14 bits).
pub const MAX_MATRICES_PER_TILE: usize = 1 << MATRIX_BITS;

/// The largest finite LOD distance, in metres (code `0xffe`).
pub const LOD_DISTANCE_MAX: f32 = 130_560.0;
/// The code for +infinity.
pub const LOD_CODE_INFINITY: u16 = 0xfff;

const fn mask(bits: u32) -> u128 {
    (1u128 << bits) - 1
}

/// A 12-bit LOD distance code (see the [module docs](self) for the format).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct LodDistance(u16);

impl LodDistance {
    /// 0 m.
    pub const ZERO: LodDistance = LodDistance(0);
    /// +infinity: a range ending here never switches out.
    pub const INFINITY: LodDistance = LodDistance(LOD_CODE_INFINITY);

    /// The code for `metres`, rounded to nearest. `f32::INFINITY` gives
    /// [`INFINITY`](Self::INFINITY). Negative, NaN, or finite above
    /// [`LOD_DISTANCE_MAX`] (after rounding) is an error naming `field`.
    pub fn encode(metres: f32, field: Field) -> Result<LodDistance, Error> {
        if metres == f32::INFINITY {
            return Ok(Self::INFINITY);
        }
        let err = Error::FloatOutOfRange {
            field,
            value: f64::from(metres),
            max: f64::from(LOD_DISTANCE_MAX),
        };
        // `!(x >= 0)` also catches NaN.
        if metres.is_nan() || metres < 0.0 {
            return Err(err);
        }
        if metres < 4.0 {
            // Exact multiples of 1/64 below 4 m; 255.5 and up rounds to code 256 = 4.0 m.
            let m = crate::math::floor(metres * 64.0 + 0.5) as u16;
            return Ok(LodDistance(m));
        }
        // metres >= 4: the f32's biased exponent is >= 129. Round the 23-bit mantissa to 8
        // bits (half up); a carry rolls into the exponent, which is what we want.
        let bits = metres.to_bits().wrapping_add(1 << 14) >> 15;
        let e = (bits >> 8) as i32 - 128;
        let m = bits & 0xff;
        if !(1..=15).contains(&e) || (e == 15 && m == 0xff) {
            return Err(err);
        }
        Ok(LodDistance(((e as u16) << 8) | m as u16))
    }

    /// The code for `metres` with the generic field name ([`Field::LodDistance`]).
    pub fn from_metres(metres: f32) -> Result<LodDistance, Error> {
        Self::encode(metres, Field::LodDistance)
    }

    /// A raw 12-bit code; `None` above `0xfff`.
    #[must_use]
    pub const fn from_code(code: u16) -> Option<LodDistance> {
        if code <= LOD_CODE_INFINITY {
            Some(LodDistance(code))
        } else {
            None
        }
    }

    /// The raw 12-bit code.
    #[must_use]
    pub const fn code(self) -> u16 {
        self.0
    }

    /// The distance in metres (exact; +infinity for [`INFINITY`](Self::INFINITY)).
    #[must_use]
    #[inline]
    pub fn metres(self) -> f32 {
        decode_lod(u32::from(self.0))
    }
}

/// Decodes a 12-bit LOD code to metres: exact, and bit-identical to the WGSL twin.
#[inline]
pub(crate) fn decode_lod(code: u32) -> f32 {
    let e = code >> 8;
    let m = code & 0xff;
    // Both forms, then selects (no branch in the query's inner loop).
    let normal = f32::from_bits(((e + 128) << 23) | (m << 15));
    let sub = m as f32 * (1.0 / 64.0);
    let v = if e == 0 { sub } else { normal };
    if code == u32::from(LOD_CODE_INFINITY) {
        f32::INFINITY
    } else {
        v
    }
}

/// A LOD level's distance bracket `[min, max)` in metres, before the object's and the
/// view's LOD scales. A level is selected when the distance from the view's LOD point to
/// the level's world-space bounds lies in `[min * s, max * s)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct LodRange {
    /// Start of the bracket (inclusive).
    pub min: LodDistance,
    /// End of the bracket (exclusive).
    pub max: LodDistance,
}

impl LodRange {
    /// `[0, infinity)`: the padding level, always selected.
    pub const ALWAYS: LodRange = LodRange {
        min: LodDistance::ZERO,
        max: LodDistance::INFINITY,
    };

    /// The bracket `[min, max)` in metres, each rounded to its 12-bit code; `fields`
    /// names the two ends in errors. Fails if either end is out of range or `min > max`.
    pub fn new(min: f32, max: f32, fields: (Field, Field)) -> Result<LodRange, Error> {
        let lo = LodDistance::encode(min, fields.0)?;
        let hi = LodDistance::encode(max, fields.1)?;
        if lo > hi {
            return Err(Error::Inverted {
                field: fields.0,
                min: f64::from(min),
                max: f64::from(max),
            });
        }
        Ok(LodRange { min: lo, max: hi })
    }

    /// `[min, max)` with the generic field name.
    pub fn from_metres(min: f32, max: f32) -> Result<LodRange, Error> {
        Self::new(min, max, (Field::LodDistance, Field::LodDistance))
    }

    /// Whether this is the always-on padding bracket.
    #[must_use]
    pub fn is_always(self) -> bool {
        self == Self::ALWAYS
    }

    /// The LOD test: `min² s² <= d² < max² s²` (`d2` the squared distance, `scale2` the
    /// squared combined LOD scale), as the query evaluates it in f32.
    #[must_use]
    #[inline]
    pub fn selects(self, d2: f32, scale2: f32) -> bool {
        lod_selects(u32::from(self.min.0), u32::from(self.max.0), d2, scale2)
    }
}

/// The LOD test on raw codes (the query's inner loop).
#[inline]
pub(crate) fn lod_selects(min_code: u32, max_code: u32, d2: f32, scale2: f32) -> bool {
    let lo = decode_lod(min_code);
    let hi = decode_lod(max_code);
    d2 >= lo * lo * scale2 && d2 < hi * hi * scale2
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
/// QueryInstance, one compute thread each. Layout in the [module docs](self). WGSL:
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

/// A 4x3 affine transform, 48 bytes: three rows `[a, b, c, t]`, so that
/// `p' = (row0 · (p, 1), row1 · (p, 1), row2 · (p, 1))`. WGSL: `array<vec4<f32>, 3>`
/// (`StaticsceneTransform`), the rows of HLSL's `float3x4`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Transform4x3 {
    /// The rows: linear part in `[0..3]`, translation in `[3]`.
    pub rows: [[f32; 4]; 3],
}

const _: () = assert!(size_of::<Transform4x3>() == 48);

impl Default for Transform4x3 {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Transform4x3 {
    /// The identity.
    pub const IDENTITY: Transform4x3 = Transform4x3 {
        rows: [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
        ],
    };

    /// From a linear part and a translation.
    #[must_use]
    pub fn from_mat3_translation(m: Mat3, t: Vec3) -> Transform4x3 {
        Transform4x3 {
            rows: [
                [m.x_axis.x, m.y_axis.x, m.z_axis.x, t.x],
                [m.x_axis.y, m.y_axis.y, m.z_axis.y, t.y],
                [m.x_axis.z, m.y_axis.z, m.z_axis.z, t.z],
            ],
        }
    }

    /// From a glam affine transform.
    #[must_use]
    pub fn from_affine(a: &Affine3A) -> Transform4x3 {
        Self::from_mat3_translation(Mat3::from(a.matrix3), Vec3::from(a.translation))
    }

    /// To a glam affine transform.
    #[must_use]
    pub fn to_affine(&self) -> Affine3A {
        Affine3A::from_mat3_translation(self.linear(), self.translation())
    }

    /// The linear part.
    #[must_use]
    pub fn linear(&self) -> Mat3 {
        let r = &self.rows;
        Mat3::from_cols(
            Vec3::new(r[0][0], r[1][0], r[2][0]),
            Vec3::new(r[0][1], r[1][1], r[2][1]),
            Vec3::new(r[0][2], r[1][2], r[2][2]),
        )
    }

    /// The translation column.
    #[must_use]
    #[inline]
    pub fn translation(&self) -> Vec3 {
        Vec3::new(self.rows[0][3], self.rows[1][3], self.rows[2][3])
    }

    /// This transform with its translation replaced.
    #[must_use]
    #[inline]
    pub fn with_translation(mut self, t: Vec3) -> Transform4x3 {
        self.rows[0][3] = t.x;
        self.rows[1][3] = t.y;
        self.rows[2][3] = t.z;
        self
    }

    /// Whether all twelve entries are finite.
    #[must_use]
    pub fn is_finite(&self) -> bool {
        self.rows.iter().flatten().all(|x| x.is_finite())
    }

    /// Transforms a point.
    #[must_use]
    #[inline]
    pub fn transform_point(&self, p: Vec3) -> Vec3 {
        let r = &self.rows;
        Vec3::new(
            r[0][0] * p.x + r[0][1] * p.y + r[0][2] * p.z + r[0][3],
            r[1][0] * p.x + r[1][1] * p.y + r[1][2] * p.z + r[1][3],
            r[2][0] * p.x + r[2][1] * p.y + r[2][2] * p.z + r[2][3],
        )
    }

    /// `self ∘ rhs`: applies `rhs` first, then `self`.
    #[must_use]
    #[inline]
    pub fn mul(&self, rhs: &Transform4x3) -> Transform4x3 {
        let a = &self.rows;
        let b = &rhs.rows;
        let mut out = [[0.0f32; 4]; 3];
        for i in 0..3 {
            for j in 0..4 {
                let mut s = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
                if j == 3 {
                    s += a[i][3];
                }
                out[i][j] = s;
            }
        }
        Transform4x3 { rows: out }
    }

    /// The axis-aligned box enclosing the transformed box `[min, max]` (centre and
    /// extent through the absolute linear part, Arvo's method). Returns `(min, max)`.
    #[must_use]
    #[inline]
    pub fn transform_aabb(&self, min: Vec3, max: Vec3) -> (Vec3, Vec3) {
        let c = (min + max) * 0.5;
        let e = (max - min) * 0.5;
        let r = &self.rows;
        let tc = self.transform_point(c);
        let te = Vec3::new(
            r[0][0].abs() * e.x + r[0][1].abs() * e.y + r[0][2].abs() * e.z,
            r[1][0].abs() * e.x + r[1][1].abs() * e.y + r[1][2].abs() * e.z,
            r[2][0].abs() * e.x + r[2][1].abs() * e.y + r[2][2].abs() * e.z,
        );
        (tc - te, tc + te)
    }
}

/// Half bits to f32, the same value as `f16::from_bits(h).to_f32()` for every pattern
/// (subnormals, infinities, NaN payloads kept in the top mantissa bits; tested against
/// `half` exhaustively), branch-free: the bits shifted into f32 position and rescaled by
/// 2^112, then infinities and NaNs patched.
///
/// Kept beside `half` on purpose: the query decodes up to 13 halves per instance it tests
/// (two half boxes and the LOD scale), and `half`'s `to_f32` (a runtime F16C check and an
/// out-of-line call per value) made `query_street` / `query_aerial` (sequential) 30% / 18%
/// slower, `to_f32_const` 11% / 7% (criterion, 2 cores, 2026-11-24).
#[inline]
fn half_to_f32_branchless(h: u16) -> f32 {
    let h = u32::from(h);
    let sign = (h & 0x8000) << 16;
    let mag = h & 0x7fff;
    // 2^112 = 0x7780_0000 as f32.
    let v = f32::from_bits(mag << 13) * f32::from_bits(0x7780_0000);
    let bits = if mag >= 0x7c00 {
        0x7f80_0000 | ((mag & 0x3ff) << 13)
    } else {
        v.to_bits()
    };
    f32::from_bits(bits | sign)
}

/// The f16 at or below `v` (`v` finite).
fn f16_floor(v: f32) -> f16 {
    let h = f16::from_f32(v);
    if h.to_f32() <= v {
        return h;
    }
    f16_step_down(h)
}

/// The f16 at or above `v` (`v` finite).
fn f16_ceil(v: f32) -> f16 {
    let h = f16::from_f32(v);
    if h.to_f32() >= v {
        return h;
    }
    f16_step_up(h)
}

fn f16_step_down(h: f16) -> f16 {
    let b = h.to_bits();
    f16::from_bits(match b {
        0x0000 | 0x8000 => 0x8001,
        b if b & 0x8000 == 0 => b - 1,
        b => b + 1,
    })
}

fn f16_step_up(h: f16) -> f16 {
    let b = h.to_bits();
    f16::from_bits(match b {
        0x0000 | 0x8000 => 0x0001,
        b if b & 0x8000 == 0 => b + 1,
        b => b - 1,
    })
}

/// A half-precision axis-aligned box, 12 bytes: `min` then `max`, three f16 each. Used for
/// the LOD bounds (object space). Encoding is conservative: the half box always contains
/// the f32 box it was made from. WGSL: `array<u32, 3>` (`StaticsceneHalfAabb`), read with
/// `unpack2x16float`.
///
/// | bytes | field |
/// | --- | --- |
/// | 0-5 | min x, y, z (f16) |
/// | 6-11 | max x, y, z (f16) |
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Pod, Zeroable)]
pub struct HalfAabb {
    /// Minimum corner, f16 bits.
    pub min: [u16; 3],
    /// Maximum corner, f16 bits.
    pub max: [u16; 3],
}

const _: () = assert!(size_of::<HalfAabb>() == 12);

impl HalfAabb {
    /// The smallest half box containing `[min, max]`: min rounded down, max rounded up.
    /// Fails if a coordinate is not finite, rounds beyond ±[`f16::MAX`], or `min > max`.
    pub fn from_aabb(min: Vec3, max: Vec3) -> Result<HalfAabb, Error> {
        let mut out = HalfAabb::default();
        for i in 0..3 {
            let (lo, hi) = (min[i], max[i]);
            for v in [lo, hi] {
                if !v.is_finite() || v.abs() > f16::MAX.to_f32_const() {
                    return Err(Error::FloatOutOfRange {
                        field: Field::HalfBounds,
                        value: f64::from(v),
                        max: f16::MAX.to_f64(),
                    });
                }
            }
            if lo > hi {
                return Err(Error::Inverted {
                    field: Field::HalfBounds,
                    min: f64::from(lo),
                    max: f64::from(hi),
                });
            }
            let (l, h) = (f16_floor(lo), f16_ceil(hi));
            if !l.is_finite() || !h.is_finite() {
                return Err(Error::FloatOutOfRange {
                    field: Field::HalfBounds,
                    value: f64::from(if l.is_finite() { hi } else { lo }),
                    max: f16::MAX.to_f64(),
                });
            }
            out.min[i] = l.to_bits();
            out.max[i] = h.to_bits();
        }
        Ok(out)
    }

    /// The minimum corner.
    #[must_use]
    #[inline]
    pub fn min(&self) -> Vec3 {
        Vec3::new(
            half_to_f32_branchless(self.min[0]),
            half_to_f32_branchless(self.min[1]),
            half_to_f32_branchless(self.min[2]),
        )
    }

    /// The maximum corner.
    #[must_use]
    #[inline]
    pub fn max(&self) -> Vec3 {
        Vec3::new(
            half_to_f32_branchless(self.max[0]),
            half_to_f32_branchless(self.max[1]),
            half_to_f32_branchless(self.max[2]),
        )
    }
}

/// The object flag: ignore the view's global LOD scale (bit 16 of [`QueryObject::lod`]).
pub const OBJECT_FLAG_IGNORE_GLOBAL_LOD_SCALE: u32 = 1 << 16;

/// One placed object (the talk's DrawableObject), 64 bytes, stored once per tile.
/// WGSL: `StaticsceneQueryObject`.
///
/// | bytes | field | meaning |
/// | --- | --- | --- |
/// | 0-47 | `object_to_snapped` | object space to the object's snapped frame: rotation and scale, and the sub-metre remainder of the position |
/// | 48-59 | `snapped` | the object's position on the 1 m integer grid, `i32` x, y, z |
/// | 60-61 | `lod` bits 0-15 | LOD scale, f16 (> 0): multiplies every LOD distance of the object |
/// | 62-63 | `lod` bits 16-31 | flags: bit 16 [`OBJECT_FLAG_IGNORE_GLOBAL_LOD_SCALE`], others zero |
///
/// World position of an object-space point `p`: `snapped + object_to_snapped(p)`, so with
/// the view's snapped origin `o` the renderer's floating-space position is
/// `(snapped - o) + object_to_snapped(p)`: the integer difference is exact in f32 up to
/// 2^24 m, and the f32 remainder stays small, so precision does not depend on the
/// distance from the world origin.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct QueryObject {
    /// Object to snapped frame.
    pub object_to_snapped: Transform4x3,
    /// Snapped integer position, metres.
    pub snapped: [i32; 3],
    /// LOD scale (f16, bits 0-15) and flags (bits 16-31).
    pub lod: u32,
}

const _: () = assert!(size_of::<QueryObject>() == 64);

/// The largest |coordinate| of an object position, metres (the snapped grid is `i32`).
pub const WORLD_MAX: f64 = 2_000_000_000.0;

impl QueryObject {
    /// An object at world `position` (metres, f64) with linear part `linear` (rotation and
    /// scale, object to world). The position is snapped to the nearest integer metre and
    /// the remainder goes into the matrix. `lod_scale` (> 0, finite, at most
    /// [`f16::MAX`]) is stored as f16 rounded to nearest.
    pub fn from_world(
        position: DVec3,
        linear: Mat3,
        lod_scale: f32,
        ignore_global_lod_scale: bool,
    ) -> Result<QueryObject, Error> {
        for c in position.to_array() {
            if !c.is_finite() || c.abs() > WORLD_MAX {
                return Err(Error::FloatOutOfRange {
                    field: Field::Position,
                    value: c,
                    max: WORLD_MAX,
                });
            }
        }
        let snapped = snap(position);
        let rem = (position - snapped.as_dvec3()).as_vec3();
        let m = Transform4x3::from_mat3_translation(linear, rem);
        if !m.is_finite() {
            return Err(Error::FloatOutOfRange {
                field: Field::Transform,
                value: f64::NAN,
                max: f64::from(f32::MAX),
            });
        }
        Self::new(m, snapped, lod_scale, ignore_global_lod_scale)
    }

    /// From its parts; fails on a non-finite matrix or a LOD scale that is not a positive
    /// finite f16.
    pub fn new(
        object_to_snapped: Transform4x3,
        snapped: IVec3,
        lod_scale: f32,
        ignore_global_lod_scale: bool,
    ) -> Result<QueryObject, Error> {
        if !object_to_snapped.is_finite() {
            return Err(Error::FloatOutOfRange {
                field: Field::Transform,
                value: f64::NAN,
                max: f64::from(f32::MAX),
            });
        }
        let h = f16::from_f32(lod_scale);
        if lod_scale.is_nan() || lod_scale <= 0.0 || !h.is_finite() || h.to_f32() <= 0.0 {
            return Err(Error::FloatOutOfRange {
                field: Field::LodScale,
                value: f64::from(lod_scale),
                max: f16::MAX.to_f64(),
            });
        }
        let flags = if ignore_global_lod_scale {
            OBJECT_FLAG_IGNORE_GLOBAL_LOD_SCALE
        } else {
            0
        };
        Ok(QueryObject {
            object_to_snapped,
            snapped: snapped.to_array(),
            lod: u32::from(h.to_bits()) | flags,
        })
    }

    /// The object's LOD scale.
    #[must_use]
    #[inline]
    pub fn lod_scale(&self) -> f32 {
        half_to_f32_branchless(self.lod as u16)
    }

    /// Whether the object ignores the view's global LOD scale.
    #[must_use]
    #[inline]
    pub fn ignores_global_lod_scale(&self) -> bool {
        self.lod & OBJECT_FLAG_IGNORE_GLOBAL_LOD_SCALE != 0
    }

    /// The snapped position.
    #[must_use]
    #[inline]
    pub fn snapped(&self) -> IVec3 {
        IVec3::from_array(self.snapped)
    }

    /// Object space to the floating space of a view whose snapped origin is `origin`.
    #[must_use]
    #[inline]
    pub fn object_to_floating(&self, origin: IVec3) -> Transform4x3 {
        let d = floating_offset(self.snapped(), origin);
        let t = self.object_to_snapped.translation();
        self.object_to_snapped.with_translation(t + d)
    }
}

/// `snapped - origin` as f32 (exact for differences up to 2^24 m).
#[inline]
pub(crate) fn floating_offset(snapped: IVec3, origin: IVec3) -> Vec3 {
    Vec3::new(
        (i64::from(snapped.x) - i64::from(origin.x)) as f32,
        (i64::from(snapped.y) - i64::from(origin.y)) as f32,
        (i64::from(snapped.z) - i64::from(origin.z)) as f32,
    )
}

/// Rounds a world position to the 1 m grid (`|c| <= WORLD_MAX` assumed).
pub(crate) fn snap(p: DVec3) -> IVec3 {
    IVec3::new(
        crate::math::round64(p.x) as i32,
        crate::math::round64(p.y) as i32,
        crate::math::round64(p.z) as i32,
    )
}

/// One DrawableSetup as the query sees it, 32 bytes, stored once per tile.
/// WGSL: `StaticsceneQuerySetup`.
///
/// | bytes | field | meaning |
/// | --- | --- | --- |
/// | 0-11 | `bounds_min` | accurate vertex bounds of the geometry, minimum, in the setup's local (mesh) space, f32 |
/// | 12-23 | `bounds_max` | maximum |
/// | 24-31 | `handle` | the renderer's handle for the DrawableSetup (the talk's CPU pointer), opaque; WGSL `vec2<u32>` (low, high) |
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct QuerySetup {
    /// Local bounds minimum.
    pub bounds_min: [f32; 3],
    /// Local bounds maximum.
    pub bounds_max: [f32; 3],
    /// Renderer handle.
    pub handle: u64,
}

const _: () = assert!(size_of::<QuerySetup>() == 32);

impl QuerySetup {
    /// A setup with local bounds `[min, max]`; fails if they are not finite or inverted.
    pub fn new(min: Vec3, max: Vec3, handle: u64) -> Result<QuerySetup, Error> {
        check_aabb(min, max, Field::Bounds)?;
        Ok(QuerySetup {
            bounds_min: min.to_array(),
            bounds_max: max.to_array(),
            handle,
        })
    }

    /// Local bounds minimum.
    #[must_use]
    #[inline]
    pub fn min(&self) -> Vec3 {
        Vec3::from_array(self.bounds_min)
    }

    /// Local bounds maximum.
    #[must_use]
    #[inline]
    pub fn max(&self) -> Vec3 {
        Vec3::from_array(self.bounds_max)
    }
}

/// Checks a float box: finite and not inverted.
pub(crate) fn check_aabb(min: Vec3, max: Vec3, field: Field) -> Result<(), Error> {
    for v in min.to_array().into_iter().chain(max.to_array()) {
        if !v.is_finite() {
            return Err(Error::FloatOutOfRange {
                field,
                value: f64::from(v),
                max: f64::from(f32::MAX),
            });
        }
    }
    for i in 0..3 {
        if min[i] > max[i] {
            return Err(Error::Inverted {
                field,
                min: f64::from(min[i]),
                max: f64::from(max[i]),
            });
        }
    }
    Ok(())
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

    #[test]
    fn lod_code_vectors() {
        let m = |d: f32| LodDistance::from_metres(d).unwrap().code();
        assert_eq!(m(0.0), 0);
        assert_eq!(m(1.0 / 64.0), 1);
        assert_eq!(m(3.984375), 255);
        assert_eq!(m(4.0), 0x100);
        assert_eq!(m(8.0), 0x200);
        assert_eq!(m(5.0), 0x140); // 5 = 4 * (1 + 64/256)
        assert_eq!(m(LOD_DISTANCE_MAX), 0xffe);
        assert_eq!(m(f32::INFINITY), 0xfff);
        assert_eq!(LodDistance(0x140).metres(), 5.0);
        assert_eq!(LodDistance(0xffe).metres(), LOD_DISTANCE_MAX);
        assert_eq!(LodDistance(0xfff).metres(), f32::INFINITY);
        assert_eq!(LodDistance(0x0ff).metres(), 255.0 / 64.0);
        assert!(LodDistance::from_metres(-1.0).is_err());
        assert!(LodDistance::from_metres(f32::NAN).is_err());
        assert!(LodDistance::from_metres(131_000.0).is_err());
        assert_eq!(
            LodDistance::encode(-0.5, Field::ChildLodMax),
            Err(Error::FloatOutOfRange {
                field: Field::ChildLodMax,
                value: -0.5,
                max: 130560.0
            })
        );
    }

    #[test]
    fn lod_codes_monotonic_and_decode_exact() {
        let mut prev = -1.0f32;
        for c in 0..0xfffu16 {
            let v = LodDistance(c).metres();
            assert!(v > prev, "code {c:#x}");
            // Decoding against the definition in f64.
            let e = u32::from(c >> 8);
            let mm = f64::from(c & 0xff);
            let want = if e == 0 {
                mm / 64.0
            } else {
                (1.0 + mm / 256.0) * 2f64.powi(e as i32 + 1)
            };
            assert_eq!(f64::from(v), want, "code {c:#x}");
            assert_eq!(LodDistance::from_metres(v).unwrap().code(), c);
            prev = v;
        }
    }

    #[test]
    fn lod_error_bound() {
        // Dense sweep: error at most half a step (1/128 m below 4 m, 2^-9 relative above).
        let mut d = 0.0f32;
        while d < 130_000.0 {
            let q = LodDistance::from_metres(d).unwrap().metres();
            let err = (f64::from(q) - f64::from(d)).abs();
            let bound = if d < 4.0 {
                1.0 / 128.0
            } else {
                f64::from(d) / 512.0
            };
            assert!(err <= bound + 1e-12, "d {d} q {q}");
            d = d * 1.0007 + 0.0013;
        }
    }

    #[test]
    fn branchless_half_decode_matches_half_for_every_pattern() {
        for h in 0..=u16::MAX {
            let want = f16::from_bits(h).to_f32();
            let got = half_to_f32_branchless(h);
            if want.is_nan() {
                assert!(got.is_nan(), "{h:#x}");
                assert_eq!(got.to_bits() & 0x8000_0000, want.to_bits() & 0x8000_0000);
            } else {
                assert_eq!(got.to_bits(), want.to_bits(), "{h:#x}");
            }
        }
    }

    #[test]
    fn half_aabb_is_conservative() {
        let min = Vec3::new(0.1, -3.3333, 1000.7);
        let max = Vec3::new(0.2, -1.0001, 2049.3);
        let h = HalfAabb::from_aabb(min, max).unwrap();
        assert!(h.min().cmple(min).all() && h.max().cmpge(max).all());
        assert_eq!(h.min().x, f16::from_bits(h.min[0]).to_f32());
        // Exact values stay exact.
        let h = HalfAabb::from_aabb(Vec3::splat(-2.0), Vec3::splat(0.5)).unwrap();
        assert_eq!((h.min(), h.max()), (Vec3::splat(-2.0), Vec3::splat(0.5)));
        // Zero rounds to itself; a tiny positive max rounds up past zero.
        let h = HalfAabb::from_aabb(Vec3::ZERO, Vec3::splat(1e-9)).unwrap();
        assert!(h.max().x > 0.0 && h.min().x == 0.0);
        assert!(HalfAabb::from_aabb(Vec3::ZERO, Vec3::splat(70_000.0)).is_err());
        assert!(HalfAabb::from_aabb(Vec3::ONE, Vec3::ZERO).is_err());
        assert!(HalfAabb::from_aabb(Vec3::NAN, Vec3::ZERO).is_err());
        // 65504 is representable; just above rounds up to infinity and is refused.
        assert!(HalfAabb::from_aabb(Vec3::ZERO, Vec3::splat(65504.0)).is_ok());
        assert!(HalfAabb::from_aabb(Vec3::ZERO, Vec3::splat(65504.5)).is_err());
    }

    #[test]
    fn object_floating_origin() {
        let p = DVec3::new(1_000_000.3, -5.75, 999_999.49);
        let o = QueryObject::from_world(p, Mat3::IDENTITY, 1.5, true).unwrap();
        assert_eq!(o.snapped, [1_000_000, -6, 999_999]);
        assert!(o.ignores_global_lod_scale());
        assert_eq!(o.lod_scale(), 1.5);
        let f = o.object_to_floating(IVec3::new(1_000_010, 0, 1_000_000));
        let t = f.translation();
        assert!((f64::from(t.x) - (-9.7)).abs() < 1e-6);
        assert!((f64::from(t.y) - (-5.75)).abs() < 1e-6);
        assert!((f64::from(t.z) - (-0.51)).abs() < 1e-6);
        assert!(QueryObject::from_world(p, Mat3::IDENTITY, 0.0, false).is_err());
        assert!(QueryObject::from_world(DVec3::splat(3e9), Mat3::IDENTITY, 1.0, false).is_err());
    }

    #[test]
    fn transform_composition_matches_glam() {
        let a = Affine3A::from_scale_rotation_translation(
            Vec3::new(1.0, 2.0, 0.5),
            glam::Quat::from_rotation_y(0.7),
            Vec3::new(3.0, -1.0, 2.0),
        );
        let b = Affine3A::from_rotation_translation(
            glam::Quat::from_rotation_x(-0.3),
            Vec3::new(0.5, 0.25, -4.0),
        );
        let m = Transform4x3::from_affine(&a).mul(&Transform4x3::from_affine(&b));
        let p = Vec3::new(0.3, -0.7, 1.9);
        let want = (a * b).transform_point3(p);
        assert!((m.transform_point(p) - want).abs().max_element() < 1e-5);
        let back = Transform4x3::from_affine(&m.to_affine());
        assert_eq!(back, m);
    }
}
