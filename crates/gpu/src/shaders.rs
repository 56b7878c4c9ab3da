//! WGSL assembly: every pass's module is the small crates' binding-free snippets (the
//! single source of each bit layout) followed by this crate's pass code.

use crate::context::PrimitiveIdPath;

const LAYDOWN: &str = include_str!("shaders/laydown.wgsl");
const LAYDOWN_BUILTIN: &str = include_str!("shaders/laydown_builtin.wgsl");
const LAYDOWN_PROVOKING: &str = include_str!("shaders/laydown_provoking.wgsl");
const LAYDOWN_XOR: &str = include_str!("shaders/laydown_xor.wgsl");
const MATERIAL: &str = include_str!("shaders/material.wgsl");
const RESOLVE_COMMON: &str = include_str!("shaders/resolve_common.wgsl");
const BASELINE: &str = include_str!("shaders/baseline.wgsl");
const LIGHTING: &str = include_str!("shaders/lighting.wgsl");

/// The laydown module for one primitive-ID path (and the baseline's depth prepass, which
/// uses the same vertex stage so both produce bit-identical depths).
pub fn laydown(path: PrimitiveIdPath) -> String {
    let (enable, fragment) = match path {
        PrimitiveIdPath::Builtin => ("enable primitive_index;\n", LAYDOWN_BUILTIN),
        PrimitiveIdPath::PerVertexXor => ("enable wgpu_per_vertex;\n", LAYDOWN_XOR),
        PrimitiveIdPath::ProvokingVertex => ("", LAYDOWN_PROVOKING),
    };
    [
        enable,
        visbuf::wgsl::ID.source,
        crate::upload::SCENE_WGSL,
        crate::frame::FRAME_WGSL,
        LAYDOWN,
        fragment,
    ]
    .concat()
}

/// The baseline's geometry pass (depth-equal, G-buffer from a fragment shader): the laydown
/// module of `path` (for its identical vertex transform) plus material evaluation and the
/// G-buffer's fragment outputs.
pub fn baseline(path: PrimitiveIdPath) -> String {
    [
        laydown(path).as_str(),
        deferred::GBUFFER_WGSL,
        MATERIAL,
        &crate::gbuffer::fragment_wgsl(),
        BASELINE,
    ]
    .concat()
}

/// The compute material resolve: per-pixel vertex pulling, barycentrics, material, G-buffer
/// store (group 1); entry points `resolve_waves` (one workgroup of `wave_width` lanes per
/// wave command, commands in group 2) and `resolve_fullscreen` (every pixel, diagnostic).
pub fn resolve(wave_width: u32) -> String {
    [
        &format!("const RESOLVE_WAVE_WIDTH: u32 = {wave_width}u;\n"),
        visbuf::wgsl::ID.source,
        tiling::wgsl::COMMON.source,
        visbuf::wgsl::BARY.source,
        deferred::GBUFFER_WGSL,
        crate::upload::SCENE_WGSL,
        crate::frame::FRAME_WGSL,
        crate::geometry::GEOMETRY_WGSL,
        crate::plan::PLAN_WGSL,
        MATERIAL,
        &crate::gbuffer::store_wgsl(1, 0),
        RESOLVE_COMMON,
    ]
    .concat()
}

/// Deferred lighting and tone mapping (G-buffer read from group 1).
pub fn lighting() -> String {
    [
        deferred::GBUFFER_WGSL,
        crate::frame::FRAME_WGSL,
        &crate::gbuffer::load_wgsl(1, 0),
        LIGHTING,
    ]
    .concat()
}

/// Fragment entry points of the laydown for `path`: (opaque, alpha-tested).
pub fn laydown_entry_points(path: PrimitiveIdPath) -> (&'static str, &'static str) {
    match path {
        PrimitiveIdPath::Builtin => ("fs_builtin", "fs_builtin_alpha"),
        PrimitiveIdPath::PerVertexXor => ("fs_xor", "fs_xor_alpha"),
        PrimitiveIdPath::ProvokingVertex => ("fs_provoking", "fs_provoking_alpha"),
    }
}

/// The naga capabilities a path's module needs (for validation without a device).
#[cfg(test)]
pub(crate) fn caps(path: PrimitiveIdPath) -> shadercheck::Caps {
    match path {
        PrimitiveIdPath::Builtin => shadercheck::Caps::PRIMITIVE_INDEX,
        PrimitiveIdPath::PerVertexXor => shadercheck::Caps::PER_VERTEX,
        PrimitiveIdPath::ProvokingVertex => shadercheck::Caps::CORE,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resolve_lighting_and_baseline_validate() {
        shadercheck::assert_valid("resolve", &resolve(32), shadercheck::Caps::CORE);
        shadercheck::assert_valid("resolve w8", &resolve(8), shadercheck::Caps::CORE);
        shadercheck::assert_valid("lighting", &lighting(), shadercheck::Caps::CORE);
        for path in PrimitiveIdPath::ALL {
            shadercheck::assert_valid(path.name(), &baseline(path), caps(path));
        }
    }

    #[test]
    fn laydown_modules_validate_with_only_their_path_capability() {
        for path in PrimitiveIdPath::ALL {
            let src = laydown(path);
            shadercheck::assert_valid(path.name(), &src, caps(path));
            if path != PrimitiveIdPath::ProvokingVertex {
                assert!(
                    shadercheck::validate(&src, shadercheck::Caps::CORE).is_err(),
                    "{} must need its feature",
                    path.name()
                );
            }
        }
    }
}
