//! What changes from frame to frame: the camera, the time, the sun and the lights
//! ([`FrameInput`]), checked before a frame renders.
//!
//! Conventions: right-handed world space, +Y up, metres, radians. Cameras look down their
//! local −Z. Projections use reversed Z (near plane at depth 1, far plane at depth 0,
//! infinite far plane), so `Depth32Float` keeps its precision far away; depth tests are
//! `Greater`.

use glam::{Mat4, Vec3, Vec4};

use crate::error::FrameError;
use crate::model::check_range;

/// The most point and spot lights a frame may carry, together. Lighting reads each
/// 16x16-pixel tile's list (at most [`deferred::lights::MAX_LIGHTS_PER_TILE`] lights: a
/// tile that meets more keeps the lowest-indexed ones). KZ2 lit 100+ lights per frame, up
/// to 300 on screen.
pub const MAX_LOCAL_LIGHTS: usize = 4096;

/// A perspective camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position (world, metres).
    pub position: Vec3,
    /// The point looked at (world, metres); not the eye position.
    pub target: Vec3,
    /// The world direction that is up on screen; must not be parallel to the view
    /// direction (+Y for a level camera; pick another to look straight up or down).
    pub up: Vec3,
    /// Vertical field of view in radians, in (0, π).
    pub fov_y: f32,
    /// Near plane distance (metres), > 0; the far plane is at infinity (reversed Z).
    pub near: f32,
}

impl Camera {
    /// A camera at `position` looking at `target`, +Y up, 60° vertical field of view, near
    /// plane at 0.1 m.
    #[must_use]
    pub fn look_at(position: Vec3, target: Vec3) -> Self {
        Self {
            position,
            target,
            up: Vec3::Y,
            fov_y: 60f32.to_radians(),
            near: 0.1,
        }
    }

    /// World-to-view matrix (right-handed, looking down −Z).
    #[must_use]
    pub fn view(&self) -> Mat4 {
        Mat4::look_at_rh(self.position, self.target, self.up)
    }

    /// View-to-clip matrix for `aspect` = width / height: reversed Z, infinite far plane.
    #[must_use]
    pub fn projection(&self, aspect: f32) -> Mat4 {
        Mat4::perspective_infinite_reverse_rh(self.fov_y, aspect, self.near)
    }

    /// World-to-clip.
    #[must_use]
    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        self.projection(aspect) * self.view()
    }

    /// The view matrix's rotation alone: camera-relative world position to view space.
    #[must_use]
    pub fn view_rotation(&self) -> Mat4 {
        let view = self.view();
        Mat4::from_cols(view.x_axis, view.y_axis, view.z_axis, Vec4::W)
    }

    /// Camera-relative-position-to-clip: the rotation and projection only, what the shaders
    /// use (positions are camera-relative on the GPU).
    #[must_use]
    pub fn relative_view_projection(&self, aspect: f32) -> Mat4 {
        self.projection(aspect) * self.view_rotation()
    }

    /// Checks every field: finite, a positive near plane, a field of view in (0, π), a
    /// target away from the eye and an up vector not parallel to the view direction.
    ///
    /// # Errors
    /// [`FrameError::OutOfRange`] or [`FrameError::CameraBasis`], naming the field.
    pub fn validate(&self) -> Result<(), FrameError> {
        finite3("camera.position", self.position)?;
        finite3("camera.target", self.target)?;
        finite3("camera.up", self.up)?;
        range(
            || "camera.fov_y".into(),
            self.fov_y,
            f32::MIN_POSITIVE,
            std::f32::consts::PI * (1.0 - f32::EPSILON),
            "(0, π) radians",
        )?;
        range(
            || "camera.near".into(),
            self.near,
            f32::MIN_POSITIVE,
            f32::MAX,
            "finite, > 0 metres",
        )?;
        let dir = self.target - self.position;
        if dir.length_squared() < 1e-12 {
            return Err(FrameError::CameraBasis {
                detail: "camera.target equals camera.position: there is no view direction",
            });
        }
        if self.up.length_squared() < 1e-12 {
            return Err(FrameError::CameraBasis {
                detail: "camera.up is zero",
            });
        }
        // sin of the angle between them under ~0.06° leaves no stable right vector.
        if dir.normalize().cross(self.up.normalize()).length() < 1e-3 {
            return Err(FrameError::CameraBasis {
                detail: "camera.up is parallel to the view direction (looking straight up or \
                         down along it); choose another up vector",
            });
        }
        Ok(())
    }
}

