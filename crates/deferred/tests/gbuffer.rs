//! G-buffer layouts: fixed vectors worked out by hand from the bit tables, roundtrip
//! bounds for every channel (proptest), and decode of arbitrary bytes.

mod common;

use deferred::gbuffer::*;
use deferred::normal::*;
use deferred::{GBufferLayout, Kz2Texels, OctTexels, Surface, TargetFormat};
use glam::{DVec3, Vec2, Vec3};
use proptest::prelude::*;

fn surface() -> Surface {
    Surface {
        lighting: Vec3::new(2.0, 0.5, 0.0),
        albedo: Vec3::new(1.0, 0.5, 0.0),
        normal: Vec3::new(0.6, 0.8, 0.0),
        roughness: 0.5,
        specular: 0.5,
        metallic: 0.0,
        sun_shadow: 1.0,
        motion: Vec2::new(1.5, -0.25),
    }
}

/// KZ2 has no metallic channel: it stores the diffuse colour, base · (1 − metallic), and
/// reads metallic back as 0, so lighting sees the same diffuse term.
#[test]
fn kz2_stores_a_metal_as_its_diffuse_colour() {
    let s = Surface {
        albedo: Vec3::new(0.8, 0.4, 0.2),
        metallic: 0.75,
        ..Surface::default()
    };
    let b = Kz2Texels::pack(&s).unpack();
    assert_eq!(b.metallic, 0.0);
    let want = Vec3::new(0.2, 0.1, 0.05);
    assert!(
        (b.albedo - want).abs().max_element() <= 0.5 / 255.0 + 1e-6,
        "{}",
        b.albedo
    );
    // The octahedral layout keeps both.
    let o = OctTexels::pack(&s).unpack();
    assert!((o.metallic - 0.75).abs() < 1e-3 && (o.albedo - s.albedo).abs().max_element() < 5e-3);
}

#[test]
fn kz2_fixed_vector() {
    let t = Kz2Texels::pack(&surface());
    // Lighting clamps to (255, 128, 0); glow = lum(2, .5, 0) / 8 = 0.7828 / 8 -> 24.95 -> 25.
    assert_eq!(t.rt0, [255, 128, 0, 25]);
    // f16(0.6) = 0x38cd, f16(0.8) = 0x3a66, little-endian bytes of the word.
    assert_eq!(t.rt1, [0xcd, 0x38, 0x66, 0x3a]);
    // Motion 1.5 px = 6 quarter steps -> 134, -0.25 -> 127; roughness 0.5 -> power
    // 2 / 0.0625 - 2 = 30 -> log2(31) / 13 * 255 = 97.2 -> 97; specular 127.5 -> 128 (even).
    assert_eq!(t.rt2, [134, 127, 97, 128]);
    assert_eq!(t.rt3, [255, 128, 0, 255]);
    assert_eq!(t.words()[1], 0x3a66_38cd, "RT1 as the Cg pack_2half word");
}

#[test]
fn oct_fixed_vector() {
    let mut s = surface();
    s.normal = Vec3::X;
    let t = OctTexels::pack(&s);
    // f16 bits of the lighting (2, 0.5, 0) and the reserved zero: HDR, no glow.
    assert_eq!(t.rt0, [0x4000, 0x3800, 0, 0]);
    // +X projects to (1, 0): codes (4094, 2047) -> 0x7ff_ffe; roughness 0.5 -> 128.
    assert_eq!(t.rt1, [0xfe, 0xff, 0x7f, 128]);
    // f16 bits of 1.5, -0.25, 0.5 and metallic 0.
    assert_eq!(t.rt2, [0x3e00, 0xb400, 0x3800, 0]);
    // sRGB(0.5) = 0.735357 -> 187.52 -> 188.
    assert_eq!(t.rt3, [255, 188, 0, 255]);
    // +Z is the centre code, -Z the folded corner.
    assert_eq!(oct_encode_precise(Vec3::Z), 2047 | (2047 << 12));
    assert_eq!(oct_encode_precise(-Vec3::Z), 4094 | (4094 << 12));
    assert_eq!(oct_decode(4094 | (4094 << 12)), -Vec3::Z);
    assert_eq!(oct_decode(2047 << 12), -Vec3::X);
}

