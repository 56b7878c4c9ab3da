//! HZD's static-scene query on the GPU (seed 001): `staticscene`'s [`QUERY_PASS`] over
//! the pooled records of every active tile ([`StaticPool`]), one dispatch per view, the
//! CPU's part being the pre-cull ([`staticscene::Scene::plan_gpu`]).
//!
//! [`StaticQuery::run`] is HZD's mode: the CPU waits for the query and reads its batches
//! back (what a CPU renderer, or `tiling::build_plan`, then consumes).
//!
//! The HiZ the query tests against is either given ([`StaticQuery::set_hiz`], a pyramid
//! built on the CPU) or built here from the frame's depth target into `staticscene`'s HiZ
//! buffer layout by `gpu::hiz_depth`, four levels per dispatch (16x16 source texels per
//! workgroup, reduced through workgroup memory): from the depth target into levels 0-4,
//! then from level 4 into 5-8, and so on (3 dispatches at 3840x2160). Texel for texel
//! `staticscene::HiZ::build`, as `staticscene`'s one-level-per-dispatch `HIZ_PASS`.

use shader::pipeline::ComputePass;
use staticscene::pass::{
    GpuPlan, HizGrid, QUERY_PASS, QueryCounters, QueryDispatch, hiz_header, hiz_words,
};
use staticscene::{
    DrawableSetupBatch, DrawableSetupInstance, HiZ, QueryOptions, QueryParams, QueryStats,
    StaticTile, TileId,
};

use crate::error::Result;
use crate::passes::depth_reductions::{HizPasses, hiz_steps};
use crate::resources::readback::read_buffer;
use crate::resources::static_draws::QueryOutputs;
use crate::resources::static_pool::{StaticPool, empty_storage};
use crate::resources::uploads::UploadSink;
use crate::timing::GpuTimer;

/// What [`StaticQuery::run`] reads back.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum QueryReadback {
    /// Counters and statistics only.
    Counters,
    /// Counters, visible instances and batches.
    Full,
}

/// One query's result.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StaticQueryOutput {
    /// Visible instances in GPU append order (empty with [`QueryReadback::Counters`]).
    pub instances: Vec<DrawableSetupInstance>,
    /// Batch headers in GPU append order (empty with [`QueryReadback::Counters`]).
    pub batches: Vec<DrawableSetupBatch>,
    /// The pre-cull's and the pass's statistics.
    pub stats: QueryStats,
    /// Threads dispatched (instances of the planned jobs).
    pub threads: u64,
    /// The pass's GPU time in milliseconds (timestamp queries; `None` without them).
    pub gpu_ms: Option<f64>,
    /// Active tiles of the scene that were not activated on the GPU (skipped).
    pub skipped_tiles: Vec<TileId>,
}

/// The HiZ buffer laid out for a depth target of one size: the uniforms of the depth
/// pass and of the reduction steps after it.
struct DepthHiz {
    size: (u32, u32),
    reversed: bool,
    /// Per dispatch: its `HizStep` uniform (the source level: 0, the depth target, first)
    /// and the size of the first level it writes.
    steps: Vec<(wgpu::Buffer, HizGrid)>,
}

/// One view's pre-cull and dispatch, ready to record.
pub(crate) struct PreparedView {
    group: wgpu::BindGroup,
    /// The second pass's group (two-pass occlusion): its params and counters.
    second: Option<wgpu::BindGroup>,
    /// The pre-cull's jobs and statistics.
    pub plan: GpuPlan,
    /// Threads dispatched.
    pub threads: u64,
    /// Records the output buffers hold.
    pub cap: u64,
    /// A shadow view: recorded with the shadow variant.
    shadow: bool,
    /// A shadow view of [`StaticQuery::prepare_shadow_views`]: its counters and the
    /// outputs it writes (`None`: the camera view's, the query's own fields).
    own: Option<ViewOutputs>,
}

