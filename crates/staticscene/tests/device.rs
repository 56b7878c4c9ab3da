//! The query's WGSL run on testkit's device (lavapipe in CI) against the Rust reference:
//! the f16 decode, the query pass against `Scene::query` over frames and on corrupt
//! records, and the HiZ pass against `HiZ::build`. A machine without a GPU driver fails,
//! saying how to install one.

/// `staticscene_f16` (the half-float decode of the culling boxes and LOD scales, written
/// out because `unpack2x16float` needs a capability) against the `half` crate for every
/// finite f16 pattern: exact.
#[test]
fn wgsl_f16_decode_is_exact_for_every_finite_half() {
    let items = 1u32 << 16;
    let out = testkit::device::run_words(
        &[staticscene::wgsl::MODULES],
        "#import staticscene::query",
        "_ = input[0];\n    output[i] = bitcast<u32>(staticscene_f16(i));",
        &[0],
        items,
        1,
        &[],
    );
    let mut checked = 0;
    for h in 0..=u16::MAX {
        let want = half::f16::from_bits(h);
        // The encoder never stores infinities or NaN.
        if !want.is_finite() {
            continue;
        }
        let got = f32::from_bits(out[usize::from(h)]);
        assert_eq!(
            got.to_bits(),
            want.to_f32().to_bits(),
            "{h:#06x}: {got} vs {want}"
        );
        checked += 1;
    }
    assert_eq!(
        checked, 63_488,
        "every finite half (2^16 - 2 * 1024 inf/NaN)"
    );
}

mod common;

use std::collections::BTreeMap;

use glam::DVec3;
use staticscene::demo::{CityConfig, box_hiz, city, street_camera};
use staticscene::pass::{
    GpuPlan, QUERY_PASS, QueryCounters, TileSlots, hiz_words, tile_record_words, tile_records,
    tile_state_words,
};
use staticscene::{
    Camera, DrawableSetupBatch, DrawableSetupInstance, HiZ, OcclusionPass, QueryOptions,
    QueryOutput, QueryParams, QueryStats, Scene, TileId, ViewDesc, canonical_batches,
};
use testkit::device::{Data, run_pass};

/// Every active tile's records in pooled buffers, in tile order (what the renderer's
/// pool does, without the allocator).
struct Pool {
    slots: BTreeMap<TileId, TileSlots>,
    instances: Vec<u32>,
    records: Vec<u32>,
    state: Vec<u32>,
}

impl Pool {
    fn new(scene: &Scene) -> Pool {
        let mut p = Pool {
            slots: BTreeMap::new(),
            instances: Vec::new(),
            records: Vec::new(),
            state: Vec::new(),
        };
        for t in scene.tiles() {
            let s = TileSlots {
                instance_base: (p.instances.len() / 4) as u32,
                records: p.records.len() as u32,
                state: p.state.len() as u32,
            };
            p.instances
                .extend_from_slice(bytemuck::cast_slice(t.instances()));
            let r = tile_records(t);
            assert_eq!(r.len(), tile_record_words(t));
            p.records.extend(r);
            p.state.extend(std::iter::repeat_n(0, tile_state_words(t)));
            p.slots.insert(t.id(), s);
        }
        p
    }

    /// The camera state byte of instance `i` of tile `id`.
    fn fade(&self, id: TileId, i: usize) -> u8 {
        let b = self.slots[&id].fade_base() as usize + i;
        (self.state[b / 4] >> ((b % 4) * 8)) as u8
    }
}

struct GpuOut {
    instances: Vec<DrawableSetupInstance>,
    batches: Vec<DrawableSetupBatch>,
    stats: QueryStats,
}

/// One run of the query pass over `pool` with `plan`; keeps the state buffer in `pool`.
fn run_query(pool: &mut Pool, plan: &GpuPlan, params: &QueryParams, hiz: Option<&HiZ>) -> GpuOut {
    run_variant(pool, plan, params, hiz, &[])
}

/// [`run_query`] with the pass composed with `features`.
fn run_variant(
    pool: &mut Pool,
    plan: &GpuPlan,
    params: &QueryParams,
    hiz: Option<&HiZ>,
    features: &[&str],
) -> GpuOut {
    run_with_table(pool, plan, &plan.wave_jobs(), params, hiz, features)
}

