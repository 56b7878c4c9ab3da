//! The fly camera: a [`gpu::Camera`] moved along its own axes and turned by yaw and pitch.
//! A camera that has not been moved stays exactly the one it started from (the scripted
//! mode's screenshots compare with a headless render of that camera).

use gpu::Camera;
use gpu::glam::Vec3;

/// Pitch stays this far from straight up or down (radians), so the view never lines up
/// with the camera's +Y up vector.
const PITCH_LIMIT: f32 = 1.5;

/// Slowest and fastest speeds the wheel reaches (metres a second).
const SPEED_RANGE: (f32, f32) = (0.05, 1000.0);

/// A camera flown by keys and the mouse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlyCamera {
    camera: Camera,
    yaw: f32,
    pitch: f32,
    /// Movement speed (metres a second).
    pub speed: f32,
}

impl FlyCamera {
    /// A fly camera starting as `camera`, at 5 m/s.
    pub fn new(camera: Camera) -> Self {
        let d = (camera.target - camera.position).normalize_or(Vec3::NEG_Z);
        Self {
            camera,
            yaw: d.x.atan2(-d.z),
            pitch: d.y.clamp(-1.0, 1.0).asin().clamp(-PITCH_LIMIT, PITCH_LIMIT),
            speed: 5.0,
        }
    }

    /// The camera to render with.
    pub fn camera(&self) -> Camera {
        self.camera
    }

    /// The unit view direction.
    pub fn forward(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        Vec3::new(cp * sy, sp, -cp * cy)
    }

    /// Moves by `right`, `up` and `forward` units of the camera's axes (forward along the
    /// view direction, right level, up world +Y) times `seconds` times the speed.
    pub fn fly(&mut self, right: f32, up: f32, forward: f32, seconds: f32) {
        if right == 0.0 && up == 0.0 && forward == 0.0 {
            return;
        }
        let f = self.forward();
        let r = f.cross(Vec3::Y).normalize_or(Vec3::X);
        let step = (r * right + Vec3::Y * up + f * forward) * self.speed * seconds;
        if step.is_finite() {
            self.camera.position += step;
            self.camera.target += step;
        }
    }

    /// Turns by `yaw` (to the right) and `pitch` (up) radians.
    pub fn look(&mut self, yaw: f32, pitch: f32) {
        if (yaw == 0.0 && pitch == 0.0) || !yaw.is_finite() || !pitch.is_finite() {
            return;
        }
        self.yaw = (self.yaw + yaw) % std::f32::consts::TAU;
        self.pitch = (self.pitch + pitch).clamp(-PITCH_LIMIT, PITCH_LIMIT);
        let distance = self.camera.position.distance(self.camera.target).max(1e-3);
        self.camera.target = self.camera.position + self.forward() * distance;
    }

    /// Multiplies the speed by 1.25 per wheel step (negative steps slow down), within
    /// 0.05 to 1000 m/s.
    pub fn wheel(&mut self, steps: f32) {
        if steps.is_finite() {
            self.speed = (self.speed * 1.25f32.powf(steps)).clamp(SPEED_RANGE.0, SPEED_RANGE.1);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_unmoved_camera_is_the_one_given() {
        let c = Camera::look_at(Vec3::new(1.0, 2.0, 3.0), Vec3::new(-4.0, 0.5, 7.0));
        let mut f = FlyCamera::new(c);
        f.fly(0.0, 0.0, 0.0, 1.0);
        f.look(0.0, 0.0);
        assert_eq!(f.camera(), c);
        let d = (c.target - c.position).normalize();
        assert!(f.forward().distance(d) < 1e-5);
    }

    #[test]
    fn flying_moves_along_the_view_and_looking_turns_it() {
        let mut f = FlyCamera::new(Camera::look_at(Vec3::ZERO, Vec3::NEG_Z));
        f.speed = 2.0;
        f.fly(0.0, 0.0, 1.0, 0.5);
        assert!(f.camera().position.distance(Vec3::new(0.0, 0.0, -1.0)) < 1e-5);
        f.fly(1.0, 0.0, 0.0, 0.5);
        assert!(f.camera().position.distance(Vec3::new(1.0, 0.0, -1.0)) < 1e-5);
        f.look(std::f32::consts::FRAC_PI_2, 0.0);
        assert!(f.forward().distance(Vec3::X) < 1e-5);
        f.look(0.0, 10.0);
        f.camera().validate().unwrap();
        f.wheel(f32::NAN);
        f.wheel(1e9);
        assert_eq!(f.speed, 1000.0);
    }
}
