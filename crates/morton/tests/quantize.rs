//! Quantisation: edges (box corners, clamping, infinities, flat axes, NaN, bad bounds),
//! and an f64 reference for the cell of random points.

use glam::{UVec2, UVec3, Vec2, Vec3};
use morton::{Error, Path, Quantizer2, Quantizer3};
use proptest::prelude::*;

/// The reference cell in f64: floor((p - min) * 2^bits / (max - min)) clamped, and whether
/// the f32 arithmetic may round across a boundary here (within 1e-3 cells of one).
fn reference(p: f32, min: f32, max: f32, bits: u32) -> (u32, bool) {
    let cells = (1u64 << bits) as f64;
    let extent = max as f64 - min as f64;
    if extent == 0.0 {
        return (0, false);
    }
    let t = (p as f64 - min as f64) * cells / extent;
    let near = (t - t.round()).abs() < 1e-3 * t.abs().max(1.0);
    (t.floor().clamp(0.0, cells - 1.0) as u32, near)
}

#[test]
fn corners_and_centre() {
    let q = Quantizer3::new(Vec3::new(-10.0, 0.0, 5.0), Vec3::new(10.0, 100.0, 6.0), 10).unwrap();
    assert_eq!(q.quantize(q.min()).unwrap(), UVec3::ZERO);
    assert_eq!(q.quantize(q.max()).unwrap(), UVec3::splat(1023));
    assert_eq!(
        q.quantize(Vec3::new(0.0, 50.0, 5.5)).unwrap(),
        UVec3::splat(512)
    );
    // Just below the middle lands in the cell before.
    assert_eq!(
        q.quantize(Vec3::new(-0.001, 49.99, 5.4999)).unwrap(),
        UVec3::splat(511)
    );
    assert_eq!(
        q.cell_size(),
        Vec3::new(20.0 / 1024.0, 100.0 / 1024.0, 1.0 / 1024.0)
    );
    let c = q.cell_center(UVec3::new(0, 1023, 512));
    assert!(
        (c - Vec3::new(
            -10.0 + 10.0 / 1024.0,
            100.0 - 50.0 / 1024.0,
            5.5 + 0.5 / 1024.0
        ))
        .abs()
        .max_element()
            < 1e-5
    );
    assert_eq!(q.morton_u32(q.max()).unwrap(), 0x3fff_ffff);
    assert_eq!(q.morton_u64(q.max()).unwrap(), 0x3fff_ffff);
}

#[test]
fn out_of_range_clamps_and_infinities_clamp() {
    let q = Quantizer3::new(Vec3::ZERO, Vec3::ONE, 4).unwrap();
    assert_eq!(
        q.quantize(Vec3::new(-5.0, 2.0, 0.5)).unwrap(),
        UVec3::new(0, 15, 8)
    );
    assert_eq!(
        q.quantize(Vec3::new(f32::NEG_INFINITY, f32::INFINITY, f32::MAX))
            .unwrap(),
        UVec3::new(0, 15, 15)
    );
    assert_eq!(q.quantize(Vec3::splat(f32::MIN)).unwrap(), UVec3::ZERO);
    // Huge boxes: (p - min) overflows f32 and still clamps.
    let q = Quantizer3::new(Vec3::splat(-f32::MAX), Vec3::splat(f32::MAX), 21).unwrap();
    assert_eq!(
        q.quantize(Vec3::splat(f32::MAX)).unwrap(),
        UVec3::splat((1 << 21) - 1)
    );
    assert_eq!(q.quantize(Vec3::ZERO).unwrap(), UVec3::splat(1 << 20));
    assert_eq!(q.quantize(Vec3::splat(-f32::MAX)).unwrap(), UVec3::ZERO);
}

#[test]
fn flat_and_tiny_axes() {
    // A flat scene: y has no extent, every y lands in cell 0.
    let q = Quantizer3::new(Vec3::new(0.0, 3.0, 0.0), Vec3::new(1.0, 3.0, 1.0), 10).unwrap();
    assert_eq!(q.scale().y, 0.0);
    for y in [3.0, -1e30, 1e30, f32::INFINITY, f32::NEG_INFINITY] {
        assert_eq!(
            q.quantize(Vec3::new(1.0, y, 0.0)).unwrap(),
            UVec3::new(1023, 0, 0)
        );
    }
    // Axes too thin for f32 cells (a subnormal extent, or 1e-38 at 20 bits) count as
    // flat; one just thick enough still puts max in the last cell.
    let tiny = f32::from_bits(1);
    let q = Quantizer3::new(Vec3::ZERO, Vec3::new(tiny, 1e-38, 1e-30), 20).unwrap();
    assert_eq!(q.scale().x, 0.0);
    assert_eq!(q.scale().y, 0.0);
    assert!(q.scale().z > 0.0);
    assert_eq!(
        q.quantize(Vec3::new(tiny, 1e-38, 1e-30)).unwrap(),
        UVec3::new(0, 0, (1 << 20) - 1)
    );
    assert_eq!(q.quantize(Vec3::splat(-1.0)).unwrap(), UVec3::ZERO);
    // The fuzzer's case: a box of about 1e-37 at 20 bits.
    let q = Quantizer3::new(
        Vec3::new(0.0, -9.489765e-38, 0.0),
        Vec3::new(1.0, 0.0, 1.0),
        20,
    )
    .unwrap();
    assert_eq!(q.quantize(Vec3::new(1.0, 0.0, 1.0)).unwrap().y, 0);
}