/// [`run_variant`] with the per-wave job table given.
fn run_with_table(
    pool: &mut Pool,
    plan: &GpuPlan,
    wave_jobs: &[u32],
    params: &QueryParams,
    hiz: Option<&HiZ>,
    features: &[&str],
) -> GpuOut {
    let cap = plan.instances() as usize + 1;
    let hiz = hiz_words(hiz).unwrap();
    let jobs = plan.job_list();
    let mut wave_jobs = wave_jobs.to_vec();
    wave_jobs.push(0); // never empty (a wave past the table is not run)
    let out = run_pass(
        &QUERY_PASS,
        features,
        &[],
        &plan.dispatch(),
        &[
            ("params", Data::Bytes(bytemuck::bytes_of(params))),
            ("job_list", Data::Words(&jobs)),
            ("wave_jobs", Data::Words(&wave_jobs)),
            ("instances", Data::Words(&pool.instances)),
            ("records", Data::Words(&pool.records)),
            ("hiz", Data::Words(&hiz)),
            ("state", Data::Words(&pool.state)),
            ("counters", Data::rows(&[QueryCounters::default()])),
            (
                "out_instances",
                Data::rows(&vec![DrawableSetupInstance::default(); cap]),
            ),
            (
                "out_batches",
                Data::rows(&vec![DrawableSetupBatch::default(); cap]),
            ),
        ],
    );
    pool.state = out.read("state", pool.state.len());
    let counters: QueryCounters = out.read::<QueryCounters>("counters", 1)[0];
    GpuOut {
        instances: out.read("out_instances", counters.instances as usize),
        batches: out.read("out_batches", counters.batches as usize),
        stats: counters.stats(&plan.stats),
    }
}

fn close(a: f32, b: f32) -> bool {
    (a - b).abs() <= 1e-4 * a.abs().max(b.abs()).max(1.0)
}

/// The GPU output of one frame against the CPU twin's.
fn assert_equal(frame: usize, gpu: &GpuOut, cpu: &QueryOutput<DrawableSetupInstance>) {
    let mut g = gpu.stats;
    let mut c = cpu.stats;
    // The pre-cull's counts (clusters skipped as not live are counted on the CPU only).
    for s in [&mut g, &mut c] {
        (s.tiles, s.tiles_culled, s.clusters, s.clusters_culled) = (0, 0, 0, 0);
    }
    assert_eq!(g, c, "frame {frame}: statistics");
    let gc = canonical_batches(&gpu.instances, &gpu.batches);
    let cc = canonical_batches(&cpu.instances, &cpu.batches);
    assert_eq!(gc.len(), cc.len(), "frame {frame}: batch count");
    assert_eq!(gc, cc, "frame {frame}: batches (setup, flags, instances)");
    // Per instance: fade, flags and the transform (f32 rounding of the product).
    let key = |d: &DrawableSetupInstance| (d.state.tile, d.state.instance);
    let cpu_by: BTreeMap<_, _> = cpu.instances.iter().map(|d| (key(d), d)).collect();
    for d in &gpu.instances {
        let c = cpu_by[&key(d)];
        assert_eq!(
            (d.state.fade, d.state.flags),
            (c.state.fade, c.state.flags),
            "frame {frame}: {:?}",
            key(d)
        );
        for (r, rc) in d
            .local_to_floating
            .rows
            .iter()
            .zip(&c.local_to_floating.rows)
        {
            for (x, y) in r.iter().zip(rc) {
                assert!(
                    close(*x, *y),
                    "frame {frame} {:?}: transform {r:?} vs {rc:?}",
                    key(d)
                );
            }
        }
    }
    // Batch spheres and sort depths, up to rounding (sqrt on the GPU is not exact).
    let by_first = |inst: &[DrawableSetupInstance], b: &DrawableSetupBatch| {
        key(&inst[b.first_instance as usize])
    };
    let cpu_b: BTreeMap<_, _> = cpu
        .batches
        .iter()
        .map(|b| (by_first(&cpu.instances, b), b))
        .collect();
    for b in &gpu.batches {
        let c = cpu_b[&by_first(&gpu.instances, b)];
        assert_eq!(b.sort_key >> 32, c.sort_key >> 32);
        assert!(close(
            f32::from_bits(b.sort_key as u32),
            f32::from_bits(c.sort_key as u32)
        ));
        for k in 0..4 {
            assert!(
                close(b.sphere[k], c.sphere[k]),
                "frame {frame}: sphere {:?} vs {:?}",
                b.sphere,
                c.sphere
            );
        }
        assert_eq!(b.stride, 64);
    }
}

