//! HFW's vertex side on the GPU (seed 000, "vertex wave commands" and the ring buffer):
//! after the classification, `tiling`'s vertex wave commands are built from mid
//! classify's vertex cull buffer (`tiling::wgsl::VERTEX_WAVES`: uber chunks, histogram
//! pyramid, micro-batch deltas and their scan, commands, one `PassDispatch` per pass), then
//! per pass one `dispatch_workgroups_indirect` of the transform (`gpu::vertex_ring`), a
//! 64-lane workgroup per command, writes each visible chunk's vertices as
//! `visbuf::VisbufVertex` (32 bytes) into the ring.
//!
//! Ring slots: pass `p` owns half `p mod 2` of the ring, and in it each micro batch the
//! range `tiling` planned at its `ring_offset` (a pass's vertices fit half the ring), vertex
//! `instance * vertex_count + vertex` of the micro batch ([`ring_slot`], WGSL
//! `gpu_ring_slot`). Passes the ring cannot bound (the static setups', whose visible
//! counts only the GPU knows) are not transformed; the resolve transforms their vertices
//! per pixel.

use shader::pipeline::ComputePass;
use shader::{Binding, Dispatch, Entry, Group, Kind, Pass, Size, Stage};
use tiling::{MicroBatchInfo, PassDispatch, PassInfo, TilingParams, UberChunk, VertexWaveCommand};

use super::context::FrameContext;
use super::raster::SCENE_GROUP;
use crate::error::Result;
use crate::resources::buffers::buffer_init;
pub(crate) use crate::resources::groups::RingBuffers as Buffers;
use crate::resources::ring::RING_NONE;
use crate::resources::ring::RING_PASS_UNIFORM_BYTES;
use crate::resources::ring::RING_VERTEX_BYTES;
use crate::resources::rows::{GpuMesh, GpuMicroBatch};
use crate::shaders::LIBRARY;
use crate::timing::GpuTimer;

/// The transform into the ring (dispatched indirectly, one pass at a time).
pub(crate) const VERTEX_RING: Pass<u32> = Pass {
    name: "vertex ring transform",
    module: "gpu::vertex_ring",
    library: LIBRARY,
    features: &[],
    groups: &[
        SCENE_GROUP,
        Group {
            name: "ring",
            bindings: &[
                Binding::new("table", Kind::read(size_of::<MicroBatchInfo>())),
                Binding::new("meshes", Kind::read(size_of::<GpuMesh>())),
                Binding::new("micro_batches", Kind::read(size_of::<GpuMicroBatch>())),
                Binding::new(
                    "vertex_commands",
                    Kind::read(size_of::<VertexWaveCommand>()),
                ),
                Binding::new("vertex_dispatches", Kind::read(size_of::<PassDispatch>())),
                Binding::new("ring", Kind::read_write(RING_VERTEX_BYTES as usize)),
                Binding::new(
                    "ring_pass",
                    Kind::Uniform {
                        size: RING_PASS_UNIFORM_BYTES as u32,
                        dynamic: true,
                    },
                ),
            ],
        },
    ],
    entries: &[Entry {
        name: "transform_vertices",
        stage: Stage::Compute([Size::Fixed(64), Size::Fixed(1), Size::Fixed(1)]),
        dispatch: Dispatch::Indirect("vertex_dispatches"),
    }],
    zeroed: &[],
};

/// The vertex side's pipelines: tiling's vertex wave commands and the transform.
pub(crate) struct VertexRing {
    waves: ComputePass<TilingParams>,
    transform: ComputePass<u32>,
}

impl VertexRing {
    pub(crate) fn new(device: &wgpu::Device) -> Result<Self> {
        Ok(Self {
            waves: ComputePass::new(device, &tiling::wgsl::VERTEX_WAVES, &[], &[])?,
            transform: ComputePass::new(device, &VERTEX_RING, &[], &[])?,
        })
    }

