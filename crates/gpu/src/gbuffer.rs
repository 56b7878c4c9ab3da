//! The G-buffer on the GPU, in either of `deferred`'s layouts
//! ([`RendererConfig::image.gbuffer`](crate::config::ImageConfig::gbuffer)): the octahedral one (the
//! default: world-space 12+12-bit normal, formats guaranteed for storage writes, render
//! attachments and 4x MSAA, 20 bytes a pixel) or KZ2's four RGBA8 targets (view-space
//! normal xy in f16 pairs, 16 bytes a pixel; feature `kz2_gbuffer` of the modules), written as
//! storage textures by the compute resolve (`gpu::gbuffer_store`), as colour attachments
//! by the baseline's fragment shader (`gpu::gbuffer_fragment`), and read as sampled
//! textures by lighting (`gpu::gbuffer_load`). The bit layout and its packing are
//! `deferred`'s; the bindings below are derived from `deferred`'s formats, and the pass
//! descriptions' naga checks tie them to the WGSL.

use deferred::{GBufferLayout, TargetFormat};
use shader::{Binding, Dim, Format, Kind, Sample};

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

/// The colour targets' wgpu formats, RT0..RT3, of `layout`.
pub(crate) fn color_formats(layout: GBufferLayout) -> Vec<wgpu::TextureFormat> {
    layout
        .color_formats()
        .iter()
        .map(|&f| wgpu_format(f))
        .collect()
}

const fn storage(layout: GBufferLayout, i: usize) -> Kind {
    Kind::storage_texture_2d(match layout.color_formats()[i] {
        TargetFormat::Rgba8Unorm => Format::Rgba8Unorm,
        TargetFormat::Rgba8Uint => Format::Rgba8Uint,
        TargetFormat::Rgba16Float => Format::Rgba16Float,
        _ => panic!("G-buffer colour targets are storage formats"),
    })
}

const fn sampled(layout: GBufferLayout, i: usize, dim: Dim) -> Kind {
    Kind::Texture {
        sample: match layout.color_formats()[i] {
            TargetFormat::Rgba8Uint => Sample::Uint,
            _ => Sample::Float { filterable: false },
        },
        dim,
    }
}

const fn store_bindings(layout: GBufferLayout) -> [Binding; 4] {
    [
        Binding::new("gbuffer_rt0", storage(layout, 0)),
        Binding::new("gbuffer_rt1", storage(layout, 1)),
        Binding::new("gbuffer_rt2", storage(layout, 2)),
        Binding::new("gbuffer_rt3", storage(layout, 3)),
    ]
}

const fn load_bindings(layout: GBufferLayout, dim: Dim) -> [Binding; 4] {
    [
        Binding::new("gbuffer_tex0", sampled(layout, 0, dim)),
        Binding::new("gbuffer_tex1", sampled(layout, 1, dim)),
        Binding::new("gbuffer_tex2", sampled(layout, 2, dim)),
        Binding::new("gbuffer_tex3", sampled(layout, 3, dim)),
    ]
}

/// RT0..RT3 as the resolve writes them (`gpu::gbuffer_store`), octahedral layout.
pub(crate) const STORE_BINDINGS: [Binding; 4] = store_bindings(GBufferLayout::Octahedral);
/// The same for the KZ2 preset (feature `kz2_gbuffer`).
pub(crate) const KZ2_STORE_BINDINGS: [Binding; 4] = store_bindings(GBufferLayout::Kz2);
/// RT0..RT3 as lighting reads them (`gpu::gbuffer_load`), octahedral layout.
pub(crate) const LOAD_BINDINGS: [Binding; 4] = load_bindings(GBufferLayout::Octahedral, Dim::D2);
/// The same for the KZ2 preset (feature `kz2_gbuffer`).
pub(crate) const KZ2_LOAD_BINDINGS: [Binding; 4] = load_bindings(GBufferLayout::Kz2, Dim::D2);
/// The baseline's multisampled G-buffer (feature `msaa`), octahedral layout.
pub(crate) const MSAA_LOAD_BINDINGS: [Binding; 4] =
    load_bindings(GBufferLayout::Octahedral, Dim::D2Multisampled);
/// The same for the KZ2 preset (features `msaa`, `kz2_gbuffer`).
pub(crate) const KZ2_MSAA_LOAD_BINDINGS: [Binding; 4] =
    load_bindings(GBufferLayout::Kz2, Dim::D2Multisampled);

/// The WGSL feature of `layout`'s G-buffer modules (none for the octahedral layout).
pub(crate) fn features(layout: GBufferLayout) -> &'static [&'static str] {
    match layout {
        GBufferLayout::Kz2 => &["kz2_gbuffer"],
        GBufferLayout::Octahedral => &[],
    }
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
