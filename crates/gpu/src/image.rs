//! PNG output and the debug views' colourings.

use std::path::Path;

use crate::error::{Error, Result};

/// An RGBA8 image (sRGB-encoded colour), row major from the top-left.
#[derive(Clone, Debug, PartialEq)]
pub struct Rgba8Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` pixels.
    pub pixels: Vec<[u8; 4]>,
}

impl Rgba8Image {
    /// A `width` × `height` image filled with `fill`.
    pub fn new(width: u32, height: u32, fill: [u8; 4]) -> Self {
        Self {
            width,
            height,
            pixels: vec![fill; (width * height) as usize],
        }
    }

    /// Writes the image as a PNG file.
    pub fn write_png(&self, path: &Path) -> Result<()> {
        let file = std::fs::File::create(path)
            .map_err(|e| Error::Image(format!("{}: {e}", path.display())))?;
        let mut enc = png::Encoder::new(std::io::BufWriter::new(file), self.width, self.height);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        let mut w = enc
            .write_header()
            .map_err(|e| Error::Image(e.to_string()))?;
        w.write_image_data(bytemuck::cast_slice(&self.pixels))
            .map_err(|e| Error::Image(e.to_string()))?;
        w.finish().map_err(|e| Error::Image(e.to_string()))
    }

    /// Reads an RGBA8 PNG (for golden-image tests).
    pub fn read_png(path: &Path) -> Result<Self> {
        let file = std::fs::File::open(path)
            .map_err(|e| Error::Image(format!("{}: {e}", path.display())))?;
        let mut dec = png::Decoder::new(std::io::BufReader::new(file));
        dec.set_transformations(png::Transformations::EXPAND | png::Transformations::ALPHA);
        let mut reader = dec.read_info().map_err(|e| Error::Image(e.to_string()))?;
        let mut buf = vec![0; reader.output_buffer_size().unwrap_or(0)];
        let info = reader
            .next_frame(&mut buf)
            .map_err(|e| Error::Image(e.to_string()))?;
        if info.color_type != png::ColorType::Rgba || info.bit_depth != png::BitDepth::Eight {
            return Err(Error::Image(format!(
                "{}: not an RGBA8 PNG",
                path.display()
            )));
        }
        buf.truncate(info.buffer_size());
        Ok(Self {
            width: info.width,
            height: info.height,
            pixels: bytemuck::pod_collect_to_vec(&buf),
        })
    }
}

/// A well-spread colour for an integer ID (the talk's colour-coded vis buffer slide).
pub fn id_color(id: u32) -> [u8; 4] {
    let mut h = id.wrapping_mul(0x9e37_79b9);
    h ^= h >> 16;
    h = h.wrapping_mul(0x85eb_ca6b);
    h ^= h >> 13;
    [
        (h & 0xff) as u8 | 0x20,
        ((h >> 8) & 0xff) as u8 | 0x20,
        ((h >> 16) & 0xff) as u8 | 0x20,
        255,
    ]
}

/// A heat-map colour for `t` in [0, 1]: black, blue, green, yellow, red, white.
pub fn heat_color(t: f32) -> [u8; 4] {
    const STOPS: [[f32; 3]; 6] = [
        [0.0, 0.0, 0.0],
        [0.0, 0.1, 0.8],
        [0.0, 0.7, 0.2],
        [0.95, 0.9, 0.0],
        [0.9, 0.1, 0.0],
        [1.0, 1.0, 1.0],
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    } * (STOPS.len() - 1) as f32;
    let i = (t as usize).min(STOPS.len() - 2);
    let f = t - i as f32;
    let c = |k: usize| ((STOPS[i][k] + (STOPS[i + 1][k] - STOPS[i][k]) * f) * 255.0 + 0.5) as u8;
    [c(0), c(1), c(2), 255]
}

/// Image difference metrics: mean absolute error over RGB in [0, 255] and the value below
/// which `percentile` of the per-pixel maximum channel errors lie.
pub fn diff_metrics(a: &Rgba8Image, b: &Rgba8Image, percentile: f64) -> Option<(f64, u8)> {
    if a.width != b.width || a.height != b.height || a.pixels.is_empty() {
        return None;
    }
    let mut sum = 0u64;
    let mut maxes: Vec<u8> = Vec::with_capacity(a.pixels.len());
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        let mut m = 0u8;
        for k in 0..3 {
            let d = p[k].abs_diff(q[k]);
            sum += u64::from(d);
            m = m.max(d);
        }
        maxes.push(m);
    }
    maxes.sort_unstable();
    let idx = ((percentile.clamp(0.0, 1.0) * (maxes.len() - 1) as f64).round()) as usize;
    Some((sum as f64 / (3 * a.pixels.len()) as f64, maxes[idx]))
}

/// A visual diff: per-pixel maximum channel error, amplified ×4, as a heat map.
pub fn diff_image(a: &Rgba8Image, b: &Rgba8Image) -> Rgba8Image {
    let mut out = Rgba8Image::new(a.width, a.height, [0, 0, 0, 255]);
    for ((o, p), q) in out.pixels.iter_mut().zip(&a.pixels).zip(&b.pixels) {
        let m = (0..3).map(|k| p[k].abs_diff(q[k])).max().unwrap_or(0);
        *o = heat_color(f32::from(m) * 4.0 / 255.0);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn png_roundtrip() {
        let mut img = Rgba8Image::new(5, 3, [1, 2, 3, 255]);
        img.pixels[7] = [200, 100, 50, 128];
        let path =
            std::env::temp_dir().join(format!("gpu-png-roundtrip-{}.png", std::process::id()));
        img.write_png(&path).unwrap();
        let back = Rgba8Image::read_png(&path).unwrap();
        std::fs::remove_file(&path).ok();
        assert_eq!(img, back);
    }

    #[test]
    fn diff_metrics_against_a_naive_count() {
        let a = Rgba8Image::new(4, 1, [10, 10, 10, 255]);
        let mut b = a.clone();
        b.pixels[0] = [20, 10, 10, 255];
        b.pixels[3] = [10, 10, 40, 255];
        let (mean, p50) = diff_metrics(&a, &b, 0.5).unwrap();
        assert!((mean - 40.0 / 12.0).abs() < 1e-9);
        assert_eq!(p50, 10, "sorted maxima are [0, 0, 10, 30]");
        assert_eq!(diff_metrics(&a, &b, 1.0).unwrap().1, 30);
        assert!(diff_metrics(&a, &Rgba8Image::new(2, 2, [0; 4]), 0.5).is_none());
    }
}
