//! The classification on many threads (rayon): tiles are independent in every phase (each
//! owns its masks, its counters and its commands, all contiguous in the tile-major
//! layout), so each phase runs its tiles in parallel and equals the sequential result
//! exactly. The vertex cull buffer is shared through relaxed `AtomicU8` stores (setting a
//! byte to 1 commutes); the prefix sums and the wave commands stay sequential (one entry
//! per (tile, pass), negligible next to the pixels).
//!
//! ```
//! # use tiling::{ClassifyConfig, MicroBatchInfo, VisBuffer};
//! # use visbuf::VisLayout;
//! # use wave::WaveWidth;
//! let row = MicroBatchInfo { id_count: 1, primitive_count: 1, vertex_count: 3,
//!     instance_count: 1, ..Default::default() };
//! let words = vec![0u32; 300 * 200]; // every pixel: micro batch 0, instance 0, triangle 0
//! let vis = VisBuffer::new(&words, 300, 200, VisLayout::Standard)?;
//! let config = ClassifyConfig { pass_count: 1, wave_width: WaveWidth::W64, chunk_count: 1, vertex_cull: true };
//! let seq = tiling::classify(&vis, &[row], &[0, 1, 2], &config)?;
//! let par = tiling::parallel::classify(&vis, &[row], &[0, 1, 2], &config)?;
//! assert_eq!(seq, par);
//! # Ok::<(), tiling::Error>(())
//! ```

use alloc::vec;
use alloc::vec::Vec;
use core::sync::atomic::AtomicU8;

use rayon::prelude::*;

use crate::classify::{
    Classification, ClassifyConfig, ClassifyOutput, CounterLut, Frame, MidClassify, PixelStats,
    TileMarks, VisBuffer, check_masks, check_mid, count_tile, cull_buffer, exclusive_scan,
    finalize_tile, output_tile, split_at_starts, tile_counter_ranges, write_waves,
};
use crate::plan::MicroBatchInfo;
use crate::{Error, fused};

/// [`crate::laydown_finalize`] over tiles in parallel.
pub fn laydown_finalize(
    vis: &VisBuffer<'_>,
    table: &[MicroBatchInfo],
    config: &ClassifyConfig,
) -> Result<(Vec<u32>, PixelStats), Error> {
    let f = Frame::new(vis, table, config)?;
    let mut masks = vec![0u32; vis.tile_count() as usize * f.passes];
    let stats = masks
        .par_chunks_mut(f.passes)
        .enumerate()
        .map(|(t, row)| finalize_tile(&f, t, row))
        .reduce(PixelStats::default, PixelStats::merge);
    Ok((masks, stats))
}

/// [`crate::mid_classify`] over tiles in parallel.
pub fn mid_classify(
    vis: &VisBuffer<'_>,
    table: &[MicroBatchInfo],
    indices: &[u32],
    config: &ClassifyConfig,
    masks: &[u32],
) -> Result<MidClassify, Error> {
    let f = Frame::new(vis, table, config)?;
    check_masks(&f, masks)?;
    let mut mid = MidClassify::default();
    mid.counter_count = exclusive_scan(
        masks.iter().map(|m| m.count_ones()),
        &mut mid.counter_offsets,
    );
    let (ranges, _) = tile_counter_ranges(&f, masks, &mid.counter_offsets)?;
    let mut counts = vec![0u32; mid.counter_count as usize];
    let cull = cull_buffer(config.chunk_count);
    let p = f.passes;
    let offsets = &mid.counter_offsets;
    let stats = split_at_starts(&mut counts, &ranges)
        .into_par_iter()
        .enumerate()
        .map_init(
            || (CounterLut::new(), TileMarks::new()),
            |scratch, (t, counts_t)| {
                count_tile(
                    &f,
                    t,
                    table,
                    indices,
                    &masks[t * p..(t + 1) * p],
                    &offsets[t * p..(t + 1) * p],
                    counts_t,
                    &cull,
                    config.chunk_count,
                    scratch,
                )
            },
        )
        .reduce(PixelStats::default, PixelStats::merge);
    mid.command_count = exclusive_scan(counts.iter().copied(), &mut mid.pixel_offsets);
    mid.counts = counts;
    mid.vertex_cull = cull.into_iter().map(AtomicU8::into_inner).collect();
    mid.stats = stats;
    Ok(mid)
}

/// [`crate::classify_output`] over tiles in parallel.
pub fn classify_output(
    vis: &VisBuffer<'_>,
    table: &[MicroBatchInfo],
    config: &ClassifyConfig,
    masks: &[u32],
    mid: &MidClassify,
) -> Result<ClassifyOutput, Error> {
    let f = Frame::new(vis, table, config)?;
    let (ranges, cmd_ranges) = check_mid(&f, masks, mid)?;
    let mut commands = vec![0u16; mid.command_count as usize];
    let mut finals = vec![0u32; mid.counter_count as usize];
    let p = f.passes;
    let cmd_pieces = split_at_starts(&mut commands, &cmd_ranges);
    let final_pieces = split_at_starts(&mut finals, &ranges);
    let stats = cmd_pieces
        .into_par_iter()
        .zip(final_pieces)
        .enumerate()
        .map_init(CounterLut::new, |lut, (t, (commands_t, finals_t))| {
            let (a, b) = ranges[t];
            output_tile(
                &f,
                t,
                &masks[t * p..(t + 1) * p],
                &mid.counter_offsets[t * p..(t + 1) * p],
                &mid.counts[a..b],
                &mid.pixel_offsets[a..b],
                commands_t,
                finals_t,
                lut,
            )
        })
        .reduce(PixelStats::default, PixelStats::merge);
    let mut out = ClassifyOutput {
        commands,
        final_counts: finals,
        stats,
        ..ClassifyOutput::default()
    };
    write_waves(
        &f,
        masks,
        &mid.counter_offsets,
        &mid.pixel_offsets,
        config.wave_width,
        &mut out,
    );
    Ok(out)
}

/// [`crate::classify()`] (all three phases fused per tile) over tiles in parallel.
pub fn classify(
    vis: &VisBuffer<'_>,
    table: &[MicroBatchInfo],
    indices: &[u32],
    config: &ClassifyConfig,
) -> Result<Classification, Error> {
    let f = Frame::new(vis, table, config)?;
    let mut masks = vec![0u32; vis.tile_count() as usize * f.passes];
    let cull = cull_buffer(config.chunk_count);
    let tiles = masks
        .par_chunks_mut(f.passes)
        .enumerate()
        .map_init(fused::Scratch::new, |s, (t, m)| {
            fused::tile(&f, t, table, indices, &cull, config.chunk_count, m, s)
        })
        .collect();
    Ok(fused::assemble_with(
        &f,
        config,
        masks,
        tiles,
        cull,
        |tiles, commands| {
            commands
                .into_par_iter()
                .zip(tiles)
                .for_each(|(out, t)| out.copy_from_slice(&t.commands));
        },
    ))
}

/// [`crate::classify_phases`] with each phase's tiles in parallel.
pub fn classify_phases(
    vis: &VisBuffer<'_>,
    table: &[MicroBatchInfo],
    indices: &[u32],
    config: &ClassifyConfig,
) -> Result<Classification, Error> {
    let (masks, _) = laydown_finalize(vis, table, config)?;
    let mid = mid_classify(vis, table, indices, config, &masks)?;
    let output = classify_output(vis, table, config, &masks, &mid)?;
    Ok(Classification { masks, mid, output })
}
