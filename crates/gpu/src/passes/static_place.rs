//! The static query's output placed in the frame (`gpu::static_place`), with no CPU round
//! trip: each of HZD's batches claims a run of its setup's reserved instance slots and
//! writes their rows (transform, vis-word fields of their rank, material), then every setup
//! with placed instances appends one indexed indirect draw to the opaque or alpha-tested
//! list, whose counts the laydown and the baseline draw with
//! (`multi_draw_indexed_indirect_count`, or `multi_draw_indexed_indirect` over zeroed
//! lists).
//!
//! With two-pass occlusion the placement runs again after the query's second pass: its
//! instances take the next slots, the full lists are rewritten to cover the whole frame,
//! and late lists hold only the new instances, for the laydown's second geometry pass.
//!
//! Slots and IDs come from `tiling::Plan::reserve` at prepare (one reserved range per
//! setup), so the classification and the resolve find a static instance exactly as a
//! planned one: vis ID -> micro batch row -> instance slot.

use shader::pipeline::ComputePass;
use shader::{Binding, Dispatch, Entry, Group, Kind, Pass, Stage};
use staticscene::{DrawableSetupBatch, DrawableSetupInstance};

use super::LIBRARY;
use crate::error::Result;
use crate::resources::rows::{GpuInstance, GpuStaticParams, GpuStaticSetup};
use crate::timing::GpuTimer;

/// `counters` word: draws appended to the full opaque list (the alpha-tested list's is
/// next).
pub(crate) const STATIC_COUNTER_DRAWS: u32 = 0;
/// `counters` word: draws appended to the late opaque list (the alpha-tested one's is next).
pub(crate) const STATIC_COUNTER_LATE_DRAWS: u32 = 2;
/// `counters` word: instances dropped past their setup's capacity.
pub(crate) const STATIC_COUNTER_OVER_CAPACITY: u32 = 4;
/// `counters` word: batches dropped (no such setup, or a source past the query's buffers).
pub(crate) const STATIC_COUNTER_BAD_BATCHES: u32 = 5;
/// `counters` word of setup 0's placed instances (setup `s` at `+ s`); then, per setup,
/// those placed by the frame's first run.
pub(crate) const STATIC_COUNTER_PLACED: u32 = 6;
/// Debug word: the first bit of the query's state flags (bits 8-15); the fade opacity,
/// 0-255, is in bits 0-7.
pub(crate) const STATIC_DEBUG_FLAGS_SHIFT: u32 = 8;
/// Debug word bit: placed by the frame's second placement (two-pass occlusion).
pub(crate) const STATIC_DEBUG_LATE: u32 = 0x1_0000;
/// Bytes of one `DrawIndexedIndirect`.
pub(crate) const DRAW_BYTES: u64 = 20;

/// The placement; the parameter is the setup count.
pub(crate) const STATIC_PLACE: Pass<u32> = Pass {
    name: "static placement",
    module: "gpu::static_place",
    library: LIBRARY,
    features: &[],
    groups: &[Group {
        name: "place",
        bindings: &[
            Binding::new("params", Kind::uniform(size_of::<GpuStaticParams>())),
            Binding::new("setups", Kind::read(size_of::<GpuStaticSetup>())),
            Binding::new("query_counters", Kind::read(4)),
            Binding::new(
                "query_instances",
                Kind::read(size_of::<DrawableSetupInstance>()),
            ),
            Binding::new("query_batches", Kind::read(size_of::<DrawableSetupBatch>())),
            Binding::new("counters", Kind::read_write(4)),
            Binding::new("instances", Kind::read_write(size_of::<GpuInstance>())),
            Binding::new("place_dispatch", Kind::read_write(4)),
            Binding::new("draws", Kind::read_write(4)),
            Binding::new("debug", Kind::read_write(4)),
        ],
    }],
    entries: &[
        Entry::once("place_args", 1),
        Entry {
            name: "place",
            // One workgroup per batch: a batch is at most one query workgroup long.
            stage: Stage::compute(staticscene::pass::QUERY_WORKGROUP, 1, 1),
            dispatch: Dispatch::Indirect("place_dispatch"),
        },
        Entry {
            name: "place_late",
            stage: Stage::compute(staticscene::pass::QUERY_WORKGROUP, 1, 1),
            dispatch: Dispatch::Indirect("place_dispatch"),
        },
        Entry::items("emit_draws", 64, |setups| *setups),
        Entry::items("emit_late_draws", 64, |setups| *setups),
    ],
    zeroed: &["counters"],
};

