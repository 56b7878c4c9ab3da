//! Running a small WGSL compute kernel over a word array: how the workspace checks each
//! crate's WGSL functions against their CPU versions on a real device.
//!
//! The kernel source gets `input: array<u32>` at binding 0 and `output: array<u32>` at
//! binding 1 of group 0, and an entry point `main` with `@workgroup_size(64)` is expected:
//!
//! ```no_run
//! let ctx = gpu::context::headless(&Default::default())?;
//! let src = "
//!   @group(0) @binding(0) var<storage, read> input: array<u32>;
//!   @group(0) @binding(1) var<storage, read_write> output: array<u32>;
//!   @compute @workgroup_size(64) fn main(@builtin(global_invocation_id) id: vec3<u32>) {
//!       if id.x < arrayLength(&input) { output[id.x] = input[id.x] * 2u; }
//!   }";
//! let out = gpu::kernel::run_u32_kernel(&ctx.device, &ctx.queue, src, &[1, 2, 3], 3, 3)?;
//! assert_eq!(out, [2, 4, 6]);
//! # Ok::<(), gpu::Error>(())
//! ```

use crate::context::scoped;
use crate::error::Result;
use crate::readback::read_buffer_as;
use crate::upload::storage_buffer;

/// Compiles `source`, runs `main` over `invocations` threads (rounded up to workgroups of
/// 64) with `input` bound at 0 and an `output_words`-word zeroed buffer at 1, and returns
/// the output. Validation errors come back as [`crate::Error::Validation`].
pub fn run_u32_kernel(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    source: &str,
    input: &[u32],
    invocations: u32,
    output_words: usize,
) -> Result<Vec<u32>> {
    let max_groups = device.limits().max_compute_workgroups_per_dimension;
    if invocations.div_ceil(64) > max_groups {
        return Err(crate::Error::DeviceLimit {
            limit: "max_compute_workgroups_per_dimension",
            needed: u64::from(invocations.div_ceil(64)),
            available: u64::from(max_groups),
        });
    }
    let output = scoped(device, || {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("test kernel"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("test kernel"),
            layout: None,
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        let input = storage_buffer(
            device,
            "kernel input",
            bytemuck::cast_slice(input),
            wgpu::BufferUsages::empty(),
        );
        let output = storage_buffer(
            device,
            "kernel output",
            &vec![0u8; output_words.max(1) * 4],
            wgpu::BufferUsages::empty(),
        );
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("test kernel"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: input.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: output.as_entire_binding(),
                },
            ],
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups(invocations.div_ceil(64), 1, 1);
        }
        queue.submit([encoder.finish()]);
        Ok(output)
    })?;
    let mut words: Vec<u32> = read_buffer_as(device, queue, &output)?;
    words.truncate(output_words);
    Ok(words)
}
