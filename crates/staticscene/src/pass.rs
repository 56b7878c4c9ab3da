//! The query as a GPU compute pass: its description ([`QUERY_PASS`], WGSL
//! `staticscene::query_pass`), the records it reads from pooled buffers, and the CPU job
//! that plans it ([`Scene::plan_gpu`]).
//!
//! Every active tile's records live in a few pooled buffers owned by the renderer: its
//! QueryInstances at `instance_base` of `instances`, its objects, setups, matrices and
//! LOD bounds as one block of words ([`tile_records`]) at `records`, its LOD fade bytes
//! and one live word per cluster in `state` ([`tile_state_words`]). Where each tile sits
//! is the renderer's choice ([`TileSlots`]); each [`GpuJob`] carries its tile's bases and
//! counts, and the pass checks every index a record holds against them, so a corrupt
//! record drops its instance (counted as invalid) and never reads another tile's data.
//!
//! The jobs are those of [`Scene::query`] (the same pre-cull, tile and cluster order); the
//! pass runs one workgroup of [`QUERY_WORKGROUP`] invocations per wave of a job, which is
//! [`query_cluster`](crate::query_cluster) with [`WaveWidth::W64`](wave::WaveWidth::W64)
//! lane for lane: the same tests, fade states and batches (batches never span waves).
//! Only the order in which jobs append differs (GPU scheduling), so results compare after
//! a canonical sort.
//!
//! Cluster liveness stays on the GPU: a cluster the pre-cull rejects by LOD in a fading
//! view still runs while some instance fades out. The CPU cannot know that without a
//! read-back, so it dispatches such a cluster flagged [`JOB_FLAG_LOD_UNLESS_LIVE`]; its
//! live word holds the serial of the last query in which some instance of it ended with a
//! fade state above zero, and the job carries the serial of the cluster's last run, so
//! the pass skips the job (one load per workgroup) unless they are equal.

use alloc::vec::Vec;

use bytemuck::{Pod, Zeroable};
use shader::{Binding, Entry, Group, Kind, Pass};

use crate::query::Consts;
use crate::{
    HiZ, QueryOptions, QueryParams, QueryStats, Scene, StaticTile, TileId,
    output::{DrawableSetupBatch, DrawableSetupInstance},
};

/// Invocations per workgroup: one wave of HZD's 64 lanes.
pub const QUERY_WORKGROUP: u32 = 64;
/// Job flag: the cluster was outside the frustum since it last ran; its fade states start
/// from the snapped value.
pub const JOB_FLAG_SNAP_FADE: u32 = 1;
/// Job flag: the pre-cull rejected the cluster by LOD; run only while it is live.
pub const JOB_FLAG_LOD_UNLESS_LIVE: u32 = 2;
/// Words per [`QueryObject`](crate::QueryObject) in a tile's record block.
pub const OBJECT_WORDS: usize = 16;
/// Words per [`QuerySetup`](crate::QuerySetup).
pub const SETUP_WORDS: usize = 8;
/// Words per [`Transform4x3`](crate::Transform4x3).
pub const TRANSFORM_WORDS: usize = 12;
/// Words per [`HalfAabb`](crate::HalfAabb).
pub const BOUNDS_WORDS: usize = 3;
/// Levels the HiZ buffer's header describes (a 16384-texel side has 15).
pub const HIZ_MAX_LEVELS: usize = 16;
/// Words of the HiZ buffer's header: the level count, three spare words, then
/// `(width, height, first texel word, 0)` per level.
pub const HIZ_HEADER_WORDS: usize = 4 + 4 * HIZ_MAX_LEVELS;

/// Statistics slot: invocations that had an instance (threads run).
pub const STAT_THREADS: usize = 0;
/// Statistics slot: ended by the filter.
pub const STAT_FILTER: usize = 1;
/// Statistics slot: ended by the LOD tests.
pub const STAT_LOD: usize = 2;
/// Statistics slot: ended by the frustum test.
pub const STAT_FRUSTUM: usize = 3;
/// Statistics slot: ended by the screen-size test.
pub const STAT_SIZE: usize = 4;
/// Statistics slot: ended by the occlusion test.
pub const STAT_OCCLUSION: usize = 5;
/// Statistics slot: faded out.
pub const STAT_FADED_OUT: usize = 6;
/// Statistics slot: an index outside its tile.
pub const STAT_INVALID: usize = 7;
/// Statistics slot: visible (unused: the instance counter counts them).
pub const STAT_VISIBLE: usize = 8;
/// Statistics slot: instances and headers past the end of their output buffers.
pub const STAT_DROPPED: usize = 9;
/// Statistics slot: visible in a second pass, drawn by the first already.
pub const STAT_DRAWN_EARLY: usize = 10;
/// Statistics slots.
pub const STAT_COUNT: usize = 11;

