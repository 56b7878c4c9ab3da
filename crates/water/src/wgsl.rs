//! The WGSL twins. Each module is a binding-free snippet (functions, structs and
//! constants, every name prefixed `water_` / `WATER_` / `Water`); the constants are tied to
//! the Rust definitions by the unit tests at the bottom of this file, and naga validates
//! every module with the core capabilities only.

/// Integer hashing, the noise texture generator, FBM with octave LOD (exact, with
/// `textureLoad`) and FBM through a sampler.
pub const NOISE_WGSL: &str = include_str!("wgsl/noise.wgsl");
/// Two-phase flow-map sampling and the phase noise. Needs [`NOISE_WGSL`] (hashes).
pub const FLOW_WGSL: &str = include_str!("wgsl/flow.wgsl");
/// Foam amount and coverage.
pub const FOAM_WGSL: &str = include_str!("wgsl/foam.wgsl");
/// Displacement decal fade, UV and resolve.
pub const DECAL_WGSL: &str = include_str!("wgsl/decal.wgsl");
/// Light transport.
pub const OPTICS_WGSL: &str = include_str!("wgsl/optics.wgsl");
/// Variance-based specular anti-aliasing.
pub const SPECAA_WGSL: &str = include_str!("wgsl/specaa.wgsl");
/// Normals from depth.
pub const NORMALS_WGSL: &str = include_str!("wgsl/normals.wgsl");
/// The mini G-buffer data word.
pub const GBUFFER_WGSL: &str = include_str!("wgsl/gbuffer.wgsl");
/// Screen tiles and the tessellated grid's vertices.
pub const TILES_WGSL: &str = include_str!("wgsl/tiles.wgsl");
/// Materials and their blend.
pub const MATERIAL_WGSL: &str = include_str!("wgsl/material.wgsl");
/// The water query over a baked world.
pub const WORLD_WGSL: &str = include_str!("wgsl/world.wgsl");
/// Flow from the flow atlas.
pub const ATLAS_WGSL: &str = include_str!("wgsl/atlas.wgsl");

