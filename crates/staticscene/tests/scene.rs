//! Tiles from streaming groups (split, orphans, removal, nothing lost), the pre-cull
//! (never changes the output), and the floating origin (0.1 mm at 10^6 m against f64).

mod common;

use std::collections::HashMap;

use common::*;
use glam::{Affine3A, DQuat, DVec3, Mat3, Mat4, Vec3};
use staticscene::demo::city;
use staticscene::{
    BuildConfig, BuiltTile, Camera, DrawableSetupInstance, DynamicReason, MIN_CLUSTER_INSTANCES,
    MeshNode, MeshPart, PlacedObject, QueryOptions, QueryOutput, QueryParams, ResourceLibrary,
    Scene, StaticTile, StreamingGroup, TILE_SPLIT_INSTANCES, TileStreamer, TileUpdate, ViewDesc,
};
use testkit::Rng;

fn assert_send<T: Send>() {}

#[test]
fn building_data_is_send() {
    assert_send::<TileStreamer>();
    assert_send::<TileUpdate>();
    assert_send::<BuiltTile>();
    assert_send::<StaticTile>();
}

/// A resource of `k` boxes side by side (k instances per placement).
fn row(k: u64, base: u64) -> MeshNode {
    MeshNode::Multi(
        (0..k)
            .map(|i| MeshPart {
                local_to_parent: Affine3A::from_translation(Vec3::new(i as f32 * 2.0, 0.0, 0.0)),
                node: mesh(base + i, Vec3::splat(-0.5), Vec3::splat(0.5)),
            })
            .collect(),
    )
}

#[test]
fn groups_split_orphan_and_remove_whole() {
    let resources = vec![row(10, 0), row(3, 100)];
    let big = group(
        1,
        (0..6000) // 60 000 instances: 3 tiles of about 20 000
            .map(|i| {
                PlacedObject::new(
                    0,
                    DVec3::new(f64::from(i % 80) * 25.0, 0.0, f64::from(i / 80) * 5.0),
                )
            })
            .collect(),
    );
    let small_a = group(
        2,
        (0..50)
            .map(|i| PlacedObject::new(1, DVec3::new(f64::from(i), 0.0, -50.0)))
            .collect(),
    );
    let small_b = group(
        3,
        (0..20)
            .map(|i| PlacedObject::new(0, DVec3::new(f64::from(i), 0.0, -90.0)))
            .collect(),
    );
    let mut streamer = TileStreamer::new(ResourceLibrary::new(&resources), BuildConfig::default());
    let mut scene = Scene::new();

    let u = streamer.add_group(&big).unwrap();
    assert_eq!(u.add.len(), 3);
    for t in &u.add {
        let n = t.tile().instances().len();
        assert!((19_000..=TILE_SPLIT_INSTANCES).contains(&n), "{n}");
        assert_eq!(t.tile().groups(), &[1]);
        // Clusters cover the tile in order, each at least the minimum.
        let mut next = 0;
        for c in t.tile().clusters() {
            assert_eq!(c.first, next);
            assert!(c.count as usize >= MIN_CLUSTER_INSTANCES);
            next += c.count;
        }
        assert_eq!(next as usize, n);
    }
    scene.apply(u);
    assert_eq!(scene.instance_count(), 60_000);

    // Small groups share the orphan tile, rebuilt as they come and go.
    let u = streamer.add_group(&small_a).unwrap();
    assert_eq!((u.add.len(), u.remove.len()), (1, 0));
    scene.apply(u);
    let u = streamer.add_group(&small_b).unwrap();
    assert_eq!((u.add.len(), u.remove.len()), (1, 1));
    assert_eq!(u.add[0].tile().groups(), &[2, 3]);
    scene.apply(u);
    assert_eq!(scene.tiles().len(), 4);
    assert_eq!(scene.instance_count(), 60_000 + 150 + 200);
    assert!(
        streamer.add_group(&small_b).is_err(),
        "adds and removes match"
    );

    let u = streamer.remove_group(2).unwrap();
    assert_eq!(u.add[0].tile().groups(), &[3]);
    scene.apply(u);
    assert_eq!(scene.instance_count(), 60_000 + 200);
    scene.apply(streamer.remove_group(1).unwrap());
    scene.apply(streamer.remove_group(3).unwrap());
    assert_eq!(scene.instance_count(), 0);
    assert!(scene.tiles().is_empty());
    assert!(streamer.remove_group(3).is_err());
}

