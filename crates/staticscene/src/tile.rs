//! Static tiles ("High level structure: StaticTile", "Building tiles") and the spatial+
//! partition into clusters ("Building tiles: Spatial partition").
//!
//! A [`StaticTile`] is flat GPU buffers (instances, objects, setups, matrices, bounds; the
//! last four stored once each, deduplicated by hashing) plus CPU [`Cluster`]s: ranges of
//! instances with bounds, a filter mask and LOD limits for the CPU pre-cull, one compute
//! job each. Tiles are immutable once built; building is a plain function on plain data,
//! so it runs on any thread.
//!
//! # The spatial+ partition
//!
//! Inside a tile, instances are ordered by the key *(filter, LOD range, spatial cell,
//! setup with a group-end bit, Morton code of the centre)*:
//!
//! 1. A stable sort by the coarse key *(filter, LOD range)* (the LOD range is the
//!    instance's tightest `[max(parent min, child min), min(parent max, child max))`
//!    bracket as 12-bit codes), so clusters are homogeneous in what the CPU pre-cull
//!    rejects them for.
//! 2. Runs of one coarse key are merged, in key order, until each region holds at least
//!    [`BuildConfig::min_cluster`] instances (the talk's 4K minimum; the last region takes
//!    any remainder).
//! 3. A region of `n` instances becomes `max(1, n / min_cluster)` clusters of near-equal
//!    size, cut spatially by [`Partition::AxisSplit`] (recursive median splits along the
//!    longest axis of the centres' bounds) or [`Partition::MortonBuckets`] (the Morton
//!    order cut into equal consecutive buckets). Both were measured on the demo city (see
//!    [`Partition`]); the default is the better one.
//! 4. Inside a cluster, instances are sorted by setup index, then Morton code; the last
//!    instance of each setup run gets the group-end bit, so the query's waves batch runs
//!    of one setup ("GPU compute thread: Batched output").
//!
//! Coordinates: a tile has an integer *anchor* (the snapped position of its first
//! object); cluster and tile bounds are f32 metres relative to it.

use alloc::vec::Vec;

use glam::{DVec3, IVec3, Vec3};

use crate::dedup::Dedup;
use crate::records::{decode_lod, floating_offset};
use crate::resource::{Aabb, DynamicReason, FlatResource, ResourceLibrary};
use crate::{
    Error, Field, HalfAabb, InstanceFields, MAX_BOUNDS_PER_TILE, MAX_MATRICES_PER_TILE,
    MAX_OBJECTS_PER_TILE, MAX_SETUPS_PER_TILE, QueryInstance, QueryObject, QuerySetup,
    Transform4x3,
};

/// The largest distance of an object's bounds from its position, metres.
pub const OBJECT_EXTENT_MAX: f64 = 1.0e6;

/// A group with more instances than this is split into several tiles (the talk's 24K).
pub const TILE_SPLIT_INSTANCES: usize = 24 * 1024;
/// A group with fewer instances than this goes to the orphan tile (the talk's 1K).
pub const ORPHAN_INSTANCES: usize = 1024;
/// The minimum cluster size (the talk's 4K).
pub const MIN_CLUSTER_INSTANCES: usize = 4096;

/// How a region of a tile is cut into clusters (step 3 of the partition).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Partition {
    /// Recursive median splits along the longest axis of the centres' bounds (what
    /// meshoptimizer's author recommends over Morton buckets). The default: on the demo
    /// city it gives clusters with less total bounds volume and fewer instances passing
    /// the pre-cull than Morton buckets (BENCHMARKS.md, `staticscene`, partition).
    #[default]
    AxisSplit,
    /// The Morton order of the centres cut into equal consecutive buckets.
    MortonBuckets,
}

