//! glTF materials and base colour textures into the renderer's materials and albedo
//! layers.

use std::io::Cursor;

use image::{ImageFormat, RgbaImage};
use scene::glam::{Mat3, Vec2, Vec3};
use scene::{AlbedoLayer, DataLayer, Material, MaterialMaps, NormalMap, OcclusionMap, ShaderKind};

use crate::{Error, LoadOptions};

/// A decoded image: RGBA8, sRGB colour, linear alpha, as glTF stores base colour.
pub(crate) fn decode_image(
    file: &str,
    doc: &gltf::Document,
    image: &gltf::Image<'_>,
    buffers: &[Vec<u8>],
    base: Option<&std::path::Path>,
    options: &LoadOptions,
) -> Result<RgbaImage, Error> {
    let err = |problem: String| Error::Image {
        file: file.to_owned(),
        image: image.index(),
        name: image.name().map(str::to_owned),
        problem,
    };
    // From the JSON: gltf's `Image::source` unwraps a missing mimeType or uri.
    let json = &doc.as_json().images[image.index()];
    let owned;
    let bytes: &[u8] = match (&json.buffer_view, &json.uri) {
        (Some(v), _) => {
            let view = &doc.as_json().buffer_views[v.value()];
            let (b, offset, len) = (
                view.buffer.value(),
                view.byte_offset.map_or(0, |o| o.0 as usize),
                view.byte_length.0 as usize,
            );
            let buffer = &buffers[b];
            match offset.checked_add(len) {
                Some(end) if end <= buffer.len() => &buffer[offset..end],
                _ => {
                    return Err(err(format!(
                        "buffer view {} reaches past the end of buffer {b} ({} bytes)",
                        v.value(),
                        buffer.len()
                    )));
                }
            }
        }
        (None, Some(uri)) => {
            owned = crate::source::read_uri(base, uri).map_err(&err)?;
            &owned
        }
        (None, None) => return Err(err("it has neither a bufferView nor a uri".to_owned())),
    };
    let format = image::guess_format(bytes)
        .map_err(|_| err("the data is not a PNG, JPEG or WebP image".to_owned()))?;
    if !matches!(
        format,
        ImageFormat::Png | ImageFormat::Jpeg | ImageFormat::WebP
    ) {
        return Err(err(format!(
            "{format:?} images are not supported (PNG, JPEG and WebP are)"
        )));
    }
    let mut reader = image::ImageReader::with_format(Cursor::new(bytes), format);
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(options.max_image_dimension);
    limits.max_image_height = Some(options.max_image_dimension);
    limits.max_alloc = Some(options.max_image_bytes);
    reader.limits(limits);
    let decoded = reader.decode().map_err(|e| err(e.to_string()))?;
    if decoded.width() == 0 || decoded.height() == 0 {
        return Err(err("the image has no texels".to_owned()));
    }
    Ok(decoded.to_rgba8())
}

/// The side of every albedo layer: the largest power of two not above the biggest side
/// among `sides`, capped at `cap` (a power of two); 1 with no textures.
pub(crate) fn layer_size(sides: impl IntoIterator<Item = u32>, cap: u32) -> u32 {
    let biggest = sides.into_iter().max().unwrap_or(1).max(1);
    (1u32 << biggest.ilog2()).min(cap)
}

fn srgb_to_linear(c: u8) -> f32 {
    let c = f32::from(c) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

fn linear_to_srgb(c: f32) -> u8 {
    let c = c.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0 + 0.5) as u8
}

/// `image` as a `size` × `size` layer. An image of that size already is copied texel for
/// texel; any other is resampled by `image`'s triangle (bilinear, widened when shrinking)
/// filter in linear light with premultiplied alpha, so transparent texels' colours do not
/// bleed into the edges of alpha-tested cut-outs.
pub(crate) fn to_layer(image: &RgbaImage, size: u32) -> AlbedoLayer {
    if image.width() == size && image.height() == size {
        return AlbedoLayer {
            size,
            texels: image.pixels().map(|p| p.0).collect(),
        };
    }
    let linear = image::Rgba32FImage::from_fn(image.width(), image.height(), |x, y| {
        let p = image.get_pixel(x, y).0;
        let a = f32::from(p[3]) / 255.0;
        image::Rgba([
            srgb_to_linear(p[0]) * a,
            srgb_to_linear(p[1]) * a,
            srgb_to_linear(p[2]) * a,
            a,
        ])
    });
    let resized =
        image::imageops::resize(&linear, size, size, image::imageops::FilterType::Triangle);
    let texels = resized
        .pixels()
        .map(|p| {
            let [r, g, b, a] = p.0;
            let a = a.clamp(0.0, 1.0);
            let un = |c: f32| if a > 0.0 { linear_to_srgb(c / a) } else { 0 };
            [un(r), un(g), un(b), (a * 255.0 + 0.5) as u8]
        })
        .collect();
    AlbedoLayer { size, texels }
}

