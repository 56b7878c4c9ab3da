//! Multi-threaded versions of the offline bakers (rayon, `parallel` feature). Each returns
//! exactly what its sequential twin returns, bit for bit (tested): the work is split into
//! independent rows or strips and nothing depends on scheduling.
//!
//! Progress is reported from the calling thread between batches of rows, so the callback
//! need not be `Sync`.

use alloc::vec::Vec;
use core::ops::ControlFlow;

use rayon::prelude::*;

use crate::Error;
use crate::edt::{
    DistanceField, INF, RowScratch, column_down, column_up, distance_row, signed_edt_with,
};
use crate::progress::Progress;

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
    let w = width as usize;
    signed_edt_with(
        mask,
        width,
        height,
        progress,
        column_pass_par,
        |y0, chunk, g| {
            chunk.par_chunks_mut(w).enumerate().for_each_init(
                || RowScratch::new(w),
                |s, (i, out)| distance_row(s, mask, g, y0 + i, out),
            );
        },
    )
}

/// [`crate::flowbake::bake_flow`] with the smoothing iterations on all rayon threads (the
/// seeds and the flood are sequential by nature: a priority order).
pub fn bake_flow(
    input: &crate::flowbake::FlowBakeInput<'_>,
    s: &crate::flowbake::FlowBakeSettings,
    progress: &mut impl FnMut(Progress) -> ControlFlow<()>,
) -> Result<crate::flowbake::FlowField, Error> {
    crate::flowbake::bake_flow_with(input, s, progress, |w, next, smooth_row| {
        next.par_chunks_mut(w)
            .enumerate()
            .for_each(|(y, row)| smooth_row(y, row));
    })
}
