//! Shared helpers of the integration tests: scenes, cameras, and the f64 references.
#![allow(dead_code)]

use glam::{Affine3A, DMat4, DQuat, DVec3, DVec4, Mat3, Mat4, Vec3};
use staticscene::demo::{BOX_TRIANGLES, CityConfig, city};
use staticscene::{
    Aabb, BuildConfig, Camera, FILTER_ALL, MeshNode, MeshPart, PlacedObject, ResourceLibrary,
    Scene, StaticMesh, StreamingGroup, TileStreamer,
};

/// Builds a scene from resources and groups.
pub fn scene(resources: &[MeshNode], groups: &[StreamingGroup], config: BuildConfig) -> Scene {
    let mut streamer = TileStreamer::new(ResourceLibrary::new(resources), config);
    let mut scene = Scene::new();
    for g in groups {
        scene.apply(streamer.add_group(g).expect("group builds"));
    }
    scene
}

/// A scene of one streaming group of `objects`, all in one tile (no orphan tile): what
/// the tests that place a few objects by hand build.
pub fn one_group_scene(resources: &[MeshNode], objects: Vec<PlacedObject>) -> Scene {
    let config = BuildConfig {
        orphan_below: 0,
        ..BuildConfig::default()
    };
    scene(resources, &[group(0, objects)], config)
}

/// A small demo city (about `instances` instances) as a scene.
pub fn city_scene(instances: usize, seed: u64) -> (Scene, CityConfig) {
    let mut cfg = CityConfig::with_instances(instances);
    cfg.seed = seed;
    let c = city(&cfg);
    (scene(&c.resources, &c.groups, BuildConfig::default()), cfg)
}

/// A static leaf.
pub fn mesh(handle: u64, min: Vec3, max: Vec3) -> MeshNode {
    MeshNode::Static(StaticMesh {
        setup: handle,
        bounds: Aabb::new(min, max),
        filter: FILTER_ALL,
        flags: 0,
    })
}

/// A LOD switch.
pub fn lod(bounds: Aabb, levels: Vec<(f32, f32, MeshNode)>) -> MeshNode {
    MeshNode::lod(bounds, levels)
}

/// A one-part multi-mesh placing `node` with `t`.
pub fn placed(t: Affine3A, node: MeshNode) -> MeshNode {
    MeshNode::Multi(vec![MeshPart {
        local_to_parent: t,
        node,
    }])
}

/// A single group holding `objects`.
pub fn group(id: u64, objects: Vec<PlacedObject>) -> StreamingGroup {
    StreamingGroup { id, objects }
}

/// A perspective camera at `pos` looking at `target` (+Y up).
pub fn perspective(pos: DVec3, target: DVec3, fov: f32, aspect: f32, reversed: bool) -> Camera {
    let proj = if reversed {
        Mat4::perspective_infinite_reverse_rh(fov, aspect, 0.1)
    } else {
        Mat4::perspective_rh(fov, aspect, 0.1, 3000.0)
    };
    Camera::look_at(pos, target, up_for(pos, target), proj, reversed)
}

/// An orthographic camera (a sun view) at `pos` looking at `target`.
pub fn orthographic(pos: DVec3, target: DVec3, half: f32, reversed: bool) -> Camera {
    let proj = if reversed {
        Mat4::orthographic_rh(-half, half, -half, half, 2000.0, 0.1)
    } else {
        Mat4::orthographic_rh(-half, half, -half, half, 0.1, 2000.0)
    };
    Camera::look_at(pos, target, up_for(pos, target), proj, reversed)
}

fn up_for(pos: DVec3, target: DVec3) -> DVec3 {
    let d = (target - pos).normalize();
    if d.y.abs() > 0.99 { DVec3::Z } else { DVec3::Y }
}

/// World to clip in f64: the reference every test measures the query against.
pub fn clip_from_world(cam: &Camera) -> DMat4 {
    cam.projection.as_dmat4() * cam.view_from_world()
}

/// `p` through a row-major 3x4 affine transform (an instance's `rows`), in f64.
pub fn rows_f64(r: &[[f32; 4]; 3], p: DVec3) -> DVec3 {
    let row = |i: usize| {
        f64::from(r[i][0]) * p.x
            + f64::from(r[i][1]) * p.y
            + f64::from(r[i][2]) * p.z
            + f64::from(r[i][3])
    };
    DVec3::new(row(0), row(1), row(2))
}

