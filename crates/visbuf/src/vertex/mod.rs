//! The 32-byte transformed vertex that HFW's vertex compute passes write into the ring
//! buffer and the pixel (material resolve) passes read back, three per pixel.
//!
//! # Layout ([`VisbufVertex`], eight little-endian 32-bit words)
//!
//! | word | bits   | standard layout                  | interpolant layout          | format |
//! |------|--------|----------------------------------|-----------------------------|--------|
//! | 0    | 15..0  | HPOS x (clip space)              | same                        | f16 |
//! | 0    | 31..16 | HPOS y                           | same                        | f16 |
//! | 1    | 31..0  | HPOS w                           | same                        | f32 |
//! | 2    | 15..0  | UV u                             | slot 0                      | u16 fixed, `u * 8192` |
//! | 2    | 31..16 | UV v                             | slot 1                      | u16 fixed, `v * 8192` |
//! | 3    | 31..0  | vertex colour, R in 7..0 ... A in 31..24 | slots 2 (15..0), 3 (31..16) | RGBA8 unorm |
//! | 4    | 31..0  | normal x 9..0, y 19..10, z 29..20, 31..30 unused (0) | same | snorm 10:10:10:2 |
//! | 5    | 31..0  | tangent xyz as the normal, handedness (+1 / -1) in 31..30 | same | snorm 10:10:10:2 |
//! | 6    | 15..0  | previous-frame HPOS x            | same                        | f16 |
//! | 6    | 31..16 | previous-frame HPOS y            | same                        | f16 |
//! | 7    | 15..0  | previous-frame HPOS w            | same                        | f16 |
//! | 7    | 31..16 | spare (extra interpolant, [`Slot`]) | slot 4                   | 16 bits |
//!
//! HPOS z is not stored: for a perspective projection it is an affine function of w,
//! recovered by [`ZFromW`]. In the interpolant layout (the talk: "UV and vertex colour
//! kicked out of the fixed format", their data read from the mesh instead) words 2 and 3
//! and the spare half of word 7 hold five 16-bit [`Slot`]s, each a half float or a
//! two-channel square-rooted unorm8 colour ("poor man's sRGB").
//!
//! # Worst-case errors (each tested exhaustively or by proptest)
//!
//! | field | range accepted by `pack` | worst-case error of unpack(pack(x)) |
//! |---|---|---|
//! | HPOS x, y; previous x, y, w (f16) | `abs(x) <= 65504` | relative `2^-11` (4.9e-4) for `abs(x) >= 2^-14`, absolute `2^-25` below |
//! | HPOS w (f32) | finite | exact |
//! | UV (16:16 / 8) | `[0, 8)` (to `65535.5 / 8192`), per component | absolute `2^-14` (6.1e-5); step `2^-13` |
//! | colour (RGBA8) | any finite, clamped to `[0, 1]` | absolute `0.5 / 255` (2.0e-3) |
//! | normal, tangent xyz (snorm10) | any finite, clamped to `[-1, 1]` | absolute `0.5 / 511` (9.8e-4) per component; 0.1 degree for unit vectors |
//! | tangent handedness (snorm2) | `w >= 0` gives +1, `w < 0` gives -1 | exact for +1 / -1 |
//! | slot as half | `abs(x) <= 65504` | as f16 above |
//! | slot as sqrt unorm8 x2 | any finite, clamped to `[0, 1]` | absolute `sqrt(c) / 255 + 1 / (4 * 255^2)`: 3.9e-3 at 1, 3.8e-6 at 0 |
//!
//! The f16 HPOS bounds the resolve's accuracy: x/w moves by up to `2^-11` relative, so at
//! the edge of a 3840-pixel-wide viewport a vertex lands up to 0.47 px from where f32 would
//! put it. HFW accepts this for foliage; keep w in f32 as the talk found necessary.
//!
//! Out-of-range or non-finite inputs make [`VisbufVertex::pack`] return an error naming the
//! field; the unorm and snorm fields clamp as GPU conversions do. Every bit pattern
//! unpacks without panicking (NaN and infinity come back as stored).