/// A walk down the demo city's street: the camera moves and turns, LODs switch and fade,
/// last frame's depth (the buildings' boxes) occludes.
fn walk(frames: usize) -> Vec<(Camera, Camera)> {
    let cfg = CityConfig::with_instances(20_000);
    let start = street_camera(&cfg);
    (0..frames)
        .map(|f| {
            let at = |f: usize| {
                let mut c = start;
                c.position += DVec3::new(0.0, 0.0, -9.0 * f as f64);
                c.rotation *= glam::DQuat::from_rotation_y(0.25 * (f as f64 * 0.7).sin());
                c
            };
            (at(f), at(f.saturating_sub(1)))
        })
        .collect()
}

/// The GPU query equals `Scene::query` (the CPU twin) frame after frame on a demo city:
/// the statistics of every test, the batches (setup, flags and instances, after the
/// canonical sort), each instance's fade and transform, and the fade states left behind.
#[test]
fn gpu_query_equals_the_cpu_twin_over_frames() {
    twin_over_frames(false, &[]);
}

/// The subgroup batch output: batches per subgroup, equal to the twin with the subgroup's
/// width, over the same frames (single pass and two-pass).
#[test]
fn gpu_query_with_subgroups_equals_the_twin_at_the_subgroup_width() {
    let info = &testkit::device::ctx().info;
    assert!(
        testkit::device::has_subgroups(),
        "{} has no subgroups (lavapipe has them: see README)",
        info.name
    );
    assert_eq!(
        info.subgroup_min_size, info.subgroup_max_size,
        "a varying subgroup size has no fixed twin width"
    );
    twin_over_frames(false, &["subgroups"]);
    twin_over_frames(true, &["subgroups"]);
}

/// Two-pass occlusion on the GPU equals the twin frame after frame: the first pass (last
/// frame's visibility, no state written) and the second (this frame's HiZ, states and
/// visibility written, the first pass's instances left out), each compared as above.
#[test]
fn gpu_two_pass_occlusion_equals_the_cpu_twin_over_frames() {
    twin_over_frames(true, &[]);
}

/// The query over a walk, compared frame by frame with the twin; `features` compose the
/// pass (with `subgroups`, the twin runs at the device's subgroup width).
fn twin_over_frames(two_pass: bool, features: &[&str]) {
    let options = if features.contains(&"subgroups") {
        let lanes = testkit::device::ctx().info.subgroup_min_size;
        QueryOptions {
            wave_width: staticscene::WaveWidth::from_lanes(lanes)
                .expect("a subgroup size of 8 to 64"),
            ..QueryOptions::default()
        }
    } else {
        QueryOptions::default()
    };
    let cfg = CityConfig::with_instances(20_000);
    let c = city(&cfg);
    let mut cpu_scene = common::scene(&c.resources, &c.groups, staticscene::BuildConfig::default());
    let mut gpu_scene = cpu_scene.clone();
    let mut pool = Pool::new(&gpu_scene);
    let (w, h) = (320u32, 180u32);
    let mut cpu_out = QueryOutput::<DrawableSetupInstance>::new();
    let mut totals = QueryStats::default();
    for (frame, (cam, prev)) in walk(12).into_iter().enumerate() {
        let mut view = ViewDesc::camera(cam, [w, h]);
        view.fade_frames = 4;
        view.lod_scale = 0.35;
        // Single pass: last frame's depth through last frame's camera. Two-pass: this
        // frame's (the boxes stand in for what the first pass drew).
        let depth_camera = if two_pass { cam } else { prev };
        let hiz = (two_pass || frame > 0)
            .then(|| box_hiz(&c.building_boxes, &cam, &depth_camera, w, h, false).unwrap());
        if hiz.is_some() {
            view.occlusion_camera = Some(depth_camera);
        }
        let passes: &[OcclusionPass] = if two_pass {
            &[OcclusionPass::First, OcclusionPass::Second]
        } else {
            &[OcclusionPass::Single]
        };
        // The GPU plans once per frame; both passes take its jobs.
        let slots = pool.slots.clone();
        let plan = gpu_scene.plan_gpu(
            &QueryParams::new(&view).unwrap(),
            &QueryOptions::default(),
            |id| slots.get(&id).copied(),
        );
        assert!(plan.skipped_tiles.is_empty());
        for &pass in passes {
            view.occlusion_pass = pass;
            let params = QueryParams::new(&view).unwrap();
            cpu_scene
                .query(&params, hiz.as_ref(), &options, &mut cpu_out)
                .unwrap();
            let gpu = run_variant(&mut pool, &plan, &params, hiz.as_ref(), features);
            assert_equal(frame, &gpu, &cpu_out);
            for t in cpu_scene.tiles() {
                for i in 0..t.instances().len() {
                    assert_eq!(
                        pool.fade(t.id(), i),
                        cpu_scene.camera_state(t.id(), i).unwrap(),
                        "frame {frame} {pass:?}: camera state of tile {:?} instance {i}",
                        t.id()
                    );
                }
            }
            totals = totals.merge(&gpu.stats);
        }
    }
    // The walk exercises every test and the fade.
    eprintln!("{totals:?}");
    assert!(
        totals.rejected_lod > 0 && totals.rejected_frustum > 0 && totals.rejected_occlusion > 0
    );
    assert!(totals.visible > 1000 && totals.batches > 0);
    if two_pass {
        // Frame-to-frame coherence (the walk moves 9 m and turns each frame).
        assert!(totals.drawn_early > 500, "{totals:?}");
    }
}

