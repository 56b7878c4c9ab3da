//! ns per code for Morton and Hilbert encode/decode, scalar and batch, each group with the
//! peer crates as baselines:
//!
//! - `scalar/*`: one call per key with `black_box` on every input, so nothing vectorises
//!   across keys: the cost of a single call inside a loop.
//! - `batch/*`: whole slices; ours through the slice functions (best path and every path),
//!   the peers through their per-key function in an iterator loop the compiler may
//!   vectorise (their best batch form).
//!
//! Peers have no 10- or 21-bit types: 3D-32 baselines encode `[u8; 3] -> u32` (8 bits per
//! axis) and `[u16; 3] -> u64`; 3D-64 baselines `[u16; 3] -> u64` (16 bits per axis).
//! Inputs are the same random values masked to each function's width.
//!
//! Run: `cargo bench -p morton --bench codes` (add `-- <filter>`, e.g. `encode3_u32`).

use std::hint::black_box;

use criterion::measurement::WallTime;
use criterion::{
    BenchmarkGroup, BenchmarkId, Criterion, Throughput, criterion_group, criterion_main,
};
use morton::{Path, batch, hilbert};

const N: usize = 16 * 1024;

struct Data {
    xs: Vec<u32>,
    ys: Vec<u32>,
    zs: Vec<u32>,
    k32: Vec<u32>,
    k64: Vec<u64>,
}

fn data(bits: u32) -> Data {
    let mut rng = testkit::Rng::new(0x2545_f491_4f6c_dd1d);
    let m = if bits >= 32 {
        u32::MAX
    } else {
        (1 << bits) - 1
    };
    let xs = (0..N).map(|_| rng.next_u32() & m).collect();
    let ys = (0..N).map(|_| rng.next_u32() & m).collect();
    let zs = (0..N).map(|_| rng.next_u32() & m).collect();
    let k32 = rng.words(N);
    let k64 = (0..N).map(|_| rng.next_u64()).collect();
    Data {
        xs,
        ys,
        zs,
        k32,
        k64,
    }
}

/// zorder's BMI2 token, if this CPU has BMI2 (its safe API checks once, like ours).
fn zorder_bmi2() -> Option<zorder::bmi2::HardwareSupportToken> {
    zorder::bmi2::HardwareSupportToken::new()
}

type Group<'a> = BenchmarkGroup<'a, WallTime>;

/// Times `out[i] = f(xs[i], ys[i], zs[i])` over every key as `name`. `OPAQUE` puts
/// `black_box` on every input (the `scalar/*` cost of one call inside a loop); without it
/// the compiler may vectorise across keys (the peers' `batch/*` form).
fn map3<const OPAQUE: bool, O>(
    g: &mut Group,
    name: &str,
    out: &mut [O],
    [xs, ys, zs]: [&[u32]; 3],
    f: impl Fn(u32, u32, u32) -> O,
) {
    let k = |v: u32| if OPAQUE { black_box(v) } else { v };
    g.bench_function(name, |b| {
        b.iter(|| {
            for (((o, &x), &y), &z) in out.iter_mut().zip(xs).zip(ys).zip(zs) {
                *o = f(k(x), k(y), k(z));
            }
            black_box(&mut *out);
        })
    });
}

/// [`map3`] over two lanes.
fn map2<const OPAQUE: bool, O>(
    g: &mut Group,
    name: &str,
    out: &mut [O],
    [xs, ys]: [&[u32]; 2],
    f: impl Fn(u32, u32) -> O,
) {
    let k = |v: u32| if OPAQUE { black_box(v) } else { v };
    g.bench_function(name, |b| {
        b.iter(|| {
            for ((o, &x), &y) in out.iter_mut().zip(xs).zip(ys) {
                *o = f(k(x), k(y));
            }
            black_box(&mut *out);
        })
    });
}

/// Times `out[i] = f(keys[i])` over every key as `name`; `OPAQUE` as in [`map3`].
fn unmap<const OPAQUE: bool, K: Copy, O>(
    g: &mut Group,
    name: &str,
    out: &mut [O],
    keys: &[K],
    f: impl Fn(K) -> O,
) {
    g.bench_function(name, |b| {
        b.iter(|| {
            for (o, &k) in out.iter_mut().zip(keys) {
                *o = f(if OPAQUE { black_box(k) } else { k });
            }
            black_box(&mut *out);
        })
    });
}

