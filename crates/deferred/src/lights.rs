//! Local lights: tiled light culling (the CPU twin of a two-pass compute culling: per-tile
//! depth range, then per-tile light lists) and Killzone 2's per-light decisions (which
//! lights want the stencil-marked light-volume path, which are enough with a depth-bounds
//! test, and fading shadows out for small lights).
//!
//! # Conventions
//!
//! Lights are in view space (right-handed, camera looking down `-z`; see [`crate::depth`]),
//! in metres. A point light lights the sphere of radius `range` around `position`; a spot
//! light the part of that sphere within `acos(cos_outer)` of `direction` (a spherical
//! sector). Tiles are [`TILE_SIZE`]² pixels, row-major from the top-left, the last row and
//! column clipped to the viewport.
//!
//! # The two passes
//!
//! 1. [`tile_depth_ranges`]: per tile, the nearest and farthest depth-buffer value of the
//!    pixels that hold geometry (the GPU does this with `atomicMax`/`atomicMin` on the
//!    depth bits: non-negative floats order like their bits).
//! 2. [`cull_tiles`]: per tile, the lights whose volume meets the tile's frustum (four side
//!    planes through the eye and the tile's depth range): spheres against planes, spots
//!    also as a cone against each plane. Conservative: every light that lights a pixel of
//!    the tile is listed (tested against a per-pixel brute force); a few that light none
//!    are too (the sphere-plane test is loose at the frustum's corners).
//!
//! # KZ2's decisions ([`LightClassifier`])
//!
//! KZ2 drew each light's volume: large lights (20% of the screen or more) and shadow
//! casters with stencil marking of the pixels inside the volume (back faces with depth
//! test `Greater`, then front faces with `LessEqual` against the stencil), small lights
//! with only the depth-bounds test (reject pixels whose *stored* depth is outside the
//! light's depth range). wgpu has no depth-bounds test: [`LightClass::depth_bounds`] is the
//! light's range in depth-buffer units, and [`depth_bounds_overlap`] the per-tile test that
//! replaces it. Shadows of small lights fade out ([`ShadowFade`]); once faded, a light uses
//! the non-shadow path.

use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3};

use crate::depth::{DeferredProjection, DepthMode};
use crate::{Error, math};

/// Tile edge in pixels.
pub const TILE_SIZE: u32 = 16;
/// Most lights one tile's list holds: further lights of a crowded tile are dropped and
/// counted in [`CullStats::overflowed_tiles`].
pub const MAX_LIGHTS_PER_TILE: u32 = 256;
/// Most lights one culling pass takes (KZ2 had 100+ per frame, up to 300 on screen).
pub const MAX_LIGHTS: u32 = 65_536;
/// Largest viewport edge in pixels.
pub const MAX_VIEWPORT: u32 = 16_384;
/// KZ2's threshold: lights covering this fraction of the screen or more take the
/// stencil-marked volume path.
pub const KZ2_VOLUME_COVERAGE: f32 = 0.2;

/// [`DeferredLight::flags`] bit: the light casts shadows.
pub const LIGHT_FLAG_SHADOW: u32 = 1;
/// [`DeferredLight::flags`] bit: the light is a spot (the cone fields are used).
pub const LIGHT_FLAG_SPOT: u32 = 2;
/// [`DeferredLight::flags`] bit: the light has no specular term, diffuse alone (KZ2's
/// no-specular light-shader permutation). Set rather than clear so that a zeroed row
/// keeps its specular term.
pub const LIGHT_FLAG_NO_SPECULAR: u32 = 4;

