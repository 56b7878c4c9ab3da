//! Which instruction set the batch functions run on, and how it is chosen.

/// An implementation of the batch functions ([`crate::batch`]). All paths give identical
/// results (tested); they differ only in speed.
///
/// [`Path::best`] picks one per process: with `std`, at run time from the CPU (`cpuid`);
/// without `std`, at compile time from the enabled `target_feature`s.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Path {
    /// Magic bits, one key at a time as the compiler emits it for the build's target
    /// (it may still vectorise when the build enables AVX2). Always available.
    Scalar,
    /// BMI2 `pdep`/`pext`, one key at a time (x86-64 with BMI2).
    Bmi2,
    /// Magic bits over struct-of-arrays lanes, compiled for AVX2 (8 lanes of u32, 4 of u64).
    Avx2,
    /// Magic bits over struct-of-arrays lanes, compiled for AVX-512 (F, VL, BW, DQ).
    Avx512,
    /// AVX-512 (F, VL, BW, DQ) with VBMI and GFNI, in 512-bit registers by explicit
    /// intrinsics: `vpermb` moves whole bytes and `gf2p8affineqb` permutes the bits inside
    /// each byte, a handful of instructions per 8 or 16 keys (Intel Ice Lake and later, AMD
    /// Zen 4 and later). The struct-of-arrays functions; the array-of-structs ones run the
    /// [`Path::Avx512`] loops.
    Gfni,
}

impl Path {
    /// Every path, slowest first.
    pub const ALL: [Path; 5] = [
        Path::Scalar,
        Path::Bmi2,
        Path::Avx2,
        Path::Avx512,
        Path::Gfni,
    ];

    /// Whether this CPU (with `std`) or this build (without) can run the path.
    pub fn is_available(self) -> bool {
        match self {
            Path::Scalar => true,
            Path::Bmi2 => cpu::has_bmi2(),
            Path::Avx2 => cpu::has_avx2(),
            Path::Avx512 => cpu::has_avx512(),
            Path::Gfni => cpu::has_gfni(),
        }
    }

    /// The paths this CPU can run, slowest first.
    pub fn available() -> impl Iterator<Item = Path> {
        Self::ALL.into_iter().filter(|p| p.is_available())
    }

    /// The fastest path for this CPU: GFNI, else AVX-512, else AVX2, else BMI2 where `pdep` is fast,
    /// else scalar magic bits. BMI2 is skipped on AMD family 17h and 18h (Zen 1, Zen 2,
    /// Hygon Dhyana), where `pdep`/`pext` are microcoded and slower than magic bits, even
    /// though the CPU reports the flag; without `std` the vendor cannot be checked and a
    /// build with `target_feature = "bmi2"` gets BMI2.
    pub fn best() -> Path {
        if Path::Gfni.is_available() {
            Path::Gfni
        } else if Path::Avx512.is_available() {
            Path::Avx512
        } else if Path::Avx2.is_available() {
            Path::Avx2
        } else if Path::Bmi2.is_available() && cpu::fast_pdep() {
            Path::Bmi2
        } else {
            Path::Scalar
        }
    }
}

#[cfg(all(feature = "std", target_arch = "x86_64"))]
mod cpu {
    use core::sync::atomic::{AtomicU8, Ordering};

    const BMI2: u8 = 1;
    const AVX2: u8 = 2;
    const AVX512: u8 = 4;
    const FAST_PDEP: u8 = 8;
    const GFNI: u8 = 16;
    const KNOWN: u8 = 128;

    static FLAGS: AtomicU8 = AtomicU8::new(0);

    /// What the scalar functions check per call, on its own so that the check is one load
    /// and one compare with a constant: [`SCALAR_PDEP`] or [`SCALAR_OTHER`], 0 until known.
    #[cfg(not(target_feature = "bmi2"))]
    static SCALAR: AtomicU8 = AtomicU8::new(0);
    #[cfg(not(target_feature = "bmi2"))]
    const SCALAR_PDEP: u8 = 1;
    #[cfg(not(target_feature = "bmi2"))]
    const SCALAR_OTHER: u8 = 2;

    #[inline(always)]
    fn flags() -> u8 {
        let f = FLAGS.load(Ordering::Relaxed);
        if f & KNOWN != 0 { f } else { detect() }
    }

