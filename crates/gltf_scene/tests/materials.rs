//! Materials and textures: alpha modes and factors, double-sided back faces, texture
//! transforms, resampling to one layer size, every map of glTF's metallic-roughness model,
//! maps on other sets, and bad factors (the importer's other tests: `import.rs`).

mod common;

use common::{Doc, checker, scene, triangle_mesh};
use gltf_scene::glam::{Vec2, Vec3};
use gltf_scene::scene::{self, ShaderKind};
use gltf_scene::{LoadOptions, load_slice};
use serde_json::json;

fn import(bytes: &[u8]) -> gltf_scene::Imported {
    load_slice(bytes, None, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn alpha_modes_and_material_factors() {
    let mut doc = Doc::new();
    let img = checker(4);
    let image = doc.png(&img);
    let tex = doc.texture(image);
    let mask = doc.push(
        "materials",
        json!({ "name": "leaves", "alphaMode": "MASK", "alphaCutoff": 0.3,
                "pbrMetallicRoughness": { "baseColorFactor": [0.5, 0.6, 0.7, 1.0],
                  "baseColorTexture": { "index": tex }, "metallicFactor": 0.0, "roughnessFactor": 0.25 } }),
    );
    let blend = doc.push(
        "materials",
        json!({ "name": "glass", "alphaMode": "BLEND" }),
    );
    let opaque = doc.push(
        "materials",
        json!({ "name": "metal", "pbrMetallicRoughness": { "metallicFactor": 1.0, "roughnessFactor": 0.5 } }),
    );
    let half = doc.push(
        "materials",
        json!({ "name": "half", "alphaMode": "MASK", "alphaCutoff": 0.2,
                "pbrMetallicRoughness": { "baseColorFactor": [1, 1, 1, 0.5], "baseColorTexture": { "index": tex } } }),
    );
    let meshes: Vec<usize> = [mask, blend, opaque, half]
        .into_iter()
        .map(|m| triangle_mesh(&mut doc, Some(m)))
        .collect();
    let nodes: Vec<usize> = meshes
        .iter()
        .map(|&m| doc.push("nodes", json!({ "mesh": m })))
        .collect();
    scene(&mut doc, &nodes);
    let imp = import(&doc.glb());
    let s = &imp.scene;
    assert_eq!(s.materials.len(), 4);
    let m = &s.materials[0];
    assert_eq!(
        (m.shader, m.alpha_cutoff, m.roughness),
        (ShaderKind::AlphaTested, 0.3, 0.25)
    );
    assert_eq!(m.tint, Vec3::new(0.5, 0.6, 0.7));
    assert_eq!(m.specular, 1.0);
    // A 4x4 texture is its own layer, texel for texel.
    let layer = &s.albedo_layers[m.albedo_layer as usize];
    assert_eq!(layer.size, 4);
    assert_eq!(layer.texels, img.pixels().map(|p| p.0).collect::<Vec<_>>());
    let b = &s.materials[1];
    assert_eq!((b.shader, b.alpha_cutoff), (ShaderKind::AlphaTested, 0.5));
    assert!(
        imp.warnings
            .iter()
            .any(|w| w.contains("BLEND") && w.contains("glass"))
    );
    // Untextured: the white layer, as large as the others.
    let w = &s.albedo_layers[b.albedo_layer as usize];
    assert!(w.texels.iter().all(|&t| t == [255; 4]) && w.size == 4);
    let o = &s.materials[2];
    assert_eq!(o.shader, ShaderKind::Opaque);
    // Fully metallic: glTF's factors as they are (the renderer shades metals).
    assert_eq!((o.tint, o.metallic, o.roughness), (Vec3::ONE, 1.0, 0.5));
    // Texture alpha × 0.5 >= 0.2  <=>  texture alpha >= 0.4.
    assert!((s.materials[3].alpha_cutoff - 0.4).abs() < 1e-6);
    assert_eq!(imp.summary.materials, 4);
    assert_eq!(imp.summary.textures, 1);
}

#[test]
fn double_sided_adds_reversed_back_faces() {
    let mut doc = Doc::new();
    let mat = doc.push("materials", json!({ "doubleSided": true }));
    let mesh = triangle_mesh(&mut doc, Some(mat));
    let node = doc.push("nodes", json!({ "mesh": mesh }));
    scene(&mut doc, &[node]);
    let imp = import(&doc.glb());
    let m = &imp.scene.meshes[0];
    assert_eq!(m.indices, [0, 1, 2, 3, 5, 4]);
    assert_eq!(m.positions[3..], m.positions[..3]);
    assert_eq!(m.normals[..3], [Vec3::Z; 3]);
    assert_eq!(m.normals[3..], [Vec3::NEG_Z; 3]);
    assert_eq!(imp.summary.double_sided, 1);
}

#[test]
fn texture_transform_is_baked_into_the_uvs() {
    let mut doc = Doc::new();
    let image = doc.png(&checker(2));
    let tex = doc.texture(image);
    doc.json["extensionsUsed"] = json!(["KHR_texture_transform"]);
    doc.json["extensionsRequired"] = json!(["KHR_texture_transform"]);
    let mat = doc.push(
        "materials",
        json!({ "pbrMetallicRoughness": { "baseColorTexture": { "index": tex,
            "extensions": { "KHR_texture_transform": {
                "offset": [0.5, 0.0], "rotation": std::f32::consts::FRAC_PI_2, "scale": [2.0, 3.0], "texCoord": 1 } } } } }),
    );
    let p = doc.floats(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let n = doc.floats(&[[0.0, 0.0, 1.0]; 3]);
    let uv0 = doc.floats(&[[9.0, 9.0]; 3]);
    let uv1 = doc.floats(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
    let mesh = doc.push(
        "meshes",
        json!({ "primitives": [{ "attributes": { "POSITION": p, "NORMAL": n, "TEXCOORD_0": uv0, "TEXCOORD_1": uv1 }, "material": mat }] }),
    );
    let node = doc.push("nodes", json!({ "mesh": mesh }));
    scene(&mut doc, &[node]);
    let m = &import(&doc.glb()).scene.meshes[0];
    // TEXCOORD_1 (the transform's texCoord), scaled (2, 3), turned a quarter counter-
    // clockwise on the image ((u, v) -> (v, -u)), offset (0.5, 0):
    // (0,0) -> (0.5, 0); (1,0) -> (2,0) -> (0,-2) -> (0.5,-2); (0,1) -> (0,3) -> (3,0) -> (3.5,0).
    let want = [
        Vec2::new(0.5, 0.0),
        Vec2::new(0.5, -2.0),
        Vec2::new(3.5, 0.0),
    ];
    for (got, want) in m.uvs.iter().zip(want) {
        assert!((*got - want).length() < 1e-5, "{got} vs {want}");
    }
}

#[test]
fn textures_of_different_sizes_are_resampled_to_one_power_of_two() {
    let mut doc = Doc::new();
    let big = doc.png(&image::RgbaImage::from_pixel(
        300,
        200,
        image::Rgba([200, 10, 10, 255]),
    ));
    let small = doc.png(&image::RgbaImage::from_pixel(
        16,
        16,
        image::Rgba([10, 200, 10, 255]),
    ));
    let mut nodes = Vec::new();
    for img in [big, small] {
        let tex = doc.texture(img);
        let mat = doc.push(
            "materials",
            json!({ "pbrMetallicRoughness": { "baseColorTexture": { "index": tex } } }),
        );
        let mesh = triangle_mesh(&mut doc, Some(mat));
        nodes.push(doc.push("nodes", json!({ "mesh": mesh })));
    }
    scene(&mut doc, &nodes);
    let imp = import(&doc.glb());
    // The largest power of two not above 300.
    assert!(imp.scene.albedo_layers.iter().all(|l| l.size == 256));
    assert_eq!(imp.summary.resampled, 2);
    assert_eq!(imp.summary.layer_size, 256);
    for (l, c) in imp
        .scene
        .albedo_layers
        .iter()
        .zip([[200, 10, 10, 255], [10, 200, 10, 255]])
    {
        assert!(
            l.texels
                .iter()
                .all(|t| t.iter().zip(c).all(|(a, b)| a.abs_diff(b) <= 1))
        );
    }
    let capped = load_slice(
        &doc.glb(),
        None,
        &LoadOptions {
            max_layer_size: 64,
            ..LoadOptions::default()
        },
    )
    .unwrap();
    assert!(capped.scene.albedo_layers.iter().all(|l| l.size == 64));
}

/// Every map of glTF 2.0's metallic-roughness model reaches the material: normal (with
/// its scale), metallic-roughness, occlusion (with its strength) and emissive (factor
/// times KHR_materials_emissive_strength), the data maps as linear layers of their own
/// size, an image shared by two materials once.
#[test]
fn every_material_map_is_imported() {
    let mut doc = Doc::new();
    let colour = doc.png(&checker(8));
    // A data image of another size than the colour's: its own array, texel for texel.
    let bumps = image::RgbaImage::from_fn(4, 4, |x, y| {
        image::Rgba([(x * 60) as u8, (y * 60) as u8, 255, 255])
    });
    let normal = doc.png(&bumps);
    let mr = doc.png(&image::RgbaImage::from_pixel(
        4,
        4,
        image::Rgba([0, 200, 100, 255]),
    ));
    let glow = doc.png(&image::RgbaImage::from_pixel(
        8,
        8,
        image::Rgba([255, 128, 0, 255]),
    ));
    let [tc, tn, tmr, tg] = [colour, normal, mr, glow].map(|i| doc.texture(i));
    doc.json["extensionsUsed"] = json!(["KHR_materials_emissive_strength"]);
    let full = doc.push(
        "materials",
        json!({ "name": "full",
                "pbrMetallicRoughness": { "baseColorTexture": { "index": tc },
                  "metallicFactor": 0.75, "roughnessFactor": 0.5,
                  "metallicRoughnessTexture": { "index": tmr } },
                "normalTexture": { "index": tn, "scale": 0.5 },
                "occlusionTexture": { "index": tmr, "strength": 0.25 },
                "emissiveTexture": { "index": tg },
                "emissiveFactor": [1.0, 0.5, 0.25],
                "extensions": { "KHR_materials_emissive_strength": { "emissiveStrength": 4.0 } } }),
    );
    // The same normal map on a second material: one layer.
    let second = doc.push(
        "materials",
        json!({ "name": "second", "normalTexture": { "index": tn } }),
    );
    let meshes = [full, second].map(|m| triangle_mesh(&mut doc, Some(m)));
    let nodes = meshes.map(|m| doc.push("nodes", json!({ "mesh": m })));
    scene(&mut doc, &nodes);
    let imp = import(&doc.glb());
    assert!(imp.warnings.is_empty(), "{:?}", imp.warnings);
    let s = &imp.scene;
    let m = &s.materials[0];
    assert_eq!((m.metallic, m.roughness), (0.75, 0.5));
    assert_eq!(m.emissive, Vec3::new(4.0, 2.0, 1.0));
    let n = m.maps.normal.expect("normal map");
    assert_eq!(n.scale, 0.5);
    let o = m.maps.occlusion.expect("occlusion map");
    assert_eq!(o.strength, 0.25);
    // The metallic-roughness and occlusion maps share their image: one data layer.
    assert_eq!(m.maps.metallic_roughness, Some(o.layer));
    assert_ne!(n.layer, o.layer);
    assert_eq!(s.data_layers.len(), 2);
    let data = &s.data_layers[n.layer as usize];
    assert_eq!(data.size, 4);
    assert_eq!(data.texels, bumps.pixels().map(|p| p.0).collect::<Vec<_>>());
    assert_eq!(
        s.data_layers[o.layer as usize].texels[0],
        [0, 200, 100, 255]
    );
    // The emissive map is a colour layer beside the base colour.
    let e = m.maps.emissive.expect("emissive map") as usize;
    assert_ne!(e, m.albedo_layer as usize);
    assert_eq!(s.albedo_layers[e].texels[0], [255, 128, 0, 255]);
    assert_eq!(s.materials[1].maps.normal.map(|n| n.layer), Some(n.layer));
    assert_eq!((imp.summary.textures, imp.summary.data_textures), (2, 2));
    assert_eq!(
        (imp.summary.layer_size, imp.summary.data_layer_size),
        (8, 4)
    );
    use scene::MaterialFeatures as F;
    assert_eq!(
        m.features(),
        F(F::NORMAL_MAP.0 | F::METALLIC_ROUGHNESS_MAP.0 | F::OCCLUSION_MAP.0 | F::EMISSIVE.0)
    );
}

/// A map on another TEXCOORD set or with another transform than the base colour's is
/// read with the base colour's, and the importer says so; a material with a non-finite
/// factor is replaced by the default material with a warning that names it and the
/// field, and the other materials are kept.
#[test]
fn maps_on_other_sets_warn_and_bad_factors_are_errors() {
    let mut doc = Doc::new();
    let t = doc.png(&checker(4));
    let tex = doc.texture(t);
    let m = doc.push(
        "materials",
        json!({ "name": "two sets",
                "pbrMetallicRoughness": { "baseColorTexture": { "index": tex } },
                "occlusionTexture": { "index": tex, "texCoord": 1 },
                "normalTexture": { "index": tex,
                  "extensions": { "KHR_texture_transform": { "scale": [2.0, 2.0] } } } }),
    );
    let mesh = triangle_mesh(&mut doc, Some(m));
    let node = doc.push("nodes", json!({ "mesh": mesh }));
    scene(&mut doc, &[node]);
    let imp = import(&doc.glb());
    let w = imp.warnings.join("\n");
    assert!(w.contains("occlusion texture reads TEXCOORD_1"), "{w}");
    assert!(
        w.contains("normal texture reads TEXCOORD_0 with a KHR_texture_transform"),
        "{w}"
    );
    assert!(imp.scene.materials[0].maps.occlusion.is_some());

    let second = doc.push(
        "materials",
        json!({ "name": "fine", "pbrMetallicRoughness": { "metallicFactor": 0.25 } }),
    );
    let mesh = triangle_mesh(&mut doc, Some(second));
    let node = doc.push("nodes", json!({ "mesh": mesh }));
    doc.json["scenes"][0]["nodes"] = json!([0, node]);
    for (field, material) in [
        (
            "emissiveFactor",
            json!({ "name": "hot", "emissiveFactor": [1.0, 1e39, 0.0] }),
        ),
        (
            "normalTexture.scale",
            json!({ "name": "hot", "normalTexture": { "index": tex, "scale": 1e39 } }),
        ),
    ] {
        let mut bad = doc.json_with_buffer(None);
        bad["materials"][0] = material;
        let bytes = common::glb(&bad, &doc.bin);
        let imp = load_slice(&bytes, None, &LoadOptions::default()).unwrap();
        let w = imp.warnings.join("\n");
        assert!(
            w.contains("material 0") && w.contains("hot") && w.contains(field),
            "{w}"
        );
        let names: Vec<_> = imp
            .scene
            .materials
            .iter()
            .map(|m| m.name.as_str())
            .collect();
        assert_eq!(names, ["hot", "fine"]);
        assert_eq!(imp.scene.materials[1].metallic, 0.25);
    }
}

/// A normal map on a primitive without texture coordinates is imported (sampled at
/// (0, 0), the mesh's coordinates all zero) with a warning naming the material and the
/// missing set.
#[test]
fn a_normal_map_without_texture_coordinates_is_warned() {
    let mut doc = Doc::new();
    let image = doc.png(&checker(4));
    let tex = doc.texture(image);
    let m = doc.push(
        "materials",
        json!({ "name": "bumpy", "normalTexture": { "index": tex } }),
    );
    let pos = doc.floats(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let mesh = doc.push(
        "meshes",
        json!({ "primitives": [{ "attributes": { "POSITION": pos }, "material": m }] }),
    );
    let node = doc.push("nodes", json!({ "mesh": mesh }));
    scene(&mut doc, &[node]);
    let imp = import(&doc.glb());
    let w = imp.warnings.join("\n");
    assert!(w.contains("bumpy") && w.contains("no TEXCOORD_0"), "{w}");
    assert!(imp.scene.materials[0].maps.normal.is_some());
    assert!(imp.scene.meshes[0].uvs.iter().all(|uv| *uv == Vec2::ZERO));
}
