//! Water materials and blending between two water bodies.
//!
//! Artists can place two rivers with very different materials next to each other; Far Cry
//! 5 stores each pixel's material and the neighbouring "blend material", and blends "from
//! one river to the other without any discontinuities" over an artist-set distance ("we
//! typically use six meters"), interpolating "only the specific ones that are required,
//! because it's kind of a waste of ALUs to do the rest" (seed 003).
//!
//! What is interpolated and what is not:
//!
//! | field | blended | why |
//! | --- | --- | --- |
//! | optics (absorption, scattering) | linear | the colour must not jump at the boundary |
//! | roughness, roughness cap | linear | specular highlight width |
//! | displacement amplitude | linear | the surface shape must not step |
//! | foam intensity, shore width | linear | foam must not end on a line |
//! | detail normal weight | linear | |
//! | shader ID, foam / algae texture indices | taken from the dominant material (`t < 0.5` keeps `a`) | indices cannot be averaged; both textures would otherwise be sampled |
//!
//! The weight comes from the signed distance to the boundary between the two bodies (the
//! baked material map): [`blend_weight`].

use bytemuck::{Pod, Zeroable};

use crate::math;
use crate::optics::{Medium, WaterType};

/// The talk's usual blend distance, metres.
pub const DEFAULT_BLEND_DISTANCE: f32 = 6.0;

/// A water material: what the material structure buffer holds per entry.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WaterMaterial {
    /// Absorption and scattering (1/m).
    pub medium: Medium,
    /// Perceptual roughness of the surface.
    pub roughness: f32,
    /// The most specular AA may widen the roughness to.
    pub max_roughness: f32,
    /// FBM displacement amplitude, metres.
    pub displacement_amplitude: f32,
    /// Foam intensity.
    pub foam_intensity: f32,
    /// Shoreline foam width, metres.
    pub shore_width: f32,
    /// Weight of the high-frequency normal against the mesh normal.
    pub detail_weight: f32,
    /// Shader ID (features the passes run).
    pub shader_id: u8,
    /// Foam texture array index.
    pub foam_texture: u16,
    /// Algae texture array index.
    pub algae_texture: u16,
}

impl WaterMaterial {
    /// A material of water type `t` with the other fields at typical values.
    #[must_use]
    pub fn from_type(t: &WaterType) -> Self {
        Self {
            medium: t.medium(),
            roughness: 0.08,
            max_roughness: 0.5,
            displacement_amplitude: 0.25,
            foam_intensity: 1.0,
            shore_width: 3.0,
            detail_weight: 0.8,
            shader_id: 0,
            foam_texture: 0,
            algae_texture: 0,
        }
    }

    /// The blend of `self` (weight `1 - t`) and `other` (weight `t`); see the module docs
    /// for which fields are interpolated. `t` is clamped to `[0, 1]` (NaN counts as 0).
    #[must_use]
    pub fn blend(&self, other: &WaterMaterial, t: f32) -> WaterMaterial {
        let t = math::saturate(t);
        let l = |a: f32, b: f32| math::mix(a, b, t);
        let dominant = if t < 0.5 { self } else { other };
        WaterMaterial {
            medium: Medium {
                absorption: math::mix3(self.medium.absorption, other.medium.absorption, t),
                scattering: math::mix3(self.medium.scattering, other.medium.scattering, t),
            },
            roughness: l(self.roughness, other.roughness),
            max_roughness: l(self.max_roughness, other.max_roughness),
            displacement_amplitude: l(self.displacement_amplitude, other.displacement_amplitude),
            foam_intensity: l(self.foam_intensity, other.foam_intensity),
            shore_width: l(self.shore_width, other.shore_width),
            detail_weight: l(self.detail_weight, other.detail_weight),
            shader_id: dominant.shader_id,
            foam_texture: dominant.foam_texture,
            algae_texture: dominant.algae_texture,
        }
    }

    /// The GPU record.
    #[must_use]
    pub fn to_gpu(&self) -> WaterMaterialGpu {
        WaterMaterialGpu {
            absorption: self.medium.absorption.extend(self.roughness).to_array(),
            scattering: self.medium.scattering.extend(self.max_roughness).to_array(),
            displacement_amplitude: self.displacement_amplitude,
            foam_intensity: self.foam_intensity,
            shore_width: self.shore_width,
            detail_weight: self.detail_weight,
            ids: u32::from(self.shader_id),
            foam_texture: u32::from(self.foam_texture),
            algae_texture: u32::from(self.algae_texture),
            _pad: 0,
        }
    }

