//! Shadow-casting spot lights (KZ2's shadowed local lights): each frame the spots that
//! cast shadows ([`SpotLight::shadow`](crate::SpotLight::shadow)) and still cover enough of
//! the screen after KZ2's fade ([`deferred::lights::ShadowFade`]) get one layer of a depth
//! array, largest on screen first, up to [`SpotShadowConfig::maps`]; the rest light
//! unshadowed (KZ2: the cheaper non-shadow shader once faded). Each map is a perspective
//! view from the light down its axis, drawn by the depth-prepass geometry (the casters
//! whose instance chunks meet its clip volume, as for the sun's slices), and lighting
//! (tiled and volume paths alike) filters it with a 3x3 PCF, blended towards lit by the
//! fade.
//!
//! Conventions: map depth in `[0, 1]`, 0 at the light's near plane (cleared to 1, tested
//! `Less`), as the sun's maps; the renderer keeps a light's map slot in its
//! [`DeferredLight::flags`](deferred::DeferredLight::flags) bits 8-15 (slot + 1; 0: no
//! map), [`LIGHT_SHADOW_SLOT_SHIFT`].

use bytemuck::{Pod, Zeroable};
use deferred::DeferredLight;
use deferred::lights::ShadowFade;
use glam::{Mat4, Vec3};

use shader::{Binding, Dim, Kind, Sample};

use crate::error::{Error, Result};

/// The maps as lighting and the light volumes bind them.
pub(crate) const MAP_BINDING: Binding = Binding::new(
    "spot_shadow_map",
    Kind::Texture {
        sample: Sample::Depth,
        dim: Dim::D2Array,
    },
);
/// The maps' rows (`GpuSpotShadow`) as lighting and the light volumes bind them.
pub(crate) const ROWS_BINDING: Binding =
    Binding::new("spot_shadows", Kind::read(size_of::<GpuSpotShadow>()));

/// Bit position of the shadow-map slot (+ 1) in a light row's flags (WGSL
/// `GPU_LIGHT_SHADOW_SLOT_SHIFT`).
pub(crate) const LIGHT_SHADOW_SLOT_SHIFT: u32 = 8;
/// The most spot shadow maps a frame may have.
pub const MAX_SPOT_SHADOW_MAPS: u32 = 16;

/// Shadow maps for the spot lights that cast shadows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpotShadowConfig {
    /// Maps per frame, 1 to [`MAX_SPOT_SHADOW_MAPS`]: the shadowed spots largest on screen
    /// get them; the others light unshadowed.
    pub maps: u32,
    /// Texels per side of each map, 64 to 4096.
    pub resolution: u32,
    /// KZ2's shadow fade by screen coverage: full strength from `fade.full`, none (and no
    /// map) at `fade.zero` and below.
    pub fade: ShadowFade,
}

impl Default for SpotShadowConfig {
    fn default() -> Self {
        Self {
            maps: 4,
            resolution: 512,
            fade: ShadowFade::default(),
        }
    }
}

impl SpotShadowConfig {
    /// Checks the ranges above.
    ///
    /// # Errors
    /// [`Error::Config`] naming the field.
    pub fn validate(&self) -> Result<()> {
        let bad = Error::config;
        if !(1..=MAX_SPOT_SHADOW_MAPS).contains(&self.maps) {
            return bad("SpotShadowConfig::maps", f64::from(self.maps), "1 to 16");
        }
        if !(64..=4096).contains(&self.resolution) {
            return bad(
                "SpotShadowConfig::resolution",
                f64::from(self.resolution),
                "64 to 4096 texels",
            );
        }
        let f = self.fade;
        if !(f.zero.is_finite() && f.full.is_finite() && f.zero >= 0.0 && f.full >= f.zero) {
            return bad(
                "SpotShadowConfig::fade",
                f64::from(f.full),
                "finite coverages, 0 <= zero <= full",
            );
        }
        Ok(())
    }
}

