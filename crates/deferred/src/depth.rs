//! Position from depth: view-space and world-space positions reconstructed from the depth
//! buffer, standard or reversed Z, finite or infinite far plane. KZ2 dropped its position
//! target and reconstructed view-space position from depth; so does every layout here.
//!
//! # Conventions
//!
//! - View space is right-handed: camera at the origin looking down `-z`, `+x` right, `+y`
//!   up. *View distance* is `-z`, positive in front of the camera.
//! - Depth is wgpu's: NDC `z` in `[0, 1]` after the divide. Standard Z has the near plane
//!   at 0; reversed Z has it at 1 and the far plane (or infinity) at 0 (better precision
//!   with float depth).
//! - Pixels are measured from the viewport's top-left corner, `+y` down, pixel centres at
//!   `+0.5`; NDC has `+y` up.
//!
//! For a perspective projection, depth is `d = α + β / distance`, so `distance = β / (d -
//! α)` ([`Perspective::linearize`]): one subtraction and one division per pixel, then
//! `view = distance · (ndc.x · tan_x, ndc.y · tan_y, -1)`. Any other projection (jittered,
//! oblique) goes through the inverse matrix ([`view_position_from_inverse`]).

use bytemuck::{Pod, Zeroable};
use glam::{DMat4, DVec4, Mat4, Vec2, Vec3, Vec4};

use crate::Error;
use crate::math;

/// Which end of `[0, 1]` the near plane maps to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DepthMode {
    /// Near plane at depth 0, far at 1; tested with `Less`, cleared to 1.
    Standard,
    /// Near plane at depth 1, far (or infinity) at 0; tested with `Greater`, cleared to 0.
    Reversed,
}

impl DepthMode {
    /// The depth of the far plane (the clear value): pixels at it hold no geometry.
    pub const fn far_depth(self) -> f32 {
        match self {
            DepthMode::Standard => 1.0,
            DepthMode::Reversed => 0.0,
        }
    }

    /// Whether `a` is nearer the camera than `b`.
    pub fn nearer(self, a: f32, b: f32) -> bool {
        match self {
            DepthMode::Standard => a < b,
            DepthMode::Reversed => a > b,
        }
    }
}

/// `distance = beta / (depth - alpha)`: the perspective depth mapping's two coefficients.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Linearize {
    /// Depth at infinite distance.
    pub alpha: f32,
    /// Scale: `depth - alpha = beta / distance`.
    pub beta: f32,
}

impl Linearize {
    /// View distance of a depth value (positive; infinite at `alpha`).
    #[inline]
    pub fn distance(&self, depth: f32) -> f32 {
        self.beta / (depth - self.alpha)
    }

    /// The depth value of a view distance.
    #[inline]
    pub fn depth(&self, distance: f32) -> f32 {
        self.alpha + self.beta / distance
    }
}

/// A symmetric perspective projection (right-handed view space, wgpu depth range).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Perspective {
    /// Vertical field of view, radians, in `(0, π)`.
    pub fov_y: f32,
    /// Width / height.
    pub aspect: f32,
    /// Near-plane distance, > 0.
    pub near: f32,
    /// Far-plane distance (> near), or `None` for an infinite far plane.
    pub far: Option<f32>,
    /// Depth convention.
    pub mode: DepthMode,
}

impl Perspective {
    /// Checks the parameters: every error names the parameter.
    pub fn try_new(
        fov_y: f32,
        aspect: f32,
        near: f32,
        far: Option<f32>,
        mode: DepthMode,
    ) -> Result<Self, Error> {
        let bad = |name, v: f32| Error::InvalidParameter {
            name,
            value: f64::from(v),
        };
        if !(fov_y > 0.0 && fov_y < core::f32::consts::PI) {
            return Err(bad("fov_y", fov_y));
        }
        if !(aspect > 0.0 && aspect.is_finite()) {
            return Err(bad("aspect", aspect));
        }
        if !(near > 0.0 && near.is_finite()) {
            return Err(bad("near", near));
        }
        if let Some(f) = far
            && !(f > near && f.is_finite())
        {
            return Err(bad("far", f));
        }
        Ok(Perspective {
            fov_y,
            aspect,
            near,
            far,
            mode,
        })
    }

    /// `tan(fov_y / 2)`.
    pub fn tan_half_y(&self) -> f64 {
        math::tan64(f64::from(self.fov_y) * 0.5)
    }

    /// The depth mapping in f64: `(alpha, beta)`.
    pub fn linearize_f64(&self) -> (f64, f64) {
        let n = f64::from(self.near);
        match (self.far.map(f64::from), self.mode) {
            (Some(f), DepthMode::Standard) => (f / (f - n), -n * f / (f - n)),
            (Some(f), DepthMode::Reversed) => (-n / (f - n), n * f / (f - n)),
            (None, DepthMode::Standard) => (1.0, -n),
            (None, DepthMode::Reversed) => (0.0, n),
        }
    }

    /// The depth mapping: `distance = beta / (depth - alpha)`.
    pub fn linearize(&self) -> Linearize {
        let (a, b) = self.linearize_f64();
        Linearize {
            alpha: a as f32,
            beta: b as f32,
        }
    }

