//! The water scene the renderer draws Far Cry 5's water from (seed 003): the baked
//! [`WaterWorld`] with its materials, noise, flow atlas, shore field and decal textures
//! ([`WaterScene`]), how to draw it ([`WaterOptions`]), the per-frame displacement decals
//! ([`WaterDecal`]), and the limits every water scene is checked against: a scene over one
//! is a [`WaterError::Limit`] naming it, never a panic.

use glam::{Affine3A, Vec2};
use water::atlas::FlowAtlas;
use water::decal::DecalTexture;
use water::edt::DistanceField;
use water::flow::FlowParams;
use water::foam::FoamParams;
use water::material::WaterMaterial;
use water::noise::{FbmParams, NoiseTexture};
use water::normals::RadiusRule;
use water::world::{BodyBounds, WaterWorld};

use crate::error::WaterError;

// The limits of what the renderer draws a world from live beside the code that builds it
// (`water::draw`); re-exported so that every water limit is named from here.
pub use water::draw::{
    MAX_WATER_BODIES, MAX_WATER_BODY_CELLS, MAX_WATER_MATERIAL_MAP, MAX_WATER_MATERIALS,
    MAX_WATER_MESH_VERTICES, MAX_WATER_SECTORS_PER_SIDE, WATER_NO_MATERIAL,
};
/// Most displacement decals in a frame.
pub const MAX_WATER_DECALS: u32 = 256;
/// Most decal texture frames (layers of the decal texture array).
pub const MAX_WATER_DECAL_LAYERS: u32 = 256;
/// Largest decal texture side, texels.
pub const MAX_WATER_DECAL_SIZE: u32 = 512;

/// How the renderer draws the water. Defaults: a mini G-buffer at half the image's
/// resolution with a 15% wider field of view, near bodies within 400 m, 64 m far sectors
/// over a 4 km ocean, half precision where the device has it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WaterOptions {
    /// The mini G-buffer's size over the image's, per axis (the talk: a 512 x 512 buffer
    /// upsampled to the viewport), in `[0.125, 1]`.
    pub resolution_scale: f32,
    /// `tan` of the water view's half field of view over the camera's, in `[1, 2]`: the
    /// margin that keeps displaced water from leaving gaps at the image's edges.
    pub fov_scale: f32,
    /// Bodies nearer than this (metres) draw their own meshes; beyond it water (and the
    /// ocean everywhere) draws through the far sectors.
    pub near_radius: f32,
    /// Side of a far sector, metres.
    pub sector_size: f32,
    /// Side of the square the far sectors cover around the world's centre when the world
    /// has an ocean, metres (without one they cover the bodies).
    pub ocean_extent: f32,
    /// Quads per far sector side, `1..=64`.
    pub far_quads: u32,
    /// Cell of the near bodies' meshes, metres (grown for a body that would need more than
    /// [`MAX_WATER_BODY_CELLS`]).
    pub near_cell: f32,
    /// Use `f16` in the composite where the device has `SHADER_F16`.
    pub half_precision: bool,
    /// Distance over which two bodies' materials blend, metres (the talk: 6).
    pub blend_distance: f32,
    /// Refraction strength: metres the refracted point moves per unit of normal tilt.
    pub refraction: f32,
    /// Screen-space reflections of the opaque scene (else the sky alone).
    pub ssr: bool,
    /// Largest height decals may add (metres): with the FBM's bound, the margin of every
    /// visibility test and the clamp of the displacement.
    pub decal_height: f32,
    /// Foam noise frequency, periods of the noise texture per metre.
    pub foam_frequency: f32,
    /// The flow-map phases.
    pub flow: FlowParams,
    /// Foam (a material's shore width and intensity replace these two fields).
    pub foam: FoamParams,
    /// The normals' sampling radius.
    pub normal_radius: RadiusRule,
}

impl Default for WaterOptions {
    fn default() -> Self {
        Self {
            resolution_scale: 0.5,
            fov_scale: 1.15,
            near_radius: 400.0,
            sector_size: 64.0,
            ocean_extent: 4096.0,
            far_quads: 16,
            near_cell: 2.0,
            half_precision: true,
            blend_distance: water::material::DEFAULT_BLEND_DISTANCE,
            refraction: 0.15,
            ssr: true,
            decal_height: 2.0,
            foam_frequency: 1.0 / 12.0,
            flow: FlowParams::default(),
            // Rapids foam from 3 m/s, full at 8 m/s.
            foam: FoamParams {
                speed_start: 3.0,
                speed_full: 8.0,
                ..FoamParams::default()
            },
            normal_radius: RadiusRule {
                radius_at_1m: 6.0,
                max_radius: 6,
            },
        }
    }
}

