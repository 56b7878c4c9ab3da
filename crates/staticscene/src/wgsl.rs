//! The WGSL twin of the records and the per-thread tests: `staticscene::query`
//! ([`QUERY`], `src/wgsl/query.wgsl`), a binding-free library module (structs, `const`s,
//! functions, every name prefixed `staticscene_` / `STATICSCENE_` / `Staticscene`) that the
//! passes import with `#import staticscene::query` (see the `shader` crate):
//! `staticscene::query_pass` ([`QUERY_PASS_MODULE`], the query) and
//! `staticscene::hiz_pass` ([`HIZ_PASS_MODULE`], one HiZ level), described in
//! [`pass`](crate::pass). naga validates them in the unit tests below with `Caps::CORE`
//! (no optional capability); `tests/device.rs` runs them against the CPU twin. Each `const` equals the Rust constant of the same meaning and
//! each struct has the Rust struct's size and member offsets (the unit tests read them
//! back).
//!
//! | WGSL | takes | gives |
//! | --- | --- | --- |
//! | `StaticsceneQueryInstance`, `StaticsceneQueryObject`, `StaticsceneQuerySetup`, `StaticsceneHalfAabb`, `StaticsceneTransform` | - | the tile's records ([`records`](crate::records)) |
//! | `StaticsceneDrawableSetupInstance`, `StaticsceneDrawableSetupBatch`, `StaticsceneInstanceState` | - | the output ([`output`](crate::output)) |
//! | `StaticsceneQueryParams` | - | the uniform block ([`QueryParams`](crate::QueryParams)) |
//! | `staticscene_filter` / `_flags` / `_setup` / `_object` / `_parent_bounds` / `_child_bounds` / `_matrix` / `_group_end` | instance words | the field |
//! | `staticscene_parent_lod(q)` / `staticscene_child_lod(q)` | instance words | `vec2(min, max)` codes |
//! | `staticscene_decode_lod(code)` | finite code | metres, exact |
//! | `staticscene_lod_selects(codes, d2, scale2)` | codes, squared distance, squared scale | the LOD test (infinity code tested explicitly) |
//! | `staticscene_f16(bits)` | f16 bits | f32, exact for finite values |
//! | `staticscene_half_box(b)`, `staticscene_setup_box(s)` | record | `StaticsceneAabb` |
//! | `staticscene_lod_scale(o)`, `staticscene_ignores_global_lod_scale(o)` | object | scale, flag |
//! | `staticscene_object_to_floating(o, origin)` | object, snapped origin | transform |
//! | `staticscene_transform_point`, `staticscene_mul`, `staticscene_transform_aabb` | transforms | as [`Transform4x3`](crate::Transform4x3) |
//! | `staticscene_dist2(p, box)` | point, box | squared distance |
//! | `staticscene_box_outside_frustum(planes, box)` | planes, box | the conservative frustum test |
//! | `staticscene_fade_step(prev, n, lod, in_frustum)` | fade state | next fade state |
//! | `staticscene_sort_key(setup, depth)` | handle words, nearest depth | key words (low, high) |

use shader::Module;

/// `staticscene::query`: the records, the output and the per-thread tests (see the
/// [module docs](self)).
pub const QUERY: Module = Module::new("staticscene::query", include_str!("wgsl/query.wgsl"));

/// `staticscene::query_pass`: the query compute pass ([`QUERY_PASS`](crate::pass::QUERY_PASS)).
pub const QUERY_PASS_MODULE: Module = Module::new(
    "staticscene::query_pass",
    include_str!("wgsl/query_pass.wgsl"),
);

/// `staticscene::hiz_pass`: one level of the HiZ pyramid ([`HIZ_PASS`](crate::pass::HIZ_PASS)).
pub const HIZ_PASS_MODULE: Module =
    Module::new("staticscene::hiz_pass", include_str!("wgsl/hiz_pass.wgsl"));

