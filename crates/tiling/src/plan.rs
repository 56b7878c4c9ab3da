//! The CPU setup work: batches sorted, split into micro batches, packed into passes, and the
//! GPU-visible tables that describe them (seed 000, "Micro Batches" and bonus slide 108).
//!
//! 1. **Sort.** Batches are sorted by shader, then per-batch data (the batch-group key:
//!    textures and constants), then the Morton code of their position quantised to 10 bits
//!    per axis over the scene's bounds, then their index (so equal keys keep the caller's
//!    order). Sorting by shader first keeps each shader's batches together: passes are
//!    per shader.
//! 2. **Split.** Each batch's instances, in the caller's order, are cut into micro batches
//!    of at most [`MAX_MICRO_BATCH_PRIMITIVES`] triangles, [`MAX_MICRO_BATCH_VERTICES`]
//!    vertices and [`MAX_MICRO_BATCH_INSTANCES`] instances (all counted over the micro
//!    batch's instances; every limit configurable downwards in [`PlanConfig`]). A micro
//!    batch whose instances outrun the vis word's `16 - p` instance bits takes consecutive
//!    micro-batch IDs ([`visbuf::micro_batch_ids_needed`], [`visbuf::VisIdRanges`]).
//! 3. **Passes.** Micro batches are packed greedily, in sorted order, into passes of one
//!    shader whose vertices stay within half the vertex ring (so the vertex transform of
//!    one pass overlaps the shading of the previous one) and which use at most
//!    [`MAX_BATCH_GROUPS_PER_PASS`] batch groups (a batch group = batches with equal shader
//!    and per-batch data). A micro batch is cut short to fill what is left of a pass, so a
//!    batch may split over passes. At most [`MAX_PASSES`] passes.
//!
//! Nothing is dropped: a geometry over 64k primitives, an instance bigger than a micro
//! batch, a 257th pass or an exhausted micro-batch-ID space is an [`Error`] that names the
//! limit and the batch. Batches with no instances produce no micro batch (and are counted
//! in [`Plan::empty_batches`]).
//!
//! # Micro-batch IDs, rows and order
//!
//! Micro batches get consecutive ID ranges in processing order, so micro batch `k` of
//! [`Plan::micro_batches`] starts at an ID no lower than micro batch `k - 1`'s. The
//! [`Plan::table`] (the MicroBatchInfoTable) is indexed by micro-batch ID: every ID of a
//! micro batch's range holds a copy of its row, so a pixel finds its row with one load of
//! the ID in its vis word. The [`Plan::order`] buffer lists the first ID of each micro
//! batch in processing order (pass by pass), which is also the order of their vertex
//! chunks in the vertex cull buffer and of their vertices in each pass's part of the ring.

use alloc::vec::Vec;

use glam::Vec3;
use morton::Quantizer3;
use visbuf::{PrimitiveBits, VisIdRanges, VisLayout};

use crate::Error;

/// Most batch groups (distinct shader + per-batch data) one pass may use: the bit width of
/// the laydown-finalise mask (bonus slide 108).
pub const MAX_BATCH_GROUPS_PER_PASS: u32 = 32;
/// Most passes a frame may have ("256 passes at 4K, which is the maximum we currently
/// support").
pub const MAX_PASSES: u32 = 256;
/// Most primitives one geometry may have: 16-bit indices (`visbuf`'s limit).
pub const MAX_PRIMITIVES_PER_GEOMETRY: u32 = visbuf::MAX_PRIMITIVES_PER_GEOMETRY;
/// Most triangles in one micro batch, over all its instances ("up to 64k triangles").
pub const MAX_MICRO_BATCH_PRIMITIVES: u32 = 65_536;
/// Most vertices in one micro batch, over all its instances ("up to 192k vertices": half
/// of PS4's 12 MiB ring at 32 bytes per vertex).
pub const MAX_MICRO_BATCH_VERTICES: u32 = 192 * 1024;
/// Most instances in one micro batch ("from 1 to 64k instances", `visbuf`'s limit).
pub const MAX_MICRO_BATCH_INSTANCES: u32 = visbuf::MAX_INSTANCES_PER_MICRO_BATCH;
/// Vertices per vertex chunk: the granularity of the vertex cull buffer and of one vertex
/// wave command.
pub const VERTEX_CHUNK_SIZE: u32 = 64;
/// Bytes of one transformed vertex in the ring (`visbuf::VisbufVertex`).
pub const RING_VERTEX_BYTES: u32 = size_of::<visbuf::vertex::VisbufVertex>() as u32;
/// The vertex ring on PS4: 12 MiB.
pub const RING_BYTES_PS4: u64 = 12 << 20;
/// The vertex ring on PS5: 24 MiB.
pub const RING_BYTES_PS5: u64 = 24 << 20;