/// `image` as a `size` × `size` data layer (normal, metallic-roughness or occlusion
/// values, linear): copied texel for texel at that size, else resampled by `image`'s
/// triangle filter on the stored values (no transfer function, no premultiplication).
pub(crate) fn to_data_layer(image: &RgbaImage, size: u32) -> DataLayer {
    let texels = if image.width() == size && image.height() == size {
        image.pixels().map(|p| p.0).collect()
    } else {
        image::imageops::resize(image, size, size, image::imageops::FilterType::Triangle)
            .pixels()
            .map(|p| p.0)
            .collect()
    };
    DataLayer { size, texels }
}

/// KHR_texture_transform as one matrix: `uv' = offset + R(rotation) · (scale ⊙ uv)`, where
/// `R` takes `(u, v)` to `(cos·u + sin·v, −sin·u + cos·v)`: counter-clockwise as seen on the
/// image (whose v runs down), the rotation of the Khronos glTF Sample Viewer and three.js
/// (older copies of the extension's README print the transposed matrix).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct UvTransform {
    pub offset: Vec2,
    pub rotation: f32,
    pub scale: Vec2,
}

impl UvTransform {
    pub(crate) fn matrix(&self) -> Mat3 {
        let (s, c) = self.rotation.sin_cos();
        let t = Mat3::from_cols(
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            self.offset.extend(1.0),
        );
        let r = Mat3::from_cols(
            Vec3::new(c, -s, 0.0),
            Vec3::new(s, c, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        );
        let sc = Mat3::from_diagonal(self.scale.extend(1.0));
        t * r * sc
    }

    pub(crate) fn apply(&self, uvs: &mut [Vec2]) {
        let m = self.matrix();
        for uv in uvs {
            *uv = m.transform_point2(*uv);
        }
    }
}

/// What the importer keeps of a glTF material.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Imported {
    /// The renderer's material; its layers are set once the layers are known (from the
    /// image indices below), its maps' strengths are set here.
    pub material: Material,
    /// Image index of the base colour texture.
    pub texture: Option<usize>,
    /// Image indices of the maps: normal, metallic-roughness, occlusion (data layers) and
    /// emissive (an albedo layer).
    pub maps: MapImages,
    pub double_sided: bool,
    /// TEXCOORD set the base colour texture reads.
    pub uv_set: u32,
    pub uv_transform: Option<UvTransform>,
    /// Nothing of it can be seen (MASK with a cutoff above the constant alpha, no texture).
    pub invisible: bool,
}

impl Imported {
    /// glTF 2.0's default material (§3.9.6: white, metallic 1, roughness 1, no textures),
    /// named as the material it stands in for.
    pub(crate) fn fallback(name: Option<&str>) -> Self {
        Imported {
            material: Material {
                name: name.unwrap_or("the default material").to_owned(),
                roughness: 1.0,
                metallic: 1.0,
                specular: SPECULAR,
                ..Material::default()
            },
            texture: None,
            maps: MapImages::default(),
            double_sided: false,
            uv_set: 0,
            uv_transform: None,
            invisible: false,
        }
    }
}

/// Image indices of a material's maps.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct MapImages {
    pub normal: Option<usize>,
    pub metallic_roughness: Option<usize>,
    pub occlusion: Option<usize>,
    pub emissive: Option<usize>,
}

impl MapImages {
    /// The data maps' images (linear layers).
    pub(crate) fn data(&self) -> impl Iterator<Item = usize> {
        [self.normal, self.metallic_roughness, self.occlusion]
            .into_iter()
            .flatten()
    }
}

/// One texture reference of a material: which image, which TEXCOORD set, which transform.
struct TextureRef {
    image: usize,
    set: u32,
    transform: Option<UvTransform>,
    clamps: bool,
}

