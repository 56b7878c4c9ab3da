//! The WGSL twins: binding-free library modules (functions, structs and constants, every
//! name prefixed `water_` / `WATER_` / `Water`) that passes import with `#import
//! water::noise` and the like (see the `shader` crate). The constants and structs are tied
//! to the Rust definitions by the unit tests at the bottom of this file, and naga
//! validates every module, composed with its imports, with the core capabilities only.
//! One module imports another: `water::flow` imports `water::noise` (its hashes).

use shader::Module;

/// `water::noise`: integer hashing, the noise texture generator, FBM with octave LOD
/// (exact, with `textureLoad`) and FBM through a sampler.
pub const NOISE: Module = Module::new("water::noise", include_str!("wgsl/noise.wgsl"));
/// `water::flow`: two-phase flow-map sampling and the phase noise (imports
/// `water::noise` for the hashes).
pub const FLOW: Module = Module::new("water::flow", include_str!("wgsl/flow.wgsl"));
/// `water::foam`: foam amount and coverage.
pub const FOAM: Module = Module::new("water::foam", include_str!("wgsl/foam.wgsl"));
/// `water::decal`: displacement decal fade, UV and resolve.
pub const DECAL: Module = Module::new("water::decal", include_str!("wgsl/decal.wgsl"));
/// `water::optics`: light transport.
pub const OPTICS: Module = Module::new("water::optics", include_str!("wgsl/optics.wgsl"));
/// `water::specaa`: variance-based specular anti-aliasing.
pub const SPECAA: Module = Module::new("water::specaa", include_str!("wgsl/specaa.wgsl"));
/// `water::normals`: normals from depth.
pub const NORMALS: Module = Module::new("water::normals", include_str!("wgsl/normals.wgsl"));
/// `water::gbuffer`: the mini G-buffer data word.
pub const GBUFFER: Module = Module::new("water::gbuffer", include_str!("wgsl/gbuffer.wgsl"));
/// `water::tiles`: screen tiles and the tessellated grid's vertices.
pub const TILES: Module = Module::new("water::tiles", include_str!("wgsl/tiles.wgsl"));
/// `water::material`: materials and their blend.
pub const MATERIAL: Module = Module::new("water::material", include_str!("wgsl/material.wgsl"));
/// `water::world`: the water query over a baked world.
pub const WORLD: Module = Module::new("water::world", include_str!("wgsl/world.wgsl"));
/// `water::atlas`: flow from the flow atlas.
pub const ATLAS: Module = Module::new("water::atlas", include_str!("wgsl/atlas.wgsl"));

