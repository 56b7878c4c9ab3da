//! Light transport in water from absorption and scattering coefficients.
//!
//! Far Cry 5 replaced artist-picked water colours with physical coefficients: "a table of
//! water types that the artists can pick from, or they can create their own ... RGB
//! scattering coefficients with a turbidity value" (seed 003). Here a [`WaterType`] is the
//! particulate absorption and scattering per unit turbidity plus a turbidity; pure water's
//! own coefficients are always added:
//!
//! - `sigma_a = PURE_WATER_ABSORPTION + turbidity * particle_absorption` (1/m, per channel)
//! - `sigma_s = PURE_WATER_SCATTERING + turbidity * particle_scattering` (1/m)
//! - `sigma_t = sigma_a + sigma_s`
//!
//! and light along a path of length `d` metres obeys Beer–Lambert, with single scattering
//! of a uniform in-scattered radiance `L_in`:
//!
//! - transmittance `T = exp(-sigma_t d)` ([`transmittance`])
//! - `L = L_bed T + L_in (sigma_s / sigma_t) (1 - T)` ([`Medium::light_transport`]),
//!   the closed form of `integral_0^d sigma_s L_in exp(-sigma_t s) ds`.
//!
//! Channels are red, green, blue at 650, 510 and 475 nm. Pure water absorption is Pope and
//! Fry (1997): 0.34, 0.0325 and 0.0114 per metre. Pure water scattering is Morel's (1974)
//! `0.00288 (lambda / 500 nm)^-4.32` per metre. Particle scattering in the table follows the
//! case-1 relation `b_p(550) = 0.416 Chl^0.766` (Loisel and Morel 1998) with a
//! `(550 / lambda)` spectrum for the ocean; the river, mud and sulfur entries are
//! illustrative choices of the same form, not measurements.

use glam::Vec3;

use crate::math;

/// Pure water absorption (1/m) at 650, 510, 475 nm (Pope and Fry 1997).
pub const PURE_WATER_ABSORPTION: Vec3 = Vec3::new(0.34, 0.0325, 0.0114);
/// Pure water scattering (1/m) at 650, 510, 475 nm (Morel 1974).
pub const PURE_WATER_SCATTERING: Vec3 = Vec3::new(0.000_927, 0.002_64, 0.003_60);

/// A water type: what an artist picks from the table or makes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WaterType {
    /// Name for tools.
    pub name: &'static str,
    /// Absorption (1/m) of the dissolved and suspended matter per unit turbidity, RGB.
    pub particle_absorption: Vec3,
    /// Scattering (1/m) of the suspended matter per unit turbidity, RGB.
    pub particle_scattering: Vec3,
    /// How much matter: multiplies both particle coefficients (0 = pure water).
    pub turbidity: f32,
}

/// Chlorophyll concentration (mg/m^3) behind the clear-ocean entry.
pub const OCEAN_CHLOROPHYLL: f32 = 0.05;

impl WaterType {
    /// Pure water.
    pub const PURE: WaterType = WaterType {
        name: "pure water",
        particle_absorption: Vec3::ZERO,
        particle_scattering: Vec3::ZERO,
        turbidity: 0.0,
    };
    /// Clear open ocean (case-1 water, 0.05 mg/m^3 chlorophyll): `b_p(550) = 0.416 *
    /// 0.05^0.766 = 0.042` per metre, times `550 / lambda`; phytoplankton absorption
    /// peaks in the blue.
    pub const CLEAR_OCEAN: WaterType = WaterType {
        name: "clear ocean",
        particle_absorption: Vec3::new(0.003, 0.004, 0.012),
        particle_scattering: Vec3::new(0.0355, 0.0452, 0.0485),
        turbidity: 1.0,
    };
    /// A clear mountain river: little sediment, some dissolved organic matter (absorbs
    /// blue).
    pub const RIVER: WaterType = WaterType {
        name: "river",
        particle_absorption: Vec3::new(0.02, 0.06, 0.15),
        particle_scattering: Vec3::new(0.25, 0.28, 0.30),
        turbidity: 1.0,
    };
    /// Muddy water: heavy sediment, brown.
    pub const MUDDY: WaterType = WaterType {
        name: "muddy",
        particle_absorption: Vec3::new(0.6, 0.9, 1.4),
        particle_scattering: Vec3::new(4.0, 3.8, 3.6),
        turbidity: 1.0,
    };
    /// A sulfur pond: colloidal sulfur scatters strongly and absorbs little, a milky
    /// turquoise.
    pub const SULFUR_POND: WaterType = WaterType {
        name: "sulfur pond",
        particle_absorption: Vec3::new(0.25, 0.02, 0.04),
        particle_scattering: Vec3::new(1.6, 2.0, 2.1),
        turbidity: 1.0,
    };

    /// The table, in the talk's order plus pure water.
    pub const TABLE: [WaterType; 5] = [
        WaterType::CLEAR_OCEAN,
        WaterType::RIVER,
        WaterType::MUDDY,
        WaterType::SULFUR_POND,
        WaterType::PURE,
    ];

    /// The same type with another turbidity.
    #[must_use]
    pub const fn with_turbidity(self, turbidity: f32) -> WaterType {
        WaterType { turbidity, ..self }
    }

