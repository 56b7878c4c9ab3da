//! Devices: the headless helper finds an adapter (lavapipe in CI) and reports its paths,
//! disabled features select the fallbacks, and device errors come back as errors.

use gpu::{HeadlessOptions, OPTIONAL_FEATURES, PrimitiveIdPath};
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
    let err = gpu::scoped(&c.device, || {
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
