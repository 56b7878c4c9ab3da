//! criterion benches for visbuf, each group with a baseline:
//! - `id_pack`, `id_unpack`: vis-ID pack / unpack of 64k words vs a naive bit-field
//!   version (primitive bits by a loop, fields by division and modulo) and a plain copy.
//! - `vertex_pack`, `vertex_unpack`: the 32-byte vertex vs copying the unpacked f32 vertex
//!   (80 bytes) it replaces.
//! - `encode`: the four primitive-ID encoders on a 1M-triangle mesh (16 grids of 65 522
//!   triangles), the talk's greedy passes being the baselines.
//! - `bary`: barycentrics + derivatives per pixel (analytic) vs the naive per-pixel method
//!   (project, screen-space edge functions, perspective-correct, derivatives from two more
//!   evaluations) and the watertight ray vs Möller–Trumbore.

#[path = "../tests/common/mod.rs"]
mod common;

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::{Mat4, Vec2, Vec3, Vec4};
use visbuf::bary::{barycentrics, barycentrics_quad};
use visbuf::ray::{intersect_moller_trumbore, intersect_watertight, pixel_ray_direction};
use visbuf::{
    PrimitiveBits, ShadingRate, Vertex, VertexCore, VisFields, VisId, VisLayout, VisbufVertex,
};

const N: usize = 65536;

fn fields(seed: u64) -> Vec<(u32, VisFields)> {
    let mut rng = testkit::Rng::new(seed);
    (0..N)
        .map(|_| {
            let r = rng.next_u64();
            let pc = (r % 65536) as u32 + 1;
            let p = PrimitiveBits::for_count(pc).unwrap();
            let f = VisFields {
                micro_batch: ((r >> 20) % 65535) as u32,
                instance: ((r >> 40) as u32) & (p.instances_per_id() - 1),
                primitive: ((r >> 8) as u32) % pc,
                rate: ShadingRate::Rate1x1,
            };
            (pc, f)
        })
        .collect()
}

/// The baseline: what one writes without the layout's tricks. Primitive bits by a loop over
/// powers of two, fields placed with multiplication, every limit checked by comparison.
fn naive_pack(primitive_count: u32, f: &VisFields) -> Option<u32> {
    let mut bits = 0u32;
    while (1u64 << bits) < primitive_count as u64 {
        bits += 1;
    }
    let instances = 1u64 << (16 - bits);
    if f.micro_batch as u64 >= 65535
        || f.instance as u64 >= instances
        || f.primitive as u64 >= (1u64 << bits)
    {
        return None;
    }
    Some(
        (f.micro_batch as u64 * 65536 + f.instance as u64 * (1u64 << bits) + f.primitive as u64)
            as u32,
    )
}

fn naive_unpack(word: u32, bits: u32) -> Option<VisFields> {
    let mb = word / 65536;
    if mb == 65535 {
        return None;
    }
    let low = word % 65536;
    Some(VisFields {
        micro_batch: mb,
        instance: low / (1 << bits),
        primitive: low % (1 << bits),
        rate: ShadingRate::Rate1x1,
    })
}

fn bench_id(c: &mut Criterion) {
    let input = fields(1);
    let words: Vec<(u32, PrimitiveBits)> = input
        .iter()
        .map(|(pc, f)| {
            let b = PrimitiveBits::for_count(*pc).unwrap();
            (VisId::pack(VisLayout::Standard, b, *f).unwrap().0, b)
        })
        .collect();
    let mut g = c.benchmark_group("id_pack");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("visbuf", |b| {
        b.iter(|| {
            let mut acc = 0u32;
            for (pc, f) in &input {
                let bits = PrimitiveBits::for_count(*pc).unwrap();
                acc ^= VisId::pack(VisLayout::Standard, bits, *f).unwrap().0;
            }
            black_box(acc)
        })
    });
    g.bench_function("naive", |b| {
        b.iter(|| {
            let mut acc = 0u32;
            for (pc, f) in &input {
                acc ^= naive_pack(*pc, f).unwrap();
            }
            black_box(acc)
        })
    });
    g.finish();
    let mut g = c.benchmark_group("id_unpack");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("visbuf", |b| {
        b.iter(|| {
            let mut acc = 0u32;
            for (w, bits) in &words {
                let f = VisId(*w).unpack(VisLayout::Standard, *bits).unwrap();
                acc ^= f.micro_batch ^ f.instance ^ f.primitive;
            }
            black_box(acc)
        })
    });
    g.bench_function("naive", |b| {
        b.iter(|| {
            let mut acc = 0u32;
            for (w, bits) in &words {
                let f = naive_unpack(*w, bits.get()).unwrap();
                acc ^= f.micro_batch ^ f.instance ^ f.primitive;
            }
            black_box(acc)
        })
    });
    g.bench_function("copy", |b| {
        b.iter(|| {
            let mut acc = 0u32;
            for (w, _) in &words {
                acc ^= *w;
            }
            black_box(acc)
        })
    });
    g.finish();
}

