//! Reading GPU buffers and textures back to the CPU (tests, debug views, statistics).

use crate::error::{Error, Result};

/// Copies `size` bytes of `buffer` (which needs `COPY_SRC`) from `offset` into a new
/// vector, after the GPU finished the work submitted so far.
///
/// # Errors
/// Mapping or waiting failed ([`Error::Map`], [`Error::Poll`]).
pub fn read_buffer(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    buffer: &wgpu::Buffer,
    offset: u64,
    size: u64,
) -> Result<Vec<u8>> {
    if size == 0 {
        return Ok(Vec::new());
    }
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback staging"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("readback"),
    });
    encoder.copy_buffer_to_buffer(buffer, offset, &staging, 0, size);
    queue.submit([encoder.finish()]);
    map_and_copy(device, &staging)
}

fn map_and_copy(device: &wgpu::Device, staging: &wgpu::Buffer) -> Result<Vec<u8>> {
    let (tx, rx) = std::sync::mpsc::channel();
    staging.slice(..).map_async(wgpu::MapMode::Read, move |r| {
        // The receiver outlives this callback: we block on it below.
        let _ = tx.send(r);
    });
    wait_idle(device)?;
    rx.recv()
        .map_err(|e| Error::Map(e.to_string()))?
        .map_err(|e| Error::Map(e.to_string()))?;
    let data = staging
        .slice(..)
        .get_mapped_range()
        .map_err(|e| Error::Map(e.to_string()))?
        .to_vec();
    staging.unmap();
    Ok(data)
}

/// Reads mip 0 / layer 0 of a 2D texture whose texels are `bytes_per_texel` bytes wide,
/// tightly packed row by row (row padding removed). The texture needs `COPY_SRC`.
pub(crate) fn read_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    aspect: wgpu::TextureAspect,
    bytes_per_texel: u32,
) -> Result<Vec<u8>> {
    read_texture_layer(device, queue, texture, aspect, bytes_per_texel, 0)
}

/// [`read_texture`] of array layer `layer`.
pub(crate) fn read_texture_layer(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    aspect: wgpu::TextureAspect,
    bytes_per_texel: u32,
    layer: u32,
) -> Result<Vec<u8>> {
    let (w, h) = (texture.width(), texture.height());
    let row = w * bytes_per_texel;
    let padded_row =
        row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("texture readback staging"),
        size: u64::from(padded_row) * u64::from(h),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("texture readback"),
    });
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d {
                x: 0,
                y: 0,
                z: layer,
            },
            aspect,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &staging,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded_row),
                rows_per_image: Some(h),
            },
        },
        wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
    );
    queue.submit([encoder.finish()]);
    let padded = map_and_copy(device, &staging)?;
    let mut out = Vec::with_capacity((row * h) as usize);
    for y in 0..h as usize {
        let start = y * padded_row as usize;
        out.extend_from_slice(&padded[start..start + row as usize]);
    }
    Ok(out)
}

/// Blocks until the GPU has finished all submitted work.
pub fn wait_idle(device: &wgpu::Device) -> Result<()> {
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map(|_| ())
        .map_err(|e| Error::Poll(e.to_string()))
}