#[test]
fn nan_is_an_error_and_batches_name_the_first() {
    let q = Quantizer3::new(Vec3::ZERO, Vec3::ONE, 10).unwrap();
    assert_eq!(
        q.quantize(Vec3::new(0.5, f32::NAN, 0.5)),
        Err(Error::NanPosition { index: 0 })
    );
    assert_eq!(
        q.quantize_unchecked_nan(Vec3::new(1.0, f32::NAN, 0.5)),
        UVec3::new(1023, 0, 512)
    );
    assert!(q.morton_u32(Vec3::NAN).is_err());
    let mut points = vec![Vec3::splat(0.5); 100];
    points[37].z = f32::NAN;
    points[80].x = -f32::NAN;
    for path in Path::available() {
        let mut keys = vec![7u32; 100];
        let e = q
            .morton_u32_slice_with(path, &points, &mut keys)
            .unwrap_err();
        assert_eq!(e, Error::NanPosition { index: 37 });
        assert_eq!(keys[36], morton::encode3_u32(512, 512, 512));
        assert_eq!(
            keys[37],
            morton::encode3_u32(512, 512, 0),
            "NaN component -> cell 0"
        );
        assert_eq!(keys[80], morton::encode3_u32(0, 512, 512));
        let mut keys = vec![7u64; 100];
        let e = q
            .morton_u64_slice_with(path, &points, &mut keys)
            .unwrap_err();
        assert_eq!(e, Error::NanPosition { index: 37 });
        assert_eq!(keys[37], morton::encode3_u64(512, 512, 0));
    }
    let mut cells = vec![UVec3::ZERO; 100];
    assert_eq!(
        q.quantize_slice(&points, &mut cells),
        Err(Error::NanPosition { index: 37 })
    );
    assert_eq!(cells[37], UVec3::new(512, 512, 0));
}

#[test]
fn bad_configurations_are_errors() {
    let (lo, hi) = (Vec3::ZERO, Vec3::ONE);
    assert_eq!(
        Quantizer3::new(lo, hi, 0),
        Err(Error::BadBits { bits: 0, max: 21 })
    );
    assert_eq!(
        Quantizer3::new(lo, hi, 22),
        Err(Error::BadBits { bits: 22, max: 21 })
    );
    assert!(Quantizer3::new(lo, hi, 21).is_ok());
    assert!(matches!(
        Quantizer3::new(hi, lo, 10),
        Err(Error::BadBounds { axis: 0, .. })
    ));
    assert!(matches!(
        Quantizer3::new(Vec3::new(0.0, 0.0, f32::NAN), hi, 10),
        Err(Error::BadBounds { axis: 2, .. })
    ));
    assert!(matches!(
        Quantizer3::new(lo, Vec3::new(1.0, f32::INFINITY, 1.0), 10),
        Err(Error::BadBounds { axis: 1, .. })
    ));
    // 32-bit keys need <= 10 bits per axis.
    let q = Quantizer3::new(lo, hi, 11).unwrap();
    assert_eq!(
        q.morton_u32(Vec3::ZERO),
        Err(Error::BadBits { bits: 11, max: 10 })
    );
    let mut out = [0u32; 1];
    assert!(q.morton_u32_slice(&[Vec3::ZERO], &mut out).is_err());
    assert!(q.morton_u64(Vec3::ZERO).is_ok());
    // Length mismatch.
    let q = Quantizer3::new(lo, hi, 10).unwrap();
    let mut out = [0u32; 2];
    assert_eq!(
        q.morton_u32_slice(&[Vec3::ZERO], &mut out),
        Err(Error::LengthMismatch {
            what: "out",
            expected: 1,
            got: 2
        })
    );
    let q2 = Quantizer2::new(Vec2::ZERO, Vec2::ONE, 17).unwrap();
    assert_eq!(
        q2.morton_u32(Vec2::ZERO),
        Err(Error::BadBits { bits: 17, max: 16 })
    );
    assert!(Quantizer2::new(Vec2::ZERO, Vec2::ONE, 22).is_err());
}

