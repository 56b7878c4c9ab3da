//! Roundtrip proptests and layout vectors for every record.

use glam::{DVec3, IVec3, Mat3, Vec3};
use proptest::prelude::*;
use staticscene::*;

fn lod_code() -> impl Strategy<Value = LodDistance> {
    (0u16..=0xfff).prop_map(|c| LodDistance::from_code(c).unwrap())
}

prop_compose! {
    fn fields()(
        filter in 0u8..8, flags in 0u8..4, setup in 0u16..4096, object in 0u32..(1 << 17),
        parent_bounds in 0u16..(1 << 15), child_bounds in 0u16..(1 << 15), matrix in 0u16..(1 << 14),
        a in lod_code(), b in lod_code(), c in lod_code(), d in lod_code(), group_end: bool,
    ) -> InstanceFields {
        InstanceFields {
            filter, flags, setup, object, parent_bounds, child_bounds, matrix,
            parent_lod: LodRange { min: a, max: b },
            child_lod: LodRange { min: c, max: d },
            group_end,
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn instance_roundtrip(f in fields()) {
        let q = QueryInstance::pack(&f).unwrap();
        prop_assert_eq!(q.try_unpack().unwrap(), f);
        prop_assert_eq!(QueryInstance::from_bytes(q.to_bytes()), q);
        // The accessors the query uses agree with the unpacked fields.
        prop_assert_eq!(q.object(), f.object);
        prop_assert_eq!(q.parent_lod_codes(), (u32::from(f.parent_lod.min.code()), u32::from(f.parent_lod.max.code())));
        prop_assert_eq!(q.child_lod_codes(), (u32::from(f.child_lod.min.code()), u32::from(f.child_lod.max.code())));
        prop_assert_eq!(q.with_group_end(!f.group_end).group_end(), !f.group_end);
    }

    #[test]
    fn any_word_without_the_spare_bit_decodes_and_repacks(v: u128) {
        let q = QueryInstance::from_u128(v);
        match q.try_unpack() {
            Ok(f) => prop_assert_eq!(QueryInstance::pack(&f).unwrap(), q),
            Err(e) => {
                prop_assert_eq!(e, Error::SpareBitSet);
                prop_assert!(v >> 127 == 1);
            }
        }
    }

    #[test]
    fn lod_distance_roundtrip(d in 0.0f32..130_000.0) {
        let c = LodDistance::from_metres(d).unwrap();
        let back = c.metres();
        // Within half a step, and the code is stable.
        let bound = if d < 4.0 { 1.0 / 128.0 } else { f64::from(d) / 512.0 };
        prop_assert!((f64::from(back) - f64::from(d)).abs() <= bound + 1e-9);
        prop_assert_eq!(LodDistance::from_metres(back).unwrap(), c);
    }

    #[test]
    fn half_aabb_contains_its_input(
        x in -60000.0f32..60000.0, y in -60000.0f32..60000.0, z in -60000.0f32..60000.0,
        ex in 0.0f32..5000.0, ey in 0.0f32..5000.0, ez in 0.0f32..5000.0,
    ) {
        let min = Vec3::new(x, y, z);
        let max = (min + Vec3::new(ex, ey, ez)).min(Vec3::splat(65504.0));
        let h = HalfAabb::from_aabb(min, max).unwrap();
        prop_assert!(h.min().cmple(min).all() && h.max().cmpge(max).all());
        // Tight: one f16 step at most (relative 2^-10, or the subnormal step).
        let tol = |v: Vec3| v.abs() * (1.0 / 1024.0) + Vec3::splat(1e-7);
        prop_assert!((min - h.min()).cmple(tol(min)).all());
        prop_assert!((h.max() - max).cmple(tol(max)).all());
        prop_assert_eq!(bytemuck::cast::<[u8; 12], HalfAabb>(bytemuck::cast(h)), h);
    }

    #[test]
    fn object_roundtrip(x in -1.0e8f64..1.0e8, y in -1.0e4f64..1.0e4, z in -1.0e8f64..1.0e8,
                        a in 0.0f32..6.3, s in 0.01f32..100.0, ignore: bool) {
        let p = DVec3::new(x, y, z);
        let m = Mat3::from_rotation_y(a);
        let o = QueryObject::from_world(p, m, s, ignore).unwrap();
        prop_assert_eq!(o.ignores_global_lod_scale(), ignore);
        prop_assert!((o.lod_scale() - s).abs() <= s / 1024.0);
        // Snapped plus remainder is the position, to f32 precision of the remainder.
        let back = o.snapped().as_dvec3() + o.object_to_snapped.translation().as_dvec3();
        prop_assert!((back - p).abs().max_element() < 1e-7);
        prop_assert!(o.object_to_snapped.translation().abs().max_element() <= 0.5);
        let bytes: [u8; 64] = bytemuck::cast(o);
        prop_assert_eq!(bytemuck::cast::<[u8; 64], QueryObject>(bytes), o);
    }

    #[test]
    fn setup_roundtrip(x in -1e5f32..1e5, e in 0.0f32..1e3, h: u64) {
        let s = QuerySetup::new(Vec3::splat(x), Vec3::splat(x + e), h).unwrap();
        let bytes: [u8; 32] = bytemuck::cast(s);
        prop_assert_eq!(u64::from_le_bytes(bytes[24..32].try_into().unwrap()), h);
        prop_assert_eq!(bytemuck::cast::<[u8; 32], QuerySetup>(bytes), s);
        prop_assert_eq!((s.min(), s.max()), (Vec3::splat(x), Vec3::splat(x + e)));
    }
}

#[test]
fn layout_vectors() {
    // QueryObject: matrix rows, snapped position at 48, LOD scale f16 and flags at 60.
    let o = QueryObject::new(
        Transform4x3::IDENTITY.with_translation(Vec3::new(0.25, -0.5, 0.125)),
        IVec3::new(7, -8, 9),
        2.0,
        true,
    )
    .unwrap();
    let b: [u8; 64] = bytemuck::cast(o);
    assert_eq!(&b[0..4], &1.0f32.to_le_bytes());
    assert_eq!(&b[12..16], &0.25f32.to_le_bytes());
    assert_eq!(&b[48..52], &7i32.to_le_bytes());
    assert_eq!(&b[56..60], &9i32.to_le_bytes());
    assert_eq!(&b[60..64], &[0x00, 0x40, 0x01, 0x00]); // f16 2.0 = 0x4000, flag bit 16
    // QuerySetup: min, max, handle.
    let s = QuerySetup::new(
        Vec3::new(1.0, 2.0, 3.0),
        Vec3::new(4.0, 5.0, 6.0),
        0x0102_0304_0506_0708,
    )
    .unwrap();
    let b: [u8; 32] = bytemuck::cast(s);
    assert_eq!(&b[20..24], &6.0f32.to_le_bytes());
    assert_eq!(&b[24..32], &[8, 7, 6, 5, 4, 3, 2, 1]);
    // HalfAabb: min xyz, max xyz as f16.
    let h = HalfAabb::from_aabb(Vec3::new(-1.0, 0.0, 0.5), Vec3::new(1.0, 2.0, 65504.0)).unwrap();
    let b: [u8; 12] = bytemuck::cast(h);
    assert_eq!(
        b,
        [
            0x00, 0xbc, 0x00, 0x00, 0x00, 0x38, 0x00, 0x3c, 0x00, 0x40, 0xff, 0x7b
        ]
    );
    // DrawableSetupBatch: key, setup, sphere, first, flags, count, stride.
    let batch = DrawableSetupBatch {
        sort_key: sort_key(0xaabb_ccdd_1122_3344, 2.0),
        setup: 5,
        sphere: [1.0, 2.0, 3.0, 4.0],
        first_instance: 6,
        flags: STATE_FADING,
        count: 7,
        stride: 64,
    };
    let b: [u8; 48] = bytemuck::cast(batch);
    assert_eq!(&b[0..8], &0x1122_3344_4000_0000u64.to_le_bytes());
    assert_eq!(
        &b[32..48],
        &[6, 0, 0, 0, 1, 0, 0, 0, 7, 0, 0, 0, 64, 0, 0, 0]
    );
    // DrawableSetupInstance: state then transform.
    let i = DrawableSetupInstance {
        state: InstanceState {
            fade: 0.5,
            flags: 1,
            tile: 2,
            instance: 3,
        },
        local_to_floating: Transform4x3::IDENTITY,
    };
    let b: [u8; 64] = bytemuck::cast(i);
    assert_eq!(
        &b[0..16],
        &[0, 0, 0, 0x3f, 1, 0, 0, 0, 2, 0, 0, 0, 3, 0, 0, 0]
    );
    assert_eq!(&b[16..20], &1.0f32.to_le_bytes());
    assert_eq!(size_of::<DrawableSetupInstancePrev>(), 112);
    assert_eq!(size_of::<QueryParams>(), 320);
}
