//! The sun's shadows: KZ2's depth slices as stable cascaded shadow maps
//! (`deferred::StableCascades`: world-aligned, texel-snapped, rotation-invariant slice
//! spheres), fitted on the CPU in f64 every frame, rendered into one layer each of a depth
//! array (each slice at its own resolution, in its layer's corner) by the depth-prepass
//! geometry (the chunks of the scene's own batches that meet the slice's clip volume;
//! in a frame with a static query, the static casters of the slice's own shadow view of
//! the query, KZ2's shadow query with size threshold: [`sun_query_view`]), and sampled by
//! lighting with each slice's PCF radius.
//!
//! Conventions: shadow clip depth in `[0, 1]`, 0 nearest the sun (cleared to 1, tested
//! `Less`); the matrices take camera-relative positions, as every pass's do.

use bytemuck::{Pod, Zeroable};
use deferred::cascades::{
    CascadeCamera, CascadeParams, DeferredCascade, MAX_CASCADES, StableCascades,
};
use glam::DVec3;

use crate::error::{Error, Result};
use crate::resources::uniforms::Camera;

/// Largest [`ShadowConfig::pcf_radius`].
pub(crate) const MAX_PCF_RADIUS: u32 = 2;

/// Largest [`ShadowConfig::static_size_threshold`], texels.
pub(crate) const MAX_STATIC_SIZE_THRESHOLD: f32 = 64.0;

/// Shadow-map depth format.
pub(crate) const SHADOW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The sun's cascaded shadow maps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowConfig {
    /// Depth slices (cascades), 1 to 8.
    pub cascades: u32,
    /// Texels per side of the finest slice's map (and of the depth array's layers), 64 to
    /// 8192.
    pub resolution: u32,
    /// KZ2's per-slice resolution: slice `k` renders `resolution / resolution_divisor[k]`
    /// texels per side (1, 2 or 4; at least 64 texels), in the corner of its layer; its
    /// stable texel grid is that size's.
    pub resolution_divisor: [u32; MAX_CASCADES],
    /// View distance where shadows end (metres), above the camera's near plane.
    pub far: f32,
    /// Practical-split blend of the slice distances, in `[0, 1]` (0 uniform, 1
    /// logarithmic).
    pub lambda: f32,
    /// KZ2's per-slice filtering: slice `k` takes a `(2 r + 1)²`-texel PCF with
    /// `r = pcf_radius[k]`, at most 2 (25, 9 or 1 taps): wide near the camera, one tap far
    /// away, where a texel covers more of the screen's pixels anyway.
    pub pcf_radius: [u32; MAX_CASCADES],
    /// Keep a slice's map while its world-space matrix and the scene stay the same (the
    /// stable cascades keep it while the camera holds still or moves within a texel):
    /// KZ2's stability turned into skipped passes. Frames with a static query always
    /// re-render (their static casters change per frame), and so do frames whose time
    /// moved in a scene with wind (its foliage's shadows sway). Off: every slice every
    /// frame.
    pub cache: bool,
    /// KZ2's removal of small objects from shadow maps, for static content: in a frame
    /// with a static query, each re-rendered slice runs the query's shadow view over its
    /// volume, which leaves out the casters whose bounding sphere's projected diameter is
    /// below this many of the slice's texels (so a caster may be in a fine slice and out
    /// of a coarse one); the baked sun map applies it in its own texels. 0 keeps every
    /// caster; finite, 0 to 64. Planned batches are drawn whole.
    pub static_size_threshold: f32,
}

impl Default for ShadowConfig {
    fn default() -> Self {
        Self {
            cascades: 4,
            resolution: 2048,
            resolution_divisor: [1, 1, 1, 2, 2, 2, 2, 2],
            far: 120.0,
            lambda: 0.75,
            pcf_radius: [2, 1, 1, 0, 0, 0, 0, 0],
            cache: true,
            // Below a texel and a half a caster darkens a texel or two of a map whose
            // lookups are filtered anyway (KZ2: "these objects usually don't contribute
            // to the shadow too much").
            static_size_threshold: 1.5,
        }
    }
}