// The scalar field codecs live in `codec.rs`, re-exported here so their paths stay
// `visbuf::vertex::*`; this file keeps the vertex records and their packing.
mod codec;

use codec::{finite, half_field};
pub use codec::{
    pack_snorm_10_10_10_2, pack_sqrt_unorm8x2, pack_unorm8x4, pack_uv_16_16, pack_uv_component,
    try_pack_half2, unpack_half2, unpack_snorm_10_10_10_2, unpack_sqrt_unorm8x2, unpack_unorm8x4,
    unpack_uv_16_16,
};

use glam::{Mat4, Vec2, Vec3, Vec4};
use half::f16;

use crate::Error;

/// UV fixed-point scale: a code is `uv * UV_SCALE` (16 bits over `[0, 8)`, i.e. unorm16 of
/// `uv / 8`).
pub const UV_SCALE: f32 = 8192.0;
/// Exclusive upper end of the UV range: values below it round to a code.
pub const UV_MAX: f32 = 65535.5 / UV_SCALE;
/// Slots available in the interpolant layout.
pub const SLOT_COUNT: usize = 5;

/// Bit position of the handedness / w field in a 10:10:10:2 word.
pub const SNORM_10_10_10_2_W_SHIFT: u32 = 30;

/// One ring-buffer vertex, 32 bytes; see the [module docs](self) for the layout. WGSL:
/// `struct VisbufVertex` with the same eight fields.
#[derive(Clone, Copy, Debug, PartialEq, Default, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
pub struct VisbufVertex {
    /// Word 0: clip-space x (bits 15..0) and y (bits 31..16) as f16.
    pub hpos_xy: u32,
    /// Word 1: clip-space w as f32.
    pub hpos_w: f32,
    /// Word 2: UV as two 16-bit fixed-point codes (u low), or slots 0 and 1.
    pub uv: u32,
    /// Word 3: RGBA8 unorm colour (R low), or slots 2 and 3.
    pub color: u32,
    /// Word 4: normal, snorm 10:10:10:2 (w bits 0).
    pub normal: u32,
    /// Word 5: tangent, snorm 10:10:10:2 with handedness in the 2-bit w.
    pub tangent: u32,
    /// Word 6: previous-frame clip-space x (low) and y (high) as f16.
    pub prev_hpos_xy: u32,
    /// Word 7: previous-frame clip-space w as f16 (low) and the spare 16 bits / slot 4
    /// (high).
    pub prev_hpos_w_extra: u32,
}

const _: () = assert!(size_of::<VisbufVertex>() == 32);

/// The fields every layout has.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct VertexCore {
    /// Clip-space position `(x, y, w)`; z is recovered from w ([`ZFromW`]).
    pub hpos: Vec3,
    /// Normal, components in `[-1, 1]` (not renormalised on unpack).
    pub normal: Vec3,
    /// Tangent xyz, and handedness in w (+1 or -1; the bitangent is
    /// `w * cross(normal, tangent)`).
    pub tangent: Vec4,
    /// Previous frame's clip-space position `(x, y, w)`, for motion vectors.
    pub prev_hpos: Vec3,
}

/// The standard layout, unpacked.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Vertex {
    /// Position, normal, tangent, previous position.
    pub core: VertexCore,
    /// Texture coordinates in `[0, 8)` (texture-space units; wrap happens in the sampler).
    pub uv: Vec2,
    /// Linear RGBA colour in `[0, 1]`.
    pub color: Vec4,
    /// The spare 16 bits, stored as given (slot 4 of the interpolant layout).
    pub extra: u16,
}

/// What one 16-bit interpolant slot holds. The shader knows which kind each slot is; the
/// vertex does not record it.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum Slot {
    /// Unused: stored as 0.
    #[default]
    Empty,
    /// A half float.
    Half(f32),
    /// Two colour channels in `[0, 1]`, each stored as `round(sqrt(c) * 255)`.
    SqrtUnorm8x2(Vec2),
    /// Bits as given.
    Raw(u16),
}

/// Depth recovery: clip-space `z = a * w + b`, which holds for any projection whose z and w
/// rows depend only on view-space z (every perspective projection glam builds, reversed or
/// infinite included).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ZFromW {
    /// Slope.
    pub a: f32,
    /// Offset.
    pub b: f32,
}

