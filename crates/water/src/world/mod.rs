//! The water query API: one entry point for "where is the water surface here".
//!
//! Far Cry 5 replaced the engine's many water-level functions by "a single function that
//! returned the water level and handled everything": the water quadtree, "all the baked
//! water height maps that are streamed in, such as lakes, rivers, and waterfalls", and the
//! ocean, plus the flow direction, because "everything we do in the GPU, we have to
//! replicate in the CPU" for objects carried by the flow (seed 003).
//!
//! [`WaterWorldBuilder`] takes the sources: flat lakes (polygon and height), rivers (a
//! spline of [`RiverPoint`]s with width, depth and speed, slopes and waterfalls allowed)
//! and an ocean level. [`WaterWorldBuilder::build`] bakes rivers to height tiles and builds
//! a quadtree over lakes and tiles, all into one array of `u32` words
//! ([`WaterWorld::words`]): that array *is* the GPU data (upload it as an `R32Uint`
//! texture with [`WaterWorld::to_texture`]), and [`WaterWorld::query`] reads the same words
//! with the same algorithm as `water_world_query` in [`wgsl::WORLD`](crate::wgsl::WORLD).
//!
//! # Conventions
//!
//! World space is metres, right-handed, z up: a query takes the horizontal position
//! `(x, y)`; heights are z. Where several bodies cover a position the highest surface wins
//! (on a tie the ocean, then the quadtree's first item). A non-finite position gives
//! `None`, never a panic.
//!
//! # Lakes
//!
//! A lake is exact: the quadtree stores, per leaf and lake, either "the whole leaf is
//! inside", or what the even-odd test of a ray from the query point towards +x needs inside
//! that leaf: the *local* edges (whose bounding box meets the leaf), tested exactly, and
//! for the *far* edges entirely to the right, whose crossing depends only on the query's
//! y, a base parity and the sorted y breakpoints inside the leaf's band. Both shrink with
//! the leaf, so leaves split until each partial lake has at most
//! [`WorldSettings::max_leaf_edges`] local edges plus breakpoints (or the depth limit is
//! hit).
//!
//! # Rivers
//!
//! A river's centre line is the uniform Catmull–Rom spline through its points in x and y,
//! with height, width, depth and speed linear between points (no overshoot at a
//! waterfall). The bake rasterises it
//! onto a world-aligned grid of texel corners [`WorldSettings::texel_size`] apart: a corner
//! is water when its horizontal distance to the centre line is at most half the width
//! there, and gets the spline's surface height, the bed depth with a parabolic cross
//! section (`depth (1 - s^2)`, `s` the distance over the half width), and the flow: the
//! spline's horizontal downstream direction times the speed with the same parabolic
//! profile. Where a river overlaps itself (a waterfall seen from above), the nearest centre
//! line wins. Corners are grouped in tiles of [`WorldSettings::tile_texels`] cells; tiles
//! share their border corners, so bilinear sampling is seamless. A query interpolates
//! bilinearly over the water corners of its cell, and finds water only where the nearest
//! corner is water (so the shore is resolved to half a texel).
//!
//! # Data layout
//!
//! | words | what |
//! | --- | --- |
//! | 0..20 | header: magic `WATR`, version, flags (bit 0: ocean), ocean level, ocean material, quadtree root `x0, y0, size`, offsets and counts of nodes, items, lakes, tiles and edges, tile texels, river count, depth, total words |
//! | nodes, 2 words | internal: first child, `0xffffffff`; leaf: first item, item count. Children: (x low, y low), (x high, y low), (x low, y high), (x high, y high) |
//! | items, 4 words | `kind << 30 \| index`, then for kind 1: start in the edge section (words), local edge count, `base << 31 \| breakpoint count`; kind 0 lake inside, 1 lake partial, 2 river tile |
//! | lakes, 2 words | height (f32), material |
//! | edge section | per partial item: its local edges `x0, y0, x1, y1` (f32), then its breakpoints (f32, sorted) |
//! | tiles, 6 words | origin `x, y` (f32), `1 / texel` (f32), river, material, first texel word |
//! | texels, 3 words | height (f32, `0xffffffff` = no water), flow `pack2x16float(x, y)`, `pack2x16float(depth, s)` |

mod bake;
mod geom;
mod read;
pub(crate) mod spline;

use alloc::vec::Vec;
use core::ops::ControlFlow;

use glam::{Vec2, Vec3};

use crate::Error;
use crate::progress::Progress;

pub use spline::RiverPoint;

