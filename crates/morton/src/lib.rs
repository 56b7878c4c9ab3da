//! Morton (Z-order) codes for spatial sort keys: encode/decode in 2D and 3D into u32 and
//! u64, quantisation of float positions onto the integer grid, and the permutation that
//! sorts points by key. Horizon Zero Dawn sorts the instances of a static tile by (filter,
//! LOD range, Morton number) to cut them into spatially coherent clusters; Horizon
//! Forbidden West sorts batches into passes by a quantised Morton code of their position.
//! This crate is that key, made fast on the CPU and mirrored on the GPU ([`wgsl::CODES`]).
//!
//! # Example
//!
//! ```
//! use morton::glam::Vec3;
//! use morton::{Quantizer3, decode3_u32, encode3_u32, sort_permutation};
//!
//! assert_eq!(encode3_u32(1, 0, 0), 1); // x is the lowest bit
//! assert_eq!(encode3_u32(0, 1, 0), 2);
//! assert_eq!(encode3_u32(0, 0, 1), 4);
//! assert_eq!(decode3_u32(encode3_u32(5, 6, 7)), [5, 6, 7]);
//!
//! // Sort instance positions along the Z-order curve of a 1024^3 grid over their box.
//! let positions = [Vec3::new(9.0, 9.0, 9.0), Vec3::new(0.0, 0.0, 0.0), Vec3::new(9.0, 0.0, 0.0)];
//! let q = Quantizer3::from_points(&positions, 10).unwrap();
//! let mut keys = [0u32; 3];
//! q.morton_u32_slice(&positions, &mut keys).unwrap();
//! let order = sort_permutation(&keys).unwrap();
//! assert_eq!(order, [1, 2, 0]);
//! ```
//!
//! # Bit layout
//!
//! Bit `i` of each coordinate goes to bit `D * i + axis` of the code (`D` = 2 or 3 axes; x
//! is axis 0, the lowest bit). Coordinates are unsigned grid cells; the scalar encoders mask
//! away bits above the code's bits per axis (the `try_` encoders reject them instead).
//!
//! | code | bits per axis | code bit: 0 | 1 | 2 | 3 | 4 | 5 | ... | unused bits |
//! | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |
//! | [`encode2_u32`] | 16 ([`BITS2_U32`]) | x0 | y0 | x1 | y1 | x2 | y2 | ..., x15 y15 (bits 30, 31) | none |
//! | [`encode2_u64`] | 32 ([`BITS2_U64`]) | x0 | y0 | x1 | y1 | x2 | y2 | ..., x31 y31 | none |
//! | [`encode3_u32`] | 10 ([`BITS3_U32`]) | x0 | y0 | z0 | x1 | y1 | z1 | ..., x9 y9 z9 (bits 27-29) | 30, 31 (zero) |
//! | [`encode3_u64`] | 21 ([`BITS3_U64`]) | x0 | y0 | z0 | x1 | y1 | z1 | ..., x20 y20 z20 (bits 60-62) | 63 (zero) |
//!
//! Decoders ignore the unused bits. Sorting codes ascending walks the Z-order curve:
//! the octree (3D) or quadtree (2D) in depth-first order, children in x, y, z bit order.
//!
//! # What is here
//!
//! - Scalar [`encode2_u32`], [`decode2_u32`], [`encode2_u64`], [`decode2_u64`],
//!   [`encode3_u32`], [`decode3_u32`], [`encode3_u64`], [`decode3_u64`], in three forms:
//!   the crate-root functions, [`per_key`] and the `const` [`magic`] bits; `try_` variants
//!   check the range.
//! - [`batch`]: the same over slices (struct-of-arrays or `[[u32; N]]`), on the fastest
//!   [`Path`] this CPU has: AVX-512 with GFNI (byte moves and bit matrices in explicit
//!   512-bit intrinsics), AVX-512 or AVX2 vectorised magic bits, BMI2 where `pdep` is fast
//!   (not AMD Zen 1/2, where it is microcoded), scalar otherwise. With `std` the path is
//!   detected at run time; without, it follows the build's target features.
//!
//! Which to call:
//!
//! | you have | call | why |
//! | --- | --- | --- |
//! | slices of coordinates or codes | [`batch`] | run-time detected vector kernels, 2-4x a plain loop |
//! | a loop that makes one key per iteration | the crate-root functions | magic bits inline, so the loop vectorises, where that measured faster than `pdep`/`pext` per key: with AVX2 in the build (`-C target-cpu=native`, `x86-64-v3`) the 32-bit codes and 2D-64 decode, with AVX-512 (`x86-64-v4`) also 2D-64 encode and 3D-64 decode; otherwise [`per_key`]. Without BMI2 in the build, `pdep` behind a one-load check per key keeps pace with a loop compiled for BMI2: both are bound by `pdep`'s one per cycle |
//! | one key among other work (the loop will not vectorise) | [`per_key`] | `pdep`/`pext` inline (build with BMI2) or behind a cached CPU check, or a table: the cheapest single key. In a loop with AVX2 in the build it does not vectorise: 2.2-3x slower than the crate-root 32-bit codes |
//! | a `const` context | [`magic`] | `const fn` |
//!
//! - [`Quantizer3`] / [`Quantizer2`]: positions in an axis-aligned box onto the grid
//!   (clamped; NaN is an error), and quantise+encode over slices.
//! - [`hilbert`]: Hilbert curve encode/decode in 2D and 3D (better locality, dearer), and
//!   [`locality`], a metric to choose between the curves on your data.
//! - [`sort_permutation`]: a stable radix sort of u32/u64 keys returning the permutation
//!   (split on the top varying byte, then cache-sized least-significant-digit passes);
//!   [`Sorter`] keeps its buffers for sorting every frame; `parallel::par_sort_permutation`
//!   under the `parallel` feature.
//! - [`wgsl`]: the GPU twin of the 32-bit codes and the quantiser (`#import morton::codes`).
//!
//! # Features
//!
//! `std` (default): run-time CPU detection for the batch paths and the scalar BMI2
//! dispatch, `std::error::Error`.
//! `libm`: float math without `std` (for glam). `parallel`: rayon versions of the
//! quantise+encode and the sort, equal to the sequential results. Without `std` the crate is
//! `no_std` and needs `alloc` only for sorting.
//!
//! Source: Will Vale, "Decima: Visibility in Horizon Zero Dawn" ("Aside: Morton numbers");
//! "Adventures with Deferred Texturing in Horizon Forbidden West" (batches sorted by a
//! quantised Morton code); magic-bits interleaving after Fabian Giesen, "Decoding Morton
//! codes" (2009).
#![no_std]
#![cfg_attr(docsrs, feature(doc_cfg))]

