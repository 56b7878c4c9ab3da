//! ns per key for every Morton width and direction against two in-group baselines written
//! out here, the methods the peers use (libmorton's magic bits and BMI2, zorder's BMI2):
//!
//! - `base/magic`: a plain magic-bits loop (shift-or-mask ladders), which the compiler may
//!   vectorise for whatever the build targets;
//! - `base/bmi2`: a `pdep`/`pext` loop compiled inside one `#[target_feature(enable =
//!   "bmi2")]` function (what a peer built with `-march=native` runs), when the CPU has BMI2.
//!
//! and ours: `batch/best` (the slice functions on `Path::best`), `batch/<Path>` (each path
//! the CPU has, forced), `loop/inline` (the scalar `morton::encode3_u32` and friends in a
//! plain loop, as a user writes it) and `loop/per_key` (`morton::per_key::*`, the per-key
//! run-time dispatched functions, in the same loop).
//!
//! Every variant runs over the same inputs (16 384 keys, struct-of-arrays, cache-resident),
//! `PASSES` passes per sample; the variants are interleaved within each round and the table
//! gives the median of `ROUNDS` rounds, and each of ours as a ratio to the faster baseline
//! measured in the same run. Timings on a shared machine drift; ratios within one run hold
//! better.
//!
//! Run: `cargo bench -p morton --bench baselines` (prints a markdown table); for the build
//! many users make, `RUSTFLAGS="-C target-cpu=native" CARGO_TARGET_DIR=target-native cargo
//! bench -p morton --bench baselines`. Optional arguments: a filter on the group name
//! (`enc3_64`), `--rounds N`, `--passes N`.

use std::hint::black_box;
use std::time::Instant;

use morton::{Path, batch};

const N: usize = 16 * 1024;

/// Independent magic-bits interleaving, written for this bench.
mod magic {
    #[inline(always)]
    pub fn spread2_32(v: u32) -> u32 {
        let mut v = v & 0xffff;
        v = (v ^ (v << 8)) & 0x00ff_00ff;
        v = (v ^ (v << 4)) & 0x0f0f_0f0f;
        v = (v ^ (v << 2)) & 0x3333_3333;
        (v ^ (v << 1)) & 0x5555_5555
    }
    #[inline(always)]
    pub fn squeeze2_32(v: u32) -> u32 {
        let mut v = v & 0x5555_5555;
        v = (v ^ (v >> 1)) & 0x3333_3333;
        v = (v ^ (v >> 2)) & 0x0f0f_0f0f;
        v = (v ^ (v >> 4)) & 0x00ff_00ff;
        (v ^ (v >> 8)) & 0xffff
    }
    #[inline(always)]
    pub fn spread3_32(v: u32) -> u32 {
        let mut v = v & 0x3ff;
        v = (v ^ (v << 16)) & 0xff00_00ff;
        v = (v ^ (v << 8)) & 0x0300_f00f;
        v = (v ^ (v << 4)) & 0x030c_30c3;
        (v ^ (v << 2)) & 0x0924_9249
    }
    #[inline(always)]
    pub fn squeeze3_32(v: u32) -> u32 {
        let mut v = v & 0x0924_9249;
        v = (v ^ (v >> 2)) & 0x030c_30c3;
        v = (v ^ (v >> 4)) & 0x0300_f00f;
        v = (v ^ (v >> 8)) & 0xff00_00ff;
        (v ^ (v >> 16)) & 0x3ff
    }
    #[inline(always)]
    pub fn spread2_64(v: u32) -> u64 {
        let mut v = v as u64;
        v = (v ^ (v << 16)) & 0x0000_ffff_0000_ffff;
        v = (v ^ (v << 8)) & 0x00ff_00ff_00ff_00ff;
        v = (v ^ (v << 4)) & 0x0f0f_0f0f_0f0f_0f0f;
        v = (v ^ (v << 2)) & 0x3333_3333_3333_3333;
        (v ^ (v << 1)) & 0x5555_5555_5555_5555
    }
    #[inline(always)]
    pub fn squeeze2_64(v: u64) -> u32 {
        let mut v = v & 0x5555_5555_5555_5555;
        v = (v ^ (v >> 1)) & 0x3333_3333_3333_3333;
        v = (v ^ (v >> 2)) & 0x0f0f_0f0f_0f0f_0f0f;
        v = (v ^ (v >> 4)) & 0x00ff_00ff_00ff_00ff;
        v = (v ^ (v >> 8)) & 0x0000_ffff_0000_ffff;
        (v ^ (v >> 16)) as u32
    }
    #[inline(always)]
    pub fn spread3_64(v: u32) -> u64 {
        let mut v = (v & 0x1f_ffff) as u64;
        v = (v ^ (v << 32)) & 0x001f_0000_0000_ffff;
        v = (v ^ (v << 16)) & 0x001f_0000_ff00_00ff;
        v = (v ^ (v << 8)) & 0x100f_00f0_0f00_f00f;
        v = (v ^ (v << 4)) & 0x10c3_0c30_c30c_30c3;
        (v ^ (v << 2)) & 0x1249_2492_4924_9249
    }
    #[inline(always)]
    pub fn squeeze3_64(v: u64) -> u32 {
        let mut v = v & 0x1249_2492_4924_9249;
        v = (v ^ (v >> 2)) & 0x10c3_0c30_c30c_30c3;
        v = (v ^ (v >> 4)) & 0x100f_00f0_0f00_f00f;
        v = (v ^ (v >> 8)) & 0x001f_0000_ff00_00ff;
        v = (v ^ (v >> 16)) & 0x001f_0000_0000_ffff;
        ((v ^ (v >> 32)) & 0x1f_ffff) as u32
    }
}

