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

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
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

fn encode3_u32(c: &mut Criterion) {
    let d = data(10);
    let mut out = vec![0u32; N];
    let mut out64 = vec![0u64; N];
    let mut g = c.benchmark_group("encode3_u32");
    g.throughput(Throughput::Elements(N as u64));
    let (xs, ys, zs) = (&d.xs, &d.ys, &d.zs);
    macro_rules! scalar {
        ($name:expr, $out:ident, $f:expr) => {
            g.bench_function($name, |b| {
                b.iter(|| {
                    for (((o, &x), &y), &z) in $out.iter_mut().zip(xs).zip(ys).zip(zs) {
                        *o = $f(black_box(x), black_box(y), black_box(z));
                    }
                    black_box(&mut $out);
                })
            });
        };
    }
    macro_rules! batch {
        ($name:expr, $out:ident, $f:expr) => {
            g.bench_function($name, |b| {
                b.iter(|| {
                    for (((o, &x), &y), &z) in $out.iter_mut().zip(xs).zip(ys).zip(zs) {
                        *o = $f(x, y, z);
                    }
                    black_box(&mut $out);
                })
            });
        };
    }
    scalar!("scalar/morton", out, morton::encode3_u32);
    scalar!("scalar/morton_magic", out, morton::magic::encode3_u32);
    scalar!("scalar/zorder_u8", out, |x: u32, y: u32, z: u32| {
        zorder::index_of([x as u8, y as u8, z as u8])
    });
    scalar!("scalar/zorder_u16_u64", out64, |x: u32, y: u32, z: u32| {
        zorder::index_of([x as u16, y as u16, z as u16])
    });
    if let Some(tok) = zorder_bmi2() {
        scalar!("scalar/zorder_bmi2_u8", out, |x: u32, y: u32, z: u32| {
            zorder::bmi2::index_of([x as u8, y as u8, z as u8], tok)
        });
        scalar!(
            "scalar/zorder_bmi2_u16_u64",
            out64,
            |x: u32, y: u32, z: u32| zorder::bmi2::index_of([x as u16, y as u16, z as u16], tok)
        );
    }
    scalar!(
        "scalar/morton_encoding_u8",
        out,
        |x: u32, y: u32, z: u32| { morton_encoding::morton_encode([x as u8, y as u8, z as u8]) }
    );
    for path in Path::available() {
        g.bench_with_input(
            BenchmarkId::new("batch/morton", format!("{path:?}")),
            &path,
            |b, &p| {
                b.iter(|| batch::encode3_u32_soa_with(p, xs, ys, zs, black_box(&mut out)).unwrap())
            },
        );
    }
    g.bench_function("batch/morton_best", |b| {
        b.iter(|| batch::encode3_u32_soa(xs, ys, zs, black_box(&mut out)).unwrap())
    });
    let aos: Vec<[u32; 3]> = (0..N).map(|i| [xs[i], ys[i], zs[i]]).collect();
    g.bench_function("batch/morton_best_aos", |b| {
        b.iter(|| batch::encode3_u32_aos(&aos, black_box(&mut out)).unwrap())
    });
    batch!("batch/zorder_u8", out, |x: u32, y: u32, z: u32| {
        zorder::index_of([x as u8, y as u8, z as u8])
    });
    if let Some(tok) = zorder_bmi2() {
        batch!("batch/zorder_bmi2_u8", out, |x: u32, y: u32, z: u32| {
            zorder::bmi2::index_of([x as u8, y as u8, z as u8], tok)
        });
        batch!(
            "batch/zorder_bmi2_u16_u64",
            out64,
            |x: u32, y: u32, z: u32| zorder::bmi2::index_of([x as u16, y as u16, z as u16], tok)
        );
    }
    batch!("batch/morton_encoding_u8", out, |x: u32, y: u32, z: u32| {
        morton_encoding::morton_encode([x as u8, y as u8, z as u8])
    });
    g.finish();
}