/// The counters and outputs one shadow view writes.
struct ViewOutputs {
    counters: wgpu::Buffer,
    instances: wgpu::Buffer,
    batches: wgpu::Buffer,
}

/// One shadow view's uniform block, job tables and counters. A frame records several
/// shadow views, and every upload lands before the frame runs, so each has its own; their
/// outputs are shared (each view's placement consumes them before the next view's query).
struct ShadowViewBuffers {
    params: wgpu::Buffer,
    job_list: wgpu::Buffer,
    wave_jobs: wgpu::Buffer,
    counters: wgpu::Buffer,
}

/// The GPU static query: the pass, the tile pool and the per-view buffers.
pub struct StaticQuery {
    pass: ComputePass<QueryDispatch>,
    /// The shadow variant (feature `shadow_view`), for views with `QUERY_FLAG_SHADOW`.
    shadow_pass: ComputePass<QueryDispatch>,
    /// Whether the passes output batches per subgroup (feature `subgroups`).
    subgroups: bool,
    /// The device's subgroup sizes (min, max).
    subgroup_sizes: (u32, u32),
    hiz_passes: HizPasses,
    pool: StaticPool,
    params: wgpu::Buffer,
    /// The second pass's params (two-pass occlusion).
    params_second: wgpu::Buffer,
    job_list: wgpu::Buffer,
    /// The job of each wave (`GpuPlan::wave_jobs`).
    wave_jobs: wgpu::Buffer,
    hiz: wgpu::Buffer,
    /// Set while `hiz` is laid out for a depth target (cleared by `set_hiz`).
    depth_hiz: Option<DepthHiz>,
    counters: wgpu::Buffer,
    /// The second pass's counters.
    counters_second: wgpu::Buffer,
    out_instances: wgpu::Buffer,
    out_batches: wgpu::Buffer,
    /// Per shadow view of a frame ([`StaticQuery::prepare_shadow_views`]).
    shadow_views: Vec<ShadowViewBuffers>,
    /// The shadow views' outputs, one view after the other.
    shadow_out_instances: wgpu::Buffer,
    shadow_out_batches: wgpu::Buffer,
    timer: GpuTimer,
}

impl StaticQuery {
    /// The pipeline and empty buffers; batches per subgroup where the device has
    /// subgroups ([`StaticQuery::with_subgroups`] chooses).
    ///
    /// # Errors
    /// A composition error (a bug).
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> Result<Self> {
        Self::with_subgroups(device, queue, true)
    }

    /// [`StaticQuery::new`] with the batch output chosen: per subgroup when `subgroups`
    /// and the device has `Features::SUBGROUP` (as `RendererConfig::geometry.subgroups` does for
    /// the frame's passes), else per 64-invocation workgroup.
    ///
    /// # Errors
    /// A composition error (a bug).
    pub fn with_subgroups(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        subgroups: bool,
    ) -> Result<Self> {
        let uniform = |label| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size_of::<QueryParams>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        // Batches per subgroup where the device has subgroups (HZD's per hardware wave).
        let subgroups = subgroups && device.features().contains(wgpu::Features::SUBGROUP);
        let (camera, shadow): (&[&str], &[&str]) = if subgroups {
            (&["subgroups"], &["shadow_view", "subgroups"])
        } else {
            (&[], &["shadow_view"])
        };
        let mut q = Self {
            pass: ComputePass::new(device, &QUERY_PASS, camera, &[])?,
            shadow_pass: ComputePass::new(device, &QUERY_PASS, shadow, &[])?,
            subgroups,
            subgroup_sizes: {
                let info = device.adapter_info();
                (info.subgroup_min_size, info.subgroup_max_size)
            },
            hiz_passes: HizPasses::new(device)?,
            pool: StaticPool::new(device),
            params: uniform("static query params"),
            params_second: uniform("static query params (second pass)"),
            job_list: empty_storage(device, "static query jobs", 4096)?,
            wave_jobs: empty_storage(device, "static query wave jobs", 4096)?,
            hiz: empty_storage(device, "static query hiz", 256)?,
            depth_hiz: None,
            counters: empty_storage(device, "static query counters", 256)?,
            counters_second: empty_storage(device, "static query counters (second pass)", 256)?,
            out_instances: empty_storage(device, "static query instances", 256)?,
            out_batches: empty_storage(device, "static query batches", 256)?,
            shadow_views: Vec::new(),
            shadow_out_instances: empty_storage(device, "static shadow query instances", 256)?,
            shadow_out_batches: empty_storage(device, "static shadow query batches", 256)?,
            timer: GpuTimer::new(device, queue, 1),
        };
        q.set_hiz(device, queue, None)?;
        Ok(q)
    }

