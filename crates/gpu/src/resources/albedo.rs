//! The albedo texture array: every layer of the scene with a full mip chain, filtered so
//! alpha-tested foliage keeps its coverage with distance.

use glam::Vec3;

use crate::scene::AlbedoLayer;

/// Mip chain of one layer, box-filtered in linear space for colour; alpha is filtered and
/// then rescaled so the fraction of texels passing the cutoff 0.5 stays that of the top
/// level (foliage does not thin out with distance).
pub(crate) fn mip_chain(layer: &AlbedoLayer) -> Vec<Vec<[u8; 4]>> {
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

/// Uploads the albedo layers as an `Rgba8UnormSrgb` 2D array with a full mip chain.
pub(crate) fn albedo_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    layers: &[AlbedoLayer],
) -> wgpu::Texture {
    let size = layers.first().map_or(1, |l| l.size);
    let count = layers.len().max(1) as u32;
    let mip_level_count = size.max(1).ilog2() + 1;
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("albedo array"),
        size: wgpu::Extent3d {
            width: size,
            height: size,
            depth_or_array_layers: count,
        },
        mip_level_count,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8UnormSrgb,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for (z, layer) in layers.iter().enumerate() {
        for (mip, texels) in mip_chain(layer).iter().enumerate() {
            let s = (size >> mip).max(1);
            queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &texture,
                    mip_level: mip as u32,
                    origin: wgpu::Origin3d {
                        x: 0,
                        y: 0,
                        z: z as u32,
                    },
                    aspect: wgpu::TextureAspect::All,
                },
                bytemuck::cast_slice(texels),
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(4 * s),
                    rows_per_image: Some(s),
                },
                wgpu::Extent3d {
                    width: s,
                    height: s,
                    depth_or_array_layers: 1,
                },
            );
        }
    }
    texture
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mips_keep_alpha_coverage() {
        let (scene, _) = crate::demo::build(&crate::demo::DemoOptions {
            density: 0.01,
            ..Default::default()
        });
        let layer = scene.albedo_layers[2].clone();
        let chain = mip_chain(&layer);
        assert_eq!(chain.len() as u32, layer.size.ilog2() + 1);
        let cov = |t: &[[u8; 4]]| t.iter().filter(|p| p[3] >= 128).count() as f32 / t.len() as f32;
        let top = cov(&chain[0]);
        for (i, level) in chain.iter().enumerate().take(6) {
            assert!(
                (cov(level) - top).abs() < 0.08,
                "mip {i}: coverage {} vs {top}",
                cov(level)
            );
        }
    }
}
