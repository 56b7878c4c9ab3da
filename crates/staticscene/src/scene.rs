//! The streaming side ([`TileStreamer`]: groups in, built tiles out, on any thread) and
//! the main-thread side ([`Scene`]: the active tiles, O(1) activation, the per-view query
//! with the CPU pre-cull of tiles and clusters).
//!
//! "On streaming thread: split adds into multiple StaticTiles if change is large, add
//! objects to orphan tile if change is small, remove whole tiles, generate spatial
//! partition, fill buffers. On main thread: just make ready tiles active."

use alloc::collections::BTreeMap;
use alloc::vec::Vec;

use glam::Vec3;
use wave::WaveWidth;

use crate::query::{Consts, run_job};
use crate::resource::{Aabb, ResourceLibrary};
use crate::tile::{
    BuildConfig, CullInfo, DynamicObject, PreparedGroup, StaticTile, StreamingGroup, TileId,
    anchor_offset, build_tiles, prepare_group,
};
use crate::view::{FRUSTUM_TOLERANCE, QueryParams, box_outside_frustum};
use crate::{ClusterJob, DrawableSetupBatch, Error, HiZ, OutputInstance, QueryStats};

/// A tile ready to activate: the immutable tile and its zeroed LOD fade states, all
/// allocated on the streaming thread.
#[derive(Clone, Debug, PartialEq)]
pub struct BuiltTile {
    tile: StaticTile,
    fade: FadeStates,
}

impl BuiltTile {
    /// Wraps a tile, allocating its fade states.
    #[must_use]
    pub fn new(tile: StaticTile) -> BuiltTile {
        let fade = FadeStates {
            instances: alloc::vec![0; tile.instances().len()],
            clusters: alloc::vec![0; tile.clusters().len()],
            last_run: alloc::vec![u32::MAX; tile.clusters().len()],
        };
        BuiltTile { tile, fade }
    }

    /// The tile.
    #[must_use]
    pub fn tile(&self) -> &StaticTile {
        &self.tile
    }
}

/// Per-tile state of the camera view: one byte per instance (fade state `0..=N` and
/// `CAMERA_STATE_VISIBLE`), one per
/// cluster (`CLUSTER_LIVE`, `CLUSTER_STALE`).
#[derive(Clone, Debug, Default, PartialEq)]
struct FadeStates {
    instances: Vec<u8>,
    clusters: Vec<u8>,
    /// The GPU query's serial of each cluster's last run (`u32::MAX`: never).
    last_run: Vec<u32>,
}

/// One tile's fade states, borrowed: per instance, per cluster.
#[cfg(feature = "parallel")]
pub(crate) type FadeParts<'a> = (&'a mut [u8], &'a mut [u8]);

/// Cluster state: some instance's fade state is above zero.
const CLUSTER_LIVE: u8 = 1;
/// Cluster state: skipped by the frustum pre-cull since it last ran.
const CLUSTER_STALE: u8 = 2;

/// What the main thread applies: tiles to activate and to remove, objects for the dynamic
/// system.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TileUpdate {
    /// Tiles to activate.
    pub add: Vec<BuiltTile>,
    /// Tiles to deactivate.
    pub remove: Vec<TileId>,
    /// Objects of the added group that did not fit the static scene (on removal of a
    /// group, the dynamic system removes that group's objects itself).
    pub dynamic: Vec<DynamicObject>,
}

#[derive(Clone, Debug, PartialEq)]
enum Loaded {
    Tiles(Vec<TileId>),
    Orphan,
}

/// The streaming thread's side: turns streaming groups into built tiles. `Send`: build
/// on any thread, hand the [`TileUpdate`]s to the main thread.
///
/// A group of at least [`BuildConfig::orphan_below`] instances becomes its own tiles
/// (split above [`BuildConfig::split_above`]); smaller groups share the orphan tiles,
/// which are rebuilt whenever an orphan group comes or goes (tiles are immutable). Adds
/// and removes match by group id.
#[derive(Clone, Debug)]
pub struct TileStreamer {
    lib: ResourceLibrary,
    config: BuildConfig,
    next_id: u32,
    loaded: BTreeMap<u64, Loaded>,
    orphans: BTreeMap<u64, PreparedGroup>,
    orphan_tiles: Vec<TileId>,
}