/// One cluster job as the pass reads it (WGSL `StaticsceneGpuJob`), 64 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct GpuJob {
    /// The tile's id (written into each output instance's state).
    pub tile: u32,
    /// First instance, tile-relative.
    pub first: u32,
    /// Instances.
    pub count: u32,
    /// `JOB_FLAG_*`.
    pub flags: u32,
    /// Index of the tile's instance 0 in the pooled `instances` buffer.
    pub instance_base: u32,
    /// Word offset of the tile's record block in `records`.
    pub records: u32,
    /// Objects in the tile.
    pub objects: u32,
    /// Setups in the tile.
    pub setups: u32,
    /// Matrices in the tile.
    pub transforms: u32,
    /// LOD bounds in the tile.
    pub bounds: u32,
    /// This job's first wave (the prefix sum of the jobs' waves).
    pub first_wave: u32,
    /// Word index of the cluster's live serial in `state`.
    pub cluster: u32,
    /// The serial of the cluster's last run (`u32::MAX`: never).
    pub last_run: u32,
    /// This query's serial.
    pub serial: u32,
    /// Byte index of the tile's first fade state in `state`.
    pub fade_base: u32,
    /// Zero.
    pub pad: u32,
}

const _: () = assert!(size_of::<GpuJob>() == 64);

/// The pass's counters (WGSL `StaticsceneQueryCounters`), 60 bytes, zeroed before each
/// dispatch.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct QueryCounters {
    /// Instances appended (visible), including those dropped past the buffer's end.
    pub instances: u32,
    /// Batch headers appended, including dropped ones.
    pub batches: u32,
    /// Zero.
    pub pad0: u32,
    /// Zero.
    pub pad1: u32,
    /// `STAT_*` slots.
    pub stats: [u32; STAT_COUNT],
}

const _: () = assert!(size_of::<QueryCounters>() == 60);

impl QueryCounters {
    /// The counters as [`QueryStats`], with the pre-cull's part from `precull`.
    #[must_use]
    pub fn stats(&self, precull: &QueryStats) -> QueryStats {
        let s = |i: usize| u64::from(self.stats[i]);
        QueryStats {
            instances: s(STAT_THREADS),
            rejected_filter: s(STAT_FILTER),
            rejected_lod: s(STAT_LOD),
            rejected_frustum: s(STAT_FRUSTUM),
            rejected_size: s(STAT_SIZE),
            rejected_occlusion: s(STAT_OCCLUSION),
            faded_out: s(STAT_FADED_OUT),
            drawn_early: s(STAT_DRAWN_EARLY),
            invalid: s(STAT_INVALID),
            visible: u64::from(self.instances),
            batches: u64::from(self.batches),
            dropped: s(STAT_DROPPED),
            ..*precull
        }
    }
}

/// Where one tile's data sits in the pooled buffers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct TileSlots {
    /// Index of the tile's instance 0 in `instances` (16-byte elements).
    pub instance_base: u32,
    /// Word offset of the tile's [`tile_records`] block in `records`.
    pub records: u32,
    /// Word offset of the tile's [`tile_state_words`] block in `state`.
    pub state: u32,
}

impl TileSlots {
    /// Byte index of the tile's first fade state in `state`.
    #[must_use]
    pub fn fade_base(&self) -> u32 {
        self.state * 4
    }

    /// Word index of the live serial of cluster `cluster` of `tile`.
    #[must_use]
    pub fn cluster_word(&self, tile: &StaticTile, cluster: usize) -> u32 {
        self.state + tile.instances().len().div_ceil(4) as u32 + cluster as u32
    }
}

/// Words of a tile's record block: objects, setups, matrices, LOD bounds.
#[must_use]
pub fn tile_record_words(tile: &StaticTile) -> usize {
    tile.objects().len() * OBJECT_WORDS
        + tile.setups().len() * SETUP_WORDS
        + tile.transforms().len() * TRANSFORM_WORDS
        + tile.bounds().len() * BOUNDS_WORDS
}

