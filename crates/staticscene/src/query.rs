//! The per-instance query, written pass-shaped: [`query_cluster`] is the CPU twin of the
//! compute shader that runs one job per visible cluster ("GPU compute job for cluster"),
//! taking the same buffers in the same order as its bindings:
//!
//! | binding | buffer | here |
//! | --- | --- | --- |
//! | uniform | the view's constants | [`QueryParams`] |
//! | storage, read | QueryInstances, QueryObjects, QuerySetups, matrices, bounds | [`TileBuffers`] |
//! | texture | last frame's HiZ pyramid | [`HiZ`] |
//! | storage, read-write | camera states, one byte per instance (fade, last visibility) | `fade` |
//! | storage, atomic | instance counter + [`DrawableSetupInstance`](crate::DrawableSetupInstance)s | `instance_counter`, `instances` |
//! | storage, atomic | batch counter + [`DrawableSetupBatch`]es | `batch_counter`, `batches` |
//! | dispatch | the cluster's instance range | [`ClusterJob`] |
//!
//! One thread per QueryInstance, in waves of `width` lanes starting at the cluster's first
//! instance. Each thread, in the talk's order ("GPU compute thread: Input and tests",
//! "Output"):
//!
//! 1. **Filter**: `filter & view.filter == 0` ends the thread; nothing else is loaded.
//! 2. **Parent LOD**: the parent bounds through the object-to-floating transform; the
//!    squared distance from the LOD point to that box against `[min, max)` times the LOD
//!    scale (object scale, times the view's unless the object ignores it).
//! 3. **Child LOD**, only if the parent is selected. A thread whose LOD is not selected
//!    and that is not fading out ends here.
//! 4. **Accurate frustum**: the setup's local bounds through local-to-floating (object
//!    transform times local-to-object matrix), tested against the six planes.
//! 5. **Screen size**: the box's enclosing sphere, projected at its nearest clip `w`, must
//!    span at least the threshold in pixels.
//! 6. **Occlusion** (camera views with a HiZ): [`HiZ::occluded`] with the matrix the depth
//!    was rendered with; skipped for instances flagged `INSTANCE_FLAG_NO_OCCLUSION`. In the
//!    first pass of two-pass occlusion ([`OcclusionPass::First`](crate::OcclusionPass)) the
//!    test is last frame's visibility instead ([`CAMERA_STATE_VISIBLE`]), and nothing is
//!    written.
//! 7. **LOD fade** (camera views): the instance's state `s` in `0..=N` (`N` the fade
//!    length): outside the frustum it snaps to `N` if the LOD is selected and `0`
//!    otherwise (nothing on screen to fade); inside, it steps one frame towards `N` when
//!    selected and towards `0` when not. An instance fading in and the one it replaces
//!    fading out have opacities `k / N` and `(N - k) / N`: they always sum to one.
//! 8. **Output**: visible threads (frustum, size and occlusion passed, and LOD selected or
//!    fade state above zero) record that in [`CAMERA_STATE_VISIBLE`]; those a second pass
//!    knows the first output are counted in [`QueryStats::drawn_early`]; the others append
//!    a [`DrawableSetupInstance`](crate::DrawableSetupInstance) with one aggregated atomic
//!    per wave, and the first visible thread of each run of one setup appends a
//!    [`DrawableSetupBatch`], through [`wave::Wave::batch_output_with`].
//!
//! Indices that point outside a buffer (possible only in hand-made [`TileBuffers`]) read
//! nothing: the instance is dropped and counted in [`QueryStats::invalid`], as robust
//! buffer access would make the GPU read zeros.

use glam::{Affine3A, Mat4, Vec3, Vec3A, Vec4};
use wave::{Counter, LaneMask, Wave, WaveWidth};

