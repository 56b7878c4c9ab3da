//! Fuzz bodies for the `tiling` crate: arbitrary vis-buffer words, validity masks, tables,
//! index buffers and configurations through the classification (fused and phase by phase,
//! sequential and parallel), the vertex wave commands and the VRS expansion; arbitrary
//! batches through the plan builder. Nothing here may panic except a check.

use tiling::{
    Batch, ClassifyConfig, Geometry, MicroBatchInfo, PassInfo, PlanConfig, VisBuffer, build_plan,
    classify, classify_phases, expand_wave, vertex_wave_commands,
};
use visbuf::VisLayout;
use wave::WaveWidth;

use crate::Input;

/// A row with every field from the input, most of them small so that some rows are
/// usable and most words hit them.
fn row(input: &mut Input<'_>) -> MicroBatchInfo {
    let mut small = |m: u32| {
        let v = input.u32();
        if v & 0x8000_0000 != 0 { v } else { v % m }
    };
    MicroBatchInfo {
        first_id: small(8),
        id_count: small(4),
        pass: small(4),
        batch_group: small(40),
        primitive_bits: small(18),
        primitive_count: small(70_000),
        vertex_count: small(300),
        instance_count: small(5000),
        first_instance: small(100),
        batch: small(16),
        batch_first_instance: small(100),
        first_index: small(64),
        base_vertex: small(64),
        first_chunk: small(64),
        ring_offset: small(64),
        order: small(16),
    }
}

/// Classification of arbitrary words with an arbitrary table: no panic, the fused and
/// phase-by-phase runs agree, every pixel is accounted for once, and every command lies
/// inside its counter and its tile.
pub fn tiling_classify(data: &[u8]) {
    let mut input = Input::new(data);
    let w = 1 + u32::from(input.u8() % 200);
    let h = 1 + u32::from(input.u8() % 150);
    let layout = if input.u8() & 1 == 1 {
        VisLayout::Vrs
    } else {
        VisLayout::Standard
    };
    // Bit 0: the validity mask; bit 1 (from the same byte, so older inputs keep their
    // meaning with vertex culling on): no vertex culling.
    let flags = input.u8();
    let masked = flags & 1 == 1;
    let vertex_cull = flags & 2 == 0;
    let pass_count = 1 + u32::from(input.u8() % 6);
    let wave_width = WaveWidth::ALL[usize::from(input.u8() % 4)];
    let chunk_count = u32::from(input.u16() % 512);
    let rows = usize::from(input.u8() % 12);
    let table: Vec<MicroBatchInfo> = (0..rows).map(|_| row(&mut input)).collect();
    let indices: Vec<u32> = (0..usize::from(input.u8()))
        .map(|_| input.u32() % 320)
        .collect();
    let n = (w * h) as usize;
    // Words: mostly small micro-batch IDs so they meet the table, some anything.
    let words: Vec<u32> = (0..n)
        .map(|_| {
            let v = input.u32();
            match v >> 30 {
                0 => v & 0x000f_ffff,
                1 => visbuf::VIS_NONE,
                _ => v,
            }
        })
        .collect();
    let mask: Vec<u32> = (0..n.div_ceil(32)).map(|_| input.u32()).collect();
    let mut vis = match VisBuffer::new(&words, w, h, layout) {
        Ok(v) => v,
        Err(e) => panic!("valid size rejected: {e}"),
    };
    if masked {
        vis = vis.with_validity(&mask).expect("mask of the right size");
    }
    let config = ClassifyConfig {
        pass_count,
        wave_width,
        chunk_count,
        vertex_cull,
    };
    let fused = classify(&vis, &table, &indices, &config).expect("valid config");
    let phases = classify_phases(&vis, &table, &indices, &config).expect("valid config");
    assert_eq!(
        fused, phases,
        "fused and phase-by-phase classification differ"
    );
    let par = tiling::parallel::classify(&vis, &table, &indices, &config).expect("valid config");
    assert_eq!(fused, par, "parallel classification differs");
    let s = fused.output.stats;
    assert_eq!(s.pixels(), n as u64, "every pixel counted once");
    assert_eq!(s.dropped, 0);
    assert_eq!(
        fused.mid.vertex_cull.len(),
        (chunk_count as usize).next_multiple_of(4)
    );
    if !vertex_cull {
        assert!(fused.mid.vertex_cull.iter().all(|&b| b == 0));
        assert_eq!(fused.mid.stats.bad_indices, 0);
    }
    let covered: u64 = fused
        .output
        .waves
        .iter()
        .map(|w| u64::from(w.command_count))
        .sum();
    assert_eq!(covered, u64::from(s.commands));
    for wc in &fused.output.waves {
        assert!(wc.command_count >= 1 && wc.command_count <= wave_width.lanes());
        assert!(wc.pass() < pass_count && wc.batch_group() < 32);
        let (tx, ty) = wc.tile_xy();
        assert!(tx < vis.tiles_x() && ty < vis.tiles_y());
        assert!((wc.first_command + wc.command_count) as usize <= fused.output.commands.len());
    }
    // The vertex pass over the cull buffer with the table's rows as the order: either
    // an error (the rows do not fit the buffer) or commands inside it.
    let order: Vec<u32> = (0..table.len() as u32)
        .filter(|&id| table[id as usize].first_id == id)
        .collect();
    let passes = [PassInfo {
        chunk_count,
        ..PassInfo::default()
    }];
    if let Ok(v) =
        vertex_wave_commands(&fused.mid.vertex_cull, chunk_count, &table, &order, &passes)
    {
        let visible = fused.mid.vertex_cull[..chunk_count as usize]
            .iter()
            .filter(|&&b| b != 0)
            .count();
        assert_eq!(v.commands.len(), visible);
    }
    // The VRS expansion of every wave's commands.
    if layout == VisLayout::Vrs {
        for wc in fused.output.waves.iter().take(64) {
            let cmds = &fused.output.commands
                [wc.first_command as usize..(wc.first_command + wc.command_count) as usize];
            let list = expand_wave(cmds, wave_width).expect("a wave's commands fit its lanes");
            let bits: u32 = cmds.iter().map(|&c| u32::from(c >> 12).count_ones()).sum();
            assert_eq!(list.entries.len() as u32, bits);
        }
    }
}

