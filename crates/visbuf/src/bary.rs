//! Barycentrics and their screen-space derivatives for the material resolve: the vis buffer
//! names a triangle, the resolve pulls its three vertices and needs, per pixel, the
//! perspective-correct barycentric weights and how they change to the next pixel (for
//! texture gradients, since compute has no hardware quads).
//!
//! # Method
//!
//! The analytic method (Schied and Dachsbacher's DAIS appendix, as used by The Forge and
//! Bevy), written in 2D homogeneous form so no vertex is ever divided by its w: with clip
//! positions `P_i = (x_i, y_i, w_i)` moved so the pixel sits at the origin
//! (`x'_i = x_i - q_x w_i`, `y'_i = y_i - q_y w_i`, `q` the pixel centre in NDC), the
//! perspective-correct weights are `lambda_i = e_i / (e_0 + e_1 + e_2)` with
//! `e_i = x'_j y'_k - x'_k y'_j` (`i, j, k` cyclic). Each `e_i` is linear in `q`, so its
//! derivatives are exact, and `d lambda_i = (d e_i - lambda_i d S) / S`. This equals the
//! DAIS formulas (the tests compare against them in f64) and stays defined for vertices
//! with `w <= 0` (behind the eye) and pixels outside the triangle (weights outside
//! `[0, 1]`, never clamped: the rasteriser already decided coverage).
//!
//! # Conventions
//!
//! - `pixel`: framebuffer coordinates relative to the viewport's top-left corner, +x right,
//!   +y down, in pixels; pixel `(i, j)` has its centre at `(i + 0.5, j + 0.5)`.
//! - `viewport`: width and height in pixels. NDC is `x = 2 px / W - 1`, `y = 1 - 2 py / H`
//!   (WebGPU: NDC +y is up, framebuffer +y is down).
//! - `ddx` / `ddy`: change per pixel to the right / per pixel down.
//! - Clip positions are `(x, y, z, w)` as the vertex stage output them (z unused).
//!   Positions should be camera-relative before projection, as for any f32 method.
//!
//! # Degenerate input
//!
//! Zero-area (or edge-on) triangles, non-finite positions, and triangles so thin that the
//! weights would overflow (`|S|` below [`DEGENERATE_EPSILON`] `* m^2`) give
//! `lambda = (1/3, 1/3, 1/3)` with zero derivatives: finite, never NaN. Inputs are scaled
//! by powers of two first, so huge and tiny coordinates work.

use core::ops::{Add, Mul};

use glam::{Vec2, Vec3, Vec4};

use crate::math;

/// A triangle counts as degenerate at a pixel when `|e_0 + e_1 + e_2|` is below this times
/// `m^2`, `m` the largest pixel-relative coordinate: `2^-40`. Above it weights stay below
/// `2^41` and their derivatives below `2^125`, so nothing overflows f32.
pub const DEGENERATE_EPSILON: f32 = 9.094947e-13;

/// The pixel's NDC position is clamped to `[-2^20, 2^20]` (a million viewports away), which
/// bounds the pixel-relative coordinates.
pub const MAX_NDC: f32 = 1048576.0;

/// Pixel-relative coordinates all below `2^-40` (after scaling the clip positions to at
/// most 1) count as degenerate.
const MIN_RELATIVE: f32 = 9.094947e-13;

/// Perspective-correct barycentric weights of one pixel and their screen-space derivatives.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Barycentrics {
    /// Weights of vertices 0, 1, 2; they sum to 1.
    pub lambda: Vec3,
    /// Change of each weight per pixel to the right (+x). Sums to 0.
    pub ddx: Vec3,
    /// Change of each weight per pixel down (+y in the framebuffer). Sums to 0.
    pub ddy: Vec3,
}

/// An interpolated attribute with its screen-space derivatives.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Interpolated<T> {
    /// Value at the pixel.
    pub value: T,
    /// Change per pixel to the right.
    pub ddx: T,
    /// Change per pixel down.
    pub ddy: T,
}

impl Barycentrics {
    /// The weights of a degenerate triangle: the centroid, no change across the screen.
    pub const DEGENERATE: Barycentrics = Barycentrics {
        lambda: Vec3::splat(1.0 / 3.0),
        ddx: Vec3::ZERO,
        ddy: Vec3::ZERO,
    };