impl TileStreamer {
    /// A streamer placing resources of `lib`.
    #[must_use]
    pub fn new(lib: ResourceLibrary, config: BuildConfig) -> TileStreamer {
        TileStreamer {
            lib,
            config,
            next_id: 0,
            loaded: BTreeMap::new(),
            orphans: BTreeMap::new(),
            orphan_tiles: Vec::new(),
        }
    }

    /// The resource library.
    #[must_use]
    pub fn library(&self) -> &ResourceLibrary {
        &self.lib
    }

    /// The orphan tiles currently built.
    #[must_use]
    pub fn orphan_tiles(&self) -> &[TileId] {
        &self.orphan_tiles
    }

    /// Builds a group's tiles (or rebuilds the orphan tiles with it). Fails on a group id
    /// already loaded or an unknown resource; nothing changes then.
    pub fn add_group(&mut self, group: &StreamingGroup) -> Result<TileUpdate, Error> {
        if self.loaded.contains_key(&group.id) {
            return Err(Error::DuplicateGroup { group: group.id });
        }
        let prepared = prepare_group(group, &self.lib)?;
        let dynamic = prepared.dynamic.clone();
        if prepared.instances < self.config.orphan_below {
            self.orphans.insert(group.id, prepared);
            let mut update = match self.rebuild_orphans() {
                Ok(u) => u,
                Err(e) => {
                    self.orphans.remove(&group.id);
                    return Err(e);
                }
            };
            self.loaded.insert(group.id, Loaded::Orphan);
            update.dynamic = dynamic;
            return Ok(update);
        }
        let objects: Vec<_> = prepared.objects.iter().collect();
        let mut id = self.next_id;
        let tiles = build_tiles(&objects, &self.lib, &self.config, &mut id)?;
        self.next_id = id;
        self.loaded.insert(
            group.id,
            Loaded::Tiles(tiles.iter().map(StaticTile::id).collect()),
        );
        Ok(TileUpdate {
            add: tiles.into_iter().map(BuiltTile::new).collect(),
            remove: Vec::new(),
            dynamic,
        })
    }

    /// Removes a group: its tiles, or its share of the orphan tiles (rebuilt without it).
    pub fn remove_group(&mut self, id: u64) -> Result<TileUpdate, Error> {
        match self.loaded.remove(&id) {
            None => Err(Error::UnknownGroup { group: id }),
            Some(Loaded::Tiles(tiles)) => Ok(TileUpdate {
                add: Vec::new(),
                remove: tiles,
                dynamic: Vec::new(),
            }),
            Some(Loaded::Orphan) => {
                let g = self.orphans.remove(&id);
                match self.rebuild_orphans() {
                    Ok(u) => Ok(u),
                    Err(e) => {
                        if let Some(g) = g {
                            self.orphans.insert(id, g);
                        }
                        self.loaded.insert(id, Loaded::Orphan);
                        Err(e)
                    }
                }
            }
        }
    }

    fn rebuild_orphans(&mut self) -> Result<TileUpdate, Error> {
        let objects: Vec<_> = self
            .orphans
            .values()
            .flat_map(|g| g.objects.iter())
            .collect();
        let mut id = self.next_id;
        let tiles = build_tiles(&objects, &self.lib, &self.config, &mut id)?;
        self.next_id = id;
        let remove = core::mem::replace(
            &mut self.orphan_tiles,
            tiles.iter().map(StaticTile::id).collect(),
        );
        Ok(TileUpdate {
            add: tiles.into_iter().map(BuiltTile::new).collect(),
            remove,
            dynamic: Vec::new(),
        })
    }
}

