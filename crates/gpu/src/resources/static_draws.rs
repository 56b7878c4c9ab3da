//! The static query's placement outputs as the raster passes draw them: the counters'
//! layout, the setups' table and indirect draw lists ([`StaticBuffers`]).

use crate::resources::rows::GpuStaticParams;
use crate::resources::rows::GpuStaticSetup;
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
        let make = |label: &str, size: u64, usage: U| buffer(device, label, size, usage);
        Self {
            setups: crate::resources::buffers::buffer_init(
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
        let make = |label: &str, size: u64, usage: U| buffer(device, label, size, usage);
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

/// A buffer of the static draws: `size` bytes (at least 16, whole words) with `usage`,
/// copied to and from.
fn buffer(
    device: &wgpu::Device,
    label: &str,
    size: u64,
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    use wgpu::BufferUsages as U;
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(16).next_multiple_of(4),
        usage: usage | U::COPY_DST | U::COPY_SRC,
        mapped_at_creation: false,
    })
}
