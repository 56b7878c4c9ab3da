//! The depth reductions two passes share, described once: the light tiles' depth ranges
//! (the local lights' tiles and the water's) and the HiZ pyramid from the depth target (the
//! static query's occlusion and the water's visibility).

use crate::shaders::LIBRARY;
use deferred::lights::{DeferredTileDepth, tile_counts};
use shader::pipeline::ComputePass;
use shader::{Binding, Dim, Entry, Group, Kind, Pass, Sample};
use staticscene::pass::{HizGrid, HizStep};

use crate::error::Result;
use crate::resources::buffers::buffer_init;

use crate::resources::lights::GpuTileDepthParams;

/// Pass 1's workgroups are TILE x TILE invocations: one per pixel of a tile.
const TILE: u32 = deferred::lights::TILE_SIZE;

/// Pass 1 over the depth target (`[width, height]`): one workgroup per 2x2 tiles.
pub(crate) const TILE_DEPTH: Pass<[u32; 2]> = Pass {
    name: "light tile depth",
    module: "gpu::tile_depth",
    library: LIBRARY,
    features: &[],
    groups: &[Group {
        name: "tiles",
        bindings: &[
            Binding::new("params", Kind::uniform(size_of::<GpuTileDepthParams>())),
            // Targets::depth_float (the multisampled variant binds the depth itself).
            Binding::new(
                "depth_texture",
                Kind::texture_2d(Sample::Float { filterable: false }),
            ),
            Binding::new(
                "tile_depths",
                Kind::read_write(size_of::<DeferredTileDepth>()),
            ),
        ],
    }],
    // One workgroup of TILE_SIZE² invocations per 2x2 tiles, an invocation a pixel of each.
    entries: &[Entry::grid("tile_depth", TILE, TILE, |size| {
        let (tx, ty) = tile_counts(size[0], size[1]);
        [tx.div_ceil(2) * TILE, ty.div_ceil(2) * TILE]
    })],
    zeroed: &[],
};

/// [`TILE_DEPTH`] over the baseline's multisampled depth (feature `msaa`): each tile's
/// range covers every sample.
pub(crate) const TILE_DEPTH_MSAA: Pass<[u32; 2]> = Pass {
    groups: &[Group {
        name: "tiles",
        bindings: &[
            TILE_DEPTH.groups[0].bindings[0],
            Binding::new(
                "depth_texture",
                Kind::Texture {
                    sample: Sample::Depth,
                    dim: Dim::D2Multisampled,
                },
            ),
            TILE_DEPTH.groups[0].bindings[2],
        ],
    }],
    features: &["msaa"],
    ..TILE_DEPTH
};

/// Levels one `gpu::hiz_depth` dispatch reduces (a 16x16 block of its source level per
/// workgroup).
pub(crate) const HIZ_LEVELS_PER_DISPATCH: usize = 4;

/// The HiZ pyramid from the depth target (`gpu::hiz_depth`), four levels per dispatch:
/// from the depth target (which it also copies into level 0) or, with feature
/// `from_buffer`, from level `step.level`. The grid is one invocation per 2x2 source texels
/// (the size of the first level written).
pub(crate) const HIZ_DEPTH: Pass<HizGrid> = Pass {
    name: "hiz from depth",
    module: "gpu::hiz_depth",
    library: LIBRARY,
    features: &["from_buffer"],
    groups: &[Group {
        name: "depth",
        bindings: &[
            Binding::new("step", Kind::uniform(size_of::<HizStep>())),
            Binding::new("depth", Kind::texture_2d(Sample::Depth)),
            Binding::new("hiz", Kind::read_write(4)),
        ],
    }],
    entries: &[Entry::grid("reduce_hiz", 8, 8, |g| [g.width, g.height])],
    zeroed: &[],
};

/// Per dispatch of a HiZ pyramid over a depth target whose `staticscene` header is `header`:
/// its `HizStep` uniform (source levels 0, the depth target, then 4, 8, ... while a
/// coarser level is left to write) and the grid of its source's quads.
pub(crate) fn hiz_steps(
    device: &wgpu::Device,
    header: &[u32],
    reversed: bool,
    label: &str,
) -> Vec<(wgpu::Buffer, HizGrid)> {
    let levels = header[0] as usize;
    (0..levels.max(2) - 1)
        .step_by(HIZ_LEVELS_PER_DISPATCH)
        .map(|level| {
            let step = HizStep {
                level: level as u32,
                reversed: u32::from(reversed),
                pad: [0; 2],
            };
            let grid = HizGrid {
                width: header[4 + 4 * level].div_ceil(2),
                height: header[5 + 4 * level].div_ceil(2),
            };
            let uniform = buffer_init(
                device,
                label,
                bytemuck::bytes_of(&step),
                size_of::<HizStep>() as u64,
                wgpu::BufferUsages::UNIFORM,
            );
            (uniform, grid)
        })
        .collect()
}

/// [`HIZ_DEPTH`]'s two pipelines: the first step from the depth target, the rest from the
/// buffer's finer level.
pub(crate) struct HizPasses {
    from_depth: ComputePass<HizGrid>,
    from_buffer: ComputePass<HizGrid>,
}

impl HizPasses {
    pub(crate) fn new(device: &wgpu::Device) -> Result<Self> {
        Ok(Self {
            from_depth: ComputePass::new(device, &HIZ_DEPTH, &[], &[])?,
            from_buffer: ComputePass::new(device, &HIZ_DEPTH, &["from_buffer"], &[])?,
        })
    }

    /// Each of `steps`' group over `depth` and the pyramid buffer `hiz`.
    pub(crate) fn groups(
        &self,
        device: &wgpu::Device,
        steps: &[(wgpu::Buffer, HizGrid)],
        depth: &wgpu::TextureView,
        hiz: &wgpu::Buffer,
    ) -> Result<Vec<(wgpu::BindGroup, HizGrid)>> {
        steps
            .iter()
            .enumerate()
            .map(|(i, (step, grid))| {
                let group = self.pass(i).bind_group(
                    device,
                    "depth",
                    &[
                        ("step", step.as_entire_binding()),
                        ("depth", wgpu::BindingResource::TextureView(depth)),
                        ("hiz", hiz.as_entire_binding()),
                    ],
                )?;
                Ok((group, *grid))
            })
            .collect()
    }

    /// Records the pyramid's dispatches with `groups` (from [`HizPasses::groups`]).
    pub(crate) fn record(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        groups: &[(wgpu::BindGroup, HizGrid)],
    ) {
        for (i, (group, grid)) in groups.iter().enumerate() {
            self.pass(i).record(pass, &[group], grid);
        }
    }

    fn pass(&self, step: usize) -> &ComputePass<HizGrid> {
        if step == 0 {
            &self.from_depth
        } else {
            &self.from_buffer
        }
    }
}