fn vertices() -> Vec<Vertex> {
    let mut rng = testkit::Rng::new(3);
    let mut r = move || rng.f32();
    (0..N)
        .map(|_| Vertex {
            core: VertexCore {
                hpos: Vec3::new(r() * 20.0 - 10.0, r() * 20.0 - 10.0, r() * 100.0),
                normal: Vec3::new(r() - 0.5, r() - 0.5, r() - 0.5).normalize(),
                tangent: Vec4::new(r() - 0.5, r() - 0.5, r() - 0.5, 1.0),
                prev_hpos: Vec3::new(r() * 20.0 - 10.0, r() * 20.0 - 10.0, r() * 100.0),
            },
            uv: Vec2::new(r() * 7.0, r() * 7.0),
            color: Vec4::new(r(), r(), r(), 1.0),
            extra: 0,
        })
        .collect()
}

fn bench_vertex(c: &mut Criterion) {
    let input = vertices();
    let packed: Vec<VisbufVertex> = input
        .iter()
        .map(|v| VisbufVertex::pack(v).unwrap())
        .collect();
    let mut out = vec![VisbufVertex::default(); N];
    let mut out_f32 = vec![Vertex::default(); N];
    let mut g = c.benchmark_group("vertex_pack");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("visbuf", |b| {
        b.iter(|| {
            for (o, v) in out.iter_mut().zip(&input) {
                *o = VisbufVertex::pack(v).unwrap();
            }
            black_box(&out);
        })
    });
    g.bench_function("copy_f32_vertex", |b| {
        b.iter(|| {
            out_f32.copy_from_slice(black_box(&input));
            black_box(&out_f32);
        })
    });
    g.finish();
    let mut g = c.benchmark_group("vertex_unpack");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("visbuf", |b| {
        b.iter(|| {
            for (o, v) in out_f32.iter_mut().zip(&packed) {
                *o = v.unpack();
            }
            black_box(&out_f32);
        })
    });
    g.bench_function("copy_f32_vertex", |b| {
        b.iter(|| {
            out_f32.copy_from_slice(black_box(&input));
            black_box(&out_f32);
        })
    });
    g.finish();
}

type Encoder = fn(&[u32], u32) -> Result<visbuf::PrimitiveIdMesh, visbuf::Error>;

fn bench_encode(c: &mut Criterion) {
    // 1M triangles: 16 geometries of 65 522 (the encoders take one geometry at a time).
    let (grid, gv) = common::grid(181);
    let chunks = 16;
    let tris = (grid.len() / 3 * chunks) as u64;
    let mut g = c.benchmark_group("encode");
    g.sample_size(10);
    g.throughput(Throughput::Elements(tris));
    let encoders: [(&str, Encoder); 4] = [
        ("provoking_matching", visbuf::encode_provoking::<u32>),
        ("provoking_greedy", visbuf::encode_provoking_greedy::<u32>),
        ("xor_peeling", visbuf::encode_xor::<u32>),
        ("xor_greedy", visbuf::encode_xor_greedy::<u32>),
    ];
    for (name, enc) in encoders {
        g.bench_function(BenchmarkId::new(name, "1M-tri grid"), |b| {
            b.iter(|| {
                let mut added = 0;
                for _ in 0..chunks {
                    added += enc(black_box(&grid), gv).unwrap().added_vertices();
                }
                black_box(added)
            })
        });
    }
    let (_, bunny) = common::bunny();
    for (name, enc) in encoders {
        g.throughput(Throughput::Elements(bunny.len() as u64 / 3));
        g.bench_function(BenchmarkId::new(name, "bunny"), |b| {
            b.iter(|| black_box(enc(black_box(&bunny), 1839).unwrap().added_vertices()))
        });
    }
    g.finish();
}