/// Query settings that are not view constants.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct QueryOptions {
    /// Lanes per wave (HZD: 64; the H100: 32). The longest batch is one wave.
    pub wave_width: WaveWidth,
    /// Run the CPU pre-cull of tiles and clusters (off: every cluster is a job).
    pub precull: bool,
}

impl Default for QueryOptions {
    fn default() -> Self {
        QueryOptions {
            wave_width: WaveWidth::W64,
            precull: true,
        }
    }
}

/// A query's output buffers, reused across frames.
#[derive(Clone, Debug, Default)]
pub struct QueryOutput<I> {
    /// Visible instances, batch by batch.
    pub instances: Vec<I>,
    /// Batch headers.
    pub batches: Vec<DrawableSetupBatch>,
    /// What happened.
    pub stats: QueryStats,
    scratch: Vec<I>,
    scratch_batches: Vec<DrawableSetupBatch>,
}

impl<I> QueryOutput<I> {
    /// Empty buffers.
    #[must_use]
    pub fn new() -> QueryOutput<I> {
        QueryOutput {
            instances: Vec::new(),
            batches: Vec::new(),
            stats: QueryStats::default(),
            scratch: Vec::new(),
            scratch_batches: Vec::new(),
        }
    }
}

/// The active static tiles (main thread).
#[derive(Clone, Debug, Default)]
pub struct Scene {
    tiles: Vec<StaticTile>,
    fades: Vec<FadeStates>,
    /// The serial of the last fading GPU query planned.
    pub(crate) gpu_serial: u32,
}

/// A job planned by the pre-cull: tile slot, cluster index, and its dispatch.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PlannedJob {
    pub(crate) slot: usize,
    pub(crate) cluster: usize,
    pub(crate) job: ClusterJob,
    /// Rejected by the LOD pre-cull in a fading view: runs only while the cluster is live.
    pub(crate) unless_live: bool,
}

/// Pre-cull constants of one view.
struct PreCull {
    planes: [[f32; 4]; 6],
    lod_point: Vec3,
    lod_scale: f32,
    filter: u8,
}

enum Verdict {
    Pass,
    Filter,
    Frustum,
    Lod,
}

/// Relative and absolute margins that keep the pre-cull conservative against the
/// per-instance tests (their boxes and distances are rounded on another path).
const PRECULL_REL: f32 = 1e-4;
const PRECULL_ABS: f32 = 1e-3;

fn dist_range(p: Vec3, b: &Aabb) -> (f32, f32) {
    let near = (b.min - p).max(p - b.max).max(Vec3::ZERO).length();
    let far = (b.min - p).abs().max((b.max - p).abs()).length();
    (near, far)
}

fn precull(info: &CullInfo, offset: Vec3, pc: &PreCull) -> Verdict {
    if info.filter & pc.filter == 0 {
        return Verdict::Filter;
    }
    let min = info.bounds.min + offset;
    let max = info.bounds.max + offset;
    let m = (min.abs().max(max.abs())) * FRUSTUM_TOLERANCE * 10.0 + Vec3::splat(PRECULL_ABS);
    if box_outside_frustum(&pc.planes, min - m, max + m) {
        return Verdict::Frustum;
    }
    let lb = Aabb::new(info.lod_bounds.min + offset, info.lod_bounds.max + offset);
    let (near, far) = dist_range(pc.lod_point, &lb);
    let near = near * (1.0 - PRECULL_REL) - PRECULL_ABS;
    let far = far * (1.0 + PRECULL_REL) + PRECULL_ABS;
    let rejected = |k: usize, g: f32| {
        let l = &info.lod[k];
        l.count == 0 || near >= l.near * g || far < l.far * g
    };
    if rejected(0, pc.lod_scale) && rejected(1, 1.0) {
        return Verdict::Lod;
    }
    Verdict::Pass
}

