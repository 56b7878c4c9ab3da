//! The import driver: the file's checks (GLB header, glTF schema, required extensions),
//! its buffers, and the walk from parsed document to the renderer's scene.

use std::collections::{HashMap, HashSet};
use std::path::Path;

use scene::{AlbedoLayer, Batch, DataLayer, MaterialId, MeshId, NormalMap, OcclusionMap, Scene};

use crate::geometry::Geometry;
use crate::nodes::walk;
use crate::primitive::primitive_geometry;
use crate::{
    Error, Imported, LoadOptions, Progress, SUPPORTED_EXTENSIONS, Stage, Summary, accessor,
    material, source,
};

/// The glTF schema check of gltf-json, minus its verdict on `extensionsRequired` (ours
/// is [`SUPPORTED_EXTENSIONS`]).
pub(crate) fn validate(file: &str, root: &gltf::json::Root) -> Result<(), Error> {
    use gltf::json::validation::Validate;
    for ext in &root.extensions_required {
        if !SUPPORTED_EXTENSIONS.contains(&ext.as_str()) {
            return Err(Error::UnsupportedExtension {
                file: file.to_owned(),
                extension: ext.clone(),
            });
        }
    }
    // gltf-json 1.4's check of POSITION's min/max indexes the accessors unchecked: check
    // every attribute's reference first.
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            for (semantic, accessor) in &prim.attributes {
                if accessor.value() >= root.accessors.len() {
                    let name = match semantic {
                        gltf::json::validation::Checked::Valid(s) => s.to_string(),
                        gltf::json::validation::Checked::Invalid => "(invalid)".to_owned(),
                    };
                    return Err(Error::Invalid {
                        file: file.to_owned(),
                        path: format!("meshes[{m}].primitives[{p}].attributes.{name}"),
                        problem: format!(
                            "accessor {} is past the end of the {} accessors",
                            accessor.value(),
                            root.accessors.len()
                        ),
                    });
                }
            }
        }
    }
    let mut errors = Vec::new();
    root.validate(root, gltf::json::Path::new, &mut |path, error| {
        let path = path().to_string();
        if !path.starts_with("extensionsRequired") {
            errors.push((path, error));
        }
    });
    match errors.first() {
        None => Ok(()),
        Some((path, error)) => Err(Error::Invalid {
            file: file.to_owned(),
            path: path.clone(),
            problem: if errors.len() > 1 {
                format!("{error} (and {} more problems)", errors.len() - 1)
            } else {
                error.to_string()
            },
        }),
    }
}

/// A `.glb`'s header checked before gltf parses it, so a truncated file says so.
pub(crate) fn check_glb_header(file: &str, bytes: &[u8]) -> Result<(), Error> {
    if !bytes.starts_with(b"glTF") {
        return Ok(());
    }
    let parse = |problem: String| Error::Parse {
        file: file.to_owned(),
        problem,
    };
    if bytes.len() < 12 {
        return Err(parse(format!(
            "truncated .glb: {} bytes, less than its 12-byte header",
            bytes.len()
        )));
    }
    let word =
        |at: usize| u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    if word(4) != 2 {
        return Err(parse(format!(".glb version {}, not 2", word(4))));
    }
    let length = word(8) as usize;
    // gltf 1.4 subtracts 12 from it unchecked.
    if length < 12 {
        return Err(parse(format!(
            ".glb header says {length} bytes, less than the header itself (12)"
        )));
    }
    if length > bytes.len() {
        return Err(parse(format!(
            "truncated .glb: its header says {length} bytes, the file has {}",
            bytes.len()
        )));
    }
    Ok(())
}

