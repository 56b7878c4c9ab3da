//! Fixed vectors after the talk's examples: the loose-tiling example (one 16x16 tile of
//! one shader, four batch groups, waves of 8 lanes), a VRS quad example with its work
//! expansion, and the talk's measurements on the same tile. Expected values are written
//! out by hand from the pictures below.

mod common;

use tiling::{
    Batch, ClassifyConfig, Geometry, PassDispatch, PlanConfig, VisBuffer, WaveCommand, build_plan,
    classify, depth_equal_waves, expand_wave, quad_command,
};
use visbuf::{ShadingRate, VIS_NONE, VisLayout};
use wave::WaveWidth;

/// The tile: A, B, C, D are four batch groups of one shader; `.` has no vis-buffer
/// geometry.
const TILE: [&str; 16] = [
    "AAAAAAAA........", // A: rows 0-3, x 0-7 (32 pixels)
    "AAAAAAAA........",
    "AAAAAAAA........",
    "AAAAAAAA........",
    "....BBBBBBB.....", // B: rows 4-6, x 4-10 (21 pixels)
    "....BBBBBBB.....",
    "....BBBBBBB.....",
    "................",
    "........C.......", // C: the diagonal x = y from 8 to 15 (8 pixels)
    ".........C......",
    "..........C.....",
    "...........C....",
    "............C...",
    ".............C..",
    "..............C.",
    "DDD............C", // D: row 15, x 0-2 (3 pixels)
];

/// Four one-triangle batches with batch data 10, 20, 30, 40: one pass, groups 0..4, micro
/// batches (and IDs) 0..4 in that order.
fn plan() -> tiling::Plan {
    let tri = Geometry {
        vertex_count: 3,
        primitive_count: 1,
        first_index: 0,
        base_vertex: 0,
    };
    let at = [[0.0f32; 3]];
    let batches: Vec<Batch<'_>> = [10, 20, 30, 40]
        .iter()
        .map(|&d| Batch {
            shader: 5,
            batch_data: d,
            geometry: tri,
            instances: &at,
        })
        .collect();
    build_plan(&batches, &PlanConfig::default()).unwrap()
}

fn words(rows: &[&str; 16]) -> Vec<u32> {
    let mut out = Vec::new();
    for row in rows {
        for ch in row.chars() {
            out.push(match ch {
                '.' => VIS_NONE,
                c => (c as u32 - 'A' as u32) << 16, // micro batch, instance 0, triangle 0
            });
        }
    }
    out
}

#[test]
fn loose_tiling_example_16x16_wave_8() {
    let plan = plan();
    assert_eq!(plan.passes.len(), 1);
    assert_eq!(plan.pass_groups[0], [10, 20, 30, 40]);
    assert_eq!(plan.order, [0, 1, 2, 3]);
    let w = words(&TILE);
    let vis = VisBuffer::new(&w, 16, 16, VisLayout::Standard).unwrap();
    let config = ClassifyConfig::for_plan(&plan, WaveWidth::W8);
    let c = classify(&vis, &plan.table, &[0, 1, 2], &config).unwrap();

    // Phase 1: one tile, one pass, four groups.
    assert_eq!(c.masks, [0b1111]);
    // Phase 2: four counters.
    assert_eq!(c.mid.counter_offsets, [0]);
    assert_eq!(c.mid.counts, [32, 21, 8, 3]);
    assert_eq!(c.mid.pixel_offsets, [0, 32, 53, 61]);
    assert_eq!(c.mid.command_count, 64);
    // Each micro batch is one 3-vertex instance: one chunk each, all visible.
    assert_eq!(c.mid.vertex_cull, [1, 1, 1, 1]);

    // Phase 3: pixel commands, x | y << 7, row-major within each group.
    #[rustfmt::skip]
    let a: [u16; 32] = [
        0, 1, 2, 3, 4, 5, 6, 7,
        128, 129, 130, 131, 132, 133, 134, 135,
        256, 257, 258, 259, 260, 261, 262, 263,
        384, 385, 386, 387, 388, 389, 390, 391,
    ];
    #[rustfmt::skip]
    let b: [u16; 21] = [
        516, 517, 518, 519, 520, 521, 522,
        644, 645, 646, 647, 648, 649, 650,
        772, 773, 774, 775, 776, 777, 778,
    ];
    let cc: [u16; 8] = [1032, 1161, 1290, 1419, 1548, 1677, 1806, 1935];
    let d: [u16; 3] = [1920, 1921, 1922];
    let expect: Vec<u16> = [&a[..], &b, &cc, &d].concat();
    assert_eq!(c.output.commands, expect);
    assert_eq!(c.output.final_counts, [32, 21, 8, 3]);

    // Wave commands: whole waves of 8 per group, the last one partial.
    let wave = |group: u32, first: u32, count: u32| WaveCommand {
        tile: 0,
        pass_group: group << 8,
        first_command: first,
        command_count: count,
    };
    assert_eq!(
        c.output.waves,
        [
            wave(0, 0, 8),
            wave(0, 8, 8),
            wave(0, 16, 8),
            wave(0, 24, 8),
            wave(1, 32, 8),
            wave(1, 40, 8),
            wave(1, 48, 5),
            wave(2, 53, 8),
            wave(3, 61, 3),
        ]
    );
    assert_eq!(c.output.wave_offsets, [0, 4, 7, 8]);
    assert_eq!(
        c.output.passes,
        [PassDispatch {
            x: 9,
            y: 1,
            z: 1,
            first: 0,
            count: 9,
            items: 64
        }]
    );
    // 9 waves x 8 lanes for 64 pixels: 8 unfilled lanes.
    assert_eq!(c.output.waves.len() * 8 - 64, 8);
    // 2 bytes per pixel command, 16 per wave command, 24 for the pass.
    assert_eq!(c.command_bytes(), 64 * 2 + 9 * 16 + 24);

    // HZD's depth-equal pass on the same tile: quads per draw A 8, B 8, C 4, D 2, times
    // 4 lanes over waves of 8: 4 + 4 + 2 + 1 = 11 waves against the 9 above.
    assert_eq!(
        depth_equal_waves(&vis, &plan.table, &config).unwrap(),
        (11, 22)
    );

    // Vertex wave commands: one per micro batch, chunk 0.
    let v = common::plan_vertex_waves(&plan, &c.mid.vertex_cull);
    let ids: Vec<(u32, u32)> = v
        .commands
        .iter()
        .map(|c| (c.micro_batch, c.chunk))
        .collect();
    assert_eq!(ids, [(0, 0), (1, 0), (2, 0), (3, 0)]);
    assert_eq!(v.deltas, [0, 1, 1, 1]);
    assert_eq!(
        v.passes[0],
        PassDispatch {
            x: 4,
            y: 1,
            z: 1,
            first: 0,
            count: 4,
            items: 12
        }
    );
}