/// The placement's pipelines.
pub(crate) struct StaticPlace {
    pass: ComputePass<u32>,
    place_args: usize,
    place: usize,
    place_late: usize,
    emit: usize,
    emit_late: usize,
}

/// A prepared scene's static buffers: the setup table, the per-frame constants and
/// counters, the placement's indirect dispatch and the two draw lists.
pub(crate) struct StaticBuffers {
    pub setups: wgpu::Buffer,
    pub params: wgpu::Buffer,
    /// `STATIC_COUNTER_*` words; the first four are the draw lists' count buffer.
    pub counters: wgpu::Buffer,
    pub place_dispatch: wgpu::Buffer,
    /// What `place` is dispatched from: `place_dispatch` copied (a buffer bound as storage
    /// in a dispatch cannot also be its indirect argument).
    pub place_indirect: wgpu::Buffer,
    /// The full lists: opaque draws (`opaque` of them), then alpha-tested draws
    /// (`alpha`); then the late lists, laid out alike.
    pub draws: wgpu::Buffer,
    /// One word per reserved slot (`debug_base` first): what placed it this frame.
    pub debug: wgpu::Buffer,
    /// The first reserved slot.
    pub debug_base: u32,
    /// Whether the placement writes debug words (the camera view's buffers only).
    pub debug_words: bool,
    /// One past the last reserved slot.
    pub slot_end: u64,
    pub setup_count: u32,
    pub opaque: u32,
    pub alpha: u32,
    /// Whether the lists are drawn with a count buffer (`MULTI_DRAW_INDIRECT_COUNT`).
    pub with_count: bool,
}

/// The query's output buffers of one frame.
pub(crate) struct QueryOutputs<'a> {
    pub counters: &'a wgpu::Buffer,
    pub instances: &'a wgpu::Buffer,
    pub batches: &'a wgpu::Buffer,
}

impl StaticBuffers {
    /// The buffers for `setups` (each list's setups counted from their `list`).
    pub(crate) fn new(device: &wgpu::Device, setups: &[GpuStaticSetup], with_count: bool) -> Self {
        use wgpu::BufferUsages as U;
        let opaque = setups.iter().filter(|s| s.list == 0).count() as u32;
        let debug_base = setups.iter().map(|s| s.first_slot).min().unwrap_or(0);
        let debug_end = setups
            .iter()
            .map(|s| u64::from(s.first_slot) + u64::from(s.capacity))
            .max()
            .unwrap_or(0);
        let alpha = setups.len() as u32 - opaque;
        let make = |label: &str, size: u64, usage: U| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size.max(16).next_multiple_of(4),
                usage: usage | U::COPY_DST | U::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        Self {
            setups: crate::resources::buffer_init(
                device,
                "static setups",
                bytemuck::cast_slice(setups),
                size_of::<GpuStaticSetup>() as u64,
                U::STORAGE,
            ),
            params: make(
                "static params",
                size_of::<GpuStaticParams>() as u64,
                U::UNIFORM,
            ),
            counters: make(
                "static counters",
                4 * (u64::from(STATIC_COUNTER_PLACED) + 2 * setups.len() as u64),
                U::STORAGE | U::INDIRECT,
            ),
            place_dispatch: make("static place dispatch", 12, U::STORAGE),
            place_indirect: make("static place indirect", 12, U::INDIRECT),
            draws: make(
                "static draws",
                2 * DRAW_BYTES * setups.len() as u64,
                U::STORAGE | U::INDIRECT,
            ),
            debug: make(
                "static debug words",
                4 * (debug_end - u64::from(debug_base)),
                U::STORAGE,
            ),
            debug_base,
            debug_words: true,
            slot_end: debug_end,
            setup_count: setups.len() as u32,
            opaque,
            alpha,
            with_count,
        }
    }

