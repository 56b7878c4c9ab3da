//! Batch encode/decode over slices, struct-of-arrays (`xs`, `ys`, `zs` lanes) or
//! array-of-structs (`[[u32; 3]]`).
//!
//! Every function comes in two forms: the plain one runs on [`Path::best`] (chosen once per
//! process), the `_with` one on a given [`Path`] (for tests and benchmarks; an unavailable
//! path is an error). Each path is one loop compiled inside one `#[target_feature]`
//! function: the AVX2 and AVX-512 paths are the magic-bits loop of
//! [`crate::magic`], written with iterators so that LLVM vectorises it across lanes; the
//! BMI2 path is one `pdep`/`pext` per axis per key.
//!
//! Slices must have equal lengths ([`Error::LengthMismatch`] otherwise, nothing
//! written). Coordinates above the code's bits per axis are masked, as in
//! [`crate::encode3_u32`].
//!
//! ```
//! let (xs, ys, zs) = ([1, 0, 0, 1023], [0, 1, 0, 1023], [0, 0, 1, 1023]);
//! let mut codes = [0u32; 4];
//! morton::batch::encode3_u32_soa(&xs, &ys, &zs, &mut codes).unwrap();
//! assert_eq!(codes, [1, 2, 4, 0x3fff_ffff]);
//!
//! let mut back = [[0u32; 3]; 4];
//! morton::batch::decode3_u32_aos(&codes, &mut back).unwrap();
//! assert_eq!(back[3], [1023, 1023, 1023]);
//! ```

use crate::{Error, Path, magic};

// The loop shapes, expanded into each path's `#[target_feature]` function.

macro_rules! unmap2 {
    ($codes:expr, $xs:expr, $ys:expr, $f:expr) => {
        for ((&c, x), y) in $codes.iter().zip($xs.iter_mut()).zip($ys.iter_mut()) {
            let [a, b] = ($f)(c);
            *x = a;
            *y = b;
        }
    };
}

macro_rules! unmap3 {
    ($codes:expr, $xs:expr, $ys:expr, $zs:expr, $f:expr) => {
        for (((&c, x), y), z) in $codes
            .iter()
            .zip($xs.iter_mut())
            .zip($ys.iter_mut())
            .zip($zs.iter_mut())
        {
            let [a, b, d] = ($f)(c);
            *x = a;
            *y = b;
            *z = d;
        }
    };
}

macro_rules! map_aos {
    ($points:expr, $out:expr, $f:expr) => {
        for (o, &p) in $out.iter_mut().zip($points) {
            *o = ($f)(p);
        }
    };
}

macro_rules! unmap_aos {
    ($codes:expr, $points:expr, $f:expr) => {
        for (&c, p) in $codes.iter().zip($points.iter_mut()) {
            *p = ($f)(c);
        }
    };
}

#[cfg(target_arch = "x86_64")]
use crate::bmi2 as pd;

kernels!(enc2_32, map2, (xs: &[u32], ys: &[u32], out: &mut [u32]),
    magic: magic::encode2_u32, bmi2: |x, y| pd::encode2_u32(x, y));
kernels!(enc2_64, map2, (xs: &[u32], ys: &[u32], out: &mut [u64]),
    magic: magic::encode2_u64, bmi2: |x, y| pd::encode2_u64(x, y));
kernels!(enc3_32, map3, (xs: &[u32], ys: &[u32], zs: &[u32], out: &mut [u32]),
    magic: magic::encode3_u32, bmi2: |x, y, z| pd::encode3_u32(x, y, z));
kernels!(enc3_64, map3, (xs: &[u32], ys: &[u32], zs: &[u32], out: &mut [u64]),
    magic: magic::encode3_u64, bmi2: |x, y, z| pd::encode3_u64(x, y, z));
kernels!(dec2_32, unmap2, (codes: &[u32], xs: &mut [u32], ys: &mut [u32]),
    magic: magic::decode2_u32, bmi2: |c| pd::decode2_u32(c));
kernels!(dec2_64, unmap2, (codes: &[u64], xs: &mut [u32], ys: &mut [u32]),
    magic: magic::decode2_u64, bmi2: |c| pd::decode2_u64(c));
kernels!(dec3_32, unmap3, (codes: &[u32], xs: &mut [u32], ys: &mut [u32], zs: &mut [u32]),
    magic: magic::decode3_u32, bmi2: |c| pd::decode3_u32(c));
kernels!(dec3_64, unmap3, (codes: &[u64], xs: &mut [u32], ys: &mut [u32], zs: &mut [u32]),
    magic: magic::decode3_u64, bmi2: |c| pd::decode3_u64(c));

kernels!(enc2_32_aos, map_aos, (points: &[[u32; 2]], out: &mut [u32]),
    magic: |[x, y]: [u32; 2]| magic::encode2_u32(x, y), bmi2: |[x, y]: [u32; 2]| pd::encode2_u32(x, y));
kernels!(enc2_64_aos, map_aos, (points: &[[u32; 2]], out: &mut [u64]),
    magic: |[x, y]: [u32; 2]| magic::encode2_u64(x, y), bmi2: |[x, y]: [u32; 2]| pd::encode2_u64(x, y));
kernels!(enc3_32_aos, map_aos, (points: &[[u32; 3]], out: &mut [u32]),
    magic: |[x, y, z]: [u32; 3]| magic::encode3_u32(x, y, z),
    bmi2: |[x, y, z]: [u32; 3]| pd::encode3_u32(x, y, z));
