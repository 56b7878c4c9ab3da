//! Multi-threaded versions of the offline bakers (rayon, `parallel` feature). Each returns
//! exactly what its sequential twin returns, bit for bit (tested): the work is split into
//! independent rows or strips and nothing depends on scheduling.
//!
//! Progress is reported from the calling thread between batches of rows, so the callback
//! need not be `Sync`.

use alloc::vec;
use alloc::vec::Vec;
use core::ops::ControlFlow;

use rayon::prelude::*;

use crate::Error;
use crate::edt::{
    DistanceField, INF, ROWS_PER_REPORT, RowScratch, check_dims, column_down, column_up,
    finish_row, row_pass,
};
use crate::progress::{Progress, Stage, report};

/// Columns per strip of the parallel column pass.
const STRIP: usize = 256;

/// The column pass split into vertical strips, one task each.
fn column_pass_par(mask: &[u8], width: usize, g: &mut [u16]) {
    let h = mask.len() / width;
    // Each strip owns its piece of every row.
    let strips = width.div_ceil(STRIP);
    let mut pieces: Vec<Vec<&mut [u16]>> = (0..strips).map(|_| Vec::with_capacity(h)).collect();
    for row in g.chunks_mut(width) {
        let mut rest = row;
        for strip in pieces.iter_mut() {
            let n = rest.len().min(STRIP);
            let (a, b) = rest.split_at_mut(n);
            strip.push(a);
            rest = b;
        }
    }
    pieces
        .into_par_iter()
        .enumerate()
        .for_each(|(s, mut rows)| {
            let x0 = s * STRIP;
            let n = rows[0].len();
            let cls = |y: usize| &mask[y * width + x0..y * width + x0 + n];
            rows[0].fill(INF);
            for y in 1..h {
                let (done, rest) = rows.split_at_mut(y);
                column_down(cls(y - 1), done[y - 1], cls(y), rest[0]);
            }
            for y in (0..h.saturating_sub(1)).rev() {
                let (head, below) = rows.split_at_mut(y + 1);
                column_up(cls(y + 1), below[0], cls(y), head[y]);
            }
        });
}

/// [`crate::edt::signed_edt`] on all rayon threads: the column pass in strips of 256
/// columns, the row pass in rows.
pub fn signed_edt(
    mask: &[u8],
    width: u32,
    height: u32,
    progress: &mut impl FnMut(Progress) -> ControlFlow<()>,
) -> Result<DistanceField, Error> {
    check_dims(width, height, mask.len())?;
    let (w, h) = (width as usize, height as usize);
    let mut g = vec![0u16; w * h];
    column_pass_par(mask, w, &mut g);
    report(progress, Stage::DistanceColumns, 1, 1)?;
    let mut values = vec![0.0f32; w * h];
    let batch = ROWS_PER_REPORT * w;
    for (b, chunk) in values.chunks_mut(batch).enumerate() {
        let y0 = b * ROWS_PER_REPORT;
        chunk.par_chunks_mut(w).enumerate().for_each_init(
            || RowScratch::new(w),
            |s, (i, out)| {
                let r = (y0 + i) * w..(y0 + i + 1) * w;
                row_pass(s, &mask[r.clone()], &g[r], |x, d| out[x] = d as f32);
                finish_row(out);
            },
        );
        let done = (y0 + chunk.len() / w) as u64;
        report(progress, Stage::DistanceRows, done, h as u64)?;
    }
    DistanceField::from_values(width, height, values)
}

/// [`crate::flowbake::bake_flow`] with the smoothing iterations on all rayon threads (the
/// seeds and the flood are sequential by nature: a priority order).
pub fn bake_flow(
    input: &crate::flowbake::FlowBakeInput<'_>,
    s: &crate::flowbake::FlowBakeSettings,
    progress: &mut impl FnMut(Progress) -> ControlFlow<()>,
) -> Result<crate::flowbake::FlowField, Error> {
    use crate::flowbake::{Prepared, field, prepare, smooth_row};
    let Prepared {
        g,
        mut flow,
        fixed,
        reached,
    } = prepare(input, s, progress)?;
    let mut next = flow.clone();
    for it in 0..s.smoothing_iterations {
        next.par_chunks_mut(g.w)
            .enumerate()
            .for_each(|(y, row)| smooth_row(&g, &flow, &fixed, &reached, y, row));
        core::mem::swap(&mut flow, &mut next);
        report(
            progress,
            Stage::FlowSmooth,
            u64::from(it + 1),
            u64::from(s.smoothing_iterations),
        )?;
    }
    Ok(field(input, g.w, g.h, flow))
}