fn encode3_u64(c: &mut Criterion) {
    let d = data(21);
    let mut out = vec![0u64; N];
    let mut g = c.benchmark_group("encode3_u64");
    g.throughput(Throughput::Elements(N as u64));
    let (xs, ys, zs) = (&d.xs, &d.ys, &d.zs);
    macro_rules! scalar {
        ($name:expr, $f:expr) => {
            g.bench_function($name, |b| {
                b.iter(|| {
                    for (((o, &x), &y), &z) in out.iter_mut().zip(xs).zip(ys).zip(zs) {
                        *o = $f(black_box(x), black_box(y), black_box(z));
                    }
                    black_box(&mut out);
                })
            });
        };
    }
    macro_rules! batch {
        ($name:expr, $f:expr) => {
            g.bench_function($name, |b| {
                b.iter(|| {
                    for (((o, &x), &y), &z) in out.iter_mut().zip(xs).zip(ys).zip(zs) {
                        *o = $f(x, y, z);
                    }
                    black_box(&mut out);
                })
            });
        };
    }
    scalar!("scalar/morton", morton::encode3_u64);
    scalar!("scalar/morton_magic", morton::magic::encode3_u64);
    scalar!("scalar/zorder_u16", |x: u32, y: u32, z: u32| {
        zorder::index_of([x as u16, y as u16, z as u16])
    });
    if let Some(tok) = zorder_bmi2() {
        scalar!("scalar/zorder_bmi2_u16", |x: u32, y: u32, z: u32| {
            zorder::bmi2::index_of([x as u16, y as u16, z as u16], tok)
        });
    }
    scalar!("scalar/morton_encoding_u16", |x: u32, y: u32, z: u32| {
        morton_encoding::morton_encode([x as u16, y as u16, z as u16])
    });
    for path in Path::available() {
        g.bench_with_input(
            BenchmarkId::new("batch/morton", format!("{path:?}")),
            &path,
            |b, &p| {
                b.iter(|| batch::encode3_u64_soa_with(p, xs, ys, zs, black_box(&mut out)).unwrap())
            },
        );
    }
    g.bench_function("batch/morton_best", |b| {
        b.iter(|| batch::encode3_u64_soa(xs, ys, zs, black_box(&mut out)).unwrap())
    });
    batch!("batch/zorder_u16", |x: u32, y: u32, z: u32| {
        zorder::index_of([x as u16, y as u16, z as u16])
    });
    if let Some(tok) = zorder_bmi2() {
        batch!("batch/zorder_bmi2_u16", |x: u32, y: u32, z: u32| {
            zorder::bmi2::index_of([x as u16, y as u16, z as u16], tok)
        });
    }
    batch!("batch/morton_encoding_u16", |x: u32, y: u32, z: u32| {
        morton_encoding::morton_encode([x as u16, y as u16, z as u16])
    });
    g.finish();
}

fn encode2(c: &mut Criterion) {
    for (name, bits) in [("encode2_u32", 16u32), ("encode2_u64", 32)] {
        let d = data(bits);
        let mut out32 = vec![0u32; N];
        let mut out64 = vec![0u64; N];
        let mut g = c.benchmark_group(name);
        g.throughput(Throughput::Elements(N as u64));
        let (xs, ys) = (&d.xs, &d.ys);
        macro_rules! scalar {
            ($label:expr, $out:ident, $f:expr) => {
                g.bench_function($label, |b| {
                    b.iter(|| {
                        for ((o, &x), &y) in $out.iter_mut().zip(xs).zip(ys) {
                            *o = $f(black_box(x), black_box(y));
                        }
                        black_box(&mut $out);
                    })
                });
            };
        }
        if bits == 16 {
            scalar!("scalar/morton", out32, morton::encode2_u32);
            scalar!("scalar/zorder", out32, |x: u32, y: u32| zorder::index_of([
                x as u16, y as u16
            ]));
            if let Some(tok) = zorder_bmi2() {
                scalar!("scalar/zorder_bmi2", out32, |x: u32, y: u32| {
                    zorder::bmi2::index_of([x as u16, y as u16], tok)
                });
            }
            scalar!("scalar/morton_encoding", out32, |x: u32, y: u32| {
                morton_encoding::morton_encode([x as u16, y as u16])
            });
            for path in Path::available() {
                g.bench_with_input(
                    BenchmarkId::new("batch/morton", format!("{path:?}")),
                    &path,
                    |b, &p| {
                        b.iter(|| {
                            batch::encode2_u32_soa_with(p, xs, ys, black_box(&mut out32)).unwrap()
                        })
                    },
                );
            }
            g.bench_function("batch/zorder", |b| {
                b.iter(|| {
                    for ((o, &x), &y) in out32.iter_mut().zip(xs).zip(ys) {
                        *o = zorder::index_of([x as u16, y as u16]);
                    }
                    black_box(&mut out32);
                })
            });
        } else {
            scalar!("scalar/morton", out64, morton::encode2_u64);
            scalar!("scalar/zorder", out64, |x: u32, y: u32| zorder::index_of([
                x, y
            ]));
            if let Some(tok) = zorder_bmi2() {
                scalar!("scalar/zorder_bmi2", out64, |x: u32, y: u32| {
                    zorder::bmi2::index_of([x, y], tok)
                });
            }
            scalar!("scalar/morton_encoding", out64, |x: u32, y: u32| {
                morton_encoding::morton_encode([x, y])
            });
            for path in Path::available() {
                g.bench_with_input(
                    BenchmarkId::new("batch/morton", format!("{path:?}")),
                    &path,
                    |b, &p| {
                        b.iter(|| {
                            batch::encode2_u64_soa_with(p, xs, ys, black_box(&mut out64)).unwrap()
                        })
                    },
                );
            }
            g.bench_function("batch/zorder", |b| {
                b.iter(|| {
                    for ((o, &x), &y) in out64.iter_mut().zip(xs).zip(ys) {
                        *o = zorder::index_of([x, y]);
                    }
                    black_box(&mut out64);
                })
            });
        }
        g.finish();
    }
}