    /// From the GPU record (texture indices above `u16::MAX` and shader IDs above 255 are
    /// truncated).
    #[must_use]
    pub fn from_gpu(g: &WaterMaterialGpu) -> Self {
        let [ax, ay, az, r] = g.absorption;
        let [sx, sy, sz, mr] = g.scattering;
        Self {
            medium: Medium {
                absorption: glam::Vec3::new(ax, ay, az),
                scattering: glam::Vec3::new(sx, sy, sz),
            },
            roughness: r,
            max_roughness: mr,
            displacement_amplitude: g.displacement_amplitude,
            foam_intensity: g.foam_intensity,
            shore_width: g.shore_width,
            detail_weight: g.detail_weight,
            shader_id: g.ids as u8,
            foam_texture: g.foam_texture as u16,
            algae_texture: g.algae_texture as u16,
        }
    }
}

/// One entry of the material structure buffer (WGSL `WaterMaterialGpu`, 64 bytes).
#[derive(Clone, Copy, Debug, PartialEq, Default, Pod, Zeroable)]
#[repr(C)]
pub struct WaterMaterialGpu {
    /// `sigma_a` (1/m) in xyz, roughness in w.
    pub absorption: [f32; 4],
    /// `sigma_s` (1/m) in xyz, roughness cap in w.
    pub scattering: [f32; 4],
    /// Metres.
    pub displacement_amplitude: f32,
    /// Foam intensity.
    pub foam_intensity: f32,
    /// Metres.
    pub shore_width: f32,
    /// Detail normal weight.
    pub detail_weight: f32,
    /// Shader ID in the low 8 bits.
    pub ids: u32,
    /// Foam texture array index.
    pub foam_texture: u32,
    /// Algae texture array index.
    pub algae_texture: u32,
    /// Padding to 64 bytes.
    pub _pad: u32,
}
const _: () = assert!(size_of::<WaterMaterialGpu>() == 64);

/// Weight of the *other* material at a pixel `signed_distance` metres from the boundary
/// between the bodies (positive inside the pixel's own body): `saturate(0.5 -
/// signed_distance / blend_distance)`. 0.5 on the boundary, 0 from `blend_distance / 2`
/// inside; seen from the other body the weights are complementary, so the blend is
/// continuous across the boundary. A non-positive `blend_distance` gives a hard switch.
#[must_use]
pub fn blend_weight(signed_distance: f32, blend_distance: f32) -> f32 {
    if !(blend_distance > 0.0) {
        return if signed_distance < 0.0 { 1.0 } else { 0.0 };
    }
    math::saturate(0.5 - signed_distance / blend_distance)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blend_is_continuous_across_the_boundary() {
        let a = WaterMaterial::from_type(&WaterType::RIVER);
        let mut b = WaterMaterial::from_type(&WaterType::MUDDY);
        b.shader_id = 3;
        b.roughness = 0.3;
        // Walk across the boundary: from a's side the pixel blends toward b, from b's side
        // toward a; both views agree at each point.
        for i in -40..=40 {
            let s = i as f32 * 0.1; // signed distance inside a
            let seen_from_a = a.blend(&b, blend_weight(s, DEFAULT_BLEND_DISTANCE));
            let seen_from_b = b.blend(&a, blend_weight(-s, DEFAULT_BLEND_DISTANCE));
            assert!((seen_from_a.roughness - seen_from_b.roughness).abs() < 1e-6);
            assert!(
                (seen_from_a.medium.absorption - seen_from_b.medium.absorption).length() < 1e-5
            );
        }
        assert_eq!(blend_weight(3.0, 6.0), 0.0);
        assert_eq!(blend_weight(-3.0, 6.0), 1.0);
        assert_eq!(a.blend(&b, 0.2).shader_id, 0);
        assert_eq!(a.blend(&b, 0.7).shader_id, 3);
        assert_eq!(blend_weight(1.0, 0.0), 0.0);
    }

    #[test]
    fn gpu_record_roundtrips() {
        let mut m = WaterMaterial::from_type(&WaterType::SULFUR_POND);
        m.shader_id = 9;
        m.foam_texture = 300;
        m.algae_texture = 7;
        assert_eq!(WaterMaterial::from_gpu(&m.to_gpu()), m);
    }
}
