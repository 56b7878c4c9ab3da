//! The 32x32 tiles (`gpu::water_tiles`): ballot-aggregated water pixel counts per tile,
//! the tile list and the tessellated grid's indexed indirect arguments; the GPU twin of
//! `water::tiles::classify`.

use shader::pipeline::ComputePass;
use shader::{Binding, Entry, Kind, Pass, Sample};

use super::groups::WaterGroups;
use super::rows::{WATER, water_group};
use super::targets::WaterTargets;
use crate::error::Result;
use crate::shaders::LIBRARY;
use crate::timing::GpuTimer;

/// What the two entry points run over: the mini G-buffer's size and its tile count.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct TilesDispatch {
    pub size: [u32; 2],
    pub tiles: u32,
}

/// The pass: `count_tiles` over the buffer in 8x8 groups, `list_tiles` per tile.
pub(crate) const TILES: Pass<TilesDispatch> = Pass {
    name: "water tiles",
    module: "gpu::water_tiles",
    library: LIBRARY,
    features: &["subgroups"],
    groups: &[water_group(&[
        WATER,
        Binding::new("data", Kind::texture_2d(Sample::Uint)),
        Binding::new("counts", Kind::read_write(4)),
        Binding::new("tile_list", Kind::read_write(4)),
        Binding::new("args", Kind::read_write(4)),
    ])],
    entries: &[
        Entry::grid(
            "count_tiles",
            water::tiles::COUNT_GROUP_SIZE,
            water::tiles::COUNT_GROUP_SIZE,
            |d| d.size,
        ),
        Entry::items("list_tiles", 64, |d| d.tiles),
    ],
    zeroed: &["counts", "args"],
};

pub(crate) struct Tiles {
    pub pass: ComputePass<TilesDispatch>,
}

impl Tiles {
    /// With `subgroups`, the ballot is a subgroup one (one atomic per subgroup), else the
    /// workgroup fallback's (one per workgroup).
    pub(crate) fn new(device: &wgpu::Device, subgroups: bool) -> Result<Self> {
        let features: &[&str] = if subgroups { &["subgroups"] } else { &[] };
        Ok(Self {
            pass: ComputePass::new(device, &TILES, features, &[])?,
        })
    }

    pub(crate) fn record(
        &self,
        e: &mut wgpu::CommandEncoder,
        t: &WaterTargets,
        g: &WaterGroups,
        timer: &mut GpuTimer,
    ) {
        let mut pass = timer.begin_compute(e, "water tiles");
        self.pass.record(
            &mut pass,
            &[&g.tiles],
            &TilesDispatch {
                size: t.size,
                tiles: t.tile_count(),
            },
        );
    }
}

#[cfg(test)]
mod tests {
    use shadercheck::Caps;

    #[test]
    fn description_matches_its_module() {
        shadercheck::check_pass(&super::TILES, |f| {
            if f.contains(&"subgroups") {
                Caps::SUBGROUP
            } else {
                Caps::CORE
            }
        });
    }
}