#[test]
fn nothing_is_lost_and_misfits_go_dynamic() {
    let cfg = staticscene::demo::CityConfig::with_instances(40_000);
    let c = city(&cfg);
    let lib = ResourceLibrary::new(&c.resources);
    let mut streamer = TileStreamer::new(lib.clone(), BuildConfig::default());
    let mut scene = Scene::new();
    let mut dynamic = Vec::new();
    for g in &c.groups {
        let u = streamer.add_group(g).unwrap();
        dynamic.extend(u.dynamic.iter().copied());
        scene.apply(u);
    }
    // Expected: every leaf of every fitting object, as (setup handle, snapped position).
    let mut want: HashMap<(u64, [i32; 3]), usize> = HashMap::new();
    let mut want_dynamic = 0;
    for g in &c.groups {
        for (i, o) in g.objects.iter().enumerate() {
            match lib.get(o.resource).unwrap() {
                Ok(f) => {
                    let snapped = staticscene::snap_origin(o.position).to_array();
                    for leaf in &f.leaves {
                        *want.entry((leaf.setup.handle, snapped)).or_default() += 1;
                    }
                }
                Err(reason) => {
                    want_dynamic += 1;
                    assert!(
                        dynamic
                            .iter()
                            .any(|d| d.group == g.id && d.object == i && d.reason == *reason),
                        "misfit {i} of group {} listed with its reason",
                        g.id
                    );
                    assert!(matches!(
                        reason,
                        DynamicReason::TooManyLodLevels { depth: 3 } | DynamicReason::NotStatic
                    ));
                }
            }
        }
    }
    assert!(want_dynamic > 0, "the demo city has misfits");
    assert_eq!(dynamic.len(), want_dynamic);
    let mut got: HashMap<(u64, [i32; 3]), usize> = HashMap::new();
    for t in scene.tiles() {
        for q in t.instances() {
            let f = q.try_unpack().unwrap();
            let h = t.setups()[f.setup as usize].handle;
            *got.entry((h, t.objects()[f.object as usize].snapped))
                .or_default() += 1;
        }
        // Stored once each.
        for (name, n, distinct) in [
            ("objects", t.objects().len(), distinct(t.objects())),
            ("setups", t.setups().len(), distinct(t.setups())),
            ("matrices", t.transforms().len(), distinct(t.transforms())),
            ("bounds", t.bounds().len(), distinct(t.bounds())),
        ] {
            assert_eq!(n, distinct, "{name} deduplicated");
        }
    }
    assert_eq!(got, want);
}

fn distinct<T: bytemuck::Pod>(v: &[T]) -> usize {
    let mut b: Vec<&[u8]> = v.iter().map(bytemuck::bytes_of).collect();
    b.sort();
    b.dedup();
    b.len()
}

#[test]
fn bad_placements_go_dynamic_with_reasons() {
    let resources = vec![mesh(1, Vec3::splat(-1.0), Vec3::ONE)];
    let mut far = PlacedObject::new(0, DVec3::new(3e9, 0.0, 0.0));
    far.lod_scale = 1.0;
    let mut zero_scale = PlacedObject::new(0, DVec3::ZERO);
    zero_scale.lod_scale = 0.0;
    let mut huge = PlacedObject::new(0, DVec3::ZERO);
    huge.linear = Mat3::from_diagonal(Vec3::splat(1e30));
    let g = StreamingGroup {
        id: 9,
        objects: vec![far, zero_scale, huge, PlacedObject::new(0, DVec3::ONE)],
    };
    let mut streamer = TileStreamer::new(ResourceLibrary::new(&resources), BuildConfig::default());
    let u = streamer.add_group(&g).unwrap();
    assert_eq!(
        u.dynamic.iter().map(|d| d.object).collect::<Vec<_>>(),
        [0, 1, 2]
    );
    assert!(
        u.dynamic
            .iter()
            .all(|d| matches!(d.reason, DynamicReason::Placement(_)))
    );
    assert_eq!(
        u.add
            .iter()
            .map(|t| t.tile().instances().len())
            .sum::<usize>(),
        1
    );
    let unknown = StreamingGroup {
        id: 10,
        objects: vec![PlacedObject::new(5, DVec3::ZERO)],
    };
    assert!(streamer.add_group(&unknown).is_err());
}