#[cfg(not(any(feature = "std", feature = "libm")))]
compile_error!("morton needs float math: enable the `std` feature (default) or `libm`");

extern crate alloc;
#[cfg(feature = "std")]
extern crate std;

#[macro_use]
mod kernels;

pub mod batch;
#[cfg(target_arch = "x86_64")]
mod bmi2;
mod error;
#[doc(hidden)]
pub mod naive;
// Not on soft-float targets (x86_64-unknown-none), where LLVM cannot lower 512-bit vectors.
#[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
mod gfni;
pub mod hilbert;
pub mod locality;
// Unused when the build has BMI2: the scalar encoders then inline `pdep`.
#[cfg_attr(all(target_arch = "x86_64", target_feature = "bmi2"), allow(dead_code))]
mod lut;
pub mod magic;
#[cfg(feature = "parallel")]
pub mod parallel;
mod path;
pub mod quantize;
pub mod sort;
mod vector;
pub mod wgsl;

pub use error::Error;
/// The glam version this crate's API uses; use `morton::glam` to avoid a version mismatch
/// with a `glam` of your own.
pub use glam;
pub use path::Path;
pub use quantize::{Quantizer2, Quantizer3};
pub use sort::{MAX_SORT_KEYS, SortKey, Sorter, sort_permutation, sort_permutation_into};