    /// View → clip matrix, computed in f64.
    pub fn matrix_f64(&self) -> DMat4 {
        let sy = 1.0 / self.tan_half_y();
        let sx = sy / f64::from(self.aspect);
        let (alpha, beta) = self.linearize_f64();
        // clip.z = -alpha · z + beta, clip.w = -z: depth = alpha + beta / (-z).
        DMat4::from_cols(
            DVec4::new(sx, 0.0, 0.0, 0.0),
            DVec4::new(0.0, sy, 0.0, 0.0),
            DVec4::new(0.0, 0.0, -alpha, -1.0),
            DVec4::new(0.0, 0.0, beta, 0.0),
        )
    }

    /// View → clip matrix.
    pub fn matrix(&self) -> Mat4 {
        self.matrix_f64().as_mat4()
    }

    /// The parameters the GPU needs for the fast reconstruction.
    pub fn gpu(&self, viewport: Vec2) -> DeferredProjection {
        let ty = self.tan_half_y();
        let l = self.linearize();
        DeferredProjection {
            tan_half: [(ty * f64::from(self.aspect)) as f32, ty as f32],
            alpha: l.alpha,
            beta: l.beta,
            viewport: [viewport.x, viewport.y, 1.0 / viewport.x, 1.0 / viewport.y],
        }
    }

    /// View-space position of the pixel centre `pixel` (pixels from the top-left, centres
    /// at +0.5) at depth `depth`, in a `viewport`-sized target.
    #[inline]
    pub fn view_position(&self, pixel: Vec2, viewport: Vec2, depth: f32) -> Vec3 {
        self.gpu(viewport).view_position(pixel, depth)
    }
}

/// The fast reconstruction's parameters, as the WGSL struct `DeferredProjection` (32
/// bytes, upload in a uniform buffer).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct DeferredProjection {
    /// `tan` of half the horizontal and vertical fields of view.
    pub tan_half: [f32; 2],
    /// [`Linearize::alpha`].
    pub alpha: f32,
    /// [`Linearize::beta`].
    pub beta: f32,
    /// Width, height, 1 / width, 1 / height, in pixels.
    pub viewport: [f32; 4],
}
const _: () = assert!(size_of::<DeferredProjection>() == 32);

impl DeferredProjection {
    /// The depth mode: reversed Z has the near plane at depth 1, which makes `beta > 0`.
    #[inline]
    pub fn mode(&self) -> DepthMode {
        if self.beta > 0.0 {
            DepthMode::Reversed
        } else {
            DepthMode::Standard
        }
    }

    /// The near plane's depth: 1 for reversed Z, 0 for standard.
    #[inline]
    pub fn near_depth(&self) -> f32 {
        match self.mode() {
            DepthMode::Reversed => 1.0,
            DepthMode::Standard => 0.0,
        }
    }

    /// Depth-buffer value of a view distance.
    #[inline]
    pub fn depth_of_distance(&self, distance: f32) -> f32 {
        self.alpha + self.beta / distance
    }

    /// View distance (`-z`) at `depth`.
    #[inline]
    pub fn distance(&self, depth: f32) -> f32 {
        self.beta / (depth - self.alpha)
    }

    /// View-space position of a pixel centre at `depth` (the WGSL
    /// `deferred_view_position`).
    #[inline]
    pub fn view_position(&self, pixel: Vec2, depth: f32) -> Vec3 {
        let ndc = ndc_from_pixel(pixel, Vec2::new(self.viewport[2], self.viewport[3]));
        let dist = self.distance(depth);
        Vec3::new(
            ndc.x * self.tan_half[0] * dist,
            ndc.y * self.tan_half[1] * dist,
            -dist,
        )
    }
}

/// NDC `xy` of a pixel position (`+y` down in pixels, up in NDC), given `1 / viewport`.
#[inline]
pub fn ndc_from_pixel(pixel: Vec2, inv_viewport: Vec2) -> Vec2 {
    Vec2::new(
        pixel.x * inv_viewport.x * 2.0 - 1.0,
        1.0 - pixel.y * inv_viewport.y * 2.0,
    )
}

/// Position from depth through any inverse projection: `inv` maps NDC `(x, y, depth, 1)`
/// back to the space you want (the inverse projection gives view space; the inverse
/// view-projection gives world space, or camera-relative world space if the view matrix
/// had no translation, as in the `gpu` crate). Works for jittered and oblique projections
/// too. Returns the homogeneous divide of the result (infinite or NaN at the far plane of
/// an infinite projection).
#[inline]
pub fn view_position_from_inverse(inv: Mat4, pixel: Vec2, viewport: Vec2, depth: f32) -> Vec3 {
    let ndc = ndc_from_pixel(pixel, viewport.recip());
    let p = inv * Vec4::new(ndc.x, ndc.y, depth, 1.0);
    p.truncate() / p.w
}

/// World-space position of a pixel from the inverse view-projection (the same computation
/// as [`view_position_from_inverse`], named for the world-space use).
#[inline]
pub fn world_position_from_depth(
    inv_view_proj: Mat4,
    pixel: Vec2,
    viewport: Vec2,
    depth: f32,
) -> Vec3 {
    view_position_from_inverse(inv_view_proj, pixel, viewport, depth)
}