    /// Uploads an active tile's records (call for each tile a `TileUpdate` adds). A tile
    /// that fails stays off the GPU: the query skips it and reports it, other tiles are
    /// unaffected.
    ///
    /// # Errors
    /// [`SceneError::StaticTile`](crate::SceneError::StaticTile) (the id is already
    /// active, or the tile passes u32 indexing), [`Error::DeviceLimit`](crate::Error)
    /// when the pool would pass `max_storage_buffer_binding_size`.
    pub fn activate(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        tile: &StaticTile,
    ) -> Result<()> {
        self.pool.activate(device, queue, tile).map(|_| ())
    }

    /// Releases a removed tile's records; false if it was not active.
    pub fn deactivate(&mut self, id: TileId) -> bool {
        self.pool.deactivate(id)
    }

    /// The lanes a batch may span, as the CPU twin's [`QueryOptions::wave_width`] that
    /// reproduces this query's batches: the device's subgroup size where it has subgroups
    /// (a fixed size of 8 to 64), else the 64-invocation workgroup (`None`: a subgroup size
    /// that varies or is outside 8-64, for which no twin width matches).
    #[must_use]
    pub fn wave_width(&self) -> Option<staticscene::WaveWidth> {
        if !self.subgroups {
            return Some(staticscene::WaveWidth::W64);
        }
        let (lo, hi) = self.subgroup_sizes;
        (lo == hi)
            .then(|| staticscene::WaveWidth::from_lanes(lo).ok())
            .flatten()
    }

    /// Active tiles on the GPU.
    #[must_use]
    pub fn tile_count(&self) -> usize {
        self.pool.len()
    }

    /// The HiZ the next queries test against (`None`: no occlusion).
    ///
    /// # Errors
    /// [`Error::StaticScene`](crate::Error::StaticScene) for a pyramid side above
    /// `staticscene::MAX_VIEWPORT`; [`Error::DeviceLimit`](crate::Error::DeviceLimit).
    pub fn set_hiz(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        hiz: Option<&HiZ>,
    ) -> Result<()> {
        let words = hiz_words(hiz)?;
        let bytes = words.len() as u64 * 4;
        if self.hiz.size() < bytes {
            self.hiz = empty_storage(device, "static query hiz", bytes)?;
        }
        queue.write_buffer(&self.hiz, 0, bytemuck::cast_slice(&words));
        self.depth_hiz = None;
        Ok(())
    }

    /// Lays the HiZ buffer out for a `width` x `height` depth target (header and level
    /// uniforms; nothing when it already is), for [`StaticQuery::record_depth_hiz`].
    pub(crate) fn prepare_depth_hiz(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        (width, height): (u32, u32),
        reversed: bool,
    ) -> Result<()> {
        if self
            .depth_hiz
            .as_ref()
            .is_some_and(|d| d.size == (width, height) && d.reversed == reversed)
        {
            return Ok(());
        }
        let (header, len) = hiz_header(width, height)?;
        let bytes = len as u64 * 4;
        if self.hiz.size() < bytes {
            self.hiz = empty_storage(device, "static query hiz", bytes)?;
        }
        queue.write_buffer(&self.hiz, 0, bytemuck::cast_slice(&header));
        let steps = hiz_steps(device, &header, reversed, "hiz step");
        self.depth_hiz = Some(DepthHiz {
            size: (width, height),
            reversed,
            steps,
        });
        Ok(())
    }