/// A point or spot light in view space, as the WGSL struct `DeferredLight` (48 bytes;
/// `array<DeferredLight>` has a 48-byte stride).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct DeferredLight {
    /// View-space position, metres.
    pub position: [f32; 3],
    /// Radius of influence, metres (> 0).
    pub range: f32,
    /// Spot axis, unit, view space (unused for point lights).
    pub direction: [f32; 3],
    /// Cosine of the spot's half-angle, in `(0, 1)`: spots are narrower than a hemisphere
    /// (unused for point lights).
    pub cos_outer: f32,
    /// Linear RGB intensity.
    pub color: [f32; 3],
    /// [`LIGHT_FLAG_SHADOW`], [`LIGHT_FLAG_SPOT`], [`LIGHT_FLAG_NO_SPECULAR`] (bits 0-7
    /// are this crate's; a renderer may keep its own data above them).
    pub flags: u32,
}
const _: () = assert!(size_of::<DeferredLight>() == 48);

impl DeferredLight {
    /// A point light.
    pub fn point(position: Vec3, range: f32, color: Vec3) -> Self {
        DeferredLight {
            position: position.into(),
            range,
            direction: [0.0, 0.0, -1.0],
            cos_outer: 0.0,
            color: color.into(),
            flags: 0,
        }
    }

    /// A spot light with half-angle `outer_angle` (radians, in `(0, π/2)`).
    pub fn spot(
        position: Vec3,
        direction: Vec3,
        range: f32,
        outer_angle: f32,
        color: Vec3,
    ) -> Self {
        DeferredLight {
            position: position.into(),
            range,
            direction: direction.normalize_or_zero().into(),
            cos_outer: math::cos(outer_angle),
            color: color.into(),
            flags: LIGHT_FLAG_SPOT,
        }
    }

    /// The same light, casting shadows.
    pub fn with_shadow(mut self) -> Self {
        self.flags |= LIGHT_FLAG_SHADOW;
        self
    }

    /// The same light without its specular term (diffuse alone).
    pub fn without_specular(mut self) -> Self {
        self.flags |= LIGHT_FLAG_NO_SPECULAR;
        self
    }

    /// Whether it has a specular term ([`LIGHT_FLAG_NO_SPECULAR`] clear).
    pub fn has_specular(&self) -> bool {
        self.flags & LIGHT_FLAG_NO_SPECULAR == 0
    }

    /// Whether it is a spot light.
    pub fn is_spot(&self) -> bool {
        self.flags & LIGHT_FLAG_SPOT != 0
    }

    /// Whether it casts shadows.
    pub fn casts_shadow(&self) -> bool {
        self.flags & LIGHT_FLAG_SHADOW != 0
    }

    /// Checks the fields: finite, `range > 0`, and for spots a unit direction and
    /// `cos_outer` in `(0, 1)`. `index` names the light in the error.
    pub fn validate(&self, index: u32) -> Result<(), Error> {
        let p = Vec3::from(self.position);
        if !p.is_finite() || !Vec3::from(self.color).is_finite() {
            return Err(Error::InvalidLight {
                index,
                field: "position/color",
            });
        }
        if !(self.range > 0.0 && self.range.is_finite()) {
            return Err(Error::InvalidLight {
                index,
                field: "range",
            });
        }
        if self.is_spot() {
            let d = Vec3::from(self.direction);
            if !d.is_finite() || (d.length_squared() - 1.0).abs() > 1e-3 {
                return Err(Error::InvalidLight {
                    index,
                    field: "direction",
                });
            }
            if !(self.cos_outer > 0.0 && self.cos_outer < 1.0) {
                return Err(Error::InvalidLight {
                    index,
                    field: "cos_outer",
                });
            }
        }
        Ok(())
    }

    /// Whether the view-space point `p` is inside the light's volume (the per-pixel test
    /// the tile lists stand in for).
    pub fn affects(&self, p: Vec3) -> bool {
        let d = p - Vec3::from(self.position);
        let r = self.range;
        if d.length_squared() > r * r {
            return false;
        }
        if !self.is_spot() {
            return true;
        }
        let along = d.dot(Vec3::from(self.direction));
        along >= 0.0 && along * along >= d.length_squared() * self.cos_outer * self.cos_outer
    }

