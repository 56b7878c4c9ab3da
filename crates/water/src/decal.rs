//! Vector displacement decals: projected boxes that push the water surface around.
//!
//! Far Cry 5 renders a projected box decal per displacement particle (splashes, a
//! helicopter's downwash): the water position comes from depth, goes to the box's object
//! space for its UVs ("otherwise you will notice distortion in screen space"), pixels
//! outside the box are clipped, the displacement texture is sampled (animated over
//! frames), and "the most important thing": the displacement fades to zero towards the box
//! edges, or it "explodes" where the box cuts a waterfall. Decals combine with a max blend
//! into a target cleared to the most negative float (seed 003).
//!
//! # Conventions
//!
//! A decal is an oriented box: `box_to_world` maps the unit box `[-1, 1]^3` to world space
//! (metres). Its texture is addressed by `uv = (local.xy + 1) / 2` (local x right, y
//! forward, z up through the box) and holds displacement vectors in the box's local frame
//! in units of the box half-extents; they are mapped to world metres by `box_to_world`'s
//! linear part, times the decal's `strength`. The fade is `prod_i smoothstep(0, fade,
//! 1 - |local_i|)` over the three axes.

use alloc::vec::Vec;

use glam::{Affine3A, Quat, Vec2, Vec3};

use crate::Error;
use crate::grid::{clamped_index, size_getters};
use crate::math;

/// The value a displacement target is cleared to before the max blend.
pub const CLEAR_DISPLACEMENT: f32 = -f32::MAX;

/// An animated vector displacement texture: `frames` frames of `width x height` texels,
/// each a displacement in box-local half-extent units.
#[derive(Clone, Debug, PartialEq)]
pub struct DecalTexture {
    width: u32,
    height: u32,
    frames: u32,
    texels: Vec<Vec3>,
}

impl DecalTexture {
    /// Wraps texels (frame-major, then row-major). All finite, dimensions at least 1.
    pub fn new(width: u32, height: u32, frames: u32, texels: Vec<Vec3>) -> Result<Self, Error> {
        for (field, v) in [
            ("decal width", width),
            ("decal height", height),
            ("decal frames", frames),
        ] {
            if v == 0 {
                return Err(Error::InvalidSize {
                    field,
                    value: 0,
                    rule: "at least 1",
                });
            }
        }
        let expected = width as usize * height as usize * frames as usize;
        if texels.len() != expected {
            return Err(Error::LengthMismatch {
                field: "decal texels",
                len: texels.len(),
                expected,
            });
        }
        if !texels.iter().all(|t| t.is_finite()) {
            return Err(Error::NonFinite {
                field: "decal texel",
            });
        }
        Ok(Self {
            width,
            height,
            frames,
            texels,
        })
    }

    /// Frames in the animation.
    #[must_use]
    pub fn frames(&self) -> u32 {
        self.frames
    }

    size_getters!("Width in texels.", "Height in texels.");

    /// The texels, frame-major then row-major (what a renderer uploads).
    #[must_use]
    pub fn texels(&self) -> &[Vec3] {
        &self.texels
    }

    fn texel(&self, frame: u32, x: i64, y: i64) -> Vec3 {
        let f = (frame % self.frames) as usize;
        let frame_texels = self.width as usize * self.height as usize;
        self.texels[f * frame_texels + clamped_index(self.width, self.height, x, y)]
    }

    /// Bilinear sample of frame `frame` at `uv` in `[0, 1]^2` (texel centres at
    /// `(i + 0.5) / width`, clamped at the edges).
    #[must_use]
    pub fn sample(&self, frame: u32, uv: Vec2) -> Vec3 {
        let p = uv * Vec2::new(self.width as f32, self.height as f32) - 0.5;
        let (fx, fy) = (math::floor(p.x), math::floor(p.y));
        let (tx, ty) = (p.x - fx, p.y - fy);
        let (x, y) = (fx as i64, fy as i64);
        let a = self
            .texel(frame, x, y)
            .lerp(self.texel(frame, x + 1, y), tx);
        let b = self
            .texel(frame, x, y + 1)
            .lerp(self.texel(frame, x + 1, y + 1), tx);
        a.lerp(b, ty)
    }

    /// Sample at a continuous frame position (`frame` frames, wrapping), blending the two
    /// nearest frames.
    #[must_use]
    pub fn sample_animated(&self, frame: f32, uv: Vec2) -> Vec3 {
        let f = if frame.is_finite() { frame } else { 0.0 };
        let base = math::floor(f);
        let t = f - base;
        let n = self.frames as i64;
        let i0 = (base as i64).rem_euclid(n) as u32;
        let i1 = (i0 + 1) % self.frames;
        self.sample(i0, uv).lerp(self.sample(i1, uv), t)
    }
}

/// One decal: a box, a texture, a strength and an animation position.
#[derive(Clone, Debug)]
pub struct DisplacementDecal<'a> {
    /// Unit box `[-1, 1]^3` to world.
    pub box_to_world: Affine3A,
    /// The displacement texture.
    pub texture: &'a DecalTexture,
    /// Multiplies the displacement.
    pub strength: f32,
    /// Animation position in frames.
    pub frame: f32,
    /// Fade width in local units (0..1] at each face; 0.25 fades over the outer quarter.
    pub fade: f32,
}

