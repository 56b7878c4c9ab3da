//! glTF 2.0's metallic-roughness materials on every path: a normal-mapped wall's shaded
//! normals equal the analytic normals of the relief the map encodes (a CPU ray cast finds
//! each pixel's texture coordinates), mirrored texture coordinates shade as the mirror
//! image, the metallic-roughness, occlusion and emissive maps reach the G-buffer as the
//! material model says, and the baseline and pixel-pull paths write the surfaces the
//! compute resolve writes.

mod common;

use glam::{Affine3A, DVec3, Mat4, Vec2, Vec3, Vec4};
use gpu::scene::{
    AlbedoLayer, DataLayer, MaterialId, MaterialMaps, MeshId, NormalMap, OcclusionMap,
};
use gpu::{Batch, Camera, FrameInput, Material, Mesh, RenderPath, RendererConfig, Scene};

const W: u32 = 96;
const H: u32 = 96;
/// The relief's period across the wall, in texture coordinates.
const WAVES: f64 = 2.0;
/// The relief's largest tilt (radians).
const TILT: f64 = 0.5;
/// The data layers' side.
const SIZE: u32 = 128;

/// The tangent-space normal the map encodes at texture coordinate `u`: a tilt about the
/// bitangent of `TILT · sin(2π · WAVES · u)`.
fn relief(u: f64) -> DVec3 {
    let a = TILT * (std::f64::consts::TAU * WAVES * u).sin();
    DVec3::new(a.sin(), 0.0, a.cos())
}

/// The normal map of [`relief`] (texel centres) and an occlusion-roughness-metallic layer
/// (R occlusion 0.25, G roughness 0.5, B metallic 1).
fn data_layers() -> Vec<DataLayer> {
    let code = |x: f64| ((x * 0.5 + 0.5) * 255.0).round() as u8;
    let normal = (0..SIZE * SIZE)
        .map(|i| {
            let n = relief((f64::from(i % SIZE) + 0.5) / f64::from(SIZE));
            [code(n.x), code(n.y), code(n.z), 255]
        })
        .collect();
    vec![
        DataLayer {
            size: SIZE,
            texels: normal,
        },
        DataLayer {
            size: SIZE,
            texels: vec![[64, 128, 255, 255]; (SIZE * SIZE) as usize],
        },
    ]
}

/// A 2 m wall in the z = 0 plane facing +Z (the camera), texture coordinates (0, 0) at its
/// top-left; `mirrored`: u runs right to left, with the tangent −X and handedness −1 (the
/// bitangent stays +Y, the texture's up).
fn wall(mirrored: bool) -> Mesh {
    let u = |x: f32| if mirrored { 1.0 - x } else { x };
    let t = if mirrored {
        Vec4::new(-1.0, 0.0, 0.0, -1.0)
    } else {
        Vec4::new(1.0, 0.0, 0.0, 1.0)
    };
    Mesh {
        name: "wall".into(),
        positions: vec![
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 1.0, 0.0),
        ],
        normals: vec![Vec3::Z; 4],
        uvs: vec![
            Vec2::new(u(0.0), 1.0),
            Vec2::new(u(1.0), 1.0),
            Vec2::new(u(1.0), 0.0),
            Vec2::new(u(0.0), 0.0),
        ],
        tangents: vec![t; 4],
        indices: vec![0, 1, 2, 0, 2, 3],
    }
}

const EMISSIVE: Vec3 = Vec3::new(0.3, 0.15, 0.05);
const METALLIC: f32 = 0.5;
const ROUGHNESS: f32 = 0.8;
const OCCLUSION_STRENGTH: f32 = 0.5;

fn scene(mirrored: bool) -> Scene {
    Scene {
        meshes: vec![wall(mirrored)],
        materials: vec![Material {
            name: "relief".into(),
            tint: Vec3::new(0.8, 0.6, 0.4),
            roughness: ROUGHNESS,
            metallic: METALLIC,
            emissive: EMISSIVE,
            maps: MaterialMaps {
                normal: Some(NormalMap {
                    layer: 0,
                    scale: 1.0,
                }),
                metallic_roughness: Some(1),
                occlusion: Some(OcclusionMap {
                    layer: 1,
                    strength: OCCLUSION_STRENGTH,
                }),
                emissive: None,
            },
            ..Material::default()
        }],
        albedo_layers: vec![AlbedoLayer {
            size: 4,
            texels: vec![[255; 4]; 16],
        }],
        data_layers: data_layers(),
        batches: vec![Batch {
            mesh: MeshId(0),
            material: MaterialId(0),
            instances: vec![Affine3A::IDENTITY],
        }],
        ..Scene::default()
    }
}

fn frame() -> FrameInput {
    FrameInput::new(Camera::look_at(Vec3::new(0.0, 0.0, 2.4), Vec3::ZERO))
}

