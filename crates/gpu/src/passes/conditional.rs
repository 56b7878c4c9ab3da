//! KZ2's conditional rendering, emulated (`gpu::conditional`). KZ2 queried a shadow-casting
//! light's stencil pass for the pixels it touched and let the GPU skip the light's shadow
//! map and its shading where there were none ("behind the pillar", "only the air in the
//! hallway"). wgpu has no conditional rendering, so for every light on the stencil-volume
//! path that owns a spot shadow map this frame:
//!
//! 1. the light volumes' test pass (the light volumes' tests (`LightVolumes::record_tests`)) draws its volume over
//!    the frame's depth as the shading would (back faces mark stencil, front faces in
//!    front of the scene where marked; from inside, back faces behind the scene) inside an
//!    occlusion query: the count is the pixels its shading would cover, exactly;
//! 2. this pass resolves the queries and writes, per light, the indirect arguments of its
//!    volume draws (one instance or none) and of its map's caster draws (the CPU's culled
//!    draws with their instances, or zeroed; with `MULTI_DRAW_INDIRECT_COUNT` also a draw
//!    count, n or 0);
//! 3. the spot maps and the volume pass draw those lights through the arguments.
//!
//! A light whose count is zero thus draws neither its map nor its shading, with no CPU
//! round trip. The image does not change: the shading of a light that covers no pixel adds
//! nothing, and its map is read by nothing else (a light on the tiles keeps its direct
//! draws). Lights on the volume path with a map but no volume draw (wholly behind the near
//! plane) are skipped by the CPU. The static query's draw lists in those maps are drawn
//! with the placement's counts, or zero, where the device has `MULTI_DRAW_INDIRECT_COUNT`
//! (else unconditionally: their lists have no per-light copy).
//!

use shader::pipeline::ComputePass;
use shader::{Binding, Entry, Group, Kind, Pass};

use super::context::FrameContext;
use crate::error::Result;
use crate::resources::conditional::COUNT_WORDS;
use crate::resources::conditional::ConditionalBuffers;
use crate::resources::conditional::ConditionalPlan;
use crate::resources::conditional::DRAW_BYTES;
use crate::resources::conditional::GpuCasterDraw;
use crate::resources::conditional::GpuConditionalParams;
use crate::resources::conditional::GpuConditionalTest;
use crate::resources::conditional::MAX_TESTS;
use crate::shaders::LIBRARY;
use crate::timing::GpuTimer;

/// The pass; the parameter is the invocation count (the larger of tests and caster rows).
pub(crate) const CONDITIONAL: Pass<u32> = Pass {
    name: "conditional volumes",
    module: "gpu::conditional",
    library: LIBRARY,
    features: &[],
    groups: &[Group {
        name: "conditional",
        bindings: &[
            Binding::new("params", Kind::uniform(size_of::<GpuConditionalParams>())),
            Binding::new("queries", Kind::read(8)),
            Binding::new("tests", Kind::read(size_of::<GpuConditionalTest>())),
            Binding::new("caster_rows", Kind::read(size_of::<GpuCasterDraw>())),
            Binding::new("static_counts", Kind::read(4)),
            Binding::new("caster_args", Kind::read_write(4)),
            Binding::new("volume_args", Kind::read_write(4)),
            Binding::new("counts", Kind::read_write(4)),
        ],
    }],
    entries: &[Entry::items("conditional_args", 64, |n| *n)],
    zeroed: &[],
};

/// The pass's pipeline.
pub(crate) struct Conditional {
    pass: ComputePass<u32>,
}

impl Conditional {
    pub(crate) fn new(device: &wgpu::Device) -> Result<Self> {
        Ok(Self {
            pass: ComputePass::new(device, &CONDITIONAL, &[], &[])?,
        })
    }