/// Tile-building parameters (defaults: the talk's figures).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct BuildConfig {
    /// Split groups above this many instances ([`TILE_SPLIT_INSTANCES`]).
    pub split_above: usize,
    /// Groups below this many instances go to the orphan tile ([`ORPHAN_INSTANCES`]).
    pub orphan_below: usize,
    /// Minimum instances per cluster ([`MIN_CLUSTER_INSTANCES`]).
    pub min_cluster: usize,
    /// The spatial cut.
    pub partition: Partition,
}

impl Default for BuildConfig {
    fn default() -> Self {
        BuildConfig {
            split_above: TILE_SPLIT_INSTANCES,
            orphan_below: ORPHAN_INSTANCES,
            min_cluster: MIN_CLUSTER_INSTANCES,
            partition: Partition::default(),
        }
    }
}

impl BuildConfig {
    fn check(&self) -> Result<(), Error> {
        if self.split_above == 0 || self.min_cluster == 0 {
            return Err(Error::Config {
                what: "split_above and min_cluster must be at least 1",
            });
        }
        Ok(())
    }
}

/// A tile's identity, unique within a [`TileStreamer`](crate::TileStreamer).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TileId(pub u32);

/// A mesh resource placed in the world (the talk's DrawableObject).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlacedObject {
    /// Index into the [`ResourceLibrary`].
    pub resource: usize,
    /// World position of the object's origin, metres (f64).
    pub position: DVec3,
    /// Object-to-world rotation and scale.
    pub linear: glam::Mat3,
    /// Object LOD distance scale (> 0).
    pub lod_scale: f32,
    /// Whether the view's global LOD scale is ignored.
    pub ignore_global_lod_scale: bool,
}

impl PlacedObject {
    /// Resource `resource` at `position`, unrotated, LOD scale 1.
    #[must_use]
    pub fn new(resource: usize, position: DVec3) -> PlacedObject {
        PlacedObject {
            resource,
            position,
            linear: glam::Mat3::IDENTITY,
            lod_scale: 1.0,
            ignore_global_lod_scale: false,
        }
    }
}

/// A set of objects the streaming system adds (and later removes) together.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StreamingGroup {
    /// The group's id (removals name it).
    pub id: u64,
    /// The objects.
    pub objects: Vec<PlacedObject>,
}

/// An object that went to the dynamic list instead of a tile.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DynamicObject {
    /// Its streaming group.
    pub group: u64,
    /// Its index in the group's `objects`.
    pub object: usize,
    /// Why.
    pub reason: DynamicReason,
}

/// LOD limits of a set of instances for the CPU pre-cull (metres, object LOD scale
/// included, view scale not). The set is surely not selected when the nearest LOD bounds
/// are at least `near` (times the view scale) away, or the farthest are closer than `far`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LodLimits {
    /// Largest `min(parent max, child max) * object scale`.
    pub near: f32,
    /// Smallest `max(parent min, child min) * object scale`.
    pub far: f32,
    /// Instances in the set.
    pub count: u32,
}

impl LodLimits {
    const EMPTY: LodLimits = LodLimits {
        near: 0.0,
        far: f32::INFINITY,
        count: 0,
    };

    fn add(&mut self, near: f32, far: f32) {
        self.near = self.near.max(near);
        self.far = self.far.min(far);
        self.count += 1;
    }

    fn merge(&mut self, o: &LodLimits) {
        self.near = self.near.max(o.near);
        self.far = self.far.min(o.far);
        self.count += o.count;
    }
}

/// What the CPU pre-cull knows about a cluster or tile (anchor-relative metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CullInfo {
    /// Union of the instances' accurate world bounds.
    pub bounds: Aabb,
    /// Union of the instances' parent and child LOD bounds.
    pub lod_bounds: Aabb,
    /// OR of the instances' filters.
    pub filter: u8,
    /// LOD limits: `[0]` instances using the view's LOD scale, `[1]` those ignoring it.
    pub lod: [LodLimits; 2],
}

impl Default for CullInfo {
    fn default() -> Self {
        CullInfo::EMPTY
    }
}

