//! Fuzz bodies for the `staticscene` crate: QueryInstance (and LOD code, half box)
//! decoding, tile building from arbitrary resource trees and placements, and the query
//! pass over arbitrary hand-made buffers. Nothing here may panic except a check.

use glam::{Affine3A, DQuat, DVec3, Mat3, Mat4, Vec3};
use staticscene::{
    Aabb, BuildConfig, Camera, ClusterJob, DrawableSetupBatch, DrawableSetupInstance, Error,
    HalfAabb, LodDistance, LodLevel, MeshNode, MeshPart, PlacedObject, QueryInstance, QueryObject,
    QueryOptions, QueryOutput, QueryParams, QuerySetup, QueryStats, ResourceLibrary, Scene,
    StaticMesh, StreamingGroup, TileBuffers, TileStreamer, Transform4x3, ViewDesc, WaveWidth,
    query_cluster,
};

use crate::Input;

/// QueryInstance decode: arbitrary 16 bytes either decode and repack to the same bytes
/// with accessors agreeing, or are refused for the spare bit; LOD codes and half boxes
/// decode without panicking, and LOD encoding is stable.
pub fn staticscene_instance_decode(data: &[u8]) {
    let mut input = Input::new(data);
    let bytes: [u8; 16] = input.bytes();
    let q = QueryInstance::from_bytes(bytes);
    match q.try_unpack() {
        Ok(f) => {
            let p = QueryInstance::pack(&f).expect("decoded fields fit");
            assert_eq!(p.to_bytes(), bytes);
            assert_eq!(q.object(), f.object);
            assert_eq!(q.setup(), u32::from(f.setup));
            assert_eq!(q.matrix(), u32::from(f.matrix));
            assert_eq!(q.group_end(), f.group_end);
            for d in [
                f.parent_lod.min,
                f.parent_lod.max,
                f.child_lod.min,
                f.child_lod.max,
            ] {
                let m = d.metres();
                assert!(m >= 0.0);
                assert_eq!(
                    LodDistance::from_metres(m).expect("decoded distance encodes"),
                    d
                );
            }
        }
        Err(e) => {
            assert_eq!(e, Error::SpareBitSet);
            assert_eq!(bytes[15] >> 7, 1);
        }
    }
    // A raw 16-bit code: valid up to 0xfff.
    let code = input.u16();
    assert_eq!(LodDistance::from_code(code).is_some(), code <= 0xfff);
    // Any float: encodes only to a code that decodes within half a step.
    let d = input.f32();
    if let Ok(c) = LodDistance::from_metres(d) {
        let back = c.metres();
        if d.is_finite() {
            let bound = if d < 4.0 {
                1.0 / 128.0
            } else {
                f64::from(d) / 512.0
            };
            assert!(
                (f64::from(back) - f64::from(d)).abs() <= bound + 1e-9,
                "{d} -> {back}"
            );
        } else {
            assert_eq!(back, f32::INFINITY);
        }
    }
    // Any 12 bytes as a half box.
    let hb: [u8; 12] = input.bytes();
    let h: HalfAabb = bytemuck::cast(hb);
    let (lo, hi) = (h.min(), h.max());
    if lo.is_finite() && hi.is_finite() && lo.cmple(hi).all() {
        let again = HalfAabb::from_aabb(lo, hi).expect("a finite ordered half box re-encodes");
        assert_eq!((again.min(), again.max()), (lo, hi));
    }
}

fn small_f32(input: &mut Input<'_>) -> f32 {
    // Mostly sane values, sometimes raw bits (NaN, infinities, huge).
    if input.u8() < 230 {
        f32::from(input.u16() as i16) / 64.0
    } else {
        input.f32()
    }
}

fn vec3(input: &mut Input<'_>) -> Vec3 {
    Vec3::new(small_f32(input), small_f32(input), small_f32(input))
}

