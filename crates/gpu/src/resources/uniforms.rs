//! The per-frame constants built from a [`FrameInput`] (the input types themselves live
//! in the `scene` crate) and the frame's local lights as `deferred`'s rows.

use deferred::DeferredLight;
use glam::{Mat4, Vec3};

use crate::resources::rows::FrameUniforms;
pub(crate) use scene::{Camera, FrameInput};
use scene::{Lighting, Wind};

/// Where the previous frame's camera was, for `prev_view_proj`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PreviousCamera {
    /// Its camera-relative view-projection.
    pub view_proj: Mat4,
    /// Its position (world).
    pub position: Vec3,
    /// Its time (seconds): the animated foliage's previous pose.
    pub time: f32,
}

/// The frame constants of `frame` for a scene prepared around `origin`, at
/// `width` × `height` pixels. `previous`: the last frame's camera on the same scene (none on
/// a first frame: no motion). `wind`: the scene's (`None`: nothing sways).
pub(crate) fn frame_uniforms(
    frame: &FrameInput,
    wind: Option<&Wind>,
    origin: Vec3,
    (width, height): (u32, u32),
    mip_bias: f32,
    frame_index: u32,
    previous: Option<PreviousCamera>,
) -> FrameUniforms {
    let aspect = width as f32 / height.max(1) as f32;
    let camera = &frame.camera;
    let vp = camera.relative_view_projection(aspect);
    // Last frame's clip position of a point at camera-relative p: its position relative
    // to the previous camera is p + (camera - previous camera).
    let prev = previous.map_or(vp, |p| {
        p.view_proj * Mat4::from_translation(camera.position - p.position)
    });
    let l = &frame.lighting;
    FrameUniforms {
        view_proj: vp.to_cols_array_2d(),
        inv_view_proj: vp.inverse().to_cols_array_2d(),
        prev_view_proj: prev.to_cols_array_2d(),
        camera_position: camera.position.extend(1.0).to_array(),
        origin_offset: (origin - camera.position).extend(0.0).to_array(),
        viewport: [
            width as f32,
            height as f32,
            1.0 / width.max(1) as f32,
            1.0 / height.max(1) as f32,
        ],
        sun_direction: l.sun_direction.normalize_or(Vec3::Y).extend(0.0).to_array(),
        sun_color: l.sun_color.extend(0.0).to_array(),
        ambient: l.ambient.extend(0.0).to_array(),
        sky: l.sky.extend(0.0).to_array(),
        local_light_count: (l.point_lights.len() + l.spot_lights.len()) as u32,
        mip_bias,
        frame_index,
        time: frame.time,
        baked_sun: [[0.0; 4]; 4],
        view_rotation: camera.view_rotation().to_cols_array_2d(),
        wind: wind.map_or([0.0; 4], Wind::uniform),
        prev_time: previous.map_or(frame.time, |p| p.time),
        _pad: [0.0; 3],
        vrs: [0.0; 4],
    }
}

/// The local lights of `lighting` in the view space of `camera` (right-handed, looking
/// down −Z, as `deferred::lights` takes them): the point lights, then the spot lights,
/// flagged spot, shadow-casting and without specular as each says.
#[must_use]
pub fn local_light_rows(lighting: &Lighting, camera: &Camera) -> Vec<DeferredLight> {
    let specular = |row: DeferredLight, on: bool| if on { row } else { row.without_specular() };
    let rotation = camera.view_rotation();
    let at = |p: Vec3| rotation.transform_vector3(p - camera.position);
    let points = lighting.point_lights.iter().map(|l| {
        specular(
            DeferredLight::point(at(l.position), l.radius, l.color),
            l.specular,
        )
    });
    let spots = lighting.spot_lights.iter().map(|l| {
        let row = DeferredLight::spot(
            at(l.position),
            rotation.transform_vector3(l.direction.normalize_or(Vec3::NEG_Z)),
            l.radius,
            l.half_angle,
            l.color,
        );
        specular(if l.shadow { row.with_shadow() } else { row }, l.specular)
    });
    points.chain(spots).collect()
}

#[cfg(test)]
mod tests {
    use glam::Vec4;
    use scene::{PointLight, SpotLight};

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

    /// View-space lights against `Camera::view` applied to world positions (f64 of the
    /// same transform): points then spots, directions rotated and unit.
    #[test]
    fn local_light_rows_are_in_view_space() {
        let cam = camera();
        let lighting = Lighting {
            point_lights: vec![PointLight {
                position: Vec3::new(12.0, 3.0, -9.0),
                color: Vec3::ONE,
                radius: 4.0,
                specular: true,
            }],
            spot_lights: vec![SpotLight {
                position: Vec3::new(9.0, 5.0, -2.0),
                direction: Vec3::new(0.0, -2.0, 0.0),
                color: Vec3::ONE,
                radius: 6.0,
                half_angle: 0.4,
                shadow: false,
                specular: false,
            }],
            ..Lighting::default()
        };
        let rows = local_light_rows(&lighting, &cam);
        assert!(rows[0].has_specular() && !rows[1].has_specular());
        let view = cam.view().as_dmat4();
        assert_eq!(rows.len(), 2);
        for (row, world) in rows
            .iter()
            .zip([Vec3::new(12.0, 3.0, -9.0), Vec3::new(9.0, 5.0, -2.0)])
        {
            let want = view.transform_point3(world.as_dvec3());
            let got = Vec3::from(row.position).as_dvec3();
            assert!((want - got).length() < 1e-4, "{want} vs {got}");
        }
        assert!(!rows[0].is_spot() && rows[1].is_spot());
        let d = view.transform_vector3(glam::DVec3::NEG_Y);
        assert!((Vec3::from(rows[1].direction).as_dvec3() - d).length() < 1e-5);
        assert!((rows[1].cos_outer - 0.4f32.cos()).abs() < 1e-6);
    }

    #[test]
    fn previous_view_projection_maps_to_last_frames_clip_space() {
        let before = camera();
        let mut now = before;
        now.position += Vec3::new(0.7, -0.1, 0.4);
        now.target += Vec3::new(1.0, 0.0, 0.0);
        let origin = Vec3::new(11.0, 0.0, 0.0);
        let prev = PreviousCamera {
            view_proj: before.relative_view_projection(2.0),
            position: before.position,
            time: 0.0,
        };
        let u = frame_uniforms(
            &FrameInput::new(now),
            None,
            origin,
            (200, 100),
            0.0,
            1,
            Some(prev),
        );
        let p = Vec3::new(14.0, 1.5, 9.0);
        let expected = before.view_projection(2.0) * p.extend(1.0);
        let got = Mat4::from_cols_array_2d(&u.prev_view_proj) * (p - now.position).extend(1.0);
        assert!(
            (expected / expected.w - got / got.w).abs().max_element() < 1e-5,
            "{expected} {got}"
        );
        // The origin offset turns origin-relative into camera-relative positions.
        let o = Vec4::from(u.origin_offset).truncate();
        assert!(((p - origin) + o - (p - now.position)).abs().max_element() < 1e-5);
        // No previous frame: no motion.
        let first = frame_uniforms(
            &FrameInput::new(now),
            None,
            origin,
            (200, 100),
            0.0,
            0,
            None,
        );
        assert_eq!(first.prev_view_proj, first.view_proj);
    }
}
