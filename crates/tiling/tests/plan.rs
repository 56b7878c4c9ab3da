//! The micro-batch and pass builder: every rule of the module docs checked with plain
//! loops on random batches, the limits as errors that name the limit and the batch, and
//! instance overflow into consecutive micro-batch IDs.

use std::collections::BTreeSet;

use proptest::prelude::*;
use tiling::{
    Batch, Error, Geometry, MAX_PASSES, MAX_PRIMITIVES_PER_GEOMETRY, Plan, PlanConfig, build_plan,
};
use visbuf::{VisFields, VisId, VisLayout};

fn geometry(prims: u32, verts: u32) -> Geometry {
    Geometry {
        vertex_count: verts,
        primitive_count: prims,
        first_index: 7,
        base_vertex: 11,
    }
}

/// A batch of shader 0 with `instances` at the given positions.
fn batch(batch_data: u64, geometry: Geometry, instances: &[[f32; 3]]) -> Batch<'_> {
    Batch {
        shader: 0,
        batch_data,
        geometry,
        instances,
    }
}

/// The plan of `batches`, checked by [`check_plan`].
fn checked_plan(batches: &[Batch<'_>], config: &PlanConfig) -> Plan {
    let plan = build_plan(batches, config).expect("the batches fit the limits");
    check_plan(batches, config, &plan);
    plan
}

/// Checks a plan against the batches with plain loops.
fn check_plan(batches: &[Batch<'_>], config: &PlanConfig, plan: &Plan) {
    let vertex_limit = u64::from(config.max_micro_batch_vertices)
        .min(config.ring_bytes / u64::from(config.vertex_bytes) / 2);
    let budget = config.ring_bytes / u64::from(config.vertex_bytes) / 2;
    // Every instance exactly once, in order within its batch.
    let mut seen: BTreeSet<(u32, u32)> = BTreeSet::new();
    for r in plan.instance_refs() {
        assert!(seen.insert((r.batch, r.instance)), "instance placed twice");
    }
    let expected: usize = batches.iter().map(|b| b.instances.len()).sum();
    assert_eq!(seen.len(), expected);
    assert_eq!(plan.instance_count as usize, expected);
    assert_eq!(
        plan.empty_batches as usize,
        batches.iter().filter(|b| b.instances.is_empty()).count()
    );

    let mut next_id = 0u32;
    let mut next_chunk = 0u32;
    let mut next_instance = 0u32;
    let mut vertices = 0u64;
    for (k, mb) in plan.micro_batches.iter().enumerate() {
        let b = &batches[mb.batch as usize];
        let g = b.geometry;
        assert_eq!(mb.order as usize, k);
        assert!(mb.instance_count >= 1);
        assert!(mb.instance_count <= config.max_micro_batch_instances);
        assert!(
            u64::from(mb.instance_count) * u64::from(g.primitive_count)
                <= u64::from(config.max_micro_batch_primitives)
        );
        assert!(u64::from(mb.instance_count) * u64::from(g.vertex_count) <= vertex_limit);
        assert_eq!(
            (
                mb.primitive_count,
                mb.vertex_count,
                mb.first_index,
                mb.base_vertex
            ),
            (
                g.primitive_count,
                g.vertex_count,
                g.first_index,
                g.base_vertex
            )
        );
        // Primitive bits by a loop; IDs = ceil(instances / 2^(16 - p)).
        let mut p = 0;
        while (1u64 << p) < u64::from(g.primitive_count) {
            p += 1;
        }
        assert_eq!(mb.primitive_bits, p);
        let per_id = 1u64 << (16 - p);
        assert_eq!(
            u64::from(mb.id_count),
            u64::from(mb.instance_count).div_ceil(per_id)
        );
        assert_eq!(mb.first_id, next_id, "IDs are consecutive");
        next_id += mb.id_count;
        for id in mb.first_id..mb.first_id + mb.id_count {
            assert_eq!(
                plan.table[id as usize], *mb,
                "every ID of the range holds the row"
            );
        }
        assert_eq!(plan.order[k], mb.first_id);
        assert_eq!(mb.first_chunk, next_chunk);
        let chunks = (u64::from(mb.instance_count) * u64::from(g.vertex_count)).div_ceil(64) as u32;
        assert_eq!(mb.chunk_count(), chunks);
        next_chunk += chunks;
        assert_eq!(mb.first_instance, next_instance);
        next_instance += mb.instance_count;
        vertices += u64::from(mb.instance_count) * u64::from(g.vertex_count);
        // The instance mapping decodes back through visbuf.
        for i in [0, mb.instance_count - 1] {
            let (id, field) = mb.instance_id(i);
            assert!(id >= mb.first_id && id < mb.first_id + mb.id_count);
            let word = VisId::pack(
                config.layout,
                mb.bits(),
                VisFields {
                    micro_batch: id,
                    instance: field,
                    primitive: 0,
                    rate: visbuf::ShadingRate::Rate1x1,
                },
            )
            .unwrap();
            let back = visbuf::instance_index(
                word.micro_batch(config.layout),
                mb.first_id,
                word.instance_field(mb.bits()),
                mb.bits(),
            );
            assert_eq!(back, i);
        }
    }
    assert_eq!(plan.table.len() as u32, next_id);
    assert_eq!(plan.chunk_count, next_chunk);
    assert_eq!(plan.vertex_count, vertices);

    // Sort: (shader, batch data) never decreases along the micro batches; a batch's micro
    // batches take its instances in order.
    let keys: Vec<(u32, u64)> = plan
        .micro_batches
        .iter()
        .map(|m| {
            (
                batches[m.batch as usize].shader,
                batches[m.batch as usize].batch_data,
            )
        })
        .collect();
    assert!(
        keys.windows(2).all(|w| w[0] <= w[1]),
        "micro batches sorted by shader and data"
    );
    let mut cursor = vec![0u32; batches.len()];
    for mb in &plan.micro_batches {
        assert_eq!(mb.batch_first_instance, cursor[mb.batch as usize]);
        cursor[mb.batch as usize] += mb.instance_count;
    }

    // Passes: contiguous runs of one shader, within budget, at most the group limit.
    assert!(plan.passes.len() as u32 <= config.max_passes);
    let mut next_mb = 0u32;
    for (p, pass) in plan.passes.iter().enumerate() {
        assert_eq!(pass.first_micro_batch, next_mb);
        assert!(pass.micro_batch_count >= 1);
        next_mb += pass.micro_batch_count;
        let mbs = &plan.micro_batches[pass.first_micro_batch as usize
            ..(pass.first_micro_batch + pass.micro_batch_count) as usize];
        let mut ring = 0u32;
        let mut groups = Vec::new();
        for mb in mbs {
            let b = &batches[mb.batch as usize];
            assert_eq!(mb.pass as usize, p);
            assert_eq!(b.shader, pass.shader);
            assert_eq!(mb.ring_offset, ring);
            ring += mb.instance_count * mb.vertex_count;
            if !groups.contains(&b.batch_data) {
                groups.push(b.batch_data);
            }
            assert_eq!(plan.pass_groups[p][mb.batch_group as usize], b.batch_data);
        }
        assert_eq!(pass.vertex_count, ring);
        assert!(u64::from(ring) <= budget, "pass {p} over half the ring");
        assert_eq!(plan.pass_groups[p], groups);
        assert_eq!(pass.batch_group_count as usize, groups.len());
        assert!(pass.batch_group_count <= config.max_batch_groups);
        assert_eq!(pass.first_chunk, mbs[0].first_chunk);
        assert_eq!(
            pass.chunk_count,
            mbs.iter().map(|m| m.chunk_count()).sum::<u32>()
        );
    }
    assert_eq!(next_mb as usize, plan.micro_batches.len());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn plans_follow_every_rule(
        batches in proptest::collection::vec((0u32..3, 0u64..8, 1u32..5000, 1u32..3000, 0usize..400), 0..40),
        vrs: bool,
        small: bool,
    ) {
        let positions: Vec<Vec<[f32; 3]>> = batches
            .iter()
            .enumerate()
            .map(|(i, b)| (0..b.4).map(|j| [i as f32, (j % 7) as f32, -(j as f32)]).collect())
            .collect();
        let bs: Vec<Batch<'_>> = batches
            .iter()
            .zip(&positions)
            .map(|(b, pos)| Batch { shader: b.0, batch_data: b.1, geometry: geometry(b.2.min(MAX_PRIMITIVES_PER_GEOMETRY), b.3), instances: pos })
            .collect();
        let mut config = PlanConfig { layout: if vrs { VisLayout::Vrs } else { VisLayout::Standard }, ..PlanConfig::ps4() };
        if small {
            config.max_micro_batch_vertices = 5000;
            config.max_micro_batch_primitives = 6000;
            config.max_micro_batch_instances = 100;
            config.max_batch_groups = 2;
            config.ring_bytes = 32 * 2 * 20_000;
        }
        match build_plan(&bs, &config) {
            Ok(plan) => check_plan(&bs, &config, &plan),
            Err(Error::InstanceTooLarge { batch, vertices, limit }) => {
                prop_assert!(vertices > limit);
                prop_assert_eq!(bs[batch as usize].geometry.vertex_count, vertices);
            }
            Err(Error::GeometryTooLarge { batch, primitives, limit }) => {
                prop_assert!(primitives > limit);
                prop_assert_eq!(bs[batch as usize].geometry.primitive_count, primitives);
            }
            Err(Error::TooManyPasses { .. }) => prop_assert!(small),
            Err(e) => prop_assert!(false, "unexpected {e}"),
        }
    }
}

#[test]
fn instance_overflow_takes_consecutive_ids() {
    // 1000 triangles: 10 primitive bits, 64 instances per ID; 65 * 1000 triangles fit one
    // micro batch, so it spans two IDs; the 66th instance starts the next micro batch.
    let pos = vec![[0.0f32; 3]; 66];
    let b = [batch(0, geometry(1000, 500), &pos)];
    let plan = checked_plan(&b, &PlanConfig::default());
    assert_eq!(plan.micro_batches.len(), 2);
    let (m0, m1) = (plan.micro_batches[0], plan.micro_batches[1]);
    assert_eq!((m0.first_id, m0.id_count, m0.instance_count), (0, 2, 65));
    assert_eq!(
        (
            m1.first_id,
            m1.id_count,
            m1.instance_count,
            m1.batch_first_instance
        ),
        (2, 1, 1, 65)
    );
    assert_eq!(plan.table.len(), 3);
    assert_eq!(plan.table[1], m0);
    assert_eq!(plan.order, [0, 2]);
    let refs = plan.instance_refs();
    assert_eq!((refs[63].micro_batch_id, refs[63].instance_field), (0, 63));
    assert_eq!((refs[64].micro_batch_id, refs[64].instance_field), (1, 0));
    assert_eq!((refs[65].micro_batch_id, refs[65].instance_field), (2, 0));
}

#[test]
fn full_16_bit_geometry_takes_one_instance_per_micro_batch() {
    let pos = vec![[0.0f32; 3]; 3];
    let b = [batch(0, geometry(65_536, 70_000), &pos)];
    let plan = build_plan(&b, &PlanConfig::default()).unwrap();
    assert_eq!(plan.micro_batches.len(), 3);
    assert!(
        plan.micro_batches
            .iter()
            .all(|m| m.instance_count == 1 && m.primitive_bits == 16 && m.id_count == 1)
    );
    // 70 000 vertices: 5 fit a PS5 pass of 393 216; all three in one pass.
    assert_eq!(plan.passes.len(), 1);
    // PS4: half the ring is 196 608 vertices: two per pass.
    let plan = build_plan(&b, &PlanConfig::ps4()).unwrap();
    assert_eq!(
        plan.passes
            .iter()
            .map(|p| p.micro_batch_count)
            .collect::<Vec<_>>(),
        [2, 1]
    );
}

#[test]
fn a_batch_splits_over_passes_to_fill_them() {
    // 100 instances of 3000 vertices = 300 000 vertices; PS4 passes hold 196 608, micro
    // batches 192k = 196 608 too: the first pass takes 65 instances (195 000), the second 35.
    let pos = vec![[0.0f32; 3]; 100];
    let b = [batch(0, geometry(100, 3000), &pos)];
    let plan = checked_plan(&b, &PlanConfig::ps4());
    let per_pass: Vec<u32> = plan.passes.iter().map(|p| p.vertex_count / 3000).collect();
    assert_eq!(per_pass, [65, 35]);
}

#[test]
fn batch_groups_are_limited_to_32_per_pass() {
    let pos = vec![[0.0f32; 3]; 1];
    let b: Vec<Batch<'_>> = (0..70u64).map(|d| batch(d, geometry(2, 4), &pos)).collect();
    let plan = checked_plan(&b, &PlanConfig::default());
    let groups: Vec<u32> = plan.passes.iter().map(|p| p.batch_group_count).collect();
    assert_eq!(groups, [32, 32, 6]);
}

#[test]
fn limits_are_errors_that_name_the_limit_and_the_batch() {
    let pos = vec![[0.0f32; 3]; 2];
    let ok = batch(0, geometry(10, 10), &pos);
    let too_many_prims = Batch {
        geometry: geometry(65_537, 10),
        ..ok
    };
    let e = build_plan(&[ok, too_many_prims], &PlanConfig::default()).unwrap_err();
    assert_eq!(
        e,
        Error::GeometryTooLarge {
            batch: 1,
            primitives: 65_537,
            limit: 65_536
        }
    );
    let msg = e.to_string();
    assert!(
        msg.contains("batch 1")
            && msg.contains("MAX_PRIMITIVES_PER_GEOMETRY")
            && msg.contains("65537"),
        "{msg}"
    );

    let empty = Batch {
        geometry: geometry(0, 10),
        ..ok
    };
    assert_eq!(
        build_plan(&[empty], &PlanConfig::default()),
        Err(Error::EmptyGeometry { batch: 0 })
    );

    let huge = Batch {
        geometry: geometry(10, 200_000),
        ..ok
    };
    let e = build_plan(&[ok, ok, huge], &PlanConfig::ps4()).unwrap_err();
    assert_eq!(
        e,
        Error::InstanceTooLarge {
            batch: 2,
            vertices: 200_000,
            limit: 196_608
        }
    );
    assert!(e.to_string().contains("MAX_MICRO_BATCH_VERTICES"));

    // 257 shaders: 257 passes. The error names the batch that needed the 257th.
    let many: Vec<Batch<'_>> = (0..257u32)
        .map(|s| Batch {
            shader: 1000 - s,
            ..ok
        })
        .collect();
    let e = build_plan(&many, &PlanConfig::default()).unwrap_err();
    assert_eq!(
        e,
        Error::TooManyPasses {
            batch: 0,
            limit: MAX_PASSES
        }
    );
    assert!(e.to_string().contains("MAX_PASSES"));
    assert!(build_plan(&many[..256], &PlanConfig::default()).is_ok());
    let few = PlanConfig {
        max_passes: 3,
        ..PlanConfig::default()
    };
    assert!(matches!(
        build_plan(&many[..4], &few),
        Err(Error::TooManyPasses { limit: 3, .. })
    ));

    // The VRS layout has 16 383 micro-batch IDs.
    let one = vec![[0.0f32; 3]; 1];
    let tiny = batch(0, geometry(1, 3), &one);
    let lots = vec![tiny; 16_384];
    let vrs = PlanConfig {
        layout: VisLayout::Vrs,
        ..PlanConfig::default()
    };
    assert!(build_plan(&lots[..16_383], &vrs).is_ok());
    let e = build_plan(&lots, &vrs).unwrap_err();
    assert_eq!(
        e,
        Error::MicroBatchIdsExhausted {
            batch: 16_383,
            needed: 1,
            available: 0,
            layout: VisLayout::Vrs
        }
    );

    // Bad configurations name the setting.
    let too_many_passes = PlanConfig {
        max_passes: 300,
        ..PlanConfig::default()
    };
    let tiny_ring = PlanConfig {
        ring_bytes: 10,
        ..PlanConfig::default()
    };
    for (bad, setting) in [(too_many_passes, "max_passes"), (tiny_ring, "ring_bytes")] {
        assert!(
            matches!(
                build_plan(&[ok], &bad),
                Err(Error::InvalidConfig { what, .. }) if what == setting
            ),
            "{setting}"
        );
    }
}

#[test]
fn empty_batches_produce_nothing_and_are_counted() {
    let pos = vec![[0.0f32; 3]; 5];
    let b = [
        Batch {
            shader: 0,
            batch_data: 0,
            geometry: geometry(10, 10),
            instances: &[],
        },
        batch(0, geometry(10, 10), &pos),
    ];
    let plan = build_plan(&b, &PlanConfig::default()).unwrap();
    assert_eq!((plan.empty_batches, plan.micro_batches.len()), (1, 1));
    assert_eq!(
        build_plan(&[], &PlanConfig::default()).unwrap(),
        Plan::default()
    );
}

#[test]
fn batches_sort_by_shader_data_then_position() {
    // Same shader and data: the Morton code of the mean position orders them (x lowest).
    let far = vec![[100.0f32, 0.0, 0.0]; 1];
    let near = vec![[0.0f32, 0.0, 0.0]; 1];
    let mid = vec![[50.0f32, 0.0, 0.0]; 1];
    let g = geometry(10, 10);
    let shader_1 = |instances| Batch {
        shader: 1,
        ..batch(0, g, instances)
    };
    let b = [
        shader_1(&far),
        shader_1(&near),
        batch(9, g, &far),
        shader_1(&mid),
    ];
    let plan = build_plan(&b, &PlanConfig::default()).unwrap();
    let order: Vec<u32> = plan.micro_batches.iter().map(|m| m.batch).collect();
    assert_eq!(order, [2, 1, 3, 0]);
    assert_eq!(plan.passes.len(), 2);
}

/// Reserved ranges: every rank's vis word decodes (through the table, with the pixel
/// decoder's arithmetic written out here) to its own slot; the planned part is untouched;
/// passes follow the shader runs; errors leave the plan as it was.
#[test]
fn reservations_map_every_rank_to_its_own_slot() {
    use tiling::Reservation;
    let positions = vec![[0.0f32; 3]; 300];
    let batches = [batch(1, geometry(30, 40), &positions)];
    let config = PlanConfig::default();
    let planned = build_plan(&batches, &config).unwrap();
    let mut plan = planned.clone();
    let res = [
        Reservation {
            shader: 0,
            batch_data: 2,
            geometry: geometry(12, 24),
            capacity: 150_000,
        },
        Reservation {
            shader: 0,
            batch_data: 3,
            geometry: geometry(1, 3),
            capacity: 70_000,
        },
        Reservation {
            shader: 1,
            batch_data: 2,
            geometry: geometry(65_536, 9),
            capacity: 3,
        },
    ];
    let ranges = plan.reserve(&res, &config).unwrap();
    assert_eq!(plan.table[..planned.table.len()], planned.table[..]);
    assert_eq!(plan.passes[..planned.passes.len()], planned.passes[..]);
    assert_eq!(plan.passes.len(), planned.passes.len() + 2);
    assert_eq!(
        plan.instance_count,
        planned.instance_count + 150_000 + 70_000 + 3
    );
    let mut slots = BTreeSet::new();
    for (r, range) in res.iter().zip(&ranges) {
        let p = range.primitive_bits;
        assert!(1u32 << p >= r.geometry.primitive_count);
        for rank in (0..r.capacity).step_by(97).chain([r.capacity - 1]) {
            let per_id = 1u32 << (16 - p);
            let id = range.first_id + rank / per_id;
            let field = rank % per_id;
            let row = plan.row(id).expect("every ID of the range has a row");
            assert!(id >= row.first_id && id - row.first_id < row.id_count);
            let within = ((id - row.first_id) << (16 - p)) | field;
            assert!(within < row.instance_count);
            let slot = row.first_instance + within;
            assert_eq!(slot, range.first_instance + rank);
            assert_eq!(plan.passes[row.pass as usize].shader, r.shader);
            assert!(row.first_chunk + row.chunk_count() <= plan.chunk_count);
            slots.insert(slot);
        }
    }
    // Too many IDs: the plan is unchanged and the error names the reservation.
    let before = plan.clone();
    let big = Reservation {
        shader: 2,
        batch_data: 0,
        geometry: geometry(65_536, 3),
        capacity: 70_000,
    };
    assert!(matches!(
        plan.reserve(&[res[1], big], &config),
        Err(Error::MicroBatchIdsExhausted { batch: 1, .. })
    ));
    assert_eq!(plan, before);
    let zero = Reservation {
        capacity: 0,
        ..res[0]
    };
    assert!(matches!(
        plan.reserve(&[zero], &config),
        Err(Error::InvalidConfig { .. })
    ));
    let empty = Reservation {
        geometry: geometry(0, 3),
        ..res[0]
    };
    assert_eq!(
        plan.reserve(&[empty], &config),
        Err(Error::EmptyGeometry { batch: 0 })
    );
    assert_eq!(plan, before);
}