    #[cold]
    #[inline(never)]
    fn detect() -> u8 {
        let mut f = KNOWN;
        if std::is_x86_feature_detected!("bmi2") {
            f |= BMI2;
            if !slow_pdep_cpu() {
                f |= FAST_PDEP;
            }
        }
        if std::is_x86_feature_detected!("avx2") {
            f |= AVX2;
        }
        if std::is_x86_feature_detected!("avx512f")
            && std::is_x86_feature_detected!("avx512vl")
            && std::is_x86_feature_detected!("avx512bw")
            && std::is_x86_feature_detected!("avx512dq")
        {
            f |= AVX512;
            if std::is_x86_feature_detected!("avx512vbmi") && std::is_x86_feature_detected!("gfni")
            {
                f |= GFNI;
            }
        }
        FLAGS.store(f, Ordering::Relaxed);
        #[cfg(not(target_feature = "bmi2"))]
        SCALAR.store(
            if f & (BMI2 | FAST_PDEP) == BMI2 | FAST_PDEP {
                SCALAR_PDEP
            } else {
                SCALAR_OTHER
            },
            Ordering::Relaxed,
        );
        f
    }

    /// AMD family 17h (Zen 1/2) and Hygon family 18h: `pdep`/`pext` in microcode.
    fn slow_pdep_cpu() -> bool {
        use core::arch::x86_64::__cpuid;
        let leaf0 = __cpuid(0);
        let mut vendor = [0u8; 12];
        vendor[0..4].copy_from_slice(&leaf0.ebx.to_le_bytes());
        vendor[4..8].copy_from_slice(&leaf0.edx.to_le_bytes());
        vendor[8..12].copy_from_slice(&leaf0.ecx.to_le_bytes());
        if &vendor != b"AuthenticAMD" && &vendor != b"HygonGenuine" {
            return false;
        }
        let eax = __cpuid(1).eax;
        let base = (eax >> 8) & 0xf;
        let family = if base == 0xf {
            base + ((eax >> 20) & 0xff)
        } else {
            base
        };
        family < 0x19
    }

    pub(super) fn has_bmi2() -> bool {
        flags() & BMI2 != 0
    }
    pub(super) fn has_avx2() -> bool {
        flags() & AVX2 != 0
    }
    pub(super) fn has_avx512() -> bool {
        flags() & AVX512 != 0
    }
    pub(super) fn has_gfni() -> bool {
        flags() & GFNI != 0
    }
    pub(super) fn fast_pdep() -> bool {
        flags() & FAST_PDEP != 0
    }
    /// BMI2 present and `pdep` fast: what the scalar functions check per call.
    #[cfg(not(target_feature = "bmi2"))]
    #[inline(always)]
    pub(crate) fn scalar_pdep() -> bool {
        match SCALAR.load(Ordering::Relaxed) {
            SCALAR_PDEP => true,
            SCALAR_OTHER => false,
            _ => {
                core::hint::cold_path();
                detect() & (BMI2 | FAST_PDEP) == BMI2 | FAST_PDEP
            }
        }
    }
}

#[cfg(all(feature = "std", target_arch = "x86_64", not(target_feature = "bmi2")))]
pub(crate) use cpu::scalar_pdep;

#[cfg(not(all(feature = "std", target_arch = "x86_64")))]
mod cpu {
    pub(super) fn has_bmi2() -> bool {
        cfg!(all(target_arch = "x86_64", target_feature = "bmi2"))
    }
    pub(super) fn has_avx2() -> bool {
        cfg!(all(target_arch = "x86_64", target_feature = "avx2"))
    }
    pub(super) fn has_avx512() -> bool {
        cfg!(all(
            target_arch = "x86_64",
            target_feature = "avx512f",
            target_feature = "avx512vl",
            target_feature = "avx512bw",
            target_feature = "avx512dq"
        ))
    }
    pub(super) fn has_gfni() -> bool {
        has_avx512()
            && cfg!(all(
                target_arch = "x86_64",
                target_feature = "sse2",
                target_feature = "avx512vbmi",
                target_feature = "gfni"
            ))
    }
    pub(super) fn fast_pdep() -> bool {
        true
    }
}