/// What lighting reads of one spot shadow map (WGSL `GpuSpotShadow`), 80 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct GpuSpotShadow {
    /// View space to the map's clip space (depth 0 at the light's near plane).
    pub view_to_clip: [[f32; 4]; 4],
    /// Shadow strength after KZ2's fade, `(0, 1]`.
    pub strength: f32,
    /// World size of a texel per metre of distance from the light (the normal offset
    /// grows with it).
    pub texel_per_metre: f32,
    /// Texels per side of the map.
    pub resolution: u32,
    /// Zero.
    pub pad: u32,
}
const _: () = assert!(size_of::<GpuSpotShadow>() == 80);

/// One map of this frame: its light (the row, slot included) and its matrix.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SpotShadow {
    /// The light's row, its slot in the flags.
    pub light: DeferredLight,
    /// View space to the map's clip space.
    pub view_to_clip: Mat4,
    /// Fade strength.
    pub strength: f32,
}

/// The spot's perspective view: from its (view-space) position down its axis, the cone's
/// full angle plus a texel's margin, from 1% of its range (at least 5 cm) to its range.
pub(crate) fn spot_view_to_clip(light: &DeferredLight, resolution: u32) -> Mat4 {
    let p = Vec3::from(light.position);
    let d = Vec3::from(light.direction).normalize_or(Vec3::NEG_Z);
    let up = if d.y.abs() < 0.99 { Vec3::Y } else { Vec3::X };
    let half = light.cos_outer.clamp(1e-3, 1.0).acos();
    // A texel's worth of margin so the PCF's taps at the cone's edge stay on the map.
    let fov = (2.0 * half * (1.0 + 2.0 / resolution as f32)).min(3.0);
    let near = (light.range * 0.01).max(0.05);
    Mat4::perspective_rh(fov, 1.0, near, light.range.max(near * 2.0)) * Mat4::look_to_rh(p, d, up)
}

/// Picks this frame's maps: the shadow-casting spots of `rows` (view space) whose fade
/// `strength(i)` is above 0, largest `coverage(i)` first, at most `config.maps`; writes
/// each one's slot into its row's flags and returns the maps in slot order.
pub(crate) fn assign_maps(
    rows: &mut [DeferredLight],
    config: &SpotShadowConfig,
    mut coverage_and_strength: impl FnMut(&DeferredLight) -> (f32, f32),
) -> Vec<SpotShadow> {
    let mut candidates: Vec<(usize, f32, f32)> = rows
        .iter()
        .enumerate()
        .filter(|(_, l)| l.is_spot() && l.casts_shadow())
        .map(|(i, l)| {
            let (c, s) = coverage_and_strength(l);
            (i, c, s)
        })
        .filter(|&(_, _, s)| s > 0.0)
        .collect();
    candidates.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    candidates
        .into_iter()
        .take(config.maps as usize)
        .enumerate()
        .map(|(slot, (i, _, strength))| {
            let row = &mut rows[i];
            row.flags |= (slot as u32 + 1) << LIGHT_SHADOW_SLOT_SHIFT;
            SpotShadow {
                light: *row,
                view_to_clip: spot_view_to_clip(row, config.resolution),
                strength,
            }
        })
        .collect()
}

impl GpuSpotShadow {
    /// The row of `map` at `resolution` texels.
    pub(crate) fn new(map: &SpotShadow, resolution: u32) -> Self {
        let half = map.light.cos_outer.clamp(1e-3, 1.0).acos();
        Self {
            view_to_clip: map.view_to_clip.to_cols_array_2d(),
            strength: map.strength,
            texel_per_metre: 2.0 * half.tan().min(1e3) / resolution as f32,
            resolution,
            ..Self::default()
        }
    }
}

/// The spot maps of one renderer: a depth array of [`SpotShadowConfig::maps`] layers (one
/// 1x1 layer without spot shadows), its views, the per-map frame uniforms the shadow
/// passes draw with, and the rows lighting reads.
pub(crate) struct SpotShadowMaps {
    pub config: Option<SpotShadowConfig>,
    /// The depth array (read back by tests).
    pub texture: wgpu::Texture,
    /// One view per layer (render attachments).
    pub layer_views: Vec<wgpu::TextureView>,
    /// The whole array (lighting samples it).
    pub array_view: wgpu::TextureView,
    /// `FrameUniforms` per map at [`crate::shadows::CASCADE_FRAME_STRIDE`].
    pub frames: wgpu::Buffer,
    /// `GpuSpotShadow` per map.
    pub rows: wgpu::Buffer,
    /// Maps this frame renders (the first `active` layers).
    pub active: u32,
}