    /// A prepared scene's buffers: `plan`'s table, order buffer and passes, the vertex cull
    /// buffer of its classification (`params` its uniform), a ring of `ring_bytes`.
    #[expect(
        clippy::too_many_arguments,
        reason = "one call site; every buffer a distinct binding"
    )]
    pub(crate) fn buffers(
        &self,
        device: &wgpu::Device,
        plan: &tiling::Plan,
        params: TilingParams,
        vertex_cull: &wgpu::Buffer,
        scene: &[(&str, wgpu::BindingResource<'_>)],
        meshes: &wgpu::Buffer,
        micro_batches: &wgpu::Buffer,
        ring_bytes: u64,
    ) -> Result<Buffers> {
        let storage = |label: &str, bytes: u64, extra: wgpu::BufferUsages| {
            crate::resources::buffers::storage_buffer(device, label, bytes.max(16), extra)
        };
        let none = wgpu::BufferUsages::empty();
        let chunks = u64::from(params.chunk_count.max(1));
        let pyramid_len: u64 = tiling::vertex::pyramid_levels(params.uber_count)
            .iter()
            .map(|&(_, l)| u64::from(l))
            .sum();
        let passes = plan.passes.len().max(1) as u64;
        let ring_vertices = u32::try_from(ring_bytes / RING_VERTEX_BYTES).unwrap_or(u32::MAX);
        let half = ring_vertices / 2;
        // Passes whose planned vertices fit half the ring (the planned ones; the static
        // setups' saturate their counts).
        let half_base: Vec<u32> = plan
            .passes
            .iter()
            .enumerate()
            .map(|(p, info): (usize, &PassInfo)| {
                if info.vertex_count <= half {
                    (p as u32 % 2) * half
                } else {
                    RING_NONE
                }
            })
            .collect();
        let stride = u64::from(device.limits().min_uniform_buffer_offset_alignment)
            .max(RING_PASS_UNIFORM_BYTES);
        let mut uniform = vec![0u8; (stride * passes) as usize];
        for (p, &base) in half_base.iter().enumerate() {
            let at = (stride * p as u64) as usize;
            uniform[at..at + 4].copy_from_slice(&(p as u32).to_le_bytes());
            uniform[at + 4..at + 8].copy_from_slice(&base.to_le_bytes());
        }
        let pass_uniforms = buffer_init(
            device,
            "ring pass uniforms",
            &uniform,
            0,
            wgpu::BufferUsages::UNIFORM,
        );
        let params_buffer = buffer_init(
            device,
            "vertex waves params",
            bytemuck::bytes_of(&params),
            0,
            wgpu::BufferUsages::UNIFORM,
        );
        let table = buffer_init(
            device,
            "vertex waves table",
            bytemuck::cast_slice(&plan.table),
            size_of::<MicroBatchInfo>() as u64,
            wgpu::BufferUsages::STORAGE,
        );
        let order = buffer_init(
            device,
            "micro-batch order",
            bytemuck::cast_slice(&plan.order),
            4,
            wgpu::BufferUsages::STORAGE,
        );
        let pass_infos = buffer_init(
            device,
            "pass infos",
            bytemuck::cast_slice(&plan.passes),
            size_of::<PassInfo>() as u64,
            wgpu::BufferUsages::STORAGE,
        );
        let ubers = storage(
            "uber chunks",
            chunks.div_ceil(64) * size_of::<UberChunk>() as u64,
            none,
        )?;
        let pyramid = storage("histogram pyramid", pyramid_len * 4, none)?;
        let deltas = storage("micro-batch deltas", chunks * 4, none)?;
        let delta_blocks = storage(
            "micro-batch delta blocks",
            u64::from(tiling::vertex::delta_block_count(params.chunk_count)) * 4,
            none,
        )?;
        let micro_batch_waves = storage(
            "micro-batch vertex waves",
            plan.order.len() as u64 * 4,
            none,
        )?;
        let vertex_commands = storage(
            "vertex wave commands",
            chunks * size_of::<VertexWaveCommand>() as u64,
            none,
        )?;
        let vertex_dispatches = storage(
            "vertex dispatches",
            passes * size_of::<PassDispatch>() as u64,
            wgpu::BufferUsages::INDIRECT,
        )?;
        let pass_items = storage("pass vertex items", passes * 4, none)?;
        let totals = storage("vertex totals", size_of::<tiling::Totals>() as u64, none)?;
        let ring = storage(
            "vertex ring",
            u64::from(ring_vertices) * RING_VERTEX_BYTES,
            none,
        )?;
        let waves_group = self.waves.bind_group(
            device,
            tiling::wgsl::VERTEX_WAVES.groups[0].name,
            &[
                ("params", params_buffer.as_entire_binding()),
                ("table", table.as_entire_binding()),
                ("order", order.as_entire_binding()),
                ("pass_infos", pass_infos.as_entire_binding()),
                ("vertex_cull", vertex_cull.as_entire_binding()),
                ("ubers", ubers.as_entire_binding()),
                ("pyramid", pyramid.as_entire_binding()),
                ("deltas", deltas.as_entire_binding()),
                ("micro_batch_waves", micro_batch_waves.as_entire_binding()),
                ("vertex_commands", vertex_commands.as_entire_binding()),
                ("vertex_dispatches", vertex_dispatches.as_entire_binding()),
                ("pass_items", pass_items.as_entire_binding()),
                ("totals", totals.as_entire_binding()),
                ("delta_blocks", delta_blocks.as_entire_binding()),
            ],
        )?;
        let ring_group = self.transform.bind_group(
            device,
            "ring",
            &[
                ("table", table.as_entire_binding()),
                ("meshes", meshes.as_entire_binding()),
                ("micro_batches", micro_batches.as_entire_binding()),
                ("vertex_commands", vertex_commands.as_entire_binding()),
                ("vertex_dispatches", vertex_dispatches.as_entire_binding()),
                ("ring", ring.as_entire_binding()),
                (
                    "ring_pass",
                    wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &pass_uniforms,
                        offset: 0,
                        size: wgpu::BufferSize::new(RING_PASS_UNIFORM_BYTES),
                    }),
                ),
            ],
        )?;
        Ok(Buffers {
            params,
            ring_vertices,
            half_base,
            ubers,
            pyramid,
            deltas,
            micro_batch_waves,
            vertex_commands,
            vertex_dispatches,
            pass_items,
            totals,
            ring,
            _pass_uniforms: pass_uniforms,
            pass_stride: stride as u32,
            waves_group,
            scene_group: self.transform.bind_group(device, "scene", scene)?,
            ring_group,
            _kept: [params_buffer, table, order, pass_infos, delta_blocks],
        })
    }

    /// Records the vertex wave commands (after mid classify has written the cull buffer),
    /// each pass's transform, in one timed compute pass each.
    pub(crate) fn record_waves(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        b: &Buffers,
        timer: &mut GpuTimer,
    ) {
        encoder.clear_buffer(&b.deltas, 0, None);
        encoder.clear_buffer(&b.pass_items, 0, None);
        let mut pass = timer.begin_compute(encoder, tiling::wgsl::VERTEX_WAVES.name);
        pass.set_bind_group(0, &b.waves_group, &[]);
        for step in &self.waves.steps {
            if let Some([x, y, z]) = self.waves.workgroups(step, &b.params) {
                pass.set_pipeline(&step.pipeline);
                pass.dispatch_workgroups(x, y, z);
            }
        }
    }

    /// Records the transform of pass `p` (one indirect dispatch) into `pass`.
    pub(crate) fn record_transform(&self, pass: &mut wgpu::ComputePass<'_>, b: &Buffers, p: u32) {
        if b.half_base.get(p as usize).is_none_or(|&h| h == RING_NONE) {
            return;
        }
        pass.set_pipeline(&self.transform.steps[0].pipeline);
        pass.set_bind_group(0, &b.scene_group, &[]);
        pass.set_bind_group(1, &b.ring_group, &[p * b.pass_stride]);
        pass.dispatch_workgroups_indirect(
            &b.vertex_dispatches,
            u64::from(p) * size_of::<PassDispatch>() as u64,
        );
    }

    /// Records pass `p`'s transform in a compute pass of its own, timed under the
    /// transform's label (summed over the passes).
    pub(crate) fn record_transform_timed(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        b: &Buffers,
        p: u32,
        timer: &mut GpuTimer,
    ) {
        if b.half_base.get(p as usize).is_none_or(|&h| h == RING_NONE) {
            return;
        }
        let mut pass = timer.begin_compute(encoder, VERTEX_RING.name);
        self.record_transform(&mut pass, b, p);
    }

    /// Records every pass's transform in one timed compute pass (the frame interleaves
    /// them with the resolve when it reads the ring).
    pub(crate) fn record_transforms(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
    ) {
        let Some(b) = &f.scene.vertex_ring else {
            return;
        };
        let mut pass = timer.begin_compute(encoder, VERTEX_RING.name);
        for p in 0..b.half_base.len() as u32 {
            self.record_transform(&mut pass, b, p);
        }
    }
}

