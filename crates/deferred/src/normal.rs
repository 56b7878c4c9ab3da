//! Normal encodings for the G-buffer: the octahedral 12+12-bit code of the improved layout
//! and Killzone 2's view-space X and Y as two f16 values with Z reconstructed.
//!
//! # Octahedral 12+12 (world space)
//!
//! The unit sphere is projected onto the octahedron `|x| + |y| + |z| = 1`, the lower half
//! folded over the upper half's diagonals, and the resulting square `[-1, 1]²` quantised to
//! 12 bits per axis (Meyer et al. 2010, "On floating-point normal vectors"; the survey and
//! the "precise" encoder are Cigolle et al., JCGT 2014, "A survey of efficient
//! representations for independent unit vectors"). The quantisation is snorm-like so that
//! the axes are exact: code `c` in `0..=4094` decodes to `(c - 2047) / 2047`.
//!
//! | bits | 23..12 | 11..0 |
//! | --- | --- | --- |
//! | field | `v` code (square y) | `u` code (square x) |
//!
//! [`oct_encode_precise`] tries the four codes around the projected point, keeping the one
//! whose decoded direction is closest to the input: the measured maximum error drops from
//! 0.059 to 0.040 degrees (figures in the crate's
//! `BENCHMARKS.md` section, reproduced by `cargo run --release -p deferred --example
//! normal_error`).
//!
//! # Killzone 2 (view space)
//!
//! KZ2 stores view-space X and Y as FP16 (Cg `unpack_4ubyte(pack_2half(n.xy))`: the 32 bits
//! of two halves written as four bytes of an RGBA8 target) and reconstructs
//! `z = sqrt(1 - x² - y²)`. View space here is right-handed, the camera looking down `-z`,
//! so a surface facing the camera head-on has `n.z = +1`.
//!
//! | bits | 31..16 | 15..0 |
//! | --- | --- | --- |
//! | field | `y` as IEEE binary16 | `x` as IEEE binary16 |
//!
//! Its known failure: a front-facing surface can have a view-space normal with negative
//! `z` (near the screen edges, the more so at wide fields of view, because the direction
//! to the eye is not `+z` there). The decoder cannot know the sign and returns the normal
//! mirrored through the XY plane. [`negative_z_fraction`] measures how often that happens.

use glam::{Vec2, Vec3};

use crate::math;

/// Bits per axis of the octahedral code.
pub const OCT_BITS: u32 = 12;
/// Mask of one axis code.
pub const OCT_AXIS_MASK: u32 = (1 << OCT_BITS) - 1;
/// The code that decodes to 0 on an axis.
pub const OCT_CENTER: u32 = 2047;
/// The largest code an encoder emits (decodes to +1). Code 4095 decodes like 4094.
pub const OCT_CODE_MAX: u32 = 2 * OCT_CENTER;
/// Bits of the packed word ([`oct_encode_precise`] and friends use bits 0..24).
pub const OCT_WORD_BITS: u32 = 2 * OCT_BITS;

/// +1 for `x >= 0` (including -0), -1 below: WGSL's `select(-1, 1, x >= 0)`, branch-free.
#[inline]
fn sign_not_zero(x: f32) -> f32 {
    f32::from_bits(1.0f32.to_bits() | (u32::from(x < 0.0) << 31))
}

/// Projects a direction onto the folded octahedron square `[-1, 1]²`. Non-finite or zero
/// input projects to the square's centre (the +Z direction).
#[inline]
pub fn oct_project(n: Vec3) -> Vec2 {
    let l1 = n.x.abs() + n.y.abs() + n.z.abs();
    if l1.is_nan() || l1 <= 0.0 || l1.is_infinite() {
        return Vec2::ZERO;
    }
    let p = Vec2::new(n.x / l1, n.y / l1);
    let folded = Vec2::new(
        (1.0 - p.y.abs()) * sign_not_zero(p.x),
        (1.0 - p.x.abs()) * sign_not_zero(p.y),
    );
    if n.z < 0.0 { folded } else { p }
}

/// Unfolds a point of the octahedron square back to a unit direction (the decode without
/// quantisation). Input is clamped to `[-1, 1]²`.
#[inline]
pub fn oct_unproject(p: Vec2) -> Vec3 {
    let v = oct_unproject_unnormalized(p);
    v * (1.0 / math::sqrt(v.length_squared()))
}

/// The unfolded point on the octahedron `|x| + |y| + |z| = 1`, before normalising.
#[inline]
fn oct_unproject_unnormalized(p: Vec2) -> Vec3 {
    let p = p.clamp(Vec2::NEG_ONE, Vec2::ONE);
    let z = 1.0 - p.x.abs() - p.y.abs();
    // Fold the lower hemisphere back (Stubbe's branch-free form of the same unfold).
    let t = (-z).max(0.0);
    let x = p.x - t * sign_not_zero(p.x);
    let y = p.y - t * sign_not_zero(p.y);
    Vec3::new(x, y, z)
}

