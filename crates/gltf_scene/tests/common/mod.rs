//! A small glTF writer for the tests: JSON built with serde_json, one binary buffer, written
//! as `.glb`, `.gltf` with a data URI, or `.gltf` next to an external `.bin`. Independent
//! of the importer (it shares no code with it).
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use serde_json::{Value, json};

/// A glTF document under construction, buffer 0 being `bin`.
pub struct Doc {
    pub json: Value,
    pub bin: Vec<u8>,
}

impl Default for Doc {
    fn default() -> Self {
        Self::new()
    }
}

impl Doc {
    pub fn new() -> Self {
        Self {
            json: json!({ "asset": { "version": "2.0", "generator": "gltf_scene tests" } }),
            bin: Vec::new(),
        }
    }

    /// Appends `v` to the top-level array `key`; its index.
    pub fn push(&mut self, key: &str, v: Value) -> usize {
        let arr = self.json[key].as_array_mut().map(std::mem::take);
        let mut arr = arr.unwrap_or_default();
        arr.push(v);
        let n = arr.len() - 1;
        self.json[key] = Value::Array(arr);
        n
    }

    /// A buffer view of `bytes` (4-byte aligned in buffer 0).
    pub fn view(&mut self, bytes: &[u8], stride: Option<usize>) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        let mut v = json!({ "buffer": 0, "byteOffset": offset, "byteLength": bytes.len() });
        if let Some(s) = stride {
            v["byteStride"] = json!(s);
        }
        self.push("bufferViews", v)
    }

    /// A float accessor of `N`-component elements (with min/max, as POSITION needs).
    pub fn floats<const N: usize>(&mut self, data: &[[f32; N]]) -> usize {
        let bytes: Vec<u8> = data
            .iter()
            .flatten()
            .flat_map(|f| f.to_le_bytes())
            .collect();
        let view = self.view(&bytes, None);
        let mut min = [f32::INFINITY; N];
        let mut max = [f32::NEG_INFINITY; N];
        for e in data {
            for k in 0..N {
                min[k] = min[k].min(e[k]);
                max[k] = max[k].max(e[k]);
            }
        }
        let ty = ["SCALAR", "VEC2", "VEC3", "VEC4"][N - 1];
        let mut a =
            json!({ "bufferView": view, "componentType": 5126, "count": data.len(), "type": ty });
        if !data.is_empty() && min.iter().chain(&max).all(|x| x.is_finite()) {
            a["min"] = json!(min.to_vec());
            a["max"] = json!(max.to_vec());
        }
        self.push("accessors", a)
    }

    /// An index accessor: u8 (5121), u16 (5123) or u32 (5125) by `component_type`.
    pub fn indices(&mut self, idx: &[u32], component_type: u32) -> usize {
        let bytes: Vec<u8> = match component_type {
            5121 => idx.iter().map(|&i| i as u8).collect(),
            5123 => idx.iter().flat_map(|&i| (i as u16).to_le_bytes()).collect(),
            _ => idx.iter().flat_map(|&i| i.to_le_bytes()).collect(),
        };
        let view = self.view(&bytes, None);
        self.push(
            "accessors",
            json!({ "bufferView": view, "componentType": component_type, "count": idx.len(), "type": "SCALAR" }),
        )
    }

    /// A PNG image stored in a buffer view; its image index.
    pub fn png(&mut self, img: &image::RgbaImage) -> usize {
        let view = self.view(&png_bytes(img), None);
        self.push(
            "images",
            json!({ "bufferView": view, "mimeType": "image/png" }),
        )
    }

    /// A texture of image `image` (default sampler).
    pub fn texture(&mut self, image: usize) -> usize {
        self.push("textures", json!({ "source": image }))
    }

    /// The document with buffer 0 given `uri` (none: the GLB BIN chunk).
    pub fn json_with_buffer(&self, uri: Option<String>) -> Value {
        let mut j = self.json.clone();
        if !self.bin.is_empty() || j.get("bufferViews").is_some() {
            let mut b = json!({ "byteLength": self.bin.len() });
            if let Some(u) = uri {
                b["uri"] = json!(u);
            }
            let mut buffers = j["buffers"].as_array().cloned().unwrap_or_default();
            buffers.insert(0, b);
            j["buffers"] = Value::Array(buffers);
        }
        j
    }

    /// `.glb` bytes.
    pub fn glb(&self) -> Vec<u8> {
        glb(&self.json_with_buffer(None), &self.bin)
    }

    /// `.gltf` bytes with the buffer as a base64 data URI.
    pub fn embedded(&self) -> Vec<u8> {
        let uri = format!("data:application/octet-stream;base64,{}", base64(&self.bin));
        serde_json::to_vec_pretty(&self.json_with_buffer(Some(uri))).unwrap()
    }

    /// Writes `dir/name.gltf` and `dir/name.bin`; the `.gltf`'s path.
    pub fn write_external(&self, dir: &Path, name: &str) -> PathBuf {
        std::fs::create_dir_all(dir).unwrap();
        std::fs::write(dir.join(format!("{name}.bin")), &self.bin).unwrap();
        let j = self.json_with_buffer(Some(format!("{name}.bin")));
        let path = dir.join(format!("{name}.gltf"));
        std::fs::write(&path, serde_json::to_vec_pretty(&j).unwrap()).unwrap();
        path
    }
}

