//! The crate's WGSL modules (`src/wgsl/<name>.wgsl`, composed as `gpu::<name>`) and the
//! library every pass composes against: the small crates' modules, then these.

use shader::Module;

macro_rules! gpu_modules {
    ($($name:ident = $file:literal),+ $(,)?) => {
        $(
            #[doc = concat!("`gpu::", $file, "`")]
            pub(crate) const $name: Module =
                Module::new(concat!("gpu::", $file), include_str!(concat!("wgsl/", $file, ".wgsl")));
        )+
        /// This crate's WGSL modules.
        pub(crate) const MODULES: &[Module] = &[$($name),+];
    };
}

gpu_modules!(
    FRAME = "frame",
    SCENE = "scene",
    SCENE_BINDINGS = "scene_bindings",
    MATERIAL = "material",
    GEOMETRY = "geometry",
    LAYDOWN = "laydown",
    LAYDOWN_BUILTIN = "laydown_builtin",
    LAYDOWN_XOR = "laydown_xor",
    LAYDOWN_PROVOKING = "laydown_provoking",
    COMPUTE_LAYDOWN_DRAWS = "compute_laydown_draws",
    COMPUTE_LAYDOWN = "compute_laydown",
    COMPUTE_LAYDOWN_HYBRID = "compute_laydown_hybrid",
    LAYDOWN_TARGET = "laydown_target",
    LAYDOWN_UNPACK = "laydown_unpack",
    BASELINE = "baseline",
    PIXEL_PULL = "pixel_pull",
    GBUFFER_STORE = "gbuffer_store",
    GBUFFER_LOAD = "gbuffer_load",
    GBUFFER_FRAGMENT = "gbuffer_fragment",
    RESOLVE = "resolve",
    LIGHTING = "lighting",
    LIGHT_SHADING = "light_shading",
    LIGHT_VOLUMES = "light_volumes",
    CONDITIONAL = "conditional",
    VIS_COPY = "vis_copy",
    ZERO = "zero",
    STATIC_PLACE = "static_place",
    HIZ_DEPTH = "hiz_depth",
    TILE_RANGE = "tile_range",
    TILE_DEPTH = "tile_depth",
    RING_SLOTS = "ring_slots",
    VERTEX_RING = "vertex_ring",
    WATER_FRAME = "water_frame",
    WATER_VISIBILITY = "water_visibility",
    WATER_POSITION = "water_position",
    WATER_DISPLACEMENT = "water_displacement",
    WATER_TILES = "water_tiles",
    WATER_TESSELLATION = "water_tessellation",
    WATER_NORMALS = "water_normals",
    WATER_FOAM = "water_foam",
    WATER_COMPOSITE = "water_composite",
);

/// Every module list the renderer's passes import from.
pub(crate) const LIBRARY: &[&[Module]] = &[
    visbuf::wgsl::MODULES,
    wave::wgsl::MODULES,
    tiling::wgsl::MODULES,
    deferred::wgsl::MODULES,
    staticscene::wgsl::MODULES,
    ::water::wgsl::MODULES,
    MODULES,
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_module_composes_with_its_imports() {
        for m in MODULES {
            shader::compose(LIBRARY, m.name, &[]).unwrap_or_else(|e| panic!("{e}"));
        }
    }
}
