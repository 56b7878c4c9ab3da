//! The glTF importer into the renderer: a generated medium scene (thousands of instances
//! of a foliage card over a ground quad) and a wall with every map of glTF's material
//! model, each written to `.glb`, imported and rendered by `gpu::Renderer` on the test
//! device (lavapipe in CI), against the same scene built directly as a `gpu::Scene` from
//! the generating values: the scenes are equal, and both give identical images (and, for
//! the field, classification statistics; tolerance: none).

// The test glTF writer lives once, beside the importer's own tests.
#[path = "../crates/gltf_scene/tests/common/mod.rs"]
mod common;

use common::{Doc, scene};
use gltf_scene::glam::{Affine3A, Quat, Vec2, Vec3, Vec4};
use gpu::scene::{AlbedoLayer, MaterialId, MeshId, ShaderKind};
use gpu::{self, Batch, Camera, FrameInput, Material, Mesh, RenderPath, Renderer, RendererConfig};
use serde_json::json;

const LEAF: u32 = 64;
const CARDS_X: u32 = 60;
const CARDS_Z: u32 = 50;

/// A leaf texture: green blobs on transparent texels (an alpha-tested cut-out).
fn leaf_texture() -> image::RgbaImage {
    image::RgbaImage::from_fn(LEAF, LEAF, |x, y| {
        let (u, v) = (x as f32 / LEAF as f32 - 0.5, y as f32 / LEAF as f32 - 0.5);
        let inside = (u * u) / 0.2 + (v * v) / 0.25 < 1.0 && ((x / 8 + y / 8) % 3 != 0);
        image::Rgba([
            (40 + x) as u8,
            (120 + y) as u8,
            30,
            if inside { 255 } else { 0 },
        ])
    })
}

/// The card's placements: a jittered grid, turned about +Y, scaled 0.7-1.3.
fn placements() -> Vec<Affine3A> {
    let mut rng = testkit::Rng::new(18);
    let mut out = Vec::new();
    for i in 0..CARDS_X {
        for k in 0..CARDS_Z {
            let x = (i as f32 - CARDS_X as f32 / 2.0) * 0.6 + (rng.next_u64() % 100) as f32 * 0.003;
            let z = -(k as f32) * 0.6 - (rng.next_u64() % 100) as f32 * 0.003;
            let angle = (rng.next_u64() % 628) as f32 * 0.01;
            let s = 0.7 + (rng.next_u64() % 60) as f32 * 0.01;
            out.push(Affine3A::from_scale_rotation_translation(
                Vec3::splat(s),
                Quat::from_rotation_y(angle),
                Vec3::new(x, 0.0, z),
            ));
        }
    }
    out
}

// The two models, as the file stores them.
const GROUND: [[f32; 3]; 4] = [
    [-20.0, 0.0, 5.0],
    [20.0, 0.0, 5.0],
    [20.0, 0.0, -35.0],
    [-20.0, 0.0, -35.0],
];
const GROUND_UV: [[f32; 2]; 4] = [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]];
const CARD: [[f32; 3]; 4] = [
    [-0.4, 0.0, 0.0],
    [0.4, 0.0, 0.0],
    [0.4, 1.2, 0.0],
    [-0.4, 1.2, 0.0],
];
const CARD_UV: [[f32; 2]; 4] = [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]];
const QUAD: [u32; 6] = [0, 1, 2, 0, 2, 3];