impl CullInfo {
    /// Nothing: empty boxes, no filter, no LOD range (the pre-cull rejects it; merging
    /// starts from it).
    pub const EMPTY: CullInfo = CullInfo {
        bounds: Aabb::EMPTY,
        lod_bounds: Aabb::EMPTY,
        filter: 0,
        lod: [LodLimits::EMPTY; 2],
    };

    fn merge(&mut self, o: &CullInfo) {
        self.bounds = self.bounds.union(o.bounds);
        self.lod_bounds = self.lod_bounds.union(o.lod_bounds);
        self.filter |= o.filter;
        self.lod[0].merge(&o.lod[0]);
        self.lod[1].merge(&o.lod[1]);
    }
}

/// A range of a tile's instances: one compute job.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cluster {
    /// First instance.
    pub first: u32,
    /// Instance count.
    pub count: u32,
    /// Pre-cull data.
    pub cull: CullInfo,
}

/// A static tile's records and clusters as plain data: what a tile streamed from disk
/// arrives as. [`StaticTile::from_parts`] checks every index before the tile can reach a
/// query; [`StaticTile::into_parts`] gives them back.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TileParts {
    /// The tile's id.
    pub id: TileId,
    /// The integer anchor cluster bounds are relative to (world metres).
    pub anchor: IVec3,
    /// The streaming groups in the tile.
    pub groups: Vec<u64>,
    /// QueryInstances.
    pub instances: Vec<QueryInstance>,
    /// QueryObjects.
    pub objects: Vec<QueryObject>,
    /// QuerySetups.
    pub setups: Vec<QuerySetup>,
    /// Local-to-object matrices.
    pub transforms: Vec<Transform4x3>,
    /// LOD bounds.
    pub bounds: Vec<HalfAabb>,
    /// Clusters, covering the instances in order.
    pub clusters: Vec<Cluster>,
    /// Pre-cull data of the whole tile.
    pub cull: CullInfo,
}

/// An immutable static tile: the GPU buffers and the CPU clusters.
#[derive(Clone, Debug, PartialEq)]
pub struct StaticTile {
    id: TileId,
    anchor: IVec3,
    groups: Vec<u64>,
    instances: Vec<QueryInstance>,
    objects: Vec<QueryObject>,
    setups: Vec<QuerySetup>,
    transforms: Vec<Transform4x3>,
    bounds: Vec<HalfAabb>,
    clusters: Vec<Cluster>,
    cull: CullInfo,
}

