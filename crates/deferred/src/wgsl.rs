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

/// `deferred::light_cull_pass`: the tiled light-culling pass
/// ([`LIGHT_CULL_PASS`](crate::pass::LIGHT_CULL_PASS)).
pub const LIGHT_CULL_PASS_MODULE: Module = Module::new(
    "deferred::light_cull_pass",
    include_str!("wgsl/light_cull_pass.wgsl"),
);

/// This crate's binding-free library modules.
pub const MODULES: &[Module] = &[GBUFFER, DEPTH, LIGHTS, SHADOW];

/// This crate's pass modules (they declare bindings).
pub const PASS_MODULES: &[Module] = &[LIGHT_CULL_PASS_MODULE];

/// What this crate's passes compose from.
pub const LIBRARY: &[&[Module]] = &[MODULES, PASS_MODULES];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gbuffer::*;
    use crate::normal::*;
    use shadercheck::{Caps, const_f32, const_u32};

    /// `m` composed with its imports and validated with `Caps::CORE`.
    fn composed(m: Module) -> naga::Module {
        shadercheck::assert_composed(&[MODULES], m.name, &[], Caps::CORE)
    }

    #[test]
    fn gbuffer_wgsl_constants_match_rust() {
        let m = composed(GBUFFER);
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
        // (A value in registers, never a buffer: its WGSL offsets are not the Rust ones.)
        let (_, members) =
            shadercheck::struct_layout(&m, "DeferredSurface").expect("DeferredSurface");
        let names: alloc::vec::Vec<_> = members.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(
            names,
            [
                "lighting",
                "albedo",
                "normal",
                "roughness",
                "specular",
                "metallic",
                "sun_shadow",
                "motion"
            ]
        );
    }

    #[test]
    fn lights_and_shadow_wgsl_match_rust() {
        use crate::lights::*;
        let m = composed(LIGHTS);
        for (name, value) in [
            ("DEFERRED_TILE_SIZE", TILE_SIZE),
            ("DEFERRED_MAX_LIGHTS_PER_TILE", MAX_LIGHTS_PER_TILE),
            ("DEFERRED_LIGHT_FLAG_SHADOW", LIGHT_FLAG_SHADOW),
            ("DEFERRED_LIGHT_FLAG_SPOT", LIGHT_FLAG_SPOT),
            ("DEFERRED_LIGHT_FLAG_NO_SPECULAR", LIGHT_FLAG_NO_SPECULAR),
        ] {
            assert_eq!(const_u32(&m, name), Some(value), "WGSL const {name}");
        }
        shadercheck::assert_struct_layout(
            &m,
            "DeferredLight",
            size_of::<DeferredLight>(),
            &[
                ("position", 0),
                ("range", 12),
                ("direction", 16),
                ("cos_outer", 28),
                ("color", 32),
                ("flags", 44),
            ],
        );
        shadercheck::assert_struct_layout(
            &m,
            "DeferredTileDepth",
            size_of::<DeferredTileDepth>(),
            &[("nearest", 0), ("farthest", 4)],
        );
        let m = composed(SHADOW);
        shadercheck::assert_struct_layout(
            &m,
            "DeferredCascade",
            size_of::<crate::DeferredCascade>(),
            &[
                ("relative_to_clip", 0),
                ("split_far", 64),
                ("texel_size", 68),
                ("radius", 72),
                ("pad", 76),
            ],
        );
        shadercheck::assert_struct_layout(
            &m,
            "DeferredPcfTap",
            size_of::<crate::msaa::DeferredPcfTap>(),
            &[("offset", 0), ("weight", 8), ("sample", 12)],
        );
    }

    #[test]
    fn depth_wgsl_struct_matches_rust() {
        let m = composed(DEPTH);
        shadercheck::assert_struct_layout(
            &m,
            "DeferredProjection",
            size_of::<crate::DeferredProjection>(),
            &[
                ("tan_half", 0),
                ("alpha", 8),
                ("beta", 12),
                ("viewport", 16),
            ],
        );
    }

    #[test]
    fn modules_are_binding_free_prefixed_and_compose_together() {
        for m in MODULES {
            let module = composed(*m);
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