fn glb() -> Vec<u8> {
    let mut doc = Doc::new();
    let image = doc.png(&leaf_texture());
    let tex = doc.texture(image);
    let ground_mat = doc.push(
        "materials",
        json!({ "name": "ground", "pbrMetallicRoughness": {
            "baseColorFactor": [0.3, 0.5, 0.2, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.9 } }),
    );
    let leaf_mat = doc.push(
        "materials",
        json!({ "name": "leaf", "alphaMode": "MASK", "doubleSided": true, "pbrMetallicRoughness": {
            "baseColorTexture": { "index": tex }, "metallicFactor": 0.0, "roughnessFactor": 0.6 } }),
    );
    let mesh = |doc: &mut Doc, pos: &[[f32; 3]], uv: &[[f32; 2]], n: [f32; 3], mat: usize| {
        let p = doc.floats(pos);
        let nn = doc.floats(&vec![n; pos.len()]);
        let t = doc.floats(&vec![[1.0, 0.0, 0.0, 1.0]; pos.len()]);
        let u = doc.floats(uv);
        let i = doc.indices(&QUAD, 5123);
        doc.push(
            "meshes",
            json!({ "primitives": [{ "attributes": { "POSITION": p, "NORMAL": nn, "TANGENT": t, "TEXCOORD_0": u },
                "indices": i, "material": mat }] }),
        )
    };
    let ground = mesh(&mut doc, &GROUND, &GROUND_UV, [0.0, 1.0, 0.0], ground_mat);
    let card = mesh(&mut doc, &CARD, &CARD_UV, [0.0, 0.0, 1.0], leaf_mat);
    let mut nodes = vec![doc.push("nodes", json!({ "mesh": ground }))];
    for t in placements() {
        let m = gpu::glam::Mat4::from(t).to_cols_array();
        nodes.push(doc.push("nodes", json!({ "mesh": card, "matrix": m })));
    }
    scene(&mut doc, &nodes);
    doc.glb()
}

fn v3(a: &[[f32; 3]]) -> Vec<Vec3> {
    a.iter().map(|&p| Vec3::from_array(p)).collect()
}
fn v2(a: &[[f32; 2]]) -> Vec<Vec2> {
    a.iter().map(|&p| Vec2::from_array(p)).collect()
}

/// The same scene built directly: a double-sided card is the front quad and its back
/// (vertices copied with the tangent frame negated, triangles reversed),
/// the leaf texture is layer 0, the untextured ground's white layer is layer 1.
fn reference() -> gpu::Scene {
    let ground = Mesh {
        name: String::new(),
        positions: v3(&GROUND),
        normals: vec![Vec3::Y; 4],
        uvs: v2(&GROUND_UV),
        tangents: vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 4],
        indices: QUAD.iter().map(|&i| i as u16).collect(),
    };
    let mut card = Mesh {
        name: String::new(),
        positions: v3(&CARD).repeat(2),
        normals: [vec![Vec3::Z; 4], vec![Vec3::NEG_Z; 4]].concat(),
        uvs: v2(&CARD_UV).repeat(2),
        tangents: [
            vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 4],
            // The back copy negates the whole tangent frame (normal, tangent, handedness).
            vec![Vec4::new(-1.0, 0.0, 0.0, -1.0); 4],
        ]
        .concat(),
        indices: vec![0, 1, 2, 0, 2, 3],
    };
    card.indices.extend_from_slice(&[4, 6, 5, 4, 7, 6]);
    let leaf = leaf_texture();
    gpu::Scene {
        data_layers: Vec::new(),
        meshes: vec![ground, card],
        materials: vec![
            Material {
                name: String::new(),
                shader: ShaderKind::Opaque,
                albedo_layer: 1,
                tint: Vec3::new(0.3, 0.5, 0.2),
                alpha_cutoff: 0.5,
                roughness: 0.9,
                specular: 1.0,
                regular: false,
                ..Default::default()
            },
            Material {
                name: String::new(),
                shader: ShaderKind::AlphaTested,
                albedo_layer: 0,
                tint: Vec3::ONE,
                alpha_cutoff: 0.5,
                roughness: 0.6,
                specular: 1.0,
                regular: false,
                ..Default::default()
            },
        ],
        albedo_layers: vec![
            AlbedoLayer {
                size: LEAF,
                texels: leaf.pixels().map(|p| p.0).collect(),
            },
            AlbedoLayer {
                size: LEAF,
                texels: vec![[255; 4]; (LEAF * LEAF) as usize],
            },
        ],
        batches: vec![
            Batch {
                mesh: MeshId(0),
                material: MaterialId(0),
                instances: vec![Affine3A::IDENTITY],
            },
            Batch {
                mesh: MeshId(1),
                material: MaterialId(1),
                instances: placements(),
            },
        ],
        static_setups: Vec::new(),
        wind: None,
    }
}

fn without_names(mut s: gpu::Scene) -> gpu::Scene {
    s.meshes.iter_mut().for_each(|m| m.name.clear());
    s.materials.iter_mut().for_each(|m| m.name.clear());
    s
}

