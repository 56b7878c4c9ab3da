//! The albedo texture array: every layer of the scene with a full mip chain, filtered so
//! alpha-tested foliage keeps its coverage with distance.

use crate::scene::AlbedoLayer;

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
        for (mip, texels) in layer.mip_chain().iter().enumerate() {
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
