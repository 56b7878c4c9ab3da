//! The G-buffer: what one sample holds ([`Surface`]), the two layouts ([`GBufferLayout`]),
//! the texture format of every target ([`TargetFormat`]) and the pack/unpack of each layout
//! ([`Kz2Texels`], [`OctTexels`]), each the reference for its WGSL twin (`deferred::gbuffer`).
//!
//! Texels are given as the bytes the texture holds (little-endian channels, R first), so a
//! readback of a G-buffer target can be cast with `bytemuck` and compared with these.
//!
//! # Killzone 2 preset: [`GBufferLayout::Kz2`], 16 bytes per sample + depth/stencil
//!
//! | target | wgpu format | R | G | B | A |
//! | --- | --- | --- | --- | --- | --- |
//! | depth | `Depth24PlusStencil8` | depth | | | stencil |
//! | RT0 | `Rgba8Unorm` | lighting accumulation R (clamped to 1) | G | B | glow: luminance / [`KZ2_GLOW_RANGE`] |
//! | RT1 | `Rgba8Unorm` (raw bytes) | view normal `x` as f16, bits 0..8 | `x` bits 8..16 | `y` as f16, bits 0..8 | `y` bits 8..16 |
//! | RT2 | `Rgba8Unorm` | motion `x`, [`KZ2_MOTION_STEP_PX`] steps + 128 | motion `y` | specular power, log range ([`spec_power_code`]) | specular intensity |
//! | RT3 | `Rgba8Unorm` | albedo R (linear) | G | B | baked sun shadow |
//!
//! # The improved layout: [`GBufferLayout::Octahedral`], 24 bytes per sample + depth
//!
//! World-space normals in 12+12-bit octahedral code with the precise encoder
//! ([`crate::normal`]), albedo in sRGB transfer, motion vectors in f16, no lost sign, the
//! geometry pass's light (ambient with occlusion, emission) in f16 HDR instead of KZ2's
//! 8 bits and glow (8-bit ambient bands on flat shaded surfaces). Every
//! target format is one wgpu guarantees for 4x multisampling, storage binding (compute
//! writes) and render attachment at once: `Rgba8Unorm`, `Rgba8Uint`, `Rgba16Float`. Depth
//! is the `gpu` crate's reversed-Z `Depth32Float`.
//!
//! | target | wgpu format | R | G | B | A |
//! | --- | --- | --- | --- | --- | --- |
//! | depth | `Depth32Float` (reversed Z) | depth | | | |
//! | RT0 | `Rgba16Float` | lighting accumulation R (HDR, to 65504) | G | B | 0 (reserved) |
//! | RT1 | `Rgba8Uint` | normal code bits 0..8 | bits 8..16 | bits 16..24 | roughness, unorm8 |
//! | RT2 | `Rgba16Float` | motion `x` (pixels) | motion `y` (pixels) | specular intensity | metallic |
//! | RT3 | `Rgba8Unorm` | albedo R (sRGB transfer) | G | B | baked sun shadow |
//!
//! # Conventions
//!
//! - Colours are linear RGB; albedo, roughness, specular intensity, metallic and sun shadow
//!   are in `[0, 1]`; lighting accumulation is linear HDR radiance, non-negative.
//! - The metallic workflow (glTF 2.0): [`Surface::albedo`] is the base colour; lighting
//!   takes the diffuse colour `albedo · (1 − metallic)` and the specular lobe's Fresnel
//!   `mix(specular · F(0.04), F(albedo), metallic)`, with Schlick's `F(f0)`. The KZ2 preset has no
//!   free channel for metallic: it packs the diffuse colour `albedo · (1 − metallic)` as its
//!   albedo and unpacks metallic 0, so a metal keeps its dielectric lobe and loses its
//!   coloured reflection (what a 2009 G-buffer of four RGBA8 targets gives up).
//! - Roughness is perceptual roughness `r` (GGX `α = r²`); KZ2 stores it as a Blinn-Phong
//!   specular power in log range ([`spec_power_from_roughness`]).
//! - Motion is the pixel's screen-space velocity in pixels, current minus previous
//!   position, `+x` right and `+y` down.
//! - [`Surface::normal`] is a unit vector in the layout's normal space
//!   ([`GBufferLayout::normal_space`]): view space for KZ2 (right-handed, camera looking
//!   down `-z`), world space (or camera-relative world, the same directions) for the
//!   octahedral layout.
//! - Packing sanitises instead of failing: NaN becomes 0, values are clamped to their
//!   ranges, a zero or non-finite normal packs as the layout's "+Z". Unpacking accepts any
//!   bytes and returns finite values.

