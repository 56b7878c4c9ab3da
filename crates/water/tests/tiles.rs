//! Screen-tile classification against a per-pixel naive count, the grid's killed triangles
//! against a per-triangle check, and the data word's roundtrip over every word.

use glam::UVec2;
use proptest::prelude::*;
use water::gbuffer::{DataFields, DataFlags, DataWord};
use water::tiles::{GridMesh, TILE_SIZE, TileGrid, classify};

fn valid_word(material: u16) -> u32 {
    DataWord::pack(DataFields {
        shader_id: 3,
        flags: DataFlags::VALID | DataFlags::LIT,
        material,
        foam_mip: 2.0,
        algae_mip: 1.5,
    })
    .unwrap()
    .0
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn classification_matches_a_per_pixel_count(
        w in 1u32..200, h in 1u32..150, density in 0u32..100, seed in any::<u32>(), tile_pow in 0u32..3,
    ) {
        let tile = 8 << tile_pow; // 8, 16, 32
        let grid = TileGrid::new(w, h, tile).unwrap();
        let data: Vec<u32> = (0..w * h)
            .map(|i| {
                let r = water::hash::hash2(i, seed);
                // Invalid words may carry garbage in the other fields.
                if r % 100 < density { valid_word((r >> 8) as u16 & 2047) } else { r & !(1 << 8) }
            })
            .collect();
        let mesh = GridMesh::new(8).unwrap();
        let c = classify(&grid, &data, &mesh).unwrap();
        let mut naive = vec![0u32; grid.tile_count() as usize];
        for y in 0..h {
            for x in 0..w {
                if data[(y * w + x) as usize] & (1 << 8) != 0 {
                    naive[((y / tile) * w.div_ceil(tile) + x / tile) as usize] += 1;
                }
            }
        }
        prop_assert_eq!(&c.counts, &naive);
        let listed: Vec<u32> = (0..naive.len() as u32).filter(|&t| naive[t as usize] > 0).collect();
        prop_assert_eq!(&c.tiles, &listed);
        prop_assert_eq!(c.args.instance_count as usize, listed.len());
        prop_assert_eq!(c.args.vertex_count, mesh.vertex_count());
        prop_assert_eq!((c.args.first_vertex, c.args.first_instance), (0, 0));
    }

    #[test]
    fn every_data_word_roundtrips(w in any::<u32>()) {
        let f = DataWord(w).unpack();
        prop_assert_eq!(DataWord::pack(f).unwrap().0, w);
    }

    #[test]
    fn grid_keeps_exactly_the_triangles_with_three_water_corners(
        quads_pow in 0u32..4, density in 0u32..100, seed in any::<u32>(),
    ) {
        let quads = 4 << quads_pow; // 4..32 per 32-pixel tile
        let grid = TileGrid::new(96, 64, TILE_SIZE).unwrap();
        let valid = |p: UVec2| water::hash::hash3(p.x, p.y, seed) % 100 < density;
        let mesh = GridMesh::new(quads).unwrap();
        for tile in 0..grid.tile_count() {
            let origin = grid.tile_origin(tile);
            let drawn = mesh.tile_triangles(&grid, tile, valid);
            // The naive reference: walk the cells, test each triangle's three pixels.
            let step = TILE_SIZE / quads;
            let px = |c: UVec2| (origin + c * step).min(UVec2::new(95, 63));
            let mut want = Vec::new();
            for cy in 0..quads {
                for cx in 0..quads {
                    let c = UVec2::new(cx, cy);
                    for tri in [[UVec2::ZERO, UVec2::X, UVec2::ONE], [UVec2::ZERO, UVec2::ONE, UVec2::Y]] {
                        let corners = tri.map(|o| c + o);
                        if corners.iter().all(|&k| valid(px(k))) {
                            want.push(corners.map(|k| origin + k * step));
                        }
                    }
                }
            }
            prop_assert_eq!(&drawn, &want);
            for t in &drawn {
                let [a, b, c] = t.map(|p| p.as_ivec2());
                prop_assert!((b - a).perp_dot(c - a) != 0, "a drawn triangle has no area");
            }
        }
    }
}

#[test]
fn bad_sizes_are_errors() {
    assert!(TileGrid::new(0, 10, 32).is_err());
    assert!(TileGrid::new(10, 10, 12).is_err());
    assert!(TileGrid::new(9000, 10, 32).is_err());
    let grid = TileGrid::new(64, 64, 32).unwrap();
    let mesh = GridMesh::new(16).unwrap();
    assert!(classify(&grid, &[0; 10], &mesh).is_err());
    // The talk's 512 x 512 buffer with 32-pixel tiles: 16 x 16 tiles.
    let g = TileGrid::new(512, 512, 32).unwrap();
    assert_eq!((g.tiles_x(), g.tiles_y()), (16, 16));
}