use crate::output::{OutputInstance, STATE_FADING, STATE_FADING_OUT, sort_key};
use crate::records::{floating_offset, lod_selects};
use crate::view::{
    CAMERA_STATE_VISIBLE, QUERY_FLAG_FADE, QUERY_FLAG_FIRST_PASS, QUERY_FLAG_OCCLUSION,
    QUERY_FLAG_SECOND_PASS, QUERY_FLAG_SIZE, QueryParams, box_outside_frustum,
};
use crate::{
    DrawableSetupBatch, Error, HalfAabb, HiZ, INSTANCE_FLAG_NO_FADE, INSTANCE_FLAG_NO_OCCLUSION,
    InstanceState, QueryInstance, QueryObject, QuerySetup, Transform4x3,
};

/// One tile's storage buffers, as the pass binds them.
#[derive(Clone, Copy, Debug)]
pub struct TileBuffers<'a> {
    /// The tile's id, written into each instance's state.
    pub tile: u32,
    /// QueryInstances.
    pub instances: &'a [QueryInstance],
    /// QueryObjects.
    pub objects: &'a [QueryObject],
    /// QuerySetups.
    pub setups: &'a [QuerySetup],
    /// Local-to-object matrices.
    pub transforms: &'a [Transform4x3],
    /// LOD bounds.
    pub bounds: &'a [HalfAabb],
}

/// One compute job: a cluster's instance range.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ClusterJob {
    /// First instance.
    pub first: u32,
    /// Instances.
    pub count: u32,
    /// The cluster was skipped (outside the frustum) since it last ran: its fade states
    /// are stale, so each starts from the snapped value (`N` if its LOD is selected, else
    /// `0`), as if it had been outside the frustum all along.
    pub snap_fade: bool,
}

/// What a query did, per stage. Instance counters count threads (QueryInstances).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct QueryStats {
    /// Tiles considered by the pre-cull.
    pub tiles: u64,
    /// Tiles rejected by the pre-cull (filter, frustum or LOD).
    pub tiles_culled: u64,
    /// Clusters considered by the pre-cull (in tiles that passed).
    pub clusters: u64,
    /// Clusters rejected by the pre-cull.
    pub clusters_culled: u64,
    /// Threads run (instances of the jobs dispatched).
    pub instances: u64,
    /// Ended by the filter test.
    pub rejected_filter: u64,
    /// Ended by the LOD tests.
    pub rejected_lod: u64,
    /// Ended by the frustum test.
    pub rejected_frustum: u64,
    /// Ended by the screen-size test.
    pub rejected_size: u64,
    /// Ended by the occlusion test.
    pub rejected_occlusion: u64,
    /// Passed the visibility tests but faded out (fade state 0).
    pub faded_out: u64,
    /// Visible in a second pass ([`OcclusionPass::Second`](crate::OcclusionPass)) but
    /// output by the first already, so not output again.
    pub drawn_early: u64,
    /// Dropped for an index outside its buffer (hand-made buffers only).
    pub invalid: u64,
    /// Instances appended (visible).
    pub visible: u64,
    /// Batch headers appended.
    pub batches: u64,
    /// Instances or headers that did not fit the output (0 with [`Scene::query`](crate::Scene::query)).
    pub dropped: u64,
}

impl QueryStats {
    /// Sums two runs.
    #[must_use]
    pub fn merge(mut self, o: &QueryStats) -> QueryStats {
        self.tiles += o.tiles;
        self.tiles_culled += o.tiles_culled;
        self.clusters += o.clusters;
        self.clusters_culled += o.clusters_culled;
        self.instances += o.instances;
        self.rejected_filter += o.rejected_filter;
        self.rejected_lod += o.rejected_lod;
        self.rejected_frustum += o.rejected_frustum;
        self.rejected_size += o.rejected_size;
        self.rejected_occlusion += o.rejected_occlusion;
        self.faded_out += o.faded_out;
        self.drawn_early += o.drawn_early;
        self.invalid += o.invalid;
        self.visible += o.visible;
        self.batches += o.batches;
        self.dropped += o.dropped;
        self
    }
}