    /// The total coefficients (pure water added, turbidity applied).
    #[must_use]
    pub fn medium(&self) -> Medium {
        Medium::new(
            PURE_WATER_ABSORPTION + self.particle_absorption * self.turbidity,
            PURE_WATER_SCATTERING + self.particle_scattering * self.turbidity,
        )
    }
}

/// Case-1 particle scattering at 550 nm, `0.416 Chl^0.766` per metre, for a chlorophyll
/// concentration in mg/m^3 (Loisel and Morel 1998).
#[must_use]
pub fn particle_scattering_550(chlorophyll: f32) -> f32 {
    0.416 * math::pow(chlorophyll.max(0.0), 0.766)
}

/// Total absorption and scattering coefficients of a medium (1/m, RGB).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Medium {
    /// `sigma_a`.
    pub absorption: Vec3,
    /// `sigma_s`.
    pub scattering: Vec3,
}

impl Medium {
    /// A medium from total coefficients (negative values are clamped to 0).
    #[must_use]
    pub fn new(absorption: Vec3, scattering: Vec3) -> Self {
        Self {
            absorption: absorption.max(Vec3::ZERO),
            scattering: scattering.max(Vec3::ZERO),
        }
    }

    /// `sigma_t = sigma_a + sigma_s`.
    #[must_use]
    pub fn extinction(&self) -> Vec3 {
        self.absorption + self.scattering
    }

    /// Single-scattering albedo `sigma_s / sigma_t` (0 where `sigma_t` is 0).
    #[must_use]
    pub fn albedo(&self) -> Vec3 {
        let t = self.extinction();
        Vec3::new(
            ratio(self.scattering.x, t.x),
            ratio(self.scattering.y, t.y),
            ratio(self.scattering.z, t.z),
        )
    }

    /// Transmittance over `distance` metres.
    #[must_use]
    pub fn transmittance(&self, distance: f32) -> Vec3 {
        transmittance(self.extinction(), distance)
    }

    /// Radiance in-scattered along `distance` metres when every point of the path receives
    /// radiance `light` (single scattering, isotropic phase folded into `light`):
    /// `light (sigma_s / sigma_t) (1 - T)`.
    #[must_use]
    pub fn in_scatter(&self, light: Vec3, distance: f32) -> Vec3 {
        light * self.albedo() * (Vec3::ONE - self.transmittance(distance))
    }

    /// What the camera sees through `distance` metres of water in front of a bed (or
    /// refracted scene) of radiance `bed`: `bed T + in_scatter`.
    #[must_use]
    pub fn light_transport(&self, bed: Vec3, light: Vec3, distance: f32) -> Vec3 {
        bed * self.transmittance(distance) + self.in_scatter(light, distance)
    }

    /// The colour deep water converges to (`distance -> inf`): `light * albedo`.
    #[must_use]
    pub fn deep_color(&self, light: Vec3) -> Vec3 {
        light * self.albedo()
    }
}

fn ratio(a: f32, b: f32) -> f32 {
    if b > 0.0 { a / b } else { 0.0 }
}

/// Beer–Lambert: `exp(-sigma_t * distance)` per channel. Negative or NaN distances count
/// as 0 (transmittance 1).
#[must_use]
pub fn transmittance(extinction: Vec3, distance: f32) -> Vec3 {
    let d = if distance > 0.0 { distance } else { 0.0 };
    Vec3::new(
        math::exp(-extinction.x * d),
        math::exp(-extinction.y * d),
        math::exp(-extinction.z * d),
    )
}

/// The GPU form of a medium: `vec4`s with the coefficients in `xyz` (w unused), as the
/// material structure buffer stores them. WGSL: `WaterMedium`.
#[derive(Clone, Copy, Debug, PartialEq, Default, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
pub struct WaterMedium {
    /// `sigma_a` in xyz.
    pub absorption: [f32; 4],
    /// `sigma_s` in xyz.
    pub scattering: [f32; 4],
}
const _: () = assert!(size_of::<WaterMedium>() == 32);

impl From<Medium> for WaterMedium {
    fn from(m: Medium) -> Self {
        Self {
            absorption: m.absorption.extend(0.0).to_array(),
            scattering: m.scattering.extend(0.0).to_array(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pure_water_red_loses_29_percent_per_metre() {
        let t = WaterType::PURE.medium().transmittance(1.0);
        assert!((f64::from(t.x) - (-0.340_927f64).exp()).abs() < 1e-6);
        assert!(t.z > t.y && t.y > t.x, "blue travels furthest");
    }

    #[test]
    fn ocean_scattering_follows_the_chlorophyll_relation() {
        let b = particle_scattering_550(OCEAN_CHLOROPHYLL);
        assert!((b - 0.0421).abs() < 1e-3, "{b}");
        // 550 / lambda spectrum at 650, 510, 475 nm.
        let s = WaterType::CLEAR_OCEAN.particle_scattering;
        for (got, l) in [(s.x, 650.0), (s.y, 510.0), (s.z, 475.0)] {
            assert!((got - b * 550.0 / l).abs() < 1e-3, "{got} at {l}");
        }
    }
}
