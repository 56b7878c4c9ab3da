//! Fuzz bodies for the `deferred` crate: G-buffer decode of arbitrary texel bytes (both
//! layouts), with the decoded surface re-packed and decoded again to the same values, and
//! the normal codecs on arbitrary floats. Nothing here may panic except a check.

use deferred::gbuffer::{GLOW_SLACK, LUMINANCE};
use deferred::glam::Vec3;
use deferred::normal::{
    kz2_decode_view_normal, kz2_encode_view_normal, oct_decode, oct_encode_fast, oct_encode_precise,
};
use deferred::{GBufferLayout, Surface};

use crate::Input;

/// Angle between two directions in degrees, in f64 with atan2 (f32 `acos` of a dot product
/// is off by up to 0.02 degrees at these small angles).
fn angle_deg(a: Vec3, b: Vec3) -> f64 {
    let (a, b) = (a.as_dvec3().normalize(), b.as_dvec3().normalize());
    a.cross(b).length().atan2(a.dot(b)).to_degrees()
}

fn check_surface(s: &Surface) {
    assert!(
        s.lighting.is_finite() && s.lighting.min_element() >= 0.0,
        "{s:?}"
    );
    assert!(
        s.albedo.min_element() >= 0.0 && s.albedo.max_element() <= 1.0,
        "{s:?}"
    );
    assert!((s.normal.length() - 1.0).abs() < 1e-5, "{s:?}");
    for v in [s.roughness, s.specular, s.sun_shadow] {
        assert!((0.0..=1.0).contains(&v), "{s:?}");
    }
    assert!(s.motion.is_finite(), "{s:?}");
}

/// G-buffer decode: any 24 bytes unpack in both layouts to finite in-range surfaces; the
/// decoded surface packs and unpacks again to the same values (within one quantisation
/// step where the layout re-rounds: the glow channel, and KZ2's f16 normal).
pub fn deferred_gbuffer_decode(data: &[u8]) {
    let mut input = Input::new(data);
    let bytes: [u8; 24] = input.bytes();
    for layout in GBufferLayout::ALL {
        let n = layout.color_bytes_per_sample() as usize;
        let s = layout.unpack_bytes(&bytes[..n]).expect("exact length");
        check_surface(&s);
        let (again, m) = layout.pack_bytes(&s);
        assert_eq!(m, n);
        let t = layout.unpack_bytes(&again[..m]).expect("exact length");
        check_surface(&t);
        assert!(
            (t.albedo - s.albedo).abs().max_element() < 1e-6,
            "{layout:?} {s:?} {t:?}"
        );
        assert!(
            (t.roughness - s.roughness).abs() < 1e-3,
            "{layout:?} {s:?} {t:?}"
        );
        assert_eq!(t.motion, s.motion, "{layout:?}");
        assert!((t.specular - s.specular).abs() < 1e-6 && t.sun_shadow == s.sun_shadow);
        let normal_bound = match layout {
            GBufferLayout::Kz2 => 1.5,
            GBufferLayout::Octahedral => 0.001,
        };
        assert!(
            angle_deg(t.normal, s.normal) <= normal_bound,
            "{layout:?} {s:?} {t:?}"
        );
        // Lighting: values below 1 read back as stored; reconstructed HDR keeps its
        // luminance (the glow channel) to within the reconstruction's slack, though not
        // its hue (KZ2's glow holds luminance only).
        if s.lighting.max_element() < 1.0 {
            assert!(
                (t.lighting - s.lighting).abs().max_element() < 1e-6,
                "{layout:?} {s:?} {t:?}"
            );
        } else {
            let (a, b) = (s.lighting.dot(LUMINANCE), t.lighting.dot(LUMINANCE));
            assert!(
                (a - b).abs() <= GLOW_SLACK + 1e-4 * a,
                "{layout:?} {s:?} {t:?}"
            );
        }
    }
}

/// Normal codecs on arbitrary floats (NaN, infinities, zero, subnormals): encoders never
/// panic, decoders give unit vectors, codes stay in 24 bits.
pub fn deferred_normal_codecs(data: &[u8]) {
    let mut input = Input::new(data);
    while input.remaining() > 0 {
        let n = Vec3::new(input.f32(), input.f32(), input.f32());
        let a = oct_encode_precise(n);
        let b = oct_encode_fast(n);
        assert!(a < 1 << 24 && b < 1 << 24);
        let (da, db) = (oct_decode(a), oct_decode(b));
        assert!((da.length() - 1.0).abs() < 1e-5 && (db.length() - 1.0).abs() < 1e-5);
        if n.is_finite() && n.length_squared() > 1e-30 && n.length_squared().is_finite() {
            // The precise encoder's bound, √2 / 2047 rad.
            assert!(angle_deg(da, n) < 0.0397, "{n} -> {da}");
        }
        let k = kz2_decode_view_normal(kz2_encode_view_normal(n));
        assert!((k.length() - 1.0).abs() < 1e-5 && k.z >= 0.0);
        let w = input.u32();
        assert!((oct_decode(w).length() - 1.0).abs() < 1e-5);
        assert!((kz2_decode_view_normal(w).length() - 1.0).abs() < 1e-5);
    }
}
