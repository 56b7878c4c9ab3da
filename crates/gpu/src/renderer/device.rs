//! What a renderer asks of its device: the features it can use and the limits it needs.

use super::*;
use crate::frame::stage_counts;

impl Renderer {
    /// The device features the renderer cannot run without: none (each optional one
    /// selects a faster path; see [`Renderer::optional_features`]).
    pub fn required_features() -> wgpu::Features {
        wgpu::Features::empty()
    }

    /// The features the renderer uses when the device has them (request them all; see
    /// [`ActivePaths`] for what each selects).
    pub fn optional_features() -> wgpu::Features {
        OPTIONAL_FEATURES
    }

    /// The device limits a renderer with `config` needs, as `wgpu::Limits::default()`
    /// raised where its passes need more (counted from every pass's bindings: classify
    /// output binds 17 storage buffers in one stage, past WebGPU's default 8 and some GL
    /// drivers' 16; four bind groups, the image size, buffers of `width * height`
    /// words). Request these, or the adapter's own limits, when you create the device.
    pub fn required_limits(config: &RendererConfig) -> wgpu::Limits {
        let c = stage_counts();
        let d = wgpu::Limits::default();
        let pixels = u64::from(config.image.width) * u64::from(config.image.height);
        // The largest buffers: the vis words (4 bytes a pixel) and the wave commands (16
        // bytes per command, at most a pixel's worth each for wave width 1; 8 lanes on
        // lavapipe make it 2 bytes a pixel plus one per counter).
        // The compute laydown's 64-bit target: 8 bytes a pixel.
        let per_pixel = if config.geometry.laydown.wants_compute() {
            8
        } else {
            4
        };
        let largest = (pixels * per_pixel).max(64 << 20);
        wgpu::Limits {
            max_storage_buffers_per_shader_stage: d
                .max_storage_buffers_per_shader_stage
                .max(c.storage_buffers),
            max_storage_textures_per_shader_stage: d
                .max_storage_textures_per_shader_stage
                .max(c.storage_textures),
            max_sampled_textures_per_shader_stage: d
                .max_sampled_textures_per_shader_stage
                .max(c.sampled_textures),
            max_samplers_per_shader_stage: d.max_samplers_per_shader_stage.max(c.samplers),
            max_uniform_buffers_per_shader_stage: d
                .max_uniform_buffers_per_shader_stage
                .max(c.uniform_buffers),
            max_dynamic_uniform_buffers_per_pipeline_layout: d
                .max_dynamic_uniform_buffers_per_pipeline_layout
                .max(c.dynamic_uniform_buffers),
            max_bind_groups: d.max_bind_groups.max(c.bind_groups),
            max_bindings_per_bind_group: d.max_bindings_per_bind_group.max(c.bindings_per_group),
            max_compute_invocations_per_workgroup: d
                .max_compute_invocations_per_workgroup
                .max(c.invocations_per_workgroup),
            max_texture_dimension_2d: d
                .max_texture_dimension_2d
                .max(config.image.width)
                .max(config.image.height),
            max_storage_buffer_binding_size: d.max_storage_buffer_binding_size.max(largest),
            max_buffer_size: d.max_buffer_size.max(largest),
            ..d
        }
    }
}

/// The first limit of `needed` that `available` falls short of (wgpu's own comparison of
/// every limit), as an error naming it.
pub(super) fn check_limits(needed: &wgpu::Limits, available: &wgpu::Limits) -> Result<()> {
    let mut first = None;
    needed.check_limits_with_fail_fn(available, true, |limit, needed, available| {
        first = Some(Error::DeviceLimit {
            limit,
            needed,
            available,
        });
    });
    first.map_or(Ok(()), Err)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::ImageConfig;

    #[test]
    fn default_limits_fall_short_by_name_and_the_required_ones_pass() {
        let config = RendererConfig::default();
        let needed = Renderer::required_limits(&config);
        assert!(check_limits(&needed, &needed).is_ok());
        match check_limits(&needed, &wgpu::Limits::default()) {
            Err(Error::DeviceLimit { limit, needed, .. }) => {
                assert_eq!(limit, "max_storage_buffers_per_shader_stage");
                assert!(needed >= 17, "{needed}");
            }
            other => panic!("{other:?}"),
        }
        // A 16K image needs a larger texture dimension than the defaults.
        let big = Renderer::required_limits(&RendererConfig {
            image: ImageConfig {
                width: 16_384,
                height: 16,
                ..Default::default()
            },
            ..RendererConfig::default()
        });
        assert_eq!(big.max_texture_dimension_2d, 16_384);
    }
}
