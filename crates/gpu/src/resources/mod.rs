//! What the passes read and write: the render targets, the records the GPU reads (`rows`),
//! and a prepared scene's buffers and bind groups ([`PreparedScene`]), made once per scene.

pub(crate) mod albedo;
pub(crate) mod buffers;
pub(crate) mod conditional;
pub(crate) mod geometry;
pub(crate) mod groups;
pub(crate) mod lights;
pub(crate) mod plan;
pub(crate) mod readback;
pub(crate) mod ring;
pub(crate) mod rows;
pub(crate) mod static_draws;
pub(crate) mod static_pool;
pub(crate) mod targets;
pub(crate) mod uniforms;
pub(crate) mod uploads;
pub(crate) mod vis64;

use glam::Vec3;

use self::geometry::Geometry;
use self::plan::Draw;
use self::rows::GpuStaticSetup;
use self::static_draws::StaticBuffers;

/// Sizes of a prepared scene, for tables.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneSummary {
    /// Instances over all batches.
    pub instances: u64,
    /// Triangles drawn (instances × their mesh's primitives).
    pub triangles: u64,
    /// Vertices of all instances (seed 000's "vertices in the scene").
    pub vertices: u64,
    /// Micro batches `tiling` made.
    pub micro_batches: usize,
    /// Passes (one or more per shader).
    pub passes: usize,
    /// Batch groups over all passes.
    pub batch_groups: usize,
    /// Wave-command resolve pipelines the scene's passes use: one per material permutation
    /// with `RendererConfig::geometry.material_permutations` (HFW's resolve per material
    /// shader), else 1 (the uber resolve).
    pub resolve_pipelines: usize,
    /// Vertices the primitive-ID encoding added (zero on the `primitive_index` path).
    pub added_vertices: u64,
    /// The floating origin instance transforms and lights are stored relative to (world,
    /// metres; the instances' bounds centre, snapped to 1 m).
    pub origin: Vec3,
}

/// A scene uploaded for one renderer: geometry encoded for its primitive-ID path, `tiling`'s
/// micro batches and passes, instance and lookup tables, the classification's buffers, and
/// every pass's bind groups. Made by [`Renderer::prepare`](crate::Renderer::prepare); frames
/// then only upload their own constants.
pub struct PreparedScene {
    pub(crate) id: u64,
    pub(crate) summary: SceneSummary,
    /// The scene's wind (`Scene::wind`), uploaded with every frame's constants.
    pub(crate) wind: Option<scene::Wind>,
    pub(crate) geometry: Geometry,
    pub(crate) tiling: tiling::Plan,
    pub(crate) draws: Vec<Draw>,
    /// The draws' chunks (bounded runs of instances), culled by shadow views.
    pub(crate) chunks: Vec<plan::DrawChunk>,
    pub(crate) index_buffer: wgpu::Buffer,
    pub(crate) laydown: groups::LaydownGroups,
    /// The compute laydown's draw table, hybrid list and groups (`None` without the
    /// compute laydown, or when the draws' items pass `u32`).
    pub(crate) compute_laydown: Option<groups::ComputeLaydownGroups>,
    /// The scene group once per sun-shadow cascade (its `frame` the cascade's).
    pub(crate) shadow_scene: Vec<wgpu::BindGroup>,
    /// Per spot shadow map: the scene group drawing with that map's frame uniforms.
    pub(crate) spot_shadow_scene: Vec<wgpu::BindGroup>,
    /// The scene group of the baked sun map's pass.
    pub(crate) bake_scene: wgpu::BindGroup,
    /// The batch instances' bounds, origin-relative (`None` without instances).
    pub(crate) bounds: Option<(Vec3, Vec3)>,
    pub(crate) baseline: wgpu::BindGroup,
    /// The mixed frame's regular geometry pass's groups (`Some` exactly in a renderer with
    /// [`RendererConfig::geometry.mixed_frame`](crate::config::GeometryConfig::mixed_frame): the laydown then leaves
    /// out the regular draws).
    pub(crate) regular: Option<groups::RegularGroups>,
    /// The pixel-pull pass's groups.
    pub(crate) pixel_pull: groups::PixelPullGroups,
    pub(crate) classification: groups::ClassifyBuffers,
    pub(crate) resolve: groups::ResolveGroups,
    /// HFW's vertex side (with `RendererConfig::geometry.vertex_ring`): vertex wave commands and
    /// the ring.
    pub(crate) vertex_ring: Option<groups::RingBuffers>,
    /// The instance table (planned instances, then the static setups' reserved slots).
    pub(crate) instances: wgpu::Buffer,
    /// The static setups' table, counters and draw lists (`None` without static setups).
    pub(crate) statics: Option<StaticBuffers>,
    /// Each static setup's capacity (index = handle).
    pub(crate) static_capacities: Vec<u32>,
    /// The static setups' GPU table (index = handle): slots, IDs, primitive bits.
    pub(crate) static_table: Vec<GpuStaticSetup>,
    /// With static setups: per sun slice (at least one with the baked map on), the static
    /// query's shadow view's placement, rows and groups; set 0 also serves the bake, whose
    /// submission runs before the frame's.
    pub(crate) static_shadows: Vec<StaticShadowSet>,
    /// Per batch: the scene's instance index at each planned position.
    pub(crate) instance_order: Vec<Vec<u32>>,
    pub(crate) _kept: Vec<wgpu::Buffer>,
    pub(crate) _albedo: wgpu::Texture,
    /// The data maps' array (kept alive for the scene group).
    pub(crate) _data: wgpu::Texture,
}

