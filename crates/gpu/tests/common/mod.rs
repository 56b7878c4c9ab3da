//! What the renderer's integration tests share: a renderer on testkit's device.
#![allow(dead_code)]

use gpu::config::ShadowConfig;
use gpu::inspect::{ClassificationStats, GpuClassification};
use gpu::scene::ShaderKind;
use gpu::{Material, PreparedScene, Renderer, RendererConfig, Rgba8Image};
use testkit::device::ctx;

pub mod laydown;

/// The sun's shadow maps of the tests' renderers: the default cascades at 512 texels
/// (lavapipe rasterises a 2048-texel map of the forest in about 0.2 s).
pub fn test_shadows() -> Option<ShadowConfig> {
    Some(ShadowConfig {
        resolution: 512,
        ..ShadowConfig::default()
    })
}

/// A renderer of `config` on the shared test device.
pub fn renderer_with(config: RendererConfig) -> Renderer {
    let c = ctx();
    Renderer::new(&c.device, &c.queue, config).unwrap_or_else(|e| panic!("{e}"))
}

/// A renderer of `width` x `height` on the shared test device, subgroups on or off, with
/// the tests' shadow maps.
pub fn renderer(width: u32, height: u32, subgroups: bool) -> Renderer {
    renderer_with({
        let mut rc = RendererConfig::sized(width, height);
        rc.geometry.subgroups = subgroups;
        rc.lighting.shadows = test_shadows();
        rc
    })
}

/// Pixels of `a` and `b` (same size) that differ in any channel.
pub fn differing_pixels(a: &Rgba8Image, b: &Rgba8Image) -> usize {
    a.pixels
        .iter()
        .zip(&b.pixels)
        .filter(|(x, y)| x != y)
        .count()
}

/// A material named `name` with `shader` on albedo layer 0: white tint, alpha cutoff 0.5,
/// roughness and specular 0.5.
pub fn material(name: &str, shader: ShaderKind) -> Material {
    Material {
        name: name.into(),
        shader,
        albedo_layer: 0,
        tint: glam::Vec3::ONE,
        alpha_cutoff: 0.5,
        roughness: 0.5,
        specular: 0.5,
        regular: false,
        ..Default::default()
    }
}

/// The talk's statistics of `gpu` (the classification `prepared`'s last frame wrote),
/// asserting first that it equals tiling's CPU twin run on the same vis words (`what`
/// names the case in the failure).
pub fn equals_twin(
    r: &Renderer,
    prepared: &PreparedScene,
    gpu: &GpuClassification,
    what: &str,
) -> ClassificationStats {
    let (stats, mismatch) = r
        .inspect()
        .classification_statistics(prepared, gpu)
        .unwrap();
    assert_eq!(
        mismatch, None,
        "{what}: GPU classification differs from the CPU twin"
    );
    stats
}