#[inline]
fn axis_value(code: u32) -> f32 {
    let c = code.min(OCT_CODE_MAX);
    (c as f32 - OCT_CENTER as f32) * (1.0 / OCT_CENTER as f32)
}

/// The code at or below a square coordinate (truncation is floor: the value is >= 0).
#[inline]
fn to_code_floor(x: f32) -> u32 {
    let s = (x.clamp(-1.0, 1.0) + 1.0) * OCT_CENTER as f32;
    (s as u32).min(OCT_CODE_MAX)
}

/// Decodes the low 24 bits of `word` (see the module's bit table) to a unit direction.
/// Every word decodes to a finite unit vector.
#[inline]
pub fn oct_decode(word: u32) -> Vec3 {
    oct_unproject(Vec2::new(
        axis_value(word & OCT_AXIS_MASK),
        axis_value((word >> OCT_BITS) & OCT_AXIS_MASK),
    ))
}

/// Encodes a direction (any length; non-finite or zero input encodes +Z) by rounding each
/// axis to the nearest code. Cheaper than [`oct_encode_precise`], larger maximum error.
#[inline]
pub fn oct_encode_fast(n: Vec3) -> u32 {
    let p = oct_project(n);
    let q = |x: f32| {
        let s = (x.clamp(-1.0, 1.0) + 1.0) * OCT_CENTER as f32;
        (math::round_half_even(s) as u32).min(OCT_CODE_MAX)
    };
    q(p.x) | (q(p.y) << OCT_BITS)
}

/// Encodes a direction with the precise encoder: of the four codes around the projected
/// point (floor and ceiling on each axis), the one whose decoded direction makes the
/// smallest angle with the input; ties keep the lower code. Non-finite or zero input
/// encodes +Z.
///
/// The angles are compared as `|a × n|² / |a|²` with `a` the decoded point before
/// normalisation: comparing dot products of unit vectors in f32 cannot tell 0.02 from 0.05
/// degrees apart (both round to within a few ulps of 1), and picked the wrong code often
/// enough to raise the maximum error by a third.
#[inline]
pub fn oct_encode_precise(n: Vec3) -> u32 {
    let p = oct_project(n);
    let len2 = n.length_squared();
    let dir = if len2 > 0.0 && len2.is_finite() {
        n * (1.0 / math::sqrt(len2))
    } else {
        Vec3::Z
    };
    let (u0, v0) = (to_code_floor(p.x), to_code_floor(p.y));
    let mut best = u0 | (v0 << OCT_BITS);
    let mut best_err = f32::INFINITY;
    for dv in 0..2u32 {
        for du in 0..2u32 {
            let u = (u0 + du).min(OCT_CODE_MAX);
            let v = (v0 + dv).min(OCT_CODE_MAX);
            let a = oct_unproject_unnormalized(Vec2::new(axis_value(u), axis_value(v)));
            let err = a.cross(dir).length_squared() / a.length_squared();
            if err < best_err {
                best_err = err;
                best = u | (v << OCT_BITS);
            }
        }
    }
    best
}

/// Encodes a view-space normal the Killzone 2 way: `x` in bits 0..16 and `y` in bits 16..32
/// as IEEE binary16 (round to nearest even). The sign of `z` is lost. Non-finite input
/// encodes `(0, 0)`, the normal facing the camera.
#[inline]
pub fn kz2_encode_view_normal(n: Vec3) -> u32 {
    let (x, y) = if n.is_finite() {
        // Normalise first: the decoder assumes a unit vector.
        let l = math::sqrt(n.length_squared());
        if l > 0.0 {
            (n.x / l, n.y / l)
        } else {
            (0.0, 0.0)
        }
    } else {
        (0.0, 0.0)
    };
    let hx = half::f16::from_f32(x).to_bits() as u32;
    let hy = half::f16::from_f32(y).to_bits() as u32;
    hx | (hy << 16)
}

/// Decodes a Killzone 2 view-space normal: `x`, `y` from the two halves, `z = sqrt(1 - x² -
/// y²) >= 0`. Words that do not hold a unit-disc point decode sanely: NaN halves decode
/// as `(0, 0, 1)`, `x² + y² > 1` as the unit vector `(x, y, 0) / |(x, y)|`.
#[inline]
pub fn kz2_decode_view_normal(word: u32) -> Vec3 {
    let x = half::f16::from_bits(word as u16).to_f32();
    let y = half::f16::from_bits((word >> 16) as u16).to_f32();
    kz2_reconstruct(x, y)
}