fn config() -> RendererConfig {
    let mut rc = RendererConfig::sized(W, H);
    rc.lighting.shadows = None;
    rc.lighting.spot_shadows = None;
    rc.lighting.baked_sun = false;
    rc
}

/// The G-buffer of `scene` on `path`.
fn surfaces(scene: &Scene, path: RenderPath) -> Vec<deferred::Surface> {
    let mut r = common::renderer_with(config());
    let prepared = r.prepare(scene).unwrap();
    r.render(&prepared, &frame(), path).unwrap();
    r.inspect().read_gbuffer().unwrap()
}

/// Each pixel centre's texture coordinate on the wall (`None` off it, or within half a
/// pixel of its edge), by a ray from the camera in f64.
fn pixel_uvs(mirrored: bool) -> Vec<Option<(f64, f64)>> {
    let cam = frame().camera;
    let view_proj: Mat4 = cam.projection(W as f32 / H as f32) * cam.view();
    let inv = view_proj.as_dmat4().inverse();
    let eye = cam.position.as_dvec3();
    let margin = 1.0 / f64::from(W);
    (0..W * H)
        .map(|i| {
            let ndc = |x: f64, y: f64| {
                let q = inv * glam::DVec4::new(x, y, 0.5, 1.0);
                q.truncate() / q.w
            };
            let x = (f64::from(i % W) + 0.5) / f64::from(W) * 2.0 - 1.0;
            let y = 1.0 - (f64::from(i / W) + 0.5) / f64::from(H) * 2.0;
            let dir = ndc(x, y) - eye;
            let t = -eye.z / dir.z;
            let p = eye + dir * t;
            if p.x.abs() > 1.0 - margin || p.y.abs() > 1.0 - margin {
                return None;
            }
            let u = (p.x + 1.0) / 2.0;
            Some((if mirrored { 1.0 - u } else { u }, (1.0 - p.y) / 2.0))
        })
        .collect()
}

/// The world normal the relief gives at `u` on the wall (tangent `t`, bitangent +Y,
/// normal +Z).
fn analytic_normal(u: f64, mirrored: bool) -> DVec3 {
    let m = relief(u);
    let t = if mirrored { DVec3::NEG_X } else { DVec3::X };
    (t * m.x + DVec3::Y * m.y + DVec3::Z * m.z).normalize()
}

fn degrees(a: Vec3, b: DVec3) -> f64 {
    a.as_dvec3()
        .normalize()
        .dot(b)
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees()
}

#[test]
fn normal_mapped_wall_shades_the_analytic_relief() {
    for mirrored in [false, true] {
        let got = surfaces(&scene(mirrored), RenderPath::Deferred);
        let mut worst = 0f64;
        let mut covered = 0;
        for (s, uv) in got.iter().zip(pixel_uvs(mirrored)) {
            let Some((u, _)) = uv else { continue };
            covered += 1;
            worst = worst.max(degrees(s.normal, analytic_normal(u, mirrored)));
        }
        eprintln!("mirrored {mirrored}: worst {worst:.3} degrees over {covered} pixels");
        assert!(covered > (W * H / 2) as usize, "{covered}");
        assert!(worst <= 2.0, "mirrored {mirrored}: worst {worst} degrees");
    }
}

/// Mirrored texture coordinates on the same map give the mirror image of the normals.
#[test]
fn mirrored_uvs_shade_as_the_mirror_image() {
    let a = surfaces(&scene(false), RenderPath::Deferred);
    let b = surfaces(&scene(true), RenderPath::Deferred);
    let uvs = pixel_uvs(false);
    let mut worst = 0f64;
    for y in 0..H {
        for x in 0..W {
            let i = (y * W + x) as usize;
            let j = (y * W + W - 1 - x) as usize;
            if uvs[i].is_none() || uvs[j].is_none() {
                continue;
            }
            let n = a[i].normal;
            let mirrored = DVec3::new(-f64::from(n.x), f64::from(n.y), f64::from(n.z));
            worst = worst.max(degrees(b[j].normal, mirrored.normalize()));
        }
    }
    assert!(worst <= 1.0, "worst {worst} degrees");
}

/// The maps' values reach the G-buffer: metallic and roughness times the map's blue and
/// green, the lighting channel the emission plus the ambient hemisphere on the diffuse
/// colour, darkened by the occlusion map at its strength.
#[test]
fn material_maps_reach_the_gbuffer() {
    let got = surfaces(&scene(false), RenderPath::Deferred);
    let f = frame();
    let ambient = f.lighting.ambient.as_dvec3();
    let occlusion = 1.0 + f64::from(OCCLUSION_STRENGTH) * (64.0 / 255.0 - 1.0);
    let base = DVec3::new(0.8, 0.6, 0.4);
    let diffuse = base * (1.0 - f64::from(METALLIC));
    let mut checked = 0;
    for (s, uv) in got.iter().zip(pixel_uvs(false)) {
        if uv.is_none() {
            continue;
        }
        checked += 1;
        assert!(
            (s.metallic - METALLIC).abs() < 2e-3,
            "metallic {}",
            s.metallic
        );
        assert!(
            (s.roughness - ROUGHNESS * 128.0 / 255.0).abs() < 3e-3,
            "roughness {}",
            s.roughness
        );
        assert!((s.albedo.as_dvec3() - base).abs().max_element() < 0.01);
        let n = s.normal.as_dvec3();
        let want = EMISSIVE.as_dvec3() + diffuse * ambient * ((0.6 + 0.4 * n.y) * occlusion);
        // The lighting channel is 8-bit: half a step, and the normal's quantisation.
        let err = (s.lighting.as_dvec3() - want).abs().max_element();
        assert!(err < 1.5 / 255.0, "lighting {} vs {want}", s.lighting);
    }
    assert!(checked > 0);
}