/// This crate's modules, for `shader::compose`'s library.
pub const MODULES: &[Module] = &[
    NOISE, FLOW, FOAM, DECAL, OPTICS, SPECAA, NORMALS, GBUFFER, TILES, MATERIAL, WORLD, ATLAS,
];

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::string::String;
    use alloc::vec::Vec;
    use shadercheck::{Caps, const_f32, const_names, const_u32};

    enum V {
        U(u32),
        F(f32),
    }

    /// `m` composed with its imports and validated with the core capabilities.
    fn composed(m: Module) -> naga::Module {
        shadercheck::assert_composed(&[MODULES], m.name, &[], Caps::CORE)
    }

    /// Composes and validates `m`, and checks that its own constants (not its imports')
    /// are exactly the listed ones, with the Rust values.
    fn check(m: Module, expect: &[(&str, V)]) -> naga::Module {
        let module = composed(m);
        for (n, v) in expect {
            match v {
                V::U(u) => assert_eq!(const_u32(&module, n), Some(*u), "{}: {n}", m.name),
                V::F(f) => assert_eq!(const_f32(&module, n), Some(*f), "{}: {n}", m.name),
            }
        }
        let imported: Vec<String> = m
            .imports(&[])
            .unwrap()
            .into_iter()
            .flat_map(|i| {
                const_names(&shadercheck::assert_composed(
                    &[MODULES],
                    i,
                    &[],
                    Caps::CORE,
                ))
            })
            .collect();
        for n in const_names(&module) {
            // Non-scalar constants are checked by their tests directly.
            if imported.contains(&n) || n == "WATER_COLLAPSED_CLIP" {
                continue;
            }
            assert!(
                expect.iter().any(|(e, _)| *e == n),
                "{}: unchecked WGSL const {n}",
                m.name
            );
        }
        module
    }

    #[test]
    fn noise() {
        use crate::noise::*;
        let m = check(
            NOISE,
            &[
                ("WATER_MAX_OCTAVES", V::U(MAX_OCTAVES)),
                ("WATER_OCTAVE_SEED", V::U(OCTAVE_SEED)),
                ("WATER_NOISE_SCALE", V::F(NOISE_SCALE)),
            ],
        );
        shadercheck::assert_struct_layout(
            &m,
            "WaterFbmParams",
            size_of::<WaterFbmParams>(),
            &[
                ("frequency", 0),
                ("amplitude", 4),
                ("gain", 8),
                ("lod_distance", 12),
                ("octaves_near", 16),
                ("octaves_far", 20),
                ("slope_variance", 24),
                ("_pad", 28),
            ],
        );
    }

    #[test]
    fn flow() {
        use crate::flow::UV_JUMP;
        check(
            FLOW,
            &[
                ("WATER_UV_JUMP_X", V::F(UV_JUMP.x)),
                ("WATER_UV_JUMP_Y", V::F(UV_JUMP.y)),
            ],
        );
        assert_eq!(FLOW.imports(&[]).unwrap(), ["water::noise"]);
    }

    #[test]
    fn foam_decal_optics_specaa() {
        check(FOAM, &[]);
        check(
            DECAL,
            &[(
                "WATER_CLEAR_DISPLACEMENT",
                V::F(crate::decal::CLEAR_DISPLACEMENT),
            )],
        );
        use crate::optics::PURE_WATER_ABSORPTION as A;
        let m = check(
            OPTICS,
            &[
                ("WATER_PURE_ABSORPTION_R", V::F(A.x)),
                ("WATER_PURE_ABSORPTION_G", V::F(A.y)),
                ("WATER_PURE_ABSORPTION_B", V::F(A.z)),
            ],
        );
        shadercheck::assert_struct_layout(
            &m,
            "WaterMedium",
            size_of::<crate::optics::WaterMedium>(),
            &[("absorption", 0), ("scattering", 16)],
        );
        check(
            SPECAA,
            &[("WATER_SPECAA_KAPPA", V::F(crate::specaa::DEFAULT_KAPPA))],
        );
    }

    #[test]
    fn normals() {
        check(
            NORMALS,
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
            GBUFFER,
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
        let m = check(
            TILES,
            &[
                ("WATER_TILE_SIZE", V::U(TILE_SIZE)),
                ("WATER_COUNT_GROUP_SIZE", V::U(COUNT_GROUP_SIZE)),
                ("WATER_MAX_GRID_QUADS", V::U(MAX_GRID_QUADS)),
                ("WATER_GRID_CELL_BITS", V::U(GRID_CELL_BITS)),
                ("WATER_GRID_HALF_SHIFT", V::U(GRID_HALF_SHIFT)),
                ("WATER_GRID_CORNER_SHIFT", V::U(GRID_CORNER_SHIFT)),
            ],
        );
        // The vec4 constant is not a scalar shadercheck reads: its components from naga.
        let (_, c) = m
            .constants
            .iter()
            .find(|(_, c)| c.name.as_deref() == Some("WATER_COLLAPSED_CLIP"))
            .expect("WATER_COLLAPSED_CLIP");
        let naga::Expression::Compose { components, .. } = &m.global_expressions[c.init] else {
            panic!("WATER_COLLAPSED_CLIP is {:?}", m.global_expressions[c.init]);
        };
        let values: Vec<f32> = components
            .iter()
            .map(|&h| match m.global_expressions[h] {
                naga::Expression::Literal(naga::Literal::F32(v)) => v,
                ref other => panic!("WATER_COLLAPSED_CLIP component {other:?}"),
            })
            .collect();
        assert_eq!(values, COLLAPSED_CLIP);
    }

    #[test]
    fn material() {
        let m = check(
            MATERIAL,
            &[(
                "WATER_DEFAULT_BLEND_DISTANCE",
                V::F(crate::material::DEFAULT_BLEND_DISTANCE),
            )],
        );
        shadercheck::assert_struct_layout(
            &m,
            "WaterMaterialGpu",
            size_of::<crate::material::WaterMaterialGpu>(),
            &[
                ("absorption", 0),
                ("scattering", 16),
                ("displacement_amplitude", 32),
                ("foam_intensity", 36),
                ("shore_width", 40),
                ("detail_weight", 44),
                ("ids", 48),
                ("foam_texture", 52),
                ("algae_texture", 56),
                ("_pad", 60),
            ],
        );
    }

    #[test]
    fn world() {
        use crate::world::*;
        check(
            WORLD,
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
            ATLAS,
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
    fn modules_are_binding_free_prefixed_and_compose_together() {
        for m in MODULES {
            let module = composed(*m);
            shadercheck::assert_prefixed(m.name, &module, "water", &[], true);
        }
        // A pass may import all of them: together they still validate (no name clashes).
        let mut all = String::new();
        for m in MODULES {
            all.push_str("#import ");
            all.push_str(m.name);
            all.push('\n');
        }
        let all = shader::compose_source(&[MODULES], "all", &all, &[]).unwrap();
        let module = shadercheck::validate(&all, Caps::CORE).unwrap();
        shadercheck::assert_prefixed("all", &module, "water", &[], true);
    }
}
