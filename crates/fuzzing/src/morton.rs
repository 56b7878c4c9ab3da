//! Fuzz bodies for the `morton` crate: decoding arbitrary words and encode-decode
//! roundtrips, every width, every batch path, the Hilbert curve, the quantiser and the sort.

use glam::Vec3;
use morton::naive::{low, naive_encode};
use morton::{Error, Path, Quantizer3, batch, hilbert};

use crate::Input;

/// Decodes arbitrary words with every width, scalar and batch on every path, checks that
/// re-encoding gives back the word's used bits, and the same for Hilbert keys.
pub fn morton_decode(data: &[u8]) {
    let mut input = Input::new(data);
    let mut k32s = Vec::new();
    let mut k64s = Vec::new();
    while input.remaining() > 0 && k64s.len() < 64 {
        k32s.push(input.u32());
        k64s.push(input.u64());
    }
    for (&k32, &k64) in k32s.iter().zip(&k64s) {
        let [x, y] = morton::decode2_u32(k32);
        assert_eq!(morton::encode2_u32(x, y), k32);
        assert_eq!(naive_encode([x, y], 16), k32 as u64);
        let [x, y] = morton::decode2_u64(k64);
        assert_eq!(morton::encode2_u64(x, y), k64);
        let [x, y, z] = morton::decode3_u32(k32);
        assert!(x < 1024 && y < 1024 && z < 1024);
        assert_eq!(morton::encode3_u32(x, y, z), k32 & 0x3fff_ffff);
        assert_eq!(naive_encode([x, y, z], 10), (k32 & 0x3fff_ffff) as u64);
        let [x, y, z] = morton::decode3_u64(k64);
        assert!(x < 1 << 21 && y < 1 << 21 && z < 1 << 21);
        assert_eq!(morton::encode3_u64(x, y, z), k64 & !(1 << 63));
        assert_eq!(morton::magic::decode3_u64(k64), [x, y, z]);

        let [x, y] = hilbert::decode2_u32(k32);
        assert_eq!(hilbert::encode2_u32(x, y), k32);
        let [x, y] = hilbert::decode2_u64(k64);
        assert_eq!(hilbert::encode2_u64(x, y), k64);
        let [x, y, z] = hilbert::decode3_u32(k32);
        assert_eq!(hilbert::encode3_u32(x, y, z), k32 & 0x3fff_ffff);
        let [x, y, z] = hilbert::decode3_u64(k64);
        assert_eq!(hilbert::encode3_u64(x, y, z), k64 & !(1 << 63));
    }
    let n = k32s.len();
    for path in Path::available() {
        let (mut a, mut b, mut c) = (vec![0; n], vec![0; n], vec![0; n]);
        batch::decode3_u32_soa_with(path, &k32s, &mut a, &mut b, &mut c).unwrap();
        let mut p3 = vec![[0u32; 3]; n];
        batch::decode3_u64_aos_with(path, &k64s, &mut p3).unwrap();
        let mut p2 = vec![[0u32; 2]; n];
        batch::decode2_u32_aos_with(path, &k32s, &mut p2).unwrap();
        for i in 0..n {
            assert_eq!([a[i], b[i], c[i]], morton::decode3_u32(k32s[i]), "{path:?}");
            assert_eq!(p3[i], morton::decode3_u64(k64s[i]), "{path:?}");
            assert_eq!(p2[i], morton::decode2_u32(k32s[i]), "{path:?}");
        }
        batch::decode2_u64_soa_with(path, &k64s, &mut a, &mut b).unwrap();
        for i in 0..n {
            assert_eq!([a[i], b[i]], morton::decode2_u64(k64s[i]), "{path:?}");
        }
    }
}