/// A point light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLight {
    /// World position (metres).
    pub position: Vec3,
    /// Linear RGB intensity, each channel finite and >= 0 (1 lights a white surface at
    /// 1 m to 1).
    pub color: Vec3,
    /// Distance at which the light fades to zero (metres), finite and > 0.
    pub radius: f32,
    /// Has a specular term (GGX over the surface's specular intensity and roughness);
    /// `false`: diffuse alone, KZ2's no-specular light shader (the stencil-volume path
    /// draws it with a pipeline compiled without the term, the compute lighting branches).
    pub specular: bool,
}

/// A spot light: a cone from `position` along `direction`, to `radius` metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpotLight {
    /// World position of the apex (metres).
    pub position: Vec3,
    /// World direction of the cone's axis (normalised by the renderer), finite, non-zero.
    pub direction: Vec3,
    /// Linear RGB intensity, as [`PointLight::color`].
    pub color: Vec3,
    /// Distance at which the light fades to zero (metres), finite and > 0.
    pub radius: f32,
    /// Half-angle of the cone (radians), in `(0, π/2)`; the edge softens over the outer
    /// quarter of its cosine range.
    pub half_angle: f32,
    /// Casts shadows: the renderer gives it a shadow map while it covers enough of the
    /// screen (`gpu::config::SpotShadowConfig`: KZ2's fade, a limited number of maps, largest
    /// lights first); otherwise it lights unshadowed.
    pub shadow: bool,
    /// Has a specular term, as [`PointLight::specular`].
    pub specular: bool,
}

/// Sun, sky and lights.
#[derive(Clone, Debug, PartialEq)]
pub struct Lighting {
    /// Direction *towards* the sun (world; normalised by the renderer), finite, non-zero.
    pub sun_direction: Vec3,
    /// Sun colour (linear RGB, each channel finite and >= 0).
    pub sun_color: Vec3,
    /// Constant ambient term (linear RGB, finite, >= 0).
    pub ambient: Vec3,
    /// Sky colour behind everything (linear RGB, finite, >= 0).
    pub sky: Vec3,
    /// Point lights ([`MAX_LOCAL_LIGHTS`] with the spot lights).
    pub point_lights: Vec<PointLight>,
    /// Spot lights ([`MAX_LOCAL_LIGHTS`] with the point lights).
    pub spot_lights: Vec<SpotLight>,
}

impl Default for Lighting {
    fn default() -> Self {
        Self {
            sun_direction: Vec3::new(0.4, 0.8, 0.3).normalize(),
            sun_color: Vec3::new(2.6, 2.4, 2.1),
            ambient: Vec3::new(0.18, 0.22, 0.28),
            sky: Vec3::new(0.45, 0.62, 0.9),
            point_lights: Vec::new(),
            spot_lights: Vec::new(),
        }
    }
}

impl Lighting {
    /// Checks every value (see the fields).
    ///
    /// # Errors
    /// [`FrameError::OutOfRange`] naming the field, or [`FrameError::TooManyLocalLights`].
    pub fn validate(&self) -> Result<(), FrameError> {
        let colour = |field: &str, v: Vec3| -> Result<(), FrameError> {
            for (k, c) in ["r", "g", "b"].into_iter().zip(v.to_array()) {
                range(|| format!("{field}.{k}"), c, 0.0, f32::MAX, "finite, >= 0")?;
            }
            Ok(())
        };
        finite3("lighting.sun_direction", self.sun_direction)?;
        if self.sun_direction.length_squared() < 1e-12 {
            return Err(FrameError::OutOfRange {
                field: "lighting.sun_direction".into(),
                value: 0.0,
                allowed: "a non-zero direction",
            });
        }
        colour("lighting.sun_color", self.sun_color)?;
        colour("lighting.ambient", self.ambient)?;
        colour("lighting.sky", self.sky)?;
        let local = self.point_lights.len() + self.spot_lights.len();
        if local > MAX_LOCAL_LIGHTS {
            return Err(FrameError::TooManyLocalLights {
                count: local,
                limit: MAX_LOCAL_LIGHTS,
            });
        }
        for (i, l) in self.point_lights.iter().enumerate() {
            finite3(&format!("lighting.point_lights[{i}].position"), l.position)?;
            colour(&format!("lighting.point_lights[{i}].color"), l.color)?;
            range(
                || format!("lighting.point_lights[{i}].radius"),
                l.radius,
                f32::MIN_POSITIVE,
                f32::MAX,
                "finite, > 0 metres",
            )?;
        }
        for (i, l) in self.spot_lights.iter().enumerate() {
            finite3(&format!("lighting.spot_lights[{i}].position"), l.position)?;
            finite3(&format!("lighting.spot_lights[{i}].direction"), l.direction)?;
            if l.direction.length_squared() < 1e-12 {
                return Err(FrameError::OutOfRange {
                    field: format!("lighting.spot_lights[{i}].direction"),
                    value: 0.0,
                    allowed: "a non-zero direction",
                });
            }
            colour(&format!("lighting.spot_lights[{i}].color"), l.color)?;
            range(
                || format!("lighting.spot_lights[{i}].radius"),
                l.radius,
                f32::MIN_POSITIVE,
                f32::MAX,
                "finite, > 0 metres",
            )?;
            range(
                || format!("lighting.spot_lights[{i}].half_angle"),
                l.half_angle,
                1e-3,
                core::f32::consts::FRAC_PI_2 - 1e-3,
                "in (0, π/2) radians",
            )?;
        }
        Ok(())
    }
}

