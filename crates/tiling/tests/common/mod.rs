//! Shared by the integration tests: random scenes and vis buffers, and the naive reference
//! classification (written from the rules in the crate docs with maps and plain
//! arithmetic, sharing no code with the crate).

#![allow(dead_code)]

use std::collections::{BTreeMap, BTreeSet};

use tiling::{
    Batch, Classification, ClassifyOutput, Geometry, MicroBatchInfo, MidClassify, PassDispatch,
    PixelStats, Plan, PlanConfig, VertexWaves, WaveCommand, build_plan, vertex_wave_commands,
};
use visbuf::{ShadingRate, VIS_NONE, VisFields, VisId, VisLayout};

pub use testkit::Rng;

/// A random scene: batches, their geometry in one index buffer, and the plan.
pub struct Scene {
    pub positions: Vec<Vec<[f32; 3]>>,
    pub geometry: Vec<Geometry>,
    pub shaders: Vec<u32>,
    pub data: Vec<u64>,
    pub indices: Vec<u32>,
    pub plan: Plan,
}

/// `batches` random batches (a few shaders and batch-data keys, small geometries, up to a
/// few hundred instances) planned with `config`.
pub fn random_scene(rng: &mut Rng, batches: usize, config: &PlanConfig) -> Scene {
    let mut geometry = Vec::new();
    let mut indices = Vec::new();
    let mut positions = Vec::new();
    let mut shaders = Vec::new();
    let mut data = Vec::new();
    for _ in 0..batches {
        let big = rng.chance(20);
        let vertex_limit = config.micro_batch_vertex_limit();
        let small = vertex_limit < 10_000;
        let prims = 1 + rng.below(if big && !small { 3000 } else { 40 }) as u32;
        let verts = (3 + rng.below(u64::from(prims) * 2) as u32).min(vertex_limit);
        let first_index = indices.len() as u32;
        for _ in 0..prims * 3 {
            indices.push(rng.below(u64::from(verts)) as u32);
        }
        geometry.push(Geometry {
            vertex_count: verts,
            primitive_count: prims,
            first_index,
            base_vertex: 0,
        });
        let n = rng.below(if small { 40 } else { 300 }) as usize;
        positions.push(
            (0..n)
                .map(|_| {
                    [
                        rng.below(1000) as f32,
                        rng.below(50) as f32,
                        rng.below(1000) as f32,
                    ]
                })
                .collect::<Vec<[f32; 3]>>(),
        );
        shaders.push(rng.below(3) as u32);
        data.push(rng.below(6));
    }
    let bs: Vec<Batch<'_>> = (0..batches)
        .map(|i| Batch {
            shader: shaders[i],
            batch_data: data[i],
            geometry: geometry[i],
            instances: &positions[i],
        })
        .collect();
    let plan = build_plan(&bs, config).expect("random scene plans");
    Scene {
        positions,
        geometry,
        shaders,
        data,
        indices,
        plan,
    }
}

/// The vis word of primitive `primitive` of instance `instance` (within the micro batch)
/// of `mb`, shaded at `rate`, through visbuf's packing and the micro batch's instance
/// mapping. Panics when the fields do not fit (a test's own mistake).
pub fn word(
    layout: VisLayout,
    mb: &MicroBatchInfo,
    instance: u32,
    primitive: u32,
    rate: ShadingRate,
) -> u32 {
    let (id, field) = mb.instance_id(instance);
    VisId::pack(
        layout,
        mb.bits(),
        VisFields {
            micro_batch: id,
            instance: field,
            primitive,
            rate,
        },
    )
    .expect("fields fit")
    .0
}

/// A valid word for a random instance and primitive of a random micro batch.
pub fn random_valid_word(rng: &mut Rng, plan: &Plan, layout: VisLayout) -> u32 {
    let mb = &plan.micro_batches[rng.below(plan.micro_batches.len() as u64) as usize];
    let i = rng.below(u64::from(mb.instance_count)) as u32;
    let prim = rng.below(u64::from(mb.primitive_count)) as u32;
    let rate = ShadingRate::from_bits(rng.below(4) as u32);
    word(layout, mb, i, prim, rate)
}

/// The vertex wave commands of `plan` over the cull buffer `cull` (its table, order
/// buffer and passes); panics on the errors the plan's own buffers never cause.
pub fn plan_vertex_waves(plan: &Plan, cull: &[u8]) -> VertexWaves {
    vertex_wave_commands(
        cull,
        plan.chunk_count,
        &plan.table,
        &plan.order,
        &plan.passes,
    )
    .expect("the plan's buffers agree")
}

