//! The scene's texture arrays: the albedo layers (sRGB, filtered so alpha-tested foliage
//! keeps its coverage with distance) and the data layers (linear: normal,
//! metallic-roughness and occlusion maps), each with a full mip chain.

use crate::error::{Error, Result};
use crate::scene::{AlbedoLayer, DataLayer};

/// Uploads the albedo layers as an `Rgba8UnormSrgb` 2D array with a full mip chain.
pub(crate) fn albedo_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    layers: &[AlbedoLayer],
) -> Result<wgpu::Texture> {
    let size = layers.first().map_or(1, |l| l.size);
    let chains: Vec<_> = layers.iter().map(AlbedoLayer::mip_chain).collect();
    layer_array(
        device,
        queue,
        ALBEDO_LIMITS,
        "albedo array",
        wgpu::TextureFormat::Rgba8UnormSrgb,
        size,
        &chains,
    )
}

/// The data layer of a scene without data maps: a flat normal (0.5, 0.5, 1), roughness
/// and metallic factors kept (G, B = 1), no occlusion (R = 1). Never read through a
/// material (whose layers are `NO_MAP`), only bound.
const NEUTRAL_DATA: [u8; 4] = [255, 128, 255, 255];

/// Uploads the data layers as an `Rgba8Unorm` 2D array with a full mip chain (one
/// neutral 1x1 layer when there are none).
pub(crate) fn data_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    layers: &[DataLayer],
) -> Result<wgpu::Texture> {
    let size = layers.first().map_or(1, |l| l.size);
    let mut chains: Vec<_> = layers.iter().map(DataLayer::mip_chain).collect();
    if chains.is_empty() {
        chains.push(vec![vec![NEUTRAL_DATA]]);
    }
    layer_array(
        device,
        queue,
        DATA_LIMITS,
        "data array",
        wgpu::TextureFormat::Rgba8Unorm,
        size,
        &chains,
    )
}

/// The device limits an array's layers must fit, named with the scene field they bound:
/// its side, then its layer count.
type ArrayLimits = [&'static str; 2];
const ALBEDO_LIMITS: ArrayLimits = [
    "max_texture_dimension_2d (Scene::albedo_layers' size)",
    "max_texture_array_layers (Scene::albedo_layers)",
];
const DATA_LIMITS: ArrayLimits = [
    "max_texture_dimension_2d (Scene::data_layers' size)",
    "max_texture_array_layers (Scene::data_layers)",
];

/// A `size` × `size` 2D array of `format` (4 bytes a texel) holding `chains` (one mip chain
/// a layer, level 0 first; at least one layer is allocated).
///
/// # Errors
/// [`Error::DeviceLimit`] naming the limit and the scene field where the side or the layer
/// count is over the device's.
fn layer_array(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    limits: ArrayLimits,
    label: &str,
    format: wgpu::TextureFormat,
    size: u32,
    chains: &[Vec<Vec<[u8; 4]>>],
) -> Result<wgpu::Texture> {
    let count = chains.len().max(1);
    let device_limits = device.limits();
    for (limit, needed, available) in [
        (
            limits[0],
            size as u64,
            device_limits.max_texture_dimension_2d,
        ),
        (
            limits[1],
            count as u64,
            device_limits.max_texture_array_layers,
        ),
    ] {
        if needed > u64::from(available) {
            return Err(Error::DeviceLimit {
                limit,
                needed,
                available: u64::from(available),
            });
        }
    }
    let count = count as u32;
    let mip_level_count = size.max(1).ilog2() + 1;
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size,
            height: size,
            depth_or_array_layers: count,
        },
        mip_level_count,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for (z, chain) in chains.iter().enumerate() {
        for (mip, texels) in chain.iter().enumerate() {
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
    Ok(texture)
}