impl ShadowConfig {
    /// Texels per side of slice `k`.
    pub fn slice_resolution(&self, k: usize) -> u32 {
        self.resolution / self.resolution_divisor.get(k).copied().unwrap_or(1).max(1)
    }

    /// Checks the ranges above.
    ///
    /// # Errors
    /// [`Error::Config`] naming the field.
    pub fn validate(&self) -> Result<()> {
        let bad = Error::config;
        if self.cascades == 0 || self.cascades as usize > MAX_CASCADES {
            return bad("ShadowConfig::cascades", f64::from(self.cascades), "1 to 8");
        }
        if !(64..=8192).contains(&self.resolution) {
            return bad(
                "ShadowConfig::resolution",
                f64::from(self.resolution),
                "64 to 8192 texels",
            );
        }
        for k in 0..self.cascades as usize {
            let d = self.resolution_divisor[k];
            if !matches!(d, 1 | 2 | 4) || self.resolution / d < 64 {
                return bad(
                    "ShadowConfig::resolution_divisor",
                    f64::from(d),
                    "1, 2 or 4, leaving at least 64 texels per slice",
                );
            }
        }
        if !(self.far.is_finite() && self.far > 0.0) {
            return bad(
                "ShadowConfig::far",
                f64::from(self.far),
                "finite, > 0 metres",
            );
        }
        if !(0.0..=1.0).contains(&self.lambda) {
            return bad("ShadowConfig::lambda", f64::from(self.lambda), "[0, 1]");
        }
        if !(0.0..=MAX_STATIC_SIZE_THRESHOLD).contains(&self.static_size_threshold) {
            return bad(
                "ShadowConfig::static_size_threshold",
                f64::from(self.static_size_threshold),
                "finite, 0 to 64 texels",
            );
        }
        if let Some(&r) = self.pcf_radius.iter().find(|&&r| r > MAX_PCF_RADIUS) {
            return bad(
                "ShadowConfig::pcf_radius",
                f64::from(r),
                "0 to 2 texels per slice",
            );
        }
        Ok(())
    }

    /// The stable cascades of `camera` (aspect `aspect`) for a sun towards
    /// `sun_direction` (world, normalised here), anchored at the world origin.
    ///
    /// # Errors
    /// A camera whose near plane is at or beyond [`ShadowConfig::far`], or other
    /// parameters `deferred` refuses ([`Error::Config`]).
    pub fn fit(
        &self,
        camera: &Camera,
        aspect: f32,
        sun_direction: glam::Vec3,
    ) -> Result<StableCascades> {
        let params = CascadeParams {
            count: self.cascades,
            near: f64::from(camera.near),
            far: f64::from(self.far),
            lambda: f64::from(self.lambda),
            resolution: self.resolution,
            resolution_divisor: self.resolution_divisor,
            ..CascadeParams::default()
        };
        let cam = CascadeCamera {
            position: camera.position.as_dvec3(),
            forward: (camera.target - camera.position).as_dvec3().normalize(),
            fov_y: f64::from(camera.fov_y),
            aspect: f64::from(aspect),
        };
        StableCascades::fit(
            &cam,
            sun_direction.as_dvec3().normalize_or(DVec3::Y),
            &params,
        )
        .map_err(|e| Error::Config {
            field: "ShadowConfig (with the camera)",
            value: f64::from(self.far),
            allowed: match e {
                deferred::Error::InvalidParameter { name: "far", .. } => {
                    "a far distance beyond the camera's near plane"
                }
                _ => "parameters StableCascades::fit accepts",
            },
        })
    }
}

/// What lighting reads of the sun's shadows (WGSL `GpuSunShadow`), 720 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub(crate) struct GpuSunShadow {
    /// The cascades, nearest first, matrices for camera-relative positions.
    pub cascades: [DeferredCascade; MAX_CASCADES],
    /// Cascades in use (0: no real-time sun shadow).
    pub count: u32,
    /// Texels per side of the depth array's layers.
    pub resolution: u32,
    /// Zero.
    pub pad: [u32; 2],
    /// Per slice: its PCF radius in texels ([`ShadowConfig::pcf_radius`]).
    pub pcf_radius: [u32; MAX_CASCADES],
    /// Per slice: texels per side of its map (the corner of its layer it renders into).
    pub slice_texels: [u32; MAX_CASCADES],
}
const _: () = assert!(size_of::<GpuSunShadow>() == 720);