impl StaticTile {
    /// The tile's id.
    #[must_use]
    pub fn id(&self) -> TileId {
        self.id
    }
    /// The integer anchor cluster bounds are relative to (world metres).
    #[must_use]
    pub fn anchor(&self) -> IVec3 {
        self.anchor
    }
    /// The streaming groups in the tile (several only for orphan tiles).
    #[must_use]
    pub fn groups(&self) -> &[u64] {
        &self.groups
    }
    /// QueryInstances, in partition order.
    #[must_use]
    pub fn instances(&self) -> &[QueryInstance] {
        &self.instances
    }
    /// QueryObjects (distinct).
    #[must_use]
    pub fn objects(&self) -> &[QueryObject] {
        &self.objects
    }
    /// QuerySetups (distinct).
    #[must_use]
    pub fn setups(&self) -> &[QuerySetup] {
        &self.setups
    }
    /// Local-to-object matrices (distinct).
    #[must_use]
    pub fn transforms(&self) -> &[Transform4x3] {
        &self.transforms
    }
    /// LOD bounds (distinct).
    #[must_use]
    pub fn bounds(&self) -> &[HalfAabb] {
        &self.bounds
    }
    /// The clusters, covering the instances in order.
    #[must_use]
    pub fn clusters(&self) -> &[Cluster] {
        &self.clusters
    }
    /// Pre-cull data of the whole tile.
    #[must_use]
    pub fn cull(&self) -> &CullInfo {
        &self.cull
    }
    /// Bytes of GPU data: the five buffers.
    #[must_use]
    pub fn gpu_bytes(&self) -> usize {
        self.instances.len() * 16
            + self.objects.len() * 64
            + self.setups.len() * 32
            + self.transforms.len() * 48
            + self.bounds.len() * 12
    }
    /// Bytes of CPU data beside the GPU buffers (clusters, tile header).
    #[must_use]
    pub fn cpu_bytes(&self) -> usize {
        self.clusters.len() * size_of::<Cluster>() + size_of::<StaticTile>() + self.groups.len() * 8
    }
    /// A tile from its parts, every record index checked: each instance's setup, object,
    /// parent and child bounds and matrix index inside its tile's tables and its spare bit
    /// clear, and the clusters covering the instances in order. A corrupt tile is
    /// [`Error::TileRecord`] naming the instance and the field, or [`Error::TileClusters`];
    /// nothing of it is kept (other tiles are unaffected).
    pub fn from_parts(parts: TileParts) -> Result<StaticTile, Error> {
        let limits = [
            (Field::Setup, parts.setups.len()),
            (Field::Object, parts.objects.len()),
            (Field::ParentBounds, parts.bounds.len()),
            (Field::ChildBounds, parts.bounds.len()),
            (Field::Matrix, parts.transforms.len()),
        ];
        for (i, q) in parts.instances.iter().enumerate() {
            if q.to_u128() >> crate::records::SPARE_SHIFT != 0 {
                return Err(Error::SpareBitSet);
            }
            let values = [
                q.setup(),
                q.object(),
                q.parent_bounds(),
                q.child_bounds(),
                q.matrix(),
            ];
            for ((field, len), value) in limits.iter().zip(values) {
                if value as usize >= *len {
                    return Err(Error::TileRecord {
                        tile: parts.id.0,
                        instance: i,
                        field: *field,
                        value,
                        len: *len,
                    });
                }
            }
        }
        let mut next = 0u64;
        for (c, cl) in parts.clusters.iter().enumerate() {
            if u64::from(cl.first) != next || cl.count == 0 {
                return Err(Error::TileClusters {
                    tile: parts.id.0,
                    cluster: c,
                });
            }
            next += u64::from(cl.count);
        }
        if next != parts.instances.len() as u64 {
            return Err(Error::TileClusters {
                tile: parts.id.0,
                cluster: parts.clusters.len(),
            });
        }
        Ok(StaticTile {
            id: parts.id,
            anchor: parts.anchor,
            groups: parts.groups,
            instances: parts.instances,
            objects: parts.objects,
            setups: parts.setups,
            transforms: parts.transforms,
            bounds: parts.bounds,
            clusters: parts.clusters,
            cull: parts.cull,
        })
    }

    /// The tile's parts ([`StaticTile::from_parts`] takes them back).
    #[must_use]
    pub fn into_parts(self) -> TileParts {
        TileParts {
            id: self.id,
            anchor: self.anchor,
            groups: self.groups,
            instances: self.instances,
            objects: self.objects,
            setups: self.setups,
            transforms: self.transforms,
            bounds: self.bounds,
            clusters: self.clusters,
            cull: self.cull,
        }
    }

    /// The tile's buffers as the query pass takes them.
    #[must_use]
    pub fn buffers(&self) -> crate::TileBuffers<'_> {
        crate::TileBuffers {
            tile: self.id.0,
            instances: &self.instances,
            objects: &self.objects,
            setups: &self.setups,
            transforms: &self.transforms,
            bounds: &self.bounds,
        }
    }
}

/// An object ready to go into a tile.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PreparedObject {
    /// Its streaming group.
    pub group: u64,
    /// Its resource.
    pub resource: usize,
    /// Its packed record.
    pub object: QueryObject,
    /// Its world position (for spatial ordering).
    pub position: DVec3,
    /// Instances it makes.
    pub instances: u32,
}