fn decode(c: &mut Criterion) {
    let d = data(32);
    let (mut a, mut b2, mut c3) = (vec![0u32; N], vec![0u32; N], vec![0u32; N]);
    let mut acc = vec![[0u32; 3]; N];
    let mut acc2 = vec![[0u32; 2]; N];

    let mut g = c.benchmark_group("decode3_u32");
    g.throughput(Throughput::Elements(N as u64));
    let k32: Vec<u32> = d.k32.iter().map(|k| k & 0x3fff_ffff).collect();
    g.bench_function("scalar/morton", |b| {
        b.iter(|| {
            for (o, &k) in acc.iter_mut().zip(&k32) {
                *o = morton::decode3_u32(black_box(k));
            }
            black_box(&mut acc);
        })
    });
    g.bench_function("scalar/zorder_u8", |b| {
        b.iter(|| {
            for (o, &k) in acc.iter_mut().zip(&k32) {
                let [x, y, z]: [u8; 3] = zorder::coord_of(black_box(k & 0xff_ffff));
                *o = [x as u32, y as u32, z as u32];
            }
            black_box(&mut acc);
        })
    });
    if let Some(tok) = zorder_bmi2() {
        g.bench_function("scalar/zorder_bmi2_u8", |b| {
            b.iter(|| {
                for (o, &k) in acc.iter_mut().zip(&k32) {
                    let [x, y, z]: [u8; 3] = zorder::bmi2::coord_of(black_box(k & 0xff_ffff), tok);
                    *o = [x as u32, y as u32, z as u32];
                }
                black_box(&mut acc);
            })
        });
    }
    g.bench_function("scalar/morton_encoding_u8", |b| {
        b.iter(|| {
            for (o, &k) in acc.iter_mut().zip(&k32) {
                let [x, y, z]: [u8; 3] = morton_encoding::morton_decode(black_box(k & 0xff_ffff));
                *o = [x as u32, y as u32, z as u32];
            }
            black_box(&mut acc);
        })
    });
    for path in Path::available() {
        g.bench_with_input(
            BenchmarkId::new("batch/morton", format!("{path:?}")),
            &path,
            |bn, &p| {
                bn.iter(|| {
                    batch::decode3_u32_soa_with(p, &k32, &mut a, &mut b2, black_box(&mut c3))
                        .unwrap()
                })
            },
        );
    }
    g.bench_function("batch/morton_best_aos", |bn| {
        bn.iter(|| batch::decode3_u32_aos(&k32, black_box(&mut acc)).unwrap())
    });
    if let Some(tok) = zorder_bmi2() {
        g.bench_function("batch/zorder_bmi2_u8", |bn| {
            bn.iter(|| {
                for (o, &k) in acc.iter_mut().zip(&k32) {
                    let [x, y, z]: [u8; 3] = zorder::bmi2::coord_of(k & 0xff_ffff, tok);
                    *o = [x as u32, y as u32, z as u32];
                }
                black_box(&mut acc);
            })
        });
    }
    g.finish();

    let mut g = c.benchmark_group("decode3_u64");
    g.throughput(Throughput::Elements(N as u64));
    let k64: Vec<u64> = d.k64.iter().map(|k| k & !(1 << 63)).collect();
    g.bench_function("scalar/morton", |b| {
        b.iter(|| {
            for (o, &k) in acc.iter_mut().zip(&k64) {
                *o = morton::decode3_u64(black_box(k));
            }
            black_box(&mut acc);
        })
    });
    g.bench_function("scalar/zorder_u16", |b| {
        b.iter(|| {
            for (o, &k) in acc.iter_mut().zip(&k64) {
                let [x, y, z]: [u16; 3] = zorder::coord_of(black_box(k & 0xffff_ffff_ffff));
                *o = [x as u32, y as u32, z as u32];
            }
            black_box(&mut acc);
        })
    });
    if let Some(tok) = zorder_bmi2() {
        g.bench_function("scalar/zorder_bmi2_u16", |b| {
            b.iter(|| {
                for (o, &k) in acc.iter_mut().zip(&k64) {
                    let [x, y, z]: [u16; 3] =
                        zorder::bmi2::coord_of(black_box(k & 0xffff_ffff_ffff), tok);
                    *o = [x as u32, y as u32, z as u32];
                }
                black_box(&mut acc);
            })
        });
    }
    g.bench_function("scalar/morton_encoding_u16", |b| {
        b.iter(|| {
            for (o, &k) in acc.iter_mut().zip(&k64) {
                let [x, y, z]: [u16; 3] =
                    morton_encoding::morton_decode(black_box(k & 0xffff_ffff_ffff));
                *o = [x as u32, y as u32, z as u32];
            }
            black_box(&mut acc);
        })
    });
    for path in Path::available() {
        g.bench_with_input(
            BenchmarkId::new("batch/morton", format!("{path:?}")),
            &path,
            |bn, &p| {
                bn.iter(|| {
                    batch::decode3_u64_soa_with(p, &k64, &mut a, &mut b2, black_box(&mut c3))
                        .unwrap()
                })
            },
        );
    }
    g.finish();

    for (name, is64) in [("decode2_u32", false), ("decode2_u64", true)] {
        let mut g = c.benchmark_group(name);
        g.throughput(Throughput::Elements(N as u64));
        if is64 {
            g.bench_function("scalar/morton", |b| {
                b.iter(|| {
                    for (o, &k) in acc2.iter_mut().zip(&d.k64) {
                        *o = morton::decode2_u64(black_box(k));
                    }
                    black_box(&mut acc2);
                })
            });
            g.bench_function("scalar/zorder", |b| {
                b.iter(|| {
                    for (o, &k) in acc2.iter_mut().zip(&d.k64) {
                        *o = zorder::coord_of(black_box(k));
                    }
                    black_box(&mut acc2);
                })
            });
            if let Some(tok) = zorder_bmi2() {
                g.bench_function("scalar/zorder_bmi2", |b| {
                    b.iter(|| {
                        for (o, &k) in acc2.iter_mut().zip(&d.k64) {
                            *o = zorder::bmi2::coord_of(black_box(k), tok);
                        }
                        black_box(&mut acc2);
                    })
                });
            }
            for path in Path::available() {
                g.bench_with_input(
                    BenchmarkId::new("batch/morton", format!("{path:?}")),
                    &path,
                    |bn, &p| {
                        bn.iter(|| {
                            batch::decode2_u64_soa_with(p, &d.k64, &mut a, black_box(&mut b2))
                                .unwrap()
                        })
                    },
                );
            }
        } else {
            g.bench_function("scalar/morton", |b| {
                b.iter(|| {
                    for (o, &k) in acc2.iter_mut().zip(&d.k32) {
                        *o = morton::decode2_u32(black_box(k));
                    }
                    black_box(&mut acc2);
                })
            });
            g.bench_function("scalar/zorder", |b| {
                b.iter(|| {
                    for (o, &k) in acc2.iter_mut().zip(&d.k32) {
                        let [x, y]: [u16; 2] = zorder::coord_of(black_box(k));
                        *o = [x as u32, y as u32];
                    }
                    black_box(&mut acc2);
                })
            });
            if let Some(tok) = zorder_bmi2() {
                g.bench_function("scalar/zorder_bmi2", |b| {
                    b.iter(|| {
                        for (o, &k) in acc2.iter_mut().zip(&d.k32) {
                            let [x, y]: [u16; 2] = zorder::bmi2::coord_of(black_box(k), tok);
                            *o = [x as u32, y as u32];
                        }
                        black_box(&mut acc2);
                    })
                });
            }
            for path in Path::available() {
                g.bench_with_input(
                    BenchmarkId::new("batch/morton", format!("{path:?}")),
                    &path,
                    |bn, &p| {
                        bn.iter(|| {
                            batch::decode2_u32_soa_with(p, &d.k32, &mut a, black_box(&mut b2))
                                .unwrap()
                        })
                    },
                );
            }
        }
        g.finish();
    }
}