/// The buffers' bytes, each cut to its `byteLength`.
pub(crate) fn load_buffers(
    file: &str,
    doc: &gltf::Document,
    mut blob: Option<Vec<u8>>,
    base: Option<&Path>,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Vec<Vec<u8>>, Error> {
    let mut out = Vec::new();
    let total = doc.buffers().len();
    progress(0, total);
    for b in doc.buffers() {
        let err = |problem: String| Error::Buffer {
            file: file.to_owned(),
            buffer: b.index(),
            name: b.name().map(str::to_owned),
            problem,
        };
        let mut data = match b.source() {
            gltf::buffer::Source::Bin => blob.take().ok_or_else(|| {
                err(
                    "it is the .glb's BIN chunk, but the file has none (or a second buffer \
                     claims it)"
                        .to_owned(),
                )
            })?,
            gltf::buffer::Source::Uri(uri) => source::read_uri(base, uri).map_err(&err)?,
        };
        if data.len() < b.length() {
            return Err(err(format!(
                "{} bytes, fewer than its byteLength {}",
                data.len(),
                b.length()
            )));
        }
        data.truncate(b.length());
        out.push(data);
        progress(out.len(), total);
    }
    Ok(out)
}

pub(crate) fn import(
    bytes: &[u8],
    base: Option<&Path>,
    file: &str,
    options: &LoadOptions,
    progress: &mut dyn FnMut(Progress),
) -> Result<Imported, Error> {
    let mut report = |stage, done: usize, total: usize| {
        progress(Progress {
            stage,
            done: done as u64,
            total: total as u64,
        });
    };
    report(Stage::Parse, 0, 1);
    check_glb_header(file, bytes)?;
    let gltf = gltf::Gltf::from_slice_without_validation(bytes).map_err(|e| Error::Parse {
        file: file.to_owned(),
        problem: e.to_string(),
    })?;
    validate(file, gltf.document.as_json())?;
    let gltf::Gltf {
        document: doc,
        blob,
    } = gltf;
    report(Stage::Parse, 1, 1);
    let buffers = load_buffers(file, &doc, blob, base, &mut |done, total| {
        report(Stage::Buffers, done, total);
    })?;
    let data = accessor::Data {
        file,
        buffers: &buffers,
    };
    let mut warnings = Vec::new();
    let walked = walk(file, &doc, options, &mut warnings)?;

    // Materials of the drawn primitives, in order of first use.
    let mesh_of = |i: usize| doc.meshes().nth(i);
    let mut materials: Vec<material::Imported> = Vec::new();
    let mut material_of: HashMap<Option<usize>, usize> = HashMap::new();
    for (key, _) in &walked.draws {
        let Some(prim) = mesh_of(key.mesh).and_then(|m| m.primitives().nth(key.primitive)) else {
            continue;
        };
        let m = prim.material();
        if let std::collections::hash_map::Entry::Vacant(e) = material_of.entry(m.index()) {
            e.insert(materials.len());
            // A material with a bad value is replaced, so the rest of the file still draws.
            materials.push(match material::import(file, &m, &mut warnings) {
                Ok(imported) => imported,
                Err(e) => {
                    warnings.push(format!("{e}: drawn with glTF's default material"));
                    material::Imported::fallback(m.name())
                }
            });
        }
    }

    // Textures: base colour and emissive images become albedo layers (sRGB), normal,
    // metallic-roughness and occlusion images data layers (linear); an image used by
    // several materials is one layer.
    let image_of = |i: usize| doc.images().nth(i);
    let mut decoded: HashMap<usize, image::RgbaImage> = HashMap::new();
    let images = doc.images().len();
    report(Stage::Images, 0, images);
    // Whether image `i` is (now) decoded.
    let mut decode = |i: usize| -> Result<bool, Error> {
        if let (false, Some(img)) = (decoded.contains_key(&i), image_of(i)) {
            let rgba = material::decode_image(file, &doc, &img, &buffers, base, options)?;
            decoded.insert(i, rgba);
            report(Stage::Images, decoded.len(), images);
        }
        Ok(decoded.contains_key(&i))
    };
    let mut albedo_images: Vec<usize> = Vec::new();
    let mut data_images: Vec<usize> = Vec::new();
    for m in materials.iter().filter(|m| !m.invisible) {
        for t in m.texture.into_iter().chain(m.maps.emissive) {
            if decode(t)? && !albedo_images.contains(&t) {
                albedo_images.push(t);
            }
        }
        for t in m.maps.data() {
            if decode(t)? && !data_images.contains(&t) {
                data_images.push(t);
            }
        }
    }
    report(Stage::Images, images, images);
    let cap = options.max_layer_size.max(1);
    let cap = 1u32 << cap.ilog2();
    // Each array's sources and its layer size.
    let sized = |chosen: &[usize]| {
        let sources: Vec<&image::RgbaImage> =
            chosen.iter().filter_map(|i| decoded.get(i)).collect();
        let size =
            material::layer_size(sources.iter().map(|img| img.width().max(img.height())), cap);
        (sources, size)
    };
    let (albedo_sources, size) = sized(&albedo_images);
    let (data_sources, data_size) = sized(&data_images);
    let resampled = albedo_sources
        .iter()
        .map(|img| (img, size))
        .chain(data_sources.iter().map(|img| (img, data_size)))
        .filter(|(img, s)| img.width() != *s || img.height() != *s)
        .count();
    let mut layers: Vec<AlbedoLayer> = albedo_sources
        .iter()
        .map(|img| material::to_layer(img, size))
        .collect();
    let data_layers: Vec<DataLayer> = data_sources
        .iter()
        .map(|img| material::to_data_layer(img, data_size))
        .collect();
    let textures = layers.len();
    let data_textures = data_layers.len();
    let mut white = None;
    let mut gpu_materials = Vec::new();
    let position = |images: &[usize], t: Option<usize>| {
        t.and_then(|t| images.iter().position(|&i| i == t))
            .map(|l| l as u32)
    };
    for m in &materials {
        let mut gm = m.material.clone();
        gm.albedo_layer = match position(&albedo_images, m.texture) {
            Some(l) => l,
            None => *white.get_or_insert_with(|| {
                layers.push(AlbedoLayer {
                    size,
                    texels: vec![[255; 4]; (size as usize).pow(2)],
                });
                layers.len() as u32 - 1
            }),
        };
        let maps = &mut gm.maps;
        maps.emissive = position(&albedo_images, m.maps.emissive);
        maps.metallic_roughness = position(&data_images, m.maps.metallic_roughness);
        maps.normal = maps.normal.and_then(|n| {
            Some(NormalMap {
                layer: position(&data_images, m.maps.normal)?,
                ..n
            })
        });
        maps.occlusion = maps.occlusion.and_then(|o| {
            Some(OcclusionMap {
                layer: position(&data_images, m.maps.occlusion)?,
                ..o
            })
        });
        gpu_materials.push(gm);
    }

    // Geometry and batches.
    let mut scene = Scene {
        materials: gpu_materials,
        albedo_layers: layers,
        data_layers,
        ..Scene::default()
    };
    let mut base_geometry: HashMap<(usize, usize), Option<Geometry>> = HashMap::new();
    let mut split = HashSet::new();
    let mut meshes_drawn = HashSet::new();
    let mut primitives_drawn = HashSet::new();
    let draws = walked.draws.len();
    for (done, (key, instances)) in walked.draws.iter().enumerate() {
        report(Stage::Meshes, done, draws);
        let Some(mesh) = mesh_of(key.mesh) else {
            continue;
        };
        let Some(prim) = mesh.primitives().nth(key.primitive) else {
            continue;
        };
        let mi = material_of[&prim.material().index()];
        if materials[mi].invisible {
            continue;
        }
        let geometry = match base_geometry.entry((key.mesh, key.primitive)) {
            std::collections::hash_map::Entry::Occupied(e) => e.into_mut(),
            std::collections::hash_map::Entry::Vacant(e) => e.insert(primitive_geometry(
                &data,
                &mesh,
                &prim,
                &materials[mi],
                &mut warnings,
            )?),
        };
        let Some(g) = geometry.as_ref() else {
            continue;
        };
        meshes_drawn.insert(key.mesh);
        primitives_drawn.insert((key.mesh, key.primitive));
        let g = if key.mirrored { g.flipped() } else { g.clone() };
        let name = format!(
            "{} primitive {}{}",
            mesh.name()
                .map_or_else(|| format!("mesh {}", mesh.index()), |n| format!("{n:?}")),
            prim.index(),
            if key.mirrored { " (mirrored)" } else { "" }
        );
        let pieces = g.into_meshes(&name);
        if pieces.len() > 1 {
            split.insert((key.mesh, key.primitive));
        }
        for piece in pieces {
            scene.batches.push(Batch {
                mesh: MeshId(scene.meshes.len()),
                material: MaterialId(mi),
                instances: instances.clone(),
            });
            scene.meshes.push(piece);
        }
    }
    report(Stage::Meshes, draws, draws);
    scene.validate().map_err(|e| Error::Scene {
        file: file.to_owned(),
        problem: e.to_string(),
    })?;

    let mut seen = HashSet::new();
    warnings.retain(|w| seen.insert(w.clone()));
    let summary = Summary {
        file: file.to_owned(),
        meshes: meshes_drawn.len(),
        primitives: primitives_drawn.len(),
        renderer_meshes: scene.meshes.len(),
        split_primitives: split.len(),
        mesh_triangles: scene
            .meshes
            .iter()
            .map(|m| m.primitive_count() as u64)
            .sum(),
        triangles: scene.triangle_count(),
        nodes: walked.nodes,
        instances: scene.instance_count(),
        batches: scene.batches.len(),
        materials: scene.materials.len(),
        double_sided: materials.iter().filter(|m| m.double_sided).count(),
        textures,
        data_textures,
        resampled,
        layer_size: size,
        data_layer_size: data_size,
        camera: walked.camera.as_ref().map(|(_, l)| l.clone()),
        warnings: warnings.len(),
    };
    Ok(Imported {
        scene,
        camera: walked.camera.map(|(c, _)| c),
        summary,
        warnings,
    })
}
