//! WGSL assembly: every pass's module is the small crates' binding-free snippets (the
//! single source of each bit layout) followed by this crate's pass code.

use crate::context::PrimitiveIdPath;

const LAYDOWN: &str = include_str!("shaders/laydown.wgsl");
const LAYDOWN_BUILTIN: &str = include_str!("shaders/laydown_builtin.wgsl");
const LAYDOWN_PROVOKING: &str = include_str!("shaders/laydown_provoking.wgsl");
const LAYDOWN_XOR: &str = include_str!("shaders/laydown_xor.wgsl");

/// The laydown module for one primitive-ID path (and the baseline's depth prepass, which
/// uses the same vertex stage so both produce bit-identical depths).
pub fn laydown(path: PrimitiveIdPath) -> String {
    let (enable, fragment) = match path {
        PrimitiveIdPath::Builtin => ("enable primitive_index;\n", LAYDOWN_BUILTIN),
        PrimitiveIdPath::PerVertexXor => ("enable wgpu_per_vertex;\n", LAYDOWN_XOR),
        PrimitiveIdPath::ProvokingVertex => ("", LAYDOWN_PROVOKING),
    };
    [enable, visbuf::ID_WGSL, crate::upload::SCENE_WGSL, crate::frame::FRAME_WGSL, LAYDOWN, fragment].concat()
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
