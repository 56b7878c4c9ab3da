//! The WGSL twins. Each module is a binding-free snippet; the constants in it are tied to
//! the Rust definitions by the unit tests at the bottom of this file.

/// G-buffer pack/unpack of both layouts and the normal codecs. See the crate docs' WGSL
/// table.
pub const GBUFFER_WGSL: &str = include_str!("wgsl/gbuffer.wgsl");

/// Position from depth: the fast symmetric-perspective path and the inverse-matrix path.
pub const DEPTH_WGSL: &str = include_str!("wgsl/depth.wgsl");

/// Tiled light culling's per-tile test, the light and tile-depth structs, and the
/// depth-bounds emulation. Needs [`DEPTH_WGSL`] in front of it.
pub const LIGHTS_WGSL: &str = include_str!("wgsl/lights.wgsl");

/// Stable cascade lookup, the MSAA PCF tap record and the edge tests.
pub const SHADOW_WGSL: &str = include_str!("wgsl/shadow.wgsl");

/// Every module above, concatenated in dependency order.
pub const WGSL: &str = concat!(
    include_str!("wgsl/gbuffer.wgsl"),
    include_str!("wgsl/depth.wgsl"),
    include_str!("wgsl/lights.wgsl"),
    include_str!("wgsl/shadow.wgsl")
);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gbuffer::*;
    use crate::normal::*;
    use shadercheck::{Caps, assert_valid, const_f32, const_u32};

    #[test]
    fn gbuffer_wgsl_constants_match_rust() {
        let m = assert_valid("deferred GBUFFER_WGSL", GBUFFER_WGSL, Caps::CORE);
        let u = [
            ("DEFERRED_OCT_BITS", OCT_BITS),
            ("DEFERRED_OCT_AXIS_MASK", OCT_AXIS_MASK),
            ("DEFERRED_OCT_CENTER", OCT_CENTER),
            ("DEFERRED_OCT_CODE_MAX", OCT_CODE_MAX),
        ];
        for (name, value) in u {
            assert_eq!(const_u32(&m, name), Some(value), "WGSL const {name}");
        }
        let f = [
            ("DEFERRED_KZ2_GLOW_RANGE", KZ2_GLOW_RANGE),
            ("DEFERRED_KZ2_MOTION_STEP_PX", KZ2_MOTION_STEP_PX),
            ("DEFERRED_GLOW_SLACK", GLOW_SLACK),
            ("DEFERRED_KZ2_SPEC_POWER_MAX", KZ2_SPEC_POWER_MAX),
            ("DEFERRED_KZ2_SPEC_LOG_RANGE", KZ2_SPEC_LOG_RANGE),
            ("DEFERRED_F16_MAX", half::f16::MAX.to_f32()),
            ("DEFERRED_LUMINANCE_R", LUMINANCE.x),
            ("DEFERRED_LUMINANCE_G", LUMINANCE.y),
            ("DEFERRED_LUMINANCE_B", LUMINANCE.z),
        ];
        for (name, value) in f {
            assert_eq!(const_f32(&m, name), Some(value), "WGSL const {name}");
        }
        for name in shadercheck::const_names(&m) {
            assert!(
                u.iter().any(|(n, _)| *n == name) || f.iter().any(|(n, _)| *n == name),
                "unchecked WGSL const {name}"
            );
        }
        // The WGSL surface struct has the Rust struct's fields, in order.
        let (_, ty) = m
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some("DeferredSurface"))
            .expect("struct DeferredSurface");
        let naga::TypeInner::Struct { members, .. } = &ty.inner else {
            panic!("DeferredSurface is not a struct");
        };
        let names: alloc::vec::Vec<_> = members.iter().map(|m| m.name.clone().unwrap()).collect();
        assert_eq!(
            names,
            [
                "lighting",
                "albedo",
                "normal",
                "roughness",
                "specular",
                "sun_shadow",
                "motion"
            ]
        );
    }

    /// Every module, with the capability set it is validated under.
    const MODULES: &[(&str, &str, &str)] = &[
        ("GBUFFER_WGSL", "", GBUFFER_WGSL),
        ("DEPTH_WGSL", "", DEPTH_WGSL),
        ("LIGHTS_WGSL", DEPTH_WGSL, LIGHTS_WGSL),
        ("SHADOW_WGSL", "", SHADOW_WGSL),
    ];

    #[test]
    fn lights_and_shadow_wgsl_match_rust() {
        use crate::lights::*;
        let src = alloc::format!("{DEPTH_WGSL}{LIGHTS_WGSL}");
        let m = assert_valid("deferred LIGHTS_WGSL", &src, Caps::CORE);
        for (name, value) in [
            ("DEFERRED_TILE_SIZE", TILE_SIZE),
            ("DEFERRED_MAX_LIGHTS_PER_TILE", MAX_LIGHTS_PER_TILE),
            ("DEFERRED_LIGHT_FLAG_SHADOW", LIGHT_FLAG_SHADOW),
            ("DEFERRED_LIGHT_FLAG_SPOT", LIGHT_FLAG_SPOT),
        ] {
            assert_eq!(const_u32(&m, name), Some(value), "WGSL const {name}");
        }
        let (offsets, size) = struct_layout(&m, "DeferredLight");
        assert_eq!(size as usize, size_of::<DeferredLight>());
        assert_eq!(offsets, [0, 12, 16, 28, 32, 44]);
        let (offsets, size) = struct_layout(&m, "DeferredTileDepth");
        assert_eq!(size as usize, size_of::<DeferredTileDepth>());
        assert_eq!(offsets, [0, 4]);
        let m = assert_valid("deferred SHADOW_WGSL", SHADOW_WGSL, Caps::CORE);
        let (offsets, size) = struct_layout(&m, "DeferredCascade");
        assert_eq!(size as usize, size_of::<crate::DeferredCascade>());
        assert_eq!(offsets, [0, 64, 68, 72, 76]);
        let (offsets, size) = struct_layout(&m, "DeferredPcfTap");
        assert_eq!(size as usize, size_of::<crate::msaa::DeferredPcfTap>());
        assert_eq!(offsets, [0, 8, 12]);
    }

    /// The byte offsets of a WGSL struct's members, and its size.
    fn struct_layout(m: &naga::Module, name: &str) -> (alloc::vec::Vec<u32>, u32) {
        let (_, ty) = m
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("struct {name}"));
        match &ty.inner {
            naga::TypeInner::Struct { members, span } => {
                (members.iter().map(|m| m.offset).collect(), *span)
            }
            other => panic!("{name} is {other:?}"),
        }
    }

    #[test]
    fn depth_wgsl_struct_matches_rust() {
        let m = assert_valid("deferred DEPTH_WGSL", DEPTH_WGSL, Caps::CORE);
        let (offsets, size) = struct_layout(&m, "DeferredProjection");
        assert_eq!(size as usize, size_of::<crate::DeferredProjection>());
        assert_eq!(offsets, [0, 8, 12, 16]);
    }

    #[test]
    fn modules_are_binding_free_prefixed_and_concatenate() {
        let mut all = alloc::string::String::new();
        for (name, needs, src) in MODULES {
            // Validate with what it needs in front, then check only its own items.
            let with = alloc::format!("{needs}{src}");
            assert_valid(name, &with, Caps::CORE);
            let m = match naga::front::wgsl::parse_str(src) {
                Ok(m) => m,
                // A module that names items of the one it needs parses only with it.
                Err(_) => naga::front::wgsl::parse_str(&with).unwrap(),
            };
            assert!(
                m.global_variables.is_empty(),
                "{name}: has bindings / module-scope vars"
            );
            assert!(m.entry_points.is_empty(), "{name}: has entry points");
            for (_, f) in m.functions.iter() {
                let n = f.name.as_deref().unwrap_or("");
                assert!(
                    n.starts_with("deferred_"),
                    "{name}: function `{n}` not prefixed"
                );
            }
            for n in shadercheck::const_names(&m) {
                assert!(
                    n.starts_with("DEFERRED_"),
                    "{name}: const `{n}` not prefixed"
                );
            }
            for (_, t) in m.types.iter() {
                if let Some(n) = t.name.as_deref()
                    && matches!(t.inner, naga::TypeInner::Struct { .. })
                    && !n.starts_with("__")
                {
                    assert!(
                        n.starts_with("Deferred"),
                        "{name}: struct `{n}` not prefixed"
                    );
                }
            }
            all.push_str(src);
        }
        assert_valid("all deferred WGSL", &all, Caps::CORE);
        assert_eq!(all, WGSL);
    }
}
