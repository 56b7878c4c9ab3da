//! Views and the query's uniform block ([`QueryParams`]).
//!
//! # Conventions
//!
//! - World space: metres, f64 positions ([`DVec3`]), right-handed; the axes mean whatever
//!   the caller's projection says (glam's `*_rh` projections look down -Z with +Y up).
//! - Floating space: world space minus the view's *snapped origin*, the camera position
//!   rounded to the nearest integer metre ([`snap_origin`]). Everything the query outputs
//!   (transforms, spheres) is in floating space, in f32.
//! - Clip space: `projection * view`, wgpu's conventions: `x, y` in `[-w, w]`, `z` in
//!   `[0, w]`, depth `z / w`. With `reversed_depth` the near plane has depth 1 and the far
//!   plane depth 0 (and an infinite far plane is allowed).
//! - Pixels: `(0, 0)` is the top-left of the viewport, `+y` down; NDC `+y` is up.

use glam::{DMat4, DQuat, DVec3, IVec3, Mat4, Vec3, Vec4};

use crate::{Error, MAX_FADE_FRAMES, MAX_VIEWPORT, records::WORLD_MAX};

/// Query flag: update and use LOD fade states (camera views).
pub const QUERY_FLAG_FADE: u32 = 1;
/// Query flag: test occlusion against the HiZ pyramid.
pub const QUERY_FLAG_OCCLUSION: u32 = 2;
/// Query flag: depth is reversed (near 1, far 0).
pub const QUERY_FLAG_REVERSED_DEPTH: u32 = 4;
/// Query flag: the screen-size threshold is on.
pub const QUERY_FLAG_SIZE: u32 = 8;
/// Query flag: the first pass of two-pass occlusion ([`OcclusionPass::First`]).
pub const QUERY_FLAG_FIRST_PASS: u32 = 16;
/// Query flag: the second pass of two-pass occlusion ([`OcclusionPass::Second`]).
pub const QUERY_FLAG_SECOND_PASS: u32 = 32;
/// Query flag: a shadow view ([`ViewKind::Shadow`]: no fade, no occlusion, no camera
/// state); GPU queries run it through the pass's shadow variant (feature `shadow_view`).
pub const QUERY_FLAG_SHADOW: u32 = 64;

/// Bit of an instance's camera state byte (beside its fade state, `0..=MAX_FADE_FRAMES`):
/// the instance passed every test, occlusion included, in the last camera query that
/// wrote it (a [`OcclusionPass::Single`] query with fading, or a
/// [`OcclusionPass::Second`]).
pub const CAMERA_STATE_VISIBLE: u8 = 0x80;

/// Which pass of the occlusion scheme a camera view's query is.
///
/// Two-pass occlusion (RedLynx, niagara, Nanite; beyond HZD, which tests against the
/// previous frame's depth): the [`First`](OcclusionPass::First) pass outputs what passes
/// every other test and was visible last frame ([`CAMERA_STATE_VISIBLE`]); the caller draws
/// it, builds a HiZ of that depth with this frame's camera, and runs the
/// [`Second`](OcclusionPass::Second) pass against it (`occlusion_camera` = this frame's
/// camera), which outputs only what is visible and was not drawn by the first. Both passes
/// take the same view otherwise. Conservative for any camera motion: the first pass's depth
/// is this frame's real geometry.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum OcclusionPass {
    /// One query, occlusion against whatever HiZ the caller gives (HZD: the previous
    /// frame's depth, reprojected through `occlusion_camera`).
    #[default]
    Single,
    /// Two-pass occlusion's first pass: an instance not visible last frame is culled as
    /// occluded (no HiZ is read); no state is written.
    First,
    /// Two-pass occlusion's second pass: every test against the HiZ of the first pass's
    /// depth; fade and visibility states updated; instances the first pass output are
    /// counted in [`QueryStats::drawn_early`](crate::QueryStats::drawn_early), not output.
    Second,
}

/// A camera in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Position, world metres.
    pub position: DVec3,
    /// Orientation: view space to world space (a rotation; the view looks down its -Z).
    pub rotation: DQuat,
    /// View space to clip space (wgpu depth 0..1), e.g. `Mat4::perspective_rh`,
    /// `Mat4::perspective_infinite_reverse_rh`, `Mat4::orthographic_rh`.
    pub projection: Mat4,
    /// Whether `projection` maps near to depth 1 and far to depth 0.
    pub reversed_depth: bool,
}