impl ZFromW {
    /// From a projection matrix (column-major, clip = `proj * view_pos`): with
    /// `z_c = m22 z + m32` and `w_c = m23 z + m33`, `z_c = (m22 / m23) w_c + m32 - m22 m33 / m23`.
    /// Errors when w does not depend on view z (orthographic) or the rows also depend on
    /// view x or y, or any term is not finite.
    #[inline]
    pub fn from_projection(proj: Mat4) -> Result<ZFromW, Error> {
        let (m22, m32) = (proj.z_axis.z, proj.w_axis.z);
        let (m23, m33) = (proj.z_axis.w, proj.w_axis.w);
        let depends_on_xy = proj.x_axis.z != 0.0
            || proj.y_axis.z != 0.0
            || proj.x_axis.w != 0.0
            || proj.y_axis.w != 0.0;
        if m23 == 0.0 || depends_on_xy {
            return Err(Error::DepthNotRecoverableFromW);
        }
        let z = ZFromW {
            a: m22 / m23,
            b: m32 - m22 * m33 / m23,
        };
        if !(z.a.is_finite() && z.b.is_finite()) {
            return Err(Error::DepthNotRecoverableFromW);
        }
        Ok(z)
    }

    /// Clip-space z for clip-space w.
    #[must_use]
    #[inline]
    pub fn z(self, w: f32) -> f32 {
        self.a * w + self.b
    }

    /// The full clip-space position from `(x, y, w)`.
    #[must_use]
    #[inline]
    pub fn clip(self, hpos: Vec3) -> Vec4 {
        Vec4::new(hpos.x, hpos.y, self.z(hpos.z), hpos.z)
    }
}

impl Slot {
    /// The slot's 16 bits; errors for a half outside the half range or not finite.
    #[inline]
    pub fn to_bits(self) -> Result<u16, Error> {
        match self {
            Slot::Empty => Ok(0),
            Slot::Half(x) => Ok(half_field("slot (half)", x)? as u16),
            Slot::SqrtUnorm8x2(c) => {
                finite("slot (sqrt unorm8) x", c.x)?;
                finite("slot (sqrt unorm8) y", c.y)?;
                Ok(pack_sqrt_unorm8x2(c))
            }
            Slot::Raw(b) => Ok(b),
        }
    }
}

#[inline]
fn pack_core(c: &VertexCore) -> Result<[u32; 6], Error> {
    let hx = half_field("hpos.x", c.hpos.x)?;
    let hy = half_field("hpos.y", c.hpos.y)?;
    let w = finite("hpos.w", c.hpos.z)?;
    for (name, x) in [
        ("normal.x", c.normal.x),
        ("normal.y", c.normal.y),
        ("normal.z", c.normal.z),
        ("tangent.x", c.tangent.x),
        ("tangent.y", c.tangent.y),
        ("tangent.z", c.tangent.z),
        ("tangent.w", c.tangent.w),
    ] {
        finite(name, x)?;
    }
    let px = half_field("prev_hpos.x", c.prev_hpos.x)?;
    let py = half_field("prev_hpos.y", c.prev_hpos.y)?;
    let pw = half_field("prev_hpos.w", c.prev_hpos.z)?;
    let handed = if c.tangent.w < 0.0 { -1.0 } else { 1.0 };
    Ok([
        hx | (hy << 16),
        w.to_bits(),
        pack_snorm_10_10_10_2(c.normal.extend(0.0)),
        pack_snorm_10_10_10_2(c.tangent.truncate().extend(handed)),
        px | (py << 16),
        pw,
    ])
}