/// `"WATR"` as a little-endian word.
pub const WORLD_MAGIC: u32 = u32::from_le_bytes(*b"WATR");
/// Version of the data layout.
pub const WORLD_VERSION: u32 = 1;
/// Header words.
pub const WORLD_HEADER_WORDS: u32 = 20;
/// Node words.
pub const NODE_WORDS: u32 = 2;
/// Item words.
pub const ITEM_WORDS: u32 = 4;
/// Lake record words.
pub const LAKE_WORDS: u32 = 2;
/// Edge words.
pub const EDGE_WORDS: u32 = 4;
/// Tile record words.
pub const TILE_WORDS: u32 = 6;
/// Words per tile texel.
pub const TEXEL_WORDS: u32 = 3;
/// The second word of an internal node.
pub const NODE_INTERNAL: u32 = u32::MAX;
/// A texel height word meaning "no water".
pub const TEXEL_NONE: u32 = u32::MAX;
/// Item kind: the whole leaf is inside the lake.
pub const ITEM_LAKE_INSIDE: u32 = 0;
/// Item kind: the lake's boundary crosses the leaf; test its edges.
pub const ITEM_LAKE_PARTIAL: u32 = 1;
/// Item kind: a river height tile.
pub const ITEM_RIVER_TILE: u32 = 2;
/// Shift of an item's (and a body ID's) kind.
pub const KIND_SHIFT: u32 = 30;
/// Body ID kind of a lake.
pub const BODY_LAKE: u32 = 1;
/// Body ID kind of a river.
pub const BODY_RIVER: u32 = 2;
/// Body ID kind of the ocean.
pub const BODY_OCEAN: u32 = 3;
/// Deepest quadtree allowed.
pub const MAX_QUADTREE_DEPTH: u32 = 20;
/// Most lakes or rivers (indices must fit under the kind bits).
pub const MAX_BODIES: u32 = 1 << KIND_SHIFT;
/// Most points in one lake polygon or one river.
pub const MAX_POINTS_PER_BODY: u32 = 1 << 20;
/// Most words in a baked world: an 8192 x 8192 `R32Uint` texture (the core wgpu limit).
pub const MAX_WORLD_WORDS: u64 = 8192 * 8192;
/// Most texels one river may cover (summed over the bounding boxes of its segments'
/// capsules), checked before any rasterising (the world bake and the flow bake).
pub const MAX_RIVER_TEXELS: u64 = 1 << 26;
/// Largest coordinate magnitude accepted, metres (f32 keeps 1/16 m there... and finer).
pub const MAX_COORDINATE: f32 = 1.0e6;

/// Header word indices.
pub mod header {
    /// Magic.
    pub const MAGIC: usize = 0;
    /// Layout version.
    pub const VERSION: usize = 1;
    /// Bit 0: there is an ocean.
    pub const FLAGS: usize = 2;
    /// Ocean level (f32).
    pub const OCEAN_LEVEL: usize = 3;
    /// Ocean material.
    pub const OCEAN_MATERIAL: usize = 4;
    /// Quadtree root minimum x (f32).
    pub const ROOT_X: usize = 5;
    /// Quadtree root minimum y (f32).
    pub const ROOT_Y: usize = 6;
    /// Quadtree root side (f32; 0 without a quadtree).
    pub const ROOT_SIZE: usize = 7;
    /// First node word.
    pub const NODES: usize = 8;
    /// Node count.
    pub const NODE_COUNT: usize = 9;
    /// First item word.
    pub const ITEMS: usize = 10;
    /// First lake record word.
    pub const LAKES: usize = 11;
    /// Lake count.
    pub const LAKE_COUNT: usize = 12;
    /// First tile record word.
    pub const TILES: usize = 13;
    /// Tile count.
    pub const TILE_COUNT: usize = 14;
    /// Cells per tile side (texels per side minus one).
    pub const TILE_TEXELS: usize = 15;
    /// First edge word.
    pub const EDGES: usize = 16;
    /// River count.
    pub const RIVER_COUNT: usize = 17;
    /// Quadtree depth.
    pub const DEPTH: usize = 18;
    /// Total words.
    pub const TOTAL: usize = 19;
}

/// A flat lake: a simple polygon (counter-clockwise or clockwise, not closed: the last
/// point connects to the first) at one surface height.
#[derive(Clone, Debug, PartialEq)]
pub struct Lake {
    /// Outline, metres.
    pub polygon: Vec<Vec2>,
    /// Surface height, metres.
    pub height: f32,
    /// Material index.
    pub material: u32,
}

