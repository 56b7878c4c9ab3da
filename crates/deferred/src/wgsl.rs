//! The WGSL twins: binding-free library modules (every name prefixed `deferred_` /
//! `DEFERRED_` / `Deferred`) that passes import with `#import deferred::gbuffer` and the
//! like (see the `shader` crate); the constants in them are tied to the Rust definitions by
//! the unit tests at the bottom of this file.

use shader::Module;

/// `deferred::gbuffer`: G-buffer pack/unpack of both layouts and the normal codecs. See
/// the crate docs' WGSL table.
pub const GBUFFER: Module = Module::new("deferred::gbuffer", include_str!("wgsl/gbuffer.wgsl"));

/// `deferred::depth`: position from depth, the fast symmetric-perspective path and the
/// inverse-matrix path.
pub const DEPTH: Module = Module::new("deferred::depth", include_str!("wgsl/depth.wgsl"));

/// `deferred::lights`: tiled light culling's per-tile test, the light and tile-depth
/// structs, and the depth-bounds emulation (imports `deferred::depth`).
pub const LIGHTS: Module = Module::new("deferred::lights", include_str!("wgsl/lights.wgsl"));

/// `deferred::shadow`: stable cascade lookup, the MSAA PCF tap record and the edge tests.
pub const SHADOW: Module = Module::new("deferred::shadow", include_str!("wgsl/shadow.wgsl"));

/// This crate's modules.
pub const MODULES: &[Module] = &[GBUFFER, DEPTH, LIGHTS, SHADOW];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gbuffer::*;
    use crate::normal::*;
    use shadercheck::{Caps, const_f32, const_u32};

    fn assert_valid(_: &str, m: Module, caps: Caps) -> naga::Module {
        shadercheck::assert_composed(&[MODULES], m.name, &[], caps)
    }

    #[test]
    fn gbuffer_wgsl_constants_match_rust() {
        let m = assert_valid("", GBUFFER, Caps::CORE);
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

    #[test]
    fn lights_and_shadow_wgsl_match_rust() {
        use crate::lights::*;
        let m = assert_valid("", LIGHTS, Caps::CORE);
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
        let m = assert_valid("", SHADOW, Caps::CORE);
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
        let m = assert_valid("", DEPTH, Caps::CORE);
        let (offsets, size) = struct_layout(&m, "DeferredProjection");
        assert_eq!(size as usize, size_of::<crate::DeferredProjection>());
        assert_eq!(offsets, [0, 8, 12, 16]);
    }

    #[test]
    fn modules_are_binding_free_prefixed_and_compose_together() {
        for m in MODULES {
            let module = assert_valid(m.name, *m, Caps::CORE);
            shadercheck::assert_prefixed(m.name, &module, "deferred", &[], true);
        }
        assert_eq!(LIGHTS.imports(&[]).unwrap(), ["deferred::depth"]);
        let all = shader::compose_source(
            &[MODULES],
            "all",
            "#import deferred::gbuffer\n#import deferred::lights\n#import deferred::shadow\n",
            &[],
        )
        .unwrap();
        shadercheck::validate(&all, Caps::CORE).unwrap();
    }
}
