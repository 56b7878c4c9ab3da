//! The bind groups a prepared scene and the renderer's targets hold, one struct per pass.
//! Each pass makes its own (its `groups`/`buffers` function) and reads only its own; they
//! are declared here, below the passes, so the prepared scene can hold them without
//! importing a pass.

use tiling::{ClassifyConfig, TilingParams};

/// The renderer's own bind groups (over its targets and frame-level buffers), which every
/// prepared scene shares.
pub(crate) struct TargetGroups {
    /// The vis copy's: vis texture -> vis words, depth -> float depth.
    pub vis_copy: wgpu::BindGroup,
    /// The compute laydown's unpack (64-bit target -> vis words, vis texture, float depth)
    /// and its conversion into the depth target.
    pub laydown_target: Option<LaydownTargetGroups>,
    /// The resolve's group 2: the G-buffer's storage views.
    pub gbuffer_store: wgpu::BindGroup,
    /// Lighting's groups.
    pub lighting: LightingGroups,
    /// The light tiles' groups.
    pub lights: LightTileGroups,
    /// The light volumes' groups, with a light path that has volumes.
    pub light_volumes: Option<LightVolumeGroups>,
}

/// A frame's classification buffers and bind groups.
pub(crate) struct ClassifyBuffers {
    pub(crate) sizes: Sizes,
    pub(crate) config: ClassifyConfig,
    pub(crate) params: TilingParams,
    pub(crate) masks: wgpu::Buffer,
    pub(crate) counter_offsets: wgpu::Buffer,
    pub(crate) counts: wgpu::Buffer,
    pub(crate) pixel_offsets: wgpu::Buffer,
    pub(crate) vertex_cull: wgpu::Buffer,
    pub(crate) totals: wgpu::Buffer,
    pub(crate) stats_mid: wgpu::Buffer,
    pub(crate) final_counts: wgpu::Buffer,
    pub(crate) commands: wgpu::Buffer,
    pub(crate) wave_offsets: wgpu::Buffer,
    pub(crate) waves: wgpu::Buffer,
    pub(crate) pass_dispatch: wgpu::Buffer,
    pub(crate) stats_out: wgpu::Buffer,
    /// Classify output's per-entry, per-block and per-pass wave sums.
    pub(crate) wave_scratch: wgpu::Buffer,
    /// Mid classify's record of each pixel (its command's slot), for classify output.
    pub(crate) slots: wgpu::Buffer,
    /// Mid classify's per-entry and per-block counter sums.
    pub(crate) offset_scratch: wgpu::Buffer,
    pub(crate) _kept: [wgpu::Buffer; 3],
    /// Every zeroed buffer in one [`ZERO_MANY`] group, and their words in all.
    pub(crate) zero_group: Option<(wgpu::BindGroup, u32)>,
    /// One-word buffers for [`ZERO_MANY`]'s bindings past the zeroed buffers (each its own:
    /// writable bindings must not alias).
    pub(crate) _spare: Vec<wgpu::Buffer>,
    /// The validity bitmask's fill with ones and its word count (the mixed frame only).
    pub(crate) fill_group: Option<(wgpu::BindGroup, u32)>,
    pub(crate) groups: Vec<wgpu::BindGroup>,
}

/// The renderer's groups of the passes over its targets: the depth target's conversion
/// and the unpack.
pub(crate) struct LaydownTargetGroups {
    pub(crate) target: wgpu::BindGroup,
    pub(crate) unpack: wgpu::BindGroup,
}

/// A prepared scene's compute-laydown resources: the draw table, the hybrid list and the
/// bind groups over them.
pub(crate) struct ComputeLaydownGroups {
    pub(crate) raster: [wgpu::BindGroup; 2],
    pub(crate) hybrid: [wgpu::BindGroup; 2],
    /// `GpuHybridList`: indirect draw arguments, then the listed items.
    pub(crate) list: wgpu::Buffer,
    /// `GpuLargeList`: `raster_large`'s dispatch arguments, the count, the items.
    pub(crate) large: wgpu::Buffer,
    /// The dispatch arguments copied out of `large` (a dispatch cannot read its
    /// arguments from a buffer it binds for writing).
    pub(crate) large_dispatch: wgpu::Buffer,
    /// Items of the draw table (the raster's invocations).
    pub(crate) items: u32,
    /// The unpack's group 0: the scene's classification (`tiling::finalize`).
    pub(crate) unpack: wgpu::BindGroup,
    pub(crate) _draws: wgpu::Buffer,
}

/// A prepared scene's bind groups for the laydown.
pub(crate) struct LaydownGroups {
    pub(crate) scene: wgpu::BindGroup,
    pub(crate) payloads: wgpu::BindGroup,
}

/// The pass's bind groups.
pub(crate) struct LightVolumeGroups {
    pub(crate) volume: wgpu::BindGroup,
    pub(crate) gbuffer: wgpu::BindGroup,
}