/// A river.
#[derive(Clone, Debug, PartialEq)]
pub struct River {
    /// Control points, upstream first.
    pub points: Vec<RiverPoint>,
    /// Material index.
    pub material: u32,
}

/// The ocean: water everywhere at one level.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ocean {
    /// Sea level, metres.
    pub level: f32,
    /// Material index.
    pub material: u32,
}

/// Bake settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorldSettings {
    /// River texel spacing, metres.
    pub texel_size: f32,
    /// Cells per river tile side (tiles hold `(n + 1)^2` texels).
    pub tile_texels: u32,
    /// Most edges a partial lake may have in a leaf before the leaf splits.
    pub max_leaf_edges: u32,
    /// Most items in a leaf before it splits.
    pub max_leaf_items: u32,
    /// Deepest quadtree level (at most [`MAX_QUADTREE_DEPTH`]).
    pub max_depth: u32,
}

impl Default for WorldSettings {
    /// 1 m texels, 64-cell tiles, 16 edges and 8 items per leaf, depth 16.
    fn default() -> Self {
        Self {
            texel_size: 1.0,
            tile_texels: 64,
            max_leaf_edges: 16,
            max_leaf_items: 8,
            max_depth: 16,
        }
    }
}

/// Collects water bodies and bakes them.
#[derive(Clone, Debug, Default)]
pub struct WaterWorldBuilder {
    /// The ocean, if any.
    pub ocean: Option<Ocean>,
    /// Lakes.
    pub lakes: Vec<Lake>,
    /// Rivers.
    pub rivers: Vec<River>,
    /// Bake settings.
    pub settings: WorldSettings,
}

/// Which body a query found.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct BodyId(pub u32);

/// What kind of body.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BodyKind {
    /// A lake (index into the builder's lakes).
    Lake(u32),
    /// A river (index into the builder's rivers).
    River(u32),
    /// The ocean.
    Ocean,
}

impl BodyId {
    /// The ocean's ID.
    pub const OCEAN: BodyId = BodyId(BODY_OCEAN << KIND_SHIFT);

    /// A lake's ID.
    #[must_use]
    pub const fn lake(index: u32) -> BodyId {
        BodyId(BODY_LAKE << KIND_SHIFT | (index & (MAX_BODIES - 1)))
    }

    /// A river's ID.
    #[must_use]
    pub const fn river(index: u32) -> BodyId {
        BodyId(BODY_RIVER << KIND_SHIFT | (index & (MAX_BODIES - 1)))
    }

    /// Decodes the kind and index (`None` for a word no query returns).
    #[must_use]
    pub fn kind(self) -> Option<BodyKind> {
        let i = self.0 & (MAX_BODIES - 1);
        match self.0 >> KIND_SHIFT {
            BODY_LAKE => Some(BodyKind::Lake(i)),
            BODY_RIVER => Some(BodyKind::River(i)),
            BODY_OCEAN if i == 0 => Some(BodyKind::Ocean),
            _ => None,
        }
    }
}

/// The answer to a water query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WaterLevel {
    /// Surface height, metres.
    pub height: f32,
    /// Which body.
    pub body: BodyId,
    /// Its material index.
    pub material: u32,
    /// Depth of the bed below the surface, metres, where known (rivers); `f32::INFINITY`
    /// for lakes and the ocean (the world knows no terrain).
    pub depth: f32,
    /// Flow velocity, m/s along x and y (zero for lakes and the ocean).
    pub flow: Vec2,
}

impl WaterLevel {
    /// Flow direction (unit, or zero) and speed (m/s).
    #[must_use]
    pub fn flow_direction_and_speed(&self) -> (Vec2, f32) {
        let s = self.flow.length();
        (self.flow.normalize_or_zero(), s)
    }

    /// Whether world point `p` is under this surface.
    #[must_use]
    pub fn is_submerged(&self, p: Vec3) -> bool {
        p.z < self.height
    }
}

/// One lake's or river's extent in a baked world ([`WaterWorld::bodies`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyBounds {
    /// Which body.
    pub body: BodyId,
    /// Its material index (a river's first tile's).
    pub material: u32,
    /// Smallest horizontal corner, metres: every point where a query finds this body lies
    /// in `[min, max]`.
    pub min: Vec2,
    /// Largest horizontal corner, metres.
    pub max: Vec2,
    /// Lowest and highest surface height, metres (equal for a lake).
    pub height: (f32, f32),
}

/// A baked water world. See the module docs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WaterWorld {
    words: Vec<u32>,
}