/// The shore's signed distance field for foam: an `edt` field (texels, positive in
/// water) over a grid of `texel_size`-metre texels whose corner is at `origin` (water
/// coordinates, +Z up: horizontal `(x, y)`).
#[derive(Clone, Debug, PartialEq)]
pub struct ShoreField {
    /// The distance field.
    pub field: DistanceField,
    /// Texel (0, 0)'s outer corner, water coordinates (metres).
    pub origin: Vec2,
    /// Metres per texel.
    pub texel_size: f32,
}

/// Everything the renderer draws water from. Coordinates inside are the `water` crate's
/// (+Z up); the renderer converts (`water::axes`).
#[derive(Clone, Debug)]
pub struct WaterScene {
    /// The baked world: the same words the CPU query reads.
    pub world: WaterWorld,
    /// The material structure buffer, indexed by the world's material indices.
    pub materials: Vec<WaterMaterial>,
    /// FBM parameters; a material's `displacement_amplitude` multiplies the height.
    pub fbm: FbmParams,
    /// The noise texture the FBM and the foam sample.
    pub noise: NoiseTexture,
    /// The world flow map and its tiles, for foam (`None`: still water).
    pub flow: Option<FlowAtlas>,
    /// The shore distance field, for foam (`None`: no shore foam).
    pub shore: Option<ShoreField>,
    /// Displacement decal textures ([`WaterDecal::texture`] indexes them).
    pub decal_textures: Vec<DecalTexture>,
    /// How to draw it.
    pub options: WaterOptions,
}

impl WaterScene {
    /// A scene of `world` and `materials` with the default FBM (unit amplitude, so the
    /// materials' amplitudes are metres), the default noise texture and options, no flow
    /// atlas, shore field or decals.
    #[must_use]
    pub fn new(world: WaterWorld, materials: Vec<WaterMaterial>) -> Self {
        Self {
            world,
            materials,
            fbm: FbmParams {
                amplitude: 1.0,
                ..FbmParams::default()
            },
            noise: NoiseTexture::default_water(),
            flow: None,
            shore: None,
            decal_textures: Vec::new(),
            options: WaterOptions::default(),
        }
    }
}

/// One displacement decal of a frame: a projected box pushing the water surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WaterDecal {
    /// The unit box `[-1, 1]^3` to world, water coordinates (+Z up).
    pub box_to_world: Affine3A,
    /// Index into [`WaterScene::decal_textures`].
    pub texture: u32,
    /// Multiplies the displacement.
    pub strength: f32,
    /// Animation position, frames.
    pub frame: f32,
    /// Edge fade width, box-local units in `(0, 1]`.
    pub fade: f32,
}

/// The limit error for `what`.
pub(crate) fn limit(
    what: &'static str,
    value: u64,
    limit: u64,
    limit_name: &'static str,
) -> WaterError {
    WaterError::Limit {
        what,
        value,
        limit,
        limit_name,
    }
}

fn range(field: &'static str, value: f32, lo: f32, hi: f32) -> Result<(), WaterError> {
    if value >= lo && value <= hi {
        Ok(())
    } else {
        Err(WaterError::Water(water::Error::OutOfRange {
            field,
            value,
            min: lo,
            max: hi,
        }))
    }
}