use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3};
use half::f16;

use crate::math::{self, round_half_even, saturate};
use crate::{normal, tables};

/// Upper end of the glow channel: luminance `KZ2_GLOW_RANGE` and above stores as 255.
pub const KZ2_GLOW_RANGE: f32 = 8.0;
/// Motion-vector quantum of KZ2's 8-bit motion channels, in pixels: codes `1..=255` hold
/// `(code - 128) * KZ2_MOTION_STEP_PX`, so motion is exact to a quarter pixel up to
/// [`KZ2_MOTION_MAX_PX`].
pub const KZ2_MOTION_STEP_PX: f32 = 0.25;
/// Largest motion KZ2's 8-bit channels hold, in pixels (longer motion is clamped).
pub const KZ2_MOTION_MAX_PX: f32 = 127.0 * KZ2_MOTION_STEP_PX;
/// Largest specular power of the log-range code: code 255 is `2^13 - 1`.
pub const KZ2_SPEC_POWER_MAX: f32 = 8191.0;
/// `log2(1 + KZ2_SPEC_POWER_MAX)`: the code is `log2(1 + power) / KZ2_SPEC_LOG_RANGE`.
pub const KZ2_SPEC_LOG_RANGE: f32 = 13.0;
/// Rec. 709 luminance weights, used for the glow channel.
pub const LUMINANCE: Vec3 = Vec3::new(0.2126, 0.7152, 0.0722);

/// A render-target format. The names are wgpu's `TextureFormat` variant names
/// ([`TargetFormat::wgpu_name`]): the `gpu` crate maps them one to one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TargetFormat {
    /// Four 8-bit unsigned-normalised channels: WGSL reads and writes `vec4<f32>`.
    Rgba8Unorm,
    /// Four 8-bit unsigned-integer channels: WGSL reads and writes `vec4<u32>`.
    Rgba8Uint,
    /// Four binary16 float channels: WGSL reads and writes `vec4<f32>`.
    Rgba16Float,
    /// 24-bit depth and 8-bit stencil (KZ2's D24S8).
    Depth24PlusStencil8,
    /// 32-bit float depth.
    Depth32Float,
}

impl TargetFormat {
    /// The wgpu `TextureFormat` variant of the same name.
    pub const fn wgpu_name(self) -> &'static str {
        match self {
            TargetFormat::Rgba8Unorm => "Rgba8Unorm",
            TargetFormat::Rgba8Uint => "Rgba8Uint",
            TargetFormat::Rgba16Float => "Rgba16Float",
            TargetFormat::Depth24PlusStencil8 => "Depth24PlusStencil8",
            TargetFormat::Depth32Float => "Depth32Float",
        }
    }

    /// Bytes per sample.
    pub const fn bytes(self) -> u32 {
        match self {
            TargetFormat::Rgba16Float => 8,
            _ => 4,
        }
    }

    /// The WGSL storage-texture format name (`texture_storage_2d<NAME, write>`), for the
    /// colour formats; `None` for depth formats (not storage formats).
    pub const fn wgsl_storage_name(self) -> Option<&'static str> {
        match self {
            TargetFormat::Rgba8Unorm => Some("rgba8unorm"),
            TargetFormat::Rgba8Uint => Some("rgba8uint"),
            TargetFormat::Rgba16Float => Some("rgba16float"),
            _ => None,
        }
    }

    /// Whether wgpu guarantees 4x multisampling for this format without optional
    /// features (wgpu-types 30 `TextureFormat::guaranteed_format_features`).
    pub const fn msaa_x4_guaranteed(self) -> bool {
        // All five are in wgpu's guaranteed MULTISAMPLE_X4 set.
        true
    }

    /// Whether wgpu guarantees storage-texture writes for this format without optional
    /// features.
    pub const fn storage_guaranteed(self) -> bool {
        self.wgsl_storage_name().is_some()
    }
}