#[test]
fn from_points_covers_and_skips_nan() {
    let pts = [
        Vec3::new(1.0, -2.0, 3.0),
        Vec3::NAN,
        Vec3::new(-1.0, 2.0, 3.0),
    ];
    let q = Quantizer3::from_points(&pts, 10).unwrap();
    assert_eq!(q.min(), Vec3::new(-1.0, -2.0, 3.0));
    assert_eq!(q.max(), Vec3::new(1.0, 2.0, 3.0));
    let q = Quantizer3::from_points(&[], 10).unwrap();
    assert_eq!((q.min(), q.max()), (Vec3::ZERO, Vec3::ZERO));
}

#[test]
fn quantizer2_matches_3d_on_a_plane() {
    let q2 = Quantizer2::new(Vec2::new(-1.0, 2.0), Vec2::new(3.0, 4.0), 16).unwrap();
    assert_eq!(
        q2.quantize(Vec2::new(3.0, 2.0)).unwrap(),
        UVec2::new(65535, 0)
    );
    assert_eq!(q2.morton_u32(Vec2::new(3.0, 4.0)).unwrap(), u32::MAX);
    assert_eq!(
        q2.morton_u64(Vec2::new(1.0, 3.0)).unwrap(),
        morton::encode2_u64(32768, 32768)
    );
    let pts = [
        Vec2::new(0.0, 3.0),
        Vec2::new(f32::NAN, 3.0),
        Vec2::new(9.0, -9.0),
    ];
    for path in Path::available() {
        let mut k = [0u32; 3];
        assert_eq!(
            q2.morton_u32_slice_with(path, &pts, &mut k),
            Err(Error::NanPosition { index: 1 })
        );
        assert_eq!(k[0], q2.morton_u32(pts[0]).unwrap());
        assert_eq!(k[2], morton::encode2_u32(65535, 0));
        let mut k = [0u64; 3];
        assert!(q2.morton_u64_slice_with(path, &pts, &mut k).is_err());
        assert_eq!(k[0], q2.morton_u64(pts[0]).unwrap());
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn cell_matches_f64_reference(
        lo in prop::array::uniform3(-1e4f32..1e4),
        ext in prop::array::uniform3(0.0f32..1e4),
        p in prop::array::uniform3(-2e4f32..2e4),
        bits in 1u32..=21,
    ) {
        let min = Vec3::from_array(lo);
        let max = min + Vec3::from_array(ext);
        let q = Quantizer3::new(min, max, bits).unwrap();
        let c = q.quantize(Vec3::from_array(p)).unwrap();
        for axis in 0..3 {
            let (want, near) = reference(p[axis], min[axis], max[axis], bits);
            if near {
                prop_assert!(c[axis].abs_diff(want) <= 1, "axis {} got {} want {}", axis, c[axis], want);
            } else {
                prop_assert_eq!(c[axis], want, "axis {}", axis);
            }
        }
    }

    #[test]
    fn batch_paths_equal_single_calls(
        pts in proptest::collection::vec(prop::array::uniform3(-2.0f32..2.0), 0..80),
        bits in 1u32..=10,
    ) {
        let pts: Vec<Vec3> = pts.into_iter().map(Vec3::from_array).collect();
        let q = Quantizer3::new(Vec3::splat(-1.0), Vec3::splat(1.5), bits).unwrap();
        for path in Path::available() {
            let mut k32 = vec![0u32; pts.len()];
            let mut k64 = vec![0u64; pts.len()];
            q.morton_u32_slice_with(path, &pts, &mut k32).unwrap();
            q.morton_u64_slice_with(path, &pts, &mut k64).unwrap();
            for (i, &p) in pts.iter().enumerate() {
                prop_assert_eq!(k32[i], q.morton_u32(p).unwrap());
                prop_assert_eq!(k64[i], q.morton_u64(p).unwrap());
            }
        }
        let q2 = Quantizer2::new(Vec2::splat(-1.0), Vec2::splat(1.5), bits).unwrap();
        let p2: Vec<Vec2> = pts.iter().map(|p| p.truncate()).collect();
        for path in Path::available() {
            let mut k32 = vec![0u32; p2.len()];
            q2.morton_u32_slice_with(path, &p2, &mut k32).unwrap();
            for (i, &p) in p2.iter().enumerate() {
                prop_assert_eq!(k32[i], q2.morton_u32(p).unwrap());
            }
        }
    }
}