    /// A sphere enclosing the light's volume, `(centre, radius)`: for a spot, the smallest
    /// sphere around its sector (through the apex and the cap's rim for half-angles up to
    /// 45 degrees, around the cap's base circle beyond).
    pub fn bounding_sphere(&self) -> (Vec3, f32) {
        let p = Vec3::from(self.position);
        if !self.is_spot() {
            return (p, self.range);
        }
        let d = Vec3::from(self.direction);
        let c = self.cos_outer;
        if c >= core::f32::consts::FRAC_1_SQRT_2 {
            let r = self.range / (2.0 * c);
            (p + d * r, r)
        } else {
            let s = math::sqrt((1.0 - c * c).max(0.0));
            (p + d * (self.range * c), self.range * s)
        }
    }

    /// The light's extent in view distance (`-z`), `[nearest, farthest]`, before clipping
    /// to the near plane.
    pub fn distance_range(&self) -> (f32, f32) {
        let (c, r) = self.bounding_sphere();
        let (mut lo, mut hi) = (-c.z - r, -c.z + r);
        if self.is_spot() {
            // The cone's extent along -z (tighter for narrow spots aimed across the view).
            let a = Vec3::from(self.position);
            let v = Vec3::new(0.0, 0.0, -1.0);
            let (cmin, cmax) =
                cone_extent(a, Vec3::from(self.direction), self.range, self.cos_outer, v);
            lo = lo.max(cmin);
            hi = hi.min(cmax);
        }
        (lo, hi)
    }
}

/// `(min, max)` of `v · p` over the cone with apex `a`, unit axis `d`, axial height `h` and
/// half-angle `acos(cos)`: the extremes are the apex or a point of the base circle.
fn cone_extent(a: Vec3, d: Vec3, h: f32, cos: f32, v: Vec3) -> (f32, f32) {
    let tan = math::sqrt((1.0 - cos * cos).max(0.0)) / cos;
    let rho = h * tan;
    let base = (a + d * h).dot(v);
    let perp = math::sqrt((v - d * v.dot(d)).length_squared());
    let apex = a.dot(v);
    (apex.min(base - rho * perp), apex.max(base + rho * perp))
}

/// Nearest and farthest depth-buffer value of a tile's geometry pixels, as the WGSL struct
/// `DeferredTileDepth` (8 bytes). A tile without geometry has `nearest` equal to the far
/// plane's depth ([`DepthMode::far_depth`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct DeferredTileDepth {
    /// Depth of the tile's nearest geometry pixel.
    pub nearest: f32,
    /// Depth of the tile's farthest geometry pixel.
    pub farthest: f32,
}
const _: () = assert!(size_of::<DeferredTileDepth>() == 8);

impl DeferredTileDepth {
    /// The value the GPU pass clears a tile to: nothing seen yet.
    pub const fn empty(mode: DepthMode) -> Self {
        match mode {
            DepthMode::Standard => DeferredTileDepth {
                nearest: 1.0,
                farthest: 0.0,
            },
            DepthMode::Reversed => DeferredTileDepth {
                nearest: 0.0,
                farthest: 1.0,
            },
        }
    }

    /// Whether the tile holds no geometry.
    pub fn is_empty(&self, mode: DepthMode) -> bool {
        self.nearest == mode.far_depth()
    }
}

/// Tiles across and down a `width` × `height` viewport.
pub const fn tile_counts(width: u32, height: u32) -> (u32, u32) {
    (width.div_ceil(TILE_SIZE), height.div_ceil(TILE_SIZE))
}

fn check_viewport(width: u32, height: u32) -> Result<(u32, u32), Error> {
    for (name, v) in [("width", width), ("height", height)] {
        if v == 0 || v > MAX_VIEWPORT {
            return Err(Error::ViewportOutOfRange {
                name,
                value: v,
                limit: MAX_VIEWPORT,
            });
        }
    }
    Ok(tile_counts(width, height))
}

fn check_len(buffer: &'static str, len: usize, needed: usize) -> Result<(), Error> {
    if len < needed {
        return Err(Error::BufferTooSmall {
            buffer,
            len,
            needed,
        });
    }
    Ok(())
}

