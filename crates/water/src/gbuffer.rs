//! The mini G-buffer's data word.
//!
//! Far Cry 5's position pass renders every water body into a lower-resolution, wider-FOV
//! "mini G-buffer": a data texture, the mesh normal and depth. The data texture holds "the
//! shader ID, which is an 8-bit" value, the shader features ("is it front face, does it
//! support lighting or not, and is it a valid pixel"), "the material structure buffer
//! index" and "the MIP level of the algae and the foam, because ... we don't have access to
//! DDX, DDY" in the later compute passes (seed 003). This module packs them into one `u32`
//! (an `R32Uint` texel), the only place that layout is defined; `water_pack_data` /
//! `water_unpack_data` in [`wgsl::GBUFFER`](crate::wgsl::GBUFFER) are tied to these constants
//! by unit tests.
//!
//! # Bit layout
//!
//! | bits | field | range |
//! | --- | --- | --- |
//! | 0..=7 | shader ID | 0..=255 |
//! | 8 | valid: the pixel has water ([`DataFlags::VALID`]) | |
//! | 9 | front face ([`DataFlags::FRONT_FACE`]) | |
//! | 10 | lit: the shader takes lighting ([`DataFlags::LIT`]) | |
//! | 11..=15 | foam mip level, unsigned 4.1 fixed point | 0.0..=15.5 in steps of 0.5 |
//! | 16..=20 | algae mip level, unsigned 4.1 fixed point | 0.0..=15.5 in steps of 0.5 |
//! | 21..=31 | material index into the material structure buffer | 0..[`MAX_MATERIALS`] (2048) |
//!
//! A word without [`DataFlags::VALID`] is "no water" whatever its other bits: the talk does
//! not clear these textures, every pass tests the valid bit. [`DATA_NONE`] (0) is the word
//! to clear to where a clear is wanted.

use glam::Vec2;

use crate::Error;
use crate::math;

/// Bits of the shader ID.
pub const SHADER_ID_BITS: u32 = 8;
/// Shift of the flag bits.
pub const FLAGS_SHIFT: u32 = 8;
/// Bits of the flags.
pub const FLAGS_BITS: u32 = 3;
/// Shift of the foam mip level.
pub const FOAM_MIP_SHIFT: u32 = 11;
/// Shift of the algae mip level.
pub const ALGAE_MIP_SHIFT: u32 = 16;
/// Bits of each mip level (4 integer bits, 1 fraction bit).
pub const MIP_BITS: u32 = 5;
/// Fixed-point steps per mip level.
pub const MIP_STEPS_PER_LEVEL: u32 = 2;
/// Largest mip level a word holds.
pub const MAX_MIP_LEVEL: f32 = 15.5;
/// Shift of the material index.
pub const MATERIAL_SHIFT: u32 = 21;
/// Bits of the material index.
pub const MATERIAL_BITS: u32 = 11;
/// Materials a data word can index (the material structure buffer's capacity).
pub const MAX_MATERIALS: u32 = 1 << MATERIAL_BITS;
/// The cleared word: no water.
pub const DATA_NONE: u32 = 0;

const _: () = assert!(SHADER_ID_BITS == FLAGS_SHIFT);
const _: () = assert!(FLAGS_SHIFT + FLAGS_BITS == FOAM_MIP_SHIFT);
const _: () = assert!(FOAM_MIP_SHIFT + MIP_BITS == ALGAE_MIP_SHIFT);
const _: () = assert!(ALGAE_MIP_SHIFT + MIP_BITS == MATERIAL_SHIFT);
const _: () = assert!(MATERIAL_SHIFT + MATERIAL_BITS == 32);
const _: () = assert!(((1 << MIP_BITS) - 1) as f32 / MIP_STEPS_PER_LEVEL as f32 == MAX_MIP_LEVEL);

/// The three shader-feature flags.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct DataFlags(pub u8);

impl DataFlags {
    /// The pixel has water.
    pub const VALID: DataFlags = DataFlags(1);
    /// The water surface faces the camera (not seen from below).
    pub const FRONT_FACE: DataFlags = DataFlags(2);
    /// The shader takes lighting.
    pub const LIT: DataFlags = DataFlags(4);
    /// All three.
    pub const ALL: DataFlags = DataFlags(7);

    /// Whether every flag of `other` is set.
    #[must_use]
    pub const fn contains(self, other: DataFlags) -> bool {
        self.0 & other.0 == other.0
    }
}

impl core::ops::BitOr for DataFlags {
    type Output = DataFlags;
    fn bitor(self, rhs: DataFlags) -> DataFlags {
        DataFlags(self.0 | rhs.0)
    }
}

/// The fields of a data word, unpacked.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct DataFields {
    /// Shader ID (selects the shader features the later passes run).
    pub shader_id: u8,
    /// Valid, front face, lit.
    pub flags: DataFlags,
    /// Index into the material structure buffer, `< MAX_MATERIALS`.
    pub material: u16,
    /// Foam texture mip level (rounded to the nearest half level, clamped to
    /// `[0, MAX_MIP_LEVEL]` when packed).
    pub foam_mip: f32,
    /// Algae texture mip level (same quantisation).
    pub algae_mip: f32,
}