/// A sun shadow view (orthographic, the sun-shadow filter, LODs from the player camera)
/// through the pass's shadow variant and through the general pass: both equal the CPU
/// twin, and neither touches the camera state.
#[test]
fn a_shadow_view_through_the_shadow_variant_equals_the_twin() {
    let cfg = CityConfig::with_instances(20_000);
    let c = city(&cfg);
    let mut cpu_scene = common::scene(&c.resources, &c.groups, staticscene::BuildConfig::default());
    let mut gpu_scene = cpu_scene.clone();
    let mut pool = Pool::new(&gpu_scene);
    let street = street_camera(&cfg);
    let ahead = street.rotation * DVec3::NEG_Z;
    let target = street.position + ahead * 60.0;
    let sun_dir = DVec3::new(0.4, -0.8, 0.3).normalize();
    let projection = glam::Mat4::orthographic_rh(-120.0, 120.0, -120.0, 120.0, 1.0, 1500.0);
    let sun = Camera::look_at(
        target - sun_dir * 700.0,
        target,
        DVec3::Y,
        projection,
        false,
    );
    let mut view = ViewDesc::shadow(
        sun,
        [1024, 1024],
        staticscene::FILTER_SUN_SHADOW,
        street.position,
    );
    view.lod_scale = 0.35;
    let params = QueryParams::new(&view).unwrap();
    assert_ne!(params.flags & staticscene::QUERY_FLAG_SHADOW, 0);
    let mut cpu_out = QueryOutput::<DrawableSetupInstance>::new();
    cpu_scene
        .query(&params, None, &QueryOptions::default(), &mut cpu_out)
        .unwrap();
    let slots = pool.slots.clone();
    let plan = gpu_scene.plan_gpu(&params, &QueryOptions::default(), |id| {
        slots.get(&id).copied()
    });
    let state = pool.state.clone();
    for features in [&["shadow_view"][..], &[]] {
        let gpu = run_variant(&mut pool, &plan, &params, None, features);
        assert_equal(0, &gpu, &cpu_out);
        assert!(
            pool.state == state,
            "{features:?}: a shadow view wrote camera state"
        );
    }
    eprintln!("sun view: {:?}", cpu_out.stats);
    assert!(cpu_out.stats.visible > 1000 && cpu_out.stats.rejected_frustum > 0);
}

/// Corrupt records never read outside their tile: instances whose object, LOD bounds,
/// matrix or setup index points past the tile's records are dropped and counted as
/// invalid, exactly as the CPU twin does on the same hand-made buffers, and a job whose
/// record block lies outside the records buffer drops every instance that passes the
/// filter; every other instance is output as before.
/// The street camera at 320x180, no fade, every cluster dispatched (the CPU twin is run
/// cluster by cluster or wave by wave against it).
fn street_without_fade_or_precull(cfg: &CityConfig) -> (QueryParams, QueryOptions) {
    let mut view = ViewDesc::camera(street_camera(cfg), [320, 180]);
    view.fade_frames = 0;
    let options = QueryOptions {
        precull: false,
        ..QueryOptions::default()
    };
    (QueryParams::new(&view).unwrap(), options)
}

/// The CPU twin run job by job on given buffers (no fade, no HiZ, W64 batches), its
/// output gathered as a [`QueryOutput`].
struct TwinJobs {
    counter: std::cell::Cell<u32>,
    batch_counter: std::cell::Cell<u32>,
    out: Vec<DrawableSetupInstance>,
    batches: Vec<DrawableSetupBatch>,
    stats: QueryStats,
}

