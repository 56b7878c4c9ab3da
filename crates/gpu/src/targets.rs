//! The frame's render targets: depth, the vis buffer, the G-buffer and the output image.

/// Depth format of every pass: reversed Z, cleared to 0, tested with `Greater`.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The vis buffer: one `visbuf` word per pixel, cleared to `visbuf::VIS_NONE`.
pub const VIS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
/// The final tone-mapped image: sRGB-encoded values written by the lighting pass (storage
/// textures cannot be `*Srgb`, so the encode is done in the shader).
pub const OUTPUT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// Size-dependent textures of one renderer.
pub struct Targets {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Depth.
    pub depth: wgpu::Texture,
    /// Vis buffer.
    pub vis: wgpu::Texture,
    /// The vis buffer as row-major words (written by the vis-copy pass) for the
    /// classification passes, which read `array<u32>`.
    pub vis_words: wgpu::Buffer,
    /// G-buffer targets, in `deferred`'s layout order.
    pub gbuffer: Vec<wgpu::Texture>,
    /// Output image.
    pub output: wgpu::Texture,
}

fn texture(
    device: &wgpu::Device,
    label: &str,
    width: u32,
    height: u32,
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

impl Targets {
    /// Creates the targets for `width` × `height` with G-buffer targets of `gbuffer_formats`.
    pub fn new(
        device: &wgpu::Device,
        width: u32,
        height: u32,
        gbuffer_formats: &[wgpu::TextureFormat],
    ) -> Self {
        use wgpu::TextureUsages as U;
        let depth = texture(
            device,
            "depth",
            width,
            height,
            DEPTH_FORMAT,
            U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC,
        );
        let vis = texture(
            device,
            "vis buffer",
            width,
            height,
            VIS_FORMAT,
            U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC,
        );
        let vis_words = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("vis buffer words"),
            size: u64::from(width) * u64::from(height) * 4,
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let gbuffer = gbuffer_formats
            .iter()
            .enumerate()
            .map(|(i, &f)| {
                texture(
                    device,
                    &format!("gbuffer {i}"),
                    width,
                    height,
                    f,
                    U::RENDER_ATTACHMENT | U::STORAGE_BINDING | U::TEXTURE_BINDING | U::COPY_SRC,
                )
            })
            .collect();
        let output = texture(
            device,
            "output",
            width,
            height,
            OUTPUT_FORMAT,
            U::STORAGE_BINDING | U::TEXTURE_BINDING | U::COPY_SRC,
        );
        Self {
            width,
            height,
            depth,
            vis,
            vis_words,
            gbuffer,
            output,
        }
    }
}