/// A streaming group checked against the resources: what goes into tiles and what goes
/// to the dynamic list.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PreparedGroup {
    /// The group's id.
    pub id: u64,
    /// Objects for tiles.
    pub objects: Vec<PreparedObject>,
    /// Objects for the dynamic list.
    pub dynamic: Vec<DynamicObject>,
    /// Instances the tile objects make.
    pub instances: usize,
}

fn fits_tile(r: &FlatResource) -> Result<(), DynamicReason> {
    for (field, needed, limit) in [
        (Field::Setup, r.setups, MAX_SETUPS_PER_TILE),
        (Field::Matrix, r.matrices, MAX_MATRICES_PER_TILE),
        (Field::ParentBounds, r.bounds, MAX_BOUNDS_PER_TILE),
    ] {
        if needed > limit {
            return Err(DynamicReason::TooLargeForTile {
                field,
                needed,
                limit,
            });
        }
    }
    Ok(())
}

/// Checks a group against the library: each object either goes to tiles or to the
/// dynamic list with its reason. Fails only on an object naming a resource the library
/// does not have.
pub fn prepare_group(
    group: &StreamingGroup,
    lib: &ResourceLibrary,
) -> Result<PreparedGroup, Error> {
    let mut out = PreparedGroup {
        id: group.id,
        ..PreparedGroup::default()
    };
    for (i, o) in group.objects.iter().enumerate() {
        let flat = lib.get(o.resource).ok_or(Error::UnknownResource {
            object: i,
            resource: o.resource,
            resources: lib.len(),
        })?;
        let dynamic = |reason| DynamicObject {
            group: group.id,
            object: i,
            reason,
        };
        let flat = match flat {
            Ok(f) => f,
            Err(reason) => {
                out.dynamic.push(dynamic(*reason));
                continue;
            }
        };
        if let Err(reason) = fits_tile(flat) {
            out.dynamic.push(dynamic(reason));
            continue;
        }
        let placed =
            QueryObject::from_world(o.position, o.linear, o.lod_scale, o.ignore_global_lod_scale)
                .and_then(|object| {
                    // The object's world bounds must stay finite and inside the world.
                    let b = flat.object_bounds.transformed(&object.object_to_snapped);
                    let m = b.min.abs().max(b.max.abs()).max_element();
                    if m.is_finite() && f64::from(m) <= OBJECT_EXTENT_MAX {
                        Ok(object)
                    } else {
                        Err(Error::FloatOutOfRange {
                            field: Field::Transform,
                            value: f64::from(m),
                            max: OBJECT_EXTENT_MAX,
                        })
                    }
                });
        match placed {
            Ok(object) => {
                out.instances += flat.leaves.len();
                out.objects.push(PreparedObject {
                    group: group.id,
                    resource: o.resource,
                    object,
                    position: o.position,
                    instances: flat.leaves.len() as u32,
                });
            }
            Err(e) => out.dynamic.push(dynamic(DynamicReason::Placement(e))),
        }
    }
    Ok(out)
}