/// A `KHR_texture_transform`: the transform and the set it overrides `texCoord` with.
struct Transform {
    tex_coord: Option<u32>,
    offset: [f32; 2],
    rotation: f32,
    scale: [f32; 2],
}

impl Transform {
    /// A `textureInfo`'s, as the gltf crate reads it.
    fn of_info(t: gltf::texture::TextureTransform<'_>) -> Self {
        Transform {
            tex_coord: t.tex_coord(),
            offset: t.offset(),
            rotation: t.rotation(),
            scale: t.scale(),
        }
    }

    /// From the extension's JSON (the gltf crate reads it on `textureInfo` only, not on
    /// `normalTexture` and `occlusionTexture`); absent members take the extension's
    /// defaults, members of the wrong type are NaN (refused as not finite).
    fn of_json(v: &gltf::json::Value) -> Self {
        let num = |v: Option<&gltf::json::Value>, default: f32| match v {
            None => default,
            Some(v) => v.as_f64().map_or(f32::NAN, |x| x as f32),
        };
        let pair = |key: &str, default: f32| {
            let a = v.get(key).and_then(|p| p.as_array());
            match (v.get(key), a) {
                (None, _) => [default; 2],
                (Some(_), Some(a)) if a.len() == 2 => [num(a.first(), 0.0), num(a.get(1), 0.0)],
                _ => [f32::NAN; 2],
            }
        };
        Transform {
            tex_coord: v
                .get("texCoord")
                .and_then(gltf::json::Value::as_u64)
                .map(|s| s.min(u64::from(u32::MAX)) as u32),
            offset: pair("offset", 0.0),
            rotation: num(v.get("rotation"), 0.0),
            scale: pair("scale", 1.0),
        }
    }
}

/// Checks that the values of a named field are finite (an error naming the material).
type FiniteCheck<'a> = dyn Fn(&str, &[f32]) -> Result<(), Error> + 'a;

/// The image, set and transform of a texture reference, the transform checked finite.
fn texture_ref(
    texture: gltf::Texture<'_>,
    tex_coord: u32,
    transform: Option<Transform>,
    finite: &FiniteCheck<'_>,
) -> Result<TextureRef, Error> {
    use gltf::texture::WrappingMode::Repeat;
    let sampler = texture.sampler();
    let (set, transform) = match transform {
        Some(t) => {
            finite("KHR_texture_transform offset", &t.offset)?;
            finite("KHR_texture_transform rotation", &[t.rotation])?;
            finite("KHR_texture_transform scale", &t.scale)?;
            (
                t.tex_coord.unwrap_or(tex_coord),
                Some(UvTransform {
                    offset: Vec2::from_array(t.offset),
                    rotation: t.rotation,
                    scale: Vec2::from_array(t.scale),
                }),
            )
        }
        None => (tex_coord, None),
    };
    Ok(TextureRef {
        image: texture.source().index(),
        set,
        transform,
        clamps: sampler.wrap_s() != Repeat || sampler.wrap_t() != Repeat,
    })
}

