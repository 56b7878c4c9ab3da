//! Integer hashing for noise: the PCG hash of Jarzynski and Olano, "Hash Functions for GPU
//! Rendering" (JCGT 2020), which they found the best quality-per-cost 32-bit hash on GPUs.
//!
//! Integer hashes give the same bits on the CPU and on every GPU (WGSL `u32` arithmetic
//! wraps like Rust's `wrapping_*`), unlike the classic `fract(sin(dot(p, k)) * 43758.5)`,
//! whose result depends on the GPU's `sin` precision. The WGSL twins are `water_pcg`,
//! `water_hash2`, `water_hash3` and `water_hash_unit` in [`wgsl::NOISE`](crate::wgsl::NOISE).

/// The PCG output permutation of one LCG step: a 32-bit to 32-bit bijection.
#[inline]
#[must_use]
pub const fn pcg(v: u32) -> u32 {
    let state = v.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// Hash of two words (lattice x, y).
#[inline]
#[must_use]
pub const fn hash2(x: u32, y: u32) -> u32 {
    pcg(x.wrapping_add(pcg(y)))
}

/// Hash of three words (lattice x, y and a seed or layer).
#[inline]
#[must_use]
pub const fn hash3(x: u32, y: u32, z: u32) -> u32 {
    pcg(x.wrapping_add(pcg(y.wrapping_add(pcg(z)))))
}

/// A hash mapped to `[0, 1)`: its top 24 bits times 2^-24 (exact in f32 on both sides).
#[inline]
#[must_use]
pub fn unit(h: u32) -> f32 {
    (h >> 8) as f32 * (1.0 / 16_777_216.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pcg_matches_the_papers_reference_values() {
        // Computed by hand from the paper's C listing:
        // state = v * 747796405u + 2891336453u;
        // word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
        // return (word >> 22u) ^ word;
        fn reference(v: u32) -> u32 {
            let state = (u64::from(v) * 747_796_405 + 2_891_336_453) as u32;
            let shift = (state >> 28) + 4;
            let word = ((u64::from((state >> shift) ^ state) * 277_803_737) & 0xffff_ffff) as u32;
            (word >> 22) ^ word
        }
        for v in [0u32, 1, 2, 12345, 0xdead_beef, u32::MAX] {
            assert_eq!(pcg(v), reference(v));
        }
    }

    #[test]
    fn hashes_are_roughly_uniform() {
        // 64 buckets over 2^16 lattice points: each within 15% of the mean.
        let mut buckets = [0u32; 64];
        for y in 0..256 {
            for x in 0..256 {
                buckets[(hash3(x, y, 7) >> 26) as usize] += 1;
            }
        }
        for b in buckets {
            assert!((870..=1180).contains(&b), "{b}");
        }
        assert!(unit(u32::MAX) < 1.0 && unit(0) == 0.0);
    }
}