/// Pass 1: the depth range of every tile. `depth` is the row-major depth buffer
/// (`width * height` values); pixels at the far plane's depth hold no geometry. NaN depths
/// are skipped. `out` gets one entry per tile, row-major.
pub fn tile_depth_ranges(
    depth: &[f32],
    width: u32,
    height: u32,
    mode: DepthMode,
    out: &mut [DeferredTileDepth],
) -> Result<(), Error> {
    let (tx, ty) = check_viewport(width, height)?;
    check_len("depth", depth.len(), width as usize * height as usize)?;
    check_len("tile depths", out.len(), (tx * ty) as usize)?;
    let far = mode.far_depth();
    for t in out[..(tx * ty) as usize].iter_mut() {
        *t = DeferredTileDepth::empty(mode);
    }
    for y in 0..height {
        let row = &depth[(y * width) as usize..((y + 1) * width) as usize];
        let tile_row =
            &mut out[((y / TILE_SIZE) * tx) as usize..((y / TILE_SIZE + 1) * tx) as usize];
        for (x, &d) in row.iter().enumerate() {
            if d == far || d.is_nan() {
                continue;
            }
            let t = &mut tile_row[x / TILE_SIZE as usize];
            match mode {
                DepthMode::Reversed => {
                    t.nearest = t.nearest.max(d);
                    t.farthest = t.farthest.min(d);
                }
                DepthMode::Standard => {
                    t.nearest = t.nearest.min(d);
                    t.farthest = t.farthest.max(d);
                }
            }
        }
    }
    Ok(())
}

/// A tile's frustum in view space: four planes through the eye (unit normals pointing
/// inwards) and the view-distance range of its geometry.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TileFrustum {
    /// Left, right, bottom, top planes `n · p >= 0` inside.
    pub planes: [Vec3; 4],
    /// Nearest view distance of the tile's geometry.
    pub near: f32,
    /// Farthest view distance of the tile's geometry.
    pub far: f32,
}

impl TileFrustum {
    /// The frustum of tile `(tx, ty)` with depth range `depth` (must not be empty).
    pub fn new(proj: &DeferredProjection, tx: u32, ty: u32, depth: DeferredTileDepth) -> Self {
        let (w, h) = (proj.viewport[0], proj.viewport[1]);
        let x0 = (tx * TILE_SIZE) as f32;
        let x1 = (((tx + 1) * TILE_SIZE) as f32).min(w);
        let y0 = (ty * TILE_SIZE) as f32;
        let y1 = (((ty + 1) * TILE_SIZE) as f32).min(h);
        // Slopes x / distance and y / distance of the tile's edges.
        let left = (x0 / w * 2.0 - 1.0) * proj.tan_half[0];
        let right = (x1 / w * 2.0 - 1.0) * proj.tan_half[0];
        let top = (1.0 - y0 / h * 2.0) * proj.tan_half[1];
        let bottom = (1.0 - y1 / h * 2.0) * proj.tan_half[1];
        // p inside the left plane iff p.x / (-p.z) >= left iff p.x + left · p.z >= 0.
        let plane = |n: Vec3| n * (1.0 / math::sqrt(n.length_squared()));
        TileFrustum {
            planes: [
                plane(Vec3::new(1.0, 0.0, left)),
                plane(Vec3::new(-1.0, 0.0, -right)),
                plane(Vec3::new(0.0, 1.0, bottom)),
                plane(Vec3::new(0.0, -1.0, -top)),
            ],
            near: proj.distance(depth.nearest),
            far: proj.distance(depth.farthest),
        }
    }

    /// Whether a sphere meets the frustum (conservative near the corners).
    pub fn sphere_visible(&self, center: Vec3, radius: f32) -> bool {
        let d = -center.z;
        if d + radius < self.near || d - radius > self.far {
            return false;
        }
        self.planes.iter().all(|n| n.dot(center) >= -radius)
    }