impl Scene {
    /// An empty scene.
    #[must_use]
    pub fn new() -> Scene {
        Scene::default()
    }

    /// Makes a built tile active: O(1) (a push; everything was allocated on the streaming
    /// thread).
    pub fn activate(&mut self, built: BuiltTile) {
        self.tiles.push(built.tile);
        self.fades.push(built.fade);
    }

    /// Removes a tile, returning it; `None` if it is not active.
    pub fn deactivate(&mut self, id: TileId) -> Option<StaticTile> {
        let i = self.tiles.iter().position(|t| t.id() == id)?;
        self.fades.swap_remove(i);
        Some(self.tiles.swap_remove(i))
    }

    /// Applies a streamer's update: removals, then activations.
    pub fn apply(&mut self, update: TileUpdate) {
        for id in update.remove {
            self.deactivate(id);
        }
        for t in update.add {
            self.activate(t);
        }
    }

    /// The active tiles.
    #[must_use]
    pub fn tiles(&self) -> &[StaticTile] {
        &self.tiles
    }

    /// Total QueryInstances.
    #[must_use]
    pub fn instance_count(&self) -> usize {
        self.tiles.iter().map(|t| t.instances().len()).sum()
    }

    /// Bytes of GPU data (the tiles' buffers, plus one fade byte per instance when
    /// `with_fade`).
    #[must_use]
    pub fn gpu_bytes(&self, with_fade: bool) -> usize {
        self.tiles
            .iter()
            .map(|t| t.gpu_bytes() + if with_fade { t.instances().len() } else { 0 })
            .sum()
    }

    /// The fade state of instance `instance` of tile `id` (camera view), `0..=N`.
    #[must_use]
    pub fn fade_state(&self, id: TileId, instance: usize) -> Option<u8> {
        self.camera_state(id, instance)
            .map(|s| s & !crate::CAMERA_STATE_VISIBLE)
    }

    /// The whole camera state byte of instance `instance` of tile `id`: its fade state
    /// and [`CAMERA_STATE_VISIBLE`](crate::CAMERA_STATE_VISIBLE) (what the GPU query keeps
    /// in its state buffer).
    #[must_use]
    pub fn camera_state(&self, id: TileId, instance: usize) -> Option<u8> {
        let i = self.tiles.iter().position(|t| t.id() == id)?;
        self.fades[i].instances.get(instance).copied()
    }

    /// The CPU pre-cull: the jobs to dispatch, in tile and cluster order; updates the
    /// clusters' stale flags (fading views only).
    ///
    /// Tiles and clusters are tested with the liveness unknown: a tile or cluster the LOD
    /// test rejects in a fading view still has to run while some instance fades out, so
    /// it becomes an `unless_live` job. With `resolve_live` (the CPU query) such a job is
    /// kept only if the cluster's `CLUSTER_LIVE` bit is set (else it is culled and its
    /// states are current: not stale); without (the GPU query) it is returned flagged
    /// and the pass skips it unless the cluster's live serial says it is live. A cluster
    /// outside the frustum is marked stale whatever its tile's LOD verdict.
    pub(crate) fn plan(
        &mut self,
        params: &QueryParams,
        options: &QueryOptions,
        fade: bool,
        resolve_live: bool,
        stats: &mut QueryStats,
    ) -> Vec<PlannedJob> {
        let pc = PreCull {
            planes: params.planes,
            lod_point: params.lod_point(),
            lod_scale: params.lod_point[3],
            filter: params.filter_mask as u8,
        };
        let origin = params.origin();
        let mut jobs = Vec::new();
        for (slot, tile) in self.tiles.iter().enumerate() {
            stats.tiles += 1;
            let states = &mut self.fades[slot].clusters;
            let job = |ci: usize, states: &[u8], unless_live: bool| PlannedJob {
                slot,
                cluster: ci,
                job: ClusterJob {
                    first: tile.clusters()[ci].first,
                    count: tile.clusters()[ci].count,
                    snap_fade: fade && states[ci] & CLUSTER_STALE != 0,
                },
                unless_live,
            };
            if !options.precull {
                for ci in 0..tile.clusters().len() {
                    stats.clusters += 1;
                    jobs.push(job(ci, states, false));
                }
                continue;
            }
            let offset = anchor_offset(tile.anchor(), origin);
            let tile_lod = match precull(tile.cull(), offset, &pc) {
                Verdict::Pass => false,
                Verdict::Lod if fade => true,
                v => {
                    stats.tiles_culled += 1;
                    if fade {
                        mark(states, &v);
                    }
                    continue;
                }
            };
            for (ci, c) in tile.clusters().iter().enumerate() {
                stats.clusters += 1;
                match precull(&c.cull, offset, &pc) {
                    Verdict::Pass if !tile_lod => jobs.push(job(ci, states, false)),
                    Verdict::Pass | Verdict::Lod if fade => {
                        if !resolve_live {
                            jobs.push(job(ci, states, true));
                        } else if states[ci] & CLUSTER_LIVE != 0 {
                            jobs.push(job(ci, states, false));
                        } else {
                            stats.clusters_culled += 1;
                            mark(&mut states[ci..=ci], &Verdict::Lod);
                        }
                    }
                    v => {
                        stats.clusters_culled += 1;
                        if fade {
                            mark(&mut states[ci..=ci], &v);
                        }
                    }
                }
            }
        }
        jobs
    }