#[test]
fn precull_never_changes_the_output() {
    let (mut scene, cfg) = city_scene(120_000, 17);
    let size = cfg.lots[0] as f64 * f64::from(cfg.lot_size);
    let mut rng = Rng::new(4);
    let mut culled = 0;
    for _ in 0..12 {
        let cam = Camera {
            position: DVec3::new(
                f64::from(rng.range(-0.2, 1.2)) * size,
                f64::from(rng.range(1.0, 200.0)),
                f64::from(rng.range(-0.2, 1.2)) * size,
            ),
            rotation: DQuat::from_euler(
                glam::EulerRot::YXZ,
                f64::from(rng.range(0.0, 6.3)),
                f64::from(rng.range(-0.8, 0.2)),
                0.0,
            ),
            projection: Mat4::perspective_rh(rng.range(0.4, 1.8), 16.0 / 9.0, 0.1, 5000.0),
            reversed_depth: false,
        };
        let mut view = ViewDesc::camera(cam, [640, 360]);
        view.fade_frames = 0;
        view.lod_scale = rng.range(0.5, 2.0);
        let params = QueryParams::new(&view).unwrap();
        let (mut on, mut off) = (
            QueryOutput::<DrawableSetupInstance>::new(),
            QueryOutput::new(),
        );
        scene
            .query(&params, None, &QueryOptions::default(), &mut on)
            .unwrap();
        scene
            .query(
                &params,
                None,
                &QueryOptions {
                    precull: false,
                    ..QueryOptions::default()
                },
                &mut off,
            )
            .unwrap();
        assert!(on.instances == off.instances);
        assert!(on.batches == off.batches);
        assert_eq!(on.stats.visible, off.stats.visible);
        culled += on.stats.clusters_culled + on.stats.tiles_culled;
    }
    assert!(culled > 0, "the pre-cull did reject something");
}

#[test]
fn floating_origin_keeps_a_tenth_of_a_millimetre_at_a_million_metres() {
    let mut rng = Rng::new(99);
    let far = DVec3::new(1.0e6, 250.0, -1.0e6);
    let mut resources = Vec::new();
    let mut objects = Vec::new();
    let mut truth = Vec::new();
    for i in 0..200 {
        let local = Affine3A::from_rotation_translation(
            rotation(rng.range(0.0, 6.3), 0.3, 0.0),
            Vec3::new(
                rng.range(-5.0, 5.0),
                rng.range(0.0, 5.0),
                rng.range(-5.0, 5.0),
            ),
        );
        resources.push(placed(
            local,
            mesh(i as u64, Vec3::splat(-0.5), Vec3::splat(0.5)),
        ));
        let p = far
            + DVec3::new(
                f64::from(rng.range(-60.0, 60.0)) + 0.123_456_7,
                f64::from(rng.range(-5.0, 5.0)),
                f64::from(rng.range(-120.0, -10.0)) + 0.765_432_1,
            );
        let linear = Mat3::from_quat(rotation(rng.range(0.0, 6.3), 0.0, 0.0));
        let mut o = PlacedObject::new(i, p);
        o.linear = linear;
        objects.push(o);
        truth.push((p, linear, local));
    }
    let mut scene = one_group_scene(&resources, objects);
    let eye = far + DVec3::new(0.37, 1.61, 0.52);
    let cam = perspective(eye, eye + DVec3::new(0.0, 0.0, -1.0), 1.6, 1.0, false);
    let mut view = ViewDesc::camera(cam, [256, 256]);
    view.fade_frames = 0;
    let params = QueryParams::new(&view).unwrap();
    let mut out = QueryOutput::<DrawableSetupInstance>::new();
    scene
        .query(&params, None, &QueryOptions::default(), &mut out)
        .unwrap();
    assert!(out.batches.len() > 50);
    let origin = params.origin().as_dvec3();
    let mut worst = 0.0f64;
    for b in &out.batches {
        let (p, linear, local) = truth[b.setup as usize];
        let inst = &out.instances[b.first_instance as usize];
        for c in corners(Vec3::splat(-0.5), Vec3::splat(0.5), |x| x) {
            // f64 reference: world position minus the snapped origin.
            let want = p + linear.as_dmat3()
                * (local.matrix3.as_dmat3() * c + local.translation.as_dvec3())
                - origin;
            let got = inst
                .local_to_floating
                .transform_point(c.as_vec3())
                .as_dvec3();
            worst = worst.max((got - want).length());
        }
    }
    println!("worst floating-space error at 10^6 m: {:.3e} m", worst);
    assert!(worst < 1e-4, "worst error {worst} m");
    // For scale: the same points in plain f32 world coordinates are off by centimetres.
    let naive = (far.x as f32 + 0.123_456_7) as f64 - (far.x + 0.123_456_7);
    assert!(naive.abs() > 1e-3);
}

