//! Fixtures shared by the integration tests (each test file includes this as a module).

use deferred::Surface;
use glam::{Vec2, Vec3};

/// A surface with every kind of bad value (NaN, infinities, out of range): packing must
/// sanitise it, the same way on the CPU and the GPU.
pub fn bad_surface() -> Surface {
    Surface {
        lighting: Vec3::new(f32::NAN, f32::INFINITY, -1.0),
        albedo: Vec3::new(f32::NAN, 2.0, -1.0),
        normal: Vec3::new(f32::NAN, 0.0, 0.0),
        roughness: f32::NAN,
        specular: f32::INFINITY,
        metallic: f32::NAN,
        sun_shadow: -3.0,
        motion: Vec2::new(f32::NAN, 1e9),
    }
}
