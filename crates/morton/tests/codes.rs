//! Morton encode/decode: fixed vectors, every function and every batch path against a
//! naive bit-by-bit loop, roundtrips for every width.

use morton::naive::{low, naive_decode, naive_encode};
use morton::{Path, batch, magic};
use proptest::prelude::*;

#[test]
fn fixed_vectors_3d() {
    assert_eq!(morton::encode3_u32(1, 0, 0), 1);
    assert_eq!(morton::encode3_u32(0, 1, 0), 2);
    assert_eq!(morton::encode3_u32(0, 0, 1), 4);
    assert_eq!(morton::encode3_u32(2, 0, 0), 8);
    assert_eq!(morton::encode3_u32(1023, 1023, 1023), 0x3fff_ffff);
    assert_eq!(morton::encode3_u32(1023, 0, 0), morton::MASK3_X_U32);
    assert_eq!(morton::encode3_u32(0, 1023, 0), morton::MASK3_Y_U32);
    assert_eq!(morton::encode3_u32(0, 0, 1023), morton::MASK3_Z_U32);
    assert_eq!(
        morton::encode3_u32(1024, 1024, 1024),
        0,
        "bit 10 is masked away"
    );
    assert_eq!(morton::encode3_u64(1, 0, 0), 1);
    assert_eq!(morton::encode3_u64(0, 1, 0), 2);
    assert_eq!(morton::encode3_u64(0, 0, 1), 4);
    let max = (1 << 21) - 1;
    assert_eq!(morton::encode3_u64(max, max, max), 0x7fff_ffff_ffff_ffff);
    assert_eq!(morton::encode3_u64(max, 0, 0), morton::MASK3_X_U64);
    assert_eq!(morton::encode3_u64(0, max, 0), morton::MASK3_Y_U64);
    assert_eq!(morton::encode3_u64(0, 0, max), morton::MASK3_Z_U64);
    assert_eq!(morton::decode3_u32(0xffff_ffff), [1023, 1023, 1023]);
    assert_eq!(morton::decode3_u64(u64::MAX), [max, max, max]);
    assert_eq!(morton::decode3_u32(0b110_101), [0b01, 0b10, 0b11]);
}

#[test]
fn fixed_vectors_2d() {
    assert_eq!(morton::encode2_u32(1, 0), 1);
    assert_eq!(morton::encode2_u32(0, 1), 2);
    assert_eq!(morton::encode2_u32(3, 0), 0b101);
    assert_eq!(morton::encode2_u32(0xffff, 0xffff), u32::MAX);
    assert_eq!(morton::encode2_u32(0xffff, 0), morton::MASK2_X_U32);
    assert_eq!(morton::encode2_u32(0, 0xffff), morton::MASK2_Y_U32);
    assert_eq!(morton::encode2_u64(u32::MAX, u32::MAX), u64::MAX);
    assert_eq!(morton::encode2_u64(u32::MAX, 0), morton::MASK2_X_U64);
    assert_eq!(morton::encode2_u64(0, u32::MAX), morton::MASK2_Y_U64);
    assert_eq!(morton::decode2_u32(u32::MAX), [0xffff, 0xffff]);
    assert_eq!(morton::decode2_u64(0b1001), [0b01, 0b10]);
}

#[test]
fn try_encoders_reject_excess_bits() {
    assert_eq!(morton::try_encode3_u32(1023, 0, 0), Ok(morton::MASK3_X_U32));
    let e = morton::try_encode3_u32(0, 1024, 0).unwrap_err();
    assert_eq!(
        e,
        morton::Error::CoordinateTooLarge {
            axis: 1,
            value: 1024,
            max: 1023
        }
    );
    assert!(e.to_string().contains("1024"));
    assert!(morton::try_encode3_u64(0, 0, 1 << 21).is_err());
    assert!(morton::try_encode3_u64(0, 0, (1 << 21) - 1).is_ok());
    assert!(morton::try_encode2_u32(1 << 16, 0).is_err());
    assert_eq!(
        morton::try_encode2_u64(u32::MAX, 0),
        Ok(morton::MASK2_X_U64)
    );
}