#[test]
fn layouts_describe_their_targets() {
    use TargetFormat::*;
    assert_eq!(GBufferLayout::Kz2.color_formats(), [Rgba8Unorm; 4]);
    assert_eq!(GBufferLayout::Kz2.depth_format(), Depth24PlusStencil8);
    assert_eq!(GBufferLayout::Kz2.color_bytes_per_sample(), 16);
    assert_eq!(
        GBufferLayout::Octahedral.color_formats(),
        [Rgba16Float, Rgba8Uint, Rgba16Float, Rgba8Unorm]
    );
    assert_eq!(GBufferLayout::Octahedral.color_bytes_per_sample(), 24);
    for layout in GBufferLayout::ALL {
        for f in layout.color_formats() {
            assert!(f.msaa_x4_guaranteed() && f.storage_guaranteed(), "{f:?}");
        }
    }
    // KZ2's memory figure: 4xRGBA8 + D24S8 at 1280x720 is 18.4 MB.
    let bytes = 1280 * 720 * (GBufferLayout::Kz2.color_bytes_per_sample() + 4);
    assert_eq!(bytes, 18_432_000);
}

#[test]
fn pack_bytes_matches_the_texel_structs() {
    let s = surface();
    let (b, n) = GBufferLayout::Kz2.pack_bytes(&s);
    assert_eq!(&b[..n], bytemuck::bytes_of(&Kz2Texels::pack(&s)));
    assert_eq!(
        GBufferLayout::Kz2.unpack_bytes(&b[..n]),
        Some(Kz2Texels::pack(&s).unpack())
    );
    let (b, n) = GBufferLayout::Octahedral.pack_bytes(&s);
    assert_eq!(n, 24);
    assert_eq!(
        GBufferLayout::Octahedral.unpack_bytes(&b[..n]),
        Some(OctTexels::pack(&s).unpack())
    );
    assert_eq!(GBufferLayout::Octahedral.unpack_bytes(&b[..23]), None);
}

#[test]
fn lighting_in_range_reads_back_exactly_and_clamped_lighting_reconstructs() {
    let mut s = surface();
    s.lighting = Vec3::new(0.02, 0.01, 0.0);
    let back = Kz2Texels::pack(&s).unpack().lighting;
    assert!((back - s.lighting).abs().max_element() <= 0.5 / 255.0 + 1e-7);
    // A bright light: luminance 4 stored in glow; reconstruction within one glow step.
    s.lighting = Vec3::splat(4.0);
    let back = Kz2Texels::pack(&s).unpack().lighting;
    assert!((back.dot(LUMINANCE) - 4.0).abs() <= 0.5 * KZ2_GLOW_RANGE / 255.0 + 1e-5);
}

/// The table-driven quantisers give the formula's code everywhere except within a hair of
/// a rounding boundary (where f32 `pow`/`log2` themselves are off by an ulp).
#[test]
fn table_quantisers_match_their_formulas() {
    let mut off = 0;
    for i in 0..=200_000 {
        let x = i as f32 / 200_000.0;
        let exact = srgb_encode(x) * 255.0;
        if srgb8(x) != unorm8(srgb_encode(x)) {
            assert!((exact - exact.floor() - 0.5).abs() < 1e-3, "{x}: {exact}");
            off += 1;
        }
        let v = srgb8_value(srgb8(x));
        assert!((v - srgb_decode(unorm8_value(srgb8(x)))).abs() <= 1e-6 * v.max(1e-3));
        // KZ2 specular power over its whole range.
        let p = (i as f32 / 200_000.0 * 13.0).exp2() - 1.0;
        let code = (1.0 + p).log2() / KZ2_SPEC_LOG_RANGE * 255.0;
        if spec_power_code(p) != unorm8((1.0 + p).log2() / KZ2_SPEC_LOG_RANGE) {
            assert!((code - code.floor() - 0.5).abs() < 1e-3, "{p}: {code}");
            off += 1;
        }
    }
    assert!(off < 20, "{off} boundary cases");
    for c in 0..=255u8 {
        let r = spec_code_roughness(c);
        assert!((r - roughness_from_spec_power(spec_power_value(c))).abs() < 1e-6);
    }
    assert_eq!(srgb8(f32::NAN), 0);
    assert_eq!(srgb8(2.0), 255);
    assert_eq!(spec_power_code(f32::NAN), 0);
}