/// A tile's record block as the pass reads it: objects, then setups, then matrices, then
/// LOD bounds, each record's bytes as little-endian words.
#[must_use]
pub fn tile_records(tile: &StaticTile) -> Vec<u32> {
    let mut words = Vec::with_capacity(tile_record_words(tile));
    words.extend_from_slice(bytemuck::cast_slice(tile.objects()));
    words.extend_from_slice(bytemuck::cast_slice(tile.setups()));
    words.extend_from_slice(bytemuck::cast_slice(tile.transforms()));
    for b in tile.bounds() {
        words.extend_from_slice(bytemuck::cast_slice(core::slice::from_ref(b)));
    }
    words
}

/// Words of a tile's state block, zeroed on upload: one fade byte per instance (four per
/// word), then one live word per cluster.
#[must_use]
pub fn tile_state_words(tile: &StaticTile) -> usize {
    tile.instances().len().div_ceil(4) + tile.clusters().len()
}

/// The HiZ buffer the pass reads: the [`hiz_header`] of its size, then every level's
/// texels as f32 bits. `None` (no occlusion): a header with zero levels. Fails on a
/// pyramid side above [`MAX_VIEWPORT`](crate::MAX_VIEWPORT).
pub fn hiz_words(hiz: Option<&HiZ>) -> Result<Vec<u32>, crate::Error> {
    let Some(z) = hiz else {
        return Ok(alloc::vec![0u32; HIZ_HEADER_WORDS]);
    };
    let (w, h) = z.size();
    let (mut words, len) = hiz_header(w, h)?;
    // `HiZ::build` and `hiz_header` halve the same way: the texels fill the layout.
    words.extend(z.texels().iter().map(|t| t.to_bits()));
    debug_assert_eq!(words.len(), len);
    Ok(words)
}

/// The HiZ buffer's header for a `width x height` level 0 (the levels of
/// [`HiZ::build`]: ceil-halved down to 1x1, texels packed level after level after the
/// header), and the buffer's length in words. Fails on a zero side or one above
/// [`MAX_VIEWPORT`](crate::MAX_VIEWPORT).
pub fn hiz_header(width: u32, height: u32) -> Result<(Vec<u32>, usize), crate::Error> {
    if width == 0 || height == 0 || width > crate::MAX_VIEWPORT || height > crate::MAX_VIEWPORT {
        return Err(crate::Error::Viewport { width, height });
    }
    let mut words = alloc::vec![0u32; HIZ_HEADER_WORDS];
    let (mut w, mut h, mut at, mut n) = (width, height, HIZ_HEADER_WORDS, 0);
    loop {
        words[4 + 4 * n] = w;
        words[5 + 4 * n] = h;
        words[6 + 4 * n] = at as u32;
        at += (w * h) as usize;
        n += 1;
        if w == 1 && h == 1 {
            break;
        }
        (w, h) = (w.div_ceil(2), h.div_ceil(2));
    }
    words[0] = n as u32;
    Ok((words, at))
}

/// The HiZ pass's uniform (WGSL `StaticsceneHizStep`): the source level of one dispatch.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct HizStep {
    /// The level read (the dispatch writes `level + 1`).
    pub level: u32,
    /// Non-zero for reversed depth (levels keep the minimum).
    pub reversed: u32,
    /// Zero.
    pub pad: [u32; 2],
}

/// The size of the level one HiZ dispatch writes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct HizGrid {
    /// Texels across.
    pub width: u32,
    /// Texels down.
    pub height: u32,
}

/// The HiZ pyramid's reduction: one bind group `hiz` (the [`HizStep`] uniform and the
/// [`hiz_header`]-laid-out buffer, level 0 filled by the caller) and one entry point
/// `hiz_reduce`, dispatched once per level over that level's texels, finest first. Equal
/// to [`HiZ::build`] texel for texel (min and max are exact).
pub const HIZ_PASS: Pass<HizGrid> = Pass {
    name: "staticscene hiz",
    module: "staticscene::hiz_pass",
    library: crate::wgsl::LIBRARY,
    features: &[],
    groups: &[Group {
        name: "hiz",
        bindings: &[
            Binding::new("step", Kind::uniform(size_of::<HizStep>())),
            Binding::new("hiz", Kind::read_write(4)),
        ],
    }],
    entries: &[Entry::grid("hiz_reduce", 8, 8, |g| [g.width, g.height])],
    zeroed: &[],
};

/// The pass's dispatch size.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct QueryDispatch {
    /// Waves (workgroups) of all jobs.
    pub waves: u32,
}

