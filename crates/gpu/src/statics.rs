//! What a frame with HZD's static query takes and reports ([`Renderer::render_static`]):
//! the query, its CPU-side scene and view, and the statistics of the query and of the
//! placement of its output into the frame.
//!
//! [`Renderer::render_static`]: crate::Renderer::render_static

pub use crate::passes::query::{QueryReadback, StaticQuery, StaticQueryOutput};
use glam::{Affine3A, Vec3};
use staticscene::{
    BuildConfig, MeshNode, QueryOptions, QueryParams, QueryStats, ResourceLibrary, StreamingGroup,
    TileId, TileStreamer, ViewDesc,
};

use crate::error::SceneError;
use crate::resources::uniforms::Camera;
use crate::scene::{Batch, Scene};

/// Where the static query's occlusion test gets its HiZ.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum StaticOcclusion {
    /// As the view says: its `occlusion_camera` with the HiZ last given to
    /// [`StaticQuery::set_hiz`] (no occlusion camera: no occlusion).
    #[default]
    Given,
    /// HZD's: the depth of the previous frame rendered with a static query, reduced on the
    /// GPU before the query and tested through that frame's camera. Off for the first such
    /// frame and after any other frame overwrote the depth target. Conservative only for a
    /// camera that holds still (what was hidden last frame may show now).
    PreviousFrame,
    /// Two-pass occlusion (beyond HZD): the query's first pass draws what was visible
    /// last frame, a HiZ is built on the GPU from that depth, the second pass tests the
    /// rest against it and the laydown draws what it found. Conservative for any camera.
    TwoPass,
}

/// The static content of a frame: the GPU query (its tiles activated), the CPU scene that
/// holds the same tiles (pre-cull, stale flags), and the view to query.
pub struct StaticView<'a> {
    /// The GPU query, with every active tile of `scene` activated.
    pub query: &'a mut StaticQuery,
    /// The CPU side: tiles, clusters and their per-frame state.
    pub scene: &'a mut staticscene::Scene,
    /// The view: [`static_view_desc`] for the frame's camera, then any change (fade
    /// frames, size threshold, the occlusion camera of the HiZ set on `query`).
    pub view: ViewDesc,
    /// Wave width and pre-cull switch.
    pub options: QueryOptions,
    /// Where occlusion gets its HiZ.
    pub occlusion: StaticOcclusion,
}

/// The camera view of `camera` for a `width` x `height` image, as the renderer draws it
/// (reversed Z, infinite far plane), with `staticscene`'s defaults (visual filter, LOD from
/// the camera, 1-pixel size threshold, 8-frame fade, no occlusion).
#[must_use]
pub fn static_view_desc(camera: &Camera, width: u32, height: u32) -> ViewDesc {
    let aspect = width as f32 / height.max(1) as f32;
    let cam = staticscene::Camera::look_at(
        camera.position.as_dvec3(),
        camera.target.as_dvec3(),
        camera.up.as_dvec3(),
        camera.projection(aspect),
        true,
    );
    let mut desc = ViewDesc::camera(cam, [width, height]);
    desc.lod_position = cam.position;
    desc
}

/// What the static query and the placement did in one frame (read back after it).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StaticFrameStats {
    /// The pre-cull's and the query pass's statistics (instances after each test); with
    /// two-pass occlusion, the first pass's.
    pub query: QueryStats,
    /// The second pass's statistics under two-pass occlusion (its `visible` are the
    /// instances it added; `drawn_early` those the first pass drew).
    pub second_pass: Option<QueryStats>,
    /// Threads the query dispatched (instances of the clusters left by the pre-cull).
    pub threads: u64,
    /// Batches the query appended (HZD's render items), both passes.
    pub batches: u32,
    /// Visible instances the query appended, both passes.
    pub instances: u32,
    /// Instances placed into reserved slots and drawn.
    pub placed: u64,
    /// Instances dropped past their setup's capacity.
    pub over_capacity: u32,
    /// Batches dropped by the placement (an unknown setup handle, or a source past the
    /// query's buffers).
    pub bad_batches: u32,
    /// Indirect draws: opaque list, alpha-tested list.
    pub draws: [u32; 2],
    /// Active tiles of the CPU scene not activated on the GPU (skipped).
    pub skipped_tiles: Vec<TileId>,
    /// Per sun slice the frame re-rendered, what the static query's shadow view over
    /// the slice's volume sent to its map (in slice order; empty with sun shadows off or
    /// in a frame that draws no lighting).
    pub shadow_slices: Vec<StaticShadowStats>,
    /// The baked sun map's shadow view, in a frame that re-baked the map (the scene, the
    /// sun or the static tiles changed).
    pub baked: Option<StaticShadowStats>,
}

/// What one of the static query's shadow views (a sun slice, or the baked map) sent to
/// its shadow map: KZ2's "shadow query with size threshold" in counts.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StaticShadowStats {
    /// The slice (0 nearest the camera); 0 for the baked map.
    pub slice: u32,
    /// Texels per side of the view's map (the size threshold is in these).
    pub texels: u32,
    /// The pre-cull's and the pass's statistics: `rejected_size` counts the casters KZ2's
    /// size threshold dropped ([`ShadowConfig::static_size_threshold`](crate::config::ShadowConfig)),
    /// `rejected_frustum` those outside the view's volume, `visible` the casters sent.
    pub query: QueryStats,
    /// Threads the view's query dispatched.
    pub threads: u64,
    /// Caster instances the query appended.
    pub instances: u32,
    /// Batches the query appended.
    pub batches: u32,
    /// Instances placed into the view's own rows and drawn into its map.
    pub placed: u64,
    /// Instances dropped past their setup's capacity (a shadow view's ranks share the
    /// setups' capacities with the camera's: size them for the largest view).
    pub over_capacity: u32,
    /// Batches the placement dropped.
    pub bad_batches: u32,
    /// Indirect draws: opaque list, alpha-tested list.
    pub draws: [u32; 2],
}