    /// Whether a light's volume meets the frustum: its bounding sphere, and for spots also
    /// the cone against every plane and the depth range.
    pub fn light_visible(&self, light: &DeferredLight) -> bool {
        let (c, r) = light.bounding_sphere();
        if !self.sphere_visible(c, r) {
            return false;
        }
        if !light.is_spot() {
            return true;
        }
        let a = Vec3::from(light.position);
        let d = Vec3::from(light.direction);
        let (lo, hi) = cone_extent(
            a,
            d,
            light.range,
            light.cos_outer,
            Vec3::new(0.0, 0.0, -1.0),
        );
        if hi < self.near || lo > self.far {
            return false;
        }
        self.planes
            .iter()
            .all(|n| cone_extent(a, d, light.range, light.cos_outer, *n).1 >= 0.0)
    }
}

/// What a culling pass did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CullStats {
    /// Tiles with geometry.
    pub tiles_with_geometry: u32,
    /// (tile, light) pairs listed.
    pub pairs: u64,
    /// Tiles whose list hit [`MAX_LIGHTS_PER_TILE`] (lights dropped).
    pub overflowed_tiles: u32,
}

/// Pass 2: per-tile light lists. `tiles` is pass 1's output (row-major, [`tile_counts`]
/// of `proj`'s viewport); `counts[t]` gets the number of lights of tile `t` (at most
/// [`MAX_LIGHTS_PER_TILE`]) and `indices[t * MAX_LIGHTS_PER_TILE ..]` their indices in
/// ascending order. The depth mode is `proj`'s ([`DeferredProjection::mode`]). Lights are
/// checked first ([`DeferredLight::validate`]).
pub fn cull_tiles(
    proj: &DeferredProjection,
    tiles: &[DeferredTileDepth],
    lights: &[DeferredLight],
    counts: &mut [u32],
    indices: &mut [u32],
) -> Result<CullStats, Error> {
    let (tx, ty) = check_viewport_f(proj)?;
    let mode = proj.mode();
    let n = (tx * ty) as usize;
    check_len("tile depths", tiles.len(), n)?;
    check_len("counts", counts.len(), n)?;
    check_len("indices", indices.len(), n * MAX_LIGHTS_PER_TILE as usize)?;
    if lights.len() > MAX_LIGHTS as usize {
        return Err(Error::TooManyLights {
            count: lights.len(),
            limit: MAX_LIGHTS,
        });
    }
    for (i, l) in lights.iter().enumerate() {
        l.validate(i as u32)?;
    }
    let mut stats = CullStats::default();
    for y in 0..ty {
        for x in 0..tx {
            let t = (y * tx + x) as usize;
            let (count, overflow) = cull_tile(proj, x, y, tiles[t], lights, tile_slot(indices, t));
            counts[t] = count;
            stats.tiles_with_geometry += u32::from(!tiles[t].is_empty(mode));
            stats.pairs += u64::from(count);
            stats.overflowed_tiles += u32::from(overflow);
        }
    }
    Ok(stats)
}

fn tile_slot(indices: &mut [u32], t: usize) -> &mut [u32] {
    let m = MAX_LIGHTS_PER_TILE as usize;
    &mut indices[t * m..(t + 1) * m]
}

pub(crate) fn check_viewport_f(proj: &DeferredProjection) -> Result<(u32, u32), Error> {
    let (w, h) = (proj.viewport[0], proj.viewport[1]);
    for (name, v) in [("viewport width", w), ("viewport height", h)] {
        if !(v >= 1.0 && v <= MAX_VIEWPORT as f32 && v == math::floor(v)) {
            return Err(Error::InvalidParameter {
                name,
                value: f64::from(v),
            });
        }
    }
    check_viewport(w as u32, h as u32)
}