impl<'a> DisplacementDecal<'a> {
    /// A box at `center` with `half_extents` (metres) rotated by `rotation`.
    #[must_use]
    pub fn new(
        center: Vec3,
        half_extents: Vec3,
        rotation: Quat,
        texture: &'a DecalTexture,
    ) -> Self {
        Self {
            box_to_world: Affine3A::from_scale_rotation_translation(half_extents, rotation, center),
            texture,
            strength: 1.0,
            frame: 0.0,
            fade: 0.25,
        }
    }

    /// The edge fade at box-local `local` (0 outside the box, 1 in its core).
    #[must_use]
    pub fn fade_at(&self, local: Vec3) -> f32 {
        edge_fade(local, self.fade)
    }

    /// The world displacement (metres) this decal adds at world position `p` on the water
    /// surface, or `None` where `p` is outside the box (the clipped pixels).
    #[must_use]
    pub fn displacement(&self, p: Vec3) -> Option<Vec3> {
        let local = self.box_to_world.inverse().transform_point3(p);
        if !(local.abs().max_element() <= 1.0) {
            return None;
        }
        let uv = (local.truncate() + 1.0) * 0.5;
        let d = self.texture.sample_animated(self.frame, uv);
        let w = self.fade_at(local) * self.strength;
        Some(self.box_to_world.transform_vector3(d) * w)
    }
}

/// The fade of a box-local point: `prod_i smoothstep(0, fade, 1 - |local_i|)`.
#[must_use]
pub fn edge_fade(local: Vec3, fade: f32) -> f32 {
    let f = fade.max(1e-6);
    let e = Vec3::ONE - local.abs();
    math::smoothstep(0.0, f, e.x) * math::smoothstep(0.0, f, e.y) * math::smoothstep(0.0, f, e.z)
}

/// The max blend: per component `max(target, value)` (what `BlendOperation::Max` does).
#[must_use]
pub fn blend_max(target: Vec3, value: Vec3) -> Vec3 {
    target.max(value)
}

/// Every decal's displacement at `p` max-blended into a target cleared to
/// [`CLEAR_DISPLACEMENT`]; a component no decal wrote reads as 0.
#[must_use]
pub fn combined_displacement(decals: &[DisplacementDecal<'_>], p: Vec3) -> Vec3 {
    let mut target = Vec3::splat(CLEAR_DISPLACEMENT);
    for d in decals {
        if let Some(v) = d.displacement(p) {
            target = blend_max(target, v);
        }
    }
    Vec3::select(
        target.cmpeq(Vec3::splat(CLEAR_DISPLACEMENT)),
        Vec3::ZERO,
        target,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::vec;

    #[test]
    fn displacement_fades_to_zero_at_the_box_edges() {
        let tex = DecalTexture::new(1, 1, 1, vec![Vec3::new(0.0, 0.0, 1.0)]).unwrap();
        let d = DisplacementDecal::new(
            Vec3::new(10.0, 0.0, 0.0),
            Vec3::new(2.0, 2.0, 1.0),
            Quat::IDENTITY,
            &tex,
        );
        // Core: full strength, 1 half-extent in z = 1 m.
        let c = d.displacement(Vec3::new(10.0, 0.0, 0.0)).unwrap();
        assert!((c - Vec3::Z).length() < 1e-6);
        // Approaching the x face, the displacement goes continuously to 0.
        let mut last = 1.0;
        for i in 0..=20 {
            let x = 10.0 + 1.5 + 0.5 * i as f32 / 20.0;
            let v = d.displacement(Vec3::new(x, 0.0, 0.0)).unwrap().z;
            assert!(v <= last + 1e-6);
            last = v;
        }
        assert!(last.abs() < 1e-6);
        assert!(d.displacement(Vec3::new(12.01, 0.0, 0.0)).is_none());
        assert!(d.displacement(Vec3::NAN).is_none());
    }

    #[test]
    fn max_blend_of_overlapping_decals() {
        let up = DecalTexture::new(1, 1, 1, vec![Vec3::new(0.5, 0.0, 1.0)]).unwrap();
        let down = DecalTexture::new(1, 1, 1, vec![Vec3::new(-0.5, 0.0, -1.0)]).unwrap();
        let a = DisplacementDecal::new(Vec3::ZERO, Vec3::ONE, Quat::IDENTITY, &up);
        let b = DisplacementDecal::new(Vec3::ZERO, Vec3::ONE, Quat::IDENTITY, &down);
        let v = combined_displacement(&[b.clone(), a], Vec3::ZERO);
        assert_eq!(v, Vec3::new(0.5, 0.0, 1.0));
        // One negative decal alone keeps its (negative) value; nothing gives zero.
        assert_eq!(
            combined_displacement(&[b], Vec3::ZERO),
            Vec3::new(-0.5, 0.0, -1.0)
        );
        assert_eq!(combined_displacement(&[], Vec3::ZERO), Vec3::ZERO);
    }
}