impl VisbufVertex {
    /// Packs the standard layout. Errors name the field: a non-finite input, an HPOS or
    /// previous-HPOS component beyond the half range, a UV outside `[0, 8)`.
    #[inline]
    pub fn pack(v: &Vertex) -> Result<VisbufVertex, Error> {
        let [hpos_xy, hpos_w, normal, tangent, prev_hpos_xy, prev_w] = pack_core(&v.core)?;
        for (name, x) in [
            ("color.r", v.color.x),
            ("color.g", v.color.y),
            ("color.b", v.color.z),
            ("color.a", v.color.w),
        ] {
            finite(name, x)?;
        }
        Ok(VisbufVertex {
            hpos_xy,
            hpos_w: f32::from_bits(hpos_w),
            uv: pack_uv_16_16(v.uv)?,
            color: pack_unorm8x4(v.color),
            normal,
            tangent,
            prev_hpos_xy,
            prev_hpos_w_extra: prev_w | (u32::from(v.extra) << 16),
        })
    }

    /// Packs the interpolant layout: the core fields plus five 16-bit slots (slots 0-3
    /// replace UV and colour, slot 4 is the spare half of word 7).
    #[inline]
    pub fn pack_with_slots(
        core: &VertexCore,
        slots: [Slot; SLOT_COUNT],
    ) -> Result<VisbufVertex, Error> {
        let [hpos_xy, hpos_w, normal, tangent, prev_hpos_xy, prev_w] = pack_core(core)?;
        let mut b = [0u32; SLOT_COUNT];
        for (dst, s) in b.iter_mut().zip(slots) {
            *dst = u32::from(s.to_bits()?);
        }
        Ok(VisbufVertex {
            hpos_xy,
            hpos_w: f32::from_bits(hpos_w),
            uv: b[0] | (b[1] << 16),
            color: b[2] | (b[3] << 16),
            normal,
            tangent,
            prev_hpos_xy,
            prev_hpos_w_extra: prev_w | (b[4] << 16),
        })
    }

    /// The fields every layout has.
    #[must_use]
    #[inline]
    pub fn core(&self) -> VertexCore {
        let xy = unpack_half2(self.hpos_xy);
        let prev = unpack_half2(self.prev_hpos_xy);
        VertexCore {
            hpos: Vec3::new(xy.x, xy.y, self.hpos_w),
            normal: unpack_snorm_10_10_10_2(self.normal).truncate(),
            tangent: unpack_snorm_10_10_10_2(self.tangent),
            prev_hpos: Vec3::new(
                prev.x,
                prev.y,
                f16::from_bits(self.prev_hpos_w_extra as u16).to_f32(),
            ),
        }
    }

    /// The standard layout, unpacked. Never panics, for any bits.
    #[must_use]
    #[inline]
    pub fn unpack(&self) -> Vertex {
        Vertex {
            core: self.core(),
            uv: unpack_uv_16_16(self.uv),
            color: unpack_unorm8x4(self.color),
            extra: (self.prev_hpos_w_extra >> 16) as u16,
        }
    }

    /// The raw 16 bits of slot `i` (0..5) of the interpolant layout; `None` past slot 4.
    #[must_use]
    #[inline]
    pub fn slot_bits(&self, i: usize) -> Option<u16> {
        Some(match i {
            0 => self.uv as u16,
            1 => (self.uv >> 16) as u16,
            2 => self.color as u16,
            3 => (self.color >> 16) as u16,
            4 => (self.prev_hpos_w_extra >> 16) as u16,
            _ => return None,
        })
    }

    /// Slot `i` read as a half float.
    #[must_use]
    #[inline]
    pub fn slot_half(&self, i: usize) -> Option<f32> {
        self.slot_bits(i).map(|b| f16::from_bits(b).to_f32())
    }

    /// Slot `i` read as two square-rooted unorm8 channels.
    #[must_use]
    #[inline]
    pub fn slot_sqrt_unorm8x2(&self, i: usize) -> Option<Vec2> {
        self.slot_bits(i).map(unpack_sqrt_unorm8x2)
    }

    /// The eight words, in memory order.
    #[must_use]
    #[inline]
    pub fn to_words(self) -> [u32; 8] {
        bytemuck::cast(self)
    }

