//! The renderer and device the arguments ask for, and the frame's lights (`--lights`, `--no-sun`).

use gpu::config::PrimitiveIdPath;
use gpu::{HeadlessOptions, RendererConfig};

use crate::args::{
    Args, GBufferArg, LaydownArg, LaydownTargetArg, MaterialShadersArg, MsaaArg, PrimitiveIdArg,
    VertexRingArg, VrsArg,
};

impl Args {
    /// The headless device's options: `--no-subgroups` and `--no-barycentrics` leave those
    /// features off, `--indirect-validation` turns wgpu's validation on.
    pub fn headless_options(&self) -> HeadlessOptions {
        let mut disable = wgpu::Features::empty();
        if self.no_subgroups {
            disable |= wgpu::Features::SUBGROUP;
        }
        if self.no_barycentrics {
            disable |= wgpu::Features::SHADER_BARYCENTRICS;
        }
        HeadlessOptions {
            disable_features: disable,
            indirect_validation: self.indirect_validation,
            ..Default::default()
        }
    }

    /// The renderer configuration the arguments ask for (`--msaa compare`: KZ2's; the
    /// second renderer lighting every sample is [`RendererConfig`] with that changed).
    pub fn renderer_config(&self) -> RendererConfig {
        let primitive_id = match self.primitive_id {
            PrimitiveIdArg::Auto => None,
            PrimitiveIdArg::Builtin => Some(PrimitiveIdPath::Builtin),
            PrimitiveIdArg::Xor => Some(PrimitiveIdPath::PerVertexXor),
            PrimitiveIdArg::Provoking => Some(PrimitiveIdPath::ProvokingVertex),
        };
        {
            let mut rc = RendererConfig::sized(self.width, self.height);
            rc.image.gbuffer = match self.gbuffer {
                GBufferArg::Octahedral => gpu::deferred::GBufferLayout::Octahedral,
                GBufferArg::Kz2 => gpu::deferred::GBufferLayout::Kz2,
            };
            rc.image.msaa = match self.msaa {
                MsaaArg::Off => None,
                MsaaArg::Kz2 | MsaaArg::Compare => Some(gpu::config::MsaaLighting::Kz2),
                MsaaArg::EverySample => Some(gpu::config::MsaaLighting::EverySample),
            };
            rc.geometry.primitive_id = primitive_id;
            rc.geometry.laydown = match self.laydown {
                LaydownArg::Hardware => gpu::Laydown::Hardware,
                LaydownArg::Compute => gpu::Laydown::Compute,
                LaydownArg::Auto => gpu::Laydown::Auto,
            };
            rc.geometry.compute_laydown_max_extent = self.laydown_max_extent;
            rc.geometry.compute_laydown_target = match self.laydown_target {
                LaydownTargetArg::Auto => None,
                LaydownTargetArg::Buffer => Some(gpu::config::LaydownTarget::Buffer),
                LaydownTargetArg::Texture => Some(gpu::config::LaydownTarget::Texture),
            };
            rc.geometry.mixed_frame = self.mixed_frame;
            rc.geometry.vertex_ring = match self.vertex_ring {
                VertexRingArg::Off => None,
                VertexRingArg::Ps4 => Some(gpu::config::RING_BYTES_PS4),
                VertexRingArg::Ps5 => Some(gpu::config::RING_BYTES_PS5),
            };
            rc.geometry.ring_resolve = !self.per_pixel_transform;
            rc.geometry.material_permutations =
                self.material_shaders == MaterialShadersArg::PerShader;
            rc.geometry.vrs = match self.vrs {
                VrsArg::Off => None,
                VrsArg::On => Some(gpu::config::VrsConfig::default()),
                VrsArg::All2x2 => Some(gpu::config::VrsConfig {
                    distance_2x1: 1e-6,
                    distance_2x2: 1e-6,
                    ..gpu::config::VrsConfig::default()
                }),
            };
            rc.lighting.light_paths = if self.all_lights {
                gpu::config::LightPaths::EveryPixel
            } else {
                self.light_paths.paths()
            };
            rc.lighting.shadows = (!self.no_shadows).then(|| gpu::config::ShadowConfig {
                cache: !self.no_shadow_cache,
                resolution_divisor: if self.uniform_shadow_resolution {
                    [1; 8]
                } else {
                    gpu::config::ShadowConfig::default().resolution_divisor
                },
                static_size_threshold: self.shadow_size_threshold,
                ..gpu::config::ShadowConfig::default()
            });
            rc.lighting.baked_sun = !self.no_baked_sun;
            rc.lighting.spot_shadows =
                (!self.no_spot_shadows).then(gpu::config::SpotShadowConfig::default);
            rc.lighting.cull_shadow_casters = !self.no_caster_culling;
            rc.lighting.conditional_volumes = !self.no_conditional_volumes;
            rc
        }
    }
}

/// `frame` with `args.lights` lights scattered within `half_extent` metres of its target
/// (`--light-area` instead, if given), and the sun and ambient dimmed to dusk so that they
/// show; the sun off with `--no-sun` ([`cli::lighting`]).
pub(crate) fn with_lights(
    args: &Args,
    mut frame: gpu::FrameInput,
    half_extent: f32,
) -> gpu::FrameInput {
    let lights = cli::LocalLights {
        no_sun: args.no_sun,
        count: args.lights,
        half_extent: args.light_area.unwrap_or(half_extent),
        seed: args.seed,
    };
    let lighting = std::mem::take(&mut frame.lighting);
    frame.lighting = cli::lighting(lighting, frame.camera.target, &lights);
    frame
}