fn node(input: &mut Input<'_>, depth: u32, handles: &mut u64) -> MeshNode {
    let kind = if depth >= 4 || input.remaining() == 0 {
        0
    } else {
        input.u8() % 8
    };
    match kind {
        0..=2 => {
            let min = vec3(input);
            let max = min + vec3(input).abs();
            *handles += 1;
            MeshNode::Static(StaticMesh {
                setup: *handles % 64,
                bounds: Aabb::new(min, max),
                filter: input.u8() % 9,
                flags: input.u8() % 5,
            })
        }
        3 | 4 => {
            let min = vec3(input);
            let max = min + vec3(input).abs();
            let n = 1 + input.u8() % 3;
            let levels = (0..n)
                .map(|_| {
                    let a = small_f32(input).abs();
                    let b = a + small_f32(input).abs();
                    LodLevel {
                        min: a,
                        max: if input.u8().is_multiple_of(4) {
                            f32::INFINITY
                        } else {
                            b
                        },
                        node: node(input, depth + 1, handles),
                    }
                })
                .collect();
            MeshNode::Lod {
                bounds: Aabb::new(min, max),
                levels,
            }
        }
        5 | 6 => {
            let n = 1 + input.u8() % 4;
            MeshNode::Multi(
                (0..n)
                    .map(|_| MeshPart {
                        local_to_parent: Affine3A::from_scale_rotation_translation(
                            Vec3::splat(small_f32(input)),
                            glam::Quat::from_rotation_y(small_f32(input)),
                            vec3(input),
                        ),
                        node: node(input, depth + 1, handles),
                    })
                    .collect(),
            )
        }
        _ => MeshNode::Skinned { setup: 0 },
    }
}

/// Tile building from arbitrary resource trees, placements and configurations, through
/// the streamer (adds, orphans, removals), then a query: no panic, every fitting leaf
/// becomes exactly one instance, clusters cover the tiles, indices stay in range.
pub fn staticscene_build(data: &[u8]) {
    let mut input = Input::new(data);
    let mut handles = 0;
    let resources: Vec<MeshNode> = (0..1 + input.u8() % 4)
        .map(|_| node(&mut input, 0, &mut handles))
        .collect();
    let lib = ResourceLibrary::new(&resources);
    let config = BuildConfig {
        split_above: usize::from(input.u8() % 64),
        orphan_below: usize::from(input.u8() % 16),
        min_cluster: usize::from(input.u8() % 16),
        partition: if input.u8().is_multiple_of(2) {
            staticscene::Partition::AxisSplit
        } else {
            staticscene::Partition::MortonBuckets
        },
    };
    let mut streamer = TileStreamer::new(lib.clone(), config);
    let mut scene = Scene::new();
    let mut expected = 0usize;
    let mut loaded = Vec::new();
    for g in 0..1 + input.u8() % 4 {
        let objects: Vec<PlacedObject> = (0..input.u8() % 24)
            .map(|_| {
                let raw = input.u8() < 20;
                let position = if raw {
                    DVec3::new(
                        f64::from(input.f32()),
                        f64::from(input.f32()),
                        f64::from(input.f32()),
                    )
                } else {
                    DVec3::new(
                        f64::from(small_f32(&mut input)) * 100.0,
                        0.0,
                        f64::from(small_f32(&mut input)) * 100.0,
                    )
                };
                PlacedObject {
                    resource: usize::from(input.u8() % 5),
                    position,
                    linear: Mat3::from_diagonal(Vec3::splat(if raw { input.f32() } else { 1.0 })),
                    lod_scale: if raw { input.f32() } else { 1.0 },
                    ignore_global_lod_scale: input.u8().is_multiple_of(2),
                }
            })
            .collect();
        let group = StreamingGroup {
            id: u64::from(g),
            objects,
        };
        match streamer.add_group(&group) {
            Ok(u) => {
                let dynamic = u.dynamic.len();
                let mut fitting = 0;
                for o in &group.objects {
                    if let Some(Ok(f)) = lib.get(o.resource) {
                        fitting += f.leaves.len();
                    }
                }
                // Objects in the dynamic list lose their leaves from the static count.
                let lost: usize = u
                    .dynamic
                    .iter()
                    .filter_map(|d| match lib.get(group.objects[d.object].resource) {
                        Some(Ok(f)) => Some(f.leaves.len()),
                        _ => None,
                    })
                    .sum();
                expected += fitting - lost;
                assert!(dynamic <= group.objects.len());
                scene.apply(u);
                loaded.push(group.id);
            }
            Err(e) => {
                assert!(
                    matches!(e, Error::UnknownResource { .. } | Error::Config { .. }),
                    "{e}"
                );
            }
        }
        assert_eq!(scene.instance_count(), expected);
    }
    for t in scene.tiles() {
        let mut next = 0;
        for c in t.clusters() {
            assert_eq!(c.first, next);
            next += c.count;
        }
        assert_eq!(next as usize, t.instances().len());
        for q in t.instances() {
            let f = q.try_unpack().expect("built instances decode");
            assert!((f.object as usize) < t.objects().len());
            assert!((f.setup as usize) < t.setups().len());
            assert!((f.matrix as usize) < t.transforms().len());
            assert!((f.parent_bounds as usize) < t.bounds().len());
            assert!((f.child_bounds as usize) < t.bounds().len());
        }
    }
    let cam = Camera {
        position: DVec3::new(
            f64::from(small_f32(&mut input)),
            2.0,
            f64::from(small_f32(&mut input)),
        ),
        rotation: DQuat::from_rotation_y(f64::from(small_f32(&mut input))),
        projection: Mat4::perspective_rh(1.0, 1.5, 0.1, 1000.0),
        reversed_depth: false,
    };
    if let Ok(params) = QueryParams::new(&ViewDesc::camera(cam, [64, 32])) {
        let mut out = QueryOutput::<DrawableSetupInstance>::new();
        scene
            .query(&params, None, &QueryOptions::default(), &mut out)
            .expect("the query runs on built tiles");
        assert_eq!(out.stats.invalid, 0);
        assert_eq!(out.stats.visible as usize, out.instances.len());
    }
    for id in loaded {
        scene.apply(streamer.remove_group(id).expect("loaded groups remove"));
    }
    assert_eq!(scene.instance_count(), 0);
}