    /// The start both query runners ([`Scene::query`] and the parallel `par_query`) share:
    /// `out` emptied, its stats zeroed, the view's constants and its planned jobs (pre-cull
    /// counted into `out.stats`, live flags resolved).
    pub(crate) fn begin_query<I>(
        &mut self,
        params: &QueryParams,
        options: &QueryOptions,
        out: &mut QueryOutput<I>,
    ) -> (Consts, Vec<PlannedJob>) {
        let c = Consts::new(params);
        out.instances.clear();
        out.batches.clear();
        out.stats = QueryStats::default();
        let jobs = self.plan(params, options, c.fade, true, &mut out.stats);
        (c, jobs)
    }

    /// Runs a view's query, sequentially: the pre-cull, then [`query_cluster`](crate::query_cluster)
    /// for each job in order, appending to `out` (cleared first). Camera views (with
    /// [`QUERY_FLAG_FADE`](crate::QUERY_FLAG_FADE)) read and update the fade states.
    ///
    /// The pre-cull never changes what is drawn without fading (tested). With fading, a
    /// cluster still fading out is never rejected for its LOD range, and a cluster skipped
    /// for being outside the frustum starts its next run from snapped states (`N` where
    /// the LOD is selected, else 0), as its instances would have snapped off screen; the
    /// only difference from running every instance every frame is one fade step for an
    /// instance whose LOD switched on the very frame its cluster came back into view.
    pub fn query<I: OutputInstance>(
        &mut self,
        params: &QueryParams,
        hiz: Option<&HiZ>,
        options: &QueryOptions,
        out: &mut QueryOutput<I>,
    ) -> Result<(), Error> {
        let (c, jobs) = self.begin_query(params, options, out);
        for pj in &jobs {
            let tile = &self.tiles[pj.slot];
            let states = &mut self.fades[pj.slot];
            let (f, e) = (
                pj.job.first as usize,
                (pj.job.first + pj.job.count) as usize,
            );
            let fade: &mut [u8] = if c.state {
                &mut states.instances[f..e]
            } else {
                &mut []
            };
            let r = run_into(
                &c,
                tile,
                hiz,
                fade,
                pj.job,
                options.wave_width,
                &mut out.scratch,
                &mut out.scratch_batches,
                &mut out.stats,
            )?;
            if c.fade && !c.first {
                set_live(&mut states.clusters[pj.cluster], r.live);
            }
            append(
                &mut out.instances,
                &mut out.batches,
                &out.scratch,
                &out.scratch_batches,
                r.instances,
                r.batches,
            );
        }
        Ok(())
    }

