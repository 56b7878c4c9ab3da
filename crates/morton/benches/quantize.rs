//! Quantise+encode of 8M random points (`Vec3`, 12 bytes each) into 32- and 64-bit Morton
//! keys, sequential and parallel, against a plain copy of the same bytes (the memory
//! floor: read 12 bytes per point, write the key's bytes) and a straightforward
//! quantise-then-encode loop (floor, clamp, cast, scalar encode).
//!
//! Run: `cargo bench -p morton --features parallel --bench quantize`.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use morton::{Path, Quantizer3};
use rayon::prelude::*;

const N: usize = 8 * 1024 * 1024;

fn points() -> Vec<Vec3> {
    let mut rng = testkit::Rng::new(0x9e37_79b9_7f4a_7c15);
    let mut next = || rng.range(-1000.0, 1000.0);
    (0..N).map(|_| Vec3::new(next(), next(), next())).collect()
}

/// The straightforward version: per point, per axis floor/clamp/cast, then encode.
fn naive_u32(min: Vec3, max: Vec3, points: &[Vec3], out: &mut [u32]) {
    let cells = Vec3::splat(1024.0) / (max - min);
    for (o, p) in out.iter_mut().zip(points) {
        let c = ((*p - min) * cells)
            .floor()
            .clamp(Vec3::ZERO, Vec3::splat(1023.0))
            .as_uvec3();
        *o = morton::encode3_u32(c.x, c.y, c.z);
    }
}

fn quantize(c: &mut Criterion) {
    let pts = points();
    let (lo, hi) = (Vec3::splat(-1000.0), Vec3::splat(1000.0));
    let q10 = Quantizer3::new(lo, hi, 10).unwrap();
    let q21 = Quantizer3::new(lo, hi, 21).unwrap();
    let mut k32 = vec![0u32; N];
    let mut k64 = vec![0u64; N];
    let mut copy = vec![Vec3::ZERO; N];
    let chunk = morton::parallel::QUANTIZE_CHUNK;

    let mut g = c.benchmark_group("quantize_encode_8M");
    g.throughput(Throughput::Elements(N as u64));
    g.sample_size(10);
    g.bench_function("u32/seq", |b| {
        b.iter(|| q10.morton_u32_slice(&pts, black_box(&mut k32)).unwrap())
    });
    g.bench_function("u32/par", |b| {
        b.iter(|| q10.par_morton_u32_slice(&pts, black_box(&mut k32)).unwrap())
    });
    g.bench_function("u64/seq", |b| {
        b.iter(|| q21.morton_u64_slice(&pts, black_box(&mut k64)).unwrap())
    });
    g.bench_function("u64/par", |b| {
        b.iter(|| q21.par_morton_u64_slice(&pts, black_box(&mut k64)).unwrap())
    });
    for path in Path::available() {
        g.bench_function(format!("u32/seq/{path:?}"), |b| {
            b.iter(|| {
                q10.morton_u32_slice_with(path, &pts, black_box(&mut k32))
                    .unwrap()
            })
        });
    }
    g.bench_function("baseline/naive_u32/seq", |b| {
        b.iter(|| naive_u32(lo, hi, &pts, black_box(&mut k32)))
    });
    g.bench_function("baseline/naive_u32/par", |b| {
        b.iter(|| {
            pts.par_chunks(chunk)
                .zip(k32.par_chunks_mut(chunk))
                .for_each(|(p, o)| naive_u32(lo, hi, p, o));
            black_box(&mut k32);
        })
    });
    // The same bytes read: a plain copy of the 12-byte points.
    g.bench_function("baseline/copy_points/seq", |b| {
        b.iter(|| black_box(&mut copy).copy_from_slice(&pts))
    });
    g.bench_function("baseline/copy_points/par", |b| {
        b.iter(|| {
            copy.par_chunks_mut(chunk)
                .zip(pts.par_chunks(chunk))
                .for_each(|(d, s)| d.copy_from_slice(s));
            black_box(&mut copy);
        })
    });
    g.finish();
}

criterion_group!(benches, quantize);
criterion_main!(benches);