/// Builds tiles from prepared objects (one group, or the orphan groups together): objects
/// in Morton order of their positions, cut into `ceil(n / split_above)` tiles of
/// near-equal instance counts, a tile closing early when one more object could overflow
/// one of its index spaces. Tile ids come from `next_id`.
pub fn build_tiles(
    objects: &[&PreparedObject],
    lib: &ResourceLibrary,
    config: &BuildConfig,
    next_id: &mut u32,
) -> Result<Vec<StaticTile>, Error> {
    config.check()?;
    if objects.is_empty() {
        return Ok(Vec::new());
    }
    // Morton order of the object positions (relative to the first, in f32).
    let base = objects[0].position;
    let pos: Vec<Vec3> = objects
        .iter()
        .map(|o| (o.position - base).as_vec3())
        .collect();
    let order = morton_order(&pos)?;
    let total: usize = objects.iter().map(|o| o.instances as usize).sum();
    let k = total.div_ceil(config.split_above).max(1);
    let target = total.div_ceil(k);

    let mut tiles = Vec::new();
    let mut current: Vec<&PreparedObject> = Vec::new();
    // Resources already in the current tile: their setups, matrices and bounds are stored
    // already, so further placements add only an object.
    let mut seen: Vec<usize> = Vec::new();
    let mut counts = [0usize; 5]; // instances, objects, setups, matrices, bounds (upper bounds)
    let limits = [
        target,
        MAX_OBJECTS_PER_TILE,
        MAX_SETUPS_PER_TILE,
        MAX_MATRICES_PER_TILE,
        MAX_BOUNDS_PER_TILE,
    ];
    for &i in &order {
        let o = objects[i as usize];
        let flat = leaves_of(lib, o)?;
        let add = |new: bool| {
            let n = usize::from(new);
            [
                o.instances as usize,
                1,
                n * flat.setups,
                n * flat.matrices,
                n * flat.bounds,
            ]
        };
        let a = add(seen.binary_search(&o.resource).is_err());
        if (0..5).any(|j| counts[j] + a[j] > limits[j]) && !current.is_empty() {
            tiles.push(fill_tile(TileId(*next_id), &current, lib, config)?);
            *next_id = next_id.wrapping_add(1);
            current.clear();
            seen.clear();
            counts = [0; 5];
        }
        let a = match seen.binary_search(&o.resource) {
            Ok(_) => add(false),
            Err(at) => {
                seen.insert(at, o.resource);
                add(true)
            }
        };
        current.push(o);
        for j in 0..5 {
            counts[j] += a[j];
        }
    }
    if !current.is_empty() {
        tiles.push(fill_tile(TileId(*next_id), &current, lib, config)?);
        *next_id = next_id.wrapping_add(1);
    }
    Ok(tiles)
}

fn leaves_of<'a>(lib: &'a ResourceLibrary, o: &PreparedObject) -> Result<&'a FlatResource, Error> {
    match lib.get(o.resource) {
        Some(Ok(f)) => Ok(f),
        _ => Err(Error::UnknownResource {
            object: 0,
            resource: o.resource,
            resources: lib.len(),
        }),
    }
}

/// Morton order of points (21 bits per axis over their bounds), via the `morton` crate.
fn morton_order(points: &[Vec3]) -> Result<Vec<u32>, Error> {
    let codes = morton_codes(points)?;
    morton::sort_permutation(&codes).map_err(|_| Error::Config {
        what: "too many instances to sort",
    })
}

fn morton_codes(points: &[Vec3]) -> Result<Vec<u64>, Error> {
    let q = morton::Quantizer3::from_points(points, 21).map_err(|_| Error::Config {
        what: "positions cannot be quantised",
    })?;
    let mut codes = alloc::vec![0u64; points.len()];
    q.morton_u64_slice(points, &mut codes)
        .map_err(|_| Error::Config {
            what: "positions cannot be quantised",
        })?;
    Ok(codes)
}

/// Per-instance data used while building one tile.
#[derive(Clone, Copy)]
struct Aux {
    centre: Vec3,
    info: CullInfo,
    coarse: u32,
    setup: u32,
}

