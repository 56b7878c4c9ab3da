//! The kernel generator shared by [`crate::batch`] and [`crate::quantize`].

/// Generates, in module `$modname`, one kernel per [`crate::Path`] for a loop shape
/// (`$shape`, a macro taking the arguments and then a per-key function, so that the
/// per-key function is called directly and inlined, not through an `Fn` shim) and a `run(path, args...)` that dispatches. Each kernel is its own
/// `#[target_feature]` function, so the whole loop is compiled for that instruction set.
macro_rules! kernels {
    (
        $modname:ident, $shape:ident, ( $($arg:ident : $ty:ty),* ),
        magic: $magic:expr, bmi2: $bmi2:expr
    ) => {
        kernels!($modname, $shape, ( $($arg : $ty),* ) -> (), magic: $magic, bmi2: $bmi2);
    };
    (
        $modname:ident, $shape:ident, ( $($arg:ident : $ty:ty),* ),
        scalar: $scalar:expr, bmi2: $bmi2:expr, simd: $simd:expr
    ) => {
        kernels!($modname, $shape, ( $($arg : $ty),* ) -> (),
            scalar: $scalar, bmi2: $bmi2, simd: $simd);
    };
    (
        $modname:ident, $shape:ident, ( $($arg:ident : $ty:ty),* ) -> $ret:ty,
        magic: $magic:expr, bmi2: $bmi2:expr
    ) => {
        kernels!($modname, $shape, ( $($arg : $ty),* ) -> $ret,
            scalar: $magic, bmi2: $bmi2, simd: $magic);
    };
    (
        $modname:ident, $shape:ident, ( $($arg:ident : $ty:ty),* ) -> $ret:ty,
        scalar: $scalar:expr, bmi2: $bmi2:expr, simd: $simd:expr
    ) => {
        mod $modname {
            #[allow(unused_imports)]
            use super::*;

            #[inline(never)]
            fn scalar($($arg: $ty),*) -> $ret {
                $shape!($($arg),*, $scalar)
            }

            #[cfg(target_arch = "x86_64")]
            #[inline(never)]
            #[target_feature(enable = "bmi2")]
            fn bmi2($($arg: $ty),*) -> $ret {
                $shape!($($arg),*, $bmi2)
            }

            #[cfg(target_arch = "x86_64")]
            #[inline(never)]
            #[target_feature(enable = "avx2")]
            fn avx2($($arg: $ty),*) -> $ret {
                $shape!($($arg),*, $simd)
            }

            #[cfg(target_arch = "x86_64")]
            #[inline(never)]
            #[target_feature(enable = "avx512f,avx512vl,avx512bw,avx512dq,avx2")]
            fn avx512($($arg: $ty),*) -> $ret {
                $shape!($($arg),*, $simd)
            }

            /// Runs on `path`, which the caller has checked is available.
            #[inline]
            pub(crate) fn run(path: $crate::Path, $($arg: $ty),*) -> $ret {
                match path {
                    #[cfg(target_arch = "x86_64")]
                    // SAFETY: the caller checked `path.is_available()`: the CPU has BMI2.
                    $crate::Path::Bmi2 => unsafe { bmi2($($arg),*) },
                    #[cfg(target_arch = "x86_64")]
                    // SAFETY: as above, the CPU has AVX2.
                    $crate::Path::Avx2 => unsafe { avx2($($arg),*) },
                    #[cfg(target_arch = "x86_64")]
                    // SAFETY: as above, the CPU has AVX-512 F, VL, BW and DQ (and so AVX2);
                    // the GFNI path needs those too and runs these loops where it has no
                    // kernel of its own.
                    $crate::Path::Avx512 | $crate::Path::Gfni => unsafe { avx512($($arg),*) },
                    _ => scalar($($arg),*),
                }
            }
        }
    };
}