/// What one job reports besides its output.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ClusterResult {
    /// Some instance's fade state is above zero after the job (the cluster must run while
    /// its instances fade out, even when the LOD pre-cull would reject it).
    pub live: bool,
}

/// The view constants the threads read, unpacked once per job.
pub(crate) struct Consts {
    pub(crate) planes: [[f32; 4]; 6],
    pub(crate) w_row: Vec4,
    pub(crate) w_row_len: f32,
    pub(crate) hiz_m: Mat4,
    pub(crate) forward: Vec4,
    pub(crate) fwd_len: f32,
    pub(crate) lod_point_a: Vec3A,
    pub(crate) lod_scale: f32,
    pub(crate) origin: glam::IVec3,
    pub(crate) prev_delta: Vec3,
    pub(crate) filter: u32,
    pub(crate) size_on: bool,
    pub(crate) size_px: f32,
    pub(crate) px_per_unit: f32,
    pub(crate) occlusion: bool,
    pub(crate) fade: bool,
    /// The camera state bytes are read (fading, or a two-pass occlusion pass).
    pub(crate) state: bool,
    /// Two-pass occlusion's first pass: reads states, writes none.
    pub(crate) first: bool,
    /// Two-pass occlusion's second pass.
    pub(crate) second: bool,
    pub(crate) fade_frames: u8,
    pub(crate) scan_levels: u32,
}

impl Consts {
    pub(crate) fn new(p: &QueryParams) -> Consts {
        let m = p.clip_from_floating();
        let w_row = m.row(3);
        let fwd = Vec4::from_array(p.forward);
        Consts {
            planes: p.planes,
            w_row,
            w_row_len: w_row.truncate().length(),
            hiz_m: p.hiz_clip_from_floating(),
            forward: fwd,
            fwd_len: fwd.truncate().length(),
            lod_point_a: Vec3A::from(p.lod_point()),
            lod_scale: p.lod_point[3],
            origin: p.origin(),
            prev_delta: floating_offset(p.origin(), p.prev_origin()),
            filter: p.filter_mask,
            size_on: p.has(QUERY_FLAG_SIZE),
            size_px: p.viewport[2],
            px_per_unit: p.viewport[3],
            occlusion: p.has(QUERY_FLAG_OCCLUSION),
            fade: p.has(QUERY_FLAG_FADE) && p.fade_frames > 0,
            state: (p.has(QUERY_FLAG_FADE) && p.fade_frames > 0)
                || p.has(QUERY_FLAG_FIRST_PASS)
                || p.has(QUERY_FLAG_SECOND_PASS),
            first: p.has(QUERY_FLAG_FIRST_PASS),
            second: p.has(QUERY_FLAG_SECOND_PASS) && !p.has(QUERY_FLAG_FIRST_PASS),
            fade_frames: p.fade_frames.min(crate::MAX_FADE_FRAMES) as u8,
            scan_levels: p.hiz_scan_levels,
        }
    }
}

/// A visible thread's results, kept for the wave's output.
#[derive(Clone, Copy, Default)]
struct Lane {
    l2f: Transform4x3,
    min: Vec3,
    max: Vec3,
    depth: f32,
    fade: f32,
    flags: u32,
    handle: u64,
}

enum Outcome {
    Filter,
    Lod,
    Frustum,
    Size,
    Occluded,
    FadedOut,
    DrawnEarly,
    Invalid,
    Visible,
}

/// Squared distance from `p` to the box `[min, max]` (0 inside).
#[inline]
fn dist2(p: Vec3A, min: Vec3A, max: Vec3A) -> f32 {
    let d = (min - p).max(p - max).max(Vec3A::ZERO);
    d.dot(d)
}

/// A transform in SIMD column form for the hot loop (the same products and sums, in the
/// same order, as [`Transform4x3::transform_point`]).
#[derive(Clone, Copy)]
struct Xf(Affine3A);