#[inline]
pub(crate) fn kz2_reconstruct(x: f32, y: f32) -> Vec3 {
    if !(x.is_finite() && y.is_finite()) {
        return Vec3::Z;
    }
    let r2 = x * x + y * y;
    if r2 > 1.0 {
        let r = math::sqrt(r2);
        return Vec3::new(x / r, y / r, 0.0);
    }
    Vec3::new(x, y, math::sqrt(1.0 - r2))
}

/// How surface normals are distributed over the directions facing the eye, for
/// [`negative_z_fraction`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum NormalWeighting {
    /// Uniform over the hemisphere facing the eye: the fraction of *directions*.
    Uniform,
    /// Weighted by projected area (cosine to the eye): the fraction of *screen pixels*
    /// covered by flipped normals when surfaces of every orientation are equally common.
    ProjectedArea,
}

/// The fraction of front-facing view-space normals that have negative `z` (the directions
/// KZ2's encoding flips), for a symmetric perspective camera with vertical field of view
/// `fov_y` (radians) and `aspect` = width / height.
///
/// Measured by a deterministic quasi-random integration: `samples` pixel positions uniform
/// over the screen, for each a normal drawn over the hemisphere facing the eye as
/// `weighting` says; the result is the fraction of (pixel, normal) pairs with `n.z < 0`.
/// Returns 0 when `samples` is 0 or the camera is degenerate.
pub fn negative_z_fraction(
    fov_y: f32,
    aspect: f32,
    weighting: NormalWeighting,
    samples: u32,
) -> f64 {
    if samples == 0 || !(fov_y > 0.0 && fov_y < core::f32::consts::PI && aspect > 0.0) {
        return 0.0;
    }
    let ty = math_tan_half(fov_y);
    let tx = ty * aspect;
    let mut negative = 0u64;
    // R4 sequence (Roberts' generalised golden ratio) over 4 dimensions.
    let g = 1.167_303_978_261_418_7_f64;
    let a = [
        1.0 / g,
        1.0 / (g * g),
        1.0 / (g * g * g),
        1.0 / (g * g * g * g),
    ];
    for i in 0..samples {
        let t: [f64; 4] = core::array::from_fn(|k| {
            let x = 0.5 + a[k] * f64::from(i + 1);
            x - math::floor64(x)
        });
        // Pixel uniform over the screen, as a point on the z = -1 plane.
        let px = (2.0 * t[0] - 1.0) * f64::from(tx);
        let py = (2.0 * t[1] - 1.0) * f64::from(ty);
        // Unit vector from the surface point towards the eye.
        let inv = 1.0 / math::sqrt64(px * px + py * py + 1.0);
        let e = [-px * inv, -py * inv, inv];
        let (s, c) = sincos64(2.0 * core::f64::consts::PI * t[3]);
        let nz = match weighting {
            NormalWeighting::Uniform => {
                // Uniform on the sphere, flipped into e's hemisphere.
                let z = 2.0 * t[2] - 1.0;
                let r = math::sqrt64((1.0 - z * z).max(0.0));
                let d = [r * c, r * s, z];
                if d[0] * e[0] + d[1] * e[1] + d[2] * e[2] < 0.0 {
                    -d[2]
                } else {
                    d[2]
                }
            }
            NormalWeighting::ProjectedArea => {
                // Cosine-weighted around e, in a frame (b1, b2, e): only z matters.
                let r = math::sqrt64(t[2]);
                let h = math::sqrt64((1.0 - t[2]).max(0.0));
                // b1 = normalize(e × x̂) has z = e.y / |..|; b2 = e × b1.
                let l = math::sqrt64(e[1] * e[1] + e[2] * e[2]);
                let b1 = [0.0, e[2] / l, -e[1] / l];
                let b2z = e[0] * b1[1] - e[1] * b1[0];
                r * c * b1[2] + r * s * b2z + h * e[2]
            }
        };
        if nz < 0.0 {
            negative += 1;
        }
    }
    negative as f64 / f64::from(samples)
}

fn math_tan_half(fov: f32) -> f32 {
    math::tan64(f64::from(fov) * 0.5) as f32
}

fn sincos64(x: f64) -> (f64, f64) {
    // cos from tan of the half angle keeps the math module small: t = tan(x/2),
    // sin = 2t / (1 + t²), cos = (1 - t²) / (1 + t²). x is in [0, 2π): at x = π, t is huge
    // but finite, giving (~0, -1).
    let t = math::tan64(x * 0.5);
    let d = 1.0 + t * t;
    (2.0 * t / d, (1.0 - t * t) / d)
}