impl PreparedScene {
    /// Sizes of the scene as prepared.
    pub fn summary(&self) -> &SceneSummary {
        &self.summary
    }

    /// `tiling`'s plan: micro batches, the MicroBatchInfoTable, passes and batch groups.
    /// Its instance indices are planned positions: see [`PreparedScene::instance_order`].
    pub fn tiling_plan(&self) -> &tiling::Plan {
        &self.tiling
    }

    /// The planned order of batch `batch`'s instances: position `k` of the batch in the
    /// plan (its micro batches, the vis IDs' instance fields, the instance table) is
    /// `scene.batches[batch].instances[order[k]]`. The renderer plans a batch's instances
    /// along a Morton curve, so consecutive ones lie close together. `None` for a batch
    /// the scene does not have.
    pub fn instance_order(&self, batch: usize) -> Option<&[u32]> {
        self.instance_order.get(batch).map(Vec::as_slice)
    }

    /// The primitive-ID payloads, one word per vertex (`_kept[1]`).
    pub(crate) fn payloads(&self) -> &wgpu::Buffer {
        &self._kept[1]
    }

    /// Words of the primitive-ID payloads (one per vertex of the encoded geometry; what
    /// [`Hooks::write_payloads`](crate::inspect::Hooks::write_payloads) takes).
    #[doc(hidden)]
    pub fn payload_count(&self) -> usize {
        (self.payloads().size() / 4) as usize
    }
}

/// One sun shadow view's static content (a slice's, and the baked map's in set 0): the
/// placement's buffers and draw lists of the static query's shadow view, its own instance
/// rows (the reserved slots, first slot first: the camera view's rows, which the resolve
/// reads by vis ID, are never written by a shadow view), and the scene groups that draw
/// them with the slice's frame uniforms and with the bake's.
pub(crate) struct StaticShadowSet {
    pub buffers: StaticBuffers,
    /// `GpuInstance` rows of the reserved slots (slot `buffers.debug_base` first).
    pub instances: wgpu::Buffer,
    /// Group 0 over `instances` with slice `k`'s frame uniforms (`None` past the slices).
    pub slice_group: Option<wgpu::BindGroup>,
    /// Group 0 over `instances` with the bake's frame uniforms (set 0 only).
    pub bake_group: Option<wgpu::BindGroup>,
}