impl Xf {
    #[inline]
    fn from_rows(t: &Transform4x3, dt: Vec3) -> Xf {
        let r = &t.rows;
        Xf(Affine3A::from_cols(
            Vec3A::new(r[0][0], r[1][0], r[2][0]),
            Vec3A::new(r[0][1], r[1][1], r[2][1]),
            Vec3A::new(r[0][2], r[1][2], r[2][2]),
            Vec3A::new(r[0][3] + dt.x, r[1][3] + dt.y, r[2][3] + dt.z),
        ))
    }

    /// The box enclosing the transformed box (centre and absolute-extent form).
    #[inline]
    fn aabb(&self, min: Vec3A, max: Vec3A) -> (Vec3A, Vec3A) {
        let c = (min + max) * 0.5;
        let e = (max - min) * 0.5;
        let m = &self.0.matrix3;
        let tc = self.0.transform_point3a(c);
        let te = m.x_axis.abs() * e.x + m.y_axis.abs() * e.y + m.z_axis.abs() * e.z;
        (tc - te, tc + te)
    }

    #[inline]
    fn to_rows(self) -> Transform4x3 {
        Transform4x3::from_affine(&self.0)
    }
}

#[inline]
fn half_box(b: &HalfAabb) -> (Vec3A, Vec3A) {
    (Vec3A::from(b.min()), Vec3A::from(b.max()))
}

const ALWAYS_MIN: u32 = 0;
const ALWAYS_MAX: u32 = crate::LOD_CODE_INFINITY as u32;

#[inline(always)]
fn lod_level(codes: (u32, u32), bounds: &HalfAabb, o2f: &Xf, c: &Consts, scale2: f32) -> bool {
    // Computed for every level, padding included (`0 <= d² < inf` holds for any finite
    // d): no data-dependent branch, so consecutive instances overlap.
    let (lo, hi) = half_box(bounds);
    let (min, max) = o2f.aabb(lo, hi);
    let always = codes == (ALWAYS_MIN, ALWAYS_MAX);
    always | lod_selects(codes.0, codes.1, dist2(c.lod_point_a, min, max), scale2)
}

/// What consecutive threads of one job share: the last object's transform and LOD scale
/// and the last parent LOD result. Instances of one object follow each other (the
/// partition sorts by setup, then Morton order), and every leaf under one LOD switch has
/// the same parent bounds and bracket, so most threads reuse the previous thread's
/// values. A pure memo of the same f32 computations: results are identical to computing
/// them per thread, as the shader does.
struct ThreadCache {
    object: u32,
    o2f: Xf,
    scale2: f32,
    parent: (u32, u32, u32),
    p_sel: bool,
}

impl ThreadCache {
    fn new() -> ThreadCache {
        ThreadCache {
            object: u32::MAX,
            o2f: Xf(Affine3A::IDENTITY),
            scale2: 0.0,
            parent: (u32::MAX, 0, 0),
            p_sel: false,
        }
    }
}

