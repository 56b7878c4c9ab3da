//! Screen tiles and the tessellated grid: the CPU twins of the passes between the mini
//! G-buffer and the screen-space tessellated mesh.
//!
//! Far Cry 5 divides the water buffer into 32 x 32 tiles ("we found 32 by 32 is the best
//! for all hardware"), counts the water pixels of each tile in 8 x 8-thread groups (one
//! atomic per group, or one per wave with a ballot), then a second pass walks the counts,
//! and for every tile with water increments the indirect draw's instance count and writes
//! the tile ID to a list. The draw then renders one tessellated grid per listed tile: with
//! a 512 x 512 buffer and 32 tiles, "512 divided by 32 ... we get 16 by 16 quads", a
//! constant, per-pixel tessellation density (seed 003).
//!
//! - [`TileGrid`]: the tiling of a `width x height` buffer into `tile_size` tiles (the
//!   talk's [`TILE_SIZE`] = 32 by default; partial tiles at the right and bottom edges).
//! - [`count_pass`] and [`list_pass`]: the two passes, buffer for buffer; [`classify`]
//!   runs both.
//! - [`GridMesh`]: the per-tile grid with 16-bit vertices.
//!
//! # Killing triangles without NaN
//!
//! The talk uses NaN positions to clip vertices that have no water. WGSL makes NaN results
//! indeterminate, so no clipping is guaranteed. A triangle is instead killed by giving all
//! three of its vertices the same position outside the clip volume ([`COLLAPSED_CLIP`]):
//! it has zero area and is culled. For that every vertex must know its whole triangle, so
//! the grid does not share vertices: each triangle has its own three 16-bit vertex words,
//! each naming its cell, which of the cell's two triangles, and which corner. Every vertex
//! of a triangle then tests the same three texels and takes the same decision. The grid
//! has `6 * quads^2` vertices and is drawn non-indexed ([`WaterDrawIndirect`]).
//!
//! # 16-bit vertex layout
//!
//! | bits | field |
//! | --- | --- |
//! | 0..=5 | cell x, `0..quads` |
//! | 6..=11 | cell y, `0..quads` |
//! | 12 | triangle of the cell: 0 = (c00, c10, c11), 1 = (c00, c11, c01) |
//! | 13..=14 | corner of that triangle, 0..=2 |
//! | 15 | 0 |
//!
//! Corners are in grid units with +x right and +y down (the texture's orientation); both
//! triangles wind clockwise there, which is counter-clockwise in NDC (+y up), wgpu's
//! default front face.

use alloc::vec;
use alloc::vec::Vec;

use bytemuck::{Pod, Zeroable};
use glam::UVec2;

use crate::Error;
use crate::gbuffer::DataWord;
use crate::grid::size_getters;

/// The talk's tile size in pixels.
pub const TILE_SIZE: u32 = 32;
/// Largest tile side [`TileGrid`] accepts.
pub const MAX_TILE_SIZE: u32 = 256;
/// Largest buffer side [`TileGrid`] accepts (a core wgpu 2D texture limit).
pub const MAX_BUFFER_SIZE: u32 = 8192;
/// Threads per side of a counting workgroup (8 x 8 = 64 threads, one wave on AMD).
pub const COUNT_GROUP_SIZE: u32 = 8;
/// Most quads per grid side (6-bit cell coordinates).
pub const MAX_GRID_QUADS: u32 = 64;
/// Bits of each cell coordinate in a grid vertex word.
pub const GRID_CELL_BITS: u32 = 6;
/// Shift of the triangle bit.
pub const GRID_HALF_SHIFT: u32 = 12;
/// Shift of the 2-bit corner.
pub const GRID_CORNER_SHIFT: u32 = 13;
/// Where a killed triangle's three vertices go: one point behind the near plane.
pub const COLLAPSED_CLIP: [f32; 4] = [0.0, 0.0, -1.0, 1.0];

/// The corner offsets of the two triangles of a cell, `[triangle][corner] = (dx, dy)`.
pub const GRID_CORNERS: [[[u32; 2]; 3]; 2] = [[[0, 0], [1, 0], [1, 1]], [[0, 0], [1, 1], [0, 1]]];

/// wgpu's `DrawIndirectArgs` for the grid: vertex count, instance count (tiles with water),
/// first vertex, first instance.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Pod, Zeroable)]
#[repr(C)]
pub struct WaterDrawIndirect {
    /// Vertices per grid (`6 * quads^2`).
    pub vertex_count: u32,
    /// Tiles with water.
    pub instance_count: u32,
    /// 0.
    pub first_vertex: u32,
    /// 0.
    pub first_instance: u32,
}
const _: () = assert!(size_of::<WaterDrawIndirect>() == 16);