/// The space [`Surface::normal`] is given in for a layout.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum NormalSpace {
    /// View space: right-handed, camera at the origin looking down `-z`, `+y` up.
    View,
    /// World space (or camera-relative world space: same directions).
    World,
}

/// A G-buffer layout.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum GBufferLayout {
    /// Killzone 2's four RGBA8 targets and D24S8 (see the module table).
    Kz2,
    /// The improved layout: octahedral 12+12 world-space normal, formats guaranteed for 4x
    /// MSAA (see the module table).
    Octahedral,
}

const KZ2_COLOR: [TargetFormat; 4] = [TargetFormat::Rgba8Unorm; 4];
const OCT_COLOR: [TargetFormat; 4] = [
    TargetFormat::Rgba16Float,
    TargetFormat::Rgba8Uint,
    TargetFormat::Rgba16Float,
    TargetFormat::Rgba8Unorm,
];

impl GBufferLayout {
    /// Both layouts.
    pub const ALL: [GBufferLayout; 2] = [GBufferLayout::Kz2, GBufferLayout::Octahedral];

    /// The colour targets RT0..RT3 in binding / attachment order.
    pub const fn color_formats(self) -> &'static [TargetFormat] {
        match self {
            GBufferLayout::Kz2 => &KZ2_COLOR,
            GBufferLayout::Octahedral => &OCT_COLOR,
        }
    }

    /// The depth(-stencil) target.
    pub const fn depth_format(self) -> TargetFormat {
        match self {
            GBufferLayout::Kz2 => TargetFormat::Depth24PlusStencil8,
            GBufferLayout::Octahedral => TargetFormat::Depth32Float,
        }
    }

    /// Bytes of colour targets per sample (16 for KZ2, 24 for the octahedral layout).
    pub const fn color_bytes_per_sample(self) -> u32 {
        let f = self.color_formats();
        let mut i = 0;
        let mut sum = 0;
        while i < f.len() {
            sum += f[i].bytes();
            i += 1;
        }
        sum
    }

    /// The space [`Surface::normal`] must be given in.
    pub const fn normal_space(self) -> NormalSpace {
        match self {
            GBufferLayout::Kz2 => NormalSpace::View,
            GBufferLayout::Octahedral => NormalSpace::World,
        }
    }

    /// Packs into the layout's texel bytes (colour targets concatenated, RT0 first): 16 or
    /// 24 bytes, see [`Kz2Texels`] and [`OctTexels`].
    pub fn pack_bytes(self, s: &Surface) -> ([u8; 24], usize) {
        let mut out = [0u8; 24];
        match self {
            GBufferLayout::Kz2 => {
                out[..16].copy_from_slice(bytemuck::bytes_of(&Kz2Texels::pack(s)));
                (out, 16)
            }
            GBufferLayout::Octahedral => {
                out.copy_from_slice(bytemuck::bytes_of(&OctTexels::pack(s)));
                (out, 24)
            }
        }
    }

    /// Unpacks texel bytes (as [`GBufferLayout::pack_bytes`] writes); `None` if `bytes` is
    /// not exactly [`GBufferLayout::color_bytes_per_sample`] long.
    pub fn unpack_bytes(self, bytes: &[u8]) -> Option<Surface> {
        match self {
            GBufferLayout::Kz2 => {
                let t: Kz2Texels = bytemuck::try_pod_read_unaligned(bytes).ok()?;
                Some(t.unpack())
            }
            GBufferLayout::Octahedral => {
                let t: OctTexels = bytemuck::try_pod_read_unaligned(bytes).ok()?;
                Some(t.unpack())
            }
        }
    }
}