/// The tests of one thread; `fade` is its fade state (when the view fades).
#[inline]
#[expect(
    clippy::too_many_arguments,
    reason = "pass-shaped CPU twin: one thread of the query pass, its bindings and per-lane state as the shader has them"
)]
fn test_instance(
    c: &Consts,
    t: &TileBuffers<'_>,
    hiz: Option<&HiZ>,
    q: QueryInstance,
    fade: Option<&mut u8>,
    snap: bool,
    lane: &mut Lane,
    live: &mut bool,
    cache: &mut ThreadCache,
) -> Outcome {
    // 1. Filter: word 0 only.
    if u32::from(q.filter()) & c.filter == 0 {
        return Outcome::Filter;
    }
    let oi = q.object();
    if oi != cache.object {
        let Some(obj) = t.objects.get(oi as usize) else {
            return Outcome::Invalid;
        };
        cache.o2f = Xf::from_rows(
            &obj.object_to_snapped,
            floating_offset(obj.snapped(), c.origin),
        );
        let scale = if obj.ignores_global_lod_scale() {
            obj.lod_scale()
        } else {
            obj.lod_scale() * c.lod_scale
        };
        cache.scale2 = scale * scale;
        cache.object = oi;
        cache.parent = (u32::MAX, 0, 0);
    }
    let o2f = cache.o2f;
    let scale2 = cache.scale2;
    // 2. Parent LOD, then 3. child LOD only if the parent is selected.
    let (Some(pb), Some(cb)) = (
        t.bounds.get(q.parent_bounds() as usize),
        t.bounds.get(q.child_bounds() as usize),
    ) else {
        return Outcome::Invalid;
    };
    let pcodes = q.parent_lod_codes();
    let pkey = (q.parent_bounds(), pcodes.0, pcodes.1);
    if pkey != cache.parent {
        cache.p_sel = lod_level(pcodes, pb, &o2f, c, scale2);
        cache.parent = pkey;
    }
    let p_sel = cache.p_sel;
    let lod_sel = p_sel && lod_level(q.child_lod_codes(), cb, &o2f, c, scale2);
    let fade_on = c.fade && q.flags() & INSTANCE_FLAG_NO_FADE == 0;
    let n = c.fade_frames;
    // The camera state byte: fade state in the low 7 bits, CAMERA_STATE_VISIBLE on top.
    // The first pass of two-pass occlusion only reads it.
    let stored = match &fade {
        Some(f) if c.state => **f,
        _ => 0,
    };
    let mut fade = if c.first { None } else { fade };
    let was_visible = stored & CAMERA_STATE_VISIBLE != 0;
    let prev = match fade_on && c.state {
        true if snap => {
            if lod_sel {
                n
            } else {
                0
            }
        }
        true => (stored & !CAMERA_STATE_VISIBLE).min(n),
        false => 0,
    };
    if !lod_sel && prev == 0 {
        if let Some(f) = fade.as_deref_mut() {
            *f = 0;
        }
        return Outcome::Lod;
    }
    // 4. Accurate frustum test of the local bounds in floating space.
    let (Some(l2o), Some(setup)) = (
        t.transforms.get(q.matrix() as usize),
        t.setups.get(q.setup() as usize),
    ) else {
        return Outcome::Invalid;
    };
    let l2f = Xf(o2f.0 * Xf::from_rows(l2o, Vec3::ZERO).0);
    let (min, max) = l2f.aabb(Vec3A::from(setup.min()), Vec3A::from(setup.max()));
    let (min, max) = (Vec3::from(min), Vec3::from(max));
    let in_frustum = !box_outside_frustum(&c.planes, min, max);
    let centre = (min + max) * 0.5;
    let radius = (max - min).length() * 0.5;
    // 5. Screen size at the sphere's nearest w.
    let big = !in_frustum || !c.size_on || {
        let w = c.w_row.truncate().dot(centre) + c.w_row.w - radius * c.w_row_len;
        w.is_nan() || w <= 0.0 || 2.0 * radius * c.px_per_unit >= c.size_px * w
    };
    // 6. Occlusion: against the HiZ, or, in the first of two passes, last frame's
    // visibility.
    let testable = in_frustum && big && q.flags() & INSTANCE_FLAG_NO_OCCLUSION == 0;
    let occluded = if c.first {
        testable && !was_visible
    } else {
        testable
            && c.occlusion
            && hiz.is_some_and(|z| z.occluded(&c.hiz_m, min, max, c.scan_levels))
    };
    // 7. LOD fade state.
    let (next, opacity, flags) = if fade_on {
        let next = if !in_frustum {
            if lod_sel { n } else { 0 }
        } else if lod_sel {
            (prev + 1).min(n)
        } else {
            prev.saturating_sub(1)
        };
        let mut flags = 0;
        if next < n {
            flags |= STATE_FADING;
        }
        if !lod_sel {
            flags |= STATE_FADING_OUT;
        }
        (next, f32::from(next) / f32::from(n), flags)
    } else {
        (0, 1.0, 0)
    };
    let shown = if fade_on { next > 0 } else { lod_sel };
    if fade_on {
        *live |= next > 0;
    }
    let visible = in_frustum && big && !occluded && shown;
    if let Some(f) = fade {
        let seen = if visible { CAMERA_STATE_VISIBLE } else { 0 };
        *f = (if fade_on { next } else { 0 }) | seen;
    }
    if !in_frustum {
        return Outcome::Frustum;
    }
    if !big {
        return Outcome::Size;
    }
    if occluded {
        return Outcome::Occluded;
    }
    if !shown {
        return Outcome::FadedOut;
    }
    // The first pass output what it would have output now: visible last frame (or never
    // occlusion-tested), and every other test as here.
    if c.second && (was_visible || q.flags() & INSTANCE_FLAG_NO_OCCLUSION != 0) {
        return Outcome::DrawnEarly;
    }
    // 8. Output data for the wave.
    *lane = Lane {
        l2f: l2f.to_rows(),
        min,
        max,
        depth: c.forward.truncate().dot(centre) + c.forward.w - radius * c.fwd_len,
        fade: opacity,
        flags,
        handle: setup.handle,
    };
    Outcome::Visible
}

