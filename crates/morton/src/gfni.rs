//! The [`crate::Path::Gfni`] kernels: Morton codes as byte moves plus one 8x8 bit matrix per
//! byte, in 512-bit registers by explicit intrinsics (so the vector width does not depend on
//! the build's tuning: `-C target-cpu=native` on Intel prefers 256-bit vectors for
//! auto-vectorised loops).
//!
//! Interleaving maps every 8 bits of a coordinate onto `D` whole bytes of the code (24 code
//! bits per coordinate byte in 3D, 16 in 2D), so each code byte depends on one byte per axis,
//! and which bits go where depends only on the code byte's *phase* (its index mod `D`).
//! `vpermb` puts the right coordinate byte under each code byte (or, decoding, gathers the
//! code bytes of one phase), and `gf2p8affineqb` applies an arbitrary 8x8 bit matrix to
//! every byte: one instruction moves all the bits that the magic-bits ladder moves in five
//! shift-or-mask steps.
//!
//! - Encoding 3D: one matrix per axis serves all three phases (each output bit belongs to
//!   the axis in exactly one phase), and the three axes are merged by bit-select on the
//!   code masks. 2D: the phases disagree, so each axis takes two masked affine steps.
//! - Decoding: the code bytes are transposed so that each 64-bit lane holds bytes of one
//!   phase and one coordinate byte (for 16 or 32 keys), one matrix per (axis, phase, lane)
//!   pulls out the axis's bits, an OR merges the phases, and `vpermb` transposes back.
//!
//! Needs AVX-512 F/BW/VL/DQ, VBMI (`vpermb`) and GFNI: Intel Ice Lake and later, AMD Zen 4
//! and later. Each kernel runs whole blocks of keys; a tail goes through the same block
//! code on a zero-padded copy.
//!
//! Uses `gf2p8affineqb` as a general 8x8 bit-matrix multiply per byte (as the Intel SDM
//! defines it), not for Galois-field arithmetic; the byte layouts and matrices are derived
//! here from this crate's bit layout by `const fn`s, so the tables follow the definition.

use core::arch::x86_64::{
    __m512i, _mm512_and_si512, _mm512_gf2p8affine_epi64_epi8, _mm512_loadu_si512,
    _mm512_mask_gf2p8affine_epi64_epi8, _mm512_maskz_gf2p8affine_epi64_epi8,
    _mm512_maskz_permutex2var_epi8, _mm512_maskz_permutexvar_epi8, _mm512_or_si512,
    _mm512_permutexvar_epi8, _mm512_set1_epi64, _mm512_storeu_si512, _mm512_ternarylogic_epi64,
};

/// A matrix with input bit `from` routed to output bit `to` added (`gf2p8affineqb` takes
/// output bit `i` from the parity of byte `7 - i` of the matrix ANDed with the input byte).
const fn route(m: u64, to: u32, from: u32) -> u64 {
    m | 1 << (8 * (7 - to) + from)
}

/// Encoding matrix for axis `a` of `d` in a code byte of phase `p`: output bit `k` of the
/// code byte is code bit `8p + k` of its `d`-byte group, which belongs to axis
/// `(8p + k) % d` and holds that axis's local bit `(8p + k) / d`.
const fn enc_matrix(d: u32, a: u32, p: u32) -> u64 {
    let mut m = 0;
    let mut k = 0;
    while k < 8 {
        let c = 8 * p + k;
        if c % d == a {
            m = route(m, k, c / d);
        }
        k += 1;
    }
    m
}

/// Decoding matrix for axis `a` of `d`: from a code byte of phase `p` serving coordinate
/// byte `b`, the axis's bits to their local positions, dropping bits at or above `bits`.
const fn dec_matrix(d: u32, a: u32, p: u32, b: u32, bits: u32) -> u64 {
    let mut m = 0;
    let mut k = 0;
    while k < 8 {
        let c = 8 * p + k;
        if c % d == a && 8 * b + c / d < bits {
            m = route(m, c / d, k);
        }
        k += 1;
    }
    m
}

/// `vpermb` indices for encoding: under code byte `j` of each `cb`-byte code, byte `j / d`
/// of the same key's u32 coordinate.
const fn enc_index(d: usize, cb: usize) -> [u8; 64] {
    let mut t = [0u8; 64];
    let mut n = 0;
    while n < 64 {
        t[n] = (4 * (n / cb) + (n % cb) / d) as u8;
        n += 1;
    }
    t
}

