//! The importer on small files written here: every feature against hand-computed values,
//! every corrupt case against its error.

mod common;

use common::{Doc, checker, scene, temp_dir, triangle_mesh};
use gltf_scene::glam::{Affine3A, Mat4, Vec2, Vec3, Vec4};
use gltf_scene::scene;
use gltf_scene::{Error, LoadOptions, load, load_slice};
use serde_json::json;

fn import(bytes: &[u8]) -> gltf_scene::Imported {
    load_slice(bytes, None, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

fn import_err(bytes: &[u8]) -> Error {
    match load_slice(bytes, None, &LoadOptions::default()) {
        Ok(_) => panic!("imported a corrupt file"),
        Err(e) => e,
    }
}

fn close(a: Affine3A, b: Mat4) {
    let a = Mat4::from(a);
    assert!(a.abs_diff_eq(b, 1e-5), "\n{a}\n is not\n{b}");
}

#[test]
fn nodes_sharing_a_mesh_make_one_batch_with_their_world_transforms() {
    let mut doc = Doc::new();
    let mesh = triangle_mesh(&mut doc, None);
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let child = doc.push(
        "nodes",
        json!({ "mesh": mesh, "translation": [0.0, 0.0, -1.0] }),
    );
    let trs = doc.push(
        "nodes",
        json!({ "name": "trs", "mesh": mesh, "translation": [1.0, 2.0, 3.0],
                "rotation": [0.0, s, 0.0, s], "scale": [2.0, 2.0, 2.0], "children": [child] }),
    );
    let matrix = doc.push(
        "nodes",
        json!({ "mesh": mesh, "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 5, 6, 7, 1] }),
    );
    let mirror = doc.push("nodes", json!({ "mesh": mesh, "scale": [-1.0, 1.0, 1.0] }));
    scene(&mut doc, &[trs, matrix, mirror]);
    let imp = import(&doc.embedded());
    let sc = &imp.scene;
    // Hand-computed: 90° about +Y takes +x to -z and +z to +x; scale 2.
    let trs_m = Mat4::from_cols(
        Vec4::new(0.0, 0.0, -2.0, 0.0),
        Vec4::new(0.0, 2.0, 0.0, 0.0),
        Vec4::new(2.0, 0.0, 0.0, 0.0),
        Vec4::new(1.0, 2.0, 3.0, 1.0),
    );
    // The child at local (0, 0, -1): the parent's z axis times -1 plus its translation.
    let mut child_m = trs_m;
    child_m.w_axis = Vec4::new(-1.0, 2.0, 3.0, 1.0);
    let matrix_m = Mat4::from_translation(Vec3::new(5.0, 6.0, 7.0));
    assert_eq!(sc.batches.len(), 2, "the unmirrored nodes share one batch");
    let b = &sc.batches[0];
    assert_eq!(b.instances.len(), 3);
    // Depth first: trs, its child, then matrix.
    close(b.instances[0], trs_m);
    close(b.instances[1], child_m);
    close(b.instances[2], matrix_m);
    // The mirroring node draws the triangle with the opposite winding.
    let mb = &sc.batches[1];
    assert_eq!(mb.instances.len(), 1);
    close(mb.instances[0], Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)));
    assert_eq!(sc.meshes[b.mesh.0].indices, [0, 1, 2]);
    assert_eq!(sc.meshes[mb.mesh.0].indices, [0, 2, 1]);
    assert_eq!(imp.summary.instances, 4);
    assert_eq!(imp.summary.nodes, 4);
    assert_eq!(imp.summary.triangles, 4);
}

/// A `w` × `h` grid of quads in the xz plane, as triangles (positions per triangle in
/// order: the independent reference of what any split must keep).
fn grid(w: u32, h: u32) -> (Vec<[f32; 3]>, Vec<u32>) {
    let pos = (0..=h)
        .flat_map(|z| (0..=w).map(move |x| [x as f32, 0.0, z as f32]))
        .collect();
    let mut idx = Vec::new();
    for z in 0..h {
        for x in 0..w {
            let a = z * (w + 1) + x;
            let (b, c, d) = (a + 1, a + w + 1, a + w + 2);
            idx.extend_from_slice(&[a, c, b, b, c, d]);
        }
    }
    (pos, idx)
}

fn world_triangles(sc: &scene::Scene) -> Vec<[Vec3; 3]> {
    sc.batches
        .iter()
        .flat_map(|b| {
            let m = &sc.meshes[b.mesh.0];
            m.indices
                .chunks_exact(3)
                .map(|t| {
                    t.iter()
                        .map(|&i| m.positions[i as usize])
                        .collect::<Vec<_>>()
                        .try_into()
                        .unwrap()
                })
                .collect::<Vec<_>>()
        })
        .collect()
}

#[test]
fn meshes_over_the_64k_limits_are_split_with_identical_geometry() {
    let mut doc = Doc::new();
    // 68 000 triangles over 34 371 vertices (u32 indices): over the primitive limit.
    let (pos, idx) = grid(200, 170);
    let p = doc.floats(&pos);
    let n = doc.floats(&vec![[0.0, 1.0, 0.0]; pos.len()]);
    let i = doc.indices(&idx, 5125);
    let big = doc.push(
        "meshes",
        json!({ "primitives": [{ "attributes": { "POSITION": p, "NORMAL": n }, "indices": i }] }),
    );
    // 22 000 unindexed triangles: 66 000 vertices, over the vertex limit.
    let soup: Vec<[f32; 3]> = (0..66_000)
        .map(|k| [(k / 3) as f32, (k % 3) as f32, ((k % 3) == 2) as u32 as f32])
        .collect();
    let sp = doc.floats(&soup);
    let sn = doc.floats(&vec![[1.0, 0.0, 0.0]; soup.len()]);
    let unindexed = doc.push(
        "meshes",
        json!({ "primitives": [{ "attributes": { "POSITION": sp, "NORMAL": sn } }] }),
    );
    let a = doc.push("nodes", json!({ "mesh": big }));
    let b = doc.push("nodes", json!({ "mesh": unindexed }));
    scene(&mut doc, &[a, b]);
    let imp = import(&doc.glb());
    let sc = &imp.scene;
    for m in &sc.meshes {
        assert!(m.positions.len() <= scene::MAX_VERTICES_PER_MESH);
        assert!(m.primitive_count() <= scene::MAX_PRIMITIVES_PER_MESH);
    }
    assert_eq!(sc.meshes.len(), 4, "two pieces each");
    assert_eq!(imp.summary.split_primitives, 2);
    assert_eq!(sc.triangle_count(), 68_000 + 22_000);
    let expected: Vec<[Vec3; 3]> = idx
        .chunks_exact(3)
        .map(|t| {
            t.iter()
                .map(|&i| Vec3::from_array(pos[i as usize]))
                .collect::<Vec<_>>()
                .try_into()
                .unwrap()
        })
        .chain(
            soup.chunks_exact(3)
                .map(|t| [0, 1, 2].map(|k| Vec3::from_array(t[k]))),
        )
        .collect();
    assert!(
        world_triangles(sc) == expected,
        "triangles differ after the split"
    );
    // Attributes travel with their vertices.
    assert!(
        sc.meshes[..2]
            .iter()
            .all(|m| m.normals.iter().all(|&n| n == Vec3::Y))
    );
    assert!(
        sc.meshes[2..]
            .iter()
            .all(|m| m.normals.iter().all(|&n| n == Vec3::X))
    );
}

#[test]
fn missing_normals_tangents_and_uvs_are_made_up() {
    let mut doc = Doc::new();
    // Two triangles sharing an edge, folded 90°: flat normals differ per triangle.
    let p = doc.floats(&[
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, -1.0],
    ]);
    let i = doc.indices(&[0, 1, 2, 0, 3, 1], 5121);
    let mesh = doc.push(
        "meshes",
        json!({ "primitives": [{ "attributes": { "POSITION": p }, "indices": i }] }),
    );
    let node = doc.push("nodes", json!({ "mesh": mesh }));
    scene(&mut doc, &[node]);
    let imp = import(&doc.glb());
    let m = &imp.scene.meshes[0];
    assert_eq!(
        m.positions.len(),
        6,
        "flat shading splits the shared vertices"
    );
    // (b − a) × (c − a): triangle 0 1 2: (1,0,0) × (0,1,0) = +z; triangle 0 3 1:
    // (0,0,−1) × (1,0,0) = (0·0 − (−1)·0, (−1)·1 − 0·0, 0·0 − 0·1) = −y.
    let expected = [
        Vec3::Z,
        Vec3::Z,
        Vec3::Z,
        Vec3::NEG_Y,
        Vec3::NEG_Y,
        Vec3::NEG_Y,
    ];
    for (k, t) in m.indices.iter().enumerate() {
        assert_eq!(m.normals[*t as usize], expected[k]);
    }
    assert!(m.uvs.iter().all(|&uv| uv == Vec2::ZERO));
    for (t, n) in m.tangents.iter().zip(&m.normals) {
        assert!((t.truncate().length() - 1.0).abs() < 1e-5, "{t}");
        assert!(t.truncate().dot(*n).abs() < 1e-5, "{t} vs {n}");
        assert!(t.w == 1.0 || t.w == -1.0);
    }
}

/// A textured scene: two meshes, a shared material, one image.
fn small_scene() -> Doc {
    let mut doc = Doc::new();
    let image = doc.png(&checker(8));
    let tex = doc.texture(image);
    let mat = doc.push(
        "materials",
        json!({ "pbrMetallicRoughness": { "baseColorTexture": { "index": tex }, "metallicFactor": 0.0 } }),
    );
    let a = triangle_mesh(&mut doc, Some(mat));
    let n0 = doc.push("nodes", json!({ "mesh": a, "name": "first" }));
    let n1 = doc.push(
        "nodes",
        json!({ "mesh": a, "translation": [3.0, 0.0, 0.0] }),
    );
    scene(&mut doc, &[n0, n1]);
    doc
}

/// The progress reports of a file with one buffer, one image and one drawn primitive:
/// the steps in order, each ending at done == total, never past it, and the same scene as
/// `load`.
#[test]
fn progress_reports_each_step_to_its_end() {
    use gltf_scene::{Progress, Stage};
    let dir = temp_dir("progress");
    let path = dir.join("scene.glb");
    std::fs::write(&path, small_scene().glb()).unwrap();
    let mut reports: Vec<Progress> = Vec::new();
    let imported =
        gltf_scene::load_with_progress(&path, &LoadOptions::default(), &mut |p| reports.push(p))
            .unwrap();
    assert_eq!(
        imported.scene,
        load(&path, &LoadOptions::default()).unwrap().scene
    );
    assert!(reports.iter().all(|p| p.done <= p.total), "{reports:?}");
    let mut stages: Vec<Stage> = reports.iter().map(|p| p.stage).collect();
    stages.dedup();
    assert_eq!(
        stages,
        [Stage::Parse, Stage::Buffers, Stage::Images, Stage::Meshes]
    );
    for stage in stages {
        let last = reports.iter().rev().find(|p| p.stage == stage).unwrap();
        assert_eq!(
            (last.done, last.total),
            (last.total, last.total),
            "{stage:?}"
        );
        assert!(last.total >= 1, "{stage:?}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn glb_embedded_and_external_buffers_import_alike() {
    let doc = small_scene();
    let glb = import(&doc.glb()).scene;
    let embedded = import(&doc.embedded()).scene;
    let dir = temp_dir("external");
    let path = doc.write_external(&dir, "scene");
    let external = load(&path, &LoadOptions::default()).unwrap().scene;
    assert_eq!(glb, embedded);
    assert_eq!(glb, external);
    assert_eq!(glb.batches[0].instances.len(), 2);
    // An external image file next to the .gltf.
    let mut doc = small_scene();
    std::fs::write(
        dir.join("checker image.png"),
        common::png_bytes(&checker(8)),
    )
    .unwrap();
    doc.json["images"] = json!([{ "uri": "checker%20image.png" }]);
    let path = doc.write_external(&dir, "image");
    assert_eq!(load(&path, &LoadOptions::default()).unwrap().scene, glb);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_first_perspective_camera_is_taken_and_the_framing_camera_sees_everything() {
    let mut doc = small_scene();
    let cam = doc.push(
        "cameras",
        json!({ "type": "perspective", "perspective": { "yfov": 0.8, "znear": 0.05 } }),
    );
    // At (0, 1, 5), turned 90° about +Y: it looks down world -X.
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let node = doc.push("nodes", json!({ "name": "eye", "camera": cam, "translation": [0.0, 1.0, 5.0], "rotation": [0.0, s, 0.0, s] }));
    let roots = doc.json["scenes"][0]["nodes"].as_array().unwrap().clone();
    let mut roots: Vec<usize> = roots.iter().map(|v| v.as_u64().unwrap() as usize).collect();
    roots.push(node);
    doc.json["scenes"][0]["nodes"] = json!(roots);
    let imp = import(&doc.glb());
    let c = imp.camera.unwrap();
    assert!((c.position - Vec3::new(0.0, 1.0, 5.0)).length() < 1e-6);
    assert!(((c.target - c.position).normalize() - Vec3::NEG_X).length() < 1e-6);
    assert!((c.up - Vec3::Y).length() < 1e-6);
    assert_eq!((c.fov_y, c.near), (0.8, 0.05));
    assert_eq!(imp.summary.camera.as_deref(), Some("eye"));

    // Every corner of every instance's bounds lands inside the framing camera's image.
    let sc = &imp.scene;
    for aspect in [16.0 / 9.0, 0.5] {
        let cam = gltf_scene::framing_camera(sc, aspect);
        cam.validate().unwrap();
        let vp = cam.view_projection(aspect);
        for b in &sc.batches {
            for t in &b.instances {
                for p in &sc.meshes[b.mesh.0].positions {
                    let clip = vp * t.transform_point3(*p).extend(1.0);
                    let ndc = clip.truncate() / clip.w;
                    assert!(
                        clip.w > 0.0 && ndc.x.abs() <= 1.0 && ndc.y.abs() <= 1.0,
                        "{ndc}"
                    );
                }
            }
        }
    }
}

fn assert_names(e: &Error, parts: &[&str]) {
    let text = e.to_string();
    for p in parts {
        assert!(text.contains(p), "`{text}` does not say {p:?}");
    }
}

#[test]
fn a_truncated_glb_is_an_error() {
    let glb = small_scene().glb();
    for cut in [glb.len() - 10, 30, 11, 4] {
        let e = import_err(&glb[..cut]);
        assert!(matches!(e, Error::Parse { .. }), "{e}");
        assert_names(&e, &[gltf_scene::SLICE_FILE]);
    }
    assert_names(&import_err(&glb[..glb.len() - 10]), &["truncated"]);
}

#[test]
fn an_accessor_past_its_buffer_view_is_an_error() {
    let mut doc = small_scene();
    doc.json["accessors"][0]["count"] = json!(1000);
    doc.json["accessors"][0]["name"] = json!("corner");
    let e = import_err(&doc.glb());
    assert!(matches!(e, Error::Accessor { accessor: 0, .. }), "{e}");
    assert_names(
        &e,
        &["accessor 0", "\"corner\"", "1000 elements", "past the end"],
    );
    // A buffer view past its buffer.
    let mut doc = small_scene();
    doc.json["bufferViews"][1]["byteLength"] = json!(1 << 20);
    let e = import_err(&doc.glb());
    assert_names(&e, &["buffer view 1", "past the end of buffer 0"]);
}

#[test]
fn an_index_past_the_vertex_count_is_an_error() {
    let mut doc = Doc::new();
    let p = doc.floats(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let i = doc.indices(&[0, 1, 3], 5123);
    let mesh = doc.push(
        "meshes",
        json!({ "name": "bad", "primitives": [{ "attributes": { "POSITION": p }, "indices": i }] }),
    );
    let node = doc.push("nodes", json!({ "mesh": mesh }));
    scene(&mut doc, &[node]);
    let e = import_err(&doc.glb());
    assert!(
        matches!(
            e,
            Error::Primitive {
                mesh: 0,
                primitive: 0,
                ..
            }
        ),
        "{e}"
    );
    assert_names(
        &e,
        &["mesh 0", "\"bad\"", "primitive 0", "index 3", "3 vertices"],
    );
}

#[test]
fn a_missing_buffer_file_is_an_error() {
    let dir = temp_dir("missing");
    let path = small_scene().write_external(&dir, "lost");
    std::fs::remove_file(dir.join("lost.bin")).unwrap();
    let e = load(&path, &LoadOptions::default()).unwrap_err();
    assert!(matches!(e, Error::Buffer { buffer: 0, .. }), "{e}");
    assert_names(&e, &["lost.gltf", "buffer 0", "lost.bin"]);
    // Bytes with an external buffer and no base directory.
    let bytes = std::fs::read(&path).unwrap();
    assert_names(&import_err(&bytes), &["buffer 0", "no base directory"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn an_unsupported_required_extension_is_an_error() {
    let mut doc = small_scene();
    doc.json["extensionsUsed"] = json!(["KHR_draco_mesh_compression"]);
    doc.json["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]);
    let e = import_err(&doc.glb());
    assert_eq!(
        e,
        Error::UnsupportedExtension {
            file: gltf_scene::SLICE_FILE.to_owned(),
            extension: "KHR_draco_mesh_compression".to_owned()
        }
    );
    // Used but not required: imported.
    doc.json
        .as_object_mut()
        .unwrap()
        .remove("extensionsRequired");
    import(&doc.glb());
}

#[test]
fn non_finite_data_is_an_error() {
    let mut doc = Doc::new();
    let p = doc.floats(&[[0.0, 0.0, 0.0], [f32::NAN, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let mesh = doc.push(
        "meshes",
        json!({ "primitives": [{ "attributes": { "POSITION": p } }] }),
    );
    let node = doc.push("nodes", json!({ "mesh": mesh }));
    scene(&mut doc, &[node]);
    let e = import_err(&doc.glb());
    assert_names(&e, &["accessor 0", "POSITION element 1 is not finite"]);
    // A transform that overflows: 1e30 × 1e30.
    let mut doc = small_scene();
    doc.json["nodes"][0]["scale"] = json!([1e30, 1e30, 1e30]);
    doc.json["nodes"][0]["children"] = json!([1]);
    doc.json["nodes"][1]["scale"] = json!([1e30, 1e30, 1e30]);
    doc.json["scenes"][0]["nodes"] = json!([0]);
    let e = import_err(&doc.glb());
    assert!(matches!(e, Error::Node { node: 1, .. }), "{e}");
}

#[test]
fn broken_hierarchies_references_and_images_are_errors() {
    // A cycle.
    let mut doc = small_scene();
    doc.json["nodes"][0]["children"] = json!([1]);
    doc.json["nodes"][1]["children"] = json!([0]);
    doc.json["scenes"][0]["nodes"] = json!([0]);
    let e = import_err(&doc.glb());
    assert!(matches!(e, Error::Node { node: 0, .. }), "{e}");
    assert_names(&e, &["node 0", "\"first\"", "reached twice"]);
    // A reference past its array.
    let mut doc = small_scene();
    doc.json["meshes"][0]["primitives"][0]["indices"] = json!(99);
    let e = import_err(&doc.glb());
    assert_names(&e, &["meshes[0].primitives[0].indices"]);
    // An image that is not one.
    let mut doc = small_scene();
    let view = doc.view(b"not a png at all", None);
    doc.json["images"][0]["bufferView"] = json!(view);
    let e = import_err(&doc.glb());
    assert!(matches!(e, Error::Image { image: 0, .. }), "{e}");
    // Not JSON.
    assert!(matches!(import_err(b"{ nope"), Error::Parse { .. }));
    // Nothing.
    assert!(matches!(import_err(b""), Error::Parse { .. }));
}

/// The fuzz target's seed corpus, `fuzz/seeds/gltf_import/`: small files covering the
/// importer's paths (JSON with a data URI and `.glb`; textures, MASK, double-sided, a
/// texture transform, a camera, u8 indices, no normals, a strip, a mirroring node).
/// Each committed seed is the file this test builds (byte for byte) and imports; with
/// `WRITE_FUZZ_SEEDS=1` in the environment the test rewrites them instead.
#[test]
fn the_committed_fuzz_seeds_are_current_and_import() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/seeds/gltf_import");
    let write = std::env::var_os("WRITE_FUZZ_SEEDS").is_some();
    let mut rich = small_scene();
    rich.json["extensionsUsed"] = json!(["KHR_texture_transform"]);
    rich.json["materials"][0]["alphaMode"] = json!("MASK");
    rich.json["materials"][0]["doubleSided"] = json!(true);
    rich.json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = json!({ "KHR_texture_transform": { "offset": [0.25, 0.5], "rotation": 0.3, "scale": [2.0, 2.0] } });
    let cam = rich.push(
        "cameras",
        json!({ "type": "perspective", "perspective": { "yfov": 0.9, "znear": 0.1 } }),
    );
    let eye = rich.push(
        "nodes",
        json!({ "camera": cam, "translation": [0.0, 1.0, 4.0] }),
    );
    let p = rich.floats(&[
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.5],
    ]);
    let i = rich.indices(&[0, 1, 2, 3], 5121);
    let strip = rich.push(
        "meshes",
        json!({ "primitives": [{ "attributes": { "POSITION": p }, "indices": i, "mode": 5 }] }),
    );
    let s = rich.push("nodes", json!({ "mesh": strip, "scale": [1.0, -1.0, 1.0] }));
    rich.json["scenes"][0]["nodes"] = json!([0, 1, eye, s]);
    for (name, bytes) in [
        ("small.glb", small_scene().glb()),
        ("small.gltf", small_scene().embedded()),
        ("rich.glb", rich.glb()),
        ("rich.gltf", rich.embedded()),
    ] {
        import(&bytes);
        let path = dir.join(name);
        if write {
            std::fs::create_dir_all(&dir).unwrap();
            std::fs::write(&path, &bytes).unwrap();
        } else {
            let committed = std::fs::read(&path).unwrap_or_else(|e| {
                panic!("{}: {e} (WRITE_FUZZ_SEEDS=1 writes it)", path.display())
            });
            assert!(
                committed == bytes,
                "{} differs from what this test builds (WRITE_FUZZ_SEEDS=1 rewrites it)",
                path.display()
            );
        }
    }
}

#[test]
fn quantized_attributes_and_sparse_accessors_decode_as_the_spec_says() {
    let mut doc = Doc::new();
    doc.json["extensionsUsed"] = json!(["KHR_mesh_quantization"]);
    doc.json["extensionsRequired"] = json!(["KHR_mesh_quantization"]);
    // POSITION as plain u16 (scaled by the node), NORMAL as normalized i8 (padded to 4
    // bytes a vertex), TEXCOORD_0 as normalized u8 (padded to 4).
    let pos: Vec<u8> = [[0u16, 0, 0], [100, 0, 0], [0, 200, 0]]
        .iter()
        .flat_map(|p| p.iter().flat_map(|c| c.to_le_bytes()).chain([0, 0]))
        .collect();
    let pv = doc.view(&pos, Some(8));
    let p = doc.push(
        "accessors",
        json!({ "bufferView": pv, "componentType": 5123, "count": 3, "type": "VEC3",
        "min": [0, 0, 0], "max": [100, 200, 0] }),
    );
    let nv = doc.view(&[0, 0, 127, 0, 0, 0, 129, 0, 0, 0, 127, 0], Some(4));
    let n = doc.push("accessors", json!({ "bufferView": nv, "componentType": 5120, "normalized": true, "count": 3, "type": "VEC3" }));
    let uvv = doc.view(&[0, 255, 0, 0, 51, 0, 0, 0, 0, 102, 0, 0], Some(4));
    let uv = doc.push("accessors", json!({ "bufferView": uvv, "componentType": 5121, "normalized": true, "count": 3, "type": "VEC2" }));
    // Indices 0 0 0 with a sparse substitution: entries 1 and 2 become 1 and 2.
    let iv = doc.view(&[0u8; 6], None);
    let sparse_i = doc.view(&[1, 0, 2, 0], None);
    let sparse_v = doc.view(&[1, 0, 2, 0], None);
    let i = doc.push(
        "accessors",
        json!({ "bufferView": iv, "componentType": 5123, "count": 3, "type": "SCALAR",
        "sparse": { "count": 2, "indices": { "bufferView": sparse_i, "componentType": 5123 },
                    "values": { "bufferView": sparse_v } } }),
    );
    let mesh = doc.push("meshes", json!({ "primitives": [{ "attributes": { "POSITION": p, "NORMAL": n, "TEXCOORD_0": uv }, "indices": i }] }));
    let node = doc.push(
        "nodes",
        json!({ "mesh": mesh, "scale": [0.01, 0.01, 0.01] }),
    );
    scene(&mut doc, &[node]);
    let m = &import(&doc.glb()).scene.meshes[0];
    assert_eq!(m.indices, [0, 1, 2]);
    assert_eq!(
        m.positions,
        [
            Vec3::ZERO,
            Vec3::new(100.0, 0.0, 0.0),
            Vec3::new(0.0, 200.0, 0.0)
        ]
    );
    // i8 normalized: max(c / 127, -1): 127 -> 1, -127 (129 as i8) -> -1.
    assert_eq!(m.normals, [Vec3::Z, Vec3::NEG_Z, Vec3::Z]);
    // u8 normalized: c / 255.
    assert_eq!(
        m.uvs,
        [
            Vec2::new(0.0, 1.0),
            Vec2::new(0.2, 0.0),
            Vec2::new(0.0, 0.4)
        ]
    );
}

/// The seeds of the fuzz target mutated (bytes replaced, digits changed in the JSON,
/// truncations): every result is an import or an error, never a panic, and an import is
/// a valid scene. `GLTF_SCENE_MUTATE_SEED=n` and `GLTF_SCENE_MUTATE_DIR=dir` (more seed
/// files) vary a run; this found the gltf-json and mikktspace panics worked around in
/// `gltf_scene`.
#[test]
fn mutated_files_never_panic() {
    const ROUNDS: usize = 1500;
    let mut rng = testkit::Rng::new(
        std::env::var("GLTF_SCENE_MUTATE_SEED").map_or(18, |s| s.parse().unwrap()),
    );
    let mut rich = small_scene();
    rich.json["materials"][0]["alphaMode"] = json!("MASK");
    rich.json["materials"][0]["doubleSided"] = json!(true);
    let mut seeds = vec![small_scene().glb(), small_scene().embedded(), rich.glb()];
    if let Ok(dir) = std::env::var("GLTF_SCENE_MUTATE_DIR") {
        for e in std::fs::read_dir(dir).unwrap() {
            seeds.push(std::fs::read(e.unwrap().path()).unwrap());
        }
    }
    let mut imported = 0;
    for seed in &seeds {
        for _ in 0..ROUNDS {
            let mut b = seed.clone();
            for _ in 0..1 + rng.next_u64() % 4 {
                if b.is_empty() {
                    break;
                }
                let at = (rng.next_u64() % b.len() as u64) as usize;
                match rng.next_u64() % 4 {
                    0 => b[at] = rng.next_u64() as u8,
                    1 if b[at].is_ascii_digit() => b[at] = b'0' + (rng.next_u64() % 10) as u8,
                    2 => b.truncate(at),
                    _ => b[at] ^= 1 << (rng.next_u64() % 8),
                }
            }
            if let Ok(i) = load_slice(&b, None, &LoadOptions::default()) {
                i.scene.validate().unwrap();
                imported += 1;
            }
        }
    }
    eprintln!(
        "{imported} of {} mutated files imported",
        seeds.len() * ROUNDS
    );
}

#[test]
fn inputs_that_made_dependencies_panic_are_imported_or_refused() {
    // Every triangle degenerate (mikktspace 0.3: `0 - 1` on a usize), and every vertex at
    // one point (its welding grid indexed past its table): imported, with tangents
    // orthogonal to the normals.
    for (pos, idx) in [
        (
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            vec![0, 0, 1, 2, 2, 1],
        ),
        (vec![[2.0, 2.0, 2.0]; 3], vec![0, 1, 2]),
    ] {
        let mut doc = Doc::new();
        let p = doc.floats(&pos);
        let i = doc.indices(&idx, 5125);
        let mesh = doc.push(
            "meshes",
            json!({ "primitives": [{ "attributes": { "POSITION": p }, "indices": i }] }),
        );
        let node = doc.push("nodes", json!({ "mesh": mesh }));
        scene(&mut doc, &[node]);
        let m = &import(&doc.glb()).scene.meshes[0];
        for (t, n) in m.tangents.iter().zip(&m.normals) {
            assert!(
                t.truncate().dot(*n).abs() < 1e-6 && (t.truncate().length() - 1.0).abs() < 1e-6
            );
        }
    }
    // A .glb header whose length is under 12 (gltf 1.4 subtracted 12 from it unchecked).
    let mut glb = small_scene().glb();
    glb[8..12].copy_from_slice(&11u32.to_le_bytes());
    assert_names(&import_err(&glb), &["less than the header"]);
    // POSITION naming an accessor that does not exist (gltf-json 1.4 indexed it unchecked).
    let mut doc = small_scene();
    doc.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(99);
    let e = import_err(&doc.glb());
    assert_names(
        &e,
        &["meshes[0].primitives[0].attributes.POSITION", "accessor 99"],
    );
    // An image in a buffer view without its mimeType (gltf's Image::source unwrapped it).
    let mut doc = small_scene();
    doc.json["images"][0]
        .as_object_mut()
        .unwrap()
        .remove("mimeType");
    match load_slice(&doc.glb(), None, &LoadOptions::default()) {
        Ok(i) => assert_eq!(i.summary.textures, 1),
        Err(e) => assert_names(&e, &["images"]),
    }
}