impl Default for GpuSunShadow {
    fn default() -> Self {
        Zeroable::zeroed()
    }
}

impl GpuSunShadow {
    /// The GPU rows of `cascades` for a camera at `origin` (world), filtered as `config`
    /// says.
    pub(crate) fn new(cascades: &StableCascades, origin: DVec3, config: &ShadowConfig) -> Self {
        let resolution = config.resolution;
        let mut s = Self::default();
        for (out, c) in s.cascades.iter_mut().zip(cascades.cascades()) {
            *out = c.gpu(origin);
        }
        s.count = cascades.cascades().len() as u32;
        s.resolution = resolution;
        s.pcf_radius = config.pcf_radius.map(|r| r.min(MAX_PCF_RADIUS));
        s.slice_texels = std::array::from_fn(|k| config.slice_resolution(k));
        s
    }
}

/// The six planes of the clip volume of `m` (a camera-relative matrix with depth in
/// `[0, 1]`), normalised, pointing inwards: left, right, bottom, top, near, far.
pub(crate) fn clip_planes(m: glam::Mat4) -> [glam::Vec4; 6] {
    let r = [m.row(0), m.row(1), m.row(2), m.row(3)];
    [
        r[3] + r[0],
        r[3] - r[0],
        r[3] + r[1],
        r[3] - r[1],
        r[2],
        r[3] - r[2],
    ]
    .map(|p| {
        let n = p.truncate().length();
        if n > 0.0 { p / n } else { p }
    })
}

/// The static query's camera for an orthographic sun view whose world-to-clip matrix is
/// `world_to_clip` (f64, depth 0 nearest the sun), seen from `position` (world, metres; it
/// sets the query's snapped floating origin) looking away from the sun `to_sun` in
/// `deferred`'s light frame (the cascades' axes). The projection is the matrix's own, so
/// the query's frustum planes and size test see exactly the map's volume and texels.
pub(crate) fn sun_query_camera(
    world_to_clip: glam::DMat4,
    position: DVec3,
    to_sun: DVec3,
) -> staticscene::Camera {
    let (right, up, fwd) = deferred::cascades::light_frame(to_sun.normalize_or(DVec3::Y));
    let rotation = glam::DQuat::from_mat3(&glam::DMat3::from_cols(right, up, -fwd));
    // Projection = world_to_clip after view-to-world: the query composes it back with its
    // view (f64 both) and rounds once.
    let view_to_world = glam::DMat4::from_rotation_translation(rotation, position);
    staticscene::Camera {
        position,
        rotation,
        projection: (world_to_clip * view_to_world).as_mat4(),
        reversed_depth: false,
    }
}

/// The static query's shadow view of a sun map (a slice, or the bake) of `texels` per
/// side: [`sun_query_camera`], the sun-shadow filter, LODs chosen from the player camera's
/// `lod_position` with its `lod_scale` (so shadows show the LODs the camera sees), and
/// KZ2's size threshold in the map's texels. No fade, no occlusion (`ViewDesc::shadow`).
pub(crate) fn sun_query_view(
    camera: staticscene::Camera,
    texels: u32,
    lod_position: DVec3,
    lod_scale: f32,
    size_threshold: f32,
) -> staticscene::ViewDesc {
    let mut view = staticscene::ViewDesc::shadow(
        camera,
        [texels, texels],
        staticscene::FILTER_SUN_SHADOW,
        lod_position,
    );
    view.lod_scale = lod_scale;
    view.size_threshold_px = size_threshold;
    view
}

/// Whether the sphere of `center` and `radius` meets the volume of `planes` (conservative:
/// a sphere outside near a corner may still count as meeting it).
pub(crate) fn sphere_meets(planes: &[glam::Vec4; 6], center: glam::Vec3, radius: f32) -> bool {
    planes
        .iter()
        .all(|p| p.truncate().dot(center) + p.w >= -radius)
}

/// What the shadow passes cull their casters with this frame: per sun slice and per spot
/// map, the clip planes of its camera-relative matrix (empty: draw every caster).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct CasterCulls {
    pub slices: Vec<[glam::Vec4; 6]>,
    pub spots: Vec<[glam::Vec4; 6]>,
}

