//! Devices: the headless helper finds an adapter (lavapipe in CI) and reports its paths,
//! disabled features select the fallbacks, and device errors come back as errors.

use gpu::config::PrimitiveIdPath;
use gpu::{HeadlessOptions, OPTIONAL_FEATURES};
use testkit::device::ctx;

#[test]
fn headless_device_reports_its_paths() {
    let ctx = ctx();
    eprintln!("adapter: {}", ctx.adapter_line());
    eprintln!("paths: {:?}", ctx.paths);
    assert_eq!(
        ctx.paths.primitive_id,
        PrimitiveIdPath::best_for(ctx.device.features())
    );
    if let Some((lo, hi)) = ctx.paths.subgroup_size {
        assert!(
            lo.is_power_of_two() && hi >= lo,
            "subgroup sizes {lo}..{hi}"
        );
    }
}

#[test]
fn disabling_features_selects_fallbacks() {
    let ctx = gpu::headless(&HeadlessOptions {
        disable_features: OPTIONAL_FEATURES,
        ..HeadlessOptions::default()
    })
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(ctx.paths.primitive_id, PrimitiveIdPath::ProvokingVertex);
    assert_eq!(ctx.paths.subgroup_size, None);
    assert!(!ctx.paths.timestamps);
}

#[test]
fn validation_errors_are_errors_not_panics() {
    let c = ctx();
    let err = gpu::inspect::scoped(&c.device, || {
        let _module = c.device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("bad"),
            source: wgpu::ShaderSource::Wgsl(
                "@compute @workgroup_size(1) fn main() { let x: u32 = 1.0; }".into(),
            ),
        });
        Ok(())
    })
    .unwrap_err();
    assert!(matches!(err, gpu::Error::Validation(_)), "{err}");
}

/// Without wgpu's indirect-argument validation the frame is the same: the renderer's
/// indirect dispatches and draws (the resolve's passes, and a static frame's placement and
/// draw lists) are valid by construction, so the injected pass only ever costs time.
#[test]
fn frames_without_indirect_validation_are_the_same() {
    use demo::{DemoOptions, DemoScene};
    use gpu::{RenderPath, Renderer, RendererConfig};
    let (scene, frame) = demo::build(&DemoOptions {
        scene: DemoScene::Grass,
        seed: 5,
        density: 0.25,
    });
    let image = |indirect_validation: bool| {
        let ctx = gpu::headless(&HeadlessOptions {
            indirect_validation,
            ..HeadlessOptions::default()
        })
        .unwrap_or_else(|e| panic!("{e}"));
        let mut config = RendererConfig::sized(160, 96);
        config.lighting.shadows = None;
        let mut r = Renderer::new(&ctx.device, &ctx.queue, config).unwrap();
        let p = r.prepare(&scene).unwrap();
        r.render(&p, &frame, RenderPath::Deferred).unwrap();
        r.read_output().unwrap()
    };
    assert_eq!(image(false).pixels, image(true).pixels);
}