    /// The weights clamped to the triangle: negative ones set to 0 and all scaled to sum
    /// to 1 (weights inside move by an ulp at most); the derivatives kept (the plane's,
    /// for texture LOD). A vis-buffer pixel lies in its triangle as the rasteriser snapped
    /// it, but HFW's vertex ring's f16 positions (or, by far less, unsnapped ones) can
    /// leave its centre outside a sub-pixel or edge-on triangle, where the weights
    /// extrapolate far along its plane: clamped, every attribute (the position, so the
    /// motion too) stays within the triangle's range. [`Barycentrics::DEGENERATE`] when
    /// the weights are not finite. WGSL: `visbuf_clamp_barycentrics` (for finite weights).
    #[must_use]
    #[inline]
    pub fn clamped(&self) -> Barycentrics {
        if !self.lambda.is_finite() {
            return Barycentrics::DEGENERATE;
        }
        // As the WGSL twin: no early return for the inside (on the GPU it cost registers).
        let l = self.lambda.max(Vec3::ZERO);
        let sum = l.x + l.y + l.z;
        // Finite weights summing to 1 keep one positive; other inputs may not.
        if sum <= 0.0 {
            return Barycentrics::DEGENERATE;
        }
        Barycentrics {
            lambda: l / sum,
            ..*self
        }
    }

    /// Interpolates a per-vertex attribute (f32 or any glam vector) with its derivatives.
    #[must_use]
    #[inline]
    pub fn interpolate<T>(&self, a: [T; 3]) -> Interpolated<T>
    where
        T: Copy + Mul<f32, Output = T> + Add<Output = T>,
    {
        let mix = |w: Vec3| a[0] * w.x + a[1] * w.y + a[2] * w.z;
        Interpolated {
            value: mix(self.lambda),
            ddx: mix(self.ddx),
            ddy: mix(self.ddy),
        }
    }
}

/// The power of two `2^-e` with `m = f 2^e`, `f` in `[0.5, 1)`: scaling by it is exact and
/// brings `m` into `[0.5, 1)`. `None` when `m` is not finite or below `2^-100` (nothing
/// meaningful is that small).
#[inline]
fn pow2_scale(m: f32) -> Option<f32> {
    if !(m.is_finite() && m >= MIN_MAGNITUDE) {
        return None;
    }
    let e = ((m.to_bits() >> 23) & 0xff) as i32 - 126; // -99 ..= 128
    Some(pow2(-e))
}

/// `2^k` for `k` in `-149 ..= 127`.
#[inline]
fn pow2(k: i32) -> f32 {
    if k >= -126 {
        f32::from_bits(((127 + k) as u32) << 23)
    } else {
        f32::from_bits(1 << (149 + k))
    }
}

/// Smallest coordinate magnitude the scaling accepts: `2^-100`.
const MIN_MAGNITUDE: f32 = 7.888609e-31;

/// Scaled pixel-relative positions and their edge functions: `(e, de/dqx, de/dqy)`, or
/// `None` when degenerate.
#[inline]
fn edges(clip: [Vec4; 3], q: Vec2) -> Option<(Vec3, Vec3, Vec3)> {
    // Bring the raw positions to at most 1 (exactly, by a power of two) so nothing below
    // overflows; weights do not depend on a common scale.
    let [c0, c1, c2] = clip;
    let m0 = (c0.x.abs().max(c0.y.abs()).max(c0.w.abs()))
        .max(c1.x.abs().max(c1.y.abs()).max(c1.w.abs()))
        .max(c2.x.abs().max(c2.y.abs()).max(c2.w.abs()));
    let s0 = pow2_scale(m0)?;
    let q = q.clamp(Vec2::splat(-MAX_NDC), Vec2::splat(MAX_NDC));
    // Pixel-relative homogeneous positions (x', y', w).
    let rel = |c: Vec4| {
        let (x, y, w) = (c.x * s0, c.y * s0, c.w * s0);
        (x - q.x * w, y - q.y * w, w)
    };
    let (x0, y0, w0) = rel(c0);
    let (x1, y1, w1) = rel(c1);
    let (x2, y2, w2) = rel(c2);
    // e_i = x'_j y'_k - x'_k y'_j; de_i/dqx = w_k y'_j - w_j y'_k; de_i/dqy = w_j x'_k - w_k x'_j.
    let e = Vec3::new(x1 * y2 - x2 * y1, x2 * y0 - x0 * y2, x0 * y1 - x1 * y0);
    let ex = Vec3::new(w2 * y1 - w1 * y2, w0 * y2 - w2 * y0, w1 * y0 - w0 * y1);
    let ey = Vec3::new(w1 * x2 - w2 * x1, w2 * x0 - w0 * x2, w0 * x1 - w1 * x0);
    // Degenerate when the sum is tiny against the squared magnitude of the pixel-relative
    // positions (scale-free), or those are all tiny.
    let m1 = (x0.abs().max(y0.abs()).max(w0.abs()))
        .max(x1.abs().max(y1.abs()).max(w1.abs()))
        .max(x2.abs().max(y2.abs()).max(w2.abs()));
    let sum = e.x + e.y + e.z;
    if !(m1 >= MIN_RELATIVE && sum.abs() >= DEGENERATE_EPSILON * (m1 * m1)) {
        return None;
    }
    Some((e, ex, ey))
}

#[inline]
fn ndc(pixel: Vec2, viewport: Vec2) -> Vec2 {
    Vec2::new(
        2.0 * pixel.x / viewport.x - 1.0,
        1.0 - 2.0 * pixel.y / viewport.y,
    )
}