/// Texels per side of the baked sun map (KZ2's pre-rendered sun shadow: low resolution,
/// the real-time slices add the detail).
pub(crate) const BAKED_SUN_RESOLUTION: u32 = 1024;

/// The baked sun map's matrix: origin-relative positions to an orthographic box around
/// the sphere of `bounds` (origin-relative), seen from the sun towards `sun_direction`
/// (world), depth 0 nearest the sun.
pub(crate) fn baked_sun_matrix(
    bounds: (glam::Vec3, glam::Vec3),
    sun_direction: glam::Vec3,
) -> glam::Mat4 {
    use glam::{Mat4, Vec3, Vec4};
    let to_sun = sun_direction.normalize_or(Vec3::Y);
    let centre = (bounds.0 + bounds.1) * 0.5;
    let radius = ((bounds.1 - bounds.0).length() * 0.5).max(1e-3);
    // The cascades' light space, so the bake and the slices share their axes.
    let (right, up, fwd) = deferred::cascades::light_frame(to_sun.as_dvec3());
    let (right, up, fwd) = (right.as_vec3(), up.as_vec3(), fwd.as_vec3());
    // Rows: x = (q - c).right / r, y = (q - c).up / r, z = ((q - c).fwd + r) / 2r.
    let row = |axis: Vec3, scale: f32, offset: f32| {
        Vec4::new(
            axis.x * scale,
            axis.y * scale,
            axis.z * scale,
            (offset - centre.dot(axis)) * scale,
        )
    };
    Mat4::from_cols(
        row(right, 1.0 / radius, 0.0),
        row(up, 1.0 / radius, 0.0),
        row(fwd, 0.5 / radius, radius),
        Vec4::W,
    )
    .transpose()
}

/// Byte stride of the per-cascade frame uniforms in their buffer (a multiple of every
/// adapter's uniform offset alignment, 256).
pub(crate) const CASCADE_FRAME_STRIDE: u64 = 512;
const _: () = assert!(
    CASCADE_FRAME_STRIDE.is_multiple_of(256)
        && CASCADE_FRAME_STRIDE >= size_of::<crate::resources::rows::FrameUniforms>() as u64
);

/// The shadow maps of one renderer: a depth array of one layer per cascade (1x1x1 when
/// shadows are off, so lighting's bindings hold something), its views, the per-cascade
/// frame uniforms the shadow passes draw with, and the uniform lighting reads.
pub(crate) struct ShadowMaps {
    pub config: Option<ShadowConfig>,
    pub texture: wgpu::Texture,
    /// One view per layer (render attachments).
    pub layer_views: Vec<wgpu::TextureView>,
    /// The whole array (lighting samples it).
    pub array_view: wgpu::TextureView,
    /// `FrameUniforms` per cascade at [`CASCADE_FRAME_STRIDE`].
    pub frames: wgpu::Buffer,
    /// `GpuSunShadow`.
    pub sun: wgpu::Buffer,
    /// The baked sun map ([`BAKED_SUN_RESOLUTION`]²; the view keeps its texture).
    pub baked_view: wgpu::TextureView,
    /// A 1x1 depth texture bound in the baked map's place while the map is the attachment.
    pub stand_in_view: wgpu::TextureView,
    /// The bake pass's frame uniforms.
    pub baked_frame: wgpu::Buffer,
    /// The scene, sun (bits) and, with static casters, the hash of the active static
    /// tiles' ids the baked map was rendered for.
    pub baked_for: Option<(u64, [u32; 3], Option<u64>)>,
    /// Per slice: the scene and world-space matrix (f64 bits) its map holds.
    pub rendered: Vec<Option<SliceKey>>,
    /// Per slice: this frame's key, and whether the frame renders the slice.
    pub pending: Vec<SliceKey>,
    pub dirty: Vec<bool>,
}

/// What a slice's map was rendered for: the scene id and the slice's world-to-clip matrix.
pub(crate) type SliceKey = (u64, [u64; 16]);