/// Fills one tile from objects.
fn fill_tile(
    id: TileId,
    objects: &[&PreparedObject],
    lib: &ResourceLibrary,
    config: &BuildConfig,
) -> Result<StaticTile, Error> {
    let anchor = objects[0].object.snapped();
    let mut objs = Dedup::<QueryObject>::new();
    let mut setups = Dedup::<QuerySetup>::new();
    let mut transforms = Dedup::<Transform4x3>::new();
    let mut bounds = Dedup::<HalfAabb>::new();
    let mut instances = Vec::new();
    let mut aux = Vec::new();
    let mut groups: Vec<u64> = objects.iter().map(|o| o.group).collect();
    groups.sort_unstable();
    groups.dedup();

    for o in objects {
        let flat = leaves_of(lib, o)?;
        let oi = objs.insert(o.object);
        let o2t = o.object.object_to_floating(anchor);
        let scale = o.object.lod_scale();
        let fixed = o.object.ignores_global_lod_scale();
        for leaf in &flat.leaves {
            let f = InstanceFields {
                filter: leaf.filter,
                flags: leaf.flags,
                setup: setups.insert(leaf.setup) as u16,
                object: oi,
                parent_bounds: bounds.insert(leaf.parent.bounds) as u16,
                child_bounds: bounds.insert(leaf.child.bounds) as u16,
                matrix: transforms.insert(leaf.local_to_object) as u16,
                parent_lod: leaf.parent.range,
                child_lod: leaf.child.range,
                group_end: false,
            };
            // The per-tile limits were checked before the object was added; pack checks
            // the field widths again, so nothing can overflow silently.
            let q = QueryInstance::pack(&f)?;
            let l2t = o2t.mul(&leaf.local_to_object);
            let acc = Aabb::new(leaf.setup.min(), leaf.setup.max()).transformed(&l2t);
            let pb =
                Aabb::new(leaf.parent.bounds.min(), leaf.parent.bounds.max()).transformed(&o2t);
            let cb = Aabb::new(leaf.child.bounds.min(), leaf.child.bounds.max()).transformed(&o2t);
            let (pmin, pmax) = (leaf.parent.range.min, leaf.parent.range.max);
            let (cmin, cmax) = (leaf.child.range.min, leaf.child.range.max);
            let near_code = pmax.min(cmax);
            let far_code = pmin.max(cmin);
            let mut lod = [LodLimits::EMPTY; 2];
            lod[usize::from(fixed)].add(
                decode_lod(u32::from(near_code.code())) * scale,
                decode_lod(u32::from(far_code.code())) * scale,
            );
            aux.push(Aux {
                centre: acc.center(),
                info: CullInfo {
                    bounds: acc,
                    lod_bounds: pb.union(cb),
                    filter: leaf.filter,
                    lod,
                },
                coarse: u32::from(leaf.filter) << 24
                    | u32::from(near_code.code()) << 12
                    | u32::from(far_code.code()),
                setup: u32::from(f.setup),
            });
            instances.push(q);
        }
    }
    for (field, len, max) in [
        (Field::Object, objs.len(), MAX_OBJECTS_PER_TILE),
        (Field::Setup, setups.len(), MAX_SETUPS_PER_TILE),
        (Field::Matrix, transforms.len(), MAX_MATRICES_PER_TILE),
        (Field::ParentBounds, bounds.len(), MAX_BOUNDS_PER_TILE),
    ] {
        if len > max {
            return Err(Error::FieldOverflow {
                field,
                value: len as u64,
                max: max as u64,
            });
        }
    }

    let centres: Vec<Vec3> = aux.iter().map(|a| a.centre).collect();
    let codes = morton_codes(&centres)?;
    let (order, ranges) = partition(&aux, &centres, &codes, config)?;

    let mut out = Vec::with_capacity(instances.len());
    let mut clusters = Vec::with_capacity(ranges.len());
    let mut cull = CullInfo::EMPTY;
    for (first, count) in ranges {
        let idx = &order[first..first + count];
        let mut info = CullInfo::EMPTY;
        for (j, &i) in idx.iter().enumerate() {
            let a = &aux[i as usize];
            let end = j + 1 == idx.len() || aux[idx[j + 1] as usize].setup != a.setup;
            out.push(instances[i as usize].with_group_end(end));
            info.merge(&a.info);
        }
        cull.merge(&info);
        clusters.push(Cluster {
            first: first as u32,
            count: count as u32,
            cull: info,
        });
    }
    Ok(StaticTile {
        id,
        anchor,
        groups,
        instances: out,
        objects: objs.into_items(),
        setups: setups.into_items(),
        transforms: transforms.into_items(),
        bounds: bounds.into_items(),
        clusters,
        cull,
    })
}