/// A GLB container (glTF 2.0 §4.4): header, JSON chunk padded with spaces, BIN chunk
/// padded with zeros.
pub fn glb(json: &Value, bin: &[u8]) -> Vec<u8> {
    let mut j = serde_json::to_vec(json).unwrap();
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let mut b = bin.to_vec();
    while !b.len().is_multiple_of(4) {
        b.push(0);
    }
    let has_bin = !bin.is_empty() || json["buffers"].is_array();
    let total = 12 + 8 + j.len() + if has_bin { 8 + b.len() } else { 0 };
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(j.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&j);
    if has_bin {
        out.extend_from_slice(&(b.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&b);
    }
    out
}

pub fn base64(data: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in data.chunks(3) {
        let n = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for k in 0..4 {
            if k <= c.len() {
                s.push(A[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

pub fn png_bytes(img: &image::RgbaImage) -> Vec<u8> {
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

/// A fresh temporary directory for one test.
pub fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gltf_scene_{}_{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// One triangle in the xy plane (positions, normals +Z, uvs) as a mesh with `material`
/// (none: the default material); its mesh index.
pub fn triangle_mesh(doc: &mut Doc, material: Option<usize>) -> usize {
    let pos = doc.floats(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let nrm = doc.floats(&[[0.0, 0.0, 1.0]; 3]);
    let uv = doc.floats(&[[0.0, 1.0], [1.0, 1.0], [0.0, 0.0]]);
    let mut prim = json!({ "attributes": { "POSITION": pos, "NORMAL": nrm, "TEXCOORD_0": uv } });
    if let Some(m) = material {
        prim["material"] = json!(m);
    }
    doc.push("meshes", json!({ "name": "tri", "primitives": [prim] }))
}

/// A scene of `nodes` (root node indices) as the default scene.
pub fn scene(doc: &mut Doc, nodes: &[usize]) {
    doc.push("scenes", json!({ "nodes": nodes }));
    doc.json["scene"] = json!(0);
}

/// A `size` × `size` checker of opaque and transparent texels, with colour ramps.
pub fn checker(size: u32) -> image::RgbaImage {
    image::RgbaImage::from_fn(size, size, |x, y| {
        let on = (x + y) % 2 == 0;
        image::Rgba([
            if on { 250 } else { 10 },
            (x * 7) as u8,
            (y * 5) as u8,
            if on { 255 } else { 0 },
        ])
    })
}