/// Times `f(path)` as `batch/morton/<path>` on every path this CPU and build have.
fn per_path(g: &mut Group, mut f: impl FnMut(Path)) {
    for path in Path::available() {
        g.bench_with_input(
            BenchmarkId::new("batch/morton", format!("{path:?}")),
            &path,
            |b, &p| b.iter(|| f(p)),
        );
    }
}

/// `[x, y, z]` widened to u32.
fn widen3<T: Into<u32>>([x, y, z]: [T; 3]) -> [u32; 3] {
    [x.into(), y.into(), z.into()]
}

fn encode3_u32(c: &mut Criterion) {
    let d = data(10);
    let mut out = vec![0u32; N];
    let mut out64 = vec![0u64; N];
    let mut g = c.benchmark_group("encode3_u32");
    g.throughput(Throughput::Elements(N as u64));
    let (xs, ys, zs) = (&d.xs[..], &d.ys[..], &d.zs[..]);
    let l = [xs, ys, zs];
    let u8s = |x: u32, y: u32, z: u32| [x as u8, y as u8, z as u8];
    let u16s = |x: u32, y: u32, z: u32| [x as u16, y as u16, z as u16];
    map3::<true, _>(&mut g, "scalar/morton", &mut out, l, morton::encode3_u32);
    map3::<true, _>(
        &mut g,
        "scalar/morton_magic",
        &mut out,
        l,
        morton::magic::encode3_u32,
    );
    map3::<true, _>(&mut g, "scalar/zorder_u8", &mut out, l, |x, y, z| {
        zorder::index_of(u8s(x, y, z))
    });
    map3::<true, _>(&mut g, "scalar/zorder_u16_u64", &mut out64, l, |x, y, z| {
        zorder::index_of(u16s(x, y, z))
    });
    if let Some(tok) = zorder_bmi2() {
        map3::<true, _>(&mut g, "scalar/zorder_bmi2_u8", &mut out, l, |x, y, z| {
            zorder::bmi2::index_of(u8s(x, y, z), tok)
        });
        map3::<true, _>(
            &mut g,
            "scalar/zorder_bmi2_u16_u64",
            &mut out64,
            l,
            |x, y, z| zorder::bmi2::index_of(u16s(x, y, z), tok),
        );
    }
    map3::<true, _>(
        &mut g,
        "scalar/morton_encoding_u8",
        &mut out,
        l,
        |x, y, z| morton_encoding::morton_encode(u8s(x, y, z)),
    );
    per_path(&mut g, |p| {
        batch::encode3_u32_soa_with(p, xs, ys, zs, black_box(&mut out)).unwrap()
    });
    g.bench_function("batch/morton_best", |b| {
        b.iter(|| batch::encode3_u32_soa(xs, ys, zs, black_box(&mut out)).unwrap())
    });
    let aos: Vec<[u32; 3]> = (0..N).map(|i| [xs[i], ys[i], zs[i]]).collect();
    g.bench_function("batch/morton_best_aos", |b| {
        b.iter(|| batch::encode3_u32_aos(&aos, black_box(&mut out)).unwrap())
    });
    map3::<false, _>(&mut g, "batch/zorder_u8", &mut out, l, |x, y, z| {
        zorder::index_of(u8s(x, y, z))
    });
    if let Some(tok) = zorder_bmi2() {
        map3::<false, _>(&mut g, "batch/zorder_bmi2_u8", &mut out, l, |x, y, z| {
            zorder::bmi2::index_of(u8s(x, y, z), tok)
        });
        map3::<false, _>(
            &mut g,
            "batch/zorder_bmi2_u16_u64",
            &mut out64,
            l,
            |x, y, z| zorder::bmi2::index_of(u16s(x, y, z), tok),
        );
    }
    map3::<false, _>(
        &mut g,
        "batch/morton_encoding_u8",
        &mut out,
        l,
        |x, y, z| morton_encoding::morton_encode(u8s(x, y, z)),
    );
    g.finish();
}