/// `pdep`/`pext` loops, each one `#[target_feature]` function around the whole loop.
#[cfg(target_arch = "x86_64")]
mod bmi2 {
    use core::arch::x86_64::{_pdep_u32, _pdep_u64, _pext_u32, _pext_u64};

    const X2: u64 = 0x5555_5555_5555_5555;
    const X3: u64 = 0x1249_2492_4924_9249;

    #[target_feature(enable = "bmi2")]
    pub fn enc2_32(xs: &[u32], ys: &[u32], out: &mut [u32]) {
        for ((o, &x), &y) in out.iter_mut().zip(xs).zip(ys) {
            *o = _pdep_u32(x, X2 as u32) | _pdep_u32(y, (X2 << 1) as u32);
        }
    }
    #[target_feature(enable = "bmi2")]
    pub fn enc2_64(xs: &[u32], ys: &[u32], out: &mut [u64]) {
        for ((o, &x), &y) in out.iter_mut().zip(xs).zip(ys) {
            *o = _pdep_u64(x as u64, X2) | _pdep_u64(y as u64, X2 << 1);
        }
    }
    #[target_feature(enable = "bmi2")]
    pub fn enc3_32(xs: &[u32], ys: &[u32], zs: &[u32], out: &mut [u32]) {
        let m = X3 as u32 & 0x3fff_ffff;
        for (((o, &x), &y), &z) in out.iter_mut().zip(xs).zip(ys).zip(zs) {
            *o = _pdep_u32(x, m) | _pdep_u32(y, m << 1) | _pdep_u32(z, m << 2);
        }
    }
    #[target_feature(enable = "bmi2")]
    pub fn enc3_64(xs: &[u32], ys: &[u32], zs: &[u32], out: &mut [u64]) {
        for (((o, &x), &y), &z) in out.iter_mut().zip(xs).zip(ys).zip(zs) {
            *o = _pdep_u64(x as u64, X3)
                | _pdep_u64(y as u64, X3 << 1)
                | _pdep_u64(z as u64, X3 << 2);
        }
    }
    #[target_feature(enable = "bmi2")]
    pub fn dec2_32(codes: &[u32], xs: &mut [u32], ys: &mut [u32]) {
        for ((&c, x), y) in codes.iter().zip(xs.iter_mut()).zip(ys.iter_mut()) {
            *x = _pext_u32(c, X2 as u32);
            *y = _pext_u32(c, (X2 << 1) as u32);
        }
    }
    #[target_feature(enable = "bmi2")]
    pub fn dec2_64(codes: &[u64], xs: &mut [u32], ys: &mut [u32]) {
        for ((&c, x), y) in codes.iter().zip(xs.iter_mut()).zip(ys.iter_mut()) {
            *x = _pext_u64(c, X2) as u32;
            *y = _pext_u64(c, X2 << 1) as u32;
        }
    }
    #[target_feature(enable = "bmi2")]
    pub fn dec3_32(codes: &[u32], xs: &mut [u32], ys: &mut [u32], zs: &mut [u32]) {
        let m = X3 as u32 & 0x3fff_ffff;
        for (((&c, x), y), z) in codes
            .iter()
            .zip(xs.iter_mut())
            .zip(ys.iter_mut())
            .zip(zs.iter_mut())
        {
            *x = _pext_u32(c, m);
            *y = _pext_u32(c, m << 1);
            *z = _pext_u32(c, m << 2);
        }
    }
    #[target_feature(enable = "bmi2")]
    pub fn dec3_64(codes: &[u64], xs: &mut [u32], ys: &mut [u32], zs: &mut [u32]) {
        for (((&c, x), y), z) in codes
            .iter()
            .zip(xs.iter_mut())
            .zip(ys.iter_mut())
            .zip(zs.iter_mut())
        {
            *x = _pext_u64(c, X3) as u32;
            *y = _pext_u64(c, X3 << 1) as u32;
            *z = _pext_u64(c, X3 << 2) as u32;
        }
    }
}

