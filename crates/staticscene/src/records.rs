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
//!
//! The records live in one file each by concern (the LOD code, the packed instance, the
//! half box, the object's transforms and setup) and are re-exported here, so their paths
//! stay `staticscene::records::*`.

mod half_box;
mod instance;
mod lod;
mod object;

pub use half_box::HalfAabb;
pub use instance::{InstanceFields, QueryInstance};
pub use lod::{LodDistance, LodRange};
pub(crate) use lod::{decode_lod, lod_selects};
pub use object::{
    OBJECT_FLAG_IGNORE_GLOBAL_LOD_SCALE, QueryObject, QuerySetup, Transform4x3, WORLD_MAX,
};
pub(crate) use object::{check_aabb, floating_offset, snap};

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