/// This crate's modules, for `shader::compose`'s library.
pub const MODULES: &[Module] = &[QUERY, QUERY_PASS_MODULE, HIZ_PASS_MODULE];

/// Every module list the query pass imports from.
pub const LIBRARY: &[&[Module]] = &[wave::wgsl::MODULES, MODULES];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::*;
    use shadercheck::{Caps, const_f32, const_u32};

    #[test]
    fn query_pass_description_matches_its_module() {
        use crate::pass::*;
        shadercheck::check_pass(&QUERY_PASS, |f| {
            if f.contains(&"subgroups") {
                Caps::SUBGROUP
            } else {
                Caps::CORE
            }
        });
        let m = shadercheck::assert_composed(LIBRARY, QUERY_PASS_MODULE.name, &[], Caps::CORE);
        shadercheck::assert_prefixed(QUERY_PASS_MODULE.name, &m, "staticscene", &["wave"], false);
        for (name, v) in [
            ("STATICSCENE_QUERY_WORKGROUP", QUERY_WORKGROUP),
            ("STATICSCENE_MAX_WORKGROUPS_X", shader::MAX_WORKGROUPS_X),
            ("STATICSCENE_JOB_SNAP_FADE", JOB_FLAG_SNAP_FADE),
            ("STATICSCENE_JOB_LOD_UNLESS_LIVE", JOB_FLAG_LOD_UNLESS_LIVE),
            ("STATICSCENE_OBJECT_WORDS", OBJECT_WORDS as u32),
            ("STATICSCENE_SETUP_WORDS", SETUP_WORDS as u32),
            ("STATICSCENE_TRANSFORM_WORDS", TRANSFORM_WORDS as u32),
            ("STATICSCENE_BOUNDS_WORDS", BOUNDS_WORDS as u32),
            ("STATICSCENE_STAT_THREADS", STAT_THREADS as u32),
            ("STATICSCENE_STAT_FILTER", STAT_FILTER as u32),
            ("STATICSCENE_STAT_LOD", STAT_LOD as u32),
            ("STATICSCENE_STAT_FRUSTUM", STAT_FRUSTUM as u32),
            ("STATICSCENE_STAT_SIZE", STAT_SIZE as u32),
            ("STATICSCENE_STAT_OCCLUSION", STAT_OCCLUSION as u32),
            ("STATICSCENE_STAT_FADED_OUT", STAT_FADED_OUT as u32),
            ("STATICSCENE_STAT_INVALID", STAT_INVALID as u32),
            ("STATICSCENE_STAT_VISIBLE", STAT_VISIBLE as u32),
            ("STATICSCENE_STAT_DROPPED", STAT_DROPPED as u32),
            ("STATICSCENE_STAT_DRAWN_EARLY", STAT_DRAWN_EARLY as u32),
            ("STATICSCENE_STAT_COUNT", STAT_COUNT as u32),
        ] {
            assert_eq!(const_u32(&m, name), Some(v), "{name}");
        }
        shadercheck::assert_struct_layout(
            &m,
            "StaticsceneGpuJob",
            size_of::<GpuJob>(),
            &shadercheck::members!(GpuJob {
                tile,
                first,
                count,
                flags,
                instance_base,
                records,
                objects,
                setups,
                transforms,
                bounds,
                first_wave,
                cluster,
                last_run,
                serial,
                fade_base,
                pad
            }),
        );
        shadercheck::assert_struct_layout(
            &m,
            "StaticsceneQueryCounters",
            size_of::<QueryCounters>(),
            &shadercheck::members!(QueryCounters {
                instances,
                batches,
                pad0,
                pad1,
                stats
            }),
        );
        // The record block's words are the records' bytes.
        assert_eq!(OBJECT_WORDS * 4, size_of::<QueryObject>());
        assert_eq!(SETUP_WORDS * 4, size_of::<QuerySetup>());
        assert_eq!(TRANSFORM_WORDS * 4, size_of::<Transform4x3>());
        assert_eq!(BOUNDS_WORDS * 4, size_of::<HalfAabb>());
    }

    #[test]
    fn hiz_pass_description_matches_its_module() {
        use crate::pass::*;
        shadercheck::check_pass(&HIZ_PASS, |_| Caps::CORE);
        let m = shadercheck::assert_composed(LIBRARY, HIZ_PASS_MODULE.name, &[], Caps::CORE);
        shadercheck::assert_struct_layout(
            &m,
            "StaticsceneHizStep",
            size_of::<HizStep>(),
            &shadercheck::members!(HizStep {
                level,
                reversed,
                pad
            }),
        );
    }

    fn module() -> naga::Module {
        shadercheck::assert_composed(&[MODULES], QUERY.name, &[], Caps::CORE)
    }

    #[test]
    fn constants_match_rust() {
        let m = module();
        for (name, v) in [
            ("STATICSCENE_FILTER_SHIFT", FILTER_SHIFT),
            ("STATICSCENE_FLAGS_SHIFT", FLAGS_SHIFT),
            ("STATICSCENE_SETUP_SHIFT", SETUP_SHIFT),
            ("STATICSCENE_OBJECT_SHIFT", OBJECT_SHIFT),
            ("STATICSCENE_PARENT_BOUNDS_SHIFT", PARENT_BOUNDS_SHIFT),
            ("STATICSCENE_CHILD_BOUNDS_SHIFT", CHILD_BOUNDS_SHIFT),
            ("STATICSCENE_MATRIX_SHIFT", MATRIX_SHIFT),
            ("STATICSCENE_PARENT_LOD_MIN_SHIFT", PARENT_LOD_MIN_SHIFT),
            ("STATICSCENE_PARENT_LOD_MAX_SHIFT", PARENT_LOD_MAX_SHIFT),
            ("STATICSCENE_CHILD_LOD_MIN_SHIFT", CHILD_LOD_MIN_SHIFT),
            ("STATICSCENE_CHILD_LOD_MAX_SHIFT", CHILD_LOD_MAX_SHIFT),
            ("STATICSCENE_GROUP_END_SHIFT", GROUP_END_SHIFT),
            (
                "STATICSCENE_INSTANCE_FLAG_NO_OCCLUSION",
                u32::from(INSTANCE_FLAG_NO_OCCLUSION),
            ),
            (
                "STATICSCENE_INSTANCE_FLAG_NO_FADE",
                u32::from(INSTANCE_FLAG_NO_FADE),
            ),
            (
                "STATICSCENE_OBJECT_FLAG_IGNORE_GLOBAL_LOD_SCALE",
                OBJECT_FLAG_IGNORE_GLOBAL_LOD_SCALE,
            ),
            (
                "STATICSCENE_LOD_CODE_INFINITY",
                u32::from(LOD_CODE_INFINITY),
            ),
            ("STATICSCENE_QUERY_FLAG_FADE", QUERY_FLAG_FADE),
            ("STATICSCENE_QUERY_FLAG_OCCLUSION", QUERY_FLAG_OCCLUSION),
            (
                "STATICSCENE_QUERY_FLAG_REVERSED_DEPTH",
                QUERY_FLAG_REVERSED_DEPTH,
            ),
            ("STATICSCENE_QUERY_FLAG_SIZE", QUERY_FLAG_SIZE),
            ("STATICSCENE_QUERY_FLAG_FIRST_PASS", QUERY_FLAG_FIRST_PASS),
            ("STATICSCENE_QUERY_FLAG_SECOND_PASS", QUERY_FLAG_SECOND_PASS),
            ("STATICSCENE_QUERY_FLAG_SHADOW", QUERY_FLAG_SHADOW),
            (
                "STATICSCENE_CAMERA_STATE_VISIBLE",
                u32::from(CAMERA_STATE_VISIBLE),
            ),
            ("STATICSCENE_STATE_FADING", STATE_FADING),
            ("STATICSCENE_STATE_FADING_OUT", STATE_FADING_OUT),
        ] {
            assert_eq!(const_u32(&m, name), Some(v), "{name}");
        }
        assert_eq!(
            const_f32(&m, "STATICSCENE_FRUSTUM_TOLERANCE"),
            Some(FRUSTUM_TOLERANCE)
        );
        assert_eq!(
            const_f32(&m, "STATICSCENE_HIZ_DEPTH_EPSILON"),
            Some(HIZ_DEPTH_EPSILON)
        );
        // Every WGSL constant is one of the above.
        let names = shadercheck::const_names(&m);
        assert_eq!(
            const_u32(&m, "STATICSCENE_HIZ_MAX_LEVELS"),
            Some(pass::HIZ_MAX_LEVELS as u32)
        );
        assert_eq!(
            const_u32(&m, "STATICSCENE_HIZ_HEADER_WORDS"),
            Some(pass::HIZ_HEADER_WORDS as u32)
        );
        assert_eq!(names.len(), 30, "{names:?}");
        assert!(names.iter().all(|n| n.starts_with("STATICSCENE_")));
    }

    #[test]
    fn structs_match_rust_layouts() {
        let m = module();
        let check = |name: &str, size: usize, members: &[(&str, u32)]| {
            shadercheck::assert_struct_layout(&m, name, size, members);
        };
        check(
            "StaticsceneQueryInstance",
            size_of::<QueryInstance>(),
            &[("words", 0)],
        );
        check(
            "StaticsceneTransform",
            size_of::<Transform4x3>(),
            &[("rows", 0)],
        );
        check(
            "StaticsceneQueryObject",
            size_of::<QueryObject>(),
            &shadercheck::members!(QueryObject {
                object_to_snapped,
                snapped,
                lod
            }),
        );
        check(
            "StaticsceneQuerySetup",
            size_of::<QuerySetup>(),
            &shadercheck::members!(QuerySetup {
                bounds_min: "bounds",
                handle
            }),
        );
        check(
            "StaticsceneHalfAabb",
            size_of::<HalfAabb>(),
            &[("words", 0)],
        );
        check(
            "StaticsceneInstanceState",
            size_of::<InstanceState>(),
            &[("fade", 0), ("flags", 4), ("tile", 8), ("instance", 12)],
        );
        check(
            "StaticsceneDrawableSetupInstance",
            size_of::<DrawableSetupInstance>(),
            &[
                ("state", 0),
                (
                    "local_to_floating",
                    core::mem::offset_of!(DrawableSetupInstance, local_to_floating) as u32,
                ),
            ],
        );
        check(
            "StaticsceneDrawableSetupBatch",
            size_of::<DrawableSetupBatch>(),
            &shadercheck::members!(DrawableSetupBatch {
                sort_key,
                setup,
                sphere,
                first_instance,
                flags,
                count,
                stride
            }),
        );
        check(
            "StaticsceneQueryParams",
            size_of::<QueryParams>(),
            &shadercheck::members!(QueryParams {
                clip_from_floating,
                hiz_clip_from_floating,
                planes,
                forward,
                lod_point,
                origin,
                prev_origin,
                viewport,
                filter_mask,
                flags,
                fade_frames,
                hiz_scan_levels
            }),
        );
    }

    #[test]
    fn modules_are_binding_free_and_prefixed() {
        // The library module (the pass module binds resources and imports `wave`).
        let module = shadercheck::assert_composed(&[MODULES], QUERY.name, &[], Caps::CORE);
        shadercheck::assert_prefixed(QUERY.name, &module, "staticscene", &[], true);
        assert!(QUERY.imports(&[]).unwrap().is_empty());
        assert!(module.functions.iter().count() >= 20);
    }
}