/// Decoding transpose for phase `p`: byte `b * k2 + key` takes code byte `d * b + p` of
/// `key` (of `k2` keys in two registers of `cb`-byte codes, for `nb` coordinate bytes).
/// Returns the `vpermt2b` indices and the mask of bytes that exist.
const fn dec_gather(d: usize, cb: usize, nb: usize, k2: usize, p: usize) -> ([u8; 64], u64) {
    let mut t = [0u8; 64];
    let mut keep = 0u64;
    let mut n = 0;
    while n < 64 {
        let (b, key) = (n / k2, n % k2);
        let j = d * b + p;
        if b < nb && j < cb {
            t[n] = (key * cb + j) as u8;
            keep |= 1 << n;
        }
        n += 1;
    }
    (t, keep)
}

/// Decoding transpose back, for output register `h` (16 keys of u32): byte `4 * key + bb`
/// takes transposed byte `bb * k2 + 16 h + key`; bytes `bb >= nb` are zero.
const fn dec_scatter(nb: usize, k2: usize, h: usize) -> ([u8; 64], u64) {
    let mut t = [0u8; 64];
    let mut keep = 0u64;
    let mut n = 0;
    while n < 64 {
        let (key, bb) = (16 * h + n / 4, n % 4);
        if bb < nb {
            t[n] = (bb * k2 + key) as u8;
            keep |= 1 << n;
        }
        n += 1;
    }
    (t, keep)
}

/// Per-lane decoding matrices for axis `a`, phase `p`: lane `l` holds coordinate byte
/// `8 l / k2`.
const fn dec_lanes(d: u32, a: u32, p: u32, nb: usize, k2: usize, bits: u32) -> [u64; 8] {
    let mut t = [0u64; 8];
    let mut l = 0;
    while l < 8 {
        let b = 8 * l / k2;
        if b < nb {
            t[l] = dec_matrix(d, a, p, b as u32, bits);
        }
        l += 1;
    }
    t
}

/// Bit-select `m ? a : b` (ternary-logic truth table 0xca over (m, a, b)).
const SELECT: i32 = 0xca;
/// Three-way OR.
const OR3: i32 = 0xfe;
/// Byte masks of the code bytes of phase 0 and 1 in 2D (even and odd bytes).
const EVEN: u64 = 0x5555_5555_5555_5555;
const ODD: u64 = !EVEN;