impl Camera {
    /// A camera at `position` looking at `target` with `up` (world metres).
    #[must_use]
    pub fn look_at(
        position: DVec3,
        target: DVec3,
        up: DVec3,
        projection: Mat4,
        reversed_depth: bool,
    ) -> Camera {
        let view = DMat4::look_at_rh(position, target, up);
        let (_, rot, _) = view.inverse().to_scale_rotation_translation();
        Camera {
            position,
            rotation: rot,
            projection,
            reversed_depth,
        }
    }

    /// World to view space (f64).
    #[must_use]
    pub fn view_from_world(&self) -> DMat4 {
        DMat4::from_quat(self.rotation.inverse()) * DMat4::from_translation(-self.position)
    }

    /// Floating space of `origin` to clip space, built in f64 and rounded once.
    #[must_use]
    pub fn clip_from_floating(&self, origin: IVec3) -> Mat4 {
        let cam_floating = self.position - origin.as_dvec3();
        let view =
            DMat4::from_quat(self.rotation.inverse()) * DMat4::from_translation(-cam_floating);
        (self.projection.as_dmat4() * view).as_mat4()
    }

    fn is_finite(&self) -> bool {
        self.position.is_finite()
            && self.rotation.is_finite()
            && self.projection.is_finite()
            && self.position.abs().max_element() <= WORLD_MAX
    }
}

/// The kind of view: what it reads and updates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ViewKind {
    /// The player camera: LOD fade states are updated, occlusion is available.
    Camera,
    /// A shadow view (orthographic sun cascade or a perspective local light): no fade,
    /// no occlusion ("used for player camera queries, not shadow maps").
    Shadow,
}

/// Everything a query needs to know about one view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewDesc {
    /// The camera that renders this view.
    pub camera: Camera,
    /// Camera or shadow.
    pub kind: ViewKind,
    /// Viewport in pixels (width, height).
    pub viewport: [u32; 2],
    /// Filter bits this view draws (`FILTER_*`).
    pub filter: u8,
    /// Where LOD distances are measured from, world metres: the player camera for every
    /// view, so shadows use the LODs the camera sees.
    pub lod_position: DVec3,
    /// Global LOD distance multiplier (> 0; objects flagged to ignore it use 1).
    pub lod_scale: f32,
    /// Cull instances whose projected bounding-sphere diameter is below this many pixels;
    /// 0 turns the test off.
    pub size_threshold_px: f32,
    /// LOD fade length in frames (camera views; 0 = switch instantly).
    pub fade_frames: u32,
    /// The camera the previous frame's depth (the HiZ) was rendered with; `None` turns
    /// occlusion off. Only camera views use it.
    pub occlusion_camera: Option<Camera>,
    /// The previous frame's snapped origin, for [`DrawableSetupInstancePrev`](crate::DrawableSetupInstancePrev);
    /// `None` = this frame's.
    pub previous_origin: Option<IVec3>,
    /// Footprints whose 2x2-texel level is at least this mip level are scanned this many
    /// levels finer (the talk's "scan box of texels for larger objects"); see
    /// [`HiZ::occluded`](crate::HiZ::occluded). 0 = always four texels.
    pub hiz_scan_levels: u32,
    /// Single-pass or one of two-pass occlusion's passes (camera views only).
    pub occlusion_pass: OcclusionPass,
}

impl ViewDesc {
    /// A camera view with the defaults: all of `FILTER_VISUAL`, LOD from the camera, LOD
    /// scale 1, 1-pixel size threshold, an 8-frame fade, no occlusion, 2 scan levels.
    #[must_use]
    pub fn camera(camera: Camera, viewport: [u32; 2]) -> ViewDesc {
        ViewDesc {
            camera,
            kind: ViewKind::Camera,
            viewport,
            filter: crate::FILTER_VISUAL,
            lod_position: camera.position,
            lod_scale: 1.0,
            size_threshold_px: 1.0,
            fade_frames: 8,
            occlusion_camera: None,
            previous_origin: None,
            hiz_scan_levels: 2,
            occlusion_pass: OcclusionPass::Single,
        }
    }

    /// A shadow view of `camera` (the light), with LODs measured from `lod_position`.
    #[must_use]
    pub fn shadow(camera: Camera, viewport: [u32; 2], filter: u8, lod_position: DVec3) -> ViewDesc {
        ViewDesc {
            kind: ViewKind::Shadow,
            filter,
            lod_position,
            fade_frames: 0,
            ..ViewDesc::camera(camera, viewport)
        }
    }
}