#[test]
fn an_imported_foliage_field_renders_like_the_scene_built_directly() {
    let imported = gltf_scene::load_slice(&glb(), None, &gltf_scene::LoadOptions::default())
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(imported.warnings.is_empty(), "{:?}", imported.warnings);
    assert_eq!(imported.summary.instances, 1 + (CARDS_X * CARDS_Z) as usize);
    let direct = reference();
    assert!(
        without_names(imported.scene.clone()) == direct,
        "the imported scene differs from the one built directly"
    );

    let c = testkit::device::ctx();
    let mut r = Renderer::new(&c.device, &c.queue, {
        let mut rc = RendererConfig::sized(192, 108);
        rc.lighting.shadows = Some(gpu::config::ShadowConfig {
            resolution: 512,
            ..gpu::config::ShadowConfig::default()
        });
        rc
    })
    .unwrap();
    let frame = FrameInput::new(Camera::look_at(
        Vec3::new(0.0, 4.0, 12.0),
        Vec3::new(0.0, 0.0, -12.0),
    ));
    let mut images = Vec::new();
    for s in [&imported.scene, &direct] {
        let p = r.prepare(s).unwrap();
        r.render(&p, &frame, RenderPath::Deferred).unwrap();
        let deferred = r.read_output().unwrap();
        let gpu_classes = r.inspect().read_classification(&p).unwrap();
        let (stats, mismatch) = r
            .inspect()
            .classification_statistics(&p, &gpu_classes)
            .unwrap();
        assert!(mismatch.is_none(), "{mismatch:?}");
        r.render(&p, &frame, RenderPath::Baseline).unwrap();
        let baseline = r.read_output().unwrap();
        images.push((deferred, baseline, stats));
    }
    let (a, b) = (&images[0], &images[1]);
    assert!(a.0 == b.0, "deferred images differ");
    assert!(a.1 == b.1, "baseline images differ");
    assert!(a.2 == b.2, "classification statistics differ");
    // The cards are drawn and cut out: sky, ground and leaves all show.
    let distinct: std::collections::HashSet<[u8; 4]> = a.0.pixels.iter().copied().collect();
    assert!(distinct.len() > 50, "{} colours", distinct.len());
}

/// A 16x16 test image: `f(x, y)` per texel.
fn image16(f: impl Fn(u32, u32) -> [u8; 4]) -> image::RgbaImage {
    image::RgbaImage::from_fn(16, 16, |x, y| image::Rgba(f(x, y)))
}