/// The plan builder on arbitrary batches and limits: an error or a plan that places every
/// instance once within its limits.
pub fn tiling_plan(data: &[u8]) {
    let mut input = Input::new(data);
    let config = PlanConfig {
        layout: if input.u8() & 1 == 1 {
            VisLayout::Vrs
        } else {
            VisLayout::Standard
        },
        ring_bytes: u64::from(input.u32()),
        vertex_bytes: u32::from(input.u8()),
        max_micro_batch_vertices: input.u32() % (1 << 20),
        max_micro_batch_primitives: input.u32() % (1 << 20),
        max_micro_batch_instances: input.u32() % 70_000,
        max_passes: u32::from(input.u16() % 300),
        max_batch_groups: u32::from(input.u8() % 40),
    };
    let count = usize::from(input.u8() % 24);
    let specs: Vec<(u32, u64, Geometry, usize)> = (0..count)
        .map(|_| {
            let shader = u32::from(input.u8() % 4);
            let data = u64::from(input.u8() % 8);
            let geometry = Geometry {
                vertex_count: input.u32() % 100_000,
                primitive_count: input.u32() % 70_000,
                first_index: input.u32(),
                base_vertex: input.u32(),
            };
            (shader, data, geometry, usize::from(input.u16() % 2000))
        })
        .collect();
    let positions: Vec<Vec<[f32; 3]>> = specs
        .iter()
        .map(|s| {
            (0..s.3)
                .map(|_| [input.f32(), input.f32(), input.f32()])
                .collect()
        })
        .collect();
    let batches: Vec<Batch<'_>> = specs
        .iter()
        .zip(&positions)
        .map(|(s, p)| Batch {
            shader: s.0,
            batch_data: s.1,
            geometry: s.2,
            instances: p,
        })
        .collect();
    let Ok(plan) = build_plan(&batches, &config) else {
        return;
    };
    let placed: usize = plan
        .micro_batches
        .iter()
        .map(|m| m.instance_count as usize)
        .sum();
    assert_eq!(placed, positions.iter().map(Vec::len).sum::<usize>());
    assert!(plan.passes.len() as u32 <= config.max_passes);
    for mb in &plan.micro_batches {
        assert!(
            u64::from(mb.instance_count) * u64::from(mb.vertex_count)
                <= u64::from(config.micro_batch_vertex_limit())
        );
        assert!(
            u64::from(mb.instance_count) * u64::from(mb.primitive_count)
                <= u64::from(config.max_micro_batch_primitives)
        );
        assert_eq!(plan.table[mb.first_id as usize], *mb);
    }
}