/// The tiling of a buffer. Tile `(tx, ty)` has ID `ty * tiles_x + tx` and covers pixels
/// `[tx * tile_size, min((tx + 1) * tile_size, width))` (same in y).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TileGrid {
    width: u32,
    height: u32,
    tile_size: u32,
}

impl TileGrid {
    /// A `width x height` buffer (each `1..=MAX_BUFFER_SIZE`) in tiles of `tile_size`
    /// (`1..=MAX_TILE_SIZE`, a multiple of [`COUNT_GROUP_SIZE`] so groups never straddle
    /// tiles).
    pub fn new(width: u32, height: u32, tile_size: u32) -> Result<Self, Error> {
        for (field, v) in [("buffer width", width), ("buffer height", height)] {
            if v == 0 || v > MAX_BUFFER_SIZE {
                return Err(Error::InvalidSize {
                    field,
                    value: v,
                    rule: "in 1..=MAX_BUFFER_SIZE (8192)",
                });
            }
        }
        if tile_size == 0
            || tile_size > MAX_TILE_SIZE
            || !tile_size.is_multiple_of(COUNT_GROUP_SIZE)
        {
            return Err(Error::InvalidSize {
                field: "tile size",
                value: tile_size,
                rule: "a multiple of COUNT_GROUP_SIZE (8) in 8..=MAX_TILE_SIZE (256)",
            });
        }
        Ok(Self {
            width,
            height,
            tile_size,
        })
    }

    size_getters!("Buffer width in pixels.", "Buffer height in pixels.");
    /// Tile side in pixels.
    #[must_use]
    pub fn tile_size(&self) -> u32 {
        self.tile_size
    }
    /// Tiles per row.
    #[must_use]
    pub fn tiles_x(&self) -> u32 {
        self.width.div_ceil(self.tile_size)
    }
    /// Tile rows.
    #[must_use]
    pub fn tiles_y(&self) -> u32 {
        self.height.div_ceil(self.tile_size)
    }
    /// Number of tiles.
    #[must_use]
    pub fn tile_count(&self) -> u32 {
        self.tiles_x() * self.tiles_y()
    }
    /// The tile holding pixel `p` (which must be inside the buffer).
    #[must_use]
    pub fn tile_of(&self, p: UVec2) -> u32 {
        (p.y / self.tile_size) * self.tiles_x() + p.x / self.tile_size
    }
    /// Top-left pixel of tile `id`.
    #[must_use]
    pub fn tile_origin(&self, id: u32) -> UVec2 {
        UVec2::new(id % self.tiles_x(), id / self.tiles_x()) * self.tile_size
    }
    /// Counting workgroups to dispatch: one per 8 x 8 pixels.
    #[must_use]
    pub fn count_workgroups(&self) -> UVec2 {
        UVec2::new(
            self.width.div_ceil(COUNT_GROUP_SIZE),
            self.height.div_ceil(COUNT_GROUP_SIZE),
        )
    }
}

/// Pass 1, per 8 x 8 group: count the group's valid pixels (a ballot and popcount on the
/// GPU), then one atomic add of the total into the tile's counter. `counts` has one entry
/// per tile and is added to (clear it first). Words past `width * height` are ignored.
pub fn count_pass(grid: &TileGrid, data: &[u32], counts: &mut [u32]) -> Result<(), Error> {
    check_len(
        "data words",
        data.len(),
        (grid.width * grid.height) as usize,
    )?;
    check_len("tile counts", counts.len(), grid.tile_count() as usize)?;
    let groups = grid.count_workgroups();
    for gy in 0..groups.y {
        for gx in 0..groups.x {
            let mut group_total = 0;
            for ly in 0..COUNT_GROUP_SIZE {
                for lx in 0..COUNT_GROUP_SIZE {
                    let (x, y) = (gx * COUNT_GROUP_SIZE + lx, gy * COUNT_GROUP_SIZE + ly);
                    if x < grid.width
                        && y < grid.height
                        && DataWord(data[(y * grid.width + x) as usize]).is_valid()
                    {
                        group_total += 1;
                    }
                }
            }
            if group_total > 0 {
                let tile = grid.tile_of(UVec2::new(gx, gy) * COUNT_GROUP_SIZE);
                counts[tile as usize] += group_total;
            }
        }
    }
    Ok(())
}