/// Bits per axis of a 2D code in a u32.
pub const BITS2_U32: u32 = 16;
/// Bits per axis of a 2D code in a u64.
pub const BITS2_U64: u32 = 32;
/// Bits per axis of a 3D code in a u32 (bits 30 and 31 stay zero).
pub const BITS3_U32: u32 = 10;
/// Bits per axis of a 3D code in a u64 (bit 63 stays zero).
pub const BITS3_U64: u32 = 21;

/// The bits of x in a 2D u32 code (the even bits).
pub const MASK2_X_U32: u32 = 0x5555_5555;
/// The bits of y in a 2D u32 code (the odd bits).
pub const MASK2_Y_U32: u32 = 0xaaaa_aaaa;
/// The bits of x in a 3D u32 code (0, 3, ..., 27).
pub const MASK3_X_U32: u32 = 0x0924_9249;
/// The bits of y in a 3D u32 code (1, 4, ..., 28).
pub const MASK3_Y_U32: u32 = 0x1249_2492;
/// The bits of z in a 3D u32 code (2, 5, ..., 29).
pub const MASK3_Z_U32: u32 = 0x2492_4924;
/// The bits of x in a 2D u64 code.
pub const MASK2_X_U64: u64 = 0x5555_5555_5555_5555;
/// The bits of y in a 2D u64 code.
pub const MASK2_Y_U64: u64 = 0xaaaa_aaaa_aaaa_aaaa;
/// The bits of x in a 3D u64 code (0, 3, ..., 60).
pub const MASK3_X_U64: u64 = 0x1249_2492_4924_9249;
/// The bits of y in a 3D u64 code (1, 4, ..., 61).
pub const MASK3_Y_U64: u64 = 0x2492_4924_9249_2492;
/// The bits of z in a 3D u64 code (2, 5, ..., 62).
pub const MASK3_Z_U64: u64 = 0x4924_9249_2492_4924;

/// Defines a scalar function: BMI2 when the build enables it (`-C target-feature=+bmi2` or
/// a `target-cpu` that has it); otherwise either `lut` (a table lookup, on every CPU), or
/// `dispatch($fallback)`: with `std` on x86-64, inline `pdep`/`pext` when the CPU has a
/// fast `pdep` (checked once, then one load and one predictable branch per call, no call),
/// and `$fallback` (`lut` or `magic`) everywhere else. `dispatch($fallback, $checked)` runs
/// `$checked` instead after a failed check.
macro_rules! scalar {
    ($name:ident ( $($arg:ident : $ty:ty),* ) -> $ret:ty, lut) => {
        #[doc = concat!("[`crate::", stringify!($name), "`] one key at a time (see [`per_key`](self)).")]
        #[inline]
        #[must_use]
        pub fn $name($($arg: $ty),*) -> $ret {
            #[cfg(all(target_arch = "x86_64", target_feature = "bmi2"))]
            // SAFETY: the build enables BMI2, so every CPU it runs on has it.
            unsafe {
                bmi2::$name($($arg),*)
            }
            #[cfg(not(all(target_arch = "x86_64", target_feature = "bmi2")))]
            {
                lut::$name($($arg),*)
            }
        }
    };
    ($name:ident ( $($arg:ident : $ty:ty),* ) -> $ret:ty, dispatch($fallback:ident)) => {
        scalar!($name($($arg: $ty),*) -> $ret, dispatch($fallback, $fallback));
    };
    ($name:ident ( $($arg:ident : $ty:ty),* ) -> $ret:ty,
        dispatch($fallback:ident, $checked:ident)) => {
        #[doc = concat!("[`crate::", stringify!($name), "`] one key at a time (see [`per_key`](self)).")]
        #[inline(always)]
        #[must_use]
        pub fn $name($($arg: $ty),*) -> $ret {
            #[cfg(all(target_arch = "x86_64", target_feature = "bmi2"))]
            // SAFETY: the build enables BMI2, so every CPU it runs on has it.
            unsafe {
                bmi2::$name($($arg),*)
            }
            #[cfg(all(target_arch = "x86_64", not(target_feature = "bmi2"), feature = "std"))]
            {
                if path::scalar_pdep() {
                    // SAFETY: checked at run time that the CPU has BMI2.
                    return unsafe { bmi2::asm::$name($($arg),*) };
                }
                // Laid out and register-allocated as the rare case, so that a loop of calls
                // keeps `pdep`'s masks in registers.
                core::hint::cold_path();
                $checked::$name($($arg),*)
            }
            #[cfg(not(all(target_arch = "x86_64", any(target_feature = "bmi2", feature = "std"))))]
            {
                $fallback::$name($($arg),*)
            }
        }
    };
}