/// A group's accumulation in the wave's scratch (the talk's LDS): bounds, nearest depth,
/// OR of flags. Commutative, as on the GPU.
#[derive(Clone, Copy)]
struct BatchAcc {
    min: Vec3,
    max: Vec3,
    depth: f32,
    flags: u32,
}

impl Default for BatchAcc {
    fn default() -> Self {
        BatchAcc {
            min: Vec3::splat(f32::INFINITY),
            max: Vec3::splat(f32::NEG_INFINITY),
            depth: f32::INFINITY,
            flags: 0,
        }
    }
}

/// Runs one cluster job: the CPU twin of the query compute shader (see the [module
/// docs](self) for the bindings and the per-thread steps).
///
/// - `fade`: the fade states of the job's instances (`fade[i]` belongs to instance
///   `job.first + i`); read and written when `params` has [`QUERY_FLAG_FADE`], and then
///   at least `job.count` long.
/// - `width`: lanes per wave; batches never span waves, so a batch holds at most `width`
///   instances (HZD: 64).
/// - The counters start wherever the caller's output stands; slots at or past the end of
///   `instances` / `batches` are dropped and counted in `stats.dropped` (the counters
///   still advance, so the caller can size the next frame's buffers).
///
/// Fails if the job's range is outside `tile.instances` or `fade` is too short.
#[expect(
    clippy::too_many_arguments,
    reason = "pass-shaped CPU twin: one cluster job of the query pass, taking the pass's bindings (params, tile buffers, HiZ, fade states, instance and batch counter + buffer pairs) in the shader's order"
)]
pub fn query_cluster<I, C1, C2>(
    params: &QueryParams,
    tile: &TileBuffers<'_>,
    hiz: Option<&HiZ>,
    fade: &mut [u8],
    job: ClusterJob,
    width: WaveWidth,
    instance_counter: &C1,
    instances: &mut [I],
    batch_counter: &C2,
    batches: &mut [DrawableSetupBatch],
    stats: &mut QueryStats,
) -> Result<ClusterResult, Error>
where
    I: OutputInstance,
    C1: Counter + ?Sized,
    C2: Counter + ?Sized,
{
    let c = Consts::new(params);
    run_job(
        &c,
        tile,
        hiz,
        fade,
        job,
        width,
        instance_counter,
        instances,
        batch_counter,
        batches,
        stats,
    )
}

