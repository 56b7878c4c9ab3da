//! Stable cascaded shadow maps for the sun (KZ2's depth slices, "Align shadow maps to
//! world instead of view": Valient, ShaderX6).
//!
//! The view's shadowed depth range is cut into slices by the practical split scheme
//! ([`practical_splits`]: a blend of logarithmic and uniform splits, Zhang et al. 2006).
//! Each slice gets one shadow map:
//!
//! 1. **Rotation-invariant size.** The map covers the slice's bounding sphere
//!    ([`slice_bounding_sphere`]), whose radius depends only on the slice's distances and
//!    the field of view, never on where the camera looks. The radius is padded by half a
//!    texel (so the snapped map still holds the whole sphere) and rounded up to
//!    [`CascadeParams::radius_step`].
//! 2. **Whole-texel movement.** The light-space projection is an orthographic box around
//!    the sphere's centre, with the centre snapped to whole shadow texels on a grid
//!    anchored at a fixed world point ([`CascadeParams::anchor`]); its depth is snapped to
//!    [`CascadeParams::depth_step`]. A static scene therefore renders to the same texels
//!    every frame unless the camera moves by a texel or more, and then the map moves by
//!    whole texels: no shimmering.
//! 3. **f64.** Everything is computed in f64 around the anchor, and the matrix handed to
//!    the GPU ([`Cascade::gpu`]) maps *camera-relative* positions, so world coordinates far
//!    from the origin cost no f32 precision.
//!
//! # Conventions
//!
//! World space is right-handed, `+y` up, metres. `to_light` is the unit direction towards
//! the sun (as the `gpu` crate's `sun_direction`). Shadow clip space is wgpu's: `x`, `y` in
//! `[-1, 1]` (`+y` up: texture `v = 0.5 - 0.5 y`), depth in `[0, 1]`, 0 nearest the light.

use bytemuck::{Pod, Zeroable};
use glam::{DMat4, DVec3, DVec4, Mat4};

use crate::{Error, math};

/// Most cascades one camera gets.
pub const MAX_CASCADES: usize = 8;

/// The camera the cascades are fitted to, in f64 world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CascadeCamera {
    /// Eye position, world space.
    pub position: DVec3,
    /// Unit view direction, world space.
    pub forward: DVec3,
    /// Vertical field of view, radians.
    pub fov_y: f64,
    /// Width / height.
    pub aspect: f64,
}

/// Parameters of a cascade set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CascadeParams {
    /// Number of cascades, `1..=MAX_CASCADES`.
    pub count: u32,
    /// View distance where shadows start (the camera's near plane), > 0.
    pub near: f64,
    /// View distance where shadows end, > near.
    pub far: f64,
    /// Practical-split blend: 0 uniform, 1 logarithmic; typically 0.5-0.9.
    pub lambda: f64,
    /// Shadow-map texels per side of the finest slice, > 1.
    pub resolution: u32,
    /// KZ2's per-slice resolution: slice `i` has `resolution / resolution_divisor[i]`
    /// texels per side (at least 2), its texel grid and snapping at that size. 1 keeps the
    /// full resolution.
    pub resolution_divisor: [u32; MAX_CASCADES],
    /// Radii are rounded up to a multiple of this (metres), e.g. 1/16, > 0.
    pub radius_step: f64,
    /// The light-space depth of the centre is snapped to a multiple of this (metres), > 0.
    pub depth_step: f64,
    /// Extra depth towards the light for casters outside the slice's sphere (metres), >= 0.
    pub caster_margin: f64,
    /// The world point the texel grid is anchored at.
    pub anchor: DVec3,
}

impl CascadeParams {
    /// Texels per side of slice `i`: `resolution / resolution_divisor[i]` (the full
    /// resolution past [`MAX_CASCADES`] or for a zero divisor, which validation refuses).
    pub fn slice_resolution(&self, i: usize) -> u32 {
        match self.resolution_divisor.get(i) {
            Some(&d) if d > 0 => self.resolution / d,
            _ => self.resolution,
        }
    }
}

impl Default for CascadeParams {
    fn default() -> Self {
        CascadeParams {
            count: 4,
            near: 0.1,
            far: 200.0,
            lambda: 0.75,
            resolution: 2048,
            resolution_divisor: [1; MAX_CASCADES],
            radius_step: 1.0 / 16.0,
            depth_step: 1.0 / 16.0,
            caster_margin: 50.0,
            anchor: DVec3::ZERO,
        }
    }
}

/// One cascade: its slice, its sphere and its world → shadow-clip matrix.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cascade {
    /// The slice's view distances `[near, far]`.
    pub split: [f64; 2],
    /// Half the orthographic box's width (metres): the slice sphere's radius, padded by
    /// half a texel and rounded up.
    pub radius: f64,
    /// World-space size of one shadow texel, `2 radius / (the slice's resolution)`.
    pub texel_size: f64,
    /// The snapped box centre in world space.
    pub center: DVec3,
    /// World → shadow clip space.
    pub world_to_clip: DMat4,
}

