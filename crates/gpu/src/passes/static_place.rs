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

use crate::error::Result;
use crate::resources::rows::{GpuInstance, GpuStaticParams, GpuStaticSetup};
use crate::resources::static_draws::QueryOutputs;
use crate::resources::static_draws::STATIC_COUNTER_OVER_CAPACITY;
use crate::resources::static_draws::StaticBuffers;
use crate::shaders::LIBRARY;
use crate::timing::GpuTimer;

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

    /// The camera view's placement's timer label; `late`: its second run.
    pub(crate) const fn camera_label(late: bool) -> &'static str {
        if late {
            "static placement (late)"
        } else {
            "static placement"
        }
    }

    /// Records the placement after the query, timed under `label` (a shadow view's, or
    /// [`StaticPlace::camera_label`]): counters (and, without a count buffer, the draw
    /// lists) zeroed, the dispatch arguments, the placement, the draws. `late`: the
    /// frame's second run (two-pass occlusion): placed counts kept, the lists' counts
    /// zeroed, full and late lists written.
    pub(crate) fn record(
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

#[cfg(test)]
mod tests {
    use super::STATIC_PLACE;
    use crate::resources::static_draws::{
        DRAW_BYTES, STATIC_COUNTER_BAD_BATCHES, STATIC_COUNTER_DRAWS, STATIC_COUNTER_LATE_DRAWS,
        STATIC_COUNTER_OVER_CAPACITY, STATIC_COUNTER_PLACED, STATIC_DEBUG_FLAGS_SHIFT,
        STATIC_DEBUG_LATE,
    };
    #[test]
    fn description_matches_its_module() {
        shadercheck::check_pass(&STATIC_PLACE, |_| shadercheck::Caps::CORE);
    }

    #[test]
    fn counter_words_match_the_wgsl() {
        let src = shadercheck::assert_composed(
            crate::shaders::LIBRARY,
            "gpu::static_place",
            &[],
            shadercheck::Caps::CORE,
        );
        for (name, value) in [
            ("GPU_STATIC_COUNTER_DRAWS", STATIC_COUNTER_DRAWS),
            ("GPU_STATIC_COUNTER_LATE_DRAWS", STATIC_COUNTER_LATE_DRAWS),
            (
                "GPU_STATIC_COUNTER_OVER_CAPACITY",
                STATIC_COUNTER_OVER_CAPACITY,
            ),
            ("GPU_STATIC_COUNTER_BAD_BATCHES", STATIC_COUNTER_BAD_BATCHES),
            ("GPU_STATIC_COUNTER_PLACED", STATIC_COUNTER_PLACED),
            ("GPU_STATIC_DRAW_WORDS", (DRAW_BYTES / 4) as u32),
            ("GPU_STATIC_DEBUG_LATE", STATIC_DEBUG_LATE),
            ("GPU_STATIC_DEBUG_FLAGS_SHIFT", STATIC_DEBUG_FLAGS_SHIFT),
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
