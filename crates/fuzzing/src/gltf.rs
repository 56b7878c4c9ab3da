//! Fuzz body for the `gltf_scene` importer: arbitrary bytes as `.gltf` JSON or `.glb`
//! (seeded with the importer's test files, `fuzz/seeds/gltf_import/`). Nothing may panic;
//! an import that succeeds must give a scene the renderer accepts.

use gltf_scene::scene::{MAX_PRIMITIVES_PER_MESH, MAX_VERTICES_PER_MESH};
use gltf_scene::{LoadOptions, load_slice};

/// Imports `data` (no base directory: external files are errors, never read) with small
/// image limits, and checks what comes back: a valid `scene::Scene` within the 64k limits,
/// and a summary that counts it.
pub fn gltf_import(data: &[u8]) {
    let options = LoadOptions {
        max_layer_size: 64,
        scene: None,
        max_image_dimension: 2048,
        max_image_bytes: 32 << 20,
    };
    let Ok(imported) = load_slice(data, None, &options) else {
        return;
    };
    let scene = &imported.scene;
    if let Err(e) = scene.validate() {
        panic!("the importer returned a scene the renderer rejects: {e}");
    }
    for m in &scene.meshes {
        assert!(m.positions.len() <= MAX_VERTICES_PER_MESH, "{}", m.name);
        assert!(m.primitive_count() <= MAX_PRIMITIVES_PER_MESH, "{}", m.name);
    }
    assert_eq!(imported.summary.instances, scene.instance_count());
    assert_eq!(imported.summary.triangles, scene.triangle_count());
    if let Some(c) = imported.camera {
        assert!(
            c.validate().is_ok(),
            "the importer returned an invalid camera"
        );
    }
}