impl TwinJobs {
    fn new(cap: usize) -> TwinJobs {
        TwinJobs {
            counter: std::cell::Cell::new(0),
            batch_counter: std::cell::Cell::new(0),
            out: vec![DrawableSetupInstance::default(); cap],
            batches: vec![DrawableSetupBatch::default(); cap],
            stats: QueryStats::default(),
        }
    }

    fn run(
        &mut self,
        params: &QueryParams,
        buffers: &staticscene::TileBuffers,
        first: u32,
        count: u32,
    ) {
        let job = staticscene::ClusterJob {
            first,
            count,
            snap_fade: false,
        };
        staticscene::query_cluster(
            params,
            buffers,
            None,
            &mut [],
            job,
            wave::WaveWidth::W64,
            &self.counter,
            &mut self.out,
            &self.batch_counter,
            &mut self.batches,
            &mut self.stats,
        )
        .unwrap();
    }

    fn output(self) -> QueryOutput<DrawableSetupInstance> {
        let mut cpu = QueryOutput::new();
        cpu.instances = self.out[..self.counter.get() as usize].to_vec();
        cpu.batches = self.batches[..self.batch_counter.get() as usize].to_vec();
        cpu.stats = self.stats;
        cpu
    }
}

#[test]
fn corrupt_records_are_dropped_as_the_twin_drops_them() {
    use staticscene::{InstanceFields, QueryInstance, TileBuffers};
    let cfg = CityConfig::with_instances(20_000);
    let c = city(&cfg);
    let mut scene = common::scene(&c.resources, &c.groups, staticscene::BuildConfig::default());
    assert!(scene.tiles().len() > 2);
    let mut pool = Pool::new(&scene);
    let mut rng = testkit::Rng::new(9);
    // Corrupt one instance in seven, each in one of four fields.
    let mut corrupted: BTreeMap<TileId, Vec<QueryInstance>> = BTreeMap::new();
    for t in scene.tiles() {
        let mut inst = t.instances().to_vec();
        for (i, q) in inst.iter_mut().enumerate() {
            if i % 7 != 3 {
                continue;
            }
            let mut f: InstanceFields = q.try_unpack().unwrap();
            match rng.below(4) {
                0 => f.object = t.objects().len() as u32 + rng.below(100) as u32,
                1 => f.parent_bounds = t.bounds().len() as u16,
                2 => f.matrix = t.transforms().len() as u16 + 3,
                _ => f.setup = t.setups().len() as u16,
            }
            *q = QueryInstance::pack(&f).unwrap();
        }
        let base = pool.slots[&t.id()].instance_base as usize * 4;
        pool.instances[base..base + inst.len() * 4].copy_from_slice(bytemuck::cast_slice(&inst));
        corrupted.insert(t.id(), inst);
    }
    // One tile's record block is moved past the end of the records buffer.
    let moved = scene.tiles()[1].id();
    pool.slots.get_mut(&moved).unwrap().records = pool.records.len() as u32 + 16;

    let (params, options) = street_without_fade_or_precull(&cfg);
    // The CPU twin on the same buffers, cluster by cluster.
    let mut twin = TwinJobs::new(40_000);
    for t in scene.tiles() {
        let inst = &corrupted[&t.id()];
        let buffers = if t.id() == moved {
            TileBuffers {
                tile: t.id().0,
                instances: inst,
                objects: &[],
                setups: &[],
                transforms: &[],
                bounds: &[],
            }
        } else {
            TileBuffers {
                instances: inst,
                ..t.buffers()
            }
        };
        for cl in t.clusters() {
            twin.run(&params, &buffers, cl.first, cl.count);
        }
    }
    let cpu = twin.output();
    let slots = pool.slots.clone();
    let plan = scene.plan_gpu(&params, &options, |id| slots.get(&id).copied());
    let gpu = run_query(&mut pool, &plan, &params, None);
    assert!(cpu.stats.invalid > 500, "{:?}", cpu.stats);
    assert!(cpu.stats.visible > 100, "{:?}", cpu.stats);
    // Only the per-thread statistics compare (the twin ran without the pre-cull's).
    assert_equal(0, &gpu, &cpu);
}