/// Pass 2, per tile: where the count is non-zero, take a slot with an atomic increment of
/// the draw's instance count and write the tile ID there. On the GPU the order of the list
/// depends on scheduling; this twin writes it in tile order, and every consumer must treat
/// it as a set. `tile_list` needs room for every tile. `args.vertex_count` is set from
/// `mesh`; `args.instance_count` is added to (clear it first).
pub fn list_pass(
    counts: &[u32],
    mesh: &GridMesh,
    tile_list: &mut [u32],
    args: &mut WaterDrawIndirect,
) -> Result<(), Error> {
    check_len("tile list", tile_list.len(), counts.len())?;
    args.vertex_count = mesh.vertex_count();
    for (tile, &c) in counts.iter().enumerate() {
        if c > 0 {
            let slot = args.instance_count as usize;
            if slot >= tile_list.len() {
                return Err(Error::LengthMismatch {
                    field: "tile list (instance count already past it)",
                    len: tile_list.len(),
                    expected: slot + 1,
                });
            }
            tile_list[slot] = tile as u32;
            args.instance_count += 1;
        }
    }
    Ok(())
}

fn check_len(field: &'static str, len: usize, expected: usize) -> Result<(), Error> {
    if len == expected {
        Ok(())
    } else {
        Err(Error::LengthMismatch {
            field,
            len,
            expected,
        })
    }
}

/// Both passes' results.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TileClassification {
    /// Water pixels per tile.
    pub counts: Vec<u32>,
    /// IDs of the tiles with water, in tile order.
    pub tiles: Vec<u32>,
    /// The draw's arguments.
    pub args: WaterDrawIndirect,
}

/// Runs [`count_pass`] and [`list_pass`] over a data-word buffer.
pub fn classify(
    grid: &TileGrid,
    data: &[u32],
    mesh: &GridMesh,
) -> Result<TileClassification, Error> {
    let mut counts = vec![0; grid.tile_count() as usize];
    count_pass(grid, data, &mut counts)?;
    let mut list = vec![0; counts.len()];
    let mut args = WaterDrawIndirect::default();
    list_pass(&counts, mesh, &mut list, &mut args)?;
    list.truncate(args.instance_count as usize);
    Ok(TileClassification {
        counts,
        tiles: list,
        args,
    })
}

/// One decoded grid vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GridVertex {
    /// The cell.
    pub cell: UVec2,
    /// Which of the cell's two triangles.
    pub triangle: u32,
    /// Which corner of it.
    pub corner: u32,
}

impl GridVertex {
    /// Packs to the 16-bit word (fields masked to their widths).
    #[must_use]
    pub fn pack(self) -> u16 {
        let m = (1 << GRID_CELL_BITS) - 1;
        ((self.cell.x & m)
            | (self.cell.y & m) << GRID_CELL_BITS
            | (self.triangle & 1) << GRID_HALF_SHIFT
            | (self.corner & 3) << GRID_CORNER_SHIFT) as u16
    }

    /// Unpacks a word. A corner field of 3 (never written) reads as corner 2.
    #[must_use]
    pub fn unpack(word: u16) -> GridVertex {
        let w = u32::from(word);
        let m = (1 << GRID_CELL_BITS) - 1;
        GridVertex {
            cell: UVec2::new(w & m, (w >> GRID_CELL_BITS) & m),
            triangle: (w >> GRID_HALF_SHIFT) & 1,
            corner: ((w >> GRID_CORNER_SHIFT) & 3).min(2),
        }
    }

    /// This vertex's position in grid units (`0..=quads` on each axis).
    #[must_use]
    pub fn position(self) -> UVec2 {
        let [dx, dy] = GRID_CORNERS[self.triangle as usize][self.corner as usize];
        self.cell + UVec2::new(dx, dy)
    }

    /// All three corners of this vertex's triangle, in grid units.
    #[must_use]
    pub fn triangle_corners(self) -> [UVec2; 3] {
        GRID_CORNERS[self.triangle as usize].map(|[dx, dy]| self.cell + UVec2::new(dx, dy))
    }
}

/// The per-tile grid: `quads x quads` cells of two triangles, 6 unshared 16-bit vertices
/// per cell (see the module docs).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GridMesh {
    quads: u32,
    vertices: Vec<u16>,
}