/// Largest `max_micro_batch_vertices` / `max_micro_batch_primitives` a [`PlanConfig`] may
/// set (keeps chunk and ring offsets in `u32`).
pub const MICRO_BATCH_SIZE_CAP: u32 = 1 << 24;

/// Where a batch's geometry lives in the shared buffers, and how big it is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct Geometry {
    /// Vertices one instance transforms (after any primitive-ID encoding added some).
    pub vertex_count: u32,
    /// Triangles, 1..=[`MAX_PRIMITIVES_PER_GEOMETRY`].
    pub primitive_count: u32,
    /// First index of the geometry in the shared index buffer (three `u32` indices per
    /// triangle, local to `base_vertex`).
    pub first_index: u32,
    /// First vertex of the geometry in the shared vertex buffer.
    pub base_vertex: u32,
}

/// A batch as the scene query hands it over: one shader, one set of per-batch data, one
/// geometry, many instances.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Batch<'a> {
    /// The shader (any stable key: an ID or a hash). Passes are per shader.
    pub shader: u32,
    /// The per-batch data (textures and constants) as a key: batches with equal `shader`
    /// and `batch_data` form one batch group.
    pub batch_data: u64,
    /// The geometry every instance draws.
    pub geometry: Geometry,
    /// One world-space position per instance (metres; any consistent frame). Only their
    /// mean is used, for the Morton sort key; their order is the instance order.
    pub instances: &'a [[f32; 3]],
}

/// Limits and sizes for [`build_plan`]. The defaults are the talk's PS5 figures; every
/// limit may be lowered (to test splitting, or for a smaller ring).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PlanConfig {
    /// The vis-buffer word layout, which decides how many micro-batch IDs there are.
    pub layout: VisLayout,
    /// Bytes of the vertex ring buffer; a pass transforms at most half of it.
    pub ring_bytes: u64,
    /// Bytes per transformed vertex in the ring.
    pub vertex_bytes: u32,
    /// Most vertices per micro batch (at most [`MICRO_BATCH_SIZE_CAP`]).
    pub max_micro_batch_vertices: u32,
    /// Most triangles per micro batch (at most [`MICRO_BATCH_SIZE_CAP`]).
    pub max_micro_batch_primitives: u32,
    /// Most instances per micro batch (at most [`MAX_MICRO_BATCH_INSTANCES`]).
    pub max_micro_batch_instances: u32,
    /// Most passes (at most [`MAX_PASSES`]).
    pub max_passes: u32,
    /// Most batch groups per pass (at most [`MAX_BATCH_GROUPS_PER_PASS`]).
    pub max_batch_groups: u32,
}

impl PlanConfig {
    /// The talk's limits with a PS4 ring (12 MiB: 192k vertices per pass).
    #[must_use]
    pub const fn ps4() -> Self {
        Self {
            layout: VisLayout::Standard,
            ring_bytes: RING_BYTES_PS4,
            vertex_bytes: RING_VERTEX_BYTES,
            max_micro_batch_vertices: MAX_MICRO_BATCH_VERTICES,
            max_micro_batch_primitives: MAX_MICRO_BATCH_PRIMITIVES,
            max_micro_batch_instances: MAX_MICRO_BATCH_INSTANCES,
            max_passes: MAX_PASSES,
            max_batch_groups: MAX_BATCH_GROUPS_PER_PASS,
        }
    }

    /// The talk's limits with a PS5 ring (24 MiB: 384k vertices per pass).
    #[must_use]
    pub const fn ps5() -> Self {
        Self {
            ring_bytes: RING_BYTES_PS5,
            ..Self::ps4()
        }
    }

    /// Vertices one pass may transform: half the ring.
    #[must_use]
    pub const fn pass_vertex_budget(&self) -> u64 {
        if self.vertex_bytes == 0 {
            return 0;
        }
        self.ring_bytes / self.vertex_bytes as u64 / 2
    }