/// What the geometry (or material-resolve) pass writes for one sample, and what lighting
/// reads back. See the module docs for units and ranges.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    /// Lighting accumulation: the pass's indirect and emissive terms, linear HDR RGB.
    pub lighting: Vec3,
    /// Diffuse albedo, linear RGB in `[0, 1]`.
    pub albedo: Vec3,
    /// Unit normal in the layout's [`NormalSpace`].
    pub normal: Vec3,
    /// Perceptual roughness in `[0, 1]` (GGX `α = roughness²`).
    pub roughness: f32,
    /// Specular intensity in `[0, 1]` (one channel: KZ2 found specular colour unused): scales
    /// a dielectric's lobe (Fresnel from 0.04).
    pub specular: f32,
    /// Metalness in `[0, 1]` (glTF's metallic): blends the diffuse colour to black and the
    /// Fresnel to the albedo's. Lost by the KZ2 preset (see the module docs).
    pub metallic: f32,
    /// Baked sun visibility in `[0, 1]` (KZ2's pre-rendered sun shadow).
    pub sun_shadow: f32,
    /// Screen-space velocity in pixels, current minus previous, `+y` down.
    pub motion: Vec2,
}

impl Default for Surface {
    fn default() -> Self {
        Surface {
            lighting: Vec3::ZERO,
            albedo: Vec3::splat(0.5),
            normal: Vec3::Z,
            roughness: 0.5,
            specular: 0.5,
            metallic: 0.0,
            sun_shadow: 1.0,
            motion: Vec2::ZERO,
        }
    }
}

// ---- channel encodings (each mirrored by a WGSL function of the same name, prefixed) ----

/// Quantises `[0, 1]` to an 8-bit code, round to nearest even; NaN → 0.
#[inline]
pub fn unorm8(x: f32) -> u8 {
    round_half_even(saturate(x) * 255.0) as u8
}

/// The sRGB 8-bit code of a linear value: `unorm8(srgb_encode(x))`, found by a binary
/// search over the 255 linear values where the code steps (no `pow`); NaN → 0.
#[inline]
pub fn srgb8(x: f32) -> u8 {
    tables::count_at_or_below(&tables::SRGB_ENCODE_THRESHOLDS, x)
}

/// The linear value of an sRGB 8-bit code, `srgb_decode(c / 255)` (a table load).
#[inline]
pub fn srgb8_value(c: u8) -> f32 {
    tables::SRGB_DECODE[c as usize]
}

/// An 8-bit code to `[0, 1]`.
#[inline]
pub fn unorm8_value(c: u8) -> f32 {
    f32::from(c) * (1.0 / 255.0)
}

/// Linear to sRGB transfer (IEC 61966-2-1), input saturated.
#[inline]
pub fn srgb_encode(x: f32) -> f32 {
    let x = saturate(x);
    if x <= 0.003_130_8 {
        x * 12.92
    } else {
        1.055 * math::powf(x, 1.0 / 2.4) - 0.055
    }
}

/// sRGB transfer to linear.
#[inline]
pub fn srgb_decode(x: f32) -> f32 {
    let x = saturate(x);
    if x <= 0.040_45 {
        x * (1.0 / 12.92)
    } else {
        math::powf((x + 0.055) * (1.0 / 1.055), 2.4)
    }
}

/// Blinn-Phong specular power equivalent to perceptual roughness `r`: `2 / α² - 2` with
/// `α = r²`, clamped to `[0, KZ2_SPEC_POWER_MAX]` (Walter et al. 2007's mapping).
#[inline]
pub fn spec_power_from_roughness(r: f32) -> f32 {
    let r = saturate(r);
    let a2 = r * r * r * r;
    if a2 <= 2.0 / (KZ2_SPEC_POWER_MAX + 2.0) {
        return KZ2_SPEC_POWER_MAX;
    }
    (2.0 / a2 - 2.0).clamp(0.0, KZ2_SPEC_POWER_MAX)
}

