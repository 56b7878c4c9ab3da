//! Albedo layers and their mip chains, filtered so alpha-tested foliage keeps its coverage
//! with distance (the CPU side of the renderer's albedo texture array).

use glam::Vec3;

/// One albedo layer: RGBA8, sRGB colour with linear alpha, `size` × `size` texels, row
/// major from the top-left. All layers of a scene share one size (a power of two).
#[derive(Clone, Debug, PartialEq)]
pub struct AlbedoLayer {
    /// Width and height in texels.
    pub size: u32,
    /// `size * size` texels.
    pub texels: Vec<[u8; 4]>,
}

impl AlbedoLayer {
    /// The mip chain the renderer uploads for this layer, level 0 (these texels) first,
    /// down to 1x1: colour box-filtered in linear space, alpha filtered and rescaled so the
    /// fraction of texels passing a cutoff of 0.5 stays level 0's (alpha-tested foliage
    /// does not thin out with distance). Sampled trilinearly, with repeat addressing.
    #[must_use]
    pub fn mip_chain(&self) -> Vec<Vec<[u8; 4]>> {
        mip_chain(self)
    }
}

/// Level 0 (`texels`, `size` × `size`, a power of two) and every level below it down to
/// 1x1: each texel `reduce` of its 2x2 parents (row-major), then `finish` over the level.
fn box_chain(
    texels: &[[u8; 4]],
    size: u32,
    reduce: impl Fn([[u8; 4]; 4]) -> [u8; 4],
    mut finish: impl FnMut(&mut [[u8; 4]]),
) -> Vec<Vec<[u8; 4]>> {
    let mut levels = vec![texels.to_vec()];
    let mut size = size as usize;
    while size > 1 {
        let prev = levels.last().expect("at least one level");
        let half = size / 2;
        let at = |x: usize, y: usize| prev[y * size + x];
        let mut next: Vec<[u8; 4]> = (0..half * half)
            .map(|i| {
                let (x, y) = (2 * (i % half), 2 * (i / half));
                reduce([at(x, y), at(x + 1, y), at(x, y + 1), at(x + 1, y + 1)])
            })
            .collect();
        finish(&mut next);
        levels.push(next);
        size = half;
    }
    levels
}

/// Mip chain of one layer, box-filtered in linear space for colour; alpha is filtered and
/// then rescaled so the fraction of texels passing the cutoff 0.5 stays that of the top
/// level (foliage does not thin out with distance).
fn mip_chain(layer: &AlbedoLayer) -> Vec<Vec<[u8; 4]>> {
    use deferred::gbuffer::{srgb8, srgb8_value};
    let coverage =
        |t: &[[u8; 4]]| t.iter().filter(|p| p[3] >= 128).count() as f32 / t.len().max(1) as f32;
    let top_cov = coverage(&layer.texels);
    let reduce = |quad: [[u8; 4]; 4]| {
        let mut c = Vec3::ZERO;
        let mut a = 0.0;
        let mut wsum = 0.0;
        for p in quad {
            let w = f32::from(p[3]) / 255.0 + 1e-3;
            c += Vec3::new(srgb8_value(p[0]), srgb8_value(p[1]), srgb8_value(p[2])) * w;
            wsum += w;
            a += f32::from(p[3]) / 255.0;
        }
        let c = c / wsum;
        [
            srgb8(c.x),
            srgb8(c.y),
            srgb8(c.z),
            (a / 4.0 * 255.0 + 0.5) as u8,
        ]
    };
    // Alpha-to-coverage preserving scale (Castaño): find the scale that keeps coverage.
    let keep_coverage = |next: &mut [[u8; 4]]| {
        if top_cov > 0.0 && top_cov < 1.0 {
            let (mut lo, mut hi) = (0.0f32, 8.0f32);
            for _ in 0..16 {
                let mid = 0.5 * (lo + hi);
                let cov = next
                    .iter()
                    .filter(|p| f32::from(p[3]) * mid >= 127.5)
                    .count() as f32
                    / next.len() as f32;
                if cov < top_cov { lo = mid } else { hi = mid }
            }
            for p in next {
                p[3] = (f32::from(p[3]) * hi).min(255.0) as u8;
            }
        }
    };
    box_chain(&layer.texels, layer.size, reduce, keep_coverage)
}

/// One data layer: RGBA8, linear values in [0, 1] (a normal map's `0.5 · n + 0.5`, a
/// metallic-roughness or occlusion map's channels), `size` × `size` texels, row major from
/// the top-left. All data layers of a scene share one size (a power of two), which may
/// differ from the albedo layers'.
#[derive(Clone, Debug, PartialEq)]
pub struct DataLayer {
    /// Width and height in texels.
    pub size: u32,
    /// `size * size` texels.
    pub texels: Vec<[u8; 4]>,
}

impl DataLayer {
    /// The mip chain the renderer uploads, level 0 (these texels) first, down to 1x1: every
    /// channel box-filtered as a linear value (a normal map's averaged normals are
    /// shorter than 1 where they diverge; the shader renormalises).
    #[must_use]
    pub fn mip_chain(&self) -> Vec<Vec<[u8; 4]>> {
        // Round half up: (sum + 2) / 4, at most 255.
        let average = |quad: [[u8; 4]; 4]| {
            std::array::from_fn(|c| {
                let sum: u32 = quad.iter().map(|p| u32::from(p[c])).sum();
                ((sum + 2) / 4) as u8
            })
        };
        box_chain(&self.texels, self.size, average, |_| {})
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every data mip texel is the rounded mean of the four texels of the level above,
    /// each channel on its own (a naive loop over level 0's texels).
    #[test]
    fn data_mips_average_each_channel() {
        let size = 8u32;
        let texels: Vec<[u8; 4]> = (0..size * size)
            .map(|i| {
                [
                    (i * 37 % 256) as u8,
                    (i * 11 % 256) as u8,
                    255,
                    (i % 2 * 255) as u8,
                ]
            })
            .collect();
        let chain = DataLayer {
            size,
            texels: texels.clone(),
        }
        .mip_chain();
        assert_eq!(chain.len(), 4);
        assert_eq!(chain[0], texels);
        for y in 0..4 {
            for x in 0..4 {
                let mut want = [0u32; 4];
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let p = texels[((2 * y + dy) * 8 + 2 * x + dx) as usize];
                    for c in 0..4 {
                        want[c] += u32::from(p[c]);
                    }
                }
                let want = want.map(|v| ((f64::from(v) / 4.0) + 0.5).floor() as u8);
                assert_eq!(chain[1][(y * 4 + x) as usize], want, "({x}, {y})");
            }
        }
        assert_eq!(chain[3].len(), 1);
    }
}
