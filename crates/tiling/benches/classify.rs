//! Classification of a 3840x2160 foliage-like vis buffer: all three phases plus command
//! output, sequential and parallel, against the naive "lists of pixels per material"
//! approach the talk compares against (one global sort of the valid pixels by material).
//! Also the vertex wave commands from the resulting cull buffer.
//!
//! The frame: 480 batches of grass cards, fern and bush geometries (60 to 2000 triangles,
//! 4 shaders, 96 batch-data keys) planned into passes; plants splatted back to front, each
//! a clump of blades of 16 consecutive 1-30 pixel triangles of one instance, the plants of a batch within about
//! 250 pixels of the batch's patch centre, so tiles hold tens of passes and (pass, group)
//! counters and primitives are a few pixels each. 10% of the pixels have no vis-buffer
//! geometry.
//!
//! `cargo bench -p tiling --bench classify --features parallel`

#[path = "../tests/common/mod.rs"]
mod common;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;
use tiling::{
    Batch, ClassifyConfig, Geometry, Plan, PlanConfig, VisBuffer, build_plan, classify,
    vertex_wave_commands,
};
use visbuf::{ShadingRate, VIS_NONE, VisId, VisLayout};
use wave::WaveWidth;

const W: u32 = 3840;
const H: u32 = 2160;

use testkit::Rng;

struct Frame {
    plan: Plan,
    indices: Vec<u32>,
    words: Vec<u32>,
}

/// Fills a triangle (pixel centres inside, either winding) with `word`; returns the pixels
/// that had no geometry before.
fn fill(words: &mut [u32], p: [(f32, f32); 3], word: u32) -> u64 {
    let (minx, maxx) = (
        p.iter().map(|v| v.0).fold(f32::MAX, f32::min),
        p.iter().map(|v| v.0).fold(f32::MIN, f32::max),
    );
    let (miny, maxy) = (
        p.iter().map(|v| v.1).fold(f32::MAX, f32::min),
        p.iter().map(|v| v.1).fold(f32::MIN, f32::max),
    );
    let x0 = minx.floor().max(0.0) as u32;
    let x1 = (maxx.ceil() as i64).clamp(0, W as i64) as u32;
    let y0 = miny.floor().max(0.0) as u32;
    let y1 = (maxy.ceil() as i64).clamp(0, H as i64) as u32;
    let edge = |a: (f32, f32), b: (f32, f32), x: f32, y: f32| {
        (b.0 - a.0) * (y - a.1) - (b.1 - a.1) * (x - a.0)
    };
    let area = edge(p[0], p[1], p[2].0, p[2].1);
    let mut fresh = 0;
    if area == 0.0 {
        return 0;
    }
    for y in y0..y1 {
        for x in x0..x1 {
            let (cx, cy) = (x as f32 + 0.5, y as f32 + 0.5);
            let e0 = edge(p[1], p[2], cx, cy) * area.signum();
            let e1 = edge(p[2], p[0], cx, cy) * area.signum();
            let e2 = edge(p[0], p[1], cx, cy) * area.signum();
            if e0 >= 0.0 && e1 >= 0.0 && e2 >= 0.0 {
                let w = &mut words[(y * W + x) as usize];
                fresh += u64::from(*w == VIS_NONE);
                *w = word;
            }
        }
    }
    fresh
}