#[test]
fn scalar_is_const() {
    const K: u32 = magic::encode3_u32(1, 2, 3);
    const C: [u32; 3] = magic::decode3_u32(K);
    assert_eq!(C, [1, 2, 3]);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn scalar_matches_naive(x: u32, y: u32, z: u32, k32: u32, k64: u64) {
        prop_assert_eq!(morton::encode2_u32(x, y) as u64, naive_encode([x, y], 16));
        prop_assert_eq!(morton::encode2_u64(x, y), naive_encode([x, y], 32));
        prop_assert_eq!(morton::encode3_u32(x, y, z) as u64, naive_encode([x, y, z], 10));
        prop_assert_eq!(morton::encode3_u64(x, y, z), naive_encode([x, y, z], 21));
        prop_assert_eq!(morton::decode2_u32(k32), naive_decode::<2>(k32 as u64, 16));
        prop_assert_eq!(morton::decode2_u64(k64), naive_decode::<2>(k64, 32));
        prop_assert_eq!(morton::decode3_u32(k32), naive_decode::<3>(k32 as u64, 10));
        prop_assert_eq!(morton::decode3_u64(k64), naive_decode::<3>(k64, 21));
        // The per-key versions (BMI2, inline assembly or tables, as this CPU and build have).
        prop_assert_eq!(morton::per_key::encode2_u32(x, y) as u64, naive_encode([x, y], 16));
        prop_assert_eq!(morton::per_key::encode2_u64(x, y), naive_encode([x, y], 32));
        prop_assert_eq!(morton::per_key::encode3_u32(x, y, z) as u64, naive_encode([x, y, z], 10));
        prop_assert_eq!(morton::per_key::encode3_u64(x, y, z), naive_encode([x, y, z], 21));
        prop_assert_eq!(morton::per_key::decode2_u32(k32), naive_decode::<2>(k32 as u64, 16));
        prop_assert_eq!(morton::per_key::decode2_u64(k64), naive_decode::<2>(k64, 32));
        prop_assert_eq!(morton::per_key::decode3_u32(k32), naive_decode::<3>(k32 as u64, 10));
        prop_assert_eq!(morton::per_key::decode3_u64(k64), naive_decode::<3>(k64, 21));
        // The const magic-bits versions too (the plain ones may be BMI2).
        prop_assert_eq!(magic::encode3_u32(x, y, z), morton::encode3_u32(x, y, z));
        prop_assert_eq!(magic::encode3_u64(x, y, z), morton::encode3_u64(x, y, z));
        prop_assert_eq!(magic::encode2_u32(x, y), morton::encode2_u32(x, y));
        prop_assert_eq!(magic::encode2_u64(x, y), morton::encode2_u64(x, y));
        prop_assert_eq!(magic::decode3_u32(k32), morton::decode3_u32(k32));
        prop_assert_eq!(magic::decode3_u64(k64), morton::decode3_u64(k64));
        prop_assert_eq!(magic::decode2_u32(k32), morton::decode2_u32(k32));
        prop_assert_eq!(magic::decode2_u64(k64), morton::decode2_u64(k64));
    }

    #[test]
    fn roundtrip_every_width(x: u32, y: u32, z: u32) {
        let (x16, y16) = (low(x, 16), low(y, 16));
        prop_assert_eq!(morton::decode2_u32(morton::encode2_u32(x, y)), [x16, y16]);
        prop_assert_eq!(morton::decode2_u64(morton::encode2_u64(x, y)), [x, y]);
        prop_assert_eq!(
            morton::decode3_u32(morton::encode3_u32(x, y, z)),
            [low(x, 10), low(y, 10), low(z, 10)]
        );
        prop_assert_eq!(
            morton::decode3_u64(morton::encode3_u64(x, y, z)),
            [low(x, 21), low(y, 21), low(z, 21)]
        );
    }

    #[test]
    fn decode_then_encode_keeps_used_bits(k32: u32, k64: u64) {
        let [x, y] = morton::decode2_u32(k32);
        prop_assert_eq!(morton::encode2_u32(x, y), k32);
        let [x, y] = morton::decode2_u64(k64);
        prop_assert_eq!(morton::encode2_u64(x, y), k64);
        let [x, y, z] = morton::decode3_u32(k32);
        prop_assert_eq!(morton::encode3_u32(x, y, z), k32 & 0x3fff_ffff);
        let [x, y, z] = morton::decode3_u64(k64);
        prop_assert_eq!(morton::encode3_u64(x, y, z), k64 & !(1 << 63));
    }

    /// Every available path, SoA and AoS, against the naive loop, at lengths that leave
    /// vector remainders.
    #[test]
    fn batch_paths_match_naive(
        coords in proptest::collection::vec(any::<[u32; 3]>(), 0..70),
        keys in proptest::collection::vec(any::<u64>(), 0..70),
    ) {
        let n = coords.len();
        let xs: Vec<u32> = coords.iter().map(|c| c[0]).collect();
        let ys: Vec<u32> = coords.iter().map(|c| c[1]).collect();
        let zs: Vec<u32> = coords.iter().map(|c| c[2]).collect();
        let pts2: Vec<[u32; 2]> = coords.iter().map(|c| [c[0], c[1]]).collect();
        let k32: Vec<u32> = keys.iter().map(|&k| k as u32).collect();
        let m = keys.len();
        for path in Path::available() {
            let mut o32 = vec![0u32; n];
            let mut o64 = vec![0u64; n];
            batch::encode2_u32_soa_with(path, &xs, &ys, &mut o32).unwrap();
            for i in 0..n { prop_assert_eq!(o32[i] as u64, naive_encode(pts2[i], 16), "{:?}", path); }
            batch::encode2_u32_aos_with(path, &pts2, &mut o32).unwrap();
            for i in 0..n { prop_assert_eq!(o32[i] as u64, naive_encode(pts2[i], 16), "{:?}", path); }
            batch::encode2_u64_soa_with(path, &xs, &ys, &mut o64).unwrap();
            for i in 0..n { prop_assert_eq!(o64[i], naive_encode(pts2[i], 32), "{:?}", path); }
            batch::encode2_u64_aos_with(path, &pts2, &mut o64).unwrap();
            for i in 0..n { prop_assert_eq!(o64[i], naive_encode(pts2[i], 32), "{:?}", path); }
            batch::encode3_u32_soa_with(path, &xs, &ys, &zs, &mut o32).unwrap();
            for i in 0..n { prop_assert_eq!(o32[i] as u64, naive_encode(coords[i], 10), "{:?}", path); }
            batch::encode3_u32_aos_with(path, &coords, &mut o32).unwrap();
            for i in 0..n { prop_assert_eq!(o32[i] as u64, naive_encode(coords[i], 10), "{:?}", path); }
            batch::encode3_u64_soa_with(path, &xs, &ys, &zs, &mut o64).unwrap();
            for i in 0..n { prop_assert_eq!(o64[i], naive_encode(coords[i], 21), "{:?}", path); }
            batch::encode3_u64_aos_with(path, &coords, &mut o64).unwrap();
            for i in 0..n { prop_assert_eq!(o64[i], naive_encode(coords[i], 21), "{:?}", path); }

            let (mut a, mut b, mut c) = (vec![0u32; m], vec![0u32; m], vec![0u32; m]);
            let mut p2 = vec![[0u32; 2]; m];
            let mut p3 = vec![[0u32; 3]; m];
            batch::decode2_u32_soa_with(path, &k32, &mut a, &mut b).unwrap();
            batch::decode2_u32_aos_with(path, &k32, &mut p2).unwrap();
            for i in 0..m {
                let want = naive_decode::<2>(k32[i] as u64, 16);
                prop_assert_eq!([a[i], b[i]], want, "{:?}", path);
                prop_assert_eq!(p2[i], want, "{:?}", path);
            }
            batch::decode2_u64_soa_with(path, &keys, &mut a, &mut b).unwrap();
            batch::decode2_u64_aos_with(path, &keys, &mut p2).unwrap();
            for i in 0..m {
                let want = naive_decode::<2>(keys[i], 32);
                prop_assert_eq!([a[i], b[i]], want, "{:?}", path);
                prop_assert_eq!(p2[i], want, "{:?}", path);
            }
            batch::decode3_u32_soa_with(path, &k32, &mut a, &mut b, &mut c).unwrap();
            batch::decode3_u32_aos_with(path, &k32, &mut p3).unwrap();
            for i in 0..m {
                let want = naive_decode::<3>(k32[i] as u64, 10);
                prop_assert_eq!([a[i], b[i], c[i]], want, "{:?}", path);
                prop_assert_eq!(p3[i], want, "{:?}", path);
            }
            batch::decode3_u64_soa_with(path, &keys, &mut a, &mut b, &mut c).unwrap();
            batch::decode3_u64_aos_with(path, &keys, &mut p3).unwrap();
            for i in 0..m {
                let want = naive_decode::<3>(keys[i], 21);
                prop_assert_eq!([a[i], b[i], c[i]], want, "{:?}", path);
                prop_assert_eq!(p3[i], want, "{:?}", path);
            }
        }
    }
}