impl WaterWorldBuilder {
    /// An empty builder with default settings.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Bakes the world (reports [`crate::Stage::RiverTiles`] and
    /// [`crate::Stage::Quadtree`]).
    pub fn build(
        &self,
        progress: &mut impl FnMut(Progress) -> ControlFlow<()>,
    ) -> Result<WaterWorld, Error> {
        let words = bake::bake(self, progress)?;
        Ok(WaterWorld { words })
    }
}

impl WaterWorld {
    /// Wraps words baked before (e.g. loaded from disk), checking the header and that every
    /// offset and count stays inside the array, so queries cannot read out of bounds
    /// (queries on any accepted array never panic).
    pub fn from_words(words: Vec<u32>) -> Result<Self, Error> {
        read::validate(&words)?;
        Ok(Self { words })
    }

    /// The baked words (the GPU buffer).
    #[must_use]
    pub fn words(&self) -> &[u32] {
        &self.words
    }

    /// The words laid out as an `R32Uint` texture `width` texels wide (word `i` at
    /// `(i % width, i / width)`), zero-padded to whole rows: `(texels, width, height)`.
    /// `width` is clamped to `1..=8192`.
    #[must_use]
    pub fn to_texture(&self, width: u32) -> (Vec<u32>, u32, u32) {
        let w = width.clamp(1, 8192);
        let h = (self.words.len() as u32).div_ceil(w).max(1);
        let mut t = self.words.clone();
        t.resize((w * h) as usize, 0);
        (t, w, h)
    }

    /// The water surface at horizontal position `p` (metres), or `None`.
    #[must_use]
    pub fn query(&self, p: Vec2) -> Option<WaterLevel> {
        read::query(&self.words, p)
    }

    /// Every body whose water covers `p`, whether or not its surface is the highest there
    /// (the ocean first, then lakes and river tiles in the quadtree's order; a river may
    /// answer once per tile that holds `p`): what [`WaterWorld::query`] chooses from. A
    /// renderer builds each body's mesh over all of its water with it, so that wherever a
    /// body wins the query its mesh is there.
    #[must_use]
    pub fn candidates(&self, p: Vec2) -> Vec<WaterLevel> {
        let mut out = Vec::new();
        read::visit(&self.words, p, |l| out.push(l));
        out
    }

    /// [`WaterWorld::query`] at a 3D position's `(x, y)`.
    #[must_use]
    pub fn water_level(&self, p: Vec3) -> Option<WaterLevel> {
        self.query(p.truncate())
    }

    /// Flow direction (unit) and speed (m/s) at `p`, or `None` where there is no water.
    #[must_use]
    pub fn water_flow(&self, p: Vec2) -> Option<(Vec2, f32)> {
        self.query(p).map(|l| l.flow_direction_and_speed())
    }

    /// Every lake's and river's bounds, material and height range (lakes first, then
    /// rivers, each by index; a body that covers no water is left out): what a renderer
    /// builds the bodies' low-resolution meshes and visibility boxes from. Lake bounds are
    /// those of the quadtree leaves holding the lake (conservative), river bounds those of
    /// its height tiles.
    #[must_use]
    pub fn bodies(&self) -> Vec<BodyBounds> {
        read::bodies(&self.words)
    }

    /// The ocean, if the world has one.
    #[must_use]
    pub fn ocean(&self) -> Option<Ocean> {
        (self.words[header::FLAGS] & 1 != 0).then(|| Ocean {
            level: f32::from_bits(self.words[header::OCEAN_LEVEL]),
            material: self.words[header::OCEAN_MATERIAL],
        })
    }

    /// The quadtree's root square `(min corner, side)` in metres (side 0: no lakes or
    /// rivers).
    #[must_use]
    pub fn root(&self) -> (Vec2, f32) {
        let f = |i: usize| f32::from_bits(self.words[i]);
        (
            Vec2::new(f(header::ROOT_X), f(header::ROOT_Y)),
            f(header::ROOT_SIZE),
        )
    }

    /// Lakes baked.
    #[must_use]
    pub fn lake_count(&self) -> u32 {
        self.words[header::LAKE_COUNT]
    }

    /// Rivers baked.
    #[must_use]
    pub fn river_count(&self) -> u32 {
        self.words[header::RIVER_COUNT]
    }

    /// River tiles baked.
    #[must_use]
    pub fn tile_count(&self) -> u32 {
        self.words[header::TILE_COUNT]
    }

    /// Quadtree nodes.
    #[must_use]
    pub fn node_count(&self) -> u32 {
        self.words[header::NODE_COUNT]
    }

    /// Quadtree depth.
    #[must_use]
    pub fn depth(&self) -> u32 {
        self.words[header::DEPTH]
    }
}