fn encode3_u64(c: &mut Criterion) {
    let d = data(21);
    let mut out = vec![0u64; N];
    let mut g = c.benchmark_group("encode3_u64");
    g.throughput(Throughput::Elements(N as u64));
    let (xs, ys, zs) = (&d.xs[..], &d.ys[..], &d.zs[..]);
    let l = [xs, ys, zs];
    let u16s = |x: u32, y: u32, z: u32| [x as u16, y as u16, z as u16];
    map3::<true, _>(&mut g, "scalar/morton", &mut out, l, morton::encode3_u64);
    map3::<true, _>(
        &mut g,
        "scalar/morton_magic",
        &mut out,
        l,
        morton::magic::encode3_u64,
    );
    map3::<true, _>(&mut g, "scalar/zorder_u16", &mut out, l, |x, y, z| {
        zorder::index_of(u16s(x, y, z))
    });
    if let Some(tok) = zorder_bmi2() {
        map3::<true, _>(&mut g, "scalar/zorder_bmi2_u16", &mut out, l, |x, y, z| {
            zorder::bmi2::index_of(u16s(x, y, z), tok)
        });
    }
    map3::<true, _>(
        &mut g,
        "scalar/morton_encoding_u16",
        &mut out,
        l,
        |x, y, z| morton_encoding::morton_encode(u16s(x, y, z)),
    );
    per_path(&mut g, |p| {
        batch::encode3_u64_soa_with(p, xs, ys, zs, black_box(&mut out)).unwrap()
    });
    g.bench_function("batch/morton_best", |b| {
        b.iter(|| batch::encode3_u64_soa(xs, ys, zs, black_box(&mut out)).unwrap())
    });
    map3::<false, _>(&mut g, "batch/zorder_u16", &mut out, l, |x, y, z| {
        zorder::index_of(u16s(x, y, z))
    });
    if let Some(tok) = zorder_bmi2() {
        map3::<false, _>(&mut g, "batch/zorder_bmi2_u16", &mut out, l, |x, y, z| {
            zorder::bmi2::index_of(u16s(x, y, z), tok)
        });
    }
    map3::<false, _>(
        &mut g,
        "batch/morton_encoding_u16",
        &mut out,
        l,
        |x, y, z| morton_encoding::morton_encode(u16s(x, y, z)),
    );
    g.finish();
}

fn encode2(c: &mut Criterion) {
    let d = data(16);
    let mut out = vec![0u32; N];
    let mut g = c.benchmark_group("encode2_u32");
    g.throughput(Throughput::Elements(N as u64));
    let (xs, ys) = (&d.xs[..], &d.ys[..]);
    let l = [xs, ys];
    let u16s = |x: u32, y: u32| [x as u16, y as u16];
    map2::<true, _>(&mut g, "scalar/morton", &mut out, l, morton::encode2_u32);
    map2::<true, _>(&mut g, "scalar/zorder", &mut out, l, |x, y| {
        zorder::index_of(u16s(x, y))
    });
    if let Some(tok) = zorder_bmi2() {
        map2::<true, _>(&mut g, "scalar/zorder_bmi2", &mut out, l, |x, y| {
            zorder::bmi2::index_of(u16s(x, y), tok)
        });
    }
    map2::<true, _>(&mut g, "scalar/morton_encoding", &mut out, l, |x, y| {
        morton_encoding::morton_encode(u16s(x, y))
    });
    per_path(&mut g, |p| {
        batch::encode2_u32_soa_with(p, xs, ys, black_box(&mut out)).unwrap()
    });
    map2::<false, _>(&mut g, "batch/zorder", &mut out, l, |x, y| {
        zorder::index_of(u16s(x, y))
    });
    g.finish();

    let d = data(32);
    let mut out = vec![0u64; N];
    let mut g = c.benchmark_group("encode2_u64");
    g.throughput(Throughput::Elements(N as u64));
    let (xs, ys) = (&d.xs[..], &d.ys[..]);
    let l = [xs, ys];
    map2::<true, _>(&mut g, "scalar/morton", &mut out, l, morton::encode2_u64);
    map2::<true, _>(&mut g, "scalar/zorder", &mut out, l, |x, y| {
        zorder::index_of([x, y])
    });
    if let Some(tok) = zorder_bmi2() {
        map2::<true, _>(&mut g, "scalar/zorder_bmi2", &mut out, l, |x, y| {
            zorder::bmi2::index_of([x, y], tok)
        });
    }
    map2::<true, _>(&mut g, "scalar/morton_encoding", &mut out, l, |x, y| {
        morton_encoding::morton_encode([x, y])
    });
    per_path(&mut g, |p| {
        batch::encode2_u64_soa_with(p, xs, ys, black_box(&mut out)).unwrap()
    });
    map2::<false, _>(&mut g, "batch/zorder", &mut out, l, |x, y| {
        zorder::index_of([x, y])
    });
    g.finish();
}