#[test]
fn kz2_flips_negative_z() {
    let n = Vec3::new(0.3, -0.4, -0.866_025_4).normalize();
    let back = kz2_decode_view_normal(kz2_encode_view_normal(n));
    let mirrored = Vec3::new(n.x, n.y, -n.z);
    assert!(back.angle_between(mirrored).to_degrees() < 0.05);
    assert!(back.angle_between(n).to_degrees() > 100.0);
}

#[test]
fn bad_input_packs_sanely() {
    let s = common::bad_surface();
    for layout in GBufferLayout::ALL {
        let (b, n) = layout.pack_bytes(&s);
        let u = layout.unpack_bytes(&b[..n]).unwrap();
        assert_eq!(u.normal, Vec3::Z, "{layout:?}");
        assert_eq!(u.albedo.x, 0.0);
        assert!((u.albedo.y - 1.0).abs() < 1e-6);
        assert_eq!(u.motion.x, 0.0);
        assert_eq!(u.sun_shadow, 0.0);
    }
}

/// Angle between an f64 reference direction and a decoded one, degrees (f64 math).
fn angle(a: DVec3, b: Vec3) -> f64 {
    let b = b.as_dvec3().normalize();
    a.cross(b).length().atan2(a.dot(b)).to_degrees()
}

fn direction() -> impl Strategy<Value = DVec3> {
    (-1.0f64..=1.0, 0.0f64..std::f64::consts::TAU).prop_map(|(z, phi)| {
        let r = (1.0 - z * z).max(0.0).sqrt();
        DVec3::new(r * phi.cos(), r * phi.sin(), z)
    })
}