/// The snapped origin of a camera at `position`: each coordinate rounded to the nearest
/// integer metre.
#[must_use]
pub fn snap_origin(position: DVec3) -> IVec3 {
    crate::records::snap(position)
}

/// The query's uniform block, one per view: the CPU twin of the compute shader's
/// constants (WGSL `StaticsceneQueryParams`, 320 bytes). Build it with
/// [`QueryParams::new`].
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct QueryParams {
    /// Floating space to clip space, columns.
    pub clip_from_floating: [[f32; 4]; 4],
    /// Floating space to the clip space of the frame the HiZ was rendered in, columns.
    pub hiz_clip_from_floating: [[f32; 4]; 4],
    /// Frustum planes `(n, d)`, inside where `n · p + d >= 0`, `|n| = 1` (or `n = 0`):
    /// left, right, bottom, top, near, far.
    pub planes: [[f32; 4]; 6],
    /// View axis: depth along it of a floating point `p` is `xyz · p + w`.
    pub forward: [f32; 4],
    /// LOD point (floating space) in xyz; global LOD scale in w.
    pub lod_point: [f32; 4],
    /// Snapped origin (xyz; w = 0).
    pub origin: [i32; 4],
    /// Previous frame's snapped origin (xyz; w = 0).
    pub prev_origin: [i32; 4],
    /// Viewport width, height (pixels), size threshold (pixels), pixels per unit of
    /// `radius / w` (the larger of `|P00| w / 2` and `|P11| h / 2`).
    pub viewport: [f32; 4],
    /// Filter bits.
    pub filter_mask: u32,
    /// `QUERY_FLAG_*`.
    pub flags: u32,
    /// LOD fade length, frames (1..=127 when fading).
    pub fade_frames: u32,
    /// HiZ scan levels.
    pub hiz_scan_levels: u32,
}

const _: () = assert!(size_of::<QueryParams>() == 320);

fn plane(v: Vec4) -> [f32; 4] {
    let n = v.truncate().length();
    if n > 0.0 && n.is_finite() {
        (v / n).to_array()
    } else {
        // A plane at infinity (infinite far): keep only the sign of d.
        [0.0, 0.0, 0.0, if v.w >= 0.0 { 1.0 } else { -1.0 }]
    }
}

impl QueryParams {
    /// The uniform block of `view`. Fails on a viewport outside 1..=[`MAX_VIEWPORT`], a
    /// non-finite camera, a fade longer than [`MAX_FADE_FRAMES`], or a LOD scale that is
    /// not positive and finite.
    pub fn new(view: &ViewDesc) -> Result<QueryParams, Error> {
        let [w, h] = view.viewport;
        if w == 0 || h == 0 || w > MAX_VIEWPORT || h > MAX_VIEWPORT {
            return Err(Error::Viewport {
                width: w,
                height: h,
            });
        }
        let cam = &view.camera;
        if !cam.is_finite()
            || !view.lod_position.is_finite()
            || view.lod_position.abs().max_element() > WORLD_MAX
            || view.occlusion_camera.is_some_and(|c| !c.is_finite())
        {
            return Err(Error::NonFiniteCamera);
        }
        if view.fade_frames > MAX_FADE_FRAMES {
            return Err(Error::FadeFrames {
                frames: view.fade_frames,
            });
        }
        if !(view.lod_scale > 0.0 && view.lod_scale.is_finite()) {
            return Err(Error::FloatOutOfRange {
                field: crate::Field::LodScale,
                value: f64::from(view.lod_scale),
                max: f64::from(f32::MAX),
            });
        }
        if !(view.size_threshold_px >= 0.0 && view.size_threshold_px.is_finite()) {
            return Err(Error::Config {
                what: "size threshold must be finite and >= 0",
            });
        }
        let origin = snap_origin(cam.position);
        let m = cam.clip_from_floating(origin);
        let r0 = m.row(0);
        let r1 = m.row(1);
        let r2 = m.row(2);
        let r3 = m.row(3);
        let planes = [
            plane(r3 + r0),
            plane(r3 - r0),
            plane(r3 + r1),
            plane(r3 - r1),
            plane(r2),
            plane(r3 - r2),
        ];
        let cam_floating = (cam.position - origin.as_dvec3()).as_vec3();
        let fwd = (cam.rotation * DVec3::NEG_Z).as_vec3();
        let lod_point = (view.lod_position - origin.as_dvec3()).as_vec3();
        let p = cam.projection;
        let px_per_unit =
            (p.x_axis.x.abs() * w as f32 * 0.5).max(p.y_axis.y.abs() * h as f32 * 0.5);
        let camera = view.kind == ViewKind::Camera;
        let mut flags = 0;
        let fade_frames = if camera { view.fade_frames } else { 0 };
        if fade_frames > 0 {
            flags |= QUERY_FLAG_FADE;
        }
        let hiz = match (camera, view.occlusion_camera) {
            (true, Some(c)) => {
                flags |= QUERY_FLAG_OCCLUSION;
                c.clip_from_floating(origin)
            }
            _ => Mat4::ZERO,
        };
        if cam.reversed_depth {
            flags |= QUERY_FLAG_REVERSED_DEPTH;
        }
        if view.size_threshold_px > 0.0 {
            flags |= QUERY_FLAG_SIZE;
        }
        if !camera {
            flags |= QUERY_FLAG_SHADOW;
        }
        match (camera, view.occlusion_pass) {
            (true, OcclusionPass::First) => flags |= QUERY_FLAG_FIRST_PASS,
            (true, OcclusionPass::Second) => flags |= QUERY_FLAG_SECOND_PASS,
            _ => {}
        }
        let prev = view.previous_origin.unwrap_or(origin);
        Ok(QueryParams {
            clip_from_floating: m.to_cols_array_2d(),
            hiz_clip_from_floating: hiz.to_cols_array_2d(),
            planes,
            forward: [fwd.x, fwd.y, fwd.z, -fwd.dot(cam_floating)],
            lod_point: [lod_point.x, lod_point.y, lod_point.z, view.lod_scale],
            origin: [origin.x, origin.y, origin.z, 0],
            prev_origin: [prev.x, prev.y, prev.z, 0],
            viewport: [w as f32, h as f32, view.size_threshold_px, px_per_unit],
            filter_mask: u32::from(view.filter & crate::FILTER_ALL),
            flags,
            fade_frames,
            hiz_scan_levels: view.hiz_scan_levels.min(8),
        })
    }