    /// The GPU serial of the last run of cluster `cluster` of the tile in `slot`.
    pub(crate) fn cluster_last_run(&self, slot: usize, cluster: usize) -> u32 {
        self.fades[slot].last_run[cluster]
    }

    /// Records that the GPU query `serial` ran a cluster: its states are current.
    pub(crate) fn ran_on_gpu(&mut self, slot: usize, cluster: usize, serial: u32) {
        let f = &mut self.fades[slot];
        f.last_run[cluster] = serial;
        f.clusters[cluster] = 0;
    }

    /// Borrows everything the parallel query needs.
    #[cfg(feature = "parallel")]
    pub(crate) fn parts_mut(&mut self) -> (&[StaticTile], Vec<FadeParts<'_>>) {
        (
            &self.tiles,
            self.fades
                .iter_mut()
                .map(|f| (f.instances.as_mut_slice(), f.clusters.as_mut_slice()))
                .collect(),
        )
    }
}

fn mark(states: &mut [u8], v: &Verdict) {
    match v {
        Verdict::Frustum => states.iter_mut().for_each(|s| *s |= CLUSTER_STALE),
        // In the frustum but out of LOD range with nothing fading (the pre-cull only
        // rejects non-live clusters by LOD): every fade state is 0, and that is current.
        Verdict::Lod => states.iter_mut().for_each(|s| *s &= !CLUSTER_STALE),
        Verdict::Filter | Verdict::Pass => {}
    }
}

pub(crate) fn set_live(state: &mut u8, live: bool) {
    *state = if live { CLUSTER_LIVE } else { 0 };
}

/// A job's output counts.
pub(crate) struct JobOut {
    pub(crate) instances: usize,
    pub(crate) batches: usize,
    pub(crate) live: bool,
}

/// Runs one job into scratch buffers sized for it (counters from 0).
#[expect(
    clippy::too_many_arguments,
    reason = "pass-shaped CPU twin: one job of the query pass into scratch outputs, the pass's bindings"
)]
pub(crate) fn run_into<I: OutputInstance>(
    c: &Consts,
    tile: &StaticTile,
    hiz: Option<&HiZ>,
    fade: &mut [u8],
    job: ClusterJob,
    width: WaveWidth,
    scratch: &mut Vec<I>,
    scratch_batches: &mut Vec<DrawableSetupBatch>,
    stats: &mut QueryStats,
) -> Result<JobOut, Error> {
    let n = job.count as usize;
    if scratch.len() < n {
        scratch.resize(n, I::zeroed());
    }
    if scratch_batches.len() < n {
        scratch_batches.resize(n, DrawableSetupBatch::default());
    }
    let ci = core::cell::Cell::new(0u32);
    let cb = core::cell::Cell::new(0u32);
    let r = run_job(
        c,
        &tile.buffers(),
        hiz,
        fade,
        job,
        width,
        &ci,
        scratch.as_mut_slice(),
        &cb,
        scratch_batches.as_mut_slice(),
        stats,
    )?;
    Ok(JobOut {
        instances: ci.get() as usize,
        batches: cb.get() as usize,
        live: r.live,
    })
}

/// Appends a job's output, rebasing its batches' first instances.
pub(crate) fn append<I: Copy>(
    instances: &mut Vec<I>,
    batches: &mut Vec<DrawableSetupBatch>,
    job_instances: &[I],
    job_batches: &[DrawableSetupBatch],
    ni: usize,
    nb: usize,
) {
    let base = instances.len() as u32;
    instances.extend_from_slice(&job_instances[..ni]);
    batches.extend(job_batches[..nb].iter().map(|b| DrawableSetupBatch {
        first_instance: b.first_instance + base,
        ..*b
    }));
}