/// The query pass over arbitrary hand-made buffers (indices out of range, any floats,
/// any job range, short outputs): an error or counted drops, never a panic.
pub fn staticscene_query(data: &[u8]) {
    let mut input = Input::new(data);
    let n = usize::from(input.u8() % 80);
    let instances: Vec<QueryInstance> = (0..n)
        .map(|_| QueryInstance {
            words: [input.u32(), input.u32(), input.u32(), input.u32()],
        })
        .collect();
    let objects: Vec<QueryObject> = (0..input.u8() % 4)
        .map(|_| {
            let mut o = QueryObject {
                object_to_snapped: Transform4x3::IDENTITY,
                snapped: [input.u32() as i32, 0, input.u32() as i32],
                lod: input.u32(),
            };
            o.object_to_snapped.rows[0][3] = small_f32(&mut input);
            o
        })
        .collect();
    let setups: Vec<QuerySetup> = (0..input.u8() % 4)
        .map(|_| QuerySetup {
            bounds_min: vec3(&mut input).to_array(),
            bounds_max: vec3(&mut input).to_array(),
            handle: input.u64(),
        })
        .collect();
    let transforms: Vec<Transform4x3> = (0..input.u8() % 3)
        .map(|_| Transform4x3::IDENTITY)
        .collect();
    let bounds: Vec<HalfAabb> = (0..input.u8() % 4)
        .map(|_| bytemuck::cast(input.bytes::<12>()))
        .collect();
    let tile = TileBuffers {
        tile: 0,
        instances: &instances,
        objects: &objects,
        setups: &setups,
        transforms: &transforms,
        bounds: &bounds,
    };
    let cam = Camera {
        position: DVec3::ZERO,
        rotation: DQuat::from_rotation_y(f64::from(small_f32(&mut input))),
        projection: Mat4::perspective_rh(1.0, 1.0, 0.1, 1e4),
        reversed_depth: input.u8().is_multiple_of(2),
    };
    let mut view = ViewDesc::camera(cam, [32, 32]);
    view.fade_frames = u32::from(input.u8() % 10);
    // Either pass of two-pass occlusion reads the camera state bytes below.
    view.occlusion_pass = match input.u8() % 3 {
        0 => staticscene::OcclusionPass::Single,
        1 => staticscene::OcclusionPass::First,
        _ => staticscene::OcclusionPass::Second,
    };
    let Ok(params) = QueryParams::new(&view) else {
        return;
    };
    let job = ClusterJob {
        first: u32::from(input.u8() % 90),
        count: u32::from(input.u8() % 90),
        snap_fade: input.u8().is_multiple_of(2),
    };
    // Arbitrary camera state bytes: fade states past the fade length, the visible bit.
    let mut fade: Vec<u8> = (0..input.u8() % 100).map(|_| input.u8()).collect();
    let before = fade.clone();
    let mut out = vec![DrawableSetupInstance::default(); usize::from(input.u8() % 40)];
    let mut batches = vec![DrawableSetupBatch::default(); usize::from(input.u8() % 40)];
    let (ci, cb) = (core::cell::Cell::new(0u32), core::cell::Cell::new(0u32));
    let mut stats = QueryStats::default();
    let r = query_cluster(
        &params,
        &tile,
        None,
        &mut fade,
        job,
        WaveWidth::W16,
        &ci,
        &mut out,
        &cb,
        &mut batches,
        &mut stats,
    );
    if view.occlusion_pass == staticscene::OcclusionPass::First {
        assert_eq!(fade, before, "the first pass of two wrote camera state");
    }
    match r {
        Ok(_) => {
            assert_eq!(stats.instances, u64::from(job.count));
            assert_eq!(u64::from(ci.get()), stats.visible);
            assert_eq!(
                stats.dropped,
                stats.visible.saturating_sub(out.len() as u64)
                    + stats.batches.saturating_sub(batches.len() as u64)
            );
        }
        Err(e) => assert!(matches!(e, Error::Config { .. }), "{e}"),
    }
}