/// One tile of pass 2 (one workgroup on the GPU): writes the tile's lights to `slot`,
/// returns `(count, overflowed)`.
pub fn cull_tile(
    proj: &DeferredProjection,
    tx: u32,
    ty: u32,
    depth: DeferredTileDepth,
    lights: &[DeferredLight],
    slot: &mut [u32],
) -> (u32, bool) {
    if depth.is_empty(proj.mode()) {
        return (0, false);
    }
    let f = TileFrustum::new(proj, tx, ty, depth);
    let cap = slot.len().min(MAX_LIGHTS_PER_TILE as usize);
    let mut count = 0usize;
    let mut overflow = false;
    for (i, l) in lights.iter().enumerate() {
        if f.light_visible(l) {
            if count == cap {
                overflow = true;
                break;
            }
            slot[count] = i as u32;
            count += 1;
        }
    }
    (count as u32, overflow)
}

/// A pixel rectangle `[min, max)` on screen (pixels from the top-left, `+y` down).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScreenRect {
    /// Top-left corner.
    pub min: Vec2,
    /// Bottom-right corner.
    pub max: Vec2,
}

impl ScreenRect {
    /// Area in pixels.
    pub fn area(&self) -> f32 {
        let s = (self.max - self.min).max(Vec2::ZERO);
        s.x * s.y
    }
}

/// The screen rectangle of a view-space sphere under a symmetric perspective (the exact
/// bounds of its projection, from the tangent planes through the eye: Mara and McGuire
/// 2013), clipped to the viewport. `None` if the sphere is entirely behind the eye; the
/// whole viewport if it reaches behind the eye plane (its projection is unbounded).
pub fn project_sphere(proj: &DeferredProjection, center: Vec3, radius: f32) -> Option<ScreenRect> {
    let d = -center.z;
    if d + radius <= 0.0 {
        return None;
    }
    let (w, h) = (proj.viewport[0], proj.viewport[1]);
    let full = ScreenRect {
        min: Vec2::ZERO,
        max: Vec2::new(w, h),
    };
    if d - radius <= 0.0 {
        return Some(full);
    }
    // Per axis, slopes (a / d) of the two tangent lines from the eye in the (a, d) plane.
    let slopes = |a: f32| {
        let t2 = a * a + d * d - radius * radius;
        let t = math::sqrt(t2.max(0.0));
        let lo = (a * t - radius * d) / (d * t + a * radius);
        let hi = (a * t + radius * d) / (d * t - a * radius);
        // A denominator at or below zero: that tangent is at or past 90 degrees from the
        // view axis, the projection reaches the screen's edge on that side.
        let lo = if d * t + a * radius > 0.0 {
            lo
        } else {
            f32::NEG_INFINITY
        };
        let hi = if d * t - a * radius > 0.0 {
            hi
        } else {
            f32::INFINITY
        };
        (lo, hi)
    };
    let (x0, x1) = slopes(center.x);
    let (y0, y1) = slopes(center.y);
    let px = |s: f32| ((s / proj.tan_half[0] + 1.0) * 0.5 * w).clamp(0.0, w);
    let py = |s: f32| ((1.0 - s / proj.tan_half[1]) * 0.5 * h).clamp(0.0, h);
    let r = ScreenRect {
        min: Vec2::new(px(x0), py(y1)),
        max: Vec2::new(px(x1), py(y0)),
    };
    if r.area() > 0.0 { Some(r) } else { None }
}

/// Real-time shadows fade out as a light gets small on screen; a faded-out light uses the
/// cheaper non-shadow shader. Coverage is the fraction of the screen its rectangle covers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowFade {
    /// Coverage at and above which shadows are at full strength.
    pub full: f32,
    /// Coverage at and below which shadows are off.
    pub zero: f32,
}

impl Default for ShadowFade {
    /// KZ2 gives no numbers (defaults with per-light artist overrides): full shadows from
    /// 2% of the screen, none below 0.5%.
    fn default() -> Self {
        ShadowFade {
            full: 0.02,
            zero: 0.005,
        }
    }
}

impl ShadowFade {
    /// Shadow strength in `[0, 1]` at a screen coverage (linear between the thresholds).
    pub fn strength(&self, coverage: f32) -> f32 {
        if coverage >= self.full {
            1.0
        } else if coverage <= self.zero || self.full <= self.zero {
            0.0
        } else {
            (coverage - self.zero) / (self.full - self.zero)
        }
    }
}