kernels!(enc3_64_aos, map_aos, (points: &[[u32; 3]], out: &mut [u64]),
    magic: |[x, y, z]: [u32; 3]| magic::encode3_u64(x, y, z),
    bmi2: |[x, y, z]: [u32; 3]| pd::encode3_u64(x, y, z));
kernels!(dec2_32_aos, unmap_aos, (codes: &[u32], points: &mut [[u32; 2]]),
    magic: magic::decode2_u32, bmi2: |c| pd::decode2_u32(c));
kernels!(dec2_64_aos, unmap_aos, (codes: &[u64], points: &mut [[u32; 2]]),
    magic: magic::decode2_u64, bmi2: |c| pd::decode2_u64(c));
kernels!(dec3_32_aos, unmap_aos, (codes: &[u32], points: &mut [[u32; 3]]),
    magic: magic::decode3_u32, bmi2: |c| pd::decode3_u32(c));
kernels!(dec3_64_aos, unmap_aos, (codes: &[u64], points: &mut [[u32; 3]]),
    magic: magic::decode3_u64, bmi2: |c| pd::decode3_u64(c));

public!(
    /// 2D Morton codes into u32 (16 bits per axis) from struct-of-arrays lanes.
    encode2_u32_soa, encode2_u32_soa_with, enc2_32, gfni: enc2_32, (xs: &[u32], ys: &[u32], out: &mut [u32]));
public!(
    /// 2D Morton codes into u64 (32 bits per axis) from struct-of-arrays lanes.
    encode2_u64_soa, encode2_u64_soa_with, enc2_64, gfni: enc2_64, (xs: &[u32], ys: &[u32], out: &mut [u64]));
public!(
    /// 3D Morton codes into u32 (10 bits per axis) from struct-of-arrays lanes.
    encode3_u32_soa, encode3_u32_soa_with, enc3_32, gfni: enc3_32,
    (xs: &[u32], ys: &[u32], zs: &[u32], out: &mut [u32]));
public!(
    /// 3D Morton codes into u64 (21 bits per axis) from struct-of-arrays lanes.
    encode3_u64_soa, encode3_u64_soa_with, enc3_64, gfni: enc3_64,
    (xs: &[u32], ys: &[u32], zs: &[u32], out: &mut [u64]));
public!(
    /// Decodes 2D u32 codes into struct-of-arrays lanes.
    decode2_u32_soa, decode2_u32_soa_with, dec2_32, gfni: dec2_32, (codes: &[u32], xs: &mut [u32], ys: &mut [u32]));
public!(
    /// Decodes 2D u64 codes into struct-of-arrays lanes.
    decode2_u64_soa, decode2_u64_soa_with, dec2_64, gfni: dec2_64, (codes: &[u64], xs: &mut [u32], ys: &mut [u32]));
public!(
    /// Decodes 3D u32 codes into struct-of-arrays lanes (bits 30 and 31 ignored).
    decode3_u32_soa, decode3_u32_soa_with, dec3_32, gfni: dec3_32,
    (codes: &[u32], xs: &mut [u32], ys: &mut [u32], zs: &mut [u32]));
public!(
    /// Decodes 3D u64 codes into struct-of-arrays lanes (bit 63 ignored).
    decode3_u64_soa, decode3_u64_soa_with, dec3_64, gfni: dec3_64,
    (codes: &[u64], xs: &mut [u32], ys: &mut [u32], zs: &mut [u32]));

public!(
    /// 2D Morton codes into u32 from `[x, y]` points (cast a `&[morton::glam::UVec2]` with
    /// `bytemuck::cast_slice`, or use `UVec2::to_array`).
    encode2_u32_aos, encode2_u32_aos_with, enc2_32_aos, (points: &[[u32; 2]], out: &mut [u32]));
public!(
    /// 2D Morton codes into u64 from `[x, y]` points.
    encode2_u64_aos, encode2_u64_aos_with, enc2_64_aos, (points: &[[u32; 2]], out: &mut [u64]));
public!(
    /// 3D Morton codes into u32 from `[x, y, z]` points.
    encode3_u32_aos, encode3_u32_aos_with, enc3_32_aos, (points: &[[u32; 3]], out: &mut [u32]));
public!(
    /// 3D Morton codes into u64 from `[x, y, z]` points.
    encode3_u64_aos, encode3_u64_aos_with, enc3_64_aos, (points: &[[u32; 3]], out: &mut [u64]));
public!(
    /// Decodes 2D u32 codes into `[x, y]` points.
    decode2_u32_aos, decode2_u32_aos_with, dec2_32_aos, (codes: &[u32], points: &mut [[u32; 2]]));
public!(
    /// Decodes 2D u64 codes into `[x, y]` points.
    decode2_u64_aos, decode2_u64_aos_with, dec2_64_aos, (codes: &[u64], points: &mut [[u32; 2]]));
public!(
    /// Decodes 3D u32 codes into `[x, y, z]` points.
    decode3_u32_aos, decode3_u32_aos_with, dec3_32_aos, (codes: &[u32], points: &mut [[u32; 3]]));
public!(
    /// Decodes 3D u64 codes into `[x, y, z]` points.
    decode3_u64_aos, decode3_u64_aos_with, dec3_64_aos, (codes: &[u64], points: &mut [[u32; 3]]));