/// Everything one frame takes: `gpu::Renderer::render` checks it, uploads the frame
/// constants and the lights.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameInput {
    /// The camera.
    pub camera: Camera,
    /// Seconds since the application's start (animation time), finite.
    pub time: f32,
    /// Sun, sky and point lights.
    pub lighting: Lighting,
}

impl FrameInput {
    /// A frame at time 0 with `camera` and the default lighting.
    #[must_use]
    pub fn new(camera: Camera) -> Self {
        Self {
            camera,
            time: 0.0,
            lighting: Lighting::default(),
        }
    }

    /// Checks the camera, the time and the lighting.
    ///
    /// # Errors
    /// The first [`FrameError`] found, naming the field and its allowed range.
    pub fn validate(&self) -> Result<(), FrameError> {
        self.camera.validate()?;
        range(
            || "time".into(),
            self.time,
            f32::MIN,
            f32::MAX,
            "finite seconds",
        )?;
        self.lighting.validate()
    }
}

/// Checks that every component of `v` is finite (`{field}.x`, `.y`, `.z` in the error).
fn finite3(field: &str, v: Vec3) -> Result<(), FrameError> {
    for (k, c) in ["x", "y", "z"].into_iter().zip(v.to_array()) {
        range(|| format!("{field}.{k}"), c, f32::MIN, f32::MAX, "finite")?;
    }
    Ok(())
}