/// Perceptual roughness of a Blinn-Phong specular power (inverse of
/// [`spec_power_from_roughness`]): `r = (2 / (power + 2))^(1/4)`.
#[inline]
pub fn roughness_from_spec_power(power: f32) -> f32 {
    let p = if power > 0.0 {
        power.min(KZ2_SPEC_POWER_MAX)
    } else {
        0.0
    };
    math::sqrt(math::sqrt(2.0 / (p + 2.0)))
}

/// KZ2's roughness channel: the specular power in log range,
/// `unorm8(log2(1 + power) / KZ2_SPEC_LOG_RANGE)`, which keeps precision at low powers
/// (rough surfaces). The smallest roughness it holds is
/// `roughness_from_spec_power(KZ2_SPEC_POWER_MAX)` ≈ 0.125.
///
/// Found by a binary search over the 255 powers where the code steps (no `log2`).
#[inline]
pub fn spec_power_code(power: f32) -> u8 {
    // NaN and negative powers read as 0 (code 0).
    let p = if power >= 0.0 { power } else { 0.0 };
    tables::count_at_or_below(&tables::SPEC_POWER_THRESHOLDS, p.min(KZ2_SPEC_POWER_MAX))
}

/// The perceptual roughness KZ2's log-range code `code` reads back as:
/// `roughness_from_spec_power(spec_power_value(code))` (a table load).
#[inline]
pub fn spec_code_roughness(code: u8) -> f32 {
    tables::KZ2_ROUGHNESS[code as usize]
}

/// The specular power of a log-range code: `2^(code / 255 · KZ2_SPEC_LOG_RANGE) - 1`.
#[inline]
pub fn spec_power_value(code: u8) -> f32 {
    math::exp2(unorm8_value(code) * KZ2_SPEC_LOG_RANGE) - 1.0
}

/// KZ2's 8-bit motion code of one axis: `128 + round(m / KZ2_MOTION_STEP_PX)` clamped to
/// `1..=255`; NaN → 128 (no motion).
#[inline]
pub fn motion_code(m: f32) -> u8 {
    let m = if m.is_nan() { 0.0 } else { m };
    let steps = round_half_even((m * (1.0 / KZ2_MOTION_STEP_PX)).clamp(-127.0, 127.0));
    (128.0 + steps) as u8
}

/// Motion in pixels of a KZ2 motion code (code 0 reads like code 1).
#[inline]
pub fn motion_value(code: u8) -> f32 {
    (f32::from(code.max(1)) - 128.0) * KZ2_MOTION_STEP_PX
}

/// Sanitises HDR lighting: NaN and negatives → 0, `+inf` → [`f16::MAX`] (65504).
#[inline]
fn sanitize_hdr(c: Vec3) -> Vec3 {
    let f = |x: f32| if x > 0.0 { x.min(HALF_MAX) } else { 0.0 };
    Vec3::new(f(c.x), f(c.y), f(c.z))
}

/// The glow channel: luminance of the HDR lighting over [`KZ2_GLOW_RANGE`], as unorm8.
#[inline]
pub fn glow_code(lighting: Vec3) -> u8 {
    unorm8(sanitize_hdr(lighting).dot(LUMINANCE) * (1.0 / KZ2_GLOW_RANGE))
}

/// How much brighter than the stored RGB the glow channel must say a sample is before
/// [`reconstruct_hdr`] scales it: half a glow step plus half an RGB step, the most the two
/// quantisations can disagree by for a sample that was not clamped.
pub const GLOW_SLACK: f32 = 0.5 * KZ2_GLOW_RANGE / 255.0 + 0.5 / 255.0;

