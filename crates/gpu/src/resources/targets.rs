//! The frame's render targets: depth, the vis buffer (and its word copy), the G-buffer and
//! the output image, with the views every pass binds.

use crate::gbuffer;
use shader::{DepthFormat, Format};

/// Depth format of every pass: reversed Z, cleared to 0, tested with `Greater`.
pub(crate) const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The depth the compute passes read (lighting, light tiles): the depth target's values
/// as a float colour texture, since compute passes can write colour storage textures but
/// never depth ones (the compute laydown writes it directly, the hardware paths copy it).
pub(crate) const DEPTH_FLOAT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
/// The vis buffer: one `visbuf` word per pixel, cleared to `visbuf::VIS_NONE`.
pub(crate) const VIS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
/// The final tone-mapped image: sRGB-encoded values written by the lighting pass (storage
/// textures cannot be `*Srgb`, so the encode is done in the shader).
pub(crate) const OUTPUT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// Size-dependent textures of one renderer.
pub(crate) struct Targets {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Depth.
    pub depth: wgpu::Texture,
    pub depth_view: wgpu::TextureView,
    /// The depth as [`DEPTH_FLOAT_FORMAT`] (same values, reversed Z, 0 where nothing was
    /// drawn), written after the geometry pass of every single-sampled frame: what the light
    /// tiles and lighting read.
    pub depth_float: wgpu::Texture,
    pub depth_float_view: wgpu::TextureView,
    /// Vis buffer.
    pub vis: wgpu::Texture,
    pub vis_view: wgpu::TextureView,
    /// The vis buffer as row-major words (written by the vis-copy pass) for the
    /// classification passes, which read `array<u32>`.
    pub vis_words: wgpu::Buffer,
    /// The compute laydown's 64-bit visibility target (depth bits high, vis word low, 8
    /// bytes a pixel, row-major), with [`Laydown::Compute`](crate::Laydown) on a device
    /// that has it (set by the renderer after [`Targets::new`]).
    pub vis64: Option<crate::resources::vis64::TargetResource>,
    /// G-buffer targets RT0..RT3, in `deferred`'s layout order (kept with their views).
    pub gbuffer: Vec<wgpu::Texture>,
    pub gbuffer_views: Vec<wgpu::TextureView>,
    /// Output image.
    pub output: wgpu::Texture,
    pub output_view: wgpu::TextureView,
    /// The sun's shadow maps (one 1x1 layer when shadows are off).
    pub shadows: crate::shadows::ShadowMaps,
    /// The spot lights' shadow maps (one 1x1 layer without them).
    pub spot_shadows: crate::spot_shadows::SpotShadowMaps,
    /// The stencil light volumes' accumulation and depth-stencil (1x1 without volumes).
    pub light_volumes: VolumeTargets,
    /// The baseline path's 4x multisampled depth and G-buffer, with MSAA on.
    pub msaa: Option<MsaaTargets>,
}

/// Bytes before the edge pixels in [`MsaaTargets::edges`] (WGSL `GpuMsaaEdges`: the
/// dispatch's three words and the count).
pub(crate) const MSAA_EDGES_HEADER: u64 = 16;

/// The baseline's multisampled targets ([`crate::config::MSAA_SAMPLES`] samples a pixel) and
/// the list of edge pixels lighting appends to.
pub(crate) struct MsaaTargets {
    /// The views (each keeps its texture alive).
    pub depth_view: wgpu::TextureView,
    pub gbuffer_views: Vec<wgpu::TextureView>,
    /// WGSL `GpuMsaaEdges`: the edge pass's indirect dispatch (3 words), the edge count,
    /// then one word per edge pixel (`x | y << 16`), room for every pixel.
    pub edges: wgpu::Buffer,
    /// The edge pass's indirect arguments, copied out of `edges` (a dispatch cannot read
    /// its arguments from a buffer it binds for writing).
    pub edge_dispatch: wgpu::Buffer,
}

impl MsaaTargets {
    fn new(
        device: &wgpu::Device,
        width: u32,
        height: u32,
        layout: deferred::GBufferLayout,
    ) -> Self {
        use wgpu::TextureUsages as U;
        let make = |label: &str, format| {
            let usage = U::RENDER_ATTACHMENT | U::TEXTURE_BINDING;
            let samples = crate::config::MSAA_SAMPLES;
            texture_samples(device, label, [width, height], format, usage, samples).1
        };
        let depth_view = make("msaa depth", DEPTH_FORMAT);
        let gbuffer_views = gbuffer::color_formats(layout)
            .into_iter()
            .enumerate()
            .map(|(i, f)| make(&format!("msaa gbuffer rt{i}"), f))
            .collect();
        let edges = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("msaa edge pixels"),
            size: MSAA_EDGES_HEADER + u64::from(width) * u64::from(height) * 4,
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let edge_dispatch = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("msaa edge dispatch"),
            size: 12,
            usage: wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self {
            depth_view,
            gbuffer_views,
            edges,
            edge_dispatch,
        }
    }
}

/// `view` as a colour attachment cleared to transparent black and stored.
pub(crate) fn cleared_color(
    view: &wgpu::TextureView,
) -> Option<wgpu::RenderPassColorAttachment<'_>> {
    Some(wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
            store: wgpu::StoreOp::Store,
        },
    })
}