impl Cascade {
    /// The matrix for camera-relative positions (`world - origin`), computed in f64 and
    /// rounded once to f32.
    pub fn relative_matrix(&self, origin: DVec3) -> Mat4 {
        (self.world_to_clip * DMat4::from_translation(origin)).as_mat4()
    }

    /// The cascade as the WGSL struct `DeferredCascade`, for camera-relative positions.
    pub fn gpu(&self, origin: DVec3) -> DeferredCascade {
        DeferredCascade {
            relative_to_clip: self.relative_matrix(origin).to_cols_array_2d(),
            split_far: self.split[1] as f32,
            texel_size: self.texel_size as f32,
            radius: self.radius as f32,
            pad: 0.0,
        }
    }
}

/// A cascade as the GPU reads it (WGSL struct `DeferredCascade`, 80 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct DeferredCascade {
    /// Camera-relative world → shadow clip, column-major (`mat4x4<f32>`).
    pub relative_to_clip: [[f32; 4]; 4],
    /// The slice's far view distance: a pixel uses the first cascade whose `split_far` is
    /// beyond its view distance.
    pub split_far: f32,
    /// World size of a texel (for normal-offset bias).
    pub texel_size: f32,
    /// Half the box's width.
    pub radius: f32,
    /// Padding, 0.
    pub pad: f32,
}
const _: () = assert!(size_of::<DeferredCascade>() == 80);

/// The practical split scheme: `count + 1` distances from `near` to `far`, each the blend
/// `lambda · log + (1 - lambda) · uniform` of the logarithmic split `near (far /
/// near)^(i / count)` and the uniform split `near + (far - near) i / count`. Writes
/// `out[..=count]`; the ends are exactly `near` and `far`.
pub fn practical_splits(near: f64, far: f64, count: u32, lambda: f64, out: &mut [f64]) {
    let n = count as usize;
    for i in 0..=n.min(out.len().saturating_sub(1)) {
        out[i] = if i == 0 {
            near
        } else if i == n {
            far
        } else {
            let t = i as f64 / n as f64;
            let log = near * math::powf64(far / near, t);
            let uni = near + (far - near) * t;
            lambda * log + (1.0 - lambda) * uni
        };
    }
}

/// The smallest sphere around the view-frustum slice between view distances `near` and
/// `far` (`tan_x`, `tan_y`: tangents of the half fields of view). Returns `(centre distance
/// along the view axis, radius)`: both independent of the camera's orientation.
pub fn slice_bounding_sphere(near: f64, far: f64, tan_x: f64, tan_y: f64) -> (f64, f64) {
    let k2 = tan_x * tan_x + tan_y * tan_y;
    // The point on the axis equidistant from the near and far corners.
    let c = 0.5 * (far + near) * (1.0 + k2);
    if c >= far {
        // The far rectangle's circumscribed sphere holds the near rectangle too.
        return (far, far * math::sqrt64(k2));
    }
    let dn = c - near;
    (c, math::sqrt64(dn * dn + near * near * k2))
}

/// A unit light frame: `(right, up, towards the scene)`, from the unit direction
/// `to_light` (towards the light) and a fixed world reference, so it depends only on the
/// light; right-handed, `up = right × forward`. The cascades' light space.
pub fn light_frame(to_light: DVec3) -> (DVec3, DVec3, DVec3) {
    let fwd = -to_light;
    let reference = if fwd.y.abs() < 0.99 {
        DVec3::Y
    } else {
        DVec3::X
    };
    let right = fwd.cross(reference).normalize();
    let up = right.cross(fwd);
    (right, up, fwd)
}

fn round_up(x: f64, step: f64) -> f64 {
    math::ceil64(x / step) * step
}

fn round_to(x: f64, step: f64) -> f64 {
    math::floor64(x / step + 0.5) * step
}

/// A fitted cascade set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StableCascades {
    count: usize,
    cascades: [Cascade; MAX_CASCADES],
}