fn foliage_frame(layout: VisLayout) -> Frame {
    let mut rng = Rng::new(0x5eed);
    // Geometries: grass cards, ferns, bushes.
    let mut geoms = Vec::new();
    let mut indices = Vec::new();
    for g in 0..24 {
        let prims = [60u32, 250, 800, 2000][g % 4];
        let verts = prims + 2;
        let first_index = indices.len() as u32;
        for t in 0..prims {
            // A strip: triangle t uses vertices t, t+1, t+2.
            indices.extend([t, t + 1, t + 2]);
        }
        geoms.push(Geometry {
            vertex_count: verts,
            primitive_count: prims,
            first_index,
            base_vertex: 0,
        });
    }
    let mut positions = Vec::new();
    let mut meta = Vec::new();
    for b in 0..480u64 {
        let n = 20 + rng.below(400) as usize;
        positions.push(
            (0..n)
                .map(|_| [rng.f32() * 200.0, 0.0, rng.f32() * 200.0])
                .collect::<Vec<[f32; 3]>>(),
        );
        meta.push((b % 4, rng.below(96), geoms[rng.below(24) as usize]));
    }
    let batches: Vec<Batch<'_>> = positions
        .iter()
        .zip(&meta)
        .map(|(p, &(s, d, g))| Batch {
            shader: s as u32,
            batch_data: d,
            geometry: g,
            instances: p,
        })
        .collect();
    let plan = build_plan(
        &batches,
        &PlanConfig {
            layout,
            ..PlanConfig::default()
        },
    )
    .expect("bench plan");

    let centers: Vec<(f32, f32)> = (0..batches.len())
        .map(|_| (rng.f32() * W as f32, rng.f32() * H as f32))
        .collect();
    let mut words = vec![VIS_NONE; (W * H) as usize];
    // Plants back to front: clumps of small triangles of one instance.
    let mut covered = 0u64;
    while covered < 9 * u64::from(W * H) / 10 {
        let mb = &plan.micro_batches[rng.below(plan.micro_batches.len() as u64) as usize];
        let inst = rng.below(u64::from(mb.instance_count)) as u32;
        let rate = ShadingRate::from_bits(rng.below(4) as u32);
        // Plants of a batch grow in one patch of the screen (a placement cell).
        let (bx, by) = centers[mb.batch as usize];
        let spread = 250.0;
        let cx = (bx + (rng.f32() + rng.f32() - 1.0) * spread).rem_euclid(W as f32);
        let cy = (by + (rng.f32() + rng.f32() - 1.0) * spread).rem_euclid(H as f32);
        let size = 12.0 + rng.f32() * 70.0;
        let tris = (size * size / 12.0) as u32;
        // Blades of 16 consecutive triangles walking across the clump.
        let start = rng.below(u64::from(mb.primitive_count)) as u32;
        let (mut tx, mut ty, mut dx, mut dy) = (cx, cy, 0.0f32, 0.0f32);
        for k in 0..tris {
            let prim = (start + k) % mb.primitive_count;
            if k % 16 == 0 {
                tx = cx + (rng.f32() - 0.5) * size;
                ty = cy + (rng.f32() - 0.5) * size;
                dx = rng.f32() - 0.5;
                dy = -1.0;
            } else {
                tx += dx + (rng.f32() - 0.5);
                ty += dy + (rng.f32() - 0.5);
            }
            let word = common::word(layout, mb, inst, prim, rate);
            let r = 1.0 + rng.f32() * 3.0;
            let p = [
                (
                    tx + (rng.f32() - 0.5) * 2.0 * r,
                    ty + (rng.f32() - 0.5) * 2.0 * r,
                ),
                (
                    tx + (rng.f32() - 0.5) * 2.0 * r,
                    ty + (rng.f32() - 0.5) * 2.0 * r,
                ),
                (
                    tx + (rng.f32() - 0.5) * 2.0 * r,
                    ty + (rng.f32() - 0.5) * 2.0 * r,
                ),
            ];
            covered += fill(&mut words, p, word);
        }
    }
    Frame {
        plan,
        indices,
        words,
    }
}

/// The baseline: lists of pixels per material by one global sort (key: pass and group of
/// the pixel's micro batch, then the pixel index), after the same decode.
fn naive_sort(frame: &Frame, layout: VisLayout) -> Vec<u64> {
    let table = &frame.plan.table;
    let mut keys: Vec<u64> = Vec::with_capacity(frame.words.len());
    for (i, &w) in frame.words.iter().enumerate() {
        if w == VIS_NONE {
            continue;
        }
        let id = VisId(w);
        let Some(row) = table.get(id.micro_batch(layout) as usize) else {
            continue;
        };
        let bits = row.bits();
        if id.primitive(bits) >= row.primitive_count {
            continue;
        }
        let material = (row.pass << 5) | row.batch_group;
        keys.push((u64::from(material) << 32) | i as u64);
    }
    keys.sort_unstable();
    keys
}

