//! The WGSL twins: binding-free library modules (functions, structs, constants, every name
//! prefixed `visbuf_` / `VISBUF_` / `Visbuf`) that passes import with `#import visbuf::id`
//! and the like (see the `shader` crate); the constants in them are tied to the Rust
//! definitions by the unit tests at the bottom of this file. None imports another.

use shader::Module;

/// `visbuf::id`: vis-buffer ID pack/unpack. See the crate docs' WGSL table.
pub const ID: Module = Module::new("visbuf::id", include_str!("wgsl/id.wgsl"));

/// `visbuf::vertex`: the 32-byte transformed vertex, decode (and encode, for the
/// vertex-transform pass). See the crate docs' WGSL table.
pub const VERTEX: Module = Module::new("visbuf::vertex", include_str!("wgsl/vertex.wgsl"));

/// `visbuf::bary`: barycentrics, their derivatives, attribute interpolation and mip
/// selection.
pub const BARY: Module = Module::new("visbuf::bary", include_str!("wgsl/bary.wgsl"));

/// `visbuf::ray`: the watertight ray-triangle fallback and the pixel ray.
pub const RAY: Module = Module::new("visbuf::ray", include_str!("wgsl/ray.wgsl"));

/// This crate's modules, for `shader::compose`'s library.
pub const MODULES: &[Module] = &[ID, VERTEX, BARY, RAY];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::id::*;
    use shadercheck::{Caps, const_u32};

    #[test]
    fn id_wgsl_is_valid_core_wgsl_and_its_constants_match_rust() {
        let m = shadercheck::assert_composed(&[MODULES], ID.name, &[], Caps::CORE);
        let expect = [
            ("VISBUF_NONE", VIS_NONE),
            ("VISBUF_MICRO_BATCH_SHIFT", VIS_MICRO_BATCH_SHIFT),
            ("VISBUF_MICRO_BATCH_MASK", MICRO_BATCH_IDS - 1),
            ("VISBUF_MICRO_BATCH_MASK_VRS", MICRO_BATCH_IDS_VRS - 1),
            ("VISBUF_RATE_SHIFT", VIS_RATE_SHIFT),
            ("VISBUF_RATE_MASK", (1 << VIS_RATE_BITS) - 1),
            ("VISBUF_RATE_2X1", ShadingRate::Rate2x1 as u32),
            ("VISBUF_RATE_2X2", ShadingRate::Rate2x2 as u32),
            (
                "VISBUF_INSTANCE_PRIMITIVE_BITS",
                VIS_INSTANCE_PRIMITIVE_BITS,
            ),
            (
                "VISBUF_INSTANCE_PRIMITIVE_MASK",
                VIS_INSTANCE_PRIMITIVE_MASK,
            ),
            ("VISBUF_MAX_PRIMITIVE_BITS", MAX_PRIMITIVE_BITS),
            ("VISBUF_MICRO_BATCH_IDS", MICRO_BATCH_IDS),
            ("VISBUF_MICRO_BATCH_IDS_VRS", MICRO_BATCH_IDS_VRS),
        ];
        for (name, value) in expect {
            assert_eq!(const_u32(&m, name), Some(value), "WGSL const {name}");
        }
        // Every constant the snippet declares is one of those checked above.
        for name in shadercheck::const_names(&m) {
            assert!(
                expect.iter().any(|(n, _)| *n == name),
                "unchecked WGSL const {name}"
            );
        }
    }

    #[test]
    fn id_range_matches_the_rust_layout() {
        let m = shadercheck::assert_composed(&[MODULES], ID.name, &[], Caps::CORE);
        shadercheck::assert_struct_layout(
            &m,
            "VisbufIdRange",
            size_of::<VisbufIdRange>(),
            &shadercheck::members!(VisbufIdRange {
                first_id,
                id_count,
                instance_count,
                primitive_count
            }),
        );
    }

    #[test]
    fn vertex_wgsl_is_valid_core_wgsl_and_its_constants_match_rust() {
        use crate::vertex::*;
        let m = shadercheck::assert_composed(&[MODULES], VERTEX.name, &[], Caps::CORE);
        assert_eq!(
            shadercheck::const_f32(&m, "VISBUF_UV_SCALE"),
            Some(UV_SCALE)
        );
        assert_eq!(shadercheck::const_f32(&m, "VISBUF_UV_MAX"), Some(UV_MAX));
        assert_eq!(
            shadercheck::const_f32(&m, "VISBUF_HALF_MAX"),
            Some(half::f16::MAX.to_f32())
        );
        assert_eq!(
            shadercheck::const_f32(&m, "VISBUF_SNORM10_MAX"),
            Some(511.0)
        );
        assert_eq!(
            const_u32(&m, "VISBUF_SNORM_W_SHIFT"),
            Some(SNORM_10_10_10_2_W_SHIFT)
        );
        assert_eq!(
            const_u32(&m, "VISBUF_VERTEX_WORDS"),
            Some((size_of::<VisbufVertex>() / 4) as u32)
        );
        // The WGSL struct has the Rust struct's size and member offsets (8 x 4 bytes).
        shadercheck::assert_struct_layout(
            &m,
            "VisbufVertex",
            size_of::<VisbufVertex>(),
            &shadercheck::members!(VisbufVertex {
                hpos_xy,
                hpos_w,
                uv,
                color,
                normal,
                tangent,
                prev_hpos_xy,
                prev_hpos_w_extra
            }),
        );
    }

    #[test]
    fn bary_wgsl_constants_match_rust() {
        let m = shadercheck::assert_composed(&[MODULES], BARY.name, &[], Caps::CORE);
        let f = |n| shadercheck::const_f32(&m, n);
        assert_eq!(
            f("VISBUF_DEGENERATE_EPSILON"),
            Some(crate::bary::DEGENERATE_EPSILON)
        );
        assert_eq!(f("VISBUF_DEGENERATE_EPSILON"), Some(2f32.powi(-40)));
        assert_eq!(f("VISBUF_MIN_MAGNITUDE"), Some(2f32.powi(-100)));
        assert_eq!(f("VISBUF_MIN_RELATIVE"), Some(2f32.powi(-40)));
        assert_eq!(f("VISBUF_MAX_NDC"), Some(crate::bary::MAX_NDC));
        assert_eq!(f("VISBUF_F32_MAX"), Some(f32::MAX));
        assert_eq!(f("VISBUF_F32_MIN_POSITIVE"), Some(f32::MIN_POSITIVE));
    }

    #[test]
    fn modules_are_binding_free_prefixed_and_compose_together() {
        for m in MODULES {
            let module = shadercheck::assert_composed(&[MODULES], m.name, &[], Caps::CORE);
            shadercheck::assert_prefixed(m.name, &module, "visbuf", &[], true);
            assert!(m.imports(&[]).unwrap().is_empty(), "{} imports", m.name);
        }
        // A pass may import all of them: together they still validate (no name clashes).
        let all = shader::compose_source(
            &[MODULES],
            "all",
            "#import visbuf::id\n#import visbuf::vertex\n#import visbuf::bary\n#import visbuf::ray\n",
            &[],
        )
        .unwrap();
        shadercheck::validate(&all, Caps::CORE).unwrap();
    }
}