/// A tile streamed in as arbitrary parts: small record tables, arbitrary instance words and
/// clusters. `StaticTile::from_parts` never panics; a tile it accepts has every index inside
/// its tables and clusters covering its instances in order, and the CPU query runs over
/// it; a refused one names an instance whose field really is out of range.
pub fn staticscene_tile_parts(data: &[u8]) {
    let mut input = Input::new(data);
    let mut parts = staticscene::TileParts {
        setups: vec![
            QuerySetup::new(Vec3::ZERO, Vec3::ONE, 1).expect("a unit box");
            usize::from(input.u8() % 4)
        ],
        objects: vec![bytemuck::Zeroable::zeroed(); usize::from(input.u8() % 4)],
        transforms: vec![Transform4x3::IDENTITY; usize::from(input.u8() % 4)],
        bounds: vec![bytemuck::Zeroable::zeroed(); usize::from(input.u8() % 4)],
        ..Default::default()
    };
    let n = usize::from(input.u8() % 48);
    for _ in 0..n {
        parts
            .instances
            .push(QueryInstance::from_bytes(input.bytes()));
    }
    let mut at = 0u32;
    while at < n as u32 && input.remaining() > 0 {
        let count = u32::from(input.u8() % 20) + u32::from(input.u8() % 2);
        parts.clusters.push(staticscene::Cluster {
            first: at,
            count,
            cull: staticscene::CullInfo::EMPTY,
        });
        at += count;
    }
    let tables = [
        parts.setups.len(),
        parts.objects.len(),
        parts.bounds.len(),
        parts.bounds.len(),
        parts.transforms.len(),
    ];
    let fields = |q: &QueryInstance| {
        [
            q.setup(),
            q.object(),
            q.parent_bounds(),
            q.child_bounds(),
            q.matrix(),
        ]
    };
    let instances = parts.instances.clone();
    match staticscene::StaticTile::from_parts(parts) {
        Ok(tile) => {
            for q in &instances {
                for (v, len) in fields(q).into_iter().zip(tables) {
                    assert!((v as usize) < len, "accepted an index past its table");
                }
            }
            let covered: u32 = tile.clusters().iter().map(|c| c.count).sum();
            assert_eq!(covered as usize, instances.len());
            let mut scene = Scene::new();
            scene.activate(staticscene::BuiltTile::new(tile));
            let cam = Camera::look_at(
                DVec3::new(0.0, 2.0, 5.0),
                DVec3::ZERO,
                DVec3::Y,
                Mat4::perspective_rh(1.0, 1.0, 0.1, 100.0),
                false,
            );
            let params = QueryParams::new(&ViewDesc::camera(cam, [64, 64])).expect("a valid view");
            let mut out = QueryOutput::<DrawableSetupInstance>::new();
            let options = QueryOptions {
                precull: false,
                ..QueryOptions::default()
            };
            scene
                .query(&params, None, &options, &mut out)
                .expect("an accepted tile queries");
        }
        Err(Error::TileRecord {
            instance,
            value,
            len,
            ..
        }) => {
            assert!(value as usize >= len);
            assert!(fields(&instances[instance]).contains(&value));
        }
        Err(Error::TileClusters { .. } | Error::SpareBitSet) => {}
        Err(e) => panic!("unexpected error {e}"),
    }
}