/// The naive per-pixel baseline: project the vertices, screen-space edge functions,
/// perspective correction, and derivatives as differences with two more evaluations.
fn naive_bary(clip: [Vec4; 3], p: Vec2, vp: Vec2) -> [Vec3; 3] {
    let at = |p: Vec2| {
        let sp = clip.map(|c| {
            Vec2::new(
                (c.x / c.w + 1.0) * 0.5 * vp.x,
                (1.0 - c.y / c.w) * 0.5 * vp.y,
            )
        });
        let cross = |a: Vec2, b: Vec2| a.x * b.y - a.y * b.x;
        let area = cross(sp[1] - sp[0], sp[2] - sp[0]);
        let b = Vec3::new(
            cross(sp[1] - p, sp[2] - p),
            cross(sp[2] - p, sp[0] - p),
            cross(sp[0] - p, sp[1] - p),
        ) / area;
        let bw = b / Vec3::new(clip[0].w, clip[1].w, clip[2].w);
        bw / bw.element_sum()
    };
    let l = at(p);
    [l, at(p + Vec2::X) - l, at(p + Vec2::Y) - l]
}

fn bench_bary(c: &mut Criterion) {
    let vp = Vec2::new(1920.0, 1080.0);
    let proj = Mat4::perspective_rh(1.0, vp.x / vp.y, 0.1, 100.0);
    let tri = [
        Vec3::new(-1.0, -0.5, -4.0),
        Vec3::new(1.5, -0.2, -5.0),
        Vec3::new(0.2, 1.0, -4.5),
    ];
    let clip = tri.map(|p| proj * p.extend(1.0));
    let inv = proj.inverse();
    let pixels: Vec<Vec2> = (0..256 * 256)
        .map(|i| Vec2::new(800.5 + (i % 256) as f32, 400.5 + (i / 256) as f32))
        .collect();
    let mut g = c.benchmark_group("bary");
    g.throughput(Throughput::Elements(pixels.len() as u64));
    g.bench_function("analytic_exact", |b| {
        b.iter(|| {
            let mut acc = Vec3::ZERO;
            for p in &pixels {
                let r = barycentrics(black_box(clip), *p, vp);
                acc += r.lambda + r.ddx + r.ddy;
            }
            black_box(acc)
        })
    });
    g.bench_function("analytic_quad", |b| {
        b.iter(|| {
            let mut acc = Vec3::ZERO;
            for p in &pixels {
                let r = barycentrics_quad(black_box(clip), *p, vp);
                acc += r.lambda + r.ddx + r.ddy;
            }
            black_box(acc)
        })
    });
    g.bench_function("naive_three_evaluations", |b| {
        b.iter(|| {
            let mut acc = Vec3::ZERO;
            for p in &pixels {
                let [l, dx, dy] = naive_bary(black_box(clip), *p, vp);
                acc += l + dx + dy;
            }
            black_box(acc)
        })
    });
    let dirs: Vec<Vec3> = pixels
        .iter()
        .map(|p| pixel_ray_direction(inv, Vec3::ZERO, *p, vp).unwrap())
        .collect();
    g.bench_function("ray_watertight", |b| {
        b.iter(|| {
            let mut acc = Vec3::ZERO;
            for d in &dirs {
                if let Some(h) = intersect_watertight(Vec3::ZERO, *d, black_box(tri)) {
                    acc += h.barycentrics;
                }
            }
            black_box(acc)
        })
    });
    g.bench_function("ray_moller_trumbore", |b| {
        b.iter(|| {
            let mut acc = Vec3::ZERO;
            for d in &dirs {
                if let Some(h) = intersect_moller_trumbore(Vec3::ZERO, *d, black_box(tri)) {
                    acc += h.barycentrics;
                }
            }
            black_box(acc)
        })
    });
    g.finish();
}

criterion_group!(benches, bench_id, bench_vertex, bench_encode, bench_bary);
criterion_main!(benches);