/// Every module above, concatenated (dependencies first).
pub const WGSL: &str = concat!(
    include_str!("wgsl/noise.wgsl"),
    include_str!("wgsl/flow.wgsl"),
    include_str!("wgsl/foam.wgsl"),
    include_str!("wgsl/decal.wgsl"),
    include_str!("wgsl/optics.wgsl"),
    include_str!("wgsl/specaa.wgsl"),
    include_str!("wgsl/normals.wgsl"),
    include_str!("wgsl/gbuffer.wgsl"),
    include_str!("wgsl/tiles.wgsl"),
    include_str!("wgsl/material.wgsl"),
    include_str!("wgsl/world.wgsl"),
    include_str!("wgsl/atlas.wgsl"),
);

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::format;
    use alloc::string::String;
    use shadercheck::{Caps, assert_valid, const_f32, const_names, const_u32};

    enum V {
        U(u32),
        F(f32),
    }

    /// Validates `src` (after `deps`) with core capabilities and checks that exactly the
    /// listed constants are declared, with the Rust values.
    fn check(name: &str, deps: &str, src: &str, expect: &[(&str, V)]) {
        let m = assert_valid(name, &format!("{deps}{src}"), Caps::CORE);
        for (n, v) in expect {
            match v {
                V::U(u) => assert_eq!(const_u32(&m, n), Some(*u), "{name}: WGSL const {n}"),
                V::F(f) => assert_eq!(const_f32(&m, n), Some(*f), "{name}: WGSL const {n}"),
            }
        }
        let dep_names: alloc::vec::Vec<String> = if deps.is_empty() {
            alloc::vec::Vec::new()
        } else {
            const_names(&assert_valid("deps", deps, Caps::CORE))
        };
        for n in const_names(&m) {
            // Non-scalar constants are checked by their tests directly.
            if dep_names.contains(&n) || n == "WATER_COLLAPSED_CLIP" {
                continue;
            }
            assert!(
                expect.iter().any(|(e, _)| *e == n),
                "{name}: unchecked WGSL const {n}"
            );
        }
    }

    #[test]
    fn noise() {
        use crate::noise::*;
        check(
            "NOISE_WGSL",
            "",
            NOISE_WGSL,
            &[
                ("WATER_MAX_OCTAVES", V::U(MAX_OCTAVES)),
                ("WATER_OCTAVE_SEED", V::U(OCTAVE_SEED)),
                ("WATER_NOISE_SCALE", V::F(NOISE_SCALE)),
            ],
        );
    }

    #[test]
    fn flow() {
        use crate::flow::UV_JUMP;
        check(
            "FLOW_WGSL",
            NOISE_WGSL,
            FLOW_WGSL,
            &[
                ("WATER_UV_JUMP_X", V::F(UV_JUMP.x)),
                ("WATER_UV_JUMP_Y", V::F(UV_JUMP.y)),
            ],
        );
    }

    #[test]
    fn foam_decal_optics_specaa() {
        check("FOAM_WGSL", "", FOAM_WGSL, &[]);
        check(
            "DECAL_WGSL",
            "",
            DECAL_WGSL,
            &[(
                "WATER_CLEAR_DISPLACEMENT",
                V::F(crate::decal::CLEAR_DISPLACEMENT),
            )],
        );
        use crate::optics::PURE_WATER_ABSORPTION as A;
        check(
            "OPTICS_WGSL",
            "",
            OPTICS_WGSL,
            &[
                ("WATER_PURE_ABSORPTION_R", V::F(A.x)),
                ("WATER_PURE_ABSORPTION_G", V::F(A.y)),
                ("WATER_PURE_ABSORPTION_B", V::F(A.z)),
            ],
        );
        check(
            "SPECAA_WGSL",
            "",
            SPECAA_WGSL,
            &[("WATER_SPECAA_KAPPA", V::F(crate::specaa::DEFAULT_KAPPA))],
        );
    }

    #[test]
    fn normals() {
        check(
            "NORMALS_WGSL",
            "",
            NORMALS_WGSL,
            &[
                ("WATER_TAPS_FIVE", V::U(5)),
                ("WATER_TAPS_NINE", V::U(9)),
                ("WATER_SMOOTH_RATIO", V::F(crate::normals::SMOOTH_RATIO)),
                ("WATER_SMOOTH_EPSILON", V::F(crate::normals::SMOOTH_EPSILON)),
            ],
        );
    }

    #[test]
    fn gbuffer() {
        use crate::gbuffer::*;
        check(
            "GBUFFER_WGSL",
            "",
            GBUFFER_WGSL,
            &[
                ("WATER_SHADER_ID_MASK", V::U((1 << SHADER_ID_BITS) - 1)),
                ("WATER_FLAGS_SHIFT", V::U(FLAGS_SHIFT)),
                ("WATER_FLAG_VALID", V::U(u32::from(DataFlags::VALID.0))),
                (
                    "WATER_FLAG_FRONT_FACE",
                    V::U(u32::from(DataFlags::FRONT_FACE.0)),
                ),
                ("WATER_FLAG_LIT", V::U(u32::from(DataFlags::LIT.0))),
                ("WATER_FOAM_MIP_SHIFT", V::U(FOAM_MIP_SHIFT)),
                ("WATER_ALGAE_MIP_SHIFT", V::U(ALGAE_MIP_SHIFT)),
                ("WATER_MIP_BITS", V::U(MIP_BITS)),
                ("WATER_MIP_MASK", V::U((1 << MIP_BITS) - 1)),
                ("WATER_MIP_STEPS_PER_LEVEL", V::U(MIP_STEPS_PER_LEVEL)),
                ("WATER_MATERIAL_SHIFT", V::U(MATERIAL_SHIFT)),
                ("WATER_MAX_MATERIALS", V::U(MAX_MATERIALS)),
                ("WATER_DATA_NONE", V::U(DATA_NONE)),
            ],
        );
    }

    #[test]
    fn tiles() {
        use crate::tiles::*;
        check(
            "TILES_WGSL",
            "",
            TILES_WGSL,
            &[
                ("WATER_TILE_SIZE", V::U(TILE_SIZE)),
                ("WATER_COUNT_GROUP_SIZE", V::U(COUNT_GROUP_SIZE)),
                ("WATER_MAX_GRID_QUADS", V::U(MAX_GRID_QUADS)),
                ("WATER_GRID_CELL_BITS", V::U(GRID_CELL_BITS)),
                ("WATER_GRID_HALF_SHIFT", V::U(GRID_HALF_SHIFT)),
                ("WATER_GRID_CORNER_SHIFT", V::U(GRID_CORNER_SHIFT)),
            ],
        );
        // The vec4 constant is not a scalar shadercheck reads; compare its source text.
        let [x, y, z, w] = COLLAPSED_CLIP;
        assert!(TILES_WGSL.contains(&format!(
            "const WATER_COLLAPSED_CLIP: vec4<f32> = vec4<f32>({x:?}, {y:?}, {z:?}, {w:?});"
        )));
    }

    #[test]
    fn material() {
        check(
            "MATERIAL_WGSL",
            "",
            MATERIAL_WGSL,
            &[(
                "WATER_DEFAULT_BLEND_DISTANCE",
                V::F(crate::material::DEFAULT_BLEND_DISTANCE),
            )],
        );
    }

    #[test]
    fn world() {
        use crate::world::*;
        check(
            "WORLD_WGSL",
            "",
            WORLD_WGSL,
            &[
                ("WATER_WORLD_MAGIC", V::U(WORLD_MAGIC)),
                ("WATER_WORLD_VERSION", V::U(WORLD_VERSION)),
                ("WATER_NODE_INTERNAL", V::U(NODE_INTERNAL)),
                ("WATER_TEXEL_NONE", V::U(TEXEL_NONE)),
                ("WATER_KIND_SHIFT", V::U(KIND_SHIFT)),
                ("WATER_ITEM_LAKE_INSIDE", V::U(ITEM_LAKE_INSIDE)),
                ("WATER_ITEM_LAKE_PARTIAL", V::U(ITEM_LAKE_PARTIAL)),
                ("WATER_ITEM_RIVER_TILE", V::U(ITEM_RIVER_TILE)),
                ("WATER_BODY_LAKE", V::U(BODY_LAKE)),
                ("WATER_BODY_RIVER", V::U(BODY_RIVER)),
                ("WATER_BODY_OCEAN", V::U(BODY_OCEAN)),
                ("WATER_ITEM_WORDS", V::U(ITEM_WORDS)),
                ("WATER_TILE_WORDS", V::U(TILE_WORDS)),
                ("WATER_TEXEL_WORDS", V::U(TEXEL_WORDS)),
                ("WATER_MAX_QUADTREE_DEPTH", V::U(MAX_QUADTREE_DEPTH)),
                ("WATER_H_FLAGS", V::U(header::FLAGS as u32)),
                ("WATER_H_OCEAN_LEVEL", V::U(header::OCEAN_LEVEL as u32)),
                (
                    "WATER_H_OCEAN_MATERIAL",
                    V::U(header::OCEAN_MATERIAL as u32),
                ),
                ("WATER_H_ROOT_X", V::U(header::ROOT_X as u32)),
                ("WATER_H_ROOT_Y", V::U(header::ROOT_Y as u32)),
                ("WATER_H_ROOT_SIZE", V::U(header::ROOT_SIZE as u32)),
                ("WATER_H_NODES", V::U(header::NODES as u32)),
                ("WATER_H_ITEMS", V::U(header::ITEMS as u32)),
                ("WATER_H_LAKES", V::U(header::LAKES as u32)),
                ("WATER_H_TILES", V::U(header::TILES as u32)),
                ("WATER_H_TILE_TEXELS", V::U(header::TILE_TEXELS as u32)),
                ("WATER_H_EDGES", V::U(header::EDGES as u32)),
            ],
        );
    }

    #[test]
    fn atlas() {
        use crate::atlas::*;
        check(
            "ATLAS_WGSL",
            "",
            ATLAS_WGSL,
            &[
                ("WATER_ATLAS_MAGIC", V::U(ATLAS_MAGIC)),
                ("WATER_SECTOR_NONE", V::U(SECTOR_NONE)),
                ("WATER_A_ORIGIN_X", V::U(header::ORIGIN_X as u32)),
                ("WATER_A_ORIGIN_Y", V::U(header::ORIGIN_Y as u32)),
                ("WATER_A_SECTOR_SIZE", V::U(header::SECTOR_SIZE as u32)),
                ("WATER_A_SECTORS_X", V::U(header::SECTORS_X as u32)),
                ("WATER_A_SECTORS_Y", V::U(header::SECTORS_Y as u32)),
                ("WATER_A_WORLD_TEXEL", V::U(header::WORLD_TEXEL as u32)),
                ("WATER_A_WORLD_W", V::U(header::WORLD_W as u32)),
                ("WATER_A_WORLD_H", V::U(header::WORLD_H as u32)),
                ("WATER_A_WORLD_TOP", V::U(header::WORLD_TOP as u32)),
                ("WATER_A_TILE_RES", V::U(header::TILE_RES as u32)),
                ("WATER_A_MAX_SPEED", V::U(header::MAX_SPEED as u32)),
                ("WATER_A_TABLE", V::U(header::TABLE as u32)),
                ("WATER_A_SLOTS_X", V::U(header::SLOTS_X as u32)),
                ("WATER_A_SLOT_TOP", V::U(header::SLOT_TOP as u32)),
            ],
        );
    }

    #[test]
    fn everything_concatenates() {
        assert_valid("water WGSL", WGSL, Caps::CORE);
        // Every module-scope name carries the crate prefix.
        let m = assert_valid("water WGSL", WGSL, Caps::CORE);
        for (_, f) in m.functions.iter() {
            let n = f.name.as_deref().unwrap_or("");
            assert!(n.starts_with("water_"), "function {n}");
        }
        for (_, t) in m.types.iter() {
            if let Some(n) = t.name.as_deref()
                && matches!(t.inner, naga::TypeInner::Struct { .. })
            {
                assert!(n.starts_with("Water"), "struct {n}");
            }
        }
        for n in const_names(&m) {
            assert!(n.starts_with("WATER_"), "const {n}");
        }
    }
}