#[inline]
fn finite_or_degenerate(b: Barycentrics) -> Barycentrics {
    // Unreachable for finite input by the bounds above; kept as a cheap guarantee.
    if (b.lambda + b.ddx + b.ddy).is_finite() {
        b
    } else {
        Barycentrics::DEGENERATE
    }
}

/// Perspective-correct barycentrics at `pixel` with their exact screen-space derivatives
/// (the analytic gradient at the pixel centre). See the [module docs](self) for the
/// conventions. A viewport with a zero or non-finite side gives [`Barycentrics::DEGENERATE`].
#[must_use]
#[inline]
pub fn barycentrics(clip: [Vec4; 3], pixel: Vec2, viewport: Vec2) -> Barycentrics {
    if !(viewport.x > 0.0 && viewport.y > 0.0 && viewport.is_finite() && pixel.is_finite()) {
        return Barycentrics::DEGENERATE;
    }
    let Some((e, ex, ey)) = edges(clip, ndc(pixel, viewport)) else {
        return Barycentrics::DEGENERATE;
    };
    let inv = 1.0 / e.element_sum();
    let lambda = e * inv;
    // d lambda / d q, then per pixel: dq_x / dpx = 2 / W, dq_y / dpy = -2 / H.
    let dqx = (ex - lambda * ex.element_sum()) * inv;
    let dqy = (ey - lambda * ey.element_sum()) * inv;
    finite_or_degenerate(Barycentrics {
        lambda,
        ddx: dqx * (2.0 / viewport.x),
        ddy: dqy * (-2.0 / viewport.y),
    })
}

/// Like [`barycentrics`], but `ddx` / `ddy` are one-pixel forward differences,
/// `lambda(pixel + (1, 0)) - lambda(pixel)` and `lambda(pixel + (0, 1)) - lambda(pixel)`,
/// which is what a hardware 2x2 quad's `dpdxFine` / `dpdyFine` give on its top-left
/// pixel. Where the neighbouring pixel's weights would be degenerate the exact derivative
/// is used instead.
///
/// The subtraction of two nearly equal weights costs precision: expect absolute errors of
/// a few f32 ulps of the weights (about 1e-6 to 4e-6), large relative to the differences
/// of big triangles. [`barycentrics`] has no such cancellation.
#[must_use]
#[inline]
pub fn barycentrics_quad(clip: [Vec4; 3], pixel: Vec2, viewport: Vec2) -> Barycentrics {
    if !(viewport.x > 0.0 && viewport.y > 0.0 && viewport.is_finite() && pixel.is_finite()) {
        return Barycentrics::DEGENERATE;
    }
    let Some((e, ex, ey)) = edges(clip, ndc(pixel, viewport)) else {
        return Barycentrics::DEGENERATE;
    };
    let s = e.element_sum();
    let lambda = e * (1.0 / s);
    let step = |de: Vec3, d: f32| {
        // e is linear in q: e(q + d) = e + de * d, exactly.
        let s1 = s + de.element_sum() * d;
        if s1.abs() >= DEGENERATE_EPSILON {
            (e + de * d) / s1 - lambda
        } else {
            (de - lambda * de.element_sum()) / s * d
        }
    };
    finite_or_degenerate(Barycentrics {
        lambda,
        ddx: step(ex, 2.0 / viewport.x),
        ddy: step(ey, -2.0 / viewport.y),
    })
}

/// The mip level a texture of `texture_size` texels would be sampled at for UV derivatives
/// `duv_dx`, `duv_dy` (UV units per pixel, as from [`Barycentrics::interpolate`]):
/// `log2(max(|duv_dx * size|, |duv_dy * size|)) + bias`, the isotropic formula of the
/// OpenGL and Vulkan specifications. Not clamped to the texture's levels; finite for finite
/// `bias` (a zero footprint gives -63 + bias, an infinite one 64 + bias).
#[must_use]
#[inline]
pub fn mip_level(duv_dx: Vec2, duv_dy: Vec2, texture_size: Vec2, bias: f32) -> f32 {
    let rho2 = (duv_dx * texture_size)
        .length_squared()
        .max((duv_dy * texture_size).length_squared());
    let rho2 = if rho2 >= f32::MIN_POSITIVE {
        rho2.min(f32::MAX)
    } else {
        f32::MIN_POSITIVE
    };
    0.5 * math::log2(rho2) + bias
}

/// Scales UV gradients by `2^bias`, which moves the sampled mip level by `bias`: WGSL's
/// `textureSampleGrad` has no bias argument.
#[must_use]
#[inline]
pub fn bias_gradients(duv_dx: Vec2, duv_dy: Vec2, bias: f32) -> (Vec2, Vec2) {
    let s = math::exp2(bias);
    (duv_dx * s, duv_dy * s)
}