/// A planned GPU query: the jobs and what the pre-cull did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GpuPlan {
    /// The jobs, in tile and cluster order.
    pub jobs: Vec<GpuJob>,
    /// Waves of all jobs.
    pub waves: u32,
    /// This query's serial.
    pub serial: u32,
    /// The pre-cull's statistics (tiles, clusters, and culled counts; cluster jobs
    /// flagged [`JOB_FLAG_LOD_UNLESS_LIVE`] count as dispatched).
    pub stats: QueryStats,
    /// Active tiles skipped because `slots` gave them no place (not uploaded).
    pub skipped_tiles: Vec<TileId>,
}

impl GpuPlan {
    /// The `job_list` buffer: a 16-byte header (job count, waves, two zero words), then
    /// the jobs.
    #[must_use]
    pub fn job_list(&self) -> Vec<u32> {
        let mut words = Vec::with_capacity(4 + self.jobs.len() * 16);
        words.extend_from_slice(&[self.jobs.len() as u32, self.waves, 0, 0]);
        words.extend_from_slice(bytemuck::cast_slice(&self.jobs));
        words
    }

    /// The `wave_jobs` buffer: for each wave (workgroup) of the dispatch, the index of
    /// its job in [`GpuPlan::jobs`] (so a workgroup finds its job in one load, not a
    /// binary search over the jobs' first waves).
    #[must_use]
    pub fn wave_jobs(&self) -> Vec<u32> {
        let mut table = Vec::with_capacity(self.waves as usize);
        for (j, job) in self.jobs.iter().enumerate() {
            let waves = job.count.div_ceil(QUERY_WORKGROUP);
            table.extend(core::iter::repeat_n(j as u32, waves as usize));
        }
        table
    }

    /// The dispatch size.
    #[must_use]
    pub fn dispatch(&self) -> QueryDispatch {
        QueryDispatch { waves: self.waves }
    }

    /// Instances of all jobs (threads the pass may run).
    #[must_use]
    pub fn instances(&self) -> u64 {
        self.jobs.iter().map(|j| u64::from(j.count)).sum()
    }
}

impl Scene {
    /// The CPU job of the GPU query: the pre-cull of [`Scene::query`], its jobs laid out
    /// for [`QUERY_PASS`] with each tile's places from `slots` (tiles it returns `None`
    /// for are skipped and listed). Updates the clusters' stale flags and, for fading
    /// views, their last-run serials, as the CPU query would after running the jobs; the
    /// fade states and liveness themselves live on the GPU (this scene's CPU fade states
    /// are not touched: use one `Scene` per query kind, CPU or GPU).
    pub fn plan_gpu(
        &mut self,
        params: &QueryParams,
        options: &QueryOptions,
        slots: impl Fn(TileId) -> Option<TileSlots>,
    ) -> GpuPlan {
        let fade = Consts::new(params).fade;
        let mut plan = GpuPlan::default();
        if fade {
            self.gpu_serial = match self.gpu_serial.wrapping_add(1) {
                0 | u32::MAX => 1,
                s => s,
            };
        }
        plan.serial = self.gpu_serial;
        let planned = self.plan(params, options, fade, false, &mut plan.stats);
        let mut skipped = Vec::new();
        for pj in planned {
            let tile = &self.tiles()[pj.slot];
            let Some(s) = slots(tile.id()) else {
                if skipped.last() != Some(&tile.id()) {
                    skipped.push(tile.id());
                }
                continue;
            };
            let mut flags = 0;
            if pj.job.snap_fade {
                flags |= JOB_FLAG_SNAP_FADE;
            }
            if pj.unless_live {
                flags |= JOB_FLAG_LOD_UNLESS_LIVE;
            }
            let last_run = self.cluster_last_run(pj.slot, pj.cluster);
            plan.jobs.push(GpuJob {
                tile: tile.id().0,
                first: pj.job.first,
                count: pj.job.count,
                flags,
                instance_base: s.instance_base,
                records: s.records,
                objects: tile.objects().len() as u32,
                setups: tile.setups().len() as u32,
                transforms: tile.transforms().len() as u32,
                bounds: tile.bounds().len() as u32,
                first_wave: plan.waves,
                cluster: s.cluster_word(tile, pj.cluster),
                last_run,
                serial: plan.serial,
                fade_base: s.fade_base(),
                pad: 0,
            });
            plan.waves += pj.job.count.div_ceil(QUERY_WORKGROUP);
            if fade {
                self.ran_on_gpu(pj.slot, pj.cluster, plan.serial);
            }
        }
        plan.skipped_tiles = skipped;
        plan
    }
}

/// The job list's header and one job: the smallest `job_list` binding.
const JOB_LIST_MIN: usize = 16 + size_of::<GpuJob>();