/// The 8 corners of a world-space oriented box: `world(p)` for the corners of `[min, max]`.
pub fn corners(min: Vec3, max: Vec3, world: impl Fn(DVec3) -> DVec3) -> [DVec3; 8] {
    std::array::from_fn(|i| {
        let p = DVec3::new(
            if i & 1 != 0 { max.x } else { min.x } as f64,
            if i & 2 != 0 { max.y } else { min.y } as f64,
            if i & 4 != 0 { max.z } else { min.z } as f64,
        );
        world(p)
    })
}

/// The exact frustum test in f64: the box is outside if all its corners fail one of the
/// six clip-space half-spaces (`-w <= x <= w`, `-w <= y <= w`, `0 <= z <= w`).
pub fn frustum_visible_f64(m: &DMat4, c: &[DVec3; 8]) -> bool {
    let clip: Vec<DVec4> = c.iter().map(|p| *m * p.extend(1.0)).collect();
    let planes: [fn(&DVec4) -> bool; 6] = [
        |v| v.x >= -v.w,
        |v| v.x <= v.w,
        |v| v.y >= -v.w,
        |v| v.y <= v.w,
        |v| v.z >= 0.0,
        |v| v.z <= v.w,
    ];
    planes.iter().all(|inside| clip.iter().any(inside))
}

/// The brute-force occlusion reference: rasterises the box's 12 triangles in f64 at pixel
/// centres and reports whether any covered pixel is nearer than `depth` there. Boxes that
/// reach in front of `near_w` are reported visible (they are not rasterised).
pub fn raster_visible_f64(
    m: &DMat4,
    c: &[DVec3; 8],
    depth: &[f32],
    w: u32,
    h: u32,
    reversed: bool,
    near_w: f64,
) -> bool {
    let clip: Vec<DVec4> = c.iter().map(|p| *m * p.extend(1.0)).collect();
    if clip.iter().any(|v| v.w <= near_w) {
        return true;
    }
    let s: Vec<DVec3> = clip
        .iter()
        .map(|v| {
            DVec3::new(
                (v.x / v.w * 0.5 + 0.5) * w as f64,
                (0.5 - v.y / v.w * 0.5) * h as f64,
                v.z / v.w,
            )
        })
        .collect();
    for t in BOX_TRIANGLES {
        let (a, b, cc) = (s[t[0]], s[t[1]], s[t[2]]);
        let area = (b.x - a.x) * (cc.y - a.y) - (cc.x - a.x) * (b.y - a.y);
        if area == 0.0 {
            continue;
        }
        let x0 = a.x.min(b.x).min(cc.x).floor().max(0.0) as i64;
        let x1 = a.x.max(b.x).max(cc.x).ceil().min(w as f64) as i64;
        let y0 = a.y.min(b.y).min(cc.y).floor().max(0.0) as i64;
        let y1 = a.y.max(b.y).max(cc.y).ceil().min(h as f64) as i64;
        for py in y0..y1 {
            for px in x0..x1 {
                let (x, y) = (px as f64 + 0.5, py as f64 + 0.5);
                let e0 = ((cc.x - b.x) * (y - b.y) - (cc.y - b.y) * (x - b.x)) / area;
                let e1 = ((a.x - cc.x) * (y - cc.y) - (a.y - cc.y) * (x - cc.x)) / area;
                let e2 = ((b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x)) / area;
                if e0 < 0.0 || e1 < 0.0 || e2 < 0.0 {
                    continue;
                }
                let z = e0 * a.z + e1 * b.z + e2 * cc.z;
                let d = f64::from(depth[(py as u32 * w + px as u32) as usize]);
                if (reversed && z > d) || (!reversed && z < d) {
                    return true;
                }
            }
        }
    }
    false
}

/// The world transform of an object placed with `position` and `linear`, applied to an
/// object-space point, in f64.
pub fn object_to_world(position: DVec3, linear: Mat3) -> impl Fn(DVec3) -> DVec3 {
    let l = linear.as_dmat3();
    move |p| position + l * p
}

/// A random rotation.
pub fn rotation(a: f32, b: f32, c: f32) -> glam::Quat {
    glam::Quat::from_euler(glam::EulerRot::YXZ, a, b, c)
}

/// `DQuat` from `Quat`.
pub fn dquat(q: glam::Quat) -> DQuat {
    q.as_dquat()
}