    /// A shadow view's buffers beside these (the camera view's): the same setup table,
    /// its own constants, counters, dispatch and draw lists, and no debug words (a
    /// 16-byte stand-in the placement never writes: its `debug_base` is `u32::MAX`).
    pub(crate) fn for_shadow_view(&self, device: &wgpu::Device) -> Self {
        use wgpu::BufferUsages as U;
        let make = |label: &str, size: u64, usage: U| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size.max(16).next_multiple_of(4),
                usage: usage | U::COPY_DST | U::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        Self {
            setups: self.setups.clone(),
            params: make(
                "static shadow params",
                size_of::<GpuStaticParams>() as u64,
                U::UNIFORM,
            ),
            counters: make(
                "static shadow counters",
                self.counters.size(),
                U::STORAGE | U::INDIRECT,
            ),
            place_dispatch: make("static shadow place dispatch", 12, U::STORAGE),
            place_indirect: make("static shadow place indirect", 12, U::INDIRECT),
            draws: make(
                "static shadow draws",
                self.draws.size(),
                U::STORAGE | U::INDIRECT,
            ),
            debug: make("static shadow debug stand-in", 16, U::STORAGE),
            debug_words: false,
            debug_base: self.debug_base,
            slot_end: self.slot_end,
            setup_count: self.setup_count,
            opaque: self.opaque,
            alpha: self.alpha,
            with_count: self.with_count,
        }
    }

    /// Reserved slots (rows of a shadow view's own instance buffer).
    pub(crate) fn reserved_slots(&self) -> u64 {
        self.slot_end - u64::from(self.debug_base)
    }

    /// The placement's constants for a query whose floating origin is `offset` (metres)
    /// from the scene's origin: rows in the scene's instance table with debug words, or,
    /// for shadow-view buffers, in the view's own rows (slot `debug_base` first) without.
    pub(crate) fn params(&self, offset: glam::Vec3) -> GpuStaticParams {
        GpuStaticParams {
            offset: offset.extend(0.0).to_array(),
            setup_count: self.setup_count,
            row_width: shader::MAX_WORKGROUPS_X,
            alpha_base: self.opaque,
            debug_base: if self.debug_words {
                self.debug_base
            } else {
                u32::MAX
            },
            row_base: if self.debug_words { 0 } else { self.debug_base },
            ..GpuStaticParams::default()
        }
    }
}

impl StaticPlace {
    pub(crate) fn new(device: &wgpu::Device) -> Result<Self> {
        let pass = ComputePass::new(device, &STATIC_PLACE, &[], &[])?;
        Ok(Self {
            place_args: pass.step_index("place_args")?,
            place: pass.step_index("place")?,
            place_late: pass.step_index("place_late")?,
            emit: pass.step_index("emit_draws")?,
            emit_late: pass.step_index("emit_late_draws")?,
            pass,
        })
    }

    /// The frame's bind group: the scene's static buffers and instance table, the query's
    /// outputs.
    pub(crate) fn group(
        &self,
        device: &wgpu::Device,
        b: &StaticBuffers,
        instances: &wgpu::Buffer,
        query: &QueryOutputs<'_>,
    ) -> Result<wgpu::BindGroup> {
        Ok(self.pass.bind_group(
            device,
            "place",
            &[
                ("params", b.params.as_entire_binding()),
                ("setups", b.setups.as_entire_binding()),
                ("query_counters", query.counters.as_entire_binding()),
                ("query_instances", query.instances.as_entire_binding()),
                ("query_batches", query.batches.as_entire_binding()),
                ("counters", b.counters.as_entire_binding()),
                ("instances", instances.as_entire_binding()),
                ("place_dispatch", b.place_dispatch.as_entire_binding()),
                ("draws", b.draws.as_entire_binding()),
                ("debug", b.debug.as_entire_binding()),
            ],
        )?)
    }