    /// From eight words.
    #[must_use]
    #[inline]
    pub fn from_words(words: [u32; 8]) -> VisbufVertex {
        bytemuck::cast(words)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn sample_vertex() -> Vertex {
        Vertex {
            core: VertexCore {
                hpos: Vec3::new(-1.25, 3.5, 7.125),
                normal: Vec3::new(0.0, 0.6, -0.8),
                tangent: Vec4::new(1.0, 0.0, 0.0, -1.0),
                prev_hpos: Vec3::new(-1.0, 3.0, 7.0),
            },
            uv: Vec2::new(0.5, 7.25),
            color: Vec4::new(1.0, 0.0, 0.2, 0.6),
            extra: 0xbeef,
        }
    }

    #[test]
    fn fixed_vector_standard_layout() {
        let p = VisbufVertex::pack(&sample_vertex()).unwrap();
        assert_eq!(p.hpos_xy, 0x4300_bd00); // 3.5 = 0x4300, -1.25 = 0xbd00
        assert_eq!(p.hpos_w, 7.125);
        assert_eq!(p.uv, (59392 << 16) | 4096); // 7.25 * 8192, 0.5 * 8192
        assert_eq!(p.color, 0x99_33_00_ff);
        // normal (0, 0.6, -0.8): x 0, y round(306.6) = 307, z round(-408.8) = -409.
        assert_eq!(p.normal, (((-409i32 as u32) & 0x3ff) << 20) | (307 << 10));
        // tangent (1, 0, 0, -1): x 511, w -1 = 0b11.
        assert_eq!(p.tangent, 511 | (3 << 30));
        assert_eq!(p.prev_hpos_xy, 0x4200_bc00);
        assert_eq!(p.prev_hpos_w_extra, 0xbeef_4700);
        let bytes: [u8; 32] = bytemuck::cast(p);
        assert_eq!(&bytes[0..4], &[0x00, 0xbd, 0x00, 0x43]);
    }

    #[test]
    fn interpolant_slots_fill_uv_colour_and_the_spare() {
        let core = sample_vertex().core;
        let slots = [
            Slot::Half(1.5),
            Slot::SqrtUnorm8x2(Vec2::new(0.25, 1.0)),
            Slot::Raw(0x1234),
            Slot::Empty,
            Slot::Half(-2.0),
        ];
        let p = VisbufVertex::pack_with_slots(&core, slots).unwrap();
        assert_eq!(
            p.core(),
            VisbufVertex::pack(&sample_vertex()).unwrap().core()
        );
        assert_eq!(p.slot_half(0), Some(1.5));
        assert_eq!(
            p.slot_sqrt_unorm8x2(1),
            Some(Vec2::new(0.25 * 1.0, 1.0).map(|c| {
                let s = (c.sqrt() * 255.0 + 0.5).floor() / 255.0;
                s * s
            }))
        );
        assert_eq!(p.slot_bits(2), Some(0x1234));
        assert_eq!(p.slot_bits(3), Some(0));
        assert_eq!(p.slot_half(4), Some(-2.0));
        assert_eq!(p.slot_bits(5), None);
        assert!(matches!(
            VisbufVertex::pack_with_slots(
                &core,
                [
                    Slot::Half(1e6),
                    Slot::Empty,
                    Slot::Empty,
                    Slot::Empty,
                    Slot::Empty
                ]
            ),
            Err(Error::ValueOutOfRange {
                field: "slot (half)",
                ..
            })
        ));
    }

    #[test]
    fn pack_errors_name_the_field() {
        let mut v = sample_vertex();
        v.core.hpos.x = 70000.0;
        assert!(matches!(
            VisbufVertex::pack(&v),
            Err(Error::ValueOutOfRange {
                field: "hpos.x",
                ..
            })
        ));
        let mut v = sample_vertex();
        v.core.hpos.z = f32::INFINITY;
        assert_eq!(
            VisbufVertex::pack(&v),
            Err(Error::NonFinite { field: "hpos.w" })
        );
        let mut v = sample_vertex();
        v.core.normal.y = f32::NAN;
        assert_eq!(
            VisbufVertex::pack(&v),
            Err(Error::NonFinite { field: "normal.y" })
        );
        let mut v = sample_vertex();
        v.core.prev_hpos.z = -1e5;
        assert!(matches!(
            VisbufVertex::pack(&v),
            Err(Error::ValueOutOfRange {
                field: "prev_hpos.w",
                ..
            })
        ));
    }

    #[test]
    fn z_from_w_recovers_depth_for_glam_projections() {
        let projs = [
            Mat4::perspective_rh(1.0, 1.5, 0.1, 100.0),
            Mat4::perspective_lh(0.7, 1.0, 0.5, 5000.0),
            Mat4::perspective_infinite_reverse_rh(1.2, 16.0 / 9.0, 0.05),
            Mat4::perspective_rh_gl(1.0, 1.0, 1.0, 10.0),
        ];
        for proj in projs {
            let z = ZFromW::from_projection(proj).unwrap();
            for d in [0.5f32, 1.0, 7.0, 60.0] {
                let view = Vec4::new(0.3, -0.2, if proj.z_axis.w < 0.0 { -d } else { d }, 1.0);
                let clip = proj * view;
                let got = z.z(clip.w);
                assert!(
                    (got - clip.z).abs() <= 1e-5 * clip.z.abs().max(1.0),
                    "{got} vs {}",
                    clip.z
                );
                assert_eq!(z.clip(Vec3::new(clip.x, clip.y, clip.w)).w, clip.w);
            }
        }
        assert_eq!(
            ZFromW::from_projection(Mat4::orthographic_rh(-1.0, 1.0, -1.0, 1.0, 0.1, 10.0)),
            Err(Error::DepthNotRecoverableFromW)
        );
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]

        #[test]
        fn standard_roundtrip_within_bounds(
            hx in -60000f32..60000.0, hy in -60000f32..60000.0, hw in -1e6f32..1e6,
            u in 0f32..7.9999, v in 0f32..7.9999,
            c in proptest::array::uniform4(0f32..=1.0),
            n in proptest::array::uniform3(-1f32..=1.0),
            t in proptest::array::uniform4(-1f32..=1.0),
            p in proptest::array::uniform3(-60000f32..60000.0),
            extra: u16,
        ) {
            let vert = Vertex {
                core: VertexCore {
                    hpos: Vec3::new(hx, hy, hw),
                    normal: Vec3::from(n),
                    tangent: Vec4::from(t),
                    prev_hpos: Vec3::from(p),
                },
                uv: Vec2::new(u, v),
                color: Vec4::from(c),
                extra,
            };
            let packed = VisbufVertex::pack(&vert).unwrap();
            // Words are stable: packing the unpacked vertex gives the same bits.
            let back = packed.unpack();
            prop_assert_eq!(VisbufVertex::pack(&back).unwrap(), packed);
            let half_ok = |got: f32, x: f32| {
                let b = if x.abs() >= 2f32.powi(-14) { x.abs() * 2f32.powi(-11) } else { 2f32.powi(-25) };
                (got - x).abs() <= b
            };
            prop_assert!(half_ok(back.core.hpos.x, hx) && half_ok(back.core.hpos.y, hy));
            prop_assert_eq!(back.core.hpos.z, hw);
            for k in 0..3 {
                prop_assert!(half_ok(back.core.prev_hpos[k], p[k]));
                prop_assert!((back.core.normal[k] - n[k]).abs() <= 0.5 / 511.0 + 1e-6);
                prop_assert!((back.core.tangent[k] - t[k]).abs() <= 0.5 / 511.0 + 1e-6);
            }
            prop_assert_eq!(back.core.tangent.w, if t[3] < 0.0 { -1.0 } else { 1.0 });
            prop_assert!((back.uv - Vec2::new(u, v)).abs().max_element() <= 2f32.powi(-14));
            prop_assert!((back.color - Vec4::from(c)).abs().max_element() <= 0.5 / 255.0 + 1e-6);
            prop_assert_eq!(back.extra, extra);
        }

        #[test]
        fn any_32_bytes_unpack_without_panicking(words: [u32; 8]) {
            let v = VisbufVertex::from_words(words);
            let u = v.unpack();
            prop_assert!(u.core.normal.abs().max_element() <= 1.0);
            prop_assert!(u.uv.max_element() < 8.0 && u.uv.min_element() >= 0.0);
            prop_assert_eq!(v.to_words(), words);
        }
    }
}