    /// Records the HiZ pyramid of `depth` (a depth target of the size last prepared with
    /// [`StaticQuery::prepare_depth_hiz`]): level 0 copied, then each level reduced.
    pub(crate) fn record_depth_hiz(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        depth: &wgpu::TextureView,
        timer: &mut GpuTimer,
        label: &'static str,
    ) -> Result<()> {
        let Some(d) = &self.depth_hiz else {
            return Ok(());
        };
        let groups = self.hiz_passes.groups(device, &d.steps, depth, &self.hiz)?;
        let mut pass = timer.begin_compute(encoder, label);
        self.hiz_passes.record(&mut pass, &groups);
        Ok(())
    }

    /// The HiZ pyramid's texels as the query last read them (every level after the
    /// other, finest first: the layout of `staticscene::HiZ::texels`), and level 0's size.
    /// A diagnostic: what the occlusion test saw.
    ///
    /// # Errors
    /// No HiZ (none set, or occlusion off), or a device or mapping error.
    pub fn read_hiz(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<(Vec<f32>, (u32, u32))> {
        let header: Vec<u32> = bytemuck::pod_collect_to_vec(&read_buffer(
            device,
            queue,
            &self.hiz,
            0,
            staticscene::pass::HIZ_HEADER_WORDS as u64 * 4,
        )?);
        if header[0] == 0 {
            return Err(crate::Error::Length {
                what: "HiZ levels (none was set or built)",
                got: 0,
                expected: 1,
            });
        }
        let (w, h) = (header[4], header[5]);
        let (_, len) = hiz_header(w, h)?;
        let start = staticscene::pass::HIZ_HEADER_WORDS as u64;
        let texels: Vec<f32> = bytemuck::pod_collect_to_vec(&read_buffer(
            device,
            queue,
            &self.hiz,
            start * 4,
            (len as u64 - start) * 4,
        )?);
        Ok((texels, (w, h)))
    }

    /// The pre-cull of one view on `scene`, and the uploads and bind group of its
    /// dispatch (the output buffers grown to one record per dispatched thread).
    pub(crate) fn prepare_view(
        &mut self,
        device: &wgpu::Device,
        uploads: &mut dyn UploadSink,
        scene: &mut staticscene::Scene,
        params: &QueryParams,
        second: Option<&QueryParams>,
        options: &QueryOptions,
    ) -> Result<PreparedView> {
        let pool = &self.pool;
        let plan: GpuPlan = scene.plan_gpu(params, options, |id| pool.slots(id));
        let threads = plan.instances();
        let jobs = plan.job_list();
        let job_bytes = jobs.len() as u64 * 4;
        if self.job_list.size() < job_bytes {
            self.job_list = empty_storage(device, "static query jobs", job_bytes * 2)?;
        }
        let wave_jobs = plan.wave_jobs();
        let table_bytes = wave_jobs.len() as u64 * 4;
        if self.wave_jobs.size() < table_bytes {
            self.wave_jobs = empty_storage(device, "static query wave jobs", table_bytes * 2)?;
        }
        // Every thread may output one instance and one header.
        let cap = threads.max(1);
        let inst_bytes = cap * size_of::<DrawableSetupInstance>() as u64;
        if self.out_instances.size() < inst_bytes {
            self.out_instances = empty_storage(device, "static query instances", inst_bytes)?;
            self.out_batches = empty_storage(
                device,
                "static query batches",
                cap * size_of::<DrawableSetupBatch>() as u64,
            )?;
        }
        uploads.write(&self.params, 0, bytemuck::bytes_of(params));
        uploads.write(&self.job_list, 0, bytemuck::cast_slice(&jobs));
        uploads.write(&self.wave_jobs, 0, bytemuck::cast_slice(&wave_jobs));
        let shadow = params.has(staticscene::QUERY_FLAG_SHADOW);
        let pass = if shadow {
            &self.shadow_pass
        } else {
            &self.pass
        };
        uploads.write(
            &self.counters,
            0,
            bytemuck::bytes_of(&QueryCounters::default()),
        );
        if let Some(p) = second {
            uploads.write(&self.params_second, 0, bytemuck::bytes_of(p));
            uploads.write(
                &self.counters_second,
                0,
                bytemuck::bytes_of(&QueryCounters::default()),
            );
        }
        let group = |params: &wgpu::Buffer, counters: &wgpu::Buffer| {
            pass.bind_group(
                device,
                "query",
                &[
                    ("params", params.as_entire_binding()),
                    ("job_list", self.job_list.as_entire_binding()),
                    ("wave_jobs", self.wave_jobs.as_entire_binding()),
                    ("instances", pool.instances.buffer.as_entire_binding()),
                    ("records", pool.records.buffer.as_entire_binding()),
                    ("hiz", self.hiz.as_entire_binding()),
                    ("state", pool.state.buffer.as_entire_binding()),
                    ("counters", counters.as_entire_binding()),
                    ("out_instances", self.out_instances.as_entire_binding()),
                    ("out_batches", self.out_batches.as_entire_binding()),
                ],
            )
        };
        let first = group(&self.params, &self.counters)?;
        let second = match second {
            Some(_) => Some(group(&self.params_second, &self.counters_second)?),
            None => None,
        };
        Ok(PreparedView {
            group: first,
            second,
            plan,
            threads,
            cap,
            shadow,
            own: None,
        })
    }

    /// The pre-cull of each of a frame's shadow views (`params`, each with
    /// `QUERY_FLAG_SHADOW`, from `ViewDesc::shadow`) on `scene`, and the uploads and bind
    /// groups of their dispatches: each view its own uniforms, job tables and counters,
    /// all of them one output pair grown to the largest view's threads. Record each view
    /// and its placement before the next view's query (they share the outputs). Shadow
    /// views write no fade or camera state, and their pre-cull leaves the scene's fade
    /// bookkeeping alone, so the camera view's query is unaffected by them.
    ///
    /// # Errors
    /// [`Error::Config`](crate::Error::Config) for params without `QUERY_FLAG_SHADOW`;
    /// [`Error::DeviceLimit`](crate::Error::DeviceLimit) when an output passes
    /// `max_storage_buffer_binding_size`.
    pub(crate) fn prepare_shadow_views(
        &mut self,
        device: &wgpu::Device,
        uploads: &mut dyn UploadSink,
        scene: &mut staticscene::Scene,
        params: &[QueryParams],
        options: &QueryOptions,
    ) -> Result<Vec<PreparedView>> {
        if params
            .iter()
            .any(|p| !p.has(staticscene::QUERY_FLAG_SHADOW))
        {
            return Err(crate::Error::Config {
                field: "static shadow view (QueryParams::flags)",
                value: 0.0,
                allowed: "views with QUERY_FLAG_SHADOW (ViewDesc::shadow)",
            });
        }
        let pool = &self.pool;
        let plans: Vec<GpuPlan> = params
            .iter()
            .map(|p| scene.plan_gpu(p, options, |id| pool.slots(id)))
            .collect();
        while self.shadow_views.len() < params.len() {
            self.shadow_views.push(ShadowViewBuffers {
                params: device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("static shadow query params"),
                    size: size_of::<QueryParams>() as u64,
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }),
                job_list: empty_storage(device, "static shadow query jobs", 4096)?,
                wave_jobs: empty_storage(device, "static shadow query wave jobs", 4096)?,
                counters: empty_storage(device, "static shadow query counters", 256)?,
            });
        }
        // Every thread of the largest view may output one instance and one header.
        let cap = plans
            .iter()
            .map(GpuPlan::instances)
            .max()
            .unwrap_or(0)
            .max(1);
        let inst_bytes = cap * size_of::<DrawableSetupInstance>() as u64;
        if self.shadow_out_instances.size() < inst_bytes {
            self.shadow_out_instances =
                empty_storage(device, "static shadow query instances", inst_bytes)?;
            self.shadow_out_batches = empty_storage(
                device,
                "static shadow query batches",
                cap * size_of::<DrawableSetupBatch>() as u64,
            )?;
        }
        let mut views = Vec::with_capacity(plans.len());
        for ((plan, p), k) in plans.into_iter().zip(params).zip(0..) {
            let b = &mut self.shadow_views[k];
            let jobs = plan.job_list();
            let job_bytes = jobs.len() as u64 * 4;
            if b.job_list.size() < job_bytes {
                b.job_list = empty_storage(device, "static shadow query jobs", job_bytes * 2)?;
            }
            let wave_jobs = plan.wave_jobs();
            let table_bytes = wave_jobs.len() as u64 * 4;
            if b.wave_jobs.size() < table_bytes {
                b.wave_jobs =
                    empty_storage(device, "static shadow query wave jobs", table_bytes * 2)?;
            }
            uploads.write(&b.params, 0, bytemuck::bytes_of(p));
            uploads.write(&b.job_list, 0, bytemuck::cast_slice(&jobs));
            uploads.write(&b.wave_jobs, 0, bytemuck::cast_slice(&wave_jobs));
            uploads.write(
                &b.counters,
                0,
                bytemuck::bytes_of(&QueryCounters::default()),
            );
            let group = self.shadow_pass.bind_group(
                device,
                "query",
                &[
                    ("params", b.params.as_entire_binding()),
                    ("job_list", b.job_list.as_entire_binding()),
                    ("wave_jobs", b.wave_jobs.as_entire_binding()),
                    ("instances", self.pool.instances.buffer.as_entire_binding()),
                    ("records", self.pool.records.buffer.as_entire_binding()),
                    ("hiz", self.hiz.as_entire_binding()),
                    ("state", self.pool.state.buffer.as_entire_binding()),
                    ("counters", b.counters.as_entire_binding()),
                    (
                        "out_instances",
                        self.shadow_out_instances.as_entire_binding(),
                    ),
                    ("out_batches", self.shadow_out_batches.as_entire_binding()),
                ],
            )?;
            let threads = plan.instances();
            views.push(PreparedView {
                group,
                second: None,
                plan,
                threads,
                cap,
                shadow: true,
                own: Some(ViewOutputs {
                    counters: b.counters.clone(),
                    instances: self.shadow_out_instances.clone(),
                    batches: self.shadow_out_batches.clone(),
                }),
            });
        }
        Ok(views)
    }

    /// The buffers a prepared view's (first or only) pass writes: a shadow view's own, or
    /// the camera view's.
    pub(crate) fn view_outputs<'a>(&'a self, view: &'a PreparedView) -> QueryOutputs<'a> {
        match &view.own {
            Some(o) => QueryOutputs {
                counters: &o.counters,
                instances: &o.instances,
                batches: &o.batches,
            },
            None => self.outputs(false),
        }
    }

    /// Reads a prepared view's counters back (after its submission).
    pub(crate) fn read_view_counters(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        view: &PreparedView,
    ) -> Result<QueryCounters> {
        Ok(bytemuck::pod_read_unaligned(&read_buffer(
            device,
            queue,
            self.view_outputs(view).counters,
            0,
            size_of::<QueryCounters>() as u64,
        )?))
    }

    /// Records a prepared view's dispatch: its first (or only) pass, or with `second`
    /// the second pass of two-pass occlusion (nothing if it was prepared without one).
    pub(crate) fn record_view(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        view: &PreparedView,
        second: bool,
    ) {
        let group = if second {
            view.second.as_ref()
        } else {
            Some(&view.group)
        };
        let variant = if view.shadow {
            &self.shadow_pass
        } else {
            &self.pass
        };
        if let Some(g) = group {
            variant.record(pass, &[g], &view.plan.dispatch());
        }
    }

    /// The buffers a pass of the query writes (the static placement reads them).
    pub(crate) fn outputs(&self, second: bool) -> QueryOutputs<'_> {
        QueryOutputs {
            counters: if second {
                &self.counters_second
            } else {
                &self.counters
            },
            instances: &self.out_instances,
            batches: &self.out_batches,
        }
    }

    /// Reads the counters of a pass of the last recorded view back (after its submission).
    pub(crate) fn read_counters(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        second: bool,
    ) -> Result<QueryCounters> {
        Ok(bytemuck::pod_read_unaligned(&read_buffer(
            device,
            queue,
            self.outputs(second).counters,
            0,
            size_of::<QueryCounters>() as u64,
        )?))
    }

    /// Runs one view's query: the pre-cull on `scene` (which must hold the tiles
    /// activated here; it keeps the clusters' stale flags and last runs), the pass, and
    /// the read-back of `readback`. Blocks until the GPU is done (HZD's mode). Shadow views
    /// (`QUERY_FLAG_SHADOW`, from `ViewDesc::shadow`) run the pass's shadow variant.
    ///
    /// # Errors
    /// [`Error::DeviceLimit`](crate::Error::DeviceLimit) when the output for every
    /// dispatched thread passes `max_storage_buffer_binding_size`; device errors
    /// (validation, out of memory, mapping).
    pub fn run(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &mut staticscene::Scene,
        params: &QueryParams,
        options: &QueryOptions,
        readback: QueryReadback,
    ) -> Result<StaticQueryOutput> {
        let view = self.prepare_view(device, &mut queue.clone(), scene, params, None, options)?;
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("static query"),
        });
        {
            let mut pass = self.timer.begin_compute(&mut encoder, "static query");
            self.record_view(&mut pass, &view, false);
        }
        self.timer.resolve(&mut encoder);
        queue.submit([encoder.finish()]);
        let gpu_ms = self.timer.read(device, queue)?.first().map(|t| t.ms);
        let counters = self.read_counters(device, queue, false)?;
        let cap = view.cap;
        let mut out = StaticQueryOutput {
            stats: counters.stats(&view.plan.stats),
            threads: view.threads,
            gpu_ms,
            skipped_tiles: view.plan.skipped_tiles,
            ..StaticQueryOutput::default()
        };
        if readback == QueryReadback::Full {
            let n = u64::from(counters.instances).min(cap);
            let b = u64::from(counters.batches).min(cap);
            out.instances = bytemuck::pod_collect_to_vec(&read_buffer(
                device,
                queue,
                &self.out_instances,
                0,
                n * size_of::<DrawableSetupInstance>() as u64,
            )?);
            out.batches = bytemuck::pod_collect_to_vec(&read_buffer(
                device,
                queue,
                &self.out_batches,
                0,
                b * size_of::<DrawableSetupBatch>() as u64,
            )?);
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use staticscene::pass::HizStep;

    #[test]
    fn hiz_depth_matches_its_description_and_the_reduction_uniform() {
        shadercheck::check_pass(&crate::passes::depth_reductions::HIZ_DEPTH, |_| {
            shadercheck::Caps::CORE
        });
        let m = shadercheck::assert_composed(
            crate::shaders::LIBRARY,
            "gpu::hiz_depth",
            &[],
            shadercheck::Caps::CORE,
        );
        assert_eq!(
            shadercheck::const_u32(&m, "GPU_HIZ_DEPTH_LEVELS_PER_DISPATCH"),
            Some(crate::passes::depth_reductions::HIZ_LEVELS_PER_DISPATCH as u32)
        );
        shadercheck::assert_struct_layout(
            &m,
            "GpuHizDepthStep",
            size_of::<HizStep>(),
            &shadercheck::members!(HizStep {
                level,
                reversed,
                pad
            }),
        );
    }
}
