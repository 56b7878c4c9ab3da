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

/// Mip chain of one layer, box-filtered in linear space for colour; alpha is filtered and
/// then rescaled so the fraction of texels passing the cutoff 0.5 stays that of the top
/// level (foliage does not thin out with distance).
fn mip_chain(layer: &AlbedoLayer) -> Vec<Vec<[u8; 4]>> {
    use deferred::gbuffer::{srgb8, srgb8_value};
    let coverage =
        |t: &[[u8; 4]]| t.iter().filter(|p| p[3] >= 128).count() as f32 / t.len().max(1) as f32;
    let top_cov = coverage(&layer.texels);
    let mut levels = vec![layer.texels.clone()];
    let mut size = layer.size as usize;
    while size > 1 {
        let prev = levels.last().expect("at least one level");
        let half = size / 2;
        let mut next = Vec::with_capacity(half * half);
        for y in 0..half {
            for x in 0..half {
                let mut c = Vec3::ZERO;
                let mut a = 0.0;
                let mut wsum = 0.0;
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let p = prev[(2 * y + dy) * size + 2 * x + dx];
                    let w = f32::from(p[3]) / 255.0 + 1e-3;
                    c += Vec3::new(srgb8_value(p[0]), srgb8_value(p[1]), srgb8_value(p[2])) * w;
                    wsum += w;
                    a += f32::from(p[3]) / 255.0;
                }
                let c = c / wsum;
                next.push([
                    srgb8(c.x),
                    srgb8(c.y),
                    srgb8(c.z),
                    (a / 4.0 * 255.0 + 0.5) as u8,
                ]);
            }
        }
        // Alpha-to-coverage preserving scale (Castaño): find the scale that keeps coverage.
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
            for p in &mut next {
                p[3] = (f32::from(p[3]) * hi).min(255.0) as u8;
            }
        }
        levels.push(next);
        size = half;
    }
    levels
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
        let mut levels = vec![self.texels.clone()];
        let mut size = self.size as usize;
        while size > 1 {
            let prev = levels.last().expect("at least one level");
            let half = size / 2;
            let mut next = Vec::with_capacity(half * half);
            for y in 0..half {
                for x in 0..half {
                    let mut sum = [0u32; 4];
                    for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                        let p = prev[(2 * y + dy) * size + 2 * x + dx];
                        for c in 0..4 {
                            sum[c] += u32::from(p[c]);
                        }
                    }
                    // Round half up: (sum + 2) / 4, at most 255.
                    next.push(sum.map(|v| ((v + 2) / 4) as u8));
                }
            }
            levels.push(next);
            size = half;
        }
        levels
    }
}