impl ShadowMaps {
    /// Decides which slices this frame renders: those whose key changed since their map
    /// was rendered, all of them without the cache or in a frame with static casters.
    pub(crate) fn plan(&mut self, keys: Vec<SliceKey>, static_frame: bool) {
        let cache = self.config.is_some_and(|c| c.cache);
        self.dirty = keys
            .iter()
            .enumerate()
            .map(|(i, k)| {
                !cache || static_frame || self.rendered.get(i).copied().flatten() != Some(*k)
            })
            .collect();
        self.pending = keys;
    }

    /// After a frame that recorded the slices: what their maps now hold (nothing reusable
    /// after a frame with static casters).
    pub(crate) fn rendered(&mut self, static_frame: bool) {
        self.rendered = self
            .pending
            .iter()
            .map(|k| (!static_frame).then_some(*k))
            .collect();
    }
}

impl ShadowMaps {
    pub(crate) fn new(device: &wgpu::Device, config: Option<ShadowConfig>) -> Self {
        let (size, layers) = config.map_or((1, 1), |c| (c.resolution, c.cascades));
        let texture = depth_texture(device, "sun shadow maps", size, layers);
        let (layer_views, array_view) = layer_views(&texture, layers);
        let frames = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sun shadow cascade frames"),
            size: CASCADE_FRAME_STRIDE * u64::from(layers),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let sun = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sun shadow"),
            size: size_of::<GpuSunShadow>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let depth =
            |label, size| depth_texture(device, label, size, 1).create_view(&Default::default());
        let baked_view = depth("baked sun map", BAKED_SUN_RESOLUTION);
        let stand_in_view = depth("baked sun stand-in", 1);
        let baked_frame = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("baked sun frame"),
            size: size_of::<crate::resources::rows::FrameUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self {
            config,
            texture,
            layer_views,
            array_view,
            frames,
            sun,
            baked_view,
            stand_in_view,
            baked_frame,
            baked_for: None,
            rendered: Vec::new(),
            pending: Vec::new(),
            dirty: Vec::new(),
        }
    }

    /// Cascades rendered each frame (0 when off).
    pub(crate) fn cascades(&self) -> u32 {
        self.config.map_or(0, |c| c.cascades)
    }
}