    /// The micro-batch vertex limit in force: the smaller of
    /// [`max_micro_batch_vertices`](Self::max_micro_batch_vertices) and half the ring.
    #[must_use]
    pub const fn micro_batch_vertex_limit(&self) -> u32 {
        let budget = self.pass_vertex_budget();
        if budget < self.max_micro_batch_vertices as u64 {
            budget as u32
        } else {
            self.max_micro_batch_vertices
        }
    }

    fn validate(&self) -> Result<(), Error> {
        let check = |what: &'static str, value: u64, min: u64, max: u64| {
            if value < min || value > max {
                Err(Error::InvalidConfig {
                    what,
                    value,
                    min,
                    max,
                })
            } else {
                Ok(())
            }
        };
        check("vertex_bytes", self.vertex_bytes.into(), 1, 1 << 16)?;
        check(
            "max_micro_batch_vertices",
            self.max_micro_batch_vertices.into(),
            1,
            MICRO_BATCH_SIZE_CAP.into(),
        )?;
        check(
            "max_micro_batch_primitives",
            self.max_micro_batch_primitives.into(),
            1,
            MICRO_BATCH_SIZE_CAP.into(),
        )?;
        check(
            "max_micro_batch_instances",
            self.max_micro_batch_instances.into(),
            1,
            MAX_MICRO_BATCH_INSTANCES.into(),
        )?;
        check("max_passes", self.max_passes.into(), 1, MAX_PASSES.into())?;
        check(
            "max_batch_groups",
            self.max_batch_groups.into(),
            1,
            MAX_BATCH_GROUPS_PER_PASS.into(),
        )?;
        // At least one vertex per pass, at most 2^31 vertices of ring.
        check(
            "ring_bytes",
            self.ring_bytes,
            2 * u64::from(self.vertex_bytes),
            (2 * u64::from(self.vertex_bytes)) << 30,
        )
    }
}

impl Default for PlanConfig {
    fn default() -> Self {
        Self::ps5()
    }
}

/// One row of the MicroBatchInfoTable (WGSL `TilingMicroBatchInfo`), 64 bytes: what the
/// GPU passes look up about the micro batch a vis word names. The table is indexed by
/// micro-batch ID; each ID of a micro batch's range holds the same row.
///
/// Units: counts are elements (vertices, triangles, instances, 64-vertex chunks), offsets
/// are element indices into the named buffer, never bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, bytemuck::Pod, bytemuck::Zeroable)]
pub struct MicroBatchInfo {
    /// First micro-batch ID of the micro batch's range.
    pub first_id: u32,
    /// IDs in the range (more than one when the instances outrun the instance bits).
    pub id_count: u32,
    /// The pass, `0..pass count`.
    pub pass: u32,
    /// The batch group within the pass, `0..32`.
    pub batch_group: u32,
    /// The geometry's primitive bits `p = ceil(log2(primitive_count))`.
    pub primitive_bits: u32,
    /// Triangles per instance.
    pub primitive_count: u32,
    /// Vertices per instance.
    pub vertex_count: u32,
    /// Instances in the micro batch.
    pub instance_count: u32,
    /// Index of its first instance in the frame's instance table (micro batches' instances
    /// laid out one after another in processing order, see [`Plan::instance_refs`]).
    pub first_instance: u32,
    /// Index of the source batch in the caller's slice.
    pub batch: u32,
    /// Index of its first instance within the source batch.
    pub batch_first_instance: u32,
    /// Geometry offset: first index in the shared index buffer.
    pub first_index: u32,
    /// Geometry offset: first vertex in the shared vertex buffer.
    pub base_vertex: u32,
    /// First entry of the micro batch in the vertex cull buffer (64-vertex chunks; the
    /// micro batch's vertices are instance-major: instance `i`'s vertex `v` is vertex
    /// `i * vertex_count + v` of the micro batch).
    pub first_chunk: u32,
    /// First vertex of the micro batch within its pass's half of the ring.
    pub ring_offset: u32,
    /// Position of the micro batch in processing order (index into [`Plan::order`] and
    /// [`Plan::micro_batches`]).
    pub order: u32,
}

const _: () = assert!(size_of::<MicroBatchInfo>() == 64);