/// A cluster's `(first, count)` in the partition order.
type Range = (usize, usize);

/// The spatial+ partition: the instance order (with each cluster sorted by setup, then
/// Morton) and the cluster ranges `(first, count)`.
fn partition(
    aux: &[Aux],
    centres: &[Vec3],
    codes: &[u64],
    config: &BuildConfig,
) -> Result<(Vec<u32>, Vec<Range>), Error> {
    let n = aux.len();
    let coarse: Vec<u32> = aux.iter().map(|a| a.coarse).collect();
    let by_coarse = morton::sort_permutation(&coarse).map_err(|_| Error::Config {
        what: "too many instances to sort",
    })?;
    // Regions: runs of one coarse key merged until each has `min_cluster` instances.
    let mut regions: Vec<(usize, usize)> = Vec::new();
    let mut start = 0;
    let mut i = 0;
    while i < n {
        let key = coarse[by_coarse[i] as usize];
        let mut j = i;
        while j < n && coarse[by_coarse[j] as usize] == key {
            j += 1;
        }
        if j - start >= config.min_cluster {
            regions.push((start, j));
            start = j;
        }
        i = j;
    }
    if start < n {
        match regions.last_mut() {
            Some(last) => last.1 = n,
            None => regions.push((start, n)),
        }
    }
    let mut order = by_coarse;
    let mut ranges = Vec::new();
    for (a, b) in regions {
        let len = b - a;
        let k = (len / config.min_cluster).max(1);
        let region = &mut order[a..b];
        let mut pieces = Vec::with_capacity(k);
        match config.partition {
            Partition::MortonBuckets => {
                region.sort_by_key(|&i| codes[i as usize]);
                for p in 0..k {
                    pieces.push((a + len * p / k, a + len * (p + 1) / k));
                }
            }
            Partition::AxisSplit => axis_split(region, centres, k, a, &mut pieces),
        }
        for (s, e) in pieces {
            order[s..e].sort_by_key(|&i| (aux[i as usize].setup, codes[i as usize]));
            ranges.push((s, e - s));
        }
    }
    Ok((order, ranges))
}

/// Cuts `items` (instance indices) into `k` near-equal pieces by recursive median splits
/// along the longest axis of their centres; pushes `(start, end)` ranges offset by `base`.
fn axis_split(
    items: &mut [u32],
    centres: &[Vec3],
    k: usize,
    base: usize,
    out: &mut Vec<(usize, usize)>,
) {
    if k <= 1 || items.len() < 2 {
        out.push((base, base + items.len()));
        return;
    }
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for &i in items.iter() {
        lo = lo.min(centres[i as usize]);
        hi = hi.max(centres[i as usize]);
    }
    let ext = hi - lo;
    let axis = if ext.x >= ext.y && ext.x >= ext.z {
        0
    } else if ext.y >= ext.z {
        1
    } else {
        2
    };
    let kl = k / 2;
    let nl = items.len() * kl / k;
    items.select_nth_unstable_by(nl, |&a, &b| {
        centres[a as usize][axis]
            .total_cmp(&centres[b as usize][axis])
            .then(a.cmp(&b))
    });
    let (left, right) = items.split_at_mut(nl);
    axis_split(left, centres, kl, base, out);
    axis_split(right, centres, k - kl, base + nl, out);
}

/// Floating-space offset of a tile's anchor for a view's snapped origin.
#[inline]
pub(crate) fn anchor_offset(anchor: IVec3, origin: IVec3) -> Vec3 {
    floating_offset(anchor, origin)
}