/// The renderer's mapping of a glTF material (`None`: the default material of glTF 2.0
/// §3.9.6). Warnings go to `warnings`.
pub(crate) fn import(
    file: &str,
    m: &gltf::Material<'_>,
    warnings: &mut Vec<String>,
) -> Result<Imported, Error> {
    let index = m.index();
    let label = match (index, m.name()) {
        (None, _) => "the default material".to_owned(),
        (Some(i), Some(n)) => format!("material {i} ({n:?})"),
        (Some(i), None) => format!("material {i}"),
    };
    let err = |problem: String| Error::Material {
        file: file.to_owned(),
        material: index.unwrap_or(usize::MAX),
        name: m.name().map(str::to_owned),
        problem,
    };
    let finite = |what: &str, v: &[f32]| -> Result<(), Error> {
        if v.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(err(format!("{what} {v:?} is not finite")))
        }
    };
    let pbr = m.pbr_metallic_roughness();
    let factor = pbr.base_color_factor();
    finite("baseColorFactor", &factor)?;
    let metallic = pbr.metallic_factor();
    let roughness = pbr.roughness_factor();
    finite("metallicFactor", &[metallic])?;
    finite("roughnessFactor", &[roughness])?;
    let cutoff = m.alpha_cutoff().unwrap_or(0.5);
    finite("alphaCutoff", &[cutoff])?;
    let texture = pbr.base_color_texture();
    let alpha = factor[3].clamp(0.0, 1.0);
    let (shader, raw_cutoff) = match m.alpha_mode() {
        gltf::material::AlphaMode::Opaque => (ShaderKind::Opaque, 0.5),
        gltf::material::AlphaMode::Mask => (ShaderKind::AlphaTested, cutoff.clamp(0.0, 1.0)),
        gltf::material::AlphaMode::Blend => {
            warnings.push(format!(
                "{label}: alphaMode BLEND is drawn as MASK with alphaCutoff 0.5 (the renderer \
                 has no blending)"
            ));
            (ShaderKind::AlphaTested, 0.5)
        }
    };
    // The laydown tests the texture's alpha alone; glTF tests texture alpha × factor alpha.
    let mut invisible = false;
    let alpha_cutoff = if shader == ShaderKind::AlphaTested && alpha < 1.0 {
        if alpha <= 0.0 || raw_cutoff / alpha > 1.0 {
            if texture.is_none() || alpha <= 0.0 {
                invisible = true;
                warnings.push(format!(
                    "{label}: baseColorFactor alpha {alpha} is under alphaCutoff {raw_cutoff}: \
                     nothing of it is drawn"
                ));
            } else {
                warnings.push(format!(
                    "{label}: alphaCutoff {raw_cutoff} over baseColorFactor alpha {alpha} passes \
                     1: only fully opaque texels are drawn"
                ));
            }
            1.0
        } else {
            raw_cutoff / alpha
        }
    } else {
        raw_cutoff
    };
    // Every map reads the mesh's one UV set: the base colour's, else the first map's.
    let finite: &FiniteCheck<'_> = &finite;
    // A `textureInfo` (base colour, metallic-roughness, emissive), whose transform the gltf
    // crate reads, and a normal or occlusion texture's, read from the JSON.
    let info = |i: &gltf::texture::Info<'_>| {
        let t = i.texture_transform().map(Transform::of_info);
        texture_ref(i.texture(), i.tex_coord(), t, finite)
    };
    // A normal or occlusion texture with its factor (scale, strength), checked finite.
    let other = |texture: gltf::Texture<'_>,
                 tex_coord: u32,
                 ext: Option<&gltf::json::Value>,
                 factor: (&str, f32)| {
        finite(factor.0, &[factor.1])?;
        let r = texture_ref(texture, tex_coord, ext.map(Transform::of_json), finite)?;
        Ok::<_, Error>((r, factor.1))
    };
    let base = texture.as_ref().map(info).transpose()?;
    let normal = m
        .normal_texture()
        .map(|i| {
            let ext = i.extension_value("KHR_texture_transform");
            other(
                i.texture(),
                i.tex_coord(),
                ext,
                ("normalTexture.scale", i.scale()),
            )
        })
        .transpose()?;
    let metallic_roughness = pbr
        .metallic_roughness_texture()
        .as_ref()
        .map(info)
        .transpose()?;
    let occlusion = m
        .occlusion_texture()
        .map(|i| {
            let ext = i.extension_value("KHR_texture_transform");
            let factor = ("occlusionTexture.strength", i.strength());
            other(i.texture(), i.tex_coord(), ext, factor)
        })
        .transpose()?;
    let emissive_texture = m.emissive_texture().as_ref().map(info).transpose()?;
    let emissive_factor = m.emissive_factor();
    finite("emissiveFactor", &emissive_factor)?;
    let strength = m.emissive_strength().unwrap_or(1.0);
    finite("KHR_materials_emissive_strength", &[strength])?;
    let refs = [
        ("base colour", base.as_ref()),
        ("normal", normal.as_ref().map(|(r, _)| r)),
        ("metallic-roughness", metallic_roughness.as_ref()),
        ("occlusion", occlusion.as_ref().map(|(r, _)| r)),
        ("emissive", emissive_texture.as_ref()),
    ];
    let first = refs.iter().find_map(|(_, r)| *r);
    let (uv_set, uv_transform) = first.map_or((0, None), |r| (r.set, r.transform));
    for (what, r) in refs {
        let Some(r) = r else { continue };
        if r.set != uv_set || r.transform != uv_transform {
            warnings.push(format!(
                "{label}: the {what} texture reads TEXCOORD_{} {}; the renderer reads every map \
                 of a material with one set and transform (TEXCOORD_{uv_set} {})",
                r.set,
                transform_words(r.transform.as_ref()),
                transform_words(uv_transform.as_ref()),
            ));
        }
        if r.clamps {
            warnings.push(format!(
                "{label}: the {what} texture's sampler clamps or mirrors; the renderer repeats \
                 every texture"
            ));
        }
    }
    let emissive = Vec3::from_array(emissive_factor) * strength;
    let material = Material {
        name: m.name().map_or_else(|| label.clone(), str::to_owned),
        shader,
        tint: Vec3::new(factor[0], factor[1], factor[2]).max(Vec3::ZERO),
        alpha_cutoff,
        roughness: roughness.clamp(0.0, 1.0),
        specular: SPECULAR,
        metallic: metallic.clamp(0.0, 1.0),
        emissive: emissive.max(Vec3::ZERO),
        maps: MaterialMaps {
            normal: normal.as_ref().map(|(_, scale)| NormalMap {
                layer: 0,
                scale: scale.clamp(-16.0, 16.0),
            }),
            metallic_roughness: metallic_roughness.as_ref().map(|_| 0),
            occlusion: occlusion.as_ref().map(|(_, strength)| OcclusionMap {
                layer: 0,
                strength: strength.clamp(0.0, 1.0),
            }),
            emissive: emissive_texture.as_ref().map(|_| 0),
        },
        ..Material::default()
    };
    Ok(Imported {
        material,
        texture: base.as_ref().map(|r| r.image),
        maps: MapImages {
            normal: normal.as_ref().map(|(r, _)| r.image),
            metallic_roughness: metallic_roughness.as_ref().map(|r| r.image),
            occlusion: occlusion.as_ref().map(|(r, _)| r.image),
            emissive: emissive_texture.as_ref().map(|r| r.image),
        },
        double_sided: m.double_sided(),
        uv_set,
        uv_transform,
        invisible,
    })
}