impl MicroBatchInfo {
    /// The geometry's primitive bits as `visbuf`'s type (16 if the row holds more).
    #[must_use]
    #[inline]
    pub fn bits(&self) -> PrimitiveBits {
        PrimitiveBits::new(self.primitive_bits.min(visbuf::MAX_PRIMITIVE_BITS)).unwrap_or_default()
    }

    /// Vertices of all instances: `instance_count * vertex_count`.
    #[must_use]
    #[inline]
    pub const fn total_vertices(&self) -> u64 {
        self.instance_count as u64 * self.vertex_count as u64
    }

    /// 64-vertex chunks of the micro batch: `ceil(total_vertices / 64)`.
    #[must_use]
    #[inline]
    pub const fn chunk_count(&self) -> u32 {
        self.total_vertices().div_ceil(VERTEX_CHUNK_SIZE as u64) as u32
    }

    /// The (micro-batch ID, instance field) the laydown writes for instance `i` of this
    /// micro batch (`0..instance_count`): `visbuf::split_instance`.
    #[must_use]
    #[inline]
    pub fn instance_id(&self, i: u32) -> (u32, u32) {
        visbuf::split_instance(self.first_id, i, self.bits())
    }
}

/// One pass (WGSL `TilingPassInfo`), 32 bytes: a run of micro batches of one shader whose
/// vertices fit half the ring.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PassInfo {
    /// Its first micro batch, as an index into [`Plan::order`].
    pub first_micro_batch: u32,
    /// Micro batches in the pass.
    pub micro_batch_count: u32,
    /// Vertices transformed by the pass (before chunk culling).
    pub vertex_count: u32,
    /// Its first 64-vertex chunk in the vertex cull buffer.
    pub first_chunk: u32,
    /// Its chunks.
    pub chunk_count: u32,
    /// Batch groups it uses, 1..=32.
    pub batch_group_count: u32,
    /// The shader key.
    pub shader: u32,
    /// Padding (zero).
    pub pad: u32,
}

const _: () = assert!(size_of::<PassInfo>() == 32);

/// Where one instance went (WGSL `TilingInstanceRef`), 16 bytes: the per-instance mapping
/// the laydown needs.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, bytemuck::Pod, bytemuck::Zeroable)]
pub struct InstanceRef {
    /// Index of the source batch in the caller's slice.
    pub batch: u32,
    /// Index of the instance within its batch.
    pub instance: u32,
    /// The micro-batch ID the laydown writes for it.
    pub micro_batch_id: u32,
    /// The instance field the laydown writes for it.
    pub instance_field: u32,
}

const _: () = assert!(size_of::<InstanceRef>() == 16);

/// The frame's micro batches and passes, and the tables the GPU reads.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Plan {
    /// The layout the IDs were allocated for.
    pub layout: VisLayout,
    /// One row per micro batch, in processing order.
    pub micro_batches: Vec<MicroBatchInfo>,
    /// The MicroBatchInfoTable, indexed by micro-batch ID (length = IDs used).
    pub table: Vec<MicroBatchInfo>,
    /// The micro-batch order buffer: the first ID of each micro batch, processing order.
    pub order: Vec<u32>,
    /// The passes, in order.
    pub passes: Vec<PassInfo>,
    /// For each pass, the per-batch data key of each of its batch groups (index = batch
    /// group).
    pub pass_groups: Vec<Vec<u64>>,
    /// 64-vertex chunks of all micro batches: the vertex cull buffer's length in entries.
    pub chunk_count: u32,
    /// Instances placed (the frame's instance-table length).
    pub instance_count: u32,
    /// Vertices of all micro batches (before culling).
    pub vertex_count: u64,
    /// Batches with no instances (nothing to draw, nothing dropped).
    pub empty_batches: u32,
}

impl Plan {
    /// The micro batch (its row) of a micro-batch ID, if the ID was handed out.
    #[must_use]
    pub fn row(&self, micro_batch_id: u32) -> Option<&MicroBatchInfo> {
        self.table.get(micro_batch_id as usize)
    }

    /// Every placed instance in instance-table order (micro batch after micro batch), with
    /// the micro-batch ID and instance field its vis words carry.
    #[must_use]
    pub fn instance_refs(&self) -> Vec<InstanceRef> {
        let mut out = Vec::with_capacity(self.instance_count as usize);
        for mb in &self.micro_batches {
            for i in 0..mb.instance_count {
                let (micro_batch_id, instance_field) = mb.instance_id(i);
                out.push(InstanceRef {
                    batch: mb.batch,
                    instance: mb.batch_first_instance + i,
                    micro_batch_id,
                    instance_field,
                });
            }
        }
        out
    }
}