fn finite_surface(s: &Surface) -> bool {
    s.lighting.is_finite()
        && s.albedo.is_finite()
        && s.normal.is_finite()
        && (s.normal.length() - 1.0).abs() < 1e-5
        && s.roughness.is_finite()
        && s.specular.is_finite()
        && s.sun_shadow.is_finite()
        && s.motion.is_finite()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// The precise encoder's bound: the circumradius of a code cell over the sphere,
    /// √2 / 2047 rad = 0.0396 degrees (measured max 0.0395); the nearest-code encoder's is
    /// the cell's half long diagonal, √(3/2) · √3 / 2047 rad = 0.0594 degrees.
    #[test]
    fn octahedral_roundtrip_error_bound(d in direction()) {
        let n = d.as_vec3();
        prop_assert!(angle(d, oct_decode(oct_encode_precise(n))) <= 0.0397);
        prop_assert!(angle(d, oct_decode(oct_encode_fast(n))) <= 0.0595);
        // Any length encodes the direction within the same bound.
        prop_assert!(angle(d, oct_decode(oct_encode_precise(n * 7.5))) <= 0.0397);
        prop_assert!(angle(d, oct_decode(oct_encode_precise(n * 1e-3))) <= 0.0397);
    }

    /// A decoded code re-encodes to a code decoding to the same direction.
    #[test]
    fn octahedral_codes_are_fixed_points(u in 0u32..=4095, v in 0u32..=4095) {
        let d = oct_decode(u | (v << 12));
        let again = oct_decode(oct_encode_precise(d));
        prop_assert!(angle(d.as_dvec3(), again) < 1e-3, "{u} {v}");
    }

    /// KZ2: f16 x and y, z reconstructed. x and y are off by at most half an f16 ulp,
    /// 2^-12, so z² is off by at most ε = 2 · √2 · 2^-12, and z by at most min(√ε, ε / z):
    /// 1.5 degrees at grazing angles (measured 1.47), falling as 1 / z.
    #[test]
    fn kz2_normal_error_bound(d in direction()) {
        let d = DVec3::new(d.x, d.y, d.z.abs());
        let e = angle(d, kz2_decode_view_normal(kz2_encode_view_normal(d.as_vec3())));
        let eps = 2.0 * 2f64.sqrt() * 2f64.powi(-12);
        let bound = eps.sqrt().min(eps / d.z).to_degrees() + 0.03;
        prop_assert!(e <= 1.48, "{e}");
        prop_assert!(e <= bound, "{e} at z {}", d.z);
    }

    #[test]
    fn kz2_roundtrip_bounds(
        albedo in prop::array::uniform3(0.0f32..=1.0),
        lighting in prop::array::uniform3(0.0f32..=1.0),
        r in 0.0f32..=1.0,
        spec in 0.0f32..=1.0,
        sun in 0.0f32..=1.0,
        mx in -40.0f32..40.0,
        my in -40.0f32..40.0,
        d in direction(),
    ) {
        let n = DVec3::new(d.x, d.y, d.z.abs()).as_vec3();
        let s = Surface { lighting: lighting.into(), albedo: albedo.into(), normal: n,
            roughness: r, specular: spec, metallic: 0.0, sun_shadow: sun, motion: Vec2::new(mx, my) };
        let b = Kz2Texels::pack(&s).unpack();
        let q = 0.5 / 255.0 + 1e-6;
        prop_assert!((b.albedo - s.albedo).abs().max_element() <= q);
        prop_assert!((b.lighting - s.lighting).abs().max_element() <= q);
        prop_assert!((b.specular - spec).abs() <= q && (b.sun_shadow - sun).abs() <= q);
        // Motion: exact to an eighth of a pixel within ±31.75 px, clamped beyond.
        let m = s.motion.clamp(Vec2::splat(-KZ2_MOTION_MAX_PX), Vec2::splat(KZ2_MOTION_MAX_PX));
        prop_assert!((b.motion - m).abs().max_element() <= KZ2_MOTION_STEP_PX / 2.0 + 1e-6);
        // Roughness: half a log step, 13 / 255 / 2 in log2(1 + power), is at most
        // ln 2 · 0.0255 / 4 = 0.0044 in roughness; below the smallest storable (0.125) it
        // reads back as that.
        let rmin = roughness_from_spec_power(KZ2_SPEC_POWER_MAX);
        prop_assert!((b.roughness - r.max(rmin)).abs() <= 0.0045, "{} vs {r}", b.roughness);
        prop_assert!(finite_surface(&b));
    }

    #[test]
    fn oct_roundtrip_bounds(
        albedo in prop::array::uniform3(0.0f32..=1.0),
        r in 0.0f32..=1.0,
        spec in 0.0f32..=1.0,
        metal in 0.0f32..=1.0,
        lighting in prop::array::uniform3(0.0f32..=60000.0),
        mx in -1000.0f32..1000.0,
        my in -1000.0f32..1000.0,
        d in direction(),
    ) {
        let s = Surface { albedo: albedo.into(), normal: d.as_vec3(), roughness: r,
            specular: spec, metallic: metal, motion: Vec2::new(mx, my),
            lighting: lighting.into(), ..Surface::default() };
        let b = OctTexels::pack(&s).unpack();
        prop_assert!(angle(d, b.normal) <= 0.0397);
        // sRGB: half a code times the decode's steepest slope (2.4 / 1.055 at 1).
        prop_assert!((b.albedo - s.albedo).abs().max_element() <= 0.5 / 255.0 * 2.275);
        prop_assert!((b.roughness - r).abs() <= 0.5 / 255.0 + 1e-6);
        // f16: relative half-ulp 2^-11.
        prop_assert!((b.specular - spec).abs() <= 2f32.powi(-12));
        prop_assert!((b.metallic - metal).abs() <= 2f32.powi(-12));
        // HDR lighting in f16: relative half-ulp (and the smallest normal's where tiny).
        let l = s.lighting;
        prop_assert!((b.lighting - l).abs().max_element() <= l.max_element() * 2f32.powi(-11) + 2f32.powi(-25));
        prop_assert!((b.motion - s.motion).abs().max_element() <= s.motion.abs().max_element() * 2f32.powi(-11));
    }

    /// Arbitrary bytes decode to finite values in range, for both layouts.
    #[test]
    fn any_bytes_decode(bytes in prop::array::uniform24(any::<u8>())) {
        for layout in GBufferLayout::ALL {
            let n = layout.color_bytes_per_sample() as usize;
            let s = layout.unpack_bytes(&bytes[..n]).unwrap();
            prop_assert!(finite_surface(&s), "{layout:?} {s:?}");
            prop_assert!(s.albedo.min_element() >= 0.0 && s.albedo.max_element() <= 1.0);
            prop_assert!((0.0..=1.0).contains(&s.roughness) && (0.0..=1.0).contains(&s.specular));
            prop_assert!(s.lighting.min_element() >= 0.0);
        }
    }
}