fn decode(c: &mut Criterion) {
    let d = data(32);
    let (mut a, mut b2, mut c3) = (vec![0u32; N], vec![0u32; N], vec![0u32; N]);
    let mut acc = vec![[0u32; 3]; N];
    let mut acc2 = vec![[0u32; 2]; N];

    let mut g = c.benchmark_group("decode3_u32");
    g.throughput(Throughput::Elements(N as u64));
    let k32: Vec<u32> = d.k32.iter().map(|k| k & 0x3fff_ffff).collect();
    unmap::<true, _, _>(&mut g, "scalar/morton", &mut acc, &k32, morton::decode3_u32);
    unmap::<true, _, _>(&mut g, "scalar/zorder_u8", &mut acc, &k32, |k| {
        widen3::<u8>(zorder::coord_of(k & 0xff_ffff))
    });
    if let Some(tok) = zorder_bmi2() {
        unmap::<true, _, _>(&mut g, "scalar/zorder_bmi2_u8", &mut acc, &k32, |k| {
            widen3::<u8>(zorder::bmi2::coord_of(k & 0xff_ffff, tok))
        });
    }
    unmap::<true, _, _>(&mut g, "scalar/morton_encoding_u8", &mut acc, &k32, |k| {
        widen3::<u8>(morton_encoding::morton_decode(k & 0xff_ffff))
    });
    per_path(&mut g, |p| {
        batch::decode3_u32_soa_with(p, &k32, &mut a, &mut b2, black_box(&mut c3)).unwrap()
    });
    g.bench_function("batch/morton_best_aos", |bn| {
        bn.iter(|| batch::decode3_u32_aos(&k32, black_box(&mut acc)).unwrap())
    });
    if let Some(tok) = zorder_bmi2() {
        unmap::<false, _, _>(&mut g, "batch/zorder_bmi2_u8", &mut acc, &k32, |k| {
            widen3::<u8>(zorder::bmi2::coord_of(k & 0xff_ffff, tok))
        });
    }
    g.finish();

    let mut g = c.benchmark_group("decode3_u64");
    g.throughput(Throughput::Elements(N as u64));
    let k64: Vec<u64> = d.k64.iter().map(|k| k & !(1 << 63)).collect();
    unmap::<true, _, _>(&mut g, "scalar/morton", &mut acc, &k64, morton::decode3_u64);
    unmap::<true, _, _>(&mut g, "scalar/zorder_u16", &mut acc, &k64, |k| {
        widen3::<u16>(zorder::coord_of(k & 0xffff_ffff_ffff))
    });
    if let Some(tok) = zorder_bmi2() {
        unmap::<true, _, _>(&mut g, "scalar/zorder_bmi2_u16", &mut acc, &k64, |k| {
            widen3::<u16>(zorder::bmi2::coord_of(k & 0xffff_ffff_ffff, tok))
        });
    }
    unmap::<true, _, _>(&mut g, "scalar/morton_encoding_u16", &mut acc, &k64, |k| {
        widen3::<u16>(morton_encoding::morton_decode(k & 0xffff_ffff_ffff))
    });
    per_path(&mut g, |p| {
        batch::decode3_u64_soa_with(p, &k64, &mut a, &mut b2, black_box(&mut c3)).unwrap()
    });
    g.finish();

    let mut g = c.benchmark_group("decode2_u32");
    g.throughput(Throughput::Elements(N as u64));
    unmap::<true, _, _>(
        &mut g,
        "scalar/morton",
        &mut acc2,
        &d.k32,
        morton::decode2_u32,
    );
    unmap::<true, _, _>(&mut g, "scalar/zorder", &mut acc2, &d.k32, |k| {
        let [x, y]: [u16; 2] = zorder::coord_of(k);
        [x as u32, y as u32]
    });
    if let Some(tok) = zorder_bmi2() {
        unmap::<true, _, _>(&mut g, "scalar/zorder_bmi2", &mut acc2, &d.k32, |k| {
            let [x, y]: [u16; 2] = zorder::bmi2::coord_of(k, tok);
            [x as u32, y as u32]
        });
    }
    per_path(&mut g, |p| {
        batch::decode2_u32_soa_with(p, &d.k32, &mut a, black_box(&mut b2)).unwrap()
    });
    g.finish();

    let mut g = c.benchmark_group("decode2_u64");
    g.throughput(Throughput::Elements(N as u64));
    unmap::<true, _, _>(
        &mut g,
        "scalar/morton",
        &mut acc2,
        &d.k64,
        morton::decode2_u64,
    );
    unmap::<true, _, _>(&mut g, "scalar/zorder", &mut acc2, &d.k64, zorder::coord_of);
    if let Some(tok) = zorder_bmi2() {
        unmap::<true, _, _>(&mut g, "scalar/zorder_bmi2", &mut acc2, &d.k64, |k| {
            zorder::bmi2::coord_of(k, tok)
        });
    }
    per_path(&mut g, |p| {
        batch::decode2_u64_soa_with(p, &d.k64, &mut a, black_box(&mut b2)).unwrap()
    });
    g.finish();
}

