//! KZ2's conditional rendering emulated: the rows, the per-frame plan and the buffers the
//! conditional pass, the light-volume tests and the spot maps' indirect draws share.

use bytemuck::{Pod, Zeroable};

/// Words of one `DrawIndexedIndirect` (WGSL `GPU_CONDITIONAL_DRAW_WORDS`).
pub(crate) const DRAW_WORDS: u32 = 5;

/// Bytes of one `DrawIndexedIndirect`.
pub(crate) const DRAW_BYTES: u64 = DRAW_WORDS as u64 * 4;

/// Count words per tested light (WGSL `GPU_CONDITIONAL_COUNT_WORDS`): its map's opaque
/// and alpha-tested caster rows, then the static lists' opaque and alpha-tested draws.
pub(crate) const COUNT_WORDS: u32 = 4;

/// The most lights tested per frame: one per spot shadow map.
pub(crate) const MAX_TESTS: u32 = crate::spot_shadows::MAX_SPOT_SHADOW_MAPS;

/// The pass's constants (WGSL `GpuConditionalParams`), 16 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub(crate) struct GpuConditionalParams {
    /// Tested lights this frame.
    pub tests: u32,
    /// Caster draw rows this frame.
    pub casters: u32,
    /// Indices of the unit volume mesh.
    pub volume_indices: u32,
    /// Zero.
    pub pad: u32,
}
const _: () = assert!(size_of::<GpuConditionalParams>() == 16);

/// One tested light (WGSL `GpuConditionalTest`), 16 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub(crate) struct GpuConditionalTest {
    /// Its `GpuLightVolume` row (the volume draw's instance).
    pub volume: u32,
    /// Its map's opaque caster draws.
    pub opaque: u32,
    /// Its map's alpha-tested caster draws.
    pub alpha: u32,
    /// Zero.
    pub pad: u32,
}
const _: () = assert!(size_of::<GpuConditionalTest>() == 16);

/// One caster draw of a tested light's map as the CPU culled it (WGSL `GpuCasterDraw`),
/// 32 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub(crate) struct GpuCasterDraw {
    pub index_count: u32,
    pub instance_count: u32,
    pub first_index: u32,
    pub base_vertex: i32,
    pub first_instance: u32,
    /// The test that decides it.
    pub test: u32,
    /// Zero.
    pub pad: [u32; 2],
}
const _: () = assert!(size_of::<GpuCasterDraw>() == 32);

/// How one spot map is drawn this frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum MapDraw {
    /// Its casters drawn directly (its light is on the tiles, or the emulation is off).
    Direct,
    /// Not drawn: its light is on the volume path but has no volume draw.
    Skipped,
    /// Through the arguments of test `test`: rows `first..` hold `opaque` opaque draws,
    /// then `alpha` alpha-tested ones.
    Indirect {
        test: u32,
        first: u32,
        opaque: u32,
        alpha: u32,
    },
}

/// This frame's plan, made on the CPU.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct ConditionalPlan {
    /// Per test: its volume draw (an index into the frame's volume draws).
    pub tests: Vec<u32>,
    /// Per volume draw: its test, if it has one.
    pub draw_test: Vec<Option<u32>>,
    /// Per spot map (slot order, the frame's active maps).
    pub maps: Vec<MapDraw>,
    /// Per test: its light's row (for read-backs).
    pub lights: Vec<deferred::DeferredLight>,
}

/// The renderer's buffers for the emulation and this frame's plan.
pub(crate) struct ConditionalBuffers {
    pub queries: wgpu::QuerySet,
    /// The queries resolved (8 bytes each).
    pub resolved: wgpu::Buffer,
    pub params: wgpu::Buffer,
    pub tests: wgpu::Buffer,
    pub caster_rows: wgpu::Buffer,
    /// The static lists' two counts, copied in per frame.
    pub static_counts: wgpu::Buffer,
    pub caster_args: wgpu::Buffer,
    pub volume_args: wgpu::Buffer,
    pub counts: wgpu::Buffer,
    pub group: wgpu::BindGroup,
    /// Caster rows the buffers hold.
    pub capacity: u32,
    /// Caster rows this frame.
    pub casters: u32,
    /// Maps drawn with a count buffer (`MULTI_DRAW_INDIRECT_COUNT`).
    pub with_count: bool,
    pub plan: ConditionalPlan,
}

/// Draws `rows` (`count` of them from row `first`) of `args`: with a count buffer, as many
/// as its word `count_word` says (at most `count`).
pub(crate) fn draw_rows(
    pass: &mut wgpu::RenderPass<'_>,
    b: &ConditionalBuffers,
    first: u32,
    count: u32,
    count_word: u64,
) {
    if count == 0 {
        return;
    }
    let offset = u64::from(first) * DRAW_BYTES;
    if b.with_count {
        pass.multi_draw_indexed_indirect_count(
            &b.caster_args,
            offset,
            &b.counts,
            count_word * 4,
            count,
        );
    } else {
        pass.multi_draw_indexed_indirect(&b.caster_args, offset, count);
    }
}