/// Encodes arbitrary coordinates with every width and decodes them back, on every path;
/// checks the `try_` encoders' range errors, Hilbert roundtrips, the quantiser on
/// arbitrary floats (NaN, infinities, any bounds) and the sort of the resulting keys.
pub fn morton_roundtrip(data: &[u8]) {
    let mut input = Input::new(data);
    let mut pts = Vec::new();
    while input.remaining() > 0 && pts.len() < 64 {
        pts.push([input.u32(), input.u32(), input.u32()]);
    }
    for &[x, y, z] in &pts {
        assert_eq!(
            morton::decode2_u32(morton::encode2_u32(x, y)),
            [low(x, 16), low(y, 16)]
        );
        assert_eq!(morton::decode2_u64(morton::encode2_u64(x, y)), [x, y]);
        let k = morton::encode3_u32(x, y, z);
        assert_eq!(k as u64, naive_encode([x, y, z], 10));
        assert_eq!(morton::decode3_u32(k), [low(x, 10), low(y, 10), low(z, 10)]);
        let k = morton::encode3_u64(x, y, z);
        assert_eq!(k, naive_encode([x, y, z], 21));
        assert_eq!(morton::decode3_u64(k), [low(x, 21), low(y, 21), low(z, 21)]);
        let fits10 = x < 1024 && y < 1024 && z < 1024;
        match morton::try_encode3_u32(x, y, z) {
            Ok(k) => assert!(fits10 && k == morton::encode3_u32(x, y, z)),
            Err(Error::CoordinateTooLarge { max, .. }) => assert!(!fits10 && max == 1023),
            Err(e) => panic!("unexpected {e}"),
        }
        assert_eq!(
            morton::try_encode3_u64(x, y, z).is_ok(),
            x.max(y).max(z) < 1 << 21
        );
        assert_eq!(morton::try_encode2_u32(x, y).is_ok(), x.max(y) < 1 << 16);

        assert_eq!(
            hilbert::decode3_u32(hilbert::encode3_u32(x, y, z)),
            [low(x, 10), low(y, 10), low(z, 10)]
        );
        assert_eq!(
            hilbert::decode3_u64(hilbert::encode3_u64(x, y, z)),
            [low(x, 21), low(y, 21), low(z, 21)]
        );
        assert_eq!(hilbert::decode2_u64(hilbert::encode2_u64(x, y)), [x, y]);
        assert_eq!(
            hilbert::decode2_u32(hilbert::encode2_u32(x, y)),
            [low(x, 16), low(y, 16)]
        );
    }

    // Batch paths against the scalar functions.
    let n = pts.len();
    let xs: Vec<u32> = pts.iter().map(|p| p[0]).collect();
    let ys: Vec<u32> = pts.iter().map(|p| p[1]).collect();
    let zs: Vec<u32> = pts.iter().map(|p| p[2]).collect();
    for path in Path::available() {
        let (mut o32, mut o64) = (vec![0u32; n], vec![0u64; n]);
        batch::encode3_u32_aos_with(path, &pts, &mut o32).unwrap();
        batch::encode3_u64_soa_with(path, &xs, &ys, &zs, &mut o64).unwrap();
        for i in 0..n {
            assert_eq!(o32[i], morton::encode3_u32(xs[i], ys[i], zs[i]), "{path:?}");
            assert_eq!(o64[i], morton::encode3_u64(xs[i], ys[i], zs[i]), "{path:?}");
        }
        batch::encode2_u32_soa_with(path, &xs, &ys, &mut o32).unwrap();
        batch::encode2_u64_soa_with(path, &xs, &ys, &mut o64).unwrap();
        for i in 0..n {
            assert_eq!(o32[i], morton::encode2_u32(xs[i], ys[i]), "{path:?}");
            assert_eq!(o64[i], morton::encode2_u64(xs[i], ys[i]), "{path:?}");
        }
        hilbert::encode3_u32_soa_with(path, &xs, &ys, &zs, &mut o32).unwrap();
        hilbert::encode3_u64_soa_with(path, &xs, &ys, &zs, &mut o64).unwrap();
        for i in 0..n {
            assert_eq!(
                o32[i],
                hilbert::encode3_u32(xs[i], ys[i], zs[i]),
                "{path:?}"
            );
            assert_eq!(
                o64[i],
                hilbert::encode3_u64(xs[i], ys[i], zs[i]),
                "{path:?}"
            );
        }
    }

    // The same words as floats: a box from the first two points, any bits per axis.
    let floats: Vec<Vec3> = pts
        .iter()
        .map(|p| {
            Vec3::new(
                f32::from_bits(p[0]),
                f32::from_bits(p[1]),
                f32::from_bits(p[2]),
            )
        })
        .collect();
    if floats.len() >= 2 {
        let bits = 1 + xs[0] % 21;
        let (lo, hi) = (floats[0].min(floats[1]), floats[0].max(floats[1]));
        match Quantizer3::new(lo, hi, bits) {
            Ok(q) => quantizer_checks(&q, &floats[2..]),
            Err(Error::BadBounds { axis, min, max }) => {
                assert!(
                    !(min.is_finite() && max.is_finite() && min <= max),
                    "axis {axis}"
                );
            }
            Err(e) => panic!("unexpected {e}"),
        }
    }
}

fn quantizer_checks(q: &Quantizer3, pts: &[Vec3]) {
    let top = (1u32 << q.bits()) - 1;
    let first_nan = pts.iter().position(|p| p.is_nan());
    for &p in pts {
        match q.quantize(p) {
            Ok(c) => {
                assert!(!p.is_nan());
                assert!(c.max_element() <= top);
                // Monotone per axis: the box corners bound every cell.
                for axis in 0..3 {
                    if p[axis] <= q.min()[axis] {
                        assert_eq!(c[axis], 0);
                    }
                    if p[axis] >= q.max()[axis] && q.scale()[axis] > 0.0 {
                        assert_eq!(c[axis], top);
                    }
                }
            }
            Err(Error::NanPosition { index: 0 }) => assert!(p.is_nan()),
            Err(e) => panic!("unexpected {e}"),
        }
    }
    let mut k64 = vec![0u64; pts.len()];
    let r = q.morton_u64_slice(pts, &mut k64);
    match first_nan {
        None => assert_eq!(r, Ok(())),
        Some(i) => assert_eq!(r, Err(Error::NanPosition { index: i })),
    }
    for (k, &p) in k64.iter().zip(pts) {
        let c = q.quantize_unchecked_nan(p);
        assert_eq!(*k, morton::encode3_u64(c.x, c.y, c.z));
    }
    let mut k32 = vec![0u32; pts.len()];
    let r = q.morton_u32_slice(pts, &mut k32);
    if q.bits() > 10 {
        assert_eq!(
            r,
            Err(Error::BadBits {
                bits: q.bits(),
                max: 10
            })
        );
    }
    // The sort permutation orders the keys, stably.
    let perm = morton::sort_permutation(&k64).unwrap();
    let mut seen = vec![false; perm.len()];
    for w in perm.windows(2) {
        let (a, b) = (w[0] as usize, w[1] as usize);
        assert!(k64[a] < k64[b] || (k64[a] == k64[b] && a < b));
    }
    for &i in &perm {
        assert!(!seen[i as usize]);
        seen[i as usize] = true;
    }
}