/// The sort key of one batch: shader, per-batch data, Morton code of the mean instance
/// position quantised to 10 bits per axis over the bounds of all batches' means
/// (`morton::Quantizer3`), index.
fn sort_keys(batches: &[Batch<'_>]) -> Vec<(u32, u64, u32, u32)> {
    // Mean positions (f64 sums; non-finite coordinates count as 0 so one bad instance
    // cannot make the key NaN).
    let means: Vec<Vec3> = batches
        .iter()
        .map(|b| {
            let mut s = [0.0f64; 3];
            for p in b.instances {
                for k in 0..3 {
                    let c = f64::from(p[k]);
                    s[k] += if c.is_finite() { c } else { 0.0 };
                }
            }
            let n = b.instances.len().max(1) as f64;
            Vec3::new((s[0] / n) as f32, (s[1] / n) as f32, (s[2] / n) as f32)
        })
        .collect();
    let quantizer = Quantizer3::from_points(&means, morton::BITS3_U32).ok();
    batches
        .iter()
        .zip(&means)
        .enumerate()
        .map(|(i, (b, &m))| {
            // The means are finite, so neither call can fail; a failure would only make
            // the spatial part of the key 0.
            let code = quantizer.and_then(|q| q.morton_u32(m).ok()).unwrap_or(0);
            (b.shader, b.batch_data, code, i as u32)
        })
        .collect()
}

/// The pass being filled.
struct OpenPass {
    info: PassInfo,
    groups: Vec<u64>,
}

impl OpenPass {
    /// A pass of `shader` starting at `plan`'s next micro batch and chunk.
    fn new(plan: &Plan, shader: u32) -> OpenPass {
        OpenPass {
            info: PassInfo {
                first_micro_batch: plan.micro_batches.len() as u32,
                first_chunk: plan.chunk_count,
                shader,
                ..PassInfo::default()
            },
            groups: Vec::new(),
        }
    }

    /// Whether a batch of `shader` and `batch_data` may join (the vertex budget aside).
    fn takes(&self, shader: u32, batch_data: u64, max_groups: u32) -> bool {
        self.info.shader == shader
            && (self.groups.contains(&batch_data) || (self.groups.len() as u32) < max_groups)
    }

    /// The batch group of `batch_data`, added if new.
    fn group(&mut self, batch_data: u64) -> u32 {
        match self.groups.iter().position(|&d| d == batch_data) {
            Some(gi) => gi as u32,
            None => {
                self.groups.push(batch_data);
                self.groups.len() as u32 - 1
            }
        }
    }
}

/// Empty geometry, or more primitives than a vis ID names, as the error of batch `batch`.
fn check_geometry(g: Geometry, batch: u32) -> Result<(), Error> {
    if g.primitive_count == 0 || g.vertex_count == 0 {
        return Err(Error::EmptyGeometry { batch });
    }
    if g.primitive_count > MAX_PRIMITIVES_PER_GEOMETRY {
        return Err(Error::GeometryTooLarge {
            batch,
            primitives: g.primitive_count,
            limit: MAX_PRIMITIVES_PER_GEOMETRY,
        });
    }
    Ok(())
}

impl Plan {
    /// Appends `row` (its table entries, order entry, chunks, instances and vertices) and
    /// counts it in `pass`.
    fn push_row(&mut self, pass: &mut OpenPass, row: MicroBatchInfo) {
        let chunks = row.chunk_count();
        let vertices = row.total_vertices();
        pass.info.micro_batch_count += 1;
        pass.info.vertex_count = pass
            .info
            .vertex_count
            .saturating_add(vertices.min(u64::from(u32::MAX)) as u32);
        pass.info.chunk_count += chunks;
        pass.info.batch_group_count = pass.groups.len() as u32;
        self.chunk_count += chunks;
        self.instance_count += row.instance_count;
        self.vertex_count += vertices;
        self.order.push(row.first_id);
        self.micro_batches.push(row);
        for _ in 0..row.id_count {
            self.table.push(row);
        }
    }
}

/// Sorts `batches`, splits them into micro batches and packs those into passes. See the
/// [module docs](self) for the rules; errors name the limit and the batch.
///
/// ```
/// use tiling::{build_plan, Batch, Geometry, PlanConfig};
///
/// let positions = vec![[0.0f32; 3]; 100];
/// let grass = Geometry { vertex_count: 40, primitive_count: 30, first_index: 0, base_vertex: 0 };
/// let batches = [Batch { shader: 1, batch_data: 7, geometry: grass, instances: &positions }];
/// let plan = build_plan(&batches, &PlanConfig::default())?;
/// // 30 triangles: 5 primitive bits, 2^11 instances per ID: one micro batch, one ID.
/// assert_eq!((plan.micro_batches.len(), plan.table.len(), plan.passes.len()), (1, 1, 1));
/// assert_eq!(plan.micro_batches[0].chunk_count(), (100 * 40usize).div_ceil(64) as u32);
/// # Ok::<(), tiling::Error>(())
/// ```
pub fn build_plan(batches: &[Batch<'_>], config: &PlanConfig) -> Result<Plan, Error> {
    config.validate()?;
    if batches.len() > u32::MAX as usize {
        return Err(Error::InvalidConfig {
            what: "batch count",
            value: batches.len() as u64,
            min: 0,
            max: u32::MAX.into(),
        });
    }
    let vertex_limit = config.micro_batch_vertex_limit();
    let pass_budget = config.pass_vertex_budget().min(u64::from(u32::MAX)) as u32;
    for (i, b) in batches.iter().enumerate() {
        let g = b.geometry;
        let batch = i as u32;
        check_geometry(g, batch)?;
        if g.vertex_count > vertex_limit {
            return Err(Error::InstanceTooLarge {
                batch,
                vertices: g.vertex_count,
                limit: vertex_limit,
            });
        }
        if g.primitive_count > config.max_micro_batch_primitives {
            return Err(Error::GeometryTooLarge {
                batch,
                primitives: g.primitive_count,
                limit: config.max_micro_batch_primitives,
            });
        }
    }

    let mut keys = sort_keys(batches);
    keys.sort_unstable();

    let mut plan = Plan {
        layout: config.layout,
        ..Plan::default()
    };
    let mut ids = VisIdRanges::new(config.layout);
    let mut open: Option<OpenPass> = None;
    let mut closed: Vec<OpenPass> = Vec::new();

    for &(_, _, _, index) in &keys {
        let b = &batches[index as usize];
        let g = b.geometry;
        if b.instances.is_empty() {
            plan.empty_batches += 1;
            continue;
        }
        let instance_count = u32::try_from(b.instances.len()).unwrap_or(u32::MAX);
        let per_micro_batch = (config.max_micro_batch_instances)
            .min(config.max_micro_batch_primitives / g.primitive_count)
            .min(vertex_limit / g.vertex_count);
        let mut done = 0u32;
        while done < instance_count {
            // The pass this micro batch goes to: the open one if the shader matches, the
            // group fits and at least one instance's vertices fit.
            let fits = open.as_ref().is_some_and(|p| {
                p.takes(b.shader, b.batch_data, config.max_batch_groups)
                    && pass_budget - p.info.vertex_count >= g.vertex_count
            });
            if !fits {
                if let Some(p) = open.take() {
                    closed.push(p);
                }
                if closed.len() as u32 >= config.max_passes {
                    return Err(Error::TooManyPasses {
                        batch: index,
                        limit: config.max_passes,
                    });
                }
            }
            let pass = open.get_or_insert_with(|| OpenPass::new(&plan, b.shader));
            let group = pass.group(b.batch_data);
            let room = (pass_budget - pass.info.vertex_count) / g.vertex_count;
            let count = (instance_count - done).min(per_micro_batch).min(room);
            let range = ids.push(g.primitive_count, count).map_err(|e| match e {
                visbuf::Error::MicroBatchIdsExhausted {
                    needed, available, ..
                } => Error::MicroBatchIdsExhausted {
                    batch: index,
                    needed,
                    available,
                    layout: config.layout,
                },
                // Counts were validated above; any other error is one of theirs.
                _ => Error::GeometryTooLarge {
                    batch: index,
                    primitives: g.primitive_count,
                    limit: MAX_PRIMITIVES_PER_GEOMETRY,
                },
            })?;
            let bits = range.primitive_bits();
            let row = MicroBatchInfo {
                first_id: range.first_id,
                id_count: range.id_count,
                pass: closed.len() as u32,
                batch_group: group,
                primitive_bits: bits.get(),
                primitive_count: g.primitive_count,
                vertex_count: g.vertex_count,
                instance_count: count,
                first_instance: plan.instance_count,
                batch: index,
                batch_first_instance: done,
                first_index: g.first_index,
                base_vertex: g.base_vertex,
                first_chunk: plan.chunk_count,
                ring_offset: pass.info.vertex_count,
                order: plan.micro_batches.len() as u32,
            };
            plan.push_row(pass, row);
            done += count;
        }
    }
    if let Some(p) = open.take() {
        closed.push(p);
    }
    for p in closed {
        plan.passes.push(p.info);
        plan.pass_groups.push(p.groups);
    }
    Ok(plan)
}

/// Instances the GPU writes each frame (a GPU-driven batch, such as one setup of the static
/// query's output): [`Plan::reserve`] gives them IDs, rows and instance-table slots for up to
/// `capacity` instances, filled in any order by rank.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Reservation {
    /// The shader (as [`Batch::shader`]).
    pub shader: u32,
    /// The per-batch data key (as [`Batch::batch_data`]).
    pub batch_data: u64,
    /// The geometry every instance draws.
    pub geometry: Geometry,
    /// Most instances one frame may place (≥ 1).
    pub capacity: u32,
}

/// Where [`Plan::reserve`] put one reservation: instance of rank `r` (`0..capacity`) sits
/// at `first_instance + r` in the instance table and its vis words carry
/// `visbuf::split_instance(first_id, r, bits)`: every micro batch of the range except the
/// last holds [`MAX_MICRO_BATCH_INSTANCES`] instances, a multiple of any geometry's
/// instances per ID, so the IDs of consecutive ranks are consecutive across micro batches.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ReservedRange {
    /// First micro-batch ID.
    pub first_id: u32,
    /// IDs of the range (over all its micro batches).
    pub id_count: u32,
    /// First slot in the instance table.
    pub first_instance: u32,
    /// Slots (the reservation's capacity).
    pub capacity: u32,
    /// The geometry's primitive bits.
    pub primitive_bits: u32,
    /// The pass its micro batches belong to.
    pub pass: u32,
}