impl WaterOptions {
    /// Checks every option's range.
    ///
    /// # Errors
    /// [`WaterError::Water`] with `water::Error::OutOfRange` naming the field
    /// (`WaterOptions::fov_scale`) and its range.
    pub fn validate(&self) -> Result<(), WaterError> {
        let o = self;
        range(
            "WaterOptions::resolution_scale",
            o.resolution_scale,
            0.125,
            1.0,
        )?;
        range("WaterOptions::fov_scale", o.fov_scale, 1.0, 2.0)?;
        range("WaterOptions::near_radius", o.near_radius, 0.0, 1.0e6)?;
        range("WaterOptions::sector_size", o.sector_size, 1.0, 1.0e5)?;
        range("WaterOptions::ocean_extent", o.ocean_extent, 1.0, 1.0e6)?;
        range("WaterOptions::far_quads", o.far_quads as f32, 1.0, 64.0)?;
        range("WaterOptions::near_cell", o.near_cell, 0.25, 1.0e4)?;
        range("WaterOptions::blend_distance", o.blend_distance, 0.0, 1.0e3)?;
        range("WaterOptions::refraction", o.refraction, 0.0, 10.0)?;
        range("WaterOptions::decal_height", o.decal_height, 0.0, 1.0e3)?;
        range(
            "WaterOptions::foam_frequency",
            o.foam_frequency,
            1.0e-6,
            1.0e3,
        )?;
        range(
            "WaterOptions::flow.interval",
            o.flow.interval,
            1.0e-3,
            1.0e6,
        )?;
        range("WaterOptions::flow.distance", o.flow.distance, 0.0, 1.0e3)?;
        range(
            "WaterOptions::flow.noise_strength",
            o.flow.noise_strength,
            0.0,
            1.0e3,
        )?;
        range(
            "WaterOptions::normal_radius.radius_at_1m",
            o.normal_radius.radius_at_1m,
            0.0,
            1.0e3,
        )?;
        range(
            "WaterOptions::normal_radius.max_radius",
            o.normal_radius.max_radius as f32,
            1.0,
            16.0,
        )?;
        let f = &o.foam;
        for (field, v) in [
            ("WaterOptions::foam.speed_start", f.speed_start),
            ("WaterOptions::foam.speed_full", f.speed_full),
            ("WaterOptions::foam.shallow_depth", f.shallow_depth),
            ("WaterOptions::foam.softness", f.softness),
            ("WaterOptions::foam.mask_bias", f.mask_bias),
        ] {
            range(field, v, -1.0e3, 1.0e3)?;
        }
        Ok(())
    }
}

impl WaterScene {
    /// Checks the materials: a count within [`MAX_WATER_MATERIALS`], finite fields, and
    /// every material the world names present. `bodies` are the world's
    /// ([`WaterWorld::bodies`]), given so a caller that needs them too finds them once.
    ///
    /// # Errors
    /// [`WaterError::Limit`] for a count or an index over its limit, [`WaterError::Water`]
    /// for no material or a non-finite one.
    pub fn check_materials(&self, bodies: &[BodyBounds]) -> Result<(), WaterError> {
        let scene = self;
        let n = scene.materials.len();
        if n == 0 {
            return Err(WaterError::Water(water::Error::InvalidSize {
                field: "water materials",
                value: 0,
                rule: "at least one",
            }));
        }
        if n as u64 > u64::from(MAX_WATER_MATERIALS) {
            return Err(limit(
                "water materials",
                n as u64,
                u64::from(MAX_WATER_MATERIALS),
                "MAX_WATER_MATERIALS",
            ));
        }
        for m in &scene.materials {
            let g = m.to_gpu();
            let finite = g
                .absorption
                .iter()
                .chain(&g.scattering)
                .all(|v| v.is_finite())
                && [
                    g.displacement_amplitude,
                    g.foam_intensity,
                    g.shore_width,
                    g.detail_weight,
                ]
                .iter()
                .all(|v| v.is_finite() && v.abs() < 1.0e4);
            if !finite {
                return Err(WaterError::Water(water::Error::NonFinite {
                    field: "water material",
                }));
            }
        }
        let named = bodies
            .iter()
            .map(|b| b.material)
            .chain(scene.world.ocean().map(|o| o.material));
        for m in named {
            if m as usize >= n {
                return Err(limit(
                    "a material index the water world names",
                    u64::from(m),
                    n as u64 - 1,
                    "WaterScene::materials.len() - 1",
                ));
            }
        }
        Ok(())
    }

    /// The largest height (metres) the FBM can reach (texels in [-1, 1]) times the largest
    /// material amplitude, plus the decals' allowance: every margin and clamp of the
    /// renderer's water passes.
    #[must_use]
    pub fn max_displacement(&self) -> f32 {
        let scene = self;
        let fbm = &scene.fbm;
        let mut a = fbm.amplitude.abs();
        let mut sum = 0.0;
        for _ in 0..fbm.octaves_near.min(water::noise::MAX_OCTAVES) {
            sum += a;
            a *= fbm.gain;
        }
        let amp = scene
            .materials
            .iter()
            .map(|m| m.displacement_amplitude.abs())
            .fold(0.0f32, f32::max);
        sum * amp + scene.options.decal_height
    }
}
