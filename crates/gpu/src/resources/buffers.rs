//! Buffers made with their contents or zeroed, padded for what a binding needs.

use crate::error::Error;
use crate::error::Result;
use wgpu::util::DeviceExt as _;

/// A buffer holding `data`, padded to at least `min_size` bytes (a binding must hold one
/// element of what the shader reads, even when there are none: an empty scene) and to a
/// multiple of 4 (wgpu's copy alignment).
pub(crate) fn buffer_init(
    device: &wgpu::Device,
    label: &str,
    data: &[u8],
    min_size: u64,
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    let size = (data.len() as u64).max(min_size).max(4).next_multiple_of(4) as usize;
    // Copied only when it needs padding (a scene's vertex and instance tables do not).
    let contents: std::borrow::Cow<'_, [u8]> = if data.len() == size {
        data.into()
    } else {
        let mut padded = data.to_vec();
        padded.resize(size, 0);
        padded.into()
    };
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: &contents,
        usage: usage | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
    })
}

/// A storage buffer of `data` after checking the device's binding-size limit.
pub(crate) fn storage(
    device: &wgpu::Device,
    label: &str,
    data: &[u8],
    min_size: usize,
    extra: wgpu::BufferUsages,
) -> Result<wgpu::Buffer> {
    let max = device.limits().max_storage_buffer_binding_size;
    if data.len() as u64 > max {
        return Err(Error::DeviceLimit {
            limit: "max_storage_buffer_binding_size",
            needed: data.len() as u64,
            available: max,
        });
    }
    Ok(buffer_init(
        device,
        label,
        data,
        min_size as u64,
        wgpu::BufferUsages::STORAGE | extra,
    ))
}

/// An uninitialised storage buffer (`STORAGE | COPY_DST | COPY_SRC | extra`) of `bytes`
/// rounded up to a multiple of 4 (at least 4), after checking the device's binding-size
/// limit: the per-frame buffers the passes zero or fill themselves.
pub(crate) fn storage_buffer(
    device: &wgpu::Device,
    label: &str,
    bytes: u64,
    extra: wgpu::BufferUsages,
) -> Result<wgpu::Buffer> {
    let size = bytes.max(4).next_multiple_of(4);
    let max = device.limits().max_storage_buffer_binding_size;
    if size > max {
        return Err(Error::DeviceLimit {
            limit: "max_storage_buffer_binding_size",
            needed: size,
            available: max,
        });
    }
    Ok(device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC
            | extra,
        mapped_at_creation: false,
    }))
}
