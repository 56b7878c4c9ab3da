//! The fullscreen-triangle blit that shows an image (the renderer's output or a debug
//! view) on the window, and the same blit into an offscreen target read back for
//! screenshots.
//!
//! The images are `Rgba8Unorm` textures holding sRGB-encoded values
//! ([`gpu::Renderer::output_texture`]): the blit loads texels unfiltered and writes them
//! to a non-sRGB view of the target, so the bytes reach the display unchanged. Images of
//! another aspect than the target (the shadow atlas) are letterboxed.

use anyhow::{Context as _, Result};
use gpu::Rgba8Image;

const SHADER: &str = r"
@group(0) @binding(0) var src: texture_2d<f32>;

struct VsOut {
    @builtin(position) position: vec4<f32>,
    @location(0) uv: vec2<f32>,
};

// One triangle covering the viewport: uv (0,0) top-left to (1,1) bottom-right.
@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> VsOut {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    var o: VsOut;
    o.position = vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, 0.0, 1.0);
    o.uv = uv;
    return o;
}

// Nearest texel, no filtering: at 1:1 each pixel gets its own texel exactly.
@fragment
fn fs_main(o: VsOut) -> @location(0) vec4<f32> {
    let size = vec2<f32>(textureDimensions(src));
    let texel = vec2<i32>(clamp(floor(o.uv * size), vec2<f32>(0.0), size - 1.0));
    return vec4<f32>(textureLoad(src, texel, 0).rgb, 1.0);
}
";

/// The blit's pipelines (one per target format, made when first needed).
pub struct Blit {
    module: wgpu::ShaderModule,
    pipelines: Vec<(wgpu::TextureFormat, wgpu::RenderPipeline)>,
}

/// The largest rectangle of `image`'s aspect centred in `target` (x, y, width, height in
/// pixels): the whole target when the aspects agree.
pub fn fit(image: (u32, u32), target: (u32, u32)) -> [f32; 4] {
    let (iw, ih) = (image.0.max(1) as f32, image.1.max(1) as f32);
    let (tw, th) = (target.0.max(1) as f32, target.1.max(1) as f32);
    let scale = (tw / iw).min(th / ih);
    let (w, h) = ((iw * scale).round().max(1.0), (ih * scale).round().max(1.0));
    if (w - tw).abs() < 1.0 && (h - th).abs() < 1.0 {
        return [0.0, 0.0, tw, th];
    }
    [((tw - w) / 2.0).floor(), ((th - h) / 2.0).floor(), w, h]
}

impl Blit {
    /// Compiles the blit's shader on `device`.
    pub fn new(device: &wgpu::Device) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("view blit"),
            source: wgpu::ShaderSource::Wgsl(SHADER.into()),
        });
        Self {
            module,
            pipelines: Vec::new(),
        }
    }

    fn pipeline(
        &mut self,
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
    ) -> &wgpu::RenderPipeline {
        if let Some(i) = self.pipelines.iter().position(|(f, _)| *f == format) {
            return &self.pipelines[i].1;
        }
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("view blit"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &self.module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &self.module,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        self.pipelines.push((format, pipeline));
        &self.pipelines[self.pipelines.len() - 1].1
    }

    /// Records the blit of `source` (an `Rgba8Unorm` texture of sRGB-encoded values, of
    /// `source_size`) into `pass`, whose colour target has `format` (non-sRGB) and
    /// `target_size`, letterboxed by [`fit`].
    pub fn draw(
        &mut self,
        device: &wgpu::Device,
        pass: &mut wgpu::RenderPass<'_>,
        format: wgpu::TextureFormat,
        source: &wgpu::TextureView,
        source_size: (u32, u32),
        target_size: (u32, u32),
    ) {
        let pipeline = self.pipeline(device, format).clone();
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("view blit source"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(source),
            }],
        });
        let [x, y, w, h] = fit(source_size, target_size);
        pass.set_viewport(x, y, w, h, 0.0, 1.0);
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.draw(0..3, 0..1);
        pass.set_viewport(
            0.0,
            0.0,
            target_size.0 as f32,
            target_size.1 as f32,
            0.0,
            1.0,
        );
    }

    /// Blits `source` (of `size`) into an offscreen `Rgba8Unorm` target of the same size,
    /// exactly as the window shows it, and reads it back: the screenshot.
    ///
    /// # Errors
    /// Mapping or waiting for the device failed.
    pub fn capture(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        source: &wgpu::TextureView,
        size: (u32, u32),
    ) -> Result<Rgba8Image> {
        let format = wgpu::TextureFormat::Rgba8Unorm;
        let (width, height) = size;
        let target = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("view screenshot"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = target.create_view(&Default::default());
        let padded = (width * 4).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let staging = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("view screenshot read-back"),
            size: u64::from(padded) * u64::from(height),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("view screenshot"),
        });
        {
            let mut pass = clear_pass(&mut encoder, "view screenshot blit", &view);
            self.draw(device, &mut pass, format, source, size, size);
        }
        encoder.copy_texture_to_buffer(
            target.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &staging,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded),
                    rows_per_image: Some(height),
                },
            },
            target.size(),
        );
        queue.submit([encoder.finish()]);
        let (tx, rx) = std::sync::mpsc::channel();
        staging
            .slice(..)
            .map_async(wgpu::MapMode::Read, move |r| drop(tx.send(r)));
        gpu::inspect::wait_idle(device)?;
        rx.recv()
            .context("the screenshot's read-back was dropped")?
            .context("mapping the screenshot")?;
        let mapped = staging
            .slice(..)
            .get_mapped_range()
            .context("reading the screenshot")?;
        let mut pixels = Vec::with_capacity((width * height) as usize);
        for row in mapped.chunks_exact(padded as usize) {
            for p in row[..(width * 4) as usize].chunks_exact(4) {
                pixels.push([p[0], p[1], p[2], p[3]]);
            }
        }
        drop(mapped);
        staging.unmap();
        Ok(Rgba8Image {
            width,
            height,
            pixels,
        })
    }
}

/// Begins a render pass named `label` that clears `target` to black: the one the window's
/// blit and overlay draw into, and the screenshot's.
pub fn clear_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    target: &wgpu::TextureView,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: target,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: None,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

/// An `Rgba8Unorm` texture holding `image` (a debug view), for the blit.
pub fn upload(device: &wgpu::Device, queue: &wgpu::Queue, image: &Rgba8Image) -> wgpu::Texture {
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("view debug image"),
        size: wgpu::Extent3d {
            width: image.width.max(1),
            height: image.height.max(1),
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8Unorm,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    if image.width > 0 && image.height > 0 {
        queue.write_texture(
            texture.as_image_copy(),
            image.pixels.as_flattened(),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(image.width * 4),
                rows_per_image: Some(image.height),
            },
            texture.size(),
        );
    }
    texture
}

#[cfg(test)]
mod tests {
    use super::fit;

    #[test]
    fn fitting_keeps_the_aspect() {
        assert_eq!(fit((320, 180), (320, 180)), [0.0, 0.0, 320.0, 180.0]);
        assert_eq!(fit((100, 100), (300, 100)), [100.0, 0.0, 100.0, 100.0]);
        assert_eq!(fit((200, 100), (100, 100)), [0.0, 25.0, 100.0, 50.0]);
        assert_eq!(fit((0, 0), (10, 10)), [0.0, 0.0, 10.0, 10.0]);
    }
}
