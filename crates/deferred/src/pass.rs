//! Tiled light culling as a GPU compute pass: [`LIGHT_CULL_PASS`] (WGSL
//! `deferred::light_cull_pass`), the twin of [`cull_tiles`](crate::lights::cull_tiles).
//!
//! Its input is pass 1's per-tile depth ranges ([`DeferredTileDepth`], one per
//! [`TILE_SIZE`](crate::lights::TILE_SIZE)² tile, row-major; the renderer reduces its depth
//! target into them) and the frame's lights in view space; its output the per-tile lists in
//! `cull_tiles`' layout: `counts[t]` lights for tile `t`, their indices ascending at
//! `indices[t * MAX_LIGHTS_PER_TILE ..]`. One workgroup per tile tests the lights 64 at a
//! time, so a tile's list costs `ceil(lights / 64)` steps whatever its length.
//!
//! The per-tile decisions are `TileFrustum::light_visible`'s in f32 on the GPU: a light
//! within rounding of a tile's plane can fall on the other side (the device tests bound
//! how often), never a light that lights a pixel of the tile by more than rounding.

use bytemuck::{Pod, Zeroable};
use shader::{Binding, Entry, Group, Kind, Pass};

use crate::depth::DeferredProjection;
use crate::lights::{
    CullStats, DeferredLight, DeferredTileDepth, MAX_LIGHTS_PER_TILE, tile_counts,
};

/// Invocations per workgroup of [`LIGHT_CULL_PASS`] (one workgroup per tile).
pub const CULL_WORKGROUP: u32 = 64;

/// The culling pass's parameters (WGSL `DeferredLightCullParams`), 48 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct LightCullParams {
    /// The camera's projection and viewport (its depth mode decides which depth is far).
    pub projection: DeferredProjection,
    /// Tiles across and down ([`tile_counts`] of the viewport).
    pub tiles: [u32; 2],
    /// Lights in the `lights` binding (at most [`MAX_LIGHTS`](crate::lights::MAX_LIGHTS)
    /// are read).
    pub light_count: u32,
    /// Zero.
    pub pad: u32,
}
const _: () = assert!(size_of::<LightCullParams>() == 48);

impl LightCullParams {
    /// The parameters for `light_count` lights seen through `projection` (its viewport
    /// gives the tiles).
    #[must_use]
    pub fn new(projection: DeferredProjection, light_count: u32) -> Self {
        let (tx, ty) = tile_counts(projection.viewport[0] as u32, projection.viewport[1] as u32);
        Self {
            projection,
            tiles: [tx, ty],
            light_count,
            pad: 0,
        }
    }

    /// Tiles of the viewport.
    #[must_use]
    pub fn tile_count(&self) -> u32 {
        self.tiles[0].saturating_mul(self.tiles[1])
    }

    /// Words the `indices` binding needs: [`MAX_LIGHTS_PER_TILE`] per tile.
    #[must_use]
    pub fn index_words(&self) -> u64 {
        u64::from(self.tile_count()) * u64::from(MAX_LIGHTS_PER_TILE)
    }
}

/// What the culling pass counted (WGSL `DeferredLightCullCounters`), 16 bytes, zeroed
/// before each dispatch.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct LightCullCounters {
    /// Tiles with geometry.
    pub tiles_with_geometry: u32,
    /// (tile, light) pairs listed.
    pub pairs: u32,
    /// Tiles whose list hit [`MAX_LIGHTS_PER_TILE`].
    pub overflowed_tiles: u32,
    /// Zero.
    pub pad: u32,
}
const _: () = assert!(size_of::<LightCullCounters>() == 16);

impl LightCullCounters {
    /// As [`CullStats`].
    #[must_use]
    pub fn stats(&self) -> CullStats {
        CullStats {
            tiles_with_geometry: self.tiles_with_geometry,
            pairs: u64::from(self.pairs),
            overflowed_tiles: self.overflowed_tiles,
        }
    }
}

/// The culling pass: one bind group `cull` (the [`LightCullParams`], the tiles' depth
/// ranges, the lights, the per-tile counts and index lists, the counters) and one entry
/// point `cull_lights` of [`CULL_WORKGROUP`] invocations per tile.
pub const LIGHT_CULL_PASS: Pass<LightCullParams> = Pass {
    name: "deferred light culling",
    module: "deferred::light_cull_pass",
    library: crate::wgsl::LIBRARY,
    features: &[],
    groups: &[Group {
        name: "cull",
        bindings: &[
            Binding::new("params", Kind::uniform(size_of::<LightCullParams>())),
            Binding::new("tile_depths", Kind::read(size_of::<DeferredTileDepth>())),
            Binding::new("lights", Kind::read(size_of::<DeferredLight>())),
            Binding::new("counts", Kind::read_write(4)),
            Binding::new("indices", Kind::read_write(4)),
            Binding::new("counters", Kind::read_write(size_of::<LightCullCounters>())),
        ],
    }],
    entries: &[Entry::items("cull_lights", CULL_WORKGROUP, |p| {
        p.tile_count().saturating_mul(CULL_WORKGROUP)
    })],
    zeroed: &["counters"],
};

#[cfg(test)]
mod tests {
    use super::*;
    use shadercheck::{Caps, assert_struct_layout, const_u32, members};

    #[test]
    fn description_matches_its_module() {
        shadercheck::check_pass(&LIGHT_CULL_PASS, |_| Caps::CORE);
    }

    #[test]
    fn wgsl_layouts_and_constants_match_rust() {
        let m = shadercheck::assert_composed(
            crate::wgsl::LIBRARY,
            LIGHT_CULL_PASS.module,
            &[],
            Caps::CORE,
        );
        assert_struct_layout(
            &m,
            "DeferredLightCullParams",
            size_of::<LightCullParams>(),
            &members!(LightCullParams {
                projection,
                tiles,
                light_count,
                pad
            }),
        );
        assert_struct_layout(
            &m,
            "DeferredLightCullCounters",
            size_of::<LightCullCounters>(),
            &members!(LightCullCounters {
                tiles_with_geometry,
                pairs,
                overflowed_tiles,
                pad
            }),
        );
        assert_eq!(
            const_u32(&m, "DEFERRED_CULL_WORKGROUP"),
            Some(CULL_WORKGROUP)
        );
        assert_eq!(
            const_u32(&m, "DEFERRED_MAX_WORKGROUPS_X"),
            Some(shader::MAX_WORKGROUPS_X)
        );
        assert_eq!(
            const_u32(&m, "DEFERRED_MAX_LIGHTS"),
            Some(crate::lights::MAX_LIGHTS)
        );
    }
}