    /// Records the placement after the query: counters (and, without a count buffer, the
    /// draw lists) zeroed, the dispatch arguments, the placement, the draws. `late`: the
    /// frame's second run (two-pass occlusion): placed counts kept, the lists' counts
    /// zeroed, full and late lists written.
    pub(crate) fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        b: &StaticBuffers,
        group: &wgpu::BindGroup,
        timer: &mut GpuTimer,
        late: bool,
    ) {
        let label = if late {
            "static placement (late)"
        } else {
            "static placement"
        };
        self.record_labelled(encoder, b, group, timer, late, label);
    }

    /// [`StaticPlace::record`] timed under `label` (a shadow view's placement).
    pub(crate) fn record_labelled(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        b: &StaticBuffers,
        group: &wgpu::BindGroup,
        timer: &mut GpuTimer,
        late: bool,
        label: &'static str,
    ) {
        if late {
            encoder.clear_buffer(
                &b.counters,
                0,
                Some(4 * u64::from(STATIC_COUNTER_OVER_CAPACITY)),
            );
        } else {
            encoder.clear_buffer(&b.counters, 0, None);
        }
        if !b.with_count {
            encoder.clear_buffer(&b.draws, 0, None);
        }
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("static placement arguments"),
                timestamp_writes: None,
            });
            pass.set_bind_group(0, group, &[]);
            let args = &self.pass.steps[self.place_args];
            if let Some([x, y, z]) = self.pass.workgroups(args, &b.setup_count) {
                pass.set_pipeline(&args.pipeline);
                pass.dispatch_workgroups(x, y, z);
            }
        }
        encoder.copy_buffer_to_buffer(&b.place_dispatch, 0, &b.place_indirect, 0, 12);
        let mut pass = timer.begin_compute(encoder, label);
        pass.set_bind_group(0, group, &[]);
        let place = if late { self.place_late } else { self.place };
        pass.set_pipeline(&self.pass.steps[place].pipeline);
        pass.dispatch_workgroups_indirect(&b.place_indirect, 0);
        let emit = &self.pass.steps[if late { self.emit_late } else { self.emit }];
        if let Some([x, y, z]) = self.pass.workgroups(emit, &b.setup_count) {
            pass.set_pipeline(&emit.pipeline);
            pass.dispatch_workgroups(x, y, z);
        }
    }
}

/// Records static draw lists into a geometry pass: the opaque list with `opaque`, the
/// alpha-tested list with `alpha` (index buffer and bind groups are the caller's); the full
/// lists, or with `late` the late ones.
pub(crate) fn record_static_draws(
    pass: &mut wgpu::RenderPass<'_>,
    b: &StaticBuffers,
    opaque: &wgpu::RenderPipeline,
    alpha: &wgpu::RenderPipeline,
    late: bool,
) {
    let (block, count_word) = if late {
        (b.setup_count, STATIC_COUNTER_LATE_DRAWS)
    } else {
        (0, STATIC_COUNTER_DRAWS)
    };
    for (list, pipeline, first, count) in [
        (0u64, opaque, 0u32, b.opaque),
        (1, alpha, b.opaque, b.alpha),
    ] {
        if count == 0 {
            continue;
        }
        pass.set_pipeline(pipeline);
        let offset = u64::from(block + first) * DRAW_BYTES;
        if b.with_count {
            pass.multi_draw_indexed_indirect_count(
                &b.draws,
                offset,
                &b.counters,
                4 * (u64::from(count_word) + list),
                count,
            );
        } else {
            pass.multi_draw_indexed_indirect(&b.draws, offset, count);
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn description_matches_its_module() {
        shadercheck::check_pass(&super::STATIC_PLACE, |_| shadercheck::Caps::CORE);
    }

    #[test]
    fn counter_words_match_the_wgsl() {
        let src = shadercheck::assert_composed(
            super::LIBRARY,
            "gpu::static_place",
            &[],
            shadercheck::Caps::CORE,
        );
        for (name, value) in [
            ("GPU_STATIC_COUNTER_DRAWS", super::STATIC_COUNTER_DRAWS),
            (
                "GPU_STATIC_COUNTER_LATE_DRAWS",
                super::STATIC_COUNTER_LATE_DRAWS,
            ),
            (
                "GPU_STATIC_COUNTER_OVER_CAPACITY",
                super::STATIC_COUNTER_OVER_CAPACITY,
            ),
            (
                "GPU_STATIC_COUNTER_BAD_BATCHES",
                super::STATIC_COUNTER_BAD_BATCHES,
            ),
            ("GPU_STATIC_COUNTER_PLACED", super::STATIC_COUNTER_PLACED),
            ("GPU_STATIC_DRAW_WORDS", (super::DRAW_BYTES / 4) as u32),
            ("GPU_STATIC_DEBUG_LATE", super::STATIC_DEBUG_LATE),
            (
                "GPU_STATIC_DEBUG_FLAGS_SHIFT",
                super::STATIC_DEBUG_FLAGS_SHIFT,
            ),
            // The query's counter words and longest batch, as staticscene lays them out.
            (
                "GPU_STATIC_QUERY_BATCHES",
                (core::mem::offset_of!(staticscene::pass::QueryCounters, batches) / 4) as u32,
            ),
            ("GPU_STATIC_BATCH_LANES", staticscene::pass::QUERY_WORKGROUP),
        ] {
            assert_eq!(shadercheck::const_u32(&src, name), Some(value), "{name}");
        }
    }
}