impl SpotShadowMaps {
    pub(crate) fn new(device: &wgpu::Device, config: Option<SpotShadowConfig>) -> Self {
        let (size, layers) = config.map_or((1, 1), |c| (c.resolution, c.maps));
        let texture = crate::shadows::depth_texture(device, "spot shadow maps", size, layers);
        let (layer_views, array_view) = crate::shadows::layer_views(&texture, layers);
        let frames = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("spot shadow frames"),
            size: crate::shadows::CASCADE_FRAME_STRIDE * u64::from(layers),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let rows = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("spot shadow rows"),
            size: size_of::<GpuSpotShadow>() as u64 * u64::from(layers),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self {
            config,
            texture,
            layer_views,
            array_view,
            frames,
            rows,
            active: 0,
        }
    }

    /// The two bindings ([`MAP_BINDING`], [`ROWS_BINDING`]) over these maps.
    pub(crate) fn resources(&self) -> [(&'static str, wgpu::BindingResource<'_>); 2] {
        [
            (
                MAP_BINDING.name,
                wgpu::BindingResource::TextureView(&self.array_view),
            ),
            (ROWS_BINDING.name, self.rows.as_entire_binding()),
        ]
    }

    /// Layers (maps a frame may render).
    pub(crate) fn layers(&self) -> u32 {
        self.config.map_or(0, |c| c.maps)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The largest shadowed spots get the maps, in order of coverage; faded-out ones and
    /// point lights none; each chosen row carries its slot.
    #[test]
    fn maps_go_to_the_largest_shadowed_spots() {
        let spot = |range: f32| {
            DeferredLight::spot(
                Vec3::new(0.0, 0.0, -5.0),
                Vec3::NEG_Z,
                range,
                0.5,
                Vec3::ONE,
            )
            .with_shadow()
        };
        let mut rows = vec![
            spot(1.0),
            DeferredLight::point(Vec3::ZERO, 9.0, Vec3::ONE).with_shadow(),
            spot(3.0),
            spot(0.1),
            spot(2.0),
            DeferredLight::spot(Vec3::ZERO, Vec3::NEG_Z, 8.0, 0.5, Vec3::ONE),
        ];
        let config = SpotShadowConfig {
            maps: 2,
            ..SpotShadowConfig::default()
        };
        // Coverage: the range; strength 0 below 0.5.
        let maps = assign_maps(&mut rows, &config, |l| {
            (l.range, if l.range < 0.5 { 0.0 } else { 1.0 })
        });
        assert_eq!(maps.len(), 2);
        let slot = |l: &DeferredLight| l.flags >> LIGHT_SHADOW_SLOT_SHIFT;
        assert_eq!(
            rows.iter().map(slot).collect::<Vec<_>>(),
            [0, 0, 1, 0, 2, 0]
        );
        // The map looks down the spot's axis: its apex-side points land inside the map.
        let ahead = maps[0].view_to_clip * Vec3::new(0.0, 0.0, -6.0).extend(1.0);
        let ndc = ahead.truncate() / ahead.w;
        assert!(ndc.x.abs() < 1e-4 && ndc.y.abs() < 1e-4 && (0.0..1.0).contains(&ndc.z));
    }

    #[test]
    fn validation_names_the_field() {
        assert!(SpotShadowConfig::default().validate().is_ok());
        for (bad, field) in [
            (
                SpotShadowConfig {
                    maps: 0,
                    ..SpotShadowConfig::default()
                },
                "maps",
            ),
            (
                SpotShadowConfig {
                    resolution: 8,
                    ..SpotShadowConfig::default()
                },
                "resolution",
            ),
        ] {
            let e = bad.validate().unwrap_err().to_string();
            assert!(e.contains(field), "{e}");
        }
    }
}