#[test]
fn vrs_quads_and_their_expansion() {
    // One micro batch of 4 one-triangle instances; the 4x4 image has four quads:
    //   quad (0,0): instance 0 at 2x2 over all four pixels     -> one command, mask 1111
    //   quad (1,0): instance 1 at 2x1, top row only            -> one command, mask 0011
    //               bottom row empty
    //   quad (0,1): instance 2 at 1x2, left column; right column instance 3 at 1x1
    //                                                          -> mask 0101, then 0010, 1000
    //   quad (1,1): instance 0 at 2x2 but only 3 pixels        -> mask 0111 (pixel 3 empty)
    let tri = Geometry {
        vertex_count: 3,
        primitive_count: 1,
        first_index: 0,
        base_vertex: 0,
    };
    let at = [[0.0f32; 3]; 4];
    let plan = build_plan(
        &[Batch {
            shader: 0,
            batch_data: 0,
            geometry: tri,
            instances: &at,
        }],
        &PlanConfig {
            layout: VisLayout::Vrs,
            ..PlanConfig::default()
        },
    )
    .unwrap();
    let mb = plan.micro_batches[0];
    let word =
        |instance: u32, rate: ShadingRate| common::word(VisLayout::Vrs, &mb, instance, 0, rate);
    let q = word(0, ShadingRate::Rate2x2);
    let h = word(1, ShadingRate::Rate2x1);
    let v = word(2, ShadingRate::Rate1x2);
    let s = word(3, ShadingRate::Rate1x1);
    let n = VIS_NONE;
    #[rustfmt::skip]
    let words = [
        q, q, h, h,
        q, q, n, n,
        v, s, q, q,
        v, s, q, n,
    ];
    let vis = VisBuffer::new(&words, 4, 4, VisLayout::Vrs).unwrap();
    let config = ClassifyConfig::for_plan(&plan, WaveWidth::W8);
    let c = classify(&vis, &plan.table, &[0, 1, 2], &config).unwrap();
    // Samples in row-major order of the pixel that carries them.
    assert_eq!(
        c.output.commands,
        [
            quad_command(0, 0, 0b1111), // (0,0)
            quad_command(1, 0, 0b0011), // (2,0)
            quad_command(0, 1, 0b0101), // (0,2)
            quad_command(0, 1, 0b0010), // (1,2)
            quad_command(1, 1, 0b0111), // (2,2)
            quad_command(0, 1, 0b1000), // (1,3)
        ]
    );
    assert_eq!((c.output.stats.valid, c.output.stats.commands), (13, 6));
    assert_eq!(c.output.waves.len(), 1);

    // The wave's work expansion: 4 + 2 + 2 + 1 + 3 + 1 = 13 entries, one per pixel.
    let list = expand_wave(&c.output.commands, WaveWidth::W8).unwrap();
    assert!(list.needs_broadcast);
    assert_eq!(list.first_entry, [0, 4, 6, 8, 9, 12]);
    assert_eq!(
        list.quad_origin,
        [(0, 0), (2, 0), (0, 2), (0, 2), (2, 2), (0, 2)]
    );
    // lane | dx << 6 | dy << 7
    assert_eq!(
        list.entries,
        [0, 64, 128, 192, 1, 65, 2, 130, 67, 4, 68, 132, 197]
    );
    let mut pixels: Vec<(u32, u32)> = list.pixels().iter().map(|&(_, x, y)| (x, y)).collect();
    pixels.sort();
    let mut valid: Vec<(u32, u32)> = (0..16u32)
        .filter(|&i| words[i as usize] != VIS_NONE)
        .map(|i| (i % 4, i / 4))
        .collect();
    valid.sort();
    assert_eq!(
        pixels, valid,
        "every covered pixel receives exactly one result"
    );
    // Without broadcast, the fast path.
    assert!(
        !expand_wave(&[quad_command(5, 6, 0b0100)], WaveWidth::W8)
            .unwrap()
            .needs_broadcast
    );
}