/// A packed data word (see the module docs for the layout).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
#[repr(transparent)]
pub struct DataWord(pub u32);

/// Quantises a mip level to 4.1 fixed point: nearest half level, clamped; NaN gives 0.
#[inline]
#[must_use]
pub fn quantize_mip(level: f32) -> u32 {
    let q = level * MIP_STEPS_PER_LEVEL as f32 + 0.5;
    let max = ((1 << MIP_BITS) - 1) as f32;
    if !(q > 0.0) {
        return 0; // negative or NaN
    }
    (if q < max { q } else { max }) as u32
}

impl DataWord {
    /// Packs the fields. Fails if the material index does not fit or the flag byte has bits
    /// beyond the three flags; mip levels are quantised (never an error).
    pub fn pack(f: DataFields) -> Result<DataWord, Error> {
        if u32::from(f.material) >= MAX_MATERIALS {
            return Err(Error::FieldTooWide {
                field: "material index",
                value: u32::from(f.material),
                bits: MATERIAL_BITS,
            });
        }
        if u32::from(f.flags.0) >> FLAGS_BITS != 0 {
            return Err(Error::FieldTooWide {
                field: "data flags",
                value: u32::from(f.flags.0),
                bits: FLAGS_BITS,
            });
        }
        Ok(DataWord(
            u32::from(f.shader_id)
                | u32::from(f.flags.0) << FLAGS_SHIFT
                | quantize_mip(f.foam_mip) << FOAM_MIP_SHIFT
                | quantize_mip(f.algae_mip) << ALGAE_MIP_SHIFT
                | u32::from(f.material) << MATERIAL_SHIFT,
        ))
    }

    /// Every field (any word decodes).
    #[must_use]
    pub fn unpack(self) -> DataFields {
        let w = self.0;
        let mip = |shift: u32| ((w >> shift) & ((1 << MIP_BITS) - 1)) as f32 * 0.5;
        DataFields {
            shader_id: (w & 0xff) as u8,
            flags: DataFlags(((w >> FLAGS_SHIFT) & 7) as u8),
            material: (w >> MATERIAL_SHIFT) as u16,
            foam_mip: mip(FOAM_MIP_SHIFT),
            algae_mip: mip(ALGAE_MIP_SHIFT),
        }
    }

    /// Whether the pixel has water.
    #[inline]
    #[must_use]
    pub const fn is_valid(self) -> bool {
        self.0 & (1 << FLAGS_SHIFT) != 0
    }

    /// The material index.
    #[inline]
    #[must_use]
    pub const fn material(self) -> u32 {
        self.0 >> MATERIAL_SHIFT
    }
}

/// The mip level the position pass stores for a texture of `texture_size` texels sampled
/// with UV derivatives `duv_dx`, `duv_dy` (UV per pixel): `log2` of the larger footprint in
/// texels, clamped at 0 (the isotropic rule GPUs use). Non-finite input gives 0.
#[must_use]
pub fn mip_level(duv_dx: Vec2, duv_dy: Vec2, texture_size: Vec2) -> f32 {
    let a = (duv_dx * texture_size).length_squared();
    let b = (duv_dy * texture_size).length_squared();
    let m = if a > b { a } else { b };
    if !(m > 1.0) || !m.is_finite() {
        return 0.0;
    }
    0.5 * math::log2(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_vectors() {
        let f = DataFields {
            shader_id: 0xab,
            flags: DataFlags::VALID | DataFlags::LIT,
            material: 1234,
            foam_mip: 3.5,
            algae_mip: 15.5,
        };
        let w = DataWord::pack(f).unwrap();
        assert_eq!(w.0, 0xab | 5 << 8 | 7 << 11 | 31 << 16 | 1234 << 21);
        assert_eq!(w.unpack(), f);
        assert!(w.is_valid());
        assert_eq!(w.material(), 1234);
        assert!(!DataWord(DATA_NONE).is_valid());
    }

    #[test]
    fn rejects_wide_fields_and_quantises_mips() {
        let f = DataFields {
            material: 2048,
            ..Default::default()
        };
        assert!(DataWord::pack(f).is_err());
        let f = DataFields {
            flags: DataFlags(8),
            ..Default::default()
        };
        assert!(DataWord::pack(f).is_err());
        assert_eq!(quantize_mip(f32::NAN), 0);
        assert_eq!(quantize_mip(-3.0), 0);
        assert_eq!(quantize_mip(100.0), 31);
        assert_eq!(quantize_mip(2.74), 5);
        assert_eq!(quantize_mip(2.76), 6);
    }

    #[test]
    fn mip_level_is_log2_of_footprint() {
        let s = Vec2::splat(256.0);
        assert_eq!(mip_level(Vec2::new(4.0 / 256.0, 0.0), Vec2::ZERO, s), 2.0);
        assert_eq!(mip_level(Vec2::ZERO, Vec2::ZERO, s), 0.0);
        assert_eq!(mip_level(Vec2::NAN, Vec2::ZERO, s), 0.0);
    }
}