impl GridMesh {
    /// A grid of `quads x quads` cells, `quads` in `1..=MAX_GRID_QUADS`.
    pub fn new(quads: u32) -> Result<Self, Error> {
        if quads == 0 || quads > MAX_GRID_QUADS {
            return Err(Error::InvalidSize {
                field: "grid quads per side",
                value: quads,
                rule: "in 1..=MAX_GRID_QUADS (64)",
            });
        }
        let mut vertices = Vec::with_capacity((6 * quads * quads) as usize);
        for y in 0..quads {
            for x in 0..quads {
                for triangle in 0..2 {
                    for corner in 0..3 {
                        vertices.push(
                            GridVertex {
                                cell: UVec2::new(x, y),
                                triangle,
                                corner,
                            }
                            .pack(),
                        );
                    }
                }
            }
        }
        Ok(Self { quads, vertices })
    }

    /// The talk's density rule: quads per tile side = water-buffer side / tiles per side,
    /// e.g. `512 / 32 = 16`.
    pub fn for_buffer(buffer_side: u32, tiles_per_side: u32) -> Result<Self, Error> {
        if tiles_per_side == 0 {
            return Err(Error::InvalidSize {
                field: "tiles per side",
                value: 0,
                rule: "at least 1",
            });
        }
        Self::new(buffer_side / tiles_per_side)
    }

    /// Quads per side.
    #[must_use]
    pub fn quads(&self) -> u32 {
        self.quads
    }

    /// Vertices (`6 * quads^2`).
    #[must_use]
    pub fn vertex_count(&self) -> u32 {
        self.vertices.len() as u32
    }

    /// The vertex buffer: one `u16` per vertex (`Uint16` is not a vertex format; upload as
    /// pairs in `Uint16x2`, or read with `vertex_index` from a storage buffer of `u32`s).
    #[must_use]
    pub fn vertices(&self) -> &[u16] {
        &self.vertices
    }

    /// The vertex shader's placement of vertex `word` of tile `tile_origin` (pixels): its
    /// pixel position in the water buffer (`tile_origin + position * tile_size / quads`),
    /// or `None` when any corner of its triangle lands on a pixel without water (or outside
    /// the buffer), in which case the shader writes [`COLLAPSED_CLIP`].
    pub fn place_vertex(
        &self,
        word: u16,
        grid: &TileGrid,
        tile_origin: UVec2,
        valid: impl Fn(UVec2) -> bool,
    ) -> Option<UVec2> {
        let v = GridVertex::unpack(word);
        let to_pixel = |p: UVec2| tile_origin + p * grid.tile_size / self.quads;
        let alive = v.triangle_corners().into_iter().all(|c| {
            let p = to_pixel(c);
            // The far edge of a tile samples the next tile's first pixel, the one the
            // neighbouring grid's near edge samples, so adjacent tiles meet without a crack
            // (clamped to the buffer's last pixel).
            let p = p.min(UVec2::new(grid.width - 1, grid.height - 1));
            valid(p)
        });
        alive.then(|| to_pixel(v.position()))
    }

    /// The triangles a tile draws (pixel positions), in vertex order: the CPU twin of the
    /// tile's draw. Killed triangles are left out.
    pub fn tile_triangles(
        &self,
        grid: &TileGrid,
        tile: u32,
        valid: impl Fn(UVec2) -> bool,
    ) -> Vec<[UVec2; 3]> {
        let origin = grid.tile_origin(tile);
        self.vertices
            .chunks_exact(3)
            .filter_map(|t| {
                let a = self.place_vertex(t[0], grid, origin, &valid)?;
                let b = self.place_vertex(t[1], grid, origin, &valid)?;
                let c = self.place_vertex(t[2], grid, origin, &valid)?;
                Some([a, b, c])
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn talk_density_512_over_32_is_16_quads() {
        let m = GridMesh::for_buffer(512, 32).unwrap();
        assert_eq!(m.quads(), 16);
        assert_eq!(m.vertex_count(), 6 * 256);
        assert!(GridMesh::new(65).is_err());
        assert!(GridMesh::new(0).is_err());
    }

    #[test]
    fn vertex_words_roundtrip() {
        let m = GridMesh::new(64).unwrap();
        for (i, &w) in m.vertices().iter().enumerate() {
            let v = GridVertex::unpack(w);
            assert_eq!(v.pack(), w);
            assert_eq!(w >> 15, 0);
            let cell = i as u32 / 6;
            assert_eq!(v.cell, UVec2::new(cell % 64, cell / 64));
        }
    }

    #[test]
    fn triangles_wind_clockwise_in_y_down_grid_space() {
        for tri in GRID_CORNERS {
            let [a, b, c] = tri.map(|[x, y]| (x as i32, y as i32));
            let cross = (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0);
            // With +y down, a positive cross product is clockwise on screen.
            assert!(cross > 0);
        }
    }
}