/// The renderer's bind groups for lighting (they change only when the light buffer grows).
pub(crate) struct LightingGroups {
    pub(crate) frame: wgpu::BindGroup,
    pub(crate) gbuffer: wgpu::BindGroup,
    /// The MSAA variant's (frame, gbuffer), with MSAA on.
    pub(crate) msaa: Option<(wgpu::BindGroup, wgpu::BindGroup)>,
}

/// Their bind groups over one set of [`LightBuffers`].
pub(crate) struct LightTileGroups {
    pub(crate) tile_depth: wgpu::BindGroup,
    pub(crate) tile_depth_msaa: Option<wgpu::BindGroup>,
    pub(crate) cull: wgpu::BindGroup,
    /// The counters, cleared before each culling pass.
    pub(crate) counters: wgpu::Buffer,
    /// Tiles across and down.
    pub(crate) tiles: [u32; 2],
}

/// A prepared scene's groups for the pass.
pub(crate) struct PixelPullGroups {
    pub(crate) scene: wgpu::BindGroup,
    pub(crate) pull: wgpu::BindGroup,
}

/// A prepared scene's groups for the pass.
pub(crate) struct RegularGroups {
    pub(crate) scene: wgpu::BindGroup,
    pub(crate) validity: wgpu::BindGroup,
}

/// A prepared scene's bind groups for the resolve (groups 0, 1 and 3; the G-buffer's group
/// 2 is the renderer's) and the per-pass uniform's stride.
pub(crate) struct ResolveGroups {
    pub(crate) scene: wgpu::BindGroup,
    pub(crate) inputs: wgpu::BindGroup,
    pub(crate) waves: wgpu::BindGroup,
    /// Per pass: the wave-command resolve specialised for its material permutation
    /// (empty: the uber resolve for every pass).
    pub(crate) pass_pipelines: Vec<wgpu::ComputePipeline>,
    pub(crate) pass_stride: u32,
    /// Whether the wave-command resolve reads the vertex ring (its passes interleaved
    /// with the ring's transforms).
    pub(crate) reads_ring: bool,
    pub(crate) _pass_uniforms: wgpu::Buffer,
    pub(crate) _ring_stand_in: wgpu::Buffer,
}

/// A prepared scene's vertex-side buffers and bind groups.
pub(crate) struct RingBuffers {
    pub(crate) params: TilingParams,
    /// Slots of the ring (its bytes / 32).
    pub(crate) ring_vertices: u32,
    /// Per pass: the first slot of its half, or [`RING_NONE`].
    pub(crate) half_base: Vec<u32>,
    pub(crate) ubers: wgpu::Buffer,
    pub(crate) pyramid: wgpu::Buffer,
    pub(crate) deltas: wgpu::Buffer,
    pub(crate) micro_batch_waves: wgpu::Buffer,
    pub(crate) vertex_commands: wgpu::Buffer,
    pub(crate) vertex_dispatches: wgpu::Buffer,
    pub(crate) pass_items: wgpu::Buffer,
    pub(crate) totals: wgpu::Buffer,
    pub(crate) ring: wgpu::Buffer,
    /// The per-pass uniforms (pass, half base) at `pass_stride`.
    pub(crate) _pass_uniforms: wgpu::Buffer,
    pub(crate) pass_stride: u32,
    pub(crate) waves_group: wgpu::BindGroup,
    pub(crate) scene_group: wgpu::BindGroup,
    pub(crate) ring_group: wgpu::BindGroup,
    pub(crate) _kept: [wgpu::Buffer; 5],
}

/// Worst-case sizes of a frame's classification buffers (elements, see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Sizes {
    pub width: u32,
    pub height: u32,
    pub tiles: u32,
    pub passes: u32,
    pub max_counters: u32,
    pub max_commands: u32,
    pub max_waves: u32,
    pub chunk_count: u32,
}

impl Sizes {
    /// The sizes for a plan whose passes hold `batch_groups` groups in all.
    pub(crate) fn new(width: u32, height: u32, config: &ClassifyConfig, batch_groups: u32) -> Self {
        let tiles = width.div_ceil(tiling::TILE_SIZE) * height.div_ceil(tiling::TILE_SIZE);
        let pixels = width * height;
        let max_counters = tiles * batch_groups.max(1);
        Self {
            width,
            height,
            tiles,
            passes: config.pass_count.max(1),
            max_counters,
            max_commands: pixels,
            max_waves: max_counters + pixels.div_ceil(config.wave_width.lanes()),
            chunk_count: config.chunk_count,
        }
    }
}

/// Words (`u32`) that `n` elements of `T` take.
pub(crate) fn words_of<T>(n: u32) -> u32 {
    const { assert!(size_of::<T>().is_multiple_of(4)) };
    n * (size_of::<T>() / 4) as u32
}