/// The baseline's and pixel pull's fragment shaders write the surfaces the compute
/// resolve writes (the same material function; only the UV gradients' source differs).
#[test]
fn every_path_writes_the_same_surfaces() {
    let s = scene(false);
    let deferred = surfaces(&s, RenderPath::Deferred);
    let uvs = pixel_uvs(false);
    for path in [RenderPath::Baseline, RenderPath::PixelPull] {
        let other = surfaces(&s, path);
        let mut worst = (0f64, 0f32);
        for ((a, b), uv) in deferred.iter().zip(&other).zip(&uvs) {
            if uv.is_none() {
                continue;
            }
            worst.0 = worst
                .0
                .max(degrees(a.normal, b.normal.as_dvec3().normalize()));
            worst.1 = worst
                .1
                .max((a.lighting - b.lighting).abs().max_element())
                .max((a.metallic - b.metallic).abs())
                .max((a.roughness - b.roughness).abs());
        }
        eprintln!(
            "{path:?}: worst normal {:.3} degrees, worst value {}",
            worst.0, worst.1
        );
        assert!(
            worst.0 <= 0.5,
            "{path:?}: normals {} degrees apart",
            worst.0
        );
        assert!(worst.1 <= 2.0 / 255.0, "{path:?}: values {} apart", worst.1);
    }
}

/// HFW's resolve per material shader: on the material scene, passes split by permutation
/// and each pass's specialised pipeline writes the G-buffer and image the uber resolve
/// writes, bit for bit.
#[test]
fn per_shader_resolves_equal_the_uber_resolve() {
    use demo::{DemoOptions, DemoScene};
    let (scene, frame) = demo::build(&DemoOptions {
        scene: DemoScene::Materials,
        ..DemoOptions::default()
    });
    let permutations: std::collections::BTreeSet<u32> = scene
        .materials
        .iter()
        .map(|m| {
            use gpu::scene::MaterialFeatures as F;
            let maps = F::NORMAL_MAP.0 | F::METALLIC_ROUGHNESS_MAP.0 | F::OCCLUSION_MAP.0;
            m.shader_key() & (maps | F::EMISSIVE.0)
        })
        .collect();
    let run = |specialised: bool| {
        let mut rc = config();
        rc.image.width = 160;
        rc.image.height = 96;
        rc.geometry.material_permutations = specialised;
        let mut r = common::renderer_with(rc);
        let prepared = r.prepare(&scene).unwrap();
        r.render(&prepared, &frame, RenderPath::Deferred).unwrap();
        (
            prepared.summary().resolve_pipelines,
            r.inspect().read_gbuffer().unwrap(),
            r.read_output().unwrap(),
        )
    };
    let (n, gbuffer, image) = run(true);
    let (uber_n, uber_gbuffer, uber_image) = run(false);
    assert_eq!((n, uber_n), (permutations.len(), 1));
    assert!(n >= 4, "the material scene has {n} permutations");
    assert!(gbuffer == uber_gbuffer, "the G-buffers differ");
    assert_eq!(common::differing_pixels(&image, &uber_image), 0);
}

/// A scene with more data layers than the device's texture arrays hold is refused with an
/// error naming the limit and the scene field, and the renderer goes on to prepare a
/// scene that fits.
#[test]
fn data_layers_over_the_device_limit_are_an_error_naming_it() {
    let r = common::renderer_with(config());
    let layers = testkit::device::ctx()
        .device
        .limits()
        .max_texture_array_layers as usize;
    let mut over = scene(false);
    over.data_layers = vec![
        DataLayer {
            size: 1,
            texels: vec![[128, 128, 255, 255]],
        };
        layers + 1
    ];
    match r.prepare(&over) {
        Err(gpu::Error::DeviceLimit {
            limit,
            needed,
            available,
        }) => {
            assert!(limit.contains("max_texture_array_layers") && limit.contains("data_layers"));
            assert_eq!((needed, available), (layers as u64 + 1, layers as u64));
        }
        Err(e) => panic!("another error: {e}"),
        Ok(_) => panic!("{} data layers accepted", layers + 1),
    }
    assert!(r.prepare(&scene(false)).is_ok());
}
