//! Tiled local lights (KZ2's hundreds of point and spot lights): the depth target reduced
//! to per-tile depth ranges (`gpu::tile_depth`, pass 1 of `deferred`'s tiled culling),
//! then `deferred`'s light-culling pass ([`deferred::pass::LIGHT_CULL_PASS`]) writes each
//! 16x16 tile's light list, which lighting reads. Lights are uploaded in view space each
//! frame ([`crate::resources::uniforms::local_light_rows`]).

use deferred::pass::{LIGHT_CULL_PASS, LightCullParams};
use shader::pipeline::ComputePass;

use super::context::FrameContext;
use crate::error::Result;
use crate::passes::depth_reductions::TILE_DEPTH;
use crate::passes::depth_reductions::TILE_DEPTH_MSAA;
pub(crate) use crate::resources::groups::LightTileGroups as Groups;
use crate::resources::lights::LightBuffers;
use crate::resources::targets::Targets;
use crate::timing::GpuTimer;

/// The two passes' pipelines.
pub(crate) struct LocalLights {
    tile_depth: ComputePass<[u32; 2]>,
    /// Over the multisampled depth, with MSAA on.
    tile_depth_msaa: Option<ComputePass<[u32; 2]>>,
    cull: ComputePass<LightCullParams>,
}

impl LocalLights {
    pub(crate) fn new(device: &wgpu::Device, msaa: bool) -> Result<Self> {
        Ok(Self {
            tile_depth: ComputePass::new(device, &TILE_DEPTH, &[], &[])?,
            tile_depth_msaa: if msaa {
                Some(ComputePass::new(device, &TILE_DEPTH_MSAA, &["msaa"], &[])?)
            } else {
                None
            },
            cull: ComputePass::new(device, &LIGHT_CULL_PASS, &[], &[])?,
        })
    }

    pub(crate) fn groups(
        &self,
        device: &wgpu::Device,
        targets: &Targets,
        b: &LightBuffers,
    ) -> Result<Groups> {
        Ok(Groups {
            tile_depth: self.tile_depth.bind_group(
                device,
                "tiles",
                &[
                    ("params", b.tile_params.as_entire_binding()),
                    (
                        "depth_texture",
                        wgpu::BindingResource::TextureView(&targets.depth_float_view),
                    ),
                    ("tile_depths", b.tile_depths.as_entire_binding()),
                ],
            )?,
            tile_depth_msaa: match (&self.tile_depth_msaa, &targets.msaa) {
                (Some(p), Some(t)) => Some(p.bind_group(
                    device,
                    "tiles",
                    &[
                        ("params", b.tile_params.as_entire_binding()),
                        (
                            "depth_texture",
                            wgpu::BindingResource::TextureView(&t.depth_view),
                        ),
                        ("tile_depths", b.tile_depths.as_entire_binding()),
                    ],
                )?),
                _ => None,
            },
            cull: self.cull.bind_group(
                device,
                "cull",
                &[
                    ("params", b.cull_params.as_entire_binding()),
                    ("tile_depths", b.tile_depths.as_entire_binding()),
                    ("lights", b.lights.as_entire_binding()),
                    ("counts", b.counts.as_entire_binding()),
                    ("indices", b.indices.as_entire_binding()),
                    ("counters", b.counters.as_entire_binding()),
                ],
            )?,
            counters: b.counters.clone(),
            tiles: b.tiles,
        })
    }

    /// Records pass 1 (unless `tile_depths_done`: the compute laydown's unpack reduced the
    /// frame's final depth already) and the culling pass (the counters cleared first).
    pub(crate) fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
        tile_depths_done: bool,
    ) {
        let g = &f.groups.lights;
        encoder.clear_buffer(&g.counters, 0, None);
        if !tile_depths_done {
            let mut pass = timer.begin_compute(encoder, "light tile depth");
            let size = [f.targets.width, f.targets.height];
            match (f.msaa, &self.tile_depth_msaa, &g.tile_depth_msaa) {
                (true, Some(p), Some(group)) => p.record(&mut pass, &[group], &size),
                _ => self.tile_depth.record(&mut pass, &[&g.tile_depth], &size),
            }
        }
        let mut pass = timer.begin_compute(encoder, "light culling");
        let dispatch = LightCullParams {
            tiles: g.tiles,
            ..LightCullParams::default()
        };
        self.cull.record(&mut pass, &[&g.cull], &dispatch);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::resources::lights::GpuTileDepthParams;
    use crate::shaders::LIBRARY;
    use shadercheck::{Caps, assert_struct_layout, members};

    #[test]
    fn description_matches_its_module() {
        shadercheck::check_pass(&TILE_DEPTH, |_| Caps::CORE);
        shadercheck::check_pass_with(&TILE_DEPTH_MSAA, &["msaa"], |_| Caps::CORE);
        let m = shadercheck::assert_composed(LIBRARY, TILE_DEPTH.module, &[], Caps::CORE);
        assert_struct_layout(
            &m,
            "GpuTileDepthParams",
            size_of::<GpuTileDepthParams>(),
            &members!(GpuTileDepthParams {
                size,
                tiles_x,
                reversed
            }),
        );
    }
}