/// The crate-root function of the same name, chosen per code by measuring a loop of calls
/// (BENCHMARKS.md): `vectorise($m, $feature)`: `$m`'s magic bits inline where the build has
/// `$feature` (the loop then vectorises; `pdep` and table lookups would not), else the
/// [`per_key`] function; `vectorise($m512, $m2)`: the same with `$m512`'s where the build
/// has AVX-512 and `$m2`'s where it has AVX2 only; `per_key`: always [`per_key`] (3D-64 encode, where no vectorised
/// loop measured beat `pdep` one key at a time).
macro_rules! top {
    ($(#[$doc:meta])* $name:ident ( $($arg:ident : $ty:ty),* ) -> $ret:ty,
        vectorise($m:ident, $feature:literal, $builds:literal)) => {
        $(#[$doc])*
        ///
        #[doc = concat!("In a loop, builds with ", $builds, " vectorise it: ")]
        #[doc = concat!("it is magic bits inline. Other builds run [`per_key::", stringify!($name), "`].")]
        /// For slices, [`batch`] is faster still.
        #[inline(always)]
        #[must_use]
        pub fn $name($($arg: $ty),*) -> $ret {
            #[cfg(all(target_arch = "x86_64", target_feature = $feature))]
            {
                $m::$name($($arg),*)
            }
            #[cfg(not(all(target_arch = "x86_64", target_feature = $feature)))]
            {
                per_key::$name($($arg),*)
            }
        }
    };
    ($(#[$doc:meta])* $name:ident ( $($arg:ident : $ty:ty),* ) -> $ret:ty,
        vectorise($m512:ident, $m2:ident)) => {
        $(#[$doc])*
        ///
        /// In a loop, builds with AVX2 (`target-cpu=native` on a recent x86-64, `x86-64-v3`)
        /// vectorise it: it is magic bits inline, spelt differently with and without AVX-512
        /// (each spelling measured the faster in its build).
        #[doc = concat!("Other builds run [`per_key::", stringify!($name), "`].")]
        /// For slices, [`batch`] is faster still.
        #[inline(always)]
        #[must_use]
        pub fn $name($($arg: $ty),*) -> $ret {
            #[cfg(all(target_arch = "x86_64", target_feature = "avx512vl"))]
            {
                $m512::$name($($arg),*)
            }
            #[cfg(all(
                target_arch = "x86_64",
                target_feature = "avx2",
                not(target_feature = "avx512vl")
            ))]
            {
                $m2::$name($($arg),*)
            }
            #[cfg(not(all(target_arch = "x86_64", target_feature = "avx2")))]
            {
                per_key::$name($($arg),*)
            }
        }
    };
    ($(#[$doc:meta])* $name:ident ( $($arg:ident : $ty:ty),* ) -> $ret:ty, per_key) => {
        $(#[$doc])*
        ///
        #[doc = concat!("It is [`per_key::", stringify!($name), "`] inline: no vectorised ")]
        /// magic-bits loop measured beat `pdep`/`pext` one key at a time for this code. For
        /// slices, [`batch`] is faster still.
        #[inline(always)]
        #[must_use]
        pub fn $name($($arg: $ty),*) -> $ret {
            per_key::$name($($arg),*)
        }
    };
}

/// The scalar codes one key at a time, for a key computed among other work where the loop
/// around it will not vectorise: BMI2 `pdep`/`pext` inline when the build enables BMI2;
/// otherwise a table (3D u32 encode, every CPU), or `pdep`/`pext` as inline assembly behind
/// a cached run-time check where the CPU has a fast `pdep` (with `std`), else tables (32-bit
/// codes) or magic bits (64-bit). The crate-root functions of the same names are these,
/// except in builds with AVX2 or AVX-512 (which codes: each function says): magic bits
/// inline there, which loops vectorise.
pub mod per_key {
    #[allow(unused_imports)]
    use crate::{bmi2, lut, magic, path};

    /// The 64-bit magic-bits fallbacks behind the run-time check, out of line: inline, their
    /// 30-odd operations and masks made the compiler leave the whole function out of line
    /// (a call per key), take registers from the `pdep` masks, or merge the paths (2D
    /// decode: both vectorised into SSE registers, the `pext` results then moved through
    /// them).
    #[cfg(all(target_arch = "x86_64", not(target_feature = "bmi2"), feature = "std"))]
    mod outline {
        use crate::magic;

        #[inline(never)]
        pub(super) fn encode2_u64(x: u32, y: u32) -> u64 {
            magic::encode2_u64(x, y)
        }
        #[inline(never)]
        pub(super) fn decode2_u64(code: u64) -> [u32; 2] {
            magic::decode2_u64(code)
        }
        #[inline(never)]
        pub(super) fn encode3_u64(x: u32, y: u32, z: u32) -> u64 {
            magic::encode3_u64(x, y, z)
        }
        #[inline(never)]
        pub(super) fn decode3_u64(code: u64) -> [u32; 3] {
            magic::decode3_u64(code)
        }
    }

    /// The fallbacks behind the run-time check, which a CPU with a fast `pdep` (where the
    /// integration tests run) never takes, against a naive bit loop.
    #[cfg(test)]
    mod tests {
        use crate::lut;

        use crate::naive::{naive_decode, naive_encode};

        /// xorshift64: inputs covering every bit.
        fn words(n: usize) -> impl Iterator<Item = u64> {
            let mut s = 0x9e37_79b9_7f4a_7c15u64;
            (0..n).map(move |_| {
                s ^= s << 13;
                s ^= s >> 7;
                s ^= s << 17;
                s
            })
        }

        #[test]
        fn fallbacks_match_naive() {
            for w in words(4096).chain([0, u64::MAX]) {
                let (a, b, c) = (w as u32, (w >> 32) as u32, w.rotate_left(17) as u32);
                assert_eq!(lut::encode2_u32(a, b) as u64, naive_encode([a, b], 16));
                assert_eq!(
                    lut::encode3_u32(a, b, c) as u64,
                    naive_encode([a, b, c], 10)
                );
                assert_eq!(lut::decode2_u32(a), naive_decode::<2>(a as u64, 16));
                assert_eq!(lut::decode3_u32(a), naive_decode::<3>(a as u64, 10));
                #[cfg(all(target_arch = "x86_64", not(target_feature = "bmi2"), feature = "std"))]
                {
                    use super::outline;
                    assert_eq!(outline::encode2_u64(a, b), naive_encode([a, b], 32));
                    assert_eq!(outline::encode3_u64(a, b, c), naive_encode([a, b, c], 21));
                    assert_eq!(outline::decode2_u64(w), naive_decode::<2>(w, 32));
                    assert_eq!(outline::decode3_u64(w), naive_decode::<3>(w, 21));
                }
            }
        }
    }

    scalar!(
        encode2_u32(x: u32, y: u32) -> u32, dispatch(lut)
    );
    scalar!(
        decode2_u32(code: u32) -> [u32; 2], dispatch(lut)
    );
    scalar!(
        encode3_u32(x: u32, y: u32, z: u32) -> u32, lut
    );
    scalar!(
        decode3_u32(code: u32) -> [u32; 3], dispatch(lut)
    );
    scalar!(
        encode2_u64(x: u32, y: u32) -> u64, dispatch(magic, outline)
    );
    scalar!(
        decode2_u64(code: u64) -> [u32; 2], dispatch(magic, outline)
    );
    scalar!(
        encode3_u64(x: u32, y: u32, z: u32) -> u64, dispatch(magic, outline)
    );
    scalar!(
        decode3_u64(code: u64) -> [u32; 3], dispatch(magic, outline)
    );
}

top!(
    /// 2D Morton code of `(x, y)` in a u32, 16 bits per axis (higher bits of `x` and `y`
    /// are ignored). `encode2_u32(1, 0) == 1`, `encode2_u32(0, 1) == 2`.
    encode2_u32(x: u32, y: u32) -> u32,
    vectorise(vector, "avx2", "AVX2 (`target-cpu=native` on a recent x86-64, `x86-64-v3`)")
);
top!(
    /// `[x, y]` of a 2D u32 code, the inverse of [`encode2_u32`].
    decode2_u32(code: u32) -> [u32; 2],
    vectorise(magic, "avx2", "AVX2 (`target-cpu=native` on a recent x86-64, `x86-64-v3`)")
);
top!(
    /// 3D Morton code of `(x, y, z)` in a u32, 10 bits per axis (higher bits ignored; code
    /// bits 30 and 31 are zero). `encode3_u32(1, 0, 0) == 1`, `(0, 1, 0)` gives 2,
    /// `(0, 0, 1)` gives 4.
    encode3_u32(x: u32, y: u32, z: u32) -> u32,
    vectorise(magic, vector)
);
top!(
    /// `[x, y, z]` of a 3D u32 code, the inverse of [`encode3_u32`] (bits 30 and 31 are
    /// ignored).
    decode3_u32(code: u32) -> [u32; 3],
    vectorise(magic, "avx2", "AVX2 (`target-cpu=native` on a recent x86-64, `x86-64-v3`)")
);
top!(
    /// 2D Morton code of `(x, y)` in a u64, 32 bits per axis.
    encode2_u64(x: u32, y: u32) -> u64,
    vectorise(vector, "avx512vl", "AVX-512 (`target-cpu=native` on such a CPU, `x86-64-v4`)")
);
top!(
    /// `[x, y]` of a 2D u64 code, the inverse of [`encode2_u64`].
    decode2_u64(code: u64) -> [u32; 2],
    vectorise(vector, "avx2", "AVX2 (`target-cpu=native` on a recent x86-64, `x86-64-v3`)")
);
top!(
    /// 3D Morton code of `(x, y, z)` in a u64, 21 bits per axis (higher bits ignored; code
    /// bit 63 is zero).
    encode3_u64(x: u32, y: u32, z: u32) -> u64,
    per_key
);
top!(
    /// `[x, y, z]` of a 3D u64 code, the inverse of [`encode3_u64`] (bit 63 is ignored).
    decode3_u64(code: u64) -> [u32; 3],
    vectorise(vector, "avx512vl", "AVX-512 (`target-cpu=native` on such a CPU, `x86-64-v4`)")
);

#[inline]
fn fits(axis: u8, value: u32, bits: u32) -> Result<(), Error> {
    let max = if bits >= 32 {
        u32::MAX
    } else {
        (1 << bits) - 1
    };
    if value <= max {
        Ok(())
    } else {
        Err(Error::CoordinateTooLarge { axis, value, max })
    }
}

/// [`encode2_u32`], rejecting coordinates of more than 16 bits.
pub fn try_encode2_u32(x: u32, y: u32) -> Result<u32, Error> {
    fits(0, x, BITS2_U32)?;
    fits(1, y, BITS2_U32)?;
    Ok(encode2_u32(x, y))
}

/// [`encode3_u32`], rejecting coordinates of more than 10 bits.
pub fn try_encode3_u32(x: u32, y: u32, z: u32) -> Result<u32, Error> {
    fits(0, x, BITS3_U32)?;
    fits(1, y, BITS3_U32)?;
    fits(2, z, BITS3_U32)?;
    Ok(encode3_u32(x, y, z))
}

/// [`encode3_u64`], rejecting coordinates of more than 21 bits.
pub fn try_encode3_u64(x: u32, y: u32, z: u32) -> Result<u64, Error> {
    fits(0, x, BITS3_U64)?;
    fits(1, y, BITS3_U64)?;
    fits(2, z, BITS3_U64)?;
    Ok(encode3_u64(x, y, z))
}

/// [`encode2_u64`]: every u32 coordinate fits, so this never fails; here for symmetry.
pub fn try_encode2_u64(x: u32, y: u32) -> Result<u64, Error> {
    Ok(encode2_u64(x, y))
}
