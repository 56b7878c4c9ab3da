//! Shared by the GPU agreement tests: one headless device per test binary, and a
//! deterministic generator.

use std::sync::OnceLock;

use gpu::context::{self, GpuContext, HeadlessOptions};

/// The device every GPU test of this binary uses (lavapipe in CI). A machine without any
/// Vulkan driver fails here, with the message saying how to install one.
pub fn ctx() -> &'static GpuContext {
    static CTX: OnceLock<GpuContext> = OnceLock::new();
    CTX.get_or_init(|| {
        context::headless(&HeadlessOptions::default()).unwrap_or_else(|e| panic!("{e}"))
    })
}

/// xorshift64*.
pub struct Rng(pub u64);

impl Rng {
    pub fn u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    pub fn u32(&mut self) -> u32 {
        (self.u64() >> 32) as u32
    }
    pub fn f32(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * ((self.u64() >> 40) as f32 / (1u64 << 24) as f32)
    }
}

/// Runs a kernel whose body maps `input[i * in_stride ..]` to `output[i * out_stride ..]`.
pub fn run(prelude: &str, body: &str, input: &[u32], items: u32, out_stride: usize) -> Vec<u32> {
    let src = format!(
        "{prelude}
@group(0) @binding(0) var<storage, read> input: array<u32>;
@group(0) @binding(1) var<storage, read_write> output: array<u32>;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {{
    let i = gid.x;
    if i >= {items}u {{ return; }}
    {body}
}}"
    );
    let c = ctx();
    gpu::kernel::run_u32_kernel(
        &c.device,
        &c.queue,
        &src,
        input,
        items,
        items as usize * out_stride,
    )
    .unwrap_or_else(|e| panic!("{e}\n--- kernel ---\n{src}"))
}
