//! Water visibility (`gpu::water_visibility`): near bodies per body and the far sectors'
//! GPU quadtree, both tested against the HiZ of this frame's opaque depth, which this
//! module also builds (`gpu::hiz_depth` into staticscene's layout, as the static query
//! does for its own).

use shader::pipeline::ComputePass;
use shader::{Binding, Entry, Kind, Pass};
use staticscene::pass::HizGrid;

use super::data::{WaterData, WaterHiz};
use super::groups::WaterGroups;
use super::rows::GpuWaterBody;
use super::rows::{FRAME, WATER, water_group};
use crate::error::Result;
use crate::passes::depth_reductions::HizPasses;
use crate::shaders::LIBRARY;
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
    groups: &[water_group(&[
        FRAME,
        WATER,
        Binding::new("bodies", Kind::read(size_of::<GpuWaterBody>())),
        Binding::new("near_args", Kind::read_write(4)),
        Binding::new("nodes", Kind::read(32)),
        Binding::new("lists", Kind::read_write(4)),
        Binding::new("far_list", Kind::read_write(4)),
        Binding::new("far_args", Kind::read_write(4)),
        Binding::new("hiz", Kind::read(4)),
        Binding::new("stats", Kind::read_write(4)),
    ])],
    entries: &[
        Entry::items("near_bodies", 64, |d| d.bodies),
        Entry::once("far_sectors", 256),
    ],
    zeroed: &["far_args", "stats"],
};

/// The pipelines: visibility, and the HiZ from the depth target and from its own levels.
pub(crate) struct Visibility {
    pub pass: ComputePass<VisibilityDispatch>,
    hiz: HizPasses,
}

impl Visibility {
    pub(crate) fn new(device: &wgpu::Device) -> Result<Self> {
        Ok(Self {
            pass: ComputePass::new(device, &VISIBILITY, &[], &[])?,
            hiz: HizPasses::new(device)?,
        })
    }

    /// Records the HiZ steps into `pass`.
    pub(crate) fn record_hiz(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        groups: &[(wgpu::BindGroup, HizGrid)],
    ) {
        self.hiz.record(pass, groups);
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

    /// Each step of `hiz`'s group over `depth`: (from the depth target, group, grid).
    pub(crate) fn hiz_groups(
        &self,
        device: &wgpu::Device,
        hiz: &WaterHiz,
        depth: &wgpu::TextureView,
    ) -> Result<Vec<(wgpu::BindGroup, HizGrid)>> {
        self.hiz.groups(device, &hiz.steps, depth, &hiz.buffer)
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn description_matches_its_module() {
        shadercheck::check_pass(&super::VISIBILITY, |_| shadercheck::Caps::CORE);
        let m = shadercheck::assert_composed(
            crate::shaders::LIBRARY,
            "gpu::water_visibility",
            &[],
            shadercheck::Caps::CORE,
        );
        let u = |n: &str| shadercheck::const_u32(&m, n);
        assert_eq!(
            u("GPU_WATER_STAT_NEAR"),
            Some(super::super::rows::STAT_NEAR as u32)
        );
        assert_eq!(
            u("GPU_WATER_STAT_FAR"),
            Some(super::super::rows::STAT_FAR as u32)
        );
        assert_eq!(
            u("GPU_WATER_STAT_NODES"),
            Some(super::super::rows::STAT_NODES as u32)
        );
        assert_eq!(
            u("MAX_WORKGROUPS_X_ITEMS"),
            Some(shader::MAX_WORKGROUPS_X * 64)
        );
    }
}