fn hilbert3(c: &mut Criterion) {
    let d = data(10);
    let (xs, ys, zs) = (&d.xs[..], &d.ys[..], &d.zs[..]);
    let l = [xs, ys, zs];
    let mut out = vec![0u32; N];
    let mut out64 = vec![0u64; N];
    let mut g = c.benchmark_group("hilbert3");
    g.throughput(Throughput::Elements(N as u64));
    map3::<true, _>(
        &mut g,
        "encode_u32/scalar/morton",
        &mut out,
        l,
        hilbert::encode3_u32,
    );
    g.bench_function("encode_u32/batch/morton_best", |b| {
        b.iter(|| hilbert::encode3_u32_soa(xs, ys, zs, black_box(&mut out)).unwrap())
    });
    map3::<true, _>(
        &mut g,
        "encode_u64/scalar/morton",
        &mut out64,
        l,
        hilbert::encode3_u64,
    );
    g.bench_function("encode_u64/batch/morton_best", |b| {
        b.iter(|| hilbert::encode3_u64_soa(xs, ys, zs, black_box(&mut out64)).unwrap())
    });
    // lindel: 10-bit values in u16 coordinates (its key is u64; it skips leading zero bits).
    map3::<true, _>(
        &mut g,
        "encode_u16/scalar/lindel",
        &mut out64,
        l,
        |x, y, z| lindel::hilbert_encode([x as u16, y as u16, z as u16]),
    );
    map3::<true, _>(&mut g, "encode_u8/scalar/lindel", &mut out, l, |x, y, z| {
        lindel::hilbert_encode([x as u8, y as u8, z as u8])
    });
    let mut acc = vec![[0u32; 3]; N];
    let keys: Vec<u32> = d.k32.iter().map(|k| k & 0x3fff_ffff).collect();
    unmap::<true, _, _>(
        &mut g,
        "decode_u32/scalar/morton",
        &mut acc,
        &keys,
        hilbert::decode3_u32,
    );
    unmap::<true, _, _>(&mut g, "decode_u16/scalar/lindel", &mut acc, &keys, |k| {
        widen3::<u16>(lindel::hilbert_decode(k as u64))
    });
    // The Morton code of the same points, for the price ratio.
    g.bench_function("morton_encode_u32/batch/morton_best", |b| {
        b.iter(|| batch::encode3_u32_soa(xs, ys, zs, black_box(&mut out)).unwrap())
    });
    g.finish();
}

criterion_group!(benches, encode3_u32, encode3_u64, encode2, decode, hilbert3);
criterion_main!(benches);