#[cfg(target_arch = "x86_64")]
fn has_bmi2() -> bool {
    std::is_x86_feature_detected!("bmi2")
}
#[cfg(not(target_arch = "x86_64"))]
fn has_bmi2() -> bool {
    false
}

/// One timed variant: a name and a closure that runs one pass over the inputs.
type Variant<'a> = (String, Box<dyn FnMut() + 'a>);

/// The inputs shared by every group.
struct Inputs {
    xs: [Vec<u32>; 4],
    ys: [Vec<u32>; 4],
    zs: [Vec<u32>; 4],
    k32: [Vec<u32>; 2],
    k64: [Vec<u64>; 2],
}

fn inputs() -> Inputs {
    let mut rng = testkit::Rng::new(0x2545_f491_4f6c_dd1d);
    // Coordinates masked to 16, 32, 10 and 21 bits; codes masked to their used bits.
    let widths = [16u32, 32, 10, 21];
    let mut lanes = || {
        widths.map(|b| {
            (0..N)
                .map(|_| rng.next_u32() & (u32::MAX >> (32 - b)))
                .collect::<Vec<u32>>()
        })
    };
    let (xs, ys, zs) = (lanes(), lanes(), lanes());
    let k32 = [
        rng.words(N),
        (0..N).map(|_| rng.next_u32() & 0x3fff_ffff).collect(),
    ];
    let k64 = [
        (0..N).map(|_| rng.next_u64()).collect(),
        (0..N).map(|_| rng.next_u64() >> 1).collect(),
    ];
    Inputs {
        xs,
        ys,
        zs,
        k32,
        k64,
    }
}

fn time(f: &mut dyn FnMut(), passes: usize) -> f64 {
    let t = Instant::now();
    for _ in 0..passes {
        f();
    }
    t.elapsed().as_secs_f64() * 1e9 / (passes * N) as f64
}

/// Encoders: `(name, coordinate width index, output type, batch fn, batch _with fn, inline
/// scalar, dispatched scalar, magic baseline, bmi2 baseline, axes)`.
macro_rules! enc_group {
    ($groups:ident, $name:expr, $w:expr, $out:ty, $batch:ident, $with:ident, $top:path,
     $disp:path, $magic:expr, $bmi2:ident, ($($ax:ident),+)) => {{
        let inp: &'static Inputs = &INPUTS;
        let ($($ax),+) = ($(&inp.$ax[$w][..]),+);
        let mut v: Vec<Variant> = Vec::new();
        let mut o = vec![0 as $out; N];
        v.push(("base/magic".into(), Box::new(move || {
            let ($($ax),+) = ($(black_box($ax)),+);
            enc_loop!(o, ($($ax),+), $magic);
            black_box(&mut o);
        })));
        #[cfg(target_arch = "x86_64")]
        if has_bmi2() {
            let mut o = vec![0 as $out; N];
            v.push(("base/bmi2".into(), Box::new(move || {
                // SAFETY: the CPU has BMI2 (checked above).
                unsafe { bmi2::$bmi2($(black_box($ax)),+, &mut o) };
                black_box(&mut o);
            })));
        }
        let mut o = vec![0 as $out; N];
        v.push(("batch/best".into(), Box::new(move || {
            batch::$batch($(black_box($ax)),+, &mut o).unwrap();
            black_box(&mut o);
        })));
        for p in Path::available() {
            let mut o = vec![0 as $out; N];
            v.push((format!("batch/{p:?}"), Box::new(move || {
                batch::$with(p, $(black_box($ax)),+, &mut o).unwrap();
                black_box(&mut o);
            })));
        }
        let mut o = vec![0 as $out; N];
        v.push(("loop/inline".into(), Box::new(move || {
            let ($($ax),+) = ($(black_box($ax)),+);
            enc_loop!(o, ($($ax),+), $top);
            black_box(&mut o);
        })));
        let mut o = vec![0 as $out; N];
        v.push(("loop/per_key".into(), Box::new(move || {
            let ($($ax),+) = ($(black_box($ax)),+);
            enc_loop!(o, ($($ax),+), $disp);
            black_box(&mut o);
        })));
        $groups.push(($name, v));
    }};
}