/// The query pass: one bind group `query` (the view's [`QueryParams`], the job list and
/// its per-wave job table ([`GpuPlan::wave_jobs`]), the pooled records, the HiZ, the fade and live state, the counters and the two outputs)
/// and one entry point `query` of [`QUERY_WORKGROUP`] invocations per wave. Feature
/// `shadow_view` compiles the shadow variant: views with
/// [`QUERY_FLAG_SHADOW`](crate::QUERY_FLAG_SHADOW) only (fade, occlusion and the camera
/// state compiled out). Feature `subgroups` (wgpu `Features::SUBGROUP`) makes the batch
/// output per subgroup, as HZD's per hardware wave: batches never span a subgroup, so the
/// output equals the CPU twin's with the subgroup size as its
/// [`WaveWidth`](crate::WaveWidth) (subgroups tiling the workgroup in local-index order,
/// as drivers lay them out); without it, batches span the 64-invocation workgroup (W64).
pub const QUERY_PASS: Pass<QueryDispatch> = Pass {
    name: "staticscene query",
    module: "staticscene::query_pass",
    library: crate::wgsl::LIBRARY,
    features: &["shadow_view", "subgroups"],
    groups: &[Group {
        name: "query",
        bindings: &[
            Binding::new("params", Kind::uniform(size_of::<QueryParams>())),
            Binding::new("job_list", Kind::read(JOB_LIST_MIN)),
            Binding::new("wave_jobs", Kind::read(4)),
            Binding::new("instances", Kind::read(16)),
            Binding::new("records", Kind::read(4)),
            Binding::new("hiz", Kind::read(4)),
            Binding::new("state", Kind::read_write(4)),
            Binding::new("counters", Kind::read_write(size_of::<QueryCounters>())),
            Binding::new(
                "out_instances",
                Kind::read_write(size_of::<DrawableSetupInstance>()),
            ),
            Binding::new(
                "out_batches",
                Kind::read_write(size_of::<DrawableSetupBatch>()),
            ),
        ],
    }],
    entries: &[Entry::items("query", QUERY_WORKGROUP, |d| {
        d.waves.saturating_mul(QUERY_WORKGROUP)
    })],
    zeroed: &["counters"],
};

#[cfg(test)]
mod tests {
    use super::*;

    /// Each wave's entry is the last job whose first wave is at or below it (a linear
    /// search), for jobs of 1, 64, 65 and 200 instances.
    #[test]
    fn wave_jobs_name_each_waves_job() {
        let mut plan = GpuPlan::default();
        for count in [1, 64, 65, 200, 1] {
            plan.jobs.push(GpuJob {
                count,
                first_wave: plan.waves,
                ..GpuJob::default()
            });
            plan.waves += count.div_ceil(QUERY_WORKGROUP);
        }
        let table = plan.wave_jobs();
        assert_eq!(table.len(), plan.waves as usize);
        for (w, &j) in table.iter().enumerate() {
            let naive = plan
                .jobs
                .iter()
                .rposition(|job| job.first_wave <= w as u32)
                .unwrap();
            assert_eq!(j as usize, naive, "wave {w}");
        }
        assert_eq!(table, [0, 1, 2, 2, 3, 3, 3, 3, 4]);
    }

    /// A fixed vector: 5x3 halves to 3x2, 2x1, 1x1; texels follow the header level after
    /// level.
    #[test]
    fn hiz_header_lays_out_ceil_halved_levels() {
        let (h, len) = hiz_header(5, 3).unwrap();
        let t = HIZ_HEADER_WORDS as u32;
        assert_eq!(h[0], 4);
        assert_eq!(
            &h[4..20],
            &[
                5,
                3,
                t,
                0,
                3,
                2,
                t + 15,
                0,
                2,
                1,
                t + 21,
                0,
                1,
                1,
                t + 23,
                0
            ]
        );
        assert!(h[20..].iter().all(|&w| w == 0));
        assert_eq!(len, HIZ_HEADER_WORDS + 15 + 6 + 2 + 1);
        assert_eq!(hiz_header(1, 1).unwrap().0[..8], [1, 0, 0, 0, 1, 1, t, 0]);
        assert!(hiz_header(0, 4).is_err());
        assert!(hiz_header(crate::MAX_VIEWPORT + 1, 4).is_err());
        // The largest viewport fits the header's levels.
        let (h, _) = hiz_header(crate::MAX_VIEWPORT, 1).unwrap();
        assert!(h[0] as usize <= HIZ_MAX_LEVELS);
    }
}