/// Everything the vertex side wrote in the last deferred frame, read back
/// ([`Inspect::read_vertex_ring`](crate::inspect::Inspect::read_vertex_ring)).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VertexRingReadback {
    /// The uber chunks (one per 64 chunks of the cull buffer).
    pub ubers: Vec<UberChunk>,
    /// The histogram pyramid, levels bottom first.
    pub pyramid: Vec<u32>,
    /// Per visible chunk: its micro-batch ID (the deltas after the scan).
    pub micro_batch_ids: Vec<u32>,
    /// Per order entry: its vertex waves.
    pub micro_batch_waves: Vec<u32>,
    /// The vertex wave commands, one per visible chunk.
    pub commands: Vec<VertexWaveCommand>,
    /// Per pass: the transform's indirect dispatch (`items`: vertices transformed).
    pub dispatches: Vec<PassDispatch>,
    /// Visible chunks (the GPU's own count).
    pub visible_chunks: u32,
    /// Slots of the ring.
    pub ring_vertices: u32,
    /// Per pass: its half's first slot, or `u32::MAX` for a pass the ring does not hold.
    pub half_base: Vec<u32>,
    /// The whole ring (slots of culled chunks hold older frames' vertices or zeros).
    pub ring: Vec<visbuf::VisbufVertex>,
}

