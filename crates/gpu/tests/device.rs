//! Device smoke tests: a headless adapter exists (lavapipe in CI), reports its paths, and
//! runs a kernel. A machine without any Vulkan driver fails here with instructions.

use gpu::context::{self, HeadlessOptions, PrimitiveIdPath};

fn ctx() -> context::GpuContext {
    context::headless(&HeadlessOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

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
    let ctx = context::headless(&HeadlessOptions {
        disable_features: context::OPTIONAL_FEATURES,
        ..HeadlessOptions::default()
    })
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(ctx.paths.primitive_id, PrimitiveIdPath::ProvokingVertex);
    assert_eq!(ctx.paths.subgroup_size, None);
    assert!(!ctx.paths.timestamps);
}

#[test]
fn kernel_runs_and_validation_errors_are_errors() {
    let ctx = ctx();
    let src = "
      @group(0) @binding(0) var<storage, read> input: array<u32>;
      @group(0) @binding(1) var<storage, read_write> output: array<u32>;
      @compute @workgroup_size(64) fn main(@builtin(global_invocation_id) id: vec3<u32>) {
          if id.x < arrayLength(&input) { output[id.x] = input[id.x] * 3u + 1u; }
      }";
    let input: Vec<u32> = (0..1000).collect();
    let out =
        gpu::kernel::run_u32_kernel(&ctx.device, &ctx.queue, src, &input, 1000, 1000).unwrap();
    assert!(out.iter().zip(&input).all(|(o, i)| *o == i * 3 + 1));
    let bad = "@compute @workgroup_size(64) fn main() { let x: u32 = 1.0; }";
    let err = gpu::kernel::run_u32_kernel(&ctx.device, &ctx.queue, bad, &input, 1, 1).unwrap_err();
    assert!(matches!(err, gpu::Error::Validation(_)), "{err}");
}
