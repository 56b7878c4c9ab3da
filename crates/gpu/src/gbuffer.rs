//! The G-buffer on the GPU: `deferred`'s octahedral layout (world-space 12+12-bit normal,
//! formats guaranteed for storage writes, render attachments and 4x MSAA), written as
//! storage textures by the compute resolve (`gpu::gbuffer_store`), as colour attachments
//! by the baseline's fragment shader (`gpu::gbuffer_fragment`), and read as sampled
//! textures by lighting (`gpu::gbuffer_load`). The bit layout and its packing are
//! `deferred`'s; the bindings below are derived from `deferred`'s formats, and the pass
//! descriptions' naga checks tie them to the WGSL.

use deferred::{GBufferLayout, TargetFormat};
use shader::{Binding, Dim, Format, Kind, Sample};

/// The layout the renderer writes.
pub(crate) const LAYOUT: GBufferLayout = GBufferLayout::Octahedral;

/// wgpu's format for a `deferred` target format.
pub(crate) fn wgpu_format(f: TargetFormat) -> wgpu::TextureFormat {
    match f {
        TargetFormat::Rgba8Unorm => wgpu::TextureFormat::Rgba8Unorm,
        TargetFormat::Rgba8Uint => wgpu::TextureFormat::Rgba8Uint,
        TargetFormat::Rgba16Float => wgpu::TextureFormat::Rgba16Float,
        TargetFormat::Depth24PlusStencil8 => wgpu::TextureFormat::Depth24PlusStencil8,
        TargetFormat::Depth32Float => wgpu::TextureFormat::Depth32Float,
    }
}

/// The colour targets' wgpu formats, RT0..RT3.
pub(crate) fn color_formats() -> Vec<wgpu::TextureFormat> {
    LAYOUT
        .color_formats()
        .iter()
        .map(|&f| wgpu_format(f))
        .collect()
}

const fn color(i: usize) -> TargetFormat {
    LAYOUT.color_formats()[i]
}

const fn storage(i: usize) -> Kind {
    Kind::storage_texture_2d(match color(i) {
        TargetFormat::Rgba8Unorm => Format::Rgba8Unorm,
        TargetFormat::Rgba8Uint => Format::Rgba8Uint,
        TargetFormat::Rgba16Float => Format::Rgba16Float,
        _ => panic!("G-buffer colour targets are storage formats"),
    })
}

const fn sampled(i: usize) -> Kind {
    Kind::Texture {
        sample: match color(i) {
            TargetFormat::Rgba8Uint => Sample::Uint,
            _ => Sample::Float { filterable: false },
        },
        dim: Dim::D2,
    }
}

/// RT0..RT3 as the resolve writes them (`gpu::gbuffer_store`).
pub(crate) const STORE_BINDINGS: [Binding; 4] = [
    Binding::new("gbuffer_rt0", storage(0)),
    Binding::new("gbuffer_rt1", storage(1)),
    Binding::new("gbuffer_rt2", storage(2)),
    Binding::new("gbuffer_rt3", storage(3)),
];

/// RT0..RT3 as lighting reads them (`gpu::gbuffer_load`).
pub(crate) const LOAD_BINDINGS: [Binding; 4] = [
    Binding::new("gbuffer_tex0", sampled(0)),
    Binding::new("gbuffer_tex1", sampled(1)),
    Binding::new("gbuffer_tex2", sampled(2)),
    Binding::new("gbuffer_tex3", sampled(3)),
];

/// The colour-target states of the baseline's geometry pass.
pub(crate) fn color_targets() -> Vec<Option<wgpu::ColorTargetState>> {
    color_formats()
        .into_iter()
        .map(|format| {
            Some(wgpu::ColorTargetState {
                format,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })
        })
        .collect()
}

/// The G-buffer's texture views RT0..RT3 as bind-group resources of `bindings`, by name.
pub(crate) fn resources<'a>(
    bindings: &'a [Binding; 4],
    views: &'a [wgpu::TextureView],
) -> Vec<(&'a str, wgpu::BindingResource<'a>)> {
    bindings
        .iter()
        .zip(views)
        .map(|(b, v)| (b.name, wgpu::BindingResource::TextureView(v)))
        .collect()
}