/// Every map of glTF's metallic-roughness model on a double-sided wall, written as `.glb`
/// by the test: it imports to the scene built directly from the same values (layers in
/// the documented order, the back faces' tangent frame negated) and both render the same
/// images on the deferred and baseline paths.
#[test]
fn every_material_feature_imports_to_the_scene_built_directly() {
    use gpu::scene::{DataLayer, MaterialMaps, NormalMap, OcclusionMap};
    let colour = image16(|x, y| [(x * 15) as u8, (y * 15) as u8, 120, 255]);
    let normal = image16(|x, _| {
        let a = (x as f32 / 16.0 * std::f32::consts::TAU).sin() * 0.4;
        let c = |v: f32| ((v * 0.5 + 0.5) * 255.0).round() as u8;
        [c(a.sin()), 128, c(a.cos()), 255]
    });
    let orm = image16(|x, y| {
        [
            (128 + x * 8) as u8,
            (60 + y * 10) as u8,
            if x < 8 { 255 } else { 0 },
            255,
        ]
    });
    let glow = image16(|x, _| {
        if x % 4 == 0 {
            [255, 200, 100, 255]
        } else {
            [0, 0, 0, 255]
        }
    });
    let wall: [[f32; 3]; 4] = [
        [-1.0, -1.0, 0.0],
        [1.0, -1.0, 0.0],
        [1.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0],
    ];

    let mut doc = Doc::new();
    let [tc, tn, to, tg] = [&colour, &normal, &orm, &glow].map(|i| {
        let image = doc.png(i);
        doc.texture(image)
    });
    doc.json["extensionsUsed"] = json!(["KHR_materials_emissive_strength"]);
    let mat = doc.push(
        "materials",
        json!({ "doubleSided": true,
            "pbrMetallicRoughness": { "baseColorTexture": { "index": tc },
                "metallicFactor": 0.9, "roughnessFactor": 0.6, "metallicRoughnessTexture": { "index": to } },
            "normalTexture": { "index": tn, "scale": 0.8 },
            "occlusionTexture": { "index": to, "strength": 0.7 },
            "emissiveTexture": { "index": tg }, "emissiveFactor": [0.5, 0.2, 0.1],
            "extensions": { "KHR_materials_emissive_strength": { "emissiveStrength": 2.0 } } }),
    );
    let p = doc.floats(&wall);
    let n = doc.floats(&[[0.0, 0.0, 1.0]; 4]);
    let t = doc.floats(&[[1.0, 0.0, 0.0, 1.0]; 4]);
    let u = doc.floats(&GROUND_UV);
    let i = doc.indices(&QUAD, 5123);
    let mesh = doc.push(
        "meshes",
        json!({ "primitives": [{ "attributes": { "POSITION": p, "NORMAL": n, "TANGENT": t, "TEXCOORD_0": u },
            "indices": i, "material": mat }] }),
    );
    let node = doc.push("nodes", json!({ "mesh": mesh }));
    scene(&mut doc, &[node]);
    let imported = gltf_scene::load_slice(&doc.glb(), None, &gltf_scene::LoadOptions::default())
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(imported.warnings.is_empty(), "{:?}", imported.warnings);

    let texels = |i: &image::RgbaImage| i.pixels().map(|p| p.0).collect::<Vec<_>>();
    let mut mesh = Mesh {
        name: String::new(),
        positions: v3(&wall).repeat(2),
        normals: [vec![Vec3::Z; 4], vec![Vec3::NEG_Z; 4]].concat(),
        uvs: v2(&GROUND_UV).repeat(2),
        tangents: [
            vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 4],
            vec![Vec4::new(-1.0, 0.0, 0.0, -1.0); 4],
        ]
        .concat(),
        indices: vec![0, 1, 2, 0, 2, 3],
    };
    mesh.indices.extend_from_slice(&[4, 6, 5, 4, 7, 6]);
    let direct = gpu::Scene {
        meshes: vec![mesh],
        materials: vec![Material {
            roughness: 0.6,
            metallic: 0.9,
            specular: gltf_scene::SPECULAR,
            emissive: Vec3::new(1.0, 0.4, 0.2),
            // Colour layers: base colour, then emissive; data layers: normal, then the
            // ORM image that metallic-roughness and occlusion share.
            maps: MaterialMaps {
                normal: Some(NormalMap {
                    layer: 0,
                    scale: 0.8,
                }),
                metallic_roughness: Some(1),
                occlusion: Some(OcclusionMap {
                    layer: 1,
                    strength: 0.7,
                }),
                emissive: Some(1),
            },
            ..Material::default()
        }],
        albedo_layers: [&colour, &glow]
            .map(|i| AlbedoLayer {
                size: 16,
                texels: texels(i),
            })
            .to_vec(),
        data_layers: [&normal, &orm]
            .map(|i| DataLayer {
                size: 16,
                texels: texels(i),
            })
            .to_vec(),
        batches: vec![Batch {
            mesh: MeshId(0),
            material: MaterialId(0),
            instances: vec![Affine3A::IDENTITY],
        }],
        ..gpu::Scene::default()
    };
    assert!(
        without_names(imported.scene.clone()) == direct,
        "the imported scene differs from the one built directly:\n{:?}\n{:?}",
        without_names(imported.scene.clone()).materials,
        direct.materials
    );

    let c = testkit::device::ctx();
    let mut r = Renderer::new(&c.device, &c.queue, RendererConfig::sized(128, 96)).unwrap();
    let frame = FrameInput::new(Camera::look_at(Vec3::new(0.3, 0.2, 2.5), Vec3::ZERO));
    let mut images = Vec::new();
    for s in [&imported.scene, &direct] {
        let p = r.prepare(s).unwrap();
        for path in [RenderPath::Deferred, RenderPath::Baseline] {
            r.render(&p, &frame, path).unwrap();
            images.push(r.read_output().unwrap());
        }
    }
    assert!(images[0] == images[2], "deferred images differ");
    assert!(images[1] == images[3], "baseline images differ");
    let distinct: std::collections::HashSet<[u8; 4]> = images[0].pixels.iter().copied().collect();
    assert!(distinct.len() > 50, "{} colours", distinct.len());
}