impl StableCascades {
    /// Fits `params.count` cascades to a camera for a sun shining from `to_light`.
    pub fn fit(
        camera: &CascadeCamera,
        to_light: DVec3,
        params: &CascadeParams,
    ) -> Result<Self, Error> {
        check(camera, to_light, params)?;
        let n = params.count as usize;
        let mut splits = [0.0; MAX_CASCADES + 1];
        practical_splits(
            params.near,
            params.far,
            params.count,
            params.lambda,
            &mut splits,
        );
        let tan_y = math::tan64(camera.fov_y * 0.5);
        let tan_x = tan_y * camera.aspect;
        let (right, up, fwd) = light_frame(to_light.normalize());
        let zero = Cascade {
            split: [0.0; 2],
            radius: 0.0,
            texel_size: 0.0,
            center: DVec3::ZERO,
            world_to_clip: DMat4::ZERO,
        };
        let mut cascades = [zero; MAX_CASCADES];
        let forward = camera.forward.normalize();
        for i in 0..n {
            let res = f64::from(params.slice_resolution(i));
            let (near, far) = (splits[i], splits[i + 1]);
            let (c, r) = slice_bounding_sphere(near, far, tan_x, tan_y);
            // Pad by half a texel of the padded box: R - R / res >= r.
            let radius = round_up(r * res / (res - 1.0), params.radius_step);
            let texel = 2.0 * radius / res;
            // Sphere centre in light space relative to the anchor, snapped.
            let centre = camera.position + forward * c - params.anchor;
            let lx = round_to(centre.dot(right), texel);
            let ly = round_to(centre.dot(up), texel);
            let lz = round_to(centre.dot(fwd), params.depth_step);
            let z_near = lz - radius - params.caster_margin;
            let z_far = lz + radius;
            let inv_depth = 1.0 / (z_far - z_near);
            // Rows: x = (p·right - lx) / R, y = (p·up - ly) / R, z = (p·fwd - z_near) / depth,
            // with p = world - anchor.
            let a = params.anchor;
            let row = |axis: DVec3, scale: f64, offset: f64| {
                DVec4::new(
                    axis.x * scale,
                    axis.y * scale,
                    axis.z * scale,
                    (-a.dot(axis) - offset) * scale,
                )
            };
            let rx = row(right, 1.0 / radius, lx);
            let ry = row(up, 1.0 / radius, ly);
            let rz = row(fwd, inv_depth, z_near);
            let world_to_clip =
                DMat4::from_cols(rx, ry, rz, DVec4::new(0.0, 0.0, 0.0, 1.0)).transpose();
            cascades[i] = Cascade {
                split: [near, far],
                radius,
                texel_size: texel,
                center: a + right * lx + up * ly + fwd * lz,
                world_to_clip,
            };
        }
        Ok(StableCascades { count: n, cascades })
    }

    /// The cascades, nearest first.
    pub fn cascades(&self) -> &[Cascade] {
        &self.cascades[..self.count]
    }

    /// Index of the cascade for a view distance (`None` beyond the last).
    pub fn select(&self, distance: f64) -> Option<usize> {
        self.cascades().iter().position(|c| distance <= c.split[1])
    }
}

fn check(camera: &CascadeCamera, to_light: DVec3, p: &CascadeParams) -> Result<(), Error> {
    let bad = |name, value: f64| Err(Error::InvalidParameter { name, value });
    if p.count == 0 || p.count as usize > MAX_CASCADES {
        return Err(Error::TooManyCascades {
            count: p.count,
            limit: MAX_CASCADES as u32,
        });
    }
    if !(p.near > 0.0 && p.near.is_finite()) {
        return bad("near", p.near);
    }
    if !(p.far > p.near && p.far.is_finite()) {
        return bad("far", p.far);
    }
    if !(0.0..=1.0).contains(&p.lambda) {
        return bad("lambda", p.lambda);
    }
    if p.resolution < 2 {
        return bad("resolution", f64::from(p.resolution));
    }
    for i in 0..(p.count as usize).min(MAX_CASCADES) {
        let d = p.resolution_divisor[i];
        if d == 0 || p.resolution / d < 2 {
            return bad("resolution_divisor", f64::from(d));
        }
    }
    if !(p.radius_step > 0.0 && p.radius_step.is_finite()) {
        return bad("radius_step", p.radius_step);
    }
    if !(p.depth_step > 0.0 && p.depth_step.is_finite()) {
        return bad("depth_step", p.depth_step);
    }
    if !(p.caster_margin >= 0.0 && p.caster_margin.is_finite()) {
        return bad("caster_margin", p.caster_margin);
    }
    if !p.anchor.is_finite() {
        return bad("anchor", f64::NAN);
    }
    if !(camera.fov_y > 0.0 && camera.fov_y < core::f64::consts::PI) {
        return bad("fov_y", camera.fov_y);
    }
    if !(camera.aspect > 0.0 && camera.aspect.is_finite()) {
        return bad("aspect", camera.aspect);
    }
    if !camera.position.is_finite() {
        return bad("camera position", f64::NAN);
    }
    let fl = camera.forward.length();
    if !(fl > 0.0 && fl.is_finite()) {
        return bad("camera forward length", fl);
    }
    let ll = to_light.length();
    if !(ll > 0.0 && ll.is_finite()) {
        return bad("to_light length", ll);
    }
    Ok(())
}
