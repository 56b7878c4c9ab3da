//! Water visibility (`gpu::water_visibility`): near bodies per body and the far sectors'
//! GPU quadtree, both tested against the HiZ of this frame's opaque depth, which this
//! module also builds (`gpu::hiz_depth` into staticscene's layout, as the static query
//! does for its own).

use shader::pipeline::ComputePass;
use shader::{Binding, Entry, Group, Kind, Pass};
use staticscene::pass::{HizGrid, HizStep, hiz_header};

use super::super::LIBRARY;
use super::super::query::{HIZ_DEPTH, HIZ_LEVELS_PER_DISPATCH};
use super::{GpuWaterBody, GpuWaterFrame, WaterData, WaterGroups};
use crate::error::Result;
use crate::resources::rows::FrameUniforms;
use crate::timing::GpuTimer;

/// The near pass's dispatch: one invocation per body.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct VisibilityDispatch {
    pub bodies: u32,
}

/// The visibility pass: `near_bodies` over the bodies, `far_sectors` one workgroup.
pub(crate) const VISIBILITY: Pass<VisibilityDispatch> = Pass {
    name: "water visibility",
    module: "gpu::water_visibility",
    library: LIBRARY,
    features: &[],
    groups: &[Group {
        name: "water",
        bindings: &[
            Binding::new("frame", Kind::uniform(size_of::<FrameUniforms>())),
            Binding::new("water", Kind::uniform(size_of::<GpuWaterFrame>())),
            Binding::new("bodies", Kind::read(size_of::<GpuWaterBody>())),
            Binding::new("near_args", Kind::read_write(4)),
            Binding::new("nodes", Kind::read(32)),
            Binding::new("lists", Kind::read_write(4)),
            Binding::new("far_list", Kind::read_write(4)),
            Binding::new("far_args", Kind::read_write(4)),
            Binding::new("hiz", Kind::read(4)),
            Binding::new("stats", Kind::read_write(4)),
        ],
    }],
    entries: &[
        Entry::items("near_bodies", 64, |d| d.bodies),
        Entry::once("far_sectors", 256),
    ],
    zeroed: &["far_args", "stats"],
};

/// The pipelines: visibility, and the HiZ from the depth target and from its own levels.
pub(crate) struct Visibility {
    pub pass: ComputePass<VisibilityDispatch>,
    hiz: ComputePass<HizGrid>,
    hiz_from_buffer: ComputePass<HizGrid>,
}

/// The water's HiZ of the opaque depth: the buffer in staticscene's layout and one step
/// uniform per `gpu::hiz_depth` dispatch.
pub(crate) struct WaterHiz {
    pub buffer: wgpu::Buffer,
    steps: Vec<(wgpu::Buffer, HizGrid)>,
}

impl WaterHiz {
    /// The HiZ of a `width` x `height` depth target (reversed depth).
    pub(crate) fn new(device: &wgpu::Device, [width, height]: [u32; 2]) -> Result<Self> {
        let (header, len) = hiz_header(width, height)?;
        let buffer = crate::resources::buffer_init(
            device,
            "water hiz",
            bytemuck::cast_slice(&header),
            len as u64 * 4,
            wgpu::BufferUsages::STORAGE,
        );
        let levels = header[0] as usize;
        let steps = (0..levels.max(2) - 1)
            .step_by(HIZ_LEVELS_PER_DISPATCH)
            .map(|level| {
                let step = HizStep {
                    level: level as u32,
                    reversed: 1,
                    pad: [0; 2],
                };
                let grid = HizGrid {
                    width: header[4 + 4 * level].div_ceil(2),
                    height: header[5 + 4 * level].div_ceil(2),
                };
                let b = crate::resources::buffer_init(
                    device,
                    "water hiz step",
                    bytemuck::bytes_of(&step),
                    size_of::<HizStep>() as u64,
                    wgpu::BufferUsages::UNIFORM,
                );
                (b, grid)
            })
            .collect();
        Ok(Self { buffer, steps })
    }

    /// Each step's group over `depth`: (from the depth target, group, grid).
    pub(crate) fn groups(
        &self,
        device: &wgpu::Device,
        v: &Visibility,
        depth: &wgpu::TextureView,
    ) -> Result<Vec<(bool, wgpu::BindGroup, HizGrid)>> {
        self.steps
            .iter()
            .enumerate()
            .map(|(i, (step, grid))| {
                let pass = if i == 0 { &v.hiz } else { &v.hiz_from_buffer };
                let group = pass.bind_group(
                    device,
                    "depth",
                    &[
                        ("step", step.as_entire_binding()),
                        ("depth", wgpu::BindingResource::TextureView(depth)),
                        ("hiz", self.buffer.as_entire_binding()),
                    ],
                )?;
                Ok((i == 0, group, *grid))
            })
            .collect()
    }
}

impl Visibility {
    pub(crate) fn new(device: &wgpu::Device) -> Result<Self> {
        Ok(Self {
            pass: ComputePass::new(device, &VISIBILITY, &[], &[])?,
            hiz: ComputePass::new(device, &HIZ_DEPTH, &[], &[])?,
            hiz_from_buffer: ComputePass::new(device, &HIZ_DEPTH, &["from_buffer"], &[])?,
        })
    }

    /// Records the HiZ steps into `pass`.
    pub(crate) fn record_hiz(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        groups: &[(bool, wgpu::BindGroup, HizGrid)],
    ) {
        for (first, group, grid) in groups {
            let p = if *first {
                &self.hiz
            } else {
                &self.hiz_from_buffer
            };
            p.record(pass, &[group], grid);
        }
    }

    /// Records the near and far visibility.
    pub(crate) fn record(
        &self,
        e: &mut wgpu::CommandEncoder,
        g: &WaterGroups,
        d: &WaterData,
        timer: &mut GpuTimer,
    ) {
        let mut pass = timer.begin_compute(e, "water visibility");
        self.pass.record(
            &mut pass,
            &[&g.visibility],
            &VisibilityDispatch {
                bodies: d.body_count,
            },
        );
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn description_matches_its_module() {
        shadercheck::check_pass(&super::VISIBILITY, |_| shadercheck::Caps::CORE);
        let m = shadercheck::assert_composed(
            super::LIBRARY,
            "gpu::water_visibility",
            &[],
            shadercheck::Caps::CORE,
        );
        let u = |n: &str| shadercheck::const_u32(&m, n);
        assert_eq!(
            u("GPU_WATER_STAT_NEAR"),
            Some(super::super::STAT_NEAR as u32)
        );
        assert_eq!(u("GPU_WATER_STAT_FAR"), Some(super::super::STAT_FAR as u32));
        assert_eq!(
            u("GPU_WATER_STAT_NODES"),
            Some(super::super::STAT_NODES as u32)
        );
        assert_eq!(
            u("MAX_WORKGROUPS_X_ITEMS"),
            Some(shader::MAX_WORKGROUPS_X * 64)
        );
    }
}