macro_rules! enc_loop {
    ($o:ident, ($x:ident, $y:ident), $f:expr) => {
        for ((r, &x), &y) in $o.iter_mut().zip($x).zip($y) {
            *r = ($f)(x, y);
        }
    };
    ($o:ident, ($x:ident, $y:ident, $z:ident), $f:expr) => {
        for (((r, &x), &y), &z) in $o.iter_mut().zip($x).zip($y).zip($z) {
            *r = ($f)(x, y, z);
        }
    };
}

macro_rules! dec_loop {
    ($k:ident, ($x:ident, $y:ident), $f:expr) => {
        for ((&c, x), y) in $k.iter().zip($x.iter_mut()).zip($y.iter_mut()) {
            [*x, *y] = ($f)(c);
        }
    };
    ($k:ident, ($x:ident, $y:ident, $z:ident), $f:expr) => {
        for (((&c, x), y), z) in $k
            .iter()
            .zip($x.iter_mut())
            .zip($y.iter_mut())
            .zip($z.iter_mut())
        {
            [*x, *y, *z] = ($f)(c);
        }
    };
}

/// Decoders, as [`enc_group`] with the keys instead of the coordinates.
macro_rules! dec_group {
    ($groups:ident, $name:expr, $keys:expr, $batch:ident, $with:ident, $top:path,
     $disp:path, $magic:expr, $bmi2:ident, ($($ax:ident),+)) => {{
        let inp: &'static Inputs = &INPUTS;
        let k = &$keys(inp)[..];
        let mut v: Vec<Variant> = Vec::new();
        let ($(mut $ax),+) = ($({ let $ax = vec![0u32; N]; $ax }),+);
        v.push(("base/magic".into(), Box::new(move || {
            let k = black_box(k);
            dec_loop!(k, ($($ax),+), $magic);
            black_box(($(&mut $ax),+));
        })));
        #[cfg(target_arch = "x86_64")]
        if has_bmi2() {
            let ($(mut $ax),+) = ($({ let $ax = vec![0u32; N]; $ax }),+);
            v.push(("base/bmi2".into(), Box::new(move || {
                // SAFETY: the CPU has BMI2 (checked above).
                unsafe { bmi2::$bmi2(black_box(k), $(&mut $ax),+) };
                black_box(($(&mut $ax),+));
            })));
        }
        let ($(mut $ax),+) = ($({ let $ax = vec![0u32; N]; $ax }),+);
        v.push(("batch/best".into(), Box::new(move || {
            batch::$batch(black_box(k), $(&mut $ax),+).unwrap();
            black_box(($(&mut $ax),+));
        })));
        for p in Path::available() {
            let ($(mut $ax),+) = ($({ let $ax = vec![0u32; N]; $ax }),+);
            v.push((format!("batch/{p:?}"), Box::new(move || {
                batch::$with(p, black_box(k), $(&mut $ax),+).unwrap();
                black_box(($(&mut $ax),+));
            })));
        }
        let ($(mut $ax),+) = ($({ let $ax = vec![0u32; N]; $ax }),+);
        v.push(("loop/inline".into(), Box::new(move || {
            let k = black_box(k);
            dec_loop!(k, ($($ax),+), $top);
            black_box(($(&mut $ax),+));
        })));
        let ($(mut $ax),+) = ($({ let $ax = vec![0u32; N]; $ax }),+);
        v.push(("loop/per_key".into(), Box::new(move || {
            let k = black_box(k);
            dec_loop!(k, ($($ax),+), $disp);
            black_box(($(&mut $ax),+));
        })));
        $groups.push(($name, v));
    }};
}

static INPUTS: std::sync::LazyLock<Inputs> = std::sync::LazyLock::new(inputs);