/// A corrupt per-wave job table never runs a wave against another job's records: waves
/// whose entry names another job (or one past the list, clamped to the last) are dropped,
/// the others run as the twin does, wave by wave.
#[test]
fn waves_with_a_corrupt_job_table_entry_are_dropped() {
    use staticscene::pass::QUERY_WORKGROUP;
    let cfg = CityConfig::with_instances(20_000);
    let c = city(&cfg);
    let mut scene = common::scene(&c.resources, &c.groups, staticscene::BuildConfig::default());
    let mut pool = Pool::new(&scene);
    let (params, options) = street_without_fade_or_precull(&cfg);
    let slots = pool.slots.clone();
    let plan = scene.plan_gpu(&params, &options, |id| slots.get(&id).copied());
    let truth = plan.wave_jobs();
    assert_eq!(truth.len(), plan.waves as usize);
    let last = plan.jobs.len() as u32 - 1;
    let mut table = truth.clone();
    for (w, entry) in table.iter_mut().enumerate() {
        match w % 3 {
            0 => *entry = (*entry + 1) % plan.jobs.len() as u32,
            1 => *entry = u32::MAX - w as u32,
            _ => {}
        }
    }
    let gpu = run_with_table(&mut pool, &plan, &table, &params, None, &[]);
    // The twin over the waves whose entry (clamped as the pass clamps it) is their job's.
    let mut twin = TwinJobs::new(40_000);
    let mut ran = 0;
    for (w, (&entry, &job_index)) in table.iter().zip(&truth).enumerate() {
        if entry.min(last) != job_index {
            continue;
        }
        ran += 1;
        let job = &plan.jobs[job_index as usize];
        let tile = scene.tiles().iter().find(|t| t.id().0 == job.tile).unwrap();
        let first = (w as u32 - job.first_wave) * QUERY_WORKGROUP;
        let count = (job.count - first).min(QUERY_WORKGROUP);
        twin.run(&params, &tile.buffers(), job.first + first, count);
    }
    assert!(
        ran > table.len() / 4 && ran < table.len(),
        "{ran} of {}",
        table.len()
    );
    let cpu = twin.output();
    assert!(cpu.stats.visible > 100, "{:?}", cpu.stats);
    assert_equal(0, &gpu, &cpu);
}

/// The HiZ reduction on the GPU equals `HiZ::build` texel for texel, level by level, on
/// non-power-of-two sizes, for standard and reversed depth (level 0 uploaded with NaN
/// already mapped to the far side, as the renderer's level-0 copy does).
#[test]
fn gpu_hiz_pyramid_equals_the_cpu_one() {
    use staticscene::pass::{HIZ_PASS, HizGrid, HizStep, hiz_header};
    let mut rng = testkit::Rng::new(3);
    for (w, h) in [
        (1u32, 1u32),
        (37, 23),
        (64, 64),
        (65, 17),
        (100, 1),
        (320, 181),
    ] {
        for reversed in [false, true] {
            let depth: Vec<f32> = (0..w * h)
                .map(|i| if i % 97 == 5 { f32::NAN } else { rng.f32() })
                .collect();
            let want = HiZ::build(&depth, w, h, reversed).unwrap();
            let (header, len) = hiz_header(w, h).unwrap();
            // The CPU pyramid's texels fill the header's layout exactly.
            let full = hiz_words(Some(&want)).unwrap();
            assert_eq!(full.len(), len, "{w}x{h}");
            // Level 0 as the CPU maps it, the rest zero.
            let mut buf = header.clone();
            buf.resize(len, 0);
            let l0 = want.levels()[0].offset + header.len();
            let far = if reversed {
                f32::NEG_INFINITY
            } else {
                f32::INFINITY
            };
            for (i, d) in depth.iter().enumerate() {
                buf[l0 + i] = if d.is_nan() { far } else { *d }.to_bits();
            }
            for (l, next) in want.levels().iter().enumerate().skip(1) {
                let step = HizStep {
                    level: l as u32 - 1,
                    reversed: u32::from(reversed),
                    pad: [0; 2],
                };
                let grid = HizGrid {
                    width: next.width,
                    height: next.height,
                };
                let out = run_pass(
                    &HIZ_PASS,
                    &[],
                    &[],
                    &grid,
                    &[
                        ("step", Data::Bytes(bytemuck::bytes_of(&step))),
                        ("hiz", Data::Words(&buf)),
                    ],
                );
                buf = out.read("hiz", len);
            }
            assert_eq!(buf, full, "{w}x{h} reversed {reversed}");
        }
    }
}