/// HZD's mode, where the CPU consumes the query: `scene` with its static setups replaced
/// by planned batches of what `out` (a [`StaticQuery::run`] with
/// [`QueryReadback::Full`] of `params`) found visible, one batch
/// per query batch (its setup's mesh and material, its instances' transforms from the
/// query's floating space back to world space). [`Renderer::prepare`](crate::Renderer::prepare)
/// then plans them with `tiling::build_plan` as any batch.
///
/// # Errors
/// [`SceneError::StaticSetup`] for a batch whose setup handle names no setup of `scene`,
/// or whose instances lie outside `out.instances` (the batch is named; nothing is kept).
pub fn scene_from_query(
    scene: &Scene,
    out: &StaticQueryOutput,
    params: &QueryParams,
) -> Result<Scene, SceneError> {
    let o = params.origin;
    // Whole metres: exact in f32 below 2^24 m.
    let origin = Affine3A::from_translation(Vec3::new(o[0] as f32, o[1] as f32, o[2] as f32));
    let mut planned = Scene {
        static_setups: Vec::new(),
        wind: None,
        ..scene.clone()
    };
    for (i, b) in out.batches.iter().enumerate() {
        let setup = usize::try_from(b.setup)
            .ok()
            .and_then(|h| scene.static_setups.get(h))
            .ok_or_else(|| SceneError::StaticSetup {
                setup: b.setup.min(usize::MAX as u64) as usize,
                problem: format!(
                    "query batch {i} names it; the scene has {}",
                    scene.static_setups.len()
                ),
            })?;
        let first = b.first_instance as usize;
        let instances = out
            .instances
            .get(first..first + b.count as usize)
            .ok_or_else(|| SceneError::StaticSetup {
                setup: b.setup as usize,
                problem: format!(
                    "query batch {i}: instances {first}..{} past the {} read back",
                    first + b.count as usize,
                    out.instances.len()
                ),
            })?;
        planned.batches.push(Batch {
            mesh: setup.mesh,
            material: setup.material,
            instances: instances
                .iter()
                .map(|d| origin * d.local_to_floating.to_affine())
                .collect(),
        });
    }
    Ok(planned)
}

/// What one pixel of a static instance shows, from the placement's debug words.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StaticPixel {
    /// The static setup (its handle: each LOD level's mesh is a setup of its own).
    pub setup: u32,
    /// LOD fade opacity, 0-1 (1 when not fading).
    pub fade: f32,
    /// The query's state flags (`staticscene::STATE_FADING`, `STATE_FADING_OUT`).
    pub flags: u32,
    /// Placed by the second placement of two-pass occlusion (found by the second pass).
    pub late: bool,
}

/// The static instances' debug words of the last frame with a static query, and how vis
/// words map to them ([`Inspect::read_static_debug`](crate::inspect::Inspect::read_static_debug)).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StaticDebug {
    /// Per setup handle: first micro-batch ID, IDs, first slot, capacity, primitive bits;
    /// sorted by first ID.
    pub(crate) ranges: Vec<(u32, crate::resources::rows::GpuStaticSetup)>,
    pub(crate) words: Vec<u32>,
    pub(crate) base: u32,
}

impl StaticDebug {
    /// The static instance a vis word shows, or `None` (the sky, a planned instance, a
    /// word past every reserved range).
    #[must_use]
    pub fn lookup(&self, vis: u32) -> Option<StaticPixel> {
        let word = visbuf::VisId(vis);
        if word.is_none() {
            return None;
        }
        let id = word.micro_batch(visbuf::VisLayout::Standard);
        let at = self.ranges.partition_point(|(_, s)| s.first_id <= id);
        let (setup, s) = self.ranges.get(at.checked_sub(1)?)?;
        let bits = visbuf::PrimitiveBits::new(s.primitive_bits).ok()?;
        let rank = u64::from(id - s.first_id) << bits.instance_bits()
            | u64::from(word.instance_field(bits));
        if rank >= u64::from(s.capacity) {
            return None;
        }
        let slot = u64::from(s.first_slot) + rank;
        let w = *self
            .words
            .get(usize::try_from(slot - u64::from(self.base)).ok()?)?;
        use crate::resources::static_draws::{STATIC_DEBUG_FLAGS_SHIFT, STATIC_DEBUG_LATE};
        let fade_mask = (1 << STATIC_DEBUG_FLAGS_SHIFT) - 1;
        Some(StaticPixel {
            setup: *setup,
            fade: (w & fade_mask) as f32 / fade_mask as f32,
            flags: (w >> STATIC_DEBUG_FLAGS_SHIFT) & 0xff,
            late: w & STATIC_DEBUG_LATE != 0,
        })
    }
}

/// Builds a static world's tiles (one streaming group after another, with `staticscene`'s
/// default build configuration), activates each on `query` and returns the CPU scene
/// that holds them. `resources` and `groups` are a world's (`demo::city`'s
/// `world.resources` and `world.groups`).
///
/// # Errors
/// A tile the static scene or the GPU pool refuses.
pub fn stream_static_world(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    query: &mut StaticQuery,
    resources: &[MeshNode],
    groups: &[StreamingGroup],
) -> crate::Result<staticscene::Scene> {
    let mut streamer = TileStreamer::new(ResourceLibrary::new(resources), BuildConfig::default());
    let mut scene = staticscene::Scene::new();
    for g in groups {
        let u = streamer.add_group(g)?;
        for tile in &u.add {
            query.activate(device, queue, tile.tile())?;
        }
        scene.apply(u);
    }
    Ok(scene)
}