#[test]
fn batch_rejects_mismatched_lengths() {
    let (xs, ys, zs) = ([1u32; 4], [2u32; 4], [3u32; 3]);
    let mut out = [0u32; 4];
    let e = batch::encode3_u32_soa(&xs, &ys, &zs, &mut out).unwrap_err();
    assert_eq!(
        e,
        morton::Error::LengthMismatch {
            what: "zs",
            expected: 4,
            got: 3
        }
    );
    assert_eq!(out, [0; 4], "nothing written on error");
    let mut short = [0u64; 2];
    assert!(batch::encode3_u64_soa(&xs, &ys, &xs, &mut short).is_err());
    let mut pts = [[0u32; 3]; 5];
    assert!(batch::decode3_u32_aos(&out, &mut pts).is_err());
}

#[test]
fn paths_report_availability() {
    assert!(Path::Scalar.is_available());
    assert!(Path::best().is_available());
    assert!(Path::available().any(|p| p == Path::best()));
    for path in Path::ALL {
        let mut out = [0u32; 1];
        let r = batch::encode2_u32_soa_with(path, &[1], &[1], &mut out);
        if path.is_available() {
            assert_eq!(r, Ok(()));
            assert_eq!(out, [3]);
        } else {
            assert_eq!(r, Err(morton::Error::PathUnavailable { path }));
        }
    }
}