/// "with no transform" or "with a KHR_texture_transform", for warnings.
fn transform_words(t: Option<&UvTransform>) -> &'static str {
    if t.is_some() {
        "with a KHR_texture_transform"
    } else {
        "with no transform"
    }
}

/// Every material's `specular`: the renderer's specular lobe has glTF's dielectric F0
/// (0.04) built in, so 1 reproduces glTF's dielectric specular.
pub const SPECULAR: f32 = 1.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layer_sizes() {
        assert_eq!(layer_size([300, 200], 1024), 256);
        assert_eq!(layer_size([256], 1024), 256);
        assert_eq!(layer_size([4096, 16], 1024), 1024);
        assert_eq!(layer_size([], 1024), 1);
        assert_eq!(layer_size([1], 1024), 1);
    }

    #[test]
    fn texture_transform_matches_the_extension() {
        // A quarter turn counter-clockwise on the image (v down) takes +u = (1, 0) to (0, -1).
        let t = UvTransform {
            offset: Vec2::new(0.5, 0.25),
            rotation: std::f32::consts::FRAC_PI_2,
            scale: Vec2::new(2.0, 3.0),
        };
        let mut uv = [Vec2::new(1.0, 0.0), Vec2::new(0.0, 1.0)];
        t.apply(&mut uv);
        // (1,0) scaled (2,0), rotated (2·cos, −2·sin) = (0, −2), offset (0.5, −1.75).
        assert!((uv[0] - Vec2::new(0.5, -1.75)).length() < 1e-6, "{}", uv[0]);
        // (0,1) scaled (0,3), rotated (3·sin, 3·cos) = (3, 0), offset (3.5, 0.25).
        assert!((uv[1] - Vec2::new(3.5, 0.25)).length() < 1e-6, "{}", uv[1]);
    }

    #[test]
    fn resampling_keeps_flat_colour_and_exact_sizes_are_copied() {
        let img = RgbaImage::from_pixel(3, 5, image::Rgba([200, 100, 50, 255]));
        let layer = to_layer(&img, 4);
        assert_eq!(layer.texels.len(), 16);
        for t in &layer.texels {
            for (a, b) in t.iter().zip([200u8, 100, 50, 255]) {
                assert!(a.abs_diff(b) <= 1, "{t:?}");
            }
        }
        let img = RgbaImage::from_fn(2, 2, |x, y| image::Rgba([x as u8, y as u8, 7, 9]));
        assert_eq!(
            to_layer(&img, 2).texels,
            [[0, 0, 7, 9], [1, 0, 7, 9], [0, 1, 7, 9], [1, 1, 7, 9]]
        );
    }
}
