//! The WGSL twins. Each module is a binding-free snippet; the constants in it are tied to
//! the Rust definitions by the unit tests at the bottom of this file.

/// Vis-buffer ID pack/unpack in WGSL. See the crate docs' WGSL table.
pub const ID_WGSL: &str = include_str!("wgsl/id.wgsl");

/// The 32-byte transformed vertex in WGSL: decode (and encode, for the vertex-transform
/// pass). See the crate docs' WGSL table.
pub const VERTEX_WGSL: &str = include_str!("wgsl/vertex.wgsl");

/// Barycentrics, their derivatives, attribute interpolation and mip selection in WGSL.
pub const BARY_WGSL: &str = include_str!("wgsl/bary.wgsl");

/// The watertight ray-triangle fallback and the pixel ray in WGSL.
pub const RAY_WGSL: &str = include_str!("wgsl/ray.wgsl");

/// Every module above, concatenated (none depends on another).
pub const WGSL: &str = concat!(
    include_str!("wgsl/id.wgsl"),
    include_str!("wgsl/vertex.wgsl"),
    include_str!("wgsl/bary.wgsl"),
    include_str!("wgsl/ray.wgsl")
);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::id::*;
    use alloc::vec::Vec;
    use shadercheck::{Caps, assert_valid, const_u32};

    #[test]
    fn id_wgsl_is_valid_core_wgsl_and_its_constants_match_rust() {
        let m = assert_valid("visbuf ID_WGSL", ID_WGSL, Caps::CORE);
        let expect = [
            ("VISBUF_NONE", VIS_NONE),
            ("VISBUF_MICRO_BATCH_SHIFT", VIS_MICRO_BATCH_SHIFT),
            ("VISBUF_MICRO_BATCH_MASK", MICRO_BATCH_IDS - 1),
            ("VISBUF_MICRO_BATCH_MASK_VRS", MICRO_BATCH_IDS_VRS - 1),
            ("VISBUF_RATE_SHIFT", VIS_RATE_SHIFT),
            ("VISBUF_RATE_MASK", (1 << VIS_RATE_BITS) - 1),
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
    fn vertex_wgsl_is_valid_core_wgsl_and_its_constants_match_rust() {
        use crate::vertex::*;
        let m = assert_valid("visbuf VERTEX_WGSL", VERTEX_WGSL, Caps::CORE);
        assert_eq!(
            shadercheck::const_f32(&m, "VISBUF_UV_SCALE"),
            Some(UV_SCALE)
        );
        assert_eq!(shadercheck::const_f32(&m, "VISBUF_UV_MAX"), Some(UV_MAX));
        assert_eq!(
            shadercheck::const_f32(&m, "VISBUF_HALF_MAX"),
            Some(HALF_MAX)
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
        // The WGSL struct has the Rust struct's size (8 x 4 bytes, no padding).
        let (_, ty) = m
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some("VisbufVertex"))
            .expect("struct VisbufVertex");
        match &ty.inner {
            naga::TypeInner::Struct { members, span } => {
                assert_eq!(*span as usize, size_of::<VisbufVertex>());
                let names: Vec<_> = members.iter().map(|m| m.name.clone().unwrap()).collect();
                assert_eq!(
                    names,
                    [
                        "hpos_xy",
                        "hpos_w",
                        "uv",
                        "color",
                        "normal",
                        "tangent",
                        "prev_hpos_xy",
                        "prev_hpos_w_extra"
                    ]
                );
                let offsets: Vec<_> = members.iter().map(|m| m.offset).collect();
                assert_eq!(offsets, [0, 4, 8, 12, 16, 20, 24, 28]);
            }
            other => panic!("VisbufVertex is {other:?}"),
        }
    }

    /// Every module, with the capability set it is validated under.
    const MODULES: &[(&str, &str)] = &[
        ("ID_WGSL", ID_WGSL),
        ("VERTEX_WGSL", VERTEX_WGSL),
        ("BARY_WGSL", BARY_WGSL),
        ("RAY_WGSL", RAY_WGSL),
    ];

    #[test]
    fn bary_wgsl_constants_match_rust() {
        let m = assert_valid("visbuf BARY_WGSL", BARY_WGSL, Caps::CORE);
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
    fn modules_are_binding_free_prefixed_and_concatenate() {
        let mut all = alloc::string::String::new();
        for (name, src) in MODULES {
            let m = assert_valid(name, src, Caps::CORE);
            assert!(
                m.global_variables.is_empty(),
                "{name}: has bindings / module-scope vars"
            );
            assert!(m.entry_points.is_empty(), "{name}: has entry points");
            for (_, f) in m.functions.iter() {
                let n = f.name.as_deref().unwrap_or("");
                assert!(
                    n.starts_with("visbuf_"),
                    "{name}: function `{n}` not prefixed"
                );
            }
            for n in shadercheck::const_names(&m) {
                assert!(n.starts_with("VISBUF_"), "{name}: const `{n}` not prefixed");
            }
            for (_, t) in m.types.iter() {
                // naga's predeclared result types (`__frexp_result_f32`, ...) are builtins.
                if let Some(n) = t.name.as_deref()
                    && matches!(t.inner, naga::TypeInner::Struct { .. })
                    && !n.starts_with("__")
                {
                    assert!(n.starts_with("Visbuf"), "{name}: struct `{n}` not prefixed");
                }
            }
            all.push_str(src);
        }
        // The gpu crate concatenates them in front of its passes: together they must
        // still validate (no duplicate names).
        assert_valid("all visbuf WGSL", &all, Caps::CORE);
        assert_eq!(all, WGSL);
    }
}