fn bench(c: &mut Criterion) {
    for layout in [VisLayout::Standard, VisLayout::Vrs] {
        let frame = foliage_frame(layout);
        let vis = VisBuffer::new(&frame.words, W, H, layout).unwrap();
        let config = ClassifyConfig::for_plan(&frame.plan, WaveWidth::W32);
        let table = &frame.plan.table;
        let result = classify(&vis, table, &frame.indices, &config).unwrap();
        let v = common::plan_vertex_waves(&frame.plan, &result.mid.vertex_cull);
        let m = tiling::measure(&vis, table, &config, &result, &v).unwrap();
        let pixels = u64::from(W * H);
        let tiles = vis.tile_count() as f64;
        let groups_per_tile = result.mid.counter_count as f64 / tiles;
        let passes_per_tile = result.masks.iter().filter(|&&m| m != 0).count() as f64 / tiles;
        eprintln!(
            "{layout:?} frame: {} passes, {} micro batches, {:.1} passes and {:.1} (pass, group) counters per tile, \
             valid pixels {:.1}%, command buffers {} bytes = {:.3} bytes per pixel ({:.3} per valid pixel); \
             waves deferred {} vs depth-equal {} ({:.1}%), unfilled lanes {:.1}%, samples/pixels {:.3}, \
             vertices {} -> {} after chunk culling ({:.1}%)",
            frame.plan.passes.len(),
            frame.plan.micro_batches.len(),
            passes_per_tile,
            groups_per_tile,
            100.0 * f64::from(result.output.stats.valid) / pixels as f64,
            result.command_bytes(),
            result.command_bytes() as f64 / pixels as f64,
            result.command_bytes() as f64 / f64::from(result.output.stats.valid),
            m.deferred_waves,
            m.depth_equal_waves,
            100.0 * m.pixel_wave_ratio(),
            100.0 * m.unfilled_lane_fraction(),
            m.sample_ratio(),
            m.scene_vertices,
            m.visible_vertices,
            100.0 * m.vertex_ratio(),
        );

        let mut g = c.benchmark_group(format!("classify_4k_{layout:?}").to_lowercase());
        g.sample_size(10);
        g.throughput(Throughput::Elements(pixels));
        #[cfg(feature = "parallel")]
        g.bench_function(BenchmarkId::new("parallel", "fused"), |b| {
            b.iter(|| {
                black_box(tiling::parallel::classify(&vis, table, &frame.indices, &config).unwrap())
            })
        });
        #[cfg(feature = "parallel")]
        g.bench_function(BenchmarkId::new("parallel", "phases"), |b| {
            b.iter(|| {
                black_box(
                    tiling::parallel::classify_phases(&vis, table, &frame.indices, &config)
                        .unwrap(),
                )
            })
        });
        g.bench_function(BenchmarkId::new("sequential", "fused"), |b| {
            b.iter(|| black_box(classify(&vis, table, &frame.indices, &config).unwrap()))
        });
        g.bench_function(BenchmarkId::new("sequential", "phases"), |b| {
            b.iter(|| {
                black_box(tiling::classify_phases(&vis, table, &frame.indices, &config).unwrap())
            })
        });
        if layout == VisLayout::Standard {
            g.bench_function(BenchmarkId::new("naive_global_sort", "by material"), |b| {
                b.iter(|| black_box(naive_sort(&frame, layout)))
            });
        }
        g.finish();
        if layout == VisLayout::Standard {
            let mut g = c.benchmark_group("vertex_waves_4k");
            g.sample_size(10);
            g.throughput(Throughput::Elements(u64::from(frame.plan.chunk_count)));
            g.bench_function("vertex_wave_commands", |b| {
                b.iter(|| {
                    black_box(
                        vertex_wave_commands(
                            &result.mid.vertex_cull,
                            frame.plan.chunk_count,
                            table,
                            &frame.plan.order,
                            &frame.plan.passes,
                        )
                        .unwrap(),
                    )
                })
            });
            g.finish();
        }
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