/// One 2D view per layer of `texture` (`layers` of them: render attachments) and one
/// view of the whole array (sampled).
pub(crate) fn layer_views(
    texture: &wgpu::Texture,
    layers: u32,
) -> (Vec<wgpu::TextureView>, wgpu::TextureView) {
    let layer_views = (0..layers)
        .map(|i| {
            texture.create_view(&wgpu::TextureViewDescriptor {
                label: Some("shadow map layer"),
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: i,
                array_layer_count: Some(1),
                ..Default::default()
            })
        })
        .collect();
    let array_view = texture.create_view(&wgpu::TextureViewDescriptor {
        label: Some("shadow maps"),
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    (layer_views, array_view)
}

/// A square [`SHADOW_FORMAT`] texture of `layers` layers, for rendering, sampling and
/// read-back.
pub(crate) fn depth_texture(
    device: &wgpu::Device,
    label: &str,
    size: u32,
    layers: u32,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size,
            height: size,
            depth_or_array_layers: layers,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: SHADOW_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every field out of range is refused by name; the default passes.
    #[test]
    fn validation_names_the_field() {
        assert!(ShadowConfig::default().validate().is_ok());
        let field = |c: ShadowConfig| match c.validate() {
            Err(Error::Config { field, .. }) => field,
            other => panic!("{other:?}"),
        };
        let d = ShadowConfig::default();
        assert_eq!(
            field(ShadowConfig { cascades: 0, ..d }),
            "ShadowConfig::cascades"
        );
        assert_eq!(
            field(ShadowConfig { cascades: 9, ..d }),
            "ShadowConfig::cascades"
        );
        assert_eq!(
            field(ShadowConfig {
                resolution: 32,
                ..d
            }),
            "ShadowConfig::resolution"
        );
        assert_eq!(
            field(ShadowConfig { far: f32::NAN, ..d }),
            "ShadowConfig::far"
        );
        assert_eq!(
            field(ShadowConfig { lambda: 1.5, ..d }),
            "ShadowConfig::lambda"
        );
        let mut wide = d;
        wide.pcf_radius[3] = 3;
        assert_eq!(field(wide), "ShadowConfig::pcf_radius");
        for t in [-0.5, 65.0, f32::NAN, f32::INFINITY] {
            assert_eq!(
                field(ShadowConfig {
                    static_size_threshold: t,
                    ..d
                }),
                "ShadowConfig::static_size_threshold"
            );
        }
    }

    /// The static query's camera of a slice reproduces the slice's matrix (the query's
    /// floating space through its clip matrix equals the world matrix, in f64 terms up to
    /// f32 rounding), and its size test's pixels per unit are the slice's texels per metre.
    #[test]
    fn a_slices_query_view_is_its_map() {
        let config = ShadowConfig::default();
        let camera = Camera {
            position: glam::Vec3::new(1234.4, 17.0, -560.2),
            ..Camera::look_at(glam::Vec3::ZERO, glam::Vec3::new(1.0, -0.2, -3.0))
        };
        let camera = Camera {
            target: camera.position + glam::Vec3::new(1.0, -0.2, -3.0),
            ..camera
        };
        let sun = glam::Vec3::new(0.3, 0.8, -0.4);
        let cascades = config.fit(&camera, 16.0 / 9.0, sun).unwrap();
        for (k, c) in cascades.cascades().iter().enumerate() {
            let q = sun_query_camera(c.world_to_clip, c.center, sun.as_dvec3());
            let texels = config.slice_resolution(k);
            let view = sun_query_view(q, texels, camera.position.as_dvec3(), 1.0, 2.0);
            let params = staticscene::QueryParams::new(&view).unwrap();
            let origin = params.origin().as_dvec3();
            let m = params.clip_from_floating();
            for p in [
                c.center,
                c.center + DVec3::new(c.radius * 0.7, -3.0, 0.2 * c.radius),
                c.center - DVec3::new(0.1, c.radius * 0.5, c.radius * 0.9),
            ] {
                let want = c.world_to_clip.project_point3(p);
                let got = m.project_point3((p - origin).as_vec3()).as_dvec3();
                assert!((want - got).abs().max_element() < 1e-5, "{k}: {want} {got}");
            }
            let per_metre = 1.0 / c.texel_size;
            assert!(
                (f64::from(params.viewport[3]) / per_metre - 1.0).abs() < 1e-5,
                "{k}: {} px per unit, {per_metre} texels per metre",
                params.viewport[3]
            );
            assert!(params.has(staticscene::QUERY_FLAG_SHADOW));
            assert!(params.has(staticscene::QUERY_FLAG_SIZE));
            assert_eq!(
                params.filter_mask,
                u32::from(staticscene::FILTER_SUN_SHADOW)
            );
        }
    }

    /// The bake's box holds the scene: its bounds' corners land inside clip x, y in
    /// [-1, 1] and depth in [0, 1], for a low and a vertical sun.
    #[test]
    fn the_baked_sun_box_holds_the_bounds() {
        let bounds = (
            glam::Vec3::new(-40.0, -2.0, -30.0),
            glam::Vec3::new(50.0, 25.0, 20.0),
        );
        for sun in [glam::Vec3::new(0.4, 0.3, 0.2), glam::Vec3::Y] {
            let m = baked_sun_matrix(bounds, sun);
            for i in 0..8 {
                let p = glam::Vec3::new(
                    if i & 1 == 0 { bounds.0.x } else { bounds.1.x },
                    if i & 2 == 0 { bounds.0.y } else { bounds.1.y },
                    if i & 4 == 0 { bounds.0.z } else { bounds.1.z },
                );
                let c = m * p.extend(1.0);
                assert!(
                    c.x.abs() <= 1.0 + 1e-5 && c.y.abs() <= 1.0 + 1e-5,
                    "{sun} {p}: {c}"
                );
                assert!((-1e-5..=1.0 + 1e-5).contains(&c.z), "{sun} {p}: {c}");
            }
            // Nearer the sun is smaller depth.
            let centre = (bounds.0 + bounds.1) * 0.5;
            let a = m * centre.extend(1.0);
            let b = m * (centre + sun.normalize() * 5.0).extend(1.0);
            assert!(b.z < a.z, "{sun}");
        }
    }
}