impl Plan {
    /// Appends GPU-filled micro batches after the planned ones: for each reservation,
    /// `ceil(capacity / MAX_MICRO_BATCH_INSTANCES)` micro batches with consecutive IDs, and
    /// `capacity` instance-table slots after the planned instances. Reservations go into
    /// passes of their own after the planned passes, one pass per run of equal shaders (in
    /// the given order) with at most `config.max_batch_groups` batch groups.
    ///
    /// The ring does not bound these passes: what the GPU writes is unknown to the CPU, so
    /// their vertex counts are capacities (saturated at `u32::MAX`) and their ring offsets
    /// 0; a ring (seed 000's vertex pass) needs the visible count, which only the GPU has.
    /// Vertex chunks are reserved for the full capacity, so the classification can mark
    /// any of them.
    ///
    /// The rows' `batch` is the reservation's index in `reservations`, and their
    /// `batch_first_instance` the rank of their first instance.
    ///
    /// On error the plan is unchanged. Errors name the reservation (as `batch`, its index
    /// in `reservations`): empty or oversized geometry, a zero capacity
    /// ([`Error::InvalidConfig`]), exhausted micro-batch IDs, too many passes, or an instance
    /// table past `u32` slots.
    ///
    /// ```
    /// use tiling::{build_plan, Geometry, PlanConfig, Reservation};
    ///
    /// let mut plan = build_plan(&[], &PlanConfig::default())?;
    /// let block = Geometry { vertex_count: 24, primitive_count: 12, first_index: 0, base_vertex: 0 };
    /// let r = Reservation { shader: 0, batch_data: 0, geometry: block, capacity: 100_000 };
    /// let ranges = plan.reserve(&[r], &PlanConfig::default())?;
    /// // 12 triangles: 4 primitive bits, 4096 instances per ID, 25 IDs in two micro batches.
    /// assert_eq!((ranges[0].first_id, ranges[0].id_count), (0, 25));
    /// assert_eq!((plan.micro_batches.len(), plan.passes.len()), (2, 1));
    /// // Rank 70 000 is in the second micro batch.
    /// let (id, field) = visbuf::split_instance(0, 70_000, visbuf::PrimitiveBits::new(4)?);
    /// assert_eq!(plan.row(id).unwrap().instance_id(70_000 - 65_536), (id, field));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn reserve(
        &mut self,
        reservations: &[Reservation],
        config: &PlanConfig,
    ) -> Result<Vec<ReservedRange>, Error> {
        config.validate()?;
        let mut next = self.clone();
        let mut out = Vec::with_capacity(reservations.len());
        let mut ids = self.table.len() as u32;
        let usable = config.layout.usable_micro_batch_ids();
        let mut open: Option<OpenPass> = None;
        let mut closed: Vec<OpenPass> = Vec::new();
        let planned_passes = next.passes.len() as u32;
        for (i, r) in reservations.iter().enumerate() {
            let batch = i as u32;
            let g = r.geometry;
            check_geometry(g, batch)?;
            if r.capacity == 0 {
                return Err(Error::InvalidConfig {
                    what: "reservation capacity",
                    value: 0,
                    min: 1,
                    max: u32::MAX.into(),
                });
            }
            let bits = PrimitiveBits::for_count(g.primitive_count).map_err(|_| {
                Error::GeometryTooLarge {
                    batch,
                    primitives: g.primitive_count,
                    limit: MAX_PRIMITIVES_PER_GEOMETRY,
                }
            })?;
            let needed = r.capacity.div_ceil(bits.instances_per_id());
            if needed > usable - ids.min(usable) {
                return Err(Error::MicroBatchIdsExhausted {
                    batch,
                    needed,
                    available: usable - ids.min(usable),
                    layout: config.layout,
                });
            }
            let first_instance = next.instance_count;
            if first_instance.checked_add(r.capacity).is_none() {
                return Err(Error::InvalidConfig {
                    what: "instance-table slots",
                    value: u64::from(first_instance) + u64::from(r.capacity),
                    min: 0,
                    max: u32::MAX.into(),
                });
            }
            let fits = open
                .as_ref()
                .is_some_and(|p| p.takes(r.shader, r.batch_data, config.max_batch_groups));
            if !fits {
                closed.extend(open.take());
                if planned_passes + closed.len() as u32 >= config.max_passes {
                    return Err(Error::TooManyPasses {
                        batch,
                        limit: config.max_passes,
                    });
                }
            }
            let pass_index = planned_passes + closed.len() as u32;
            let pass = open.get_or_insert_with(|| OpenPass::new(&next, r.shader));
            let group = pass.group(r.batch_data);
            let range = ReservedRange {
                first_id: ids,
                id_count: needed,
                first_instance,
                capacity: r.capacity,
                primitive_bits: bits.get(),
                pass: pass_index,
            };
            let mut done = 0u32;
            while done < r.capacity {
                let count = (r.capacity - done).min(MAX_MICRO_BATCH_INSTANCES);
                let id_count = count.div_ceil(bits.instances_per_id());
                let row = MicroBatchInfo {
                    first_id: ids,
                    id_count,
                    pass: pass_index,
                    batch_group: group,
                    primitive_bits: bits.get(),
                    primitive_count: g.primitive_count,
                    vertex_count: g.vertex_count,
                    instance_count: count,
                    first_instance: first_instance + done,
                    batch,
                    batch_first_instance: done,
                    first_index: g.first_index,
                    base_vertex: g.base_vertex,
                    first_chunk: next.chunk_count,
                    ring_offset: 0,
                    order: next.micro_batches.len() as u32,
                };
                let chunks = row.chunk_count();
                if next.chunk_count.checked_add(chunks).is_none() {
                    return Err(Error::InvalidConfig {
                        what: "vertex chunks",
                        value: u64::from(next.chunk_count) + u64::from(chunks),
                        min: 0,
                        max: u32::MAX.into(),
                    });
                }
                next.push_row(pass, row);
                ids += id_count;
                done += count;
            }
            out.push(range);
        }
        closed.extend(open.take());
        for p in closed {
            next.passes.push(p.info);
            next.pass_groups.push(p.groups);
        }
        *self = next;
        Ok(out)
    }
}