/// The instruction sets every kernel here needs; [`crate::Path::Gfni`] checks them.
macro_rules! gfni_fn {
    ($(#[$m:meta])* $v:vis unsafe fn $($rest:tt)*) => {
        $(#[$m])*
        #[inline]
        #[target_feature(enable = "avx512f,avx512bw,avx512vl,avx512dq,avx512vbmi,gfni")]
        $v unsafe fn $($rest)*
    };
    ($(#[$m:meta])* $v:vis fn $($rest:tt)*) => {
        $(#[$m])*
        #[inline(never)]
        #[target_feature(enable = "avx512f,avx512bw,avx512vl,avx512dq,avx512vbmi,gfni")]
        $v fn $($rest)*
    };
}

/// 64 bytes from `p`.
///
/// # Safety
/// `p` must point to 64 readable bytes.
#[inline(always)]
unsafe fn load<T>(p: *const T) -> __m512i {
    // SAFETY: forwarded; `loadu` has no alignment requirement.
    unsafe { _mm512_loadu_si512(p.cast()) }
}

/// 64 bytes to `p`.
///
/// # Safety
/// `p` must point to 64 writable bytes.
#[inline(always)]
unsafe fn store<T>(p: *mut T, v: __m512i) {
    // SAFETY: forwarded; `storeu` has no alignment requirement.
    unsafe { _mm512_storeu_si512(p.cast(), v) }
}

/// A constant table as a register.
#[inline(always)]
fn bytes(t: &[u8; 64]) -> __m512i {
    // SAFETY: 64 bytes.
    unsafe { load(t.as_ptr()) }
}

#[inline(always)]
fn qwords(t: &[u64; 8]) -> __m512i {
    // SAFETY: 64 bytes.
    unsafe { load(t.as_ptr()) }
}

/// `enc_index` for output register `h` of a block of 16 keys.
const fn enc_index_h(d: usize, cb: usize, h: usize) -> [u8; 64] {
    let mut t = enc_index(d, cb);
    let mut n = 0;
    while n < 64 {
        t[n] += (4 * h * (64 / cb)) as u8;
        n += 1;
    }
    t
}

const ENC3_32: [u8; 64] = enc_index_h(3, 4, 0);
const ENC3_64: [[u8; 64]; 2] = [enc_index_h(3, 8, 0), enc_index_h(3, 8, 1)];
const ENC2_32: [u8; 64] = enc_index_h(2, 4, 0);
const ENC2_64: [[u8; 64]; 2] = [enc_index_h(2, 8, 0), enc_index_h(2, 8, 1)];
/// One matrix per axis for 3D (the phases use disjoint output bits).
const ENC3_M: [u64; 3] = {
    let mut t = [0u64; 3];
    let mut a = 0;
    while a < 3 {
        t[a] = enc_matrix(3, a as u32, 0) | enc_matrix(3, a as u32, 1) | enc_matrix(3, a as u32, 2);
        a += 1;
    }
    t
};

gfni_fn! {
    /// One register of 3D codes from coordinates already under their code bytes.
    unsafe fn enc3_merge(vx: __m512i, vy: __m512i, vz: __m512i, mx: i64, my: i64, valid: i64) -> __m512i {
        let gx = _mm512_gf2p8affine_epi64_epi8::<0>(vx, _mm512_set1_epi64(ENC3_M[0] as i64));
        let gy = _mm512_gf2p8affine_epi64_epi8::<0>(vy, _mm512_set1_epi64(ENC3_M[1] as i64));
        let gz = _mm512_gf2p8affine_epi64_epi8::<0>(vz, _mm512_set1_epi64(ENC3_M[2] as i64));
        // Each axis's register is right on that axis's bits: select them by the code masks,
        // then clear the bits above the code (coordinate bits above its width land there).
        let yz = _mm512_ternarylogic_epi64::<SELECT>(_mm512_set1_epi64(my), gy, gz);
        let code = _mm512_ternarylogic_epi64::<SELECT>(_mm512_set1_epi64(mx), gx, yz);
        _mm512_and_si512(code, _mm512_set1_epi64(valid))
    }
}

gfni_fn! {
    /// One register of 2D codes: two masked affine steps per axis (one per phase).
    unsafe fn enc2_merge(vx: __m512i, vy: __m512i) -> __m512i {
        let m = |a: u32, p: u32| _mm512_set1_epi64(enc_matrix(2, a, p) as i64);
        let gx = _mm512_maskz_gf2p8affine_epi64_epi8::<0>(EVEN, vx, m(0, 0));
        let gx = _mm512_mask_gf2p8affine_epi64_epi8::<0>(gx, ODD, vx, m(0, 1));
        let gy = _mm512_maskz_gf2p8affine_epi64_epi8::<0>(EVEN, vy, m(1, 0));
        let gy = _mm512_mask_gf2p8affine_epi64_epi8::<0>(gy, ODD, vy, m(1, 1));
        _mm512_or_si512(gx, gy)
    }
}

gfni_fn! {
    /// 16 keys of 3D u32 codes.
    unsafe fn enc3_32_block(x: *const u32, y: *const u32, z: *const u32, out: *mut u32) {
        let idx = bytes(&ENC3_32);
        // SAFETY: the caller passes 16 keys.
        let (x, y, z) = unsafe { (load(x), load(y), load(z)) };
        let v = |c| _mm512_permutexvar_epi8(idx, c);
        const M: [u64; 3] = [crate::MASK3_X_U32 as u64, crate::MASK3_Y_U32 as u64, 0x3fff_ffff];
        let rep = |m: u64| (m | m << 32) as i64;
        // SAFETY: the caller passes 16 keys.
        unsafe {
            let code = enc3_merge(v(x), v(y), v(z), rep(M[0]), rep(M[1]), rep(M[2]));
            store(out, code);
        }
    }
}

gfni_fn! {
    /// 16 keys of 3D u64 codes.
    unsafe fn enc3_64_block(x: *const u32, y: *const u32, z: *const u32, out: *mut u64) {
        // SAFETY: the caller passes 16 keys.
        let (x, y, z) = unsafe { (load(x), load(y), load(z)) };
        for (h, idx) in ENC3_64.iter().enumerate() {
            let idx = bytes(idx);
            let v = |c| _mm512_permutexvar_epi8(idx, c);
            // SAFETY: the caller passes 16 keys.
            unsafe {
                let code = enc3_merge(
                    v(x),
                    v(y),
                    v(z),
                    crate::MASK3_X_U64 as i64,
                    crate::MASK3_Y_U64 as i64,
                    i64::MAX,
                );
                store(out.add(8 * h), code);
            }
        }
    }
}

gfni_fn! {
    /// 16 keys of 2D u32 codes.
    unsafe fn enc2_32_block(x: *const u32, y: *const u32, out: *mut u32) {
        let idx = bytes(&ENC2_32);
        // SAFETY: the caller passes 16 keys.
        unsafe {
            let (x, y) = (load(x), load(y));
            store(out, enc2_merge(_mm512_permutexvar_epi8(idx, x), _mm512_permutexvar_epi8(idx, y)));
        }
    }
}

gfni_fn! {
    /// 16 keys of 2D u64 codes.
    unsafe fn enc2_64_block(x: *const u32, y: *const u32, out: *mut u64) {
        // SAFETY: the caller passes 16 keys.
        unsafe {
            let (x, y) = (load(x), load(y));
            for (h, idx) in ENC2_64.iter().enumerate() {
                let idx = bytes(idx);
                let code = enc2_merge(_mm512_permutexvar_epi8(idx, x), _mm512_permutexvar_epi8(idx, y));
                store(out.add(8 * h), code);
            }
        }
    }
}

/// Keys per decoding block: one register of u32 outputs per axis. (Blocks of 32 keys, two
/// registers of u32 codes, ran 1.5x slower from L2 on the Xeon of BENCHMARKS.md, though
/// faster from L1.)
const DEC_KEYS: usize = 16;

/// The decoding tables of one code type: `D` axes, `CB` bytes per code, `NB` coordinate
/// bytes per axis, `K2` keys per block (two registers of codes), `BITS` bits per axis.
struct Dec<const D: usize> {
    /// Per phase: `vpermt2b` indices and the bytes that exist.
    gather: [([u8; 64], u64); D],
    /// Per axis, per phase: the lane matrices.
    matrices: [[[u64; 8]; D]; D],
    /// `vpermb` indices of the output registers and the bytes that exist.
    scatter: ([u8; 64], u64),
}

const fn dec_tables<const D: usize>(cb: usize, nb: usize, bits: u32) -> Dec<D> {
    let k2 = DEC_KEYS;
    let mut gather = [([0u8; 64], 0u64); D];
    let mut matrices = [[[0u64; 8]; D]; D];
    let mut p = 0;
    while p < D {
        gather[p] = dec_gather(D, cb, nb, k2, p);
        let mut a = 0;
        while a < D {
            matrices[a][p] = dec_lanes(D as u32, a as u32, p as u32, nb, k2, bits);
            a += 1;
        }
        p += 1;
    }
    Dec {
        gather,
        matrices,
        scatter: dec_scatter(nb, k2, 0),
    }
}

const DEC3_32: Dec<3> = dec_tables(4, 2, 10);
const DEC3_64: Dec<3> = dec_tables(8, 3, 21);
const DEC2_32: Dec<2> = dec_tables(4, 2, 16);
const DEC2_64: Dec<2> = dec_tables(8, 4, 32);

gfni_fn! {
    /// One block of 3D codes (`2 * 64 / CB` keys) from `codes` into the three axes.
    unsafe fn dec3_block<const CB: usize>(t: &Dec<3>, codes: *const u8, out: [*mut u32; 3]) {
        // SAFETY: the caller passes one block (16 keys: one register of u32 codes, two of
        // u64; with u32 codes the indices never reach the second).
        let (c0, c1) = unsafe { (load(codes), if CB == 8 { load(codes.add(64)) } else { load(codes) }) };
        let g = |p: usize| _mm512_maskz_permutex2var_epi8(t.gather[p].1, c0, bytes(&t.gather[p].0), c1);
        let tp = [g(0), g(1), g(2)];
        let r = [0, 1, 2].map(|a| {
            let f = |p: usize| _mm512_gf2p8affine_epi64_epi8::<0>(tp[p], qwords(&t.matrices[a][p]));
            _mm512_ternarylogic_epi64::<OR3>(f(0), f(1), f(2))
        });
        let (idx, keep) = t.scatter;
        for (&o, &r) in out.iter().zip(&r) {
            // SAFETY: the caller passes one block.
            unsafe { store(o, _mm512_maskz_permutexvar_epi8(keep, bytes(&idx), r)) };
        }
    }
}

gfni_fn! {
    /// One block of 2D codes.
    unsafe fn dec2_block<const CB: usize>(t: &Dec<2>, codes: *const u8, out: [*mut u32; 2]) {
        // SAFETY: the caller passes one block (16 keys: one register of u32 codes, two of
        // u64; with u32 codes the indices never reach the second).
        let (c0, c1) = unsafe { (load(codes), if CB == 8 { load(codes.add(64)) } else { load(codes) }) };
        let g = |p: usize| _mm512_maskz_permutex2var_epi8(t.gather[p].1, c0, bytes(&t.gather[p].0), c1);
        let tp = [g(0), g(1)];
        let r = [0, 1].map(|a| {
            let f = |p: usize| _mm512_gf2p8affine_epi64_epi8::<0>(tp[p], qwords(&t.matrices[a][p]));
            _mm512_or_si512(f(0), f(1))
        });
        let (idx, keep) = t.scatter;
        for (&o, &r) in out.iter().zip(&r) {
            // SAFETY: the caller passes one block.
            unsafe { store(o, _mm512_maskz_permutexvar_epi8(keep, bytes(&idx), r)) };
        }
    }
}

/// A zero-padded copy of a tail shorter than `K`.
#[inline(always)]
fn pad<T: Copy + Default, const K: usize>(s: &[T]) -> [T; K] {
    let mut b = [T::default(); K];
    b[..s.len()].copy_from_slice(s);
    b
}

/// Encoders over slices of equal length (checked by the caller): whole blocks of 16 keys,
/// then the tail through a padded copy.
macro_rules! encoder {
    ($name:ident, $block:ident, $out:ty, ($($ax:ident),+)) => {
        gfni_fn! {
            pub(crate) fn $name($($ax: &[u32],)+ out: &mut [$out]) {
                const K: usize = 16;
                let n = out.len();
                let full = n - n % K;
                let mut i = 0;
                while i < full {
                    // SAFETY: `i + K <= n`, and every slice has `n` elements.
                    unsafe { $block($($ax.as_ptr().add(i),)+ out.as_mut_ptr().add(i)) };
                    i += K;
                }
                if full < n {
                    $( let $ax: [u32; K] = pad(&$ax[full..n]); )+
                    let mut o = [0 as $out; K];
                    // SAFETY: `K` keys each.
                    unsafe { $block($($ax.as_ptr(),)+ o.as_mut_ptr()) };
                    out[full..].copy_from_slice(&o[..n - full]);
                }
            }
        }
    };
}

encoder!(enc3_32, enc3_32_block, u32, (xs, ys, zs));
encoder!(enc3_64, enc3_64_block, u64, (xs, ys, zs));
encoder!(enc2_32, enc2_32_block, u32, (xs, ys));
encoder!(enc2_64, enc2_64_block, u64, (xs, ys));

/// Decoders: whole blocks of `2 * 64 / CB` keys, then the tail through a padded copy.
macro_rules! decoder {
    ($name:ident, $block:ident, $code:ty, $tables:expr, ($($ax:ident),+)) => {
        gfni_fn! {
            pub(crate) fn $name(codes: &[$code], $($ax: &mut [u32]),+) {
                const CB: usize = size_of::<$code>();
                const K: usize = DEC_KEYS;
                let n = codes.len();
                let full = n - n % K;
                let mut i = 0;
                while i < full {
                    // SAFETY: `i + K <= n`, and every slice has `n` elements.
                    unsafe { $block::<CB>(&$tables, codes.as_ptr().add(i).cast(), [$($ax.as_mut_ptr().add(i)),+]) };
                    i += K;
                }
                if full < n {
                    let c: [$code; K] = pad(&codes[full..n]);
                    let mut o = [[0u32; K]; [$(stringify!($ax)),+].len()];
                    // SAFETY: `K` keys each.
                    unsafe { $block::<CB>(&$tables, c.as_ptr().cast(), o.each_mut().map(|b| b.as_mut_ptr())) };
                    for (dst, src) in [$(&mut $ax[full..n]),+].into_iter().zip(&o) {
                        dst.copy_from_slice(&src[..n - full]);
                    }
                }
            }
        }
    };
}

decoder!(dec3_32, dec3_block, u32, DEC3_32, (xs, ys, zs));
decoder!(dec3_64, dec3_block, u64, DEC3_64, (xs, ys, zs));
decoder!(dec2_32, dec2_block, u32, DEC2_32, (xs, ys));
decoder!(dec2_64, dec2_block, u64, DEC2_64, (xs, ys));