/// A word of a real micro batch whose primitive (or instance) lies past its counts, or a
/// valid word when the counts fill the fields.
pub fn out_of_range_word(rng: &mut Rng, plan: &Plan, layout: VisLayout) -> u32 {
    let mb = &plan.micro_batches[rng.below(plan.micro_batches.len() as u64) as usize];
    let bits = mb.bits();
    let last = mb.first_id + mb.id_count - 1;
    let used_in_last = mb.instance_count - ((mb.id_count - 1) << bits.instance_bits());
    let (id, field, prim) = if mb.primitive_count <= bits.primitive_mask() {
        (mb.first_id, 0, mb.primitive_count)
    } else if used_in_last < bits.instances_per_id() {
        (last, used_in_last, 0)
    } else {
        (mb.first_id, 0, 0)
    };
    VisId::pack(
        layout,
        bits,
        VisFields {
            micro_batch: id,
            instance: field,
            primitive: prim,
            rate: ShadingRate::Rate1x1,
        },
    )
    .expect("fields fit")
    .0
}

/// A `w x h` vis buffer with spatial coherence (pixels often repeat a neighbour's word),
/// some empty pixels and `garbage` percent of random words.
pub fn random_vis(
    rng: &mut Rng,
    plan: &Plan,
    w: u32,
    h: u32,
    layout: VisLayout,
    garbage: u64,
) -> Vec<u32> {
    let mut words = vec![VIS_NONE; (w * h) as usize];
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            let r = rng.below(100);
            words[i] = if r < 35 && x > 0 {
                words[i - 1]
            } else if r < 60 && y > 0 {
                words[i - w as usize]
            } else if r < 70 || plan.micro_batches.is_empty() {
                VIS_NONE
            } else if rng.below(100) < garbage {
                if rng.chance(50) {
                    rng.next_u64() as u32
                } else {
                    out_of_range_word(rng, plan, layout)
                }
            } else {
                random_valid_word(rng, plan, layout)
            };
        }
    }
    words
}

/// A random validity bitmask with about `percent` of the bits set.
pub fn random_mask(rng: &mut Rng, w: u32, h: u32, percent: u64) -> Vec<u32> {
    let n = (w * h) as usize;
    let mut m = vec![0u32; n.div_ceil(32)];
    for i in 0..n {
        if rng.chance(percent) {
            m[i / 32] |= 1 << (i % 32);
        }
    }
    m
}

/// A decoded valid pixel, by arithmetic.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    pub id: u32,
    pub pass: u32,
    pub group: u32,
    pub instance: u32,
    pub prim: u32,
}

/// 0 empty, 1 unknown, 2 out of range, 3 valid.
pub fn naive_decode(
    word: u32,
    valid: bool,
    layout: VisLayout,
    table: &[MicroBatchInfo],
    passes: u32,
) -> (u8, Option<Hit>) {
    if word == 0xffff_ffff || !valid {
        return (0, None);
    }
    let ids: u32 = if layout == VisLayout::Vrs {
        16384
    } else {
        65536
    };
    let id = (word / 65536) % ids;
    if id == ids - 1 || id as usize >= table.len() {
        return (1, None);
    }
    let r = table[id as usize];
    let in_range = id >= r.first_id && (id as u64) < r.first_id as u64 + r.id_count as u64;
    if !in_range || r.pass >= passes || r.batch_group >= 32 || r.primitive_bits > 16 {
        return (1, None);
    }
    let low = word % 65536;
    let field = low / (1 << r.primitive_bits);
    let prim = low % (1 << r.primitive_bits);
    let instance = (id - r.first_id) as u64 * (1u64 << (16 - r.primitive_bits)) + field as u64;
    if instance >= r.instance_count as u64 || prim >= r.primitive_count {
        return (2, None);
    }
    (
        3,
        Some(Hit {
            id,
            pass: r.pass,
            group: r.batch_group,
            instance: instance as u32,
            prim,
        }),
    )
}

/// The naive classification of a frame: maps keyed by (tile, pass, group).
pub struct NaiveInput<'a> {
    pub words: &'a [u32],
    pub valid: Option<&'a [u32]>,
    pub w: u32,
    pub h: u32,
    pub layout: VisLayout,
    pub table: &'a [MicroBatchInfo],
    pub indices: &'a [u32],
    pub passes: u32,
    pub wave: u32,
    pub chunk_count: u32,
}

fn bit(mask: Option<&[u32]>, i: usize) -> bool {
    mask.is_none_or(|m| (m[i / 32] >> (i % 32)) & 1 == 1)
}