/// How KZ2 draws a light.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LightPath {
    /// Off screen or behind the eye: nothing to draw.
    Culled,
    /// Small and not shadowed: the light's depth range against the stored depth is enough
    /// (depth-bounds test; per tile with [`depth_bounds_overlap`] in wgpu).
    DepthBounds,
    /// Large or shadow casting: stencil-mark the pixels inside the light volume first (and
    /// run the pixel query that skips a shadow map nobody sees).
    Volume,
}

/// The decisions for one light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightClass {
    /// The path.
    pub path: LightPath,
    /// Screen rectangle of the light's bounding sphere.
    pub rect: ScreenRect,
    /// `rect`'s area over the viewport's.
    pub coverage: f32,
    /// The light's depth range in depth-buffer units, `[nearest, farthest]` in the order
    /// of the depth mode (for reversed Z `nearest >= farthest`), clamped to `[0, 1]`.
    pub depth_bounds: [f32; 2],
    /// Shadow strength after the fade (0 for lights that cast none).
    pub shadow: f32,
    /// The eye is inside the light's bounding sphere (a volume pass must then draw back
    /// faces only).
    pub camera_inside: bool,
}

/// KZ2's per-light classification.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightClassifier {
    /// Coverage from which a light takes the volume path ([`KZ2_VOLUME_COVERAGE`]).
    pub volume_coverage: f32,
    /// Shadow fade for small lights.
    pub fade: ShadowFade,
}

impl Default for LightClassifier {
    fn default() -> Self {
        LightClassifier {
            volume_coverage: KZ2_VOLUME_COVERAGE,
            fade: ShadowFade::default(),
        }
    }
}

impl LightClassifier {
    /// Classifies one light (view space) for a projection.
    pub fn classify(&self, proj: &DeferredProjection, light: &DeferredLight) -> LightClass {
        let (c, r) = light.bounding_sphere();
        let camera_inside = c.length_squared() <= r * r;
        let (lo, hi) = light.distance_range();
        let near_distance = proj.distance(proj.near_depth());
        let rect = if hi < near_distance {
            None
        } else {
            project_sphere(proj, c, r)
        };
        let bounds = |dist: f32| {
            if dist <= near_distance {
                proj.near_depth()
            } else {
                proj.depth_of_distance(dist).clamp(0.0, 1.0)
            }
        };
        let depth_bounds = [bounds(lo), bounds(hi)];
        let Some(rect) = rect else {
            return LightClass {
                path: LightPath::Culled,
                rect: ScreenRect {
                    min: Vec2::ZERO,
                    max: Vec2::ZERO,
                },
                coverage: 0.0,
                depth_bounds,
                shadow: 0.0,
                camera_inside,
            };
        };
        let coverage = rect.area() / (proj.viewport[0] * proj.viewport[1]);
        let shadow = if light.casts_shadow() {
            self.fade.strength(coverage)
        } else {
            0.0
        };
        let path = if shadow > 0.0 || coverage >= self.volume_coverage || camera_inside {
            LightPath::Volume
        } else {
            LightPath::DepthBounds
        };
        LightClass {
            path,
            rect,
            coverage,
            depth_bounds,
            shadow,
            camera_inside,
        }
    }
}

/// The depth-bounds test per tile: whether a tile's geometry depth range meets a light's
/// [`LightClass::depth_bounds`].
pub fn depth_bounds_overlap(tile: DeferredTileDepth, bounds: [f32; 2], mode: DepthMode) -> bool {
    if tile.is_empty(mode) {
        return false;
    }
    match mode {
        // Reversed: larger is nearer. Overlap iff tile.nearest >= bounds far and
        // tile.farthest <= bounds near.
        DepthMode::Reversed => tile.nearest >= bounds[1] && tile.farthest <= bounds[0],
        DepthMode::Standard => tile.nearest <= bounds[1] && tile.farthest >= bounds[0],
    }
}