fn range(
    field: impl FnOnce() -> String,
    value: f32,
    lo: f32,
    hi: f32,
    allowed: &'static str,
) -> Result<(), FrameError> {
    check_range(field, value, lo, hi, allowed).map_err(|(field, value, allowed)| {
        FrameError::OutOfRange {
            field,
            value,
            allowed,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera {
            position: Vec3::new(10.0, 2.0, -5.0),
            target: Vec3::new(12.0, 1.0, 5.0),
            up: Vec3::Y,
            fov_y: 1.0,
            near: 0.1,
        }
    }

    #[test]
    fn relative_projection_matches_the_full_one() {
        let c = camera();
        let full = c.view_projection(16.0 / 9.0);
        let rel = c.relative_view_projection(16.0 / 9.0);
        let p = Vec3::new(13.0, 0.5, 9.0);
        let a = full * p.extend(1.0);
        let b = rel * (p - c.position).extend(1.0);
        assert!((a / a.w - b / b.w).abs().max_element() < 1e-5, "{a} {b}");
    }

    #[test]
    fn bad_cameras_are_named() {
        let field = |c: Camera| match c.validate() {
            Err(FrameError::OutOfRange { field, .. }) => field,
            Err(FrameError::CameraBasis { detail }) => detail.into(),
            other => panic!("{other:?}"),
        };
        let c = camera();
        assert!(c.validate().is_ok());
        assert_eq!(field(Camera { fov_y: 3.2, ..c }), "camera.fov_y");
        assert_eq!(
            field(Camera {
                fov_y: std::f32::consts::PI,
                ..c
            }),
            "camera.fov_y"
        );
        assert_eq!(field(Camera { fov_y: 0.0, ..c }), "camera.fov_y");
        assert_eq!(field(Camera { near: 0.0, ..c }), "camera.near");
        assert_eq!(
            field(Camera {
                near: f32::NAN,
                ..c
            }),
            "camera.near"
        );
        assert_eq!(
            field(Camera {
                position: Vec3::new(f32::INFINITY, 0.0, 0.0),
                ..c
            }),
            "camera.position.x"
        );
        let straight_up = Camera {
            target: c.position + Vec3::Y * 5.0,
            ..c
        };
        assert!(field(straight_up).contains("parallel"));
        // Looking straight down is fine with another up vector.
        let down = Camera {
            target: c.position - Vec3::Y,
            up: Vec3::Z,
            ..c
        };
        assert!(down.validate().is_ok());
        assert!(
            field(Camera {
                target: c.position,
                ..c
            })
            .contains("no view direction")
        );
    }

    #[test]
    fn bad_lighting_is_named() {
        let light = PointLight {
            position: Vec3::ZERO,
            color: Vec3::ONE,
            radius: 5.0,
            specular: true,
        };
        let field = |l: Lighting| match l.validate() {
            Err(FrameError::OutOfRange { field, .. }) => field,
            other => panic!("{other:?}"),
        };
        assert!(Lighting::default().validate().is_ok());
        assert_eq!(
            field(Lighting {
                sun_direction: Vec3::new(f32::NAN, 1.0, 0.0),
                ..Lighting::default()
            }),
            "lighting.sun_direction.x"
        );
        assert_eq!(
            field(Lighting {
                sun_direction: Vec3::ZERO,
                ..Lighting::default()
            }),
            "lighting.sun_direction"
        );
        assert_eq!(
            field(Lighting {
                sky: Vec3::new(0.0, -1.0, 0.0),
                ..Lighting::default()
            }),
            "lighting.sky.g"
        );
        assert_eq!(
            field(Lighting {
                point_lights: vec![
                    light,
                    PointLight {
                        radius: f32::NAN,
                        ..light
                    }
                ],
                ..Lighting::default()
            }),
            "lighting.point_lights[1].radius"
        );
        assert_eq!(
            field(Lighting {
                point_lights: vec![PointLight {
                    color: Vec3::new(1.0, 1.0, f32::INFINITY),
                    ..light
                }],
                ..Lighting::default()
            }),
            "lighting.point_lights[0].color.b"
        );
        assert!(matches!(
            Lighting {
                point_lights: vec![light; MAX_LOCAL_LIGHTS + 1],
                ..Lighting::default()
            }
            .validate(),
            Err(FrameError::TooManyLocalLights { .. })
        ));
        let spot = SpotLight {
            position: Vec3::ZERO,
            direction: Vec3::NEG_Y,
            color: Vec3::ONE,
            radius: 5.0,
            half_angle: 0.5,
            shadow: false,
            specular: true,
        };
        let spot_field = |s: SpotLight| match (Lighting {
            spot_lights: vec![spot, s],
            ..Lighting::default()
        })
        .validate()
        {
            Err(FrameError::OutOfRange { field, .. }) => field,
            other => panic!("{other:?}"),
        };
        assert_eq!(
            spot_field(SpotLight {
                half_angle: 1.6,
                ..spot
            }),
            "lighting.spot_lights[1].half_angle"
        );
        assert_eq!(
            spot_field(SpotLight {
                direction: Vec3::ZERO,
                ..spot
            }),
            "lighting.spot_lights[1].direction"
        );
        assert_eq!(
            spot_field(SpotLight {
                radius: f32::NAN,
                ..spot
            }),
            "lighting.spot_lights[1].radius"
        );
        // Point and spot lights count together.
        assert!(matches!(
            Lighting {
                point_lights: vec![light; MAX_LOCAL_LIGHTS],
                spot_lights: vec![spot],
                ..Lighting::default()
            }
            .validate(),
            Err(FrameError::TooManyLocalLights { count, .. }) if count == MAX_LOCAL_LIGHTS + 1
        ));
        let mut f = FrameInput::new(camera());
        f.time = f32::NAN;
        assert!(
            matches!(f.validate(), Err(FrameError::OutOfRange { field, .. }) if field == "time")
        );
    }
}