pub fn naive_classify(n: &NaiveInput<'_>) -> Classification {
    let tiles_x = n.w.div_ceil(128);
    let tiles = (tiles_x * n.h.div_ceil(128)) as usize;
    let p_count = n.passes as usize;
    // (tile, pass, group) -> commands (sort key, command).
    let mut lists: BTreeMap<(usize, u32, u32), Vec<(u32, u16)>> = BTreeMap::new();
    let mut stats = PixelStats::default();
    let mut cull = vec![0u8; (n.chunk_count as usize).next_multiple_of(4)];
    let mut bad = 0u32;
    let decode = |i: usize| naive_decode(n.words[i], bit(n.valid, i), n.layout, n.table, n.passes);
    // VRS blocks already emitted: (word, block x, block y).
    let mut blocks: BTreeSet<(u32, u32, u32)> = BTreeSet::new();
    for y in 0..n.h {
        for x in 0..n.w {
            let i = (y * n.w + x) as usize;
            let (kind, hit) = decode(i);
            match kind {
                0 => stats.empty += 1,
                1 => stats.unknown += 1,
                2 => stats.out_of_range += 1,
                _ => stats.valid += 1,
            }
            let Some(hit) = hit else { continue };
            // Bad indices count run starts: no valid left or upper neighbour with this word.
            let same = |j: usize| n.words[j] == n.words[i] && bit(n.valid, j);
            let run_start = !((x > 0 && same(i - 1)) || (y > 0 && same(i - n.w as usize)));
            // Vertex cull.
            let r = n.table[hit.id as usize];
            let first = r.first_index as u64 + 3 * hit.prim as u64;
            if first + 3 > n.indices.len() as u64 {
                bad += u32::from(run_start);
            } else {
                let mut ok = true;
                for k in 0..3 {
                    let v = n.indices[(first + k) as usize];
                    let chunk = if v < r.vertex_count {
                        r.first_chunk as u64
                            + (hit.instance as u64 * r.vertex_count as u64 + v as u64) / 64
                    } else {
                        u64::MAX
                    };
                    if chunk < n.chunk_count as u64 {
                        cull[chunk as usize] = 1;
                    } else {
                        ok = false;
                    }
                }
                bad += u32::from(!ok && run_start);
            }
            let t = ((y / 128) * tiles_x + x / 128) as usize;
            let (tx, ty) = (x % 128, y % 128);
            let cmd = if n.layout == VisLayout::Standard {
                (tx + 128 * ty, (tx + 128 * ty) as u16)
            } else {
                let rate = n.words[i] >> 30;
                let (rw, rh) = (1 + (rate >> 1), 1 + (rate & 1));
                let (bx, by) = (x / rw, y / rh);
                if !blocks.insert((n.words[i], bx, by)) {
                    continue;
                }
                // Members: same word, valid, in the block.
                let mut mask = 0u32;
                for py in by * rh..(by * rh + rh).min(n.h) {
                    for px in bx * rw..(bx * rw + rw).min(n.w) {
                        let j = (py * n.w + px) as usize;
                        if n.words[j] == n.words[i] && bit(n.valid, j) {
                            mask |= 1 << ((py % 2) * 2 + px % 2);
                        }
                    }
                }
                let (qx, qy) = (tx / 2, ty / 2);
                (tx + 128 * ty, (qx + 64 * qy + 4096 * mask) as u16)
            };
            lists.entry((t, hit.pass, hit.group)).or_default().push(cmd);
        }
    }
    // Phase 1.
    let mut masks = vec![0u32; tiles * p_count];
    for &(t, p, g) in lists.keys() {
        masks[t * p_count + p as usize] |= 1 << g;
    }
    // Phase 2: counters in (tile, pass, group) order = the map's order.
    let mut mid = MidClassify::default();
    let mut running = 0u32;
    for (e, m) in masks.iter().enumerate() {
        let _ = e;
        mid.counter_offsets.push(running);
        running += m.count_ones();
    }
    mid.counter_count = running;
    let mut at = 0u32;
    for v in lists.values() {
        mid.counts.push(v.len() as u32);
        mid.pixel_offsets.push(at);
        at += v.len() as u32;
    }
    mid.command_count = at;
    mid.vertex_cull = cull;
    let commands_total: u32 = at;
    mid.stats = PixelStats {
        commands: commands_total,
        bad_indices: bad,
        ..stats
    };
    // Phase 3.
    let mut out = ClassifyOutput::default();
    for v in lists.values() {
        let mut v = v.clone();
        v.sort();
        out.commands.extend(v.iter().map(|&(_, c)| c));
        out.final_counts.push(v.len() as u32);
    }
    out.wave_offsets = vec![0; lists.len()];
    let keys: Vec<(usize, u32, u32)> = lists.keys().copied().collect();
    let mut pass_major: Vec<(u32, usize, u32, usize)> = keys
        .iter()
        .enumerate()
        .map(|(c, &(t, p, g))| (p, t, g, c))
        .collect();
    pass_major.sort();
    for p in 0..n.passes {
        let first = out.waves.len() as u32;
        let mut items = 0;
        for &(pp, t, g, c) in &pass_major {
            if pp != p {
                continue;
            }
            let cnt = mid.counts[c];
            out.wave_offsets[c] = out.waves.len() as u32;
            let mut k = 0;
            while k < cnt {
                out.waves.push(WaveCommand {
                    tile: (t as u32 % tiles_x) | ((t as u32 / tiles_x) << 16),
                    pass_group: p | (g << 8),
                    first_command: mid.pixel_offsets[c] + k,
                    command_count: (cnt - k).min(n.wave),
                });
                k += n.wave;
            }
            items += cnt;
        }
        let count = out.waves.len() as u32 - first;
        out.passes.push(PassDispatch {
            x: count.min(65535),
            y: count.div_ceil(65535),
            z: u32::from(count > 0),
            first,
            count,
            items,
        });
    }
    out.stats = PixelStats {
        commands: commands_total,
        ..stats
    };
    Classification {
        masks,
        mid,
        output: out,
    }
}