fn main() {
    let mut args = std::env::args().skip(1);
    let (mut filter, mut rounds, mut passes) = (String::new(), 9usize, 256usize);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--rounds" => rounds = args.next().and_then(|v| v.parse().ok()).unwrap_or(rounds),
            "--passes" => passes = args.next().and_then(|v| v.parse().ok()).unwrap_or(passes),
            "--bench" => {}
            f => filter = f.to_string(),
        }
    }
    let mut groups: Vec<(&str, Vec<Variant>)> = Vec::new();
    use magic as m;
    enc_group!(
        groups,
        "enc2_32",
        0,
        u32,
        encode2_u32_soa,
        encode2_u32_soa_with,
        morton::encode2_u32,
        morton::per_key::encode2_u32,
        |x, y| m::spread2_32(x) | (m::spread2_32(y) << 1),
        enc2_32,
        (xs, ys)
    );
    enc_group!(
        groups,
        "enc2_64",
        1,
        u64,
        encode2_u64_soa,
        encode2_u64_soa_with,
        morton::encode2_u64,
        morton::per_key::encode2_u64,
        |x, y| m::spread2_64(x) | (m::spread2_64(y) << 1),
        enc2_64,
        (xs, ys)
    );
    enc_group!(
        groups,
        "enc3_32",
        2,
        u32,
        encode3_u32_soa,
        encode3_u32_soa_with,
        morton::encode3_u32,
        morton::per_key::encode3_u32,
        |x, y, z| m::spread3_32(x) | (m::spread3_32(y) << 1) | (m::spread3_32(z) << 2),
        enc3_32,
        (xs, ys, zs)
    );
    enc_group!(
        groups,
        "enc3_64",
        3,
        u64,
        encode3_u64_soa,
        encode3_u64_soa_with,
        morton::encode3_u64,
        morton::per_key::encode3_u64,
        |x, y, z| m::spread3_64(x) | (m::spread3_64(y) << 1) | (m::spread3_64(z) << 2),
        enc3_64,
        (xs, ys, zs)
    );
    dec_group!(
        groups,
        "dec2_32",
        |i: &'static Inputs| &i.k32[0],
        decode2_u32_soa,
        decode2_u32_soa_with,
        morton::decode2_u32,
        morton::per_key::decode2_u32,
        |c: u32| [m::squeeze2_32(c), m::squeeze2_32(c >> 1)],
        dec2_32,
        (xs, ys)
    );
    dec_group!(
        groups,
        "dec2_64",
        |i: &'static Inputs| &i.k64[0],
        decode2_u64_soa,
        decode2_u64_soa_with,
        morton::decode2_u64,
        morton::per_key::decode2_u64,
        |c: u64| [m::squeeze2_64(c), m::squeeze2_64(c >> 1)],
        dec2_64,
        (xs, ys)
    );
    dec_group!(
        groups,
        "dec3_32",
        |i: &'static Inputs| &i.k32[1],
        decode3_u32_soa,
        decode3_u32_soa_with,
        morton::decode3_u32,
        morton::per_key::decode3_u32,
        |c: u32| [
            m::squeeze3_32(c),
            m::squeeze3_32(c >> 1),
            m::squeeze3_32(c >> 2)
        ],
        dec3_32,
        (xs, ys, zs)
    );
    dec_group!(
        groups,
        "dec3_64",
        |i: &'static Inputs| &i.k64[1],
        decode3_u64_soa,
        decode3_u64_soa_with,
        morton::decode3_u64,
        morton::per_key::decode3_u64,
        |c: u64| [
            m::squeeze3_64(c),
            m::squeeze3_64(c >> 1),
            m::squeeze3_64(c >> 2)
        ],
        dec3_64,
        (xs, ys, zs)
    );
    groups.retain(|(name, _)| name.contains(filter.as_str()));

    // Interleaved: every variant of every group once per round, then the medians.
    let mut samples: Vec<Vec<Vec<f64>>> = groups
        .iter()
        .map(|(_, v)| vec![Vec::new(); v.len()])
        .collect();
    for (g, (_, vs)) in groups.iter_mut().enumerate() {
        for (i, (_, f)) in vs.iter_mut().enumerate() {
            time(f.as_mut(), passes / 8 + 1); // warm-up
            let _ = (g, i);
        }
    }
    for _ in 0..rounds {
        for (g, (_, vs)) in groups.iter_mut().enumerate() {
            for (i, (_, f)) in vs.iter_mut().enumerate() {
                samples[g][i].push(time(f.as_mut(), passes));
            }
        }
    }
    let median = |s: &mut Vec<f64>| {
        s.sort_by(f64::total_cmp);
        s[s.len() / 2]
    };
    println!(
        "{N} keys x {passes} passes, median of {rounds} interleaved rounds; ns per key \
         (ratio to the faster baseline)\n"
    );
    println!("| group | variant | ns/key | vs best baseline |\n|---|---|---|---|");
    for (g, (name, vs)) in groups.iter().enumerate() {
        let med: Vec<f64> = samples[g].iter_mut().map(median).collect();
        let base = vs
            .iter()
            .zip(&med)
            .filter(|((n, _), _)| n.starts_with("base/"))
            .map(|(_, &m)| m)
            .fold(f64::INFINITY, f64::min);
        for ((label, _), m) in vs.iter().zip(&med) {
            println!("| {name} | {label} | {m:.3} | {:.2} |", m / base);
        }
    }
}
