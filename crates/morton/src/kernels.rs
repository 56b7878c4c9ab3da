//! The kernel generator shared by [`crate::batch`], [`crate::hilbert`] and
//! [`crate::quantize`], the loop shapes of the slice encoders, and the generator of their
//! public `name` / `name_with` pairs with the checks every one of them makes.

use crate::{Error, Path};

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

/// `Ok` if slice `what` has the `expected` length (the first slice's), else
/// [`Error::LengthMismatch`].
#[inline(always)]
pub(crate) fn check(what: &'static str, expected: usize, got: usize) -> Result<(), Error> {
    if expected == got {
        Ok(())
    } else {
        Err(Error::LengthMismatch {
            what,
            expected,
            got,
        })
    }
}

/// `Ok` if this CPU and build can run `path`, else [`Error::PathUnavailable`].
#[inline(always)]
pub(crate) fn available(path: Path) -> Result<(), Error> {
    if path.is_available() {
        Ok(())
    } else {
        Err(Error::PathUnavailable { path })
    }
}

// The loop shapes of the struct-of-arrays encoders, expanded into each path's
// `#[target_feature]` function.

macro_rules! map2 {
    ($xs:expr, $ys:expr, $out:expr, $f:expr) => {
        for ((o, &x), &y) in $out.iter_mut().zip($xs).zip($ys) {
            *o = ($f)(x, y);
        }
    };
}

macro_rules! map3 {
    ($xs:expr, $ys:expr, $zs:expr, $out:expr, $f:expr) => {
        for (((o, &x), &y), &z) in $out.iter_mut().zip($xs).zip($ys).zip($zs) {
            *o = ($f)(x, y, z);
        }
    };
}

/// Generates the public `name` (best path) and `name_with` (given path) pair over the
/// kernels `$kernel` made by [`kernels!`]: the path's availability first, then every slice's
/// length against the first, in order; nothing is written on an error. With
/// `gfni: kernel`, [`Path::Gfni`] runs that kernel of [`crate::gfni`].
macro_rules! public {
    (
        $(#[$doc:meta])*
        $name:ident, $with:ident, $kernel:ident, gfni: $gfni:ident,
        ( $first:ident : $fty:ty $(, $arg:ident : $ty:ty)* )
    ) => {
        public!(@pair path, [
            #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
            if path == Path::Gfni {
                // SAFETY: `available` checked that the CPU has what the GFNI kernels need;
                // the lengths are equal.
                unsafe { crate::gfni::$gfni($first $(, $arg)*) };
                return Ok(());
            }
        ], $(#[$doc])* $name, $with, $kernel, ($first : $fty $(, $arg : $ty)*));
    };
    (
        $(#[$doc:meta])*
        $name:ident, $with:ident, $kernel:ident,
        ( $first:ident : $fty:ty $(, $arg:ident : $ty:ty)* )
    ) => {
        public!(@pair path, [], $(#[$doc])* $name, $with, $kernel,
            ($first : $fty $(, $arg : $ty)*));
    };
    // `$path` names the path argument for the statements `$pre` (run after the checks).
    (
        @pair $path:ident, [ $($pre:tt)* ],
        $(#[$doc:meta])*
        $name:ident, $with:ident, $kernel:ident,
        ( $first:ident : $fty:ty $(, $arg:ident : $ty:ty)* )
    ) => {
        $(#[$doc])*
        #[inline]
        pub fn $name($first: $fty $(, $arg: $ty)*) -> Result<(), Error> {
            $with(Path::best(), $first $(, $arg)*)
        }

        #[doc = concat!("[`", stringify!($name), "`] on a given [`Path`]; ",
            "[`Error::PathUnavailable`] if this CPU or build lacks it.")]
        pub fn $with($path: Path, $first: $fty $(, $arg: $ty)*) -> Result<(), Error> {
            $crate::kernels::available($path)?;
            $( $crate::kernels::check(stringify!($arg), $first.len(), $arg.len())?; )*
            $($pre)*
            $kernel::run($path, $first $(, $arg)*);
            Ok(())
        }
    };
}
