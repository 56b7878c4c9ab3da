//! HZD's static-scene query on the GPU (seed 001): `staticscene`'s [`QUERY_PASS`] over
//! the pooled records of every active tile ([`StaticPool`]), one dispatch per view, the
//! CPU's part being the pre-cull ([`staticscene::Scene::plan_gpu`]).
//!
//! [`StaticQuery::run`] is HZD's mode: the CPU waits for the query and reads its batches
//! back (what a CPU renderer, or `tiling::build_plan`, then consumes).

use shader::pipeline::ComputePass;
use staticscene::pass::{GpuPlan, QUERY_PASS, QueryCounters, QueryDispatch, hiz_words};
use staticscene::{
    DrawableSetupBatch, DrawableSetupInstance, HiZ, QueryOptions, QueryParams, QueryStats,
    StaticTile, TileId,
};

use super::static_place::QueryOutputs;
use crate::error::Result;
use crate::resources::readback::read_buffer;
use crate::resources::static_pool::{StaticPool, empty_storage};
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

/// One view's pre-cull and dispatch, ready to record.
pub(crate) struct PreparedView {
    group: wgpu::BindGroup,
    /// The pre-cull's jobs and statistics.
    pub plan: GpuPlan,
    /// Threads dispatched.
    pub threads: u64,
    /// Records the output buffers hold.
    pub cap: u64,
}

/// The GPU static query: the pass, the tile pool and the per-view buffers.
pub struct StaticQuery {
    pass: ComputePass<QueryDispatch>,
    pool: StaticPool,
    params: wgpu::Buffer,
    job_list: wgpu::Buffer,
    hiz: wgpu::Buffer,
    counters: wgpu::Buffer,
    out_instances: wgpu::Buffer,
    out_batches: wgpu::Buffer,
    timer: GpuTimer,
}

impl StaticQuery {
    /// The pipeline and empty buffers.
    ///
    /// # Errors
    /// A composition error (a bug).
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> Result<Self> {
        let mut q = Self {
            pass: ComputePass::new(device, &QUERY_PASS, &[], &[])?,
            pool: StaticPool::new(device),
            params: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("static query params"),
                size: size_of::<QueryParams>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            job_list: empty_storage(device, "static query jobs", 4096)?,
            hiz: empty_storage(device, "static query hiz", 256)?,
            counters: empty_storage(device, "static query counters", 256)?,
            out_instances: empty_storage(device, "static query instances", 256)?,
            out_batches: empty_storage(device, "static query batches", 256)?,
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
        Ok(())
    }

    /// The pre-cull of one view on `scene`, and the uploads and bind group of its
    /// dispatch (the output buffers grown to one record per dispatched thread).
    pub(crate) fn prepare_view(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &mut staticscene::Scene,
        params: &QueryParams,
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
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(params));
        queue.write_buffer(&self.job_list, 0, bytemuck::cast_slice(&jobs));
        queue.write_buffer(
            &self.counters,
            0,
            bytemuck::bytes_of(&QueryCounters::default()),
        );
        let group = self.pass.bind_group(
            device,
            "query",
            &[
                ("params", self.params.as_entire_binding()),
                ("job_list", self.job_list.as_entire_binding()),
                ("instances", pool.instances.buffer.as_entire_binding()),
                ("records", pool.records.buffer.as_entire_binding()),
                ("hiz", self.hiz.as_entire_binding()),
                ("state", pool.state.buffer.as_entire_binding()),
                ("counters", self.counters.as_entire_binding()),
                ("out_instances", self.out_instances.as_entire_binding()),
                ("out_batches", self.out_batches.as_entire_binding()),
            ],
        )?;
        Ok(PreparedView {
            group,
            plan,
            threads,
            cap,
        })
    }

    /// Records a prepared view's dispatch.
    pub(crate) fn record_view(&self, pass: &mut wgpu::ComputePass<'_>, view: &PreparedView) {
        self.pass
            .record(pass, &[&view.group], &view.plan.dispatch());
    }

    /// The buffers the query writes (the static placement reads them).
    pub(crate) fn outputs(&self) -> QueryOutputs<'_> {
        QueryOutputs {
            counters: &self.counters,
            instances: &self.out_instances,
            batches: &self.out_batches,
        }
    }

    /// Reads the counters of the last recorded view back (after its submission).
    pub(crate) fn read_counters(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<QueryCounters> {
        Ok(bytemuck::pod_read_unaligned(&read_buffer(
            device,
            queue,
            &self.counters,
            0,
            size_of::<QueryCounters>() as u64,
        )?))
    }

    /// Runs one view's query: the pre-cull on `scene` (which must hold the tiles
    /// activated here; it keeps the clusters' stale flags and last runs), the pass, and
    /// the read-back of `readback`. Blocks until the GPU is done (HZD's mode).
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
        let view = self.prepare_view(device, queue, scene, params, options)?;
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("static query"),
        });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("static query"),
                timestamp_writes: self.timer.compute("static query"),
            });
            self.record_view(&mut pass, &view);
        }
        self.timer.resolve(&mut encoder);
        queue.submit([encoder.finish()]);
        let gpu_ms = self.timer.read(device, queue)?.first().map(|t| t.ms);
        let counters = self.read_counters(device, queue)?;
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