/// KZ2's HDR reconstruction for bloom: where a channel was clamped (reads 1) and the glow
/// channel's luminance is brighter than the RGB's by more than [`GLOW_SLACK`], the RGB is
/// scaled up to it, `rgb · glow · KZ2_GLOW_RANGE / lum(rgb)`; other values read back as
/// stored (so lighting in `[0, 1]` roundtrips to half a code).
#[inline]
pub fn reconstruct_hdr(rgb: Vec3, glow: f32) -> Vec3 {
    let lum = rgb.dot(LUMINANCE);
    let target = saturate(glow) * KZ2_GLOW_RANGE;
    if rgb.max_element() >= 1.0 && lum > 0.0 && target > lum + GLOW_SLACK {
        rgb * (target / lum)
    } else {
        rgb
    }
}

#[inline]
fn sanitize_unit(n: Vec3) -> Vec3 {
    if n.is_finite() && n.length_squared() > 0.0 {
        n
    } else {
        Vec3::Z
    }
}

/// [`f16::MAX`] as f32, folded at compile time (`to_f32_const`), for the clamps below.
const HALF_MAX: f32 = f16::MAX.to_f32_const();

/// f32 → half bits (`f16::from_f32`: round to nearest even), saturating: NaN → 0,
/// overflow clamped to ±[`f16::MAX`].
#[inline]
pub fn half_bits(x: f32) -> u16 {
    let x = if x.is_nan() {
        0.0
    } else {
        x.clamp(-HALF_MAX, HALF_MAX)
    };
    f16::from_f32(x).to_bits()
}

/// Half bits → f32 (`f16::to_f32`), finite: NaN → 0, infinities → ±[`f16::MAX`]. WGSL:
/// `deferred_half_value`.
#[inline]
pub fn half_value(bits: u16) -> f32 {
    let v = f16::from_bits(bits).to_f32();
    if v.is_nan() {
        0.0
    } else {
        v.clamp(-HALF_MAX, HALF_MAX)
    }
}

#[inline]
fn rt0(s: &Surface) -> [u8; 4] {
    let l = sanitize_hdr(s.lighting);
    [unorm8(l.x), unorm8(l.y), unorm8(l.z), glow_code(l)]
}

#[inline]
fn rt0_lighting(t: [u8; 4]) -> Vec3 {
    reconstruct_hdr(
        Vec3::new(unorm8_value(t[0]), unorm8_value(t[1]), unorm8_value(t[2])),
        unorm8_value(t[3]),
    )
}

/// One sample of the KZ2 layout: the bytes of RT0..RT3 (16 bytes, see the module table).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Pod, Zeroable)]
pub struct Kz2Texels {
    /// Lighting accumulation RGB + glow.
    pub rt0: [u8; 4],
    /// View normal `x`, `y` as two f16 (the word of [`normal::kz2_encode_view_normal`],
    /// little-endian).
    pub rt1: [u8; 4],
    /// Motion `x`, `y`, log-range specular power, specular intensity.
    pub rt2: [u8; 4],
    /// Albedo RGB (linear) + sun shadow.
    pub rt3: [u8; 4],
}
const _: () = assert!(size_of::<Kz2Texels>() == 16);

impl Kz2Texels {
    /// Packs a surface whose normal is in view space.
    pub fn pack(s: &Surface) -> Self {
        let n = normal::kz2_encode_view_normal(sanitize_unit(s.normal));
        Kz2Texels {
            rt0: rt0(s),
            rt1: n.to_le_bytes(),
            rt2: [
                motion_code(s.motion.x),
                motion_code(s.motion.y),
                spec_power_code(spec_power_from_roughness(s.roughness)),
                unorm8(s.specular),
            ],
            rt3: {
                let diffuse = s.albedo * (1.0 - saturate(s.metallic));
                [
                    unorm8(diffuse.x),
                    unorm8(diffuse.y),
                    unorm8(diffuse.z),
                    unorm8(s.sun_shadow),
                ]
            },
        }
    }