/// A single-sample 2D texture of `width` × `height` and its default view.
pub(crate) fn texture(
    device: &wgpu::Device,
    label: &str,
    width: u32,
    height: u32,
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> (wgpu::Texture, wgpu::TextureView) {
    texture_samples(device, label, [width, height], format, usage, 1)
}

/// A 2D texture of `size` pixels at `samples` samples a pixel and its default view.
fn texture_samples(
    device: &wgpu::Device,
    label: &str,
    [width, height]: [u32; 2],
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
    samples: u32,
) -> (wgpu::Texture, wgpu::TextureView) {
    let t = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: samples,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    });
    let v = t.create_view(&Default::default());
    (t, v)
}

impl Targets {
    /// The targets for `width` × `height` pixels, the sun's shadow maps of `shadows`, with
    /// `light_volumes` the stencil volumes' targets, the G-buffer of `gbuffer_layout`, and
    /// the spot shadow maps of `spot_shadows`, and with `msaa` the baseline's
    /// multisampled targets.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        device: &wgpu::Device,
        width: u32,
        height: u32,
        shadows: Option<crate::shadows::ShadowConfig>,
        light_volumes: bool,
        gbuffer_layout: deferred::GBufferLayout,
        spot_shadows: Option<crate::config::SpotShadowConfig>,
        msaa: bool,
    ) -> Self {
        use wgpu::TextureUsages as U;
        let (depth, depth_view) = texture(
            device,
            "depth",
            width,
            height,
            DEPTH_FORMAT,
            U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC,
        );
        let (depth_float, depth_float_view) = texture(
            device,
            "depth (float)",
            width,
            height,
            DEPTH_FLOAT_FORMAT,
            U::STORAGE_BINDING | U::TEXTURE_BINDING | U::COPY_SRC,
        );
        let (vis, vis_view) = texture(
            device,
            "vis buffer",
            width,
            height,
            VIS_FORMAT,
            U::RENDER_ATTACHMENT | U::STORAGE_BINDING | U::TEXTURE_BINDING | U::COPY_SRC,
        );
        let vis_words = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("vis buffer words"),
            size: u64::from(width) * u64::from(height) * 4,
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let (gbuffer, gbuffer_views) = gbuffer::color_formats(gbuffer_layout)
            .into_iter()
            .enumerate()
            .map(|(i, f)| {
                texture(
                    device,
                    &format!("gbuffer rt{i}"),
                    width,
                    height,
                    f,
                    U::RENDER_ATTACHMENT | U::STORAGE_BINDING | U::TEXTURE_BINDING | U::COPY_SRC,
                )
            })
            .unzip();
        let (output, output_view) = texture(
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
            depth_view,
            depth_float,
            depth_float_view,
            vis,
            vis_view,
            vis_words,
            vis64: None,
            gbuffer,
            gbuffer_views,
            output,
            output_view,
            shadows: crate::shadows::ShadowMaps::new(device, shadows),
            spot_shadows: crate::spot_shadows::SpotShadowMaps::new(device, spot_shadows),
            light_volumes: VolumeTargets::new(device, width, height, light_volumes),
            msaa: msaa.then(|| MsaaTargets::new(device, width, height, gbuffer_layout)),
        }
    }
}

/// The volume pass's own targets: the light accumulation (read by lighting) and the
/// depth-stencil copy of the frame's depth. 1x1 when no light may take the path.
/// (Views keep their textures alive.)
pub(crate) struct VolumeTargets {
    pub accumulation_view: wgpu::TextureView,
    pub depth_stencil_view: wgpu::TextureView,
}

/// The accumulation's format: 32-bit float where the device blends it (the sum then
/// rounds as the compute lighting's own does), else 16-bit.
pub(crate) fn accumulation_format(device: &wgpu::Device) -> wgpu::TextureFormat {
    shader::pipeline::texture_format(accumulation(device))
}

/// [`accumulation_format`] in the descriptions' terms.
pub(crate) fn accumulation(device: &wgpu::Device) -> Format {
    if device
        .features()
        .contains(wgpu::Features::FLOAT32_BLENDABLE)
    {
        Format::Rgba32Float
    } else {
        Format::Rgba16Float
    }
}

/// The depth-stencil copy's format: the depth target's 32-bit float with stencil where
/// the device has it, else 24-bit depth.
pub(crate) fn depth_stencil_format(device: &wgpu::Device) -> wgpu::TextureFormat {
    shader::pipeline::depth_format(depth_stencil(device))
}

/// [`depth_stencil_format`] in the descriptions' terms.
pub(crate) fn depth_stencil(device: &wgpu::Device) -> DepthFormat {
    if device
        .features()
        .contains(wgpu::Features::DEPTH32FLOAT_STENCIL8)
    {
        DepthFormat::Depth32FloatStencil8
    } else {
        DepthFormat::Depth24PlusStencil8
    }
}

impl VolumeTargets {
    /// Targets of `width` × `height` pixels, or 1x1 ones without `enabled`.
    pub(crate) fn new(device: &wgpu::Device, width: u32, height: u32, enabled: bool) -> Self {
        use wgpu::TextureUsages as U;
        let (w, h) = if enabled { (width, height) } else { (1, 1) };
        let make = |label, format, usage| texture(device, label, w, h, format, usage).1;
        let accumulation_view = make(
            "light accumulation",
            accumulation_format(device),
            U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC,
        );
        let depth_stencil_view = make(
            "light volume depth-stencil",
            depth_stencil_format(device),
            U::RENDER_ATTACHMENT,
        );
        Self {
            accumulation_view,
            depth_stencil_view,
        }
    }
}