#[test]
fn index_spaces_split_tiles() {
    // 5000 objects with a setup each: more than a tile's 4096 setups, so two tiles although
    // the 5000 instances are far below the 24K split.
    let resources: Vec<MeshNode> = (0..5000)
        .map(|i| mesh(i, Vec3::splat(-0.5), Vec3::splat(0.5)))
        .collect();
    let objects = (0..5000)
        .map(|i| PlacedObject::new(i, DVec3::new(i as f64, 0.0, 0.0)))
        .collect();
    let mut streamer = TileStreamer::new(ResourceLibrary::new(&resources), BuildConfig::default());
    let u = streamer.add_group(&group(1, objects)).unwrap();
    assert_eq!(u.add.len(), 2);
    for t in &u.add {
        assert!(t.tile().setups().len() <= staticscene::MAX_SETUPS_PER_TILE);
    }
    assert_eq!(
        u.add
            .iter()
            .map(|t| t.tile().instances().len())
            .sum::<usize>(),
        5000
    );
}

/// Moves one index field of an instance past its table.
type Corrupt = fn(&mut staticscene::InstanceFields, &staticscene::TileParts);

/// A tile streamed in as plain parts: the builder's tiles round-trip; an instance whose
/// setup, object, bounds or matrix index points past its tile's table is refused naming
/// the tile, the instance and the field; clusters that skip or stop short are refused; the
/// spare bit is refused.
#[test]
fn tiles_from_parts_check_every_record_index() {
    let (scene, _) = city_scene(4_000, 3);
    // Every tile the builder makes round-trips through its parts.
    for t in scene.tiles() {
        assert_eq!(
            StaticTile::from_parts(t.clone().into_parts()).as_ref(),
            Ok(t)
        );
    }
    let tile = scene.tiles()[0].clone();
    let parts = tile.clone().into_parts();
    let n = parts.instances.len();
    let at = n / 2;
    let fields = parts.instances[at].try_unpack().unwrap();
    let corrupt: [(&str, Corrupt); 5] = [
        ("setup index", |f, p| f.setup = p.setups.len() as u16),
        ("object index", |f, p| f.object = p.objects.len() as u32),
        ("parent bounds index", |f, p| {
            f.parent_bounds = p.bounds.len() as u16
        }),
        ("child bounds index", |f, p| {
            f.child_bounds = p.bounds.len() as u16 + 3
        }),
        ("matrix index", |f, p| f.matrix = p.transforms.len() as u16),
    ];
    for (name, change) in corrupt {
        let mut bad = parts.clone();
        let mut f = fields;
        change(&mut f, &parts);
        bad.instances[at] = staticscene::QueryInstance::pack(&f).unwrap();
        let e = StaticTile::from_parts(bad).unwrap_err();
        let msg = e.to_string();
        assert!(
            msg.contains(name) && msg.contains(&format!("instance {at}")),
            "{name}: {msg}"
        );
    }
    let mut gap = parts.clone();
    if gap.clusters.len() > 1 {
        gap.clusters[1].first += 1;
    } else {
        gap.clusters[0].count -= 1;
    }
    assert!(matches!(
        StaticTile::from_parts(gap),
        Err(staticscene::Error::TileClusters { .. })
    ));
    let mut short = parts.clone();
    short.clusters.pop();
    assert!(StaticTile::from_parts(short).is_err());
    let mut spare = parts;
    spare.instances[0].words[3] |= 1 << 31;
    assert_eq!(
        StaticTile::from_parts(spare),
        Err(staticscene::Error::SpareBitSet)
    );
}