/// The crate-root functions in a loop the compiler may vectorise (magic bits inline in
/// builds with AVX2) against the naive reference, every width and direction.
#[test]
fn scalar_loops_match_naive() {
    let n = 1000;
    let mut rng = testkit::Rng::new(0x0123_4567_89ab_cdef);
    let (xs, ys, zs): (Vec<u32>, Vec<u32>, Vec<u32>) = (rng.words(n), rng.words(n), rng.words(n));
    let k64: Vec<u64> = (0..n).map(|_| rng.next_u64()).collect();
    let k32: Vec<u32> = k64.iter().map(|&k| k as u32).collect();
    let e2: Vec<u32> = xs
        .iter()
        .zip(&ys)
        .map(|(&x, &y)| morton::encode2_u32(x, y))
        .collect();
    let e2w: Vec<u64> = xs
        .iter()
        .zip(&ys)
        .map(|(&x, &y)| morton::encode2_u64(x, y))
        .collect();
    let e3: Vec<u32> = (0..n)
        .map(|i| morton::encode3_u32(xs[i], ys[i], zs[i]))
        .collect();
    let e3w: Vec<u64> = (0..n)
        .map(|i| morton::encode3_u64(xs[i], ys[i], zs[i]))
        .collect();
    let d2: Vec<[u32; 2]> = k32.iter().map(|&k| morton::decode2_u32(k)).collect();
    let d2w: Vec<[u32; 2]> = k64.iter().map(|&k| morton::decode2_u64(k)).collect();
    let d3: Vec<[u32; 3]> = k32.iter().map(|&k| morton::decode3_u32(k)).collect();
    let d3w: Vec<[u32; 3]> = k64.iter().map(|&k| morton::decode3_u64(k)).collect();
    for i in 0..n {
        let (p2, p3) = ([xs[i], ys[i]], [xs[i], ys[i], zs[i]]);
        assert_eq!(e2[i] as u64, naive_encode(p2, 16), "{i}");
        assert_eq!(e2w[i], naive_encode(p2, 32), "{i}");
        assert_eq!(e3[i] as u64, naive_encode(p3, 10), "{i}");
        assert_eq!(e3w[i], naive_encode(p3, 21), "{i}");
        assert_eq!(d2[i], naive_decode::<2>(k32[i] as u64, 16), "{i}");
        assert_eq!(d2w[i], naive_decode::<2>(k64[i], 32), "{i}");
        assert_eq!(d3[i], naive_decode::<3>(k32[i] as u64, 10), "{i}");
        assert_eq!(d3w[i], naive_decode::<3>(k64[i], 21), "{i}");
    }
}

/// A long batch (many full vectors) on every path equals the scalar function.
#[test]
fn long_batches_equal_scalar() {
    let n = 10_007;
    let mut rng = testkit::Rng::new(0x9e37_79b9_7f4a_7c15);
    let xs: Vec<u32> = rng.words(n);
    let ys: Vec<u32> = rng.words(n);
    let zs: Vec<u32> = rng.words(n);
    for path in Path::available() {
        let mut o = vec![0u64; n];
        batch::encode3_u64_soa_with(path, &xs, &ys, &zs, &mut o).unwrap();
        for i in 0..n {
            assert_eq!(
                o[i],
                morton::encode3_u64(xs[i], ys[i], zs[i]),
                "{path:?} {i}"
            );
        }
        let mut o = vec![0u32; n];
        batch::encode3_u32_soa_with(path, &xs, &ys, &zs, &mut o).unwrap();
        for i in 0..n {
            assert_eq!(
                o[i],
                morton::encode3_u32(xs[i], ys[i], zs[i]),
                "{path:?} {i}"
            );
        }
    }
}