#[expect(
    clippy::too_many_arguments,
    reason = "pass-shaped CPU twin: `query_cluster`'s body, the same bindings"
)]
pub(crate) fn run_job<I, C1, C2>(
    c: &Consts,
    tile: &TileBuffers<'_>,
    hiz: Option<&HiZ>,
    fade: &mut [u8],
    job: ClusterJob,
    width: WaveWidth,
    instance_counter: &C1,
    instances: &mut [I],
    batch_counter: &C2,
    batches: &mut [DrawableSetupBatch],
    stats: &mut QueryStats,
) -> Result<ClusterResult, Error>
where
    I: OutputInstance,
    C1: Counter + ?Sized,
    C2: Counter + ?Sized,
{
    let first = job.first as usize;
    let count = job.count as usize;
    let Some(items) = tile.instances.get(first..first + count) else {
        return Err(Error::Config {
            what: "cluster job outside the tile's instances",
        });
    };
    if c.state && fade.len() < count {
        return Err(Error::Config {
            what: "fade states shorter than the cluster job",
        });
    }
    let mut result = ClusterResult::default();
    let mut lanes = [Lane::default(); 64];
    let mut cache = ThreadCache::new();
    let wl = width.len();
    for (w, chunk) in items.chunks(wl).enumerate() {
        let mut visible = 0u64;
        let mut ends = 0u64;
        for (l, q) in chunk.iter().enumerate() {
            if q.group_end() {
                ends |= 1 << l;
            }
            let i = w * wl + l;
            let f = if c.state { fade.get_mut(i) } else { None };
            let outcome = test_instance(
                c,
                tile,
                hiz,
                *q,
                f,
                job.snap_fade,
                &mut lanes[l],
                &mut result.live,
                &mut cache,
            );
            match outcome {
                Outcome::Filter => stats.rejected_filter += 1,
                Outcome::Lod => stats.rejected_lod += 1,
                Outcome::Frustum => stats.rejected_frustum += 1,
                Outcome::Size => stats.rejected_size += 1,
                Outcome::Occluded => stats.rejected_occlusion += 1,
                Outcome::FadedOut => stats.faded_out += 1,
                Outcome::DrawnEarly => stats.drawn_early += 1,
                Outcome::Invalid => stats.invalid += 1,
                Outcome::Visible => visible |= 1 << l,
            }
        }
        stats.instances += chunk.len() as u64;
        if visible == 0 {
            continue;
        }
        let base = (job.first as usize + w * wl) as u32;
        let wave = Wave::with_lane_count(width, chunk.len() as u32)?;
        let lanes = &lanes;
        let o = wave.batch_output_with(
            LaneMask(ends),
            LaneMask(visible),
            instance_counter,
            instances,
            batch_counter,
            batches,
            |l| {
                let d = &lanes[l as usize];
                I::make(
                    InstanceState {
                        fade: d.fade,
                        flags: d.flags,
                        tile: tile.tile,
                        instance: base + l,
                    },
                    d.l2f,
                    || d.l2f.with_translation(d.l2f.translation() + c.prev_delta),
                )
            },
            |acc: &mut BatchAcc, l| {
                let d = &lanes[l as usize];
                acc.min = acc.min.min(d.min);
                acc.max = acc.max.max(d.max);
                acc.depth = acc.depth.min(d.depth);
                acc.flags |= d.flags;
            },
            |b| {
                let d = &lanes[b.first_lane() as usize];
                let a = &b.acc;
                let centre = (a.min + a.max) * 0.5;
                let r = (a.max - a.min).length() * 0.5;
                DrawableSetupBatch {
                    sort_key: sort_key(d.handle, a.depth),
                    setup: d.handle,
                    sphere: [centre.x, centre.y, centre.z, r],
                    first_instance: b.first_instance,
                    flags: a.flags,
                    count: b.instance_count,
                    stride: I::STRIDE,
                }
            },
        );
        stats.visible += u64::from(o.instances.count);
        stats.batches += u64::from(o.batches.count);
        stats.dropped += u64::from(o.instances.dropped() + o.batches.dropped());
    }
    Ok(result)
}
