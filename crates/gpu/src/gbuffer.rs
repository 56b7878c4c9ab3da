//! The G-buffer on the GPU: `deferred`'s octahedral layout (world-space 12+12-bit normal,
//! formats guaranteed for storage writes, render attachments and 4x MSAA), bound as
//! storage textures for the compute resolve, as colour attachments for the baseline's
//! fragment shader, and as sampled textures for lighting. The bit layout and its WGSL are
//! `deferred`'s; this module only maps formats and binds.

use deferred::{GBufferLayout, TargetFormat};

/// The layout the renderer writes.
pub const LAYOUT: GBufferLayout = GBufferLayout::Octahedral;

/// wgpu's format for a `deferred` target format.
pub fn wgpu_format(f: TargetFormat) -> wgpu::TextureFormat {
    match f {
        TargetFormat::Rgba8Unorm => wgpu::TextureFormat::Rgba8Unorm,
        TargetFormat::Rgba8Uint => wgpu::TextureFormat::Rgba8Uint,
        TargetFormat::Rgba16Float => wgpu::TextureFormat::Rgba16Float,
        TargetFormat::Depth24PlusStencil8 => wgpu::TextureFormat::Depth24PlusStencil8,
        TargetFormat::Depth32Float => wgpu::TextureFormat::Depth32Float,
    }
}

/// The colour targets' wgpu formats, RT0..RT3.
pub fn color_formats() -> Vec<wgpu::TextureFormat> {
    LAYOUT
        .color_formats()
        .iter()
        .map(|&f| wgpu_format(f))
        .collect()
}

/// WGSL sample type of a target format when bound for `textureLoad`.
fn sample_type(f: TargetFormat) -> wgpu::TextureSampleType {
    match f {
        TargetFormat::Rgba8Uint => wgpu::TextureSampleType::Uint,
        _ => wgpu::TextureSampleType::Float { filterable: false },
    }
}

/// Storage-texture bindings (write) of RT0..RT3 at `first_binding..` in `group`: WGSL
/// declarations plus `gbuffer_store(pixel, surface)`.
pub fn store_wgsl(group: u32, first_binding: u32) -> String {
    let mut s = String::new();
    for (i, f) in LAYOUT.color_formats().iter().enumerate() {
        let name = f
            .wgsl_storage_name()
            .expect("colour targets are storage formats");
        s += &format!(
            "@group({group}) @binding({}) var gbuffer_rt{i}: texture_storage_2d<{name}, write>;\n",
            first_binding + i as u32
        );
    }
    s += "fn gbuffer_store(pixel: vec2<u32>, surface: DeferredSurface) {\n";
    s += "    let t = deferred_gbuffer_oct_pack(surface);\n";
    for i in 0..LAYOUT.color_formats().len() {
        s += &format!("    textureStore(gbuffer_rt{i}, vec2<i32>(pixel), t.rt{i});\n");
    }
    s += "}\n";
    s
}

/// Fragment outputs RT0..RT3: the struct `GBufferOut` and `gbuffer_fragment(surface)`.
pub fn fragment_wgsl() -> String {
    let mut s = String::from("struct GBufferOut {\n");
    for (i, f) in LAYOUT.color_formats().iter().enumerate() {
        let ty = if *f == TargetFormat::Rgba8Uint {
            "vec4<u32>"
        } else {
            "vec4<f32>"
        };
        s += &format!("    @location({i}) rt{i}: {ty},\n");
    }
    s += "}\nfn gbuffer_fragment(surface: DeferredSurface) -> GBufferOut {\n";
    s += "    let t = deferred_gbuffer_oct_pack(surface);\n    var o: GBufferOut;\n";
    for i in 0..LAYOUT.color_formats().len() {
        s += &format!("    o.rt{i} = t.rt{i};\n");
    }
    s += "    return o;\n}\n";
    s
}

/// Sampled-texture bindings of RT0..RT3 at `first_binding..` in `group`, and
/// `gbuffer_surface(pixel) -> DeferredSurface`.
pub fn load_wgsl(group: u32, first_binding: u32) -> String {
    let mut s = String::new();
    for (i, f) in LAYOUT.color_formats().iter().enumerate() {
        let ty = if *f == TargetFormat::Rgba8Uint {
            "texture_2d<u32>"
        } else {
            "texture_2d<f32>"
        };
        s += &format!(
            "@group({group}) @binding({}) var gbuffer_tex{i}: {ty};\n",
            first_binding + i as u32
        );
    }
    s += "fn gbuffer_surface(pixel: vec2<u32>) -> DeferredSurface {\n";
    s += "    let p = vec2<i32>(pixel);\n";
    s += "    return deferred_gbuffer_oct_unpack(textureLoad(gbuffer_tex0, p, 0), textureLoad(gbuffer_tex1, p, 0), \
          textureLoad(gbuffer_tex2, p, 0), textureLoad(gbuffer_tex3, p, 0));\n}\n";
    s
}

/// Layout entries of the storage bindings written by [`store_wgsl`].
pub fn store_layout_entries(
    first_binding: u32,
    stages: wgpu::ShaderStages,
) -> Vec<wgpu::BindGroupLayoutEntry> {
    LAYOUT
        .color_formats()
        .iter()
        .enumerate()
        .map(|(i, &f)| {
            crate::binding::storage_texture(first_binding + i as u32, stages, wgpu_format(f))
        })
        .collect()
}

/// Layout entries of the sampled bindings read by [`load_wgsl`].
pub fn load_layout_entries(
    first_binding: u32,
    stages: wgpu::ShaderStages,
) -> Vec<wgpu::BindGroupLayoutEntry> {
    LAYOUT
        .color_formats()
        .iter()
        .enumerate()
        .map(|(i, &f)| {
            crate::binding::texture(
                first_binding + i as u32,
                stages,
                sample_type(f),
                wgpu::TextureViewDimension::D2,
            )
        })
        .collect()
}

/// The colour-target states of the baseline's geometry pass.
pub fn color_targets() -> Vec<Option<wgpu::ColorTargetState>> {
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