    /// The snapped origin.
    #[must_use]
    #[inline]
    pub fn origin(&self) -> IVec3 {
        IVec3::new(self.origin[0], self.origin[1], self.origin[2])
    }

    /// The previous frame's snapped origin.
    #[must_use]
    #[inline]
    pub fn prev_origin(&self) -> IVec3 {
        IVec3::new(
            self.prev_origin[0],
            self.prev_origin[1],
            self.prev_origin[2],
        )
    }

    /// The LOD point in floating space.
    #[must_use]
    #[inline]
    pub fn lod_point(&self) -> Vec3 {
        Vec3::new(self.lod_point[0], self.lod_point[1], self.lod_point[2])
    }

    /// Floating to clip.
    #[must_use]
    pub fn clip_from_floating(&self) -> Mat4 {
        Mat4::from_cols_array_2d(&self.clip_from_floating)
    }

    /// Floating to the HiZ frame's clip space.
    #[must_use]
    pub fn hiz_clip_from_floating(&self) -> Mat4 {
        Mat4::from_cols_array_2d(&self.hiz_clip_from_floating)
    }

    /// Whether a flag is set.
    #[must_use]
    #[inline]
    pub fn has(&self, flag: u32) -> bool {
        self.flags & flag != 0
    }
}

/// The relative tolerance of the frustum tests: a box is outside a plane only if it is
/// beyond it by more than this fraction of the magnitudes involved (absorbs f32 rounding,
/// so the test stays conservative against an exact one).
pub const FRUSTUM_TOLERANCE: f32 = 1e-5;

/// Whether the box `[min, max]` (floating space) is entirely outside one of `planes`
/// (conservative: a box within rounding of a plane is kept).
#[inline]
pub fn box_outside_frustum(planes: &[[f32; 4]; 6], min: Vec3, max: Vec3) -> bool {
    for p in planes {
        // The corner furthest along the normal.
        let x = if p[0] >= 0.0 { max.x } else { min.x };
        let y = if p[1] >= 0.0 { max.y } else { min.y };
        let z = if p[2] >= 0.0 { max.z } else { min.z };
        let (a, b, c) = (p[0] * x, p[1] * y, p[2] * z);
        let d = a + b + c + p[3];
        let mag = a.abs() + b.abs() + c.abs() + p[3].abs();
        if d < -FRUSTUM_TOLERANCE * mag {
            return true;
        }
    }
    false
}