    /// The buffers for `capacity` caster rows (at least 64).
    pub(crate) fn buffers(
        &self,
        device: &wgpu::Device,
        capacity: u32,
    ) -> Result<ConditionalBuffers> {
        use wgpu::BufferUsages as U;
        let capacity = capacity.max(64);
        let buffer = |label, size: u64, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        let tests = u64::from(MAX_TESTS);
        let queries = device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("light volume tests"),
            ty: wgpu::QueryType::Occlusion,
            count: MAX_TESTS,
        });
        let resolved = buffer(
            "light volume test counts",
            tests * 8,
            U::QUERY_RESOLVE | U::STORAGE | U::COPY_SRC,
        );
        let params = buffer(
            "conditional params",
            size_of::<GpuConditionalParams>() as u64,
            U::UNIFORM | U::COPY_DST,
        );
        let test_rows = buffer(
            "conditional tests",
            tests * size_of::<GpuConditionalTest>() as u64,
            U::STORAGE | U::COPY_DST,
        );
        let caster_rows = buffer(
            "conditional caster rows",
            u64::from(capacity) * size_of::<GpuCasterDraw>() as u64,
            U::STORAGE | U::COPY_DST,
        );
        let static_counts = buffer("conditional static counts", 8, U::STORAGE | U::COPY_DST);
        let indirect = U::STORAGE | U::INDIRECT | U::COPY_SRC;
        let caster_args = buffer(
            "conditional caster draws",
            u64::from(capacity) * DRAW_BYTES,
            indirect,
        );
        let volume_args = buffer("conditional volume draws", tests * DRAW_BYTES, indirect);
        let counts = buffer(
            "conditional caster counts",
            tests * 4 * u64::from(COUNT_WORDS),
            indirect,
        );
        let group = self.pass.bind_group(
            device,
            "conditional",
            &[
                ("params", params.as_entire_binding()),
                ("queries", resolved.as_entire_binding()),
                ("tests", test_rows.as_entire_binding()),
                ("caster_rows", caster_rows.as_entire_binding()),
                ("static_counts", static_counts.as_entire_binding()),
                ("caster_args", caster_args.as_entire_binding()),
                ("volume_args", volume_args.as_entire_binding()),
                ("counts", counts.as_entire_binding()),
            ],
        )?;
        Ok(ConditionalBuffers {
            queries,
            resolved,
            params,
            tests: test_rows,
            caster_rows,
            static_counts,
            caster_args,
            volume_args,
            counts,
            group,
            capacity,
            casters: 0,
            with_count: device
                .features()
                .contains(wgpu::Features::MULTI_DRAW_INDIRECT_COUNT),
            plan: ConditionalPlan::default(),
        })
    }

    /// Resolves this frame's queries and writes the indirect arguments (after the volume
    /// tests, before the spot maps). Records nothing without tests.
    pub(crate) fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
    ) {
        let Some(b) = f.conditional else {
            return;
        };
        let tests = b.plan.tests.len() as u32;
        if tests == 0 {
            return;
        }
        encoder.resolve_query_set(&b.queries, 0..tests.min(MAX_TESTS), &b.resolved, 0);
        // The static lists' counts as the placement left them (full lists), or none.
        match f
            .scene
            .statics
            .as_ref()
            .filter(|s| f.static_query && s.with_count)
        {
            Some(s) => encoder.copy_buffer_to_buffer(
                &s.counters,
                4 * u64::from(crate::resources::static_draws::STATIC_COUNTER_DRAWS),
                &b.static_counts,
                0,
                8,
            ),
            None => encoder.clear_buffer(&b.static_counts, 0, None),
        }
        let mut pass = timer.begin_compute(encoder, "conditional volumes");
        self.pass
            .record(&mut pass, &[&b.group], &tests.max(b.casters));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::resources::conditional::DRAW_WORDS;
    use shadercheck::{Caps, assert_struct_layout, members};

    #[test]
    fn description_matches_its_module() {
        shadercheck::check_pass(&CONDITIONAL, |_| Caps::CORE);
        let m = shadercheck::assert_composed(LIBRARY, CONDITIONAL.module, &[], Caps::CORE);
        assert_eq!(
            shadercheck::const_u32(&m, "GPU_CONDITIONAL_DRAW_WORDS"),
            Some(DRAW_WORDS)
        );
        assert_eq!(
            shadercheck::const_u32(&m, "GPU_CONDITIONAL_COUNT_WORDS"),
            Some(COUNT_WORDS)
        );
        assert_struct_layout(
            &m,
            "GpuConditionalParams",
            size_of::<GpuConditionalParams>(),
            &members!(GpuConditionalParams {
                tests,
                casters,
                volume_indices,
                pad
            }),
        );
        assert_struct_layout(
            &m,
            "GpuConditionalTest",
            size_of::<GpuConditionalTest>(),
            &members!(GpuConditionalTest {
                volume,
                opaque,
                alpha,
                pad
            }),
        );
        assert_struct_layout(
            &m,
            "GpuCasterDraw",
            size_of::<GpuCasterDraw>(),
            &members!(GpuCasterDraw {
                index_count,
                instance_count,
                first_index,
                base_vertex,
                first_instance,
                test,
                pad
            }),
        );
        assert_eq!(
            DRAW_BYTES,
            size_of::<wgpu::util::DrawIndexedIndirectArgs>() as u64
        );
    }

    /// On a device: a counted test keeps its volume draw, its casters and the static
    /// counts, an uncounted one zeroes them (a count in the high word counts), a caster
    /// row naming a test that does not exist is zeroed, and constants claiming more tests
    /// and rows than the buffers hold write nothing past them.
    #[test]
    fn arguments_follow_the_counts_and_stay_in_bounds() {
        use testkit::device::{Data, run_pass};
        let queries: [u32; 6] = [5, 0, 0, 0, 0, 1];
        let test = |volume, opaque, alpha| GpuConditionalTest {
            volume,
            opaque,
            alpha,
            pad: 0,
        };
        let tests = [test(7, 2, 1), test(8, 1, 0), test(9, 0, 0)];
        let rows: Vec<GpuCasterDraw> = [0, 0, 1, 2, 99]
            .into_iter()
            .enumerate()
            .map(|(i, test)| GpuCasterDraw {
                index_count: 3 * (i as u32 + 1),
                instance_count: 10 + i as u32,
                first_index: 100 + i as u32,
                base_vertex: -(i as i32),
                first_instance: 1000 + i as u32,
                test,
                pad: [0; 2],
            })
            .collect();
        let params = GpuConditionalParams {
            tests: 100,
            casters: 100,
            volume_indices: 240,
            pad: 0,
        };
        let out = run_pass(
            &CONDITIONAL,
            &[],
            &[],
            &100,
            &[
                ("params", Data::Bytes(bytemuck::bytes_of(&params))),
                ("queries", Data::Words(&queries)),
                ("tests", Data::rows(&tests)),
                ("caster_rows", Data::rows(&rows)),
                ("static_counts", Data::Words(&[11, 12])),
                ("caster_args", Data::Zeros(5 * DRAW_WORDS as usize)),
                ("volume_args", Data::Zeros(3 * DRAW_WORDS as usize)),
                ("counts", Data::Zeros(3 * COUNT_WORDS as usize)),
            ],
        );
        assert_eq!(
            out.read::<u32>("volume_args", 15),
            [240, 1, 0, 0, 7, 240, 0, 0, 0, 8, 240, 1, 0, 0, 9]
        );
        assert_eq!(
            out.read::<u32>("counts", 12),
            [2, 1, 11, 12, 0, 0, 0, 0, 0, 0, 11, 12]
        );
        let args = out.read::<u32>("caster_args", 25);
        for (i, (r, a)) in rows.iter().zip(args.chunks_exact(5)).enumerate() {
            let kept = [0, 2].contains(&r.test);
            let want = [
                r.index_count,
                if kept { r.instance_count } else { 0 },
                r.first_index,
                r.base_vertex as u32,
                r.first_instance,
            ];
            assert_eq!(a, want, "row {i}");
        }
    }
}