    /// Unpacks; lighting is the HDR reconstruction ([`reconstruct_hdr`]), the normal has
    /// `z >= 0` (KZ2 cannot store its sign).
    pub fn unpack(&self) -> Surface {
        let t = self;
        Surface {
            lighting: rt0_lighting(t.rt0),
            albedo: Vec3::new(
                unorm8_value(t.rt3[0]),
                unorm8_value(t.rt3[1]),
                unorm8_value(t.rt3[2]),
            ),
            normal: normal::kz2_decode_view_normal(u32::from_le_bytes(t.rt1)),
            roughness: spec_code_roughness(t.rt2[2]),
            specular: unorm8_value(t.rt2[3]),
            metallic: 0.0,
            sun_shadow: unorm8_value(t.rt3[3]),
            motion: Vec2::new(motion_value(t.rt2[0]), motion_value(t.rt2[1])),
        }
    }

    /// The four targets as `u32` words (R in bits 0..8), as a shader's `pack4x8unorm` of
    /// the target values gives them.
    pub fn words(&self) -> [u32; 4] {
        [
            u32::from_le_bytes(self.rt0),
            u32::from_le_bytes(self.rt1),
            u32::from_le_bytes(self.rt2),
            u32::from_le_bytes(self.rt3),
        ]
    }
}

/// One sample of the octahedral layout: the bytes of RT0..RT3 (24 bytes, see the module
/// table).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Pod, Zeroable)]
pub struct OctTexels {
    /// Lighting accumulation RGB (HDR) and a reserved 0, as binary16 bits (`Rgba16Float`).
    pub rt0: [u16; 4],
    /// Normal code bytes 0..3 + roughness (`Rgba8Uint`).
    pub rt1: [u8; 4],
    /// Motion `x`, `y`, specular intensity, metallic, as binary16 bits (`Rgba16Float`).
    pub rt2: [u16; 4],
    /// Albedo RGB (sRGB transfer) + sun shadow (`Rgba8Unorm`).
    pub rt3: [u8; 4],
}
const _: () = assert!(size_of::<OctTexels>() == 24);

impl OctTexels {
    /// Packs a surface whose normal is in world space, with the precise encoder.
    pub fn pack(s: &Surface) -> Self {
        let code = normal::oct_encode_precise(sanitize_unit(s.normal));
        let rt1 = (code | (u32::from(unorm8(s.roughness)) << 24)).to_le_bytes();
        OctTexels {
            rt0: {
                let l = sanitize_hdr(s.lighting);
                [half_bits(l.x), half_bits(l.y), half_bits(l.z), 0]
            },
            rt1,
            rt2: [
                half_bits(s.motion.x),
                half_bits(s.motion.y),
                half_bits(saturate(s.specular)),
                half_bits(saturate(s.metallic)),
            ],
            rt3: [
                srgb8(s.albedo.x),
                srgb8(s.albedo.y),
                srgb8(s.albedo.z),
                unorm8(s.sun_shadow),
            ],
        }
    }

    /// Unpacks.
    pub fn unpack(&self) -> Surface {
        let t = self;
        let word = u32::from_le_bytes(t.rt1);
        Surface {
            lighting: Vec3::new(
                half_value(t.rt0[0]),
                half_value(t.rt0[1]),
                half_value(t.rt0[2]),
            )
            .max(Vec3::ZERO),
            albedo: Vec3::new(
                srgb8_value(t.rt3[0]),
                srgb8_value(t.rt3[1]),
                srgb8_value(t.rt3[2]),
            ),
            normal: normal::oct_decode(word),
            roughness: unorm8_value(t.rt1[3]),
            specular: saturate(half_value(t.rt2[2])),
            metallic: saturate(half_value(t.rt2[3])),
            sun_shadow: unorm8_value(t.rt3[3]),
            motion: Vec2::new(half_value(t.rt2[0]), half_value(t.rt2[1])),
        }
    }
}