impl VertexRingReadback {
    /// Vertices transformed in the ring (the talk's "vertices after culling", counted by
    /// the GPU: the dispatches' items of the passes the ring holds).
    #[must_use]
    pub fn vertices_transformed(&self) -> u64 {
        self.dispatches
            .iter()
            .zip(&self.half_base)
            .filter(|&(_, &h)| h != RING_NONE)
            .map(|(d, _)| u64::from(d.items))
            .sum()
    }

    /// Reads every buffer back (waits for the GPU).
    pub(crate) fn read(device: &wgpu::Device, queue: &wgpu::Queue, b: &Buffers) -> Result<Self> {
        use crate::resources::readback::read_buffer;
        let all = |buf: &wgpu::Buffer| read_buffer(device, queue, buf, 0, buf.size());
        let totals: tiling::Totals = bytemuck::pod_read_unaligned(&read_buffer(
            device,
            queue,
            &b.totals,
            0,
            size_of::<tiling::Totals>() as u64,
        )?);
        let visible = totals.visible_chunks.min(b.params.chunk_count) as usize;
        let pyramid_len: usize = tiling::vertex::pyramid_levels(b.params.uber_count)
            .iter()
            .map(|&(_, l)| l as usize)
            .sum();
        let passes = b.half_base.len();
        let ids: Vec<u32> = bytemuck::pod_collect_to_vec(&all(&b.deltas)?);
        let pyramid: Vec<u32> = bytemuck::pod_collect_to_vec(&all(&b.pyramid)?);
        let ubers: Vec<UberChunk> = bytemuck::pod_collect_to_vec(&all(&b.ubers)?);
        let waves: Vec<u32> = bytemuck::pod_collect_to_vec(&all(&b.micro_batch_waves)?);
        let commands: Vec<VertexWaveCommand> =
            bytemuck::pod_collect_to_vec(&all(&b.vertex_commands)?);
        let dispatches: Vec<PassDispatch> =
            bytemuck::pod_collect_to_vec(&all(&b.vertex_dispatches)?);
        Ok(Self {
            ubers: ubers[..b.params.uber_count as usize].to_vec(),
            pyramid: pyramid[..pyramid_len].to_vec(),
            micro_batch_ids: ids[..visible].to_vec(),
            micro_batch_waves: waves[..b.params.micro_batch_count as usize].to_vec(),
            commands: commands[..visible].to_vec(),
            dispatches: dispatches[..passes].to_vec(),
            visible_chunks: totals.visible_chunks,
            ring_vertices: b.ring_vertices,
            half_base: b.half_base.clone(),
            ring: bytemuck::pod_collect_to_vec(&all(&b.ring)?),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::resources::ring::RING_UV_FROM_VERTICES;
    use crate::resources::ring::ring_slot;

    #[test]
    fn description_matches_its_module() {
        shadercheck::check_pass(&VERTEX_RING, |_| shadercheck::Caps::CORE);
    }

    #[test]
    fn ring_constants_match_the_wgsl() {
        let m =
            shadercheck::assert_composed(LIBRARY, "gpu::ring_slots", &[], shadercheck::Caps::CORE);
        assert_eq!(shadercheck::const_u32(&m, "GPU_RING_NONE"), Some(RING_NONE));
        assert_eq!(
            shadercheck::const_u32(&m, "GPU_RING_UV_FROM_VERTICES"),
            Some(u32::from(RING_UV_FROM_VERTICES))
        );
    }

    #[test]
    fn passes_alternate_halves() {
        assert_eq!(ring_slot(1000, 0, 10, 7, 2, 3), 10 + 14 + 3);
        assert_eq!(ring_slot(1000, 3, 10, 7, 2, 3), 500 + 10 + 14 + 3);
    }
}