fn hilbert3(c: &mut Criterion) {
    let d = data(10);
    let (xs, ys, zs) = (&d.xs, &d.ys, &d.zs);
    let mut out = vec![0u32; N];
    let mut out64 = vec![0u64; N];
    let mut g = c.benchmark_group("hilbert3");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("encode_u32/scalar/morton", |b| {
        b.iter(|| {
            for (((o, &x), &y), &z) in out.iter_mut().zip(xs).zip(ys).zip(zs) {
                *o = hilbert::encode3_u32(black_box(x), black_box(y), black_box(z));
            }
            black_box(&mut out);
        })
    });
    g.bench_function("encode_u32/batch/morton_best", |b| {
        b.iter(|| hilbert::encode3_u32_soa(xs, ys, zs, black_box(&mut out)).unwrap())
    });
    g.bench_function("encode_u64/scalar/morton", |b| {
        b.iter(|| {
            for (((o, &x), &y), &z) in out64.iter_mut().zip(xs).zip(ys).zip(zs) {
                *o = hilbert::encode3_u64(black_box(x), black_box(y), black_box(z));
            }
            black_box(&mut out64);
        })
    });
    g.bench_function("encode_u64/batch/morton_best", |b| {
        b.iter(|| hilbert::encode3_u64_soa(xs, ys, zs, black_box(&mut out64)).unwrap())
    });
    // lindel: 10-bit values in u16 coordinates (its key is u64; it skips leading zero bits).
    g.bench_function("encode_u16/scalar/lindel", |b| {
        b.iter(|| {
            for (((o, &x), &y), &z) in out64.iter_mut().zip(xs).zip(ys).zip(zs) {
                *o = lindel::hilbert_encode([
                    black_box(x) as u16,
                    black_box(y) as u16,
                    black_box(z) as u16,
                ]);
            }
            black_box(&mut out64);
        })
    });
    g.bench_function("encode_u8/scalar/lindel", |b| {
        b.iter(|| {
            for (((o, &x), &y), &z) in out.iter_mut().zip(xs).zip(ys).zip(zs) {
                *o = lindel::hilbert_encode([
                    black_box(x) as u8,
                    black_box(y) as u8,
                    black_box(z) as u8,
                ]);
            }
            black_box(&mut out);
        })
    });
    let mut acc = vec![[0u32; 3]; N];
    let keys: Vec<u32> = d.k32.iter().map(|k| k & 0x3fff_ffff).collect();
    g.bench_function("decode_u32/scalar/morton", |b| {
        b.iter(|| {
            for (o, &k) in acc.iter_mut().zip(&keys) {
                *o = hilbert::decode3_u32(black_box(k));
            }
            black_box(&mut acc);
        })
    });
    g.bench_function("decode_u16/scalar/lindel", |b| {
        b.iter(|| {
            for (o, &k) in acc.iter_mut().zip(&keys) {
                let [x, y, z]: [u16; 3] = lindel::hilbert_decode(black_box(k as u64));
                *o = [x as u32, y as u32, z as u32];
            }
            black_box(&mut acc);
        })
    });
    // The Morton code of the same points, for the price ratio.
    g.bench_function("morton_encode_u32/batch/morton_best", |b| {
        b.iter(|| batch::encode3_u32_soa(xs, ys, zs, black_box(&mut out)).unwrap())
    });
    g.finish();
}

criterion_group!(benches, encode3_u32, encode3_u64, encode2, decode, hilbert3);
criterion_main!(benches);
