//! glTF materials and base colour textures into the renderer's materials and albedo
//! layers.

use std::io::Cursor;

use image::{ImageFormat, RgbaImage};
use scene::glam::{Mat3, Vec2, Vec3};
use scene::{AlbedoLayer, Material, ShaderKind};

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
    /// The renderer's material; `albedo_layer` is the glTF image index of the base colour
    /// texture until the layers are known ([`Imported::texture`]).
    pub material: Material,
    /// Image index of the base colour texture.
    pub texture: Option<usize>,
    /// Image index of the metallic-roughness texture.
    pub metallic_roughness_texture: Option<usize>,
    pub metallic: f32,
    pub double_sided: bool,
    /// TEXCOORD set the base colour texture reads.
    pub uv_set: u32,
    pub uv_transform: Option<UvTransform>,
    /// Nothing of it can be seen (MASK with a cutoff above the constant alpha, no texture).
    pub invisible: bool,
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
    let (uv_set, uv_transform) = match &texture {
        Some(info) => {
            let sampler = info.texture().sampler();
            use gltf::texture::WrappingMode::Repeat;
            if sampler.wrap_s() != Repeat || sampler.wrap_t() != Repeat {
                warnings.push(format!(
                    "{label}: the base colour texture's sampler clamps or mirrors; the renderer \
                     repeats every texture"
                ));
            }
            match info.texture_transform() {
                Some(t) => {
                    finite("KHR_texture_transform offset", &t.offset())?;
                    finite("KHR_texture_transform rotation", &[t.rotation()])?;
                    finite("KHR_texture_transform scale", &t.scale())?;
                    (
                        t.tex_coord().unwrap_or(info.tex_coord()),
                        Some(UvTransform {
                            offset: Vec2::from_array(t.offset()),
                            rotation: t.rotation(),
                            scale: Vec2::from_array(t.scale()),
                        }),
                    )
                }
                None => (info.tex_coord(), None),
            }
        }
        None => (0, None),
    };
    let metallic = metallic.clamp(0.0, 1.0);
    let tint = Vec3::new(factor[0], factor[1], factor[2]).max(Vec3::ZERO);
    Ok(Imported {
        material: Material {
            name: m.name().map_or_else(|| label.clone(), str::to_owned),
            shader,
            albedo_layer: 0,
            tint,
            alpha_cutoff,
            roughness: roughness.clamp(0.0, 1.0),
            specular: SPECULAR,
            regular: false,
            ..Default::default()
        },
        texture: texture.map(|t| t.texture().source().index()),
        metallic_roughness_texture: pbr
            .metallic_roughness_texture()
            .map(|t| t.texture().source().index()),
        metallic,
        double_sided: m.double_sided(),
        uv_set,
        uv_transform,
        invisible,
    })
}

/// Every material's `specular`: the renderer's specular lobe has glTF's dielectric F0
/// (0.04) built in, so 1 reproduces glTF's dielectric specular.
pub const SPECULAR: f32 = 1.0;

/// How much a metal's base colour is darkened in the tint (`tint × (1 − METAL_DARKENING ×
/// metallic)`): the renderer has no coloured specular, so a metal keeps a darkened diffuse
/// version of its colour instead of glTF's black diffuse and coloured reflection.
pub const METAL_DARKENING: f32 = 0.5;

/// The means of a metallic-roughness texture's green (roughness) and blue (metallic)
/// channels, in [0, 1].
pub(crate) fn mean_roughness_metallic(image: &RgbaImage) -> (f32, f32) {
    let n = (image.width() as u64 * image.height() as u64).max(1) as f64;
    let (mut g, mut b) = (0u64, 0u64);
    for p in image.pixels() {
        g += u64::from(p.0[1]);
        b += u64::from(p.0[2]);
    }
    ((g as f64 / n / 255.0) as f32, (b as f64 / n / 255.0) as f32)
}

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
