//! Mid classify's vertex culling: the triangles of each tile's valid pixels marked in the
//! vertex cull buffer (one byte per 64-vertex chunk), shared by the phase-shaped
//! [`mid_classify`](crate::mid_classify) and the fused [`classify`](crate::classify()).

use alloc::vec;
use alloc::vec::Vec;
use core::sync::atomic::{AtomicU8, Ordering};

use visbuf::VIS_NONE;

use super::frame::Frame;
use super::types::PixelStats;
use crate::decode::Decoded;
use crate::layout::TILE_SIZE;
use crate::plan::{MicroBatchInfo, VERTEX_CHUNK_SIZE};

/// The vertex cull buffer while the tiles mark it, with what marking reads: the table and
/// the shared index buffer its `first_index` points into. The bytes are relaxed atomics
/// (setting a byte to 1 commutes), so tiles on many threads share one buffer.
pub(crate) struct CullBuffer<'a> {
    table: &'a [MicroBatchInfo],
    indices: &'a [u32],
    /// Entries that name a chunk; `cells` has `chunk_count` rounded up to 4.
    chunk_count: u32,
    cells: Vec<AtomicU8>,
}

impl<'a> CullBuffer<'a> {
    /// A cleared buffer of `chunk_count` entries, padded with zeros to a multiple of 4
    /// bytes (it casts to the GPU's `array<u32>`).
    pub fn new(table: &'a [MicroBatchInfo], indices: &'a [u32], chunk_count: u32) -> Self {
        Self {
            table,
            indices,
            chunk_count,
            cells: (0..chunk_count.next_multiple_of(4))
                .map(|_| AtomicU8::new(0))
                .collect(),
        }
    }

    /// The bytes, 1 where a chunk was marked.
    pub fn into_bytes(self) -> Vec<u8> {
        self.cells.into_iter().map(AtomicU8::into_inner).collect()
    }
}

/// The triangles of one tile's valid pixels, gathered during the pixel scan and marked in
/// the cull buffer after it. A direct-mapped cache of words (per thread, kept from tile to
/// tile) folds most repeats into one request; the marking then runs in two loops whose iterations are independent (load
/// each triangle's indices into chunk numbers, then set the chunks' bytes), so their cache
/// misses overlap. Triangles with bad indices are rare: their pixels are counted by a
/// second look at the tile only when there are any.
pub(crate) struct TileMarks {
    slots: Vec<u32>,
    /// Room for one request per pixel of a tile; the first `n` are the tile's.
    requests: Vec<MarkRequest>,
    n: usize,
    chunks: Vec<u32>,
    bad_words: Vec<u32>,
}

#[derive(Clone, Copy, Default)]
struct MarkRequest {
    word: u32,
    mb: u32,
    instance: u32,
    prim: u32,
}

impl TileMarks {
    const BITS: u32 = 14;

    pub fn new() -> Self {
        Self {
            slots: vec![VIS_NONE; 1 << Self::BITS],
            requests: vec![MarkRequest::default(); (TILE_SIZE * TILE_SIZE) as usize + 1],
            n: 0,
            chunks: Vec::new(),
            bad_words: Vec::new(),
        }
    }

    /// Starts a tile. The cache of words persists from tile to tile (a cached word's
    /// triangle is marked, and words with bad indices are taken out of it).
    pub fn begin(&mut self) {
        self.n = 0;
    }

    #[inline(always)]
    fn hash(word: u32) -> usize {
        (word.wrapping_mul(0x9e37_79b1) >> (32 - Self::BITS)) as usize
    }

    /// Records pixel word `word` if `valid` (without a branch: the request is always
    /// written, and kept only when it is valid and new).
    #[inline(always)]
    pub fn add(&mut self, word: u32, d: &Decoded, valid: bool) {
        let slot = &mut self.slots[Self::hash(word)];
        let new = valid & (*slot != word);
        *slot = if valid { word } else { *slot };
        // At most one request per pixel of the tile, so `n` stays within the buffer.
        let at = self.n.min(self.requests.len() - 1);
        self.requests[at] = MarkRequest {
            word,
            mb: d.mb,
            instance: d.instance,
            prim: d.prim,
        };
        self.n += usize::from(new);
    }

    /// Marks every recorded triangle of tile `t`; returns the valid pixels whose triangle
    /// has bad indices.
    pub fn finish(&mut self, f: &Frame<'_>, t: usize, cull: &CullBuffer<'_>) -> u32 {
        self.chunks.clear();
        self.bad_words.clear();
        for r in &self.requests[..self.n] {
            if !triangle_chunks(
                &cull.table[r.mb as usize],
                r.instance,
                r.prim,
                cull.indices,
                cull.chunk_count,
                &mut self.chunks,
            ) {
                self.bad_words.push(r.word);
            }
        }
        let mut prev = u32::MAX;
        for &c in &self.chunks {
            if c != prev {
                let cell = &cull.cells[c as usize];
                if cell.load(Ordering::Relaxed) == 0 {
                    cell.store(1, Ordering::Relaxed);
                }
                prev = c;
            }
        }
        if self.bad_words.is_empty() {
            return 0;
        }
        self.bad_words.sort_unstable();
        self.bad_words.dedup();
        // Bad triangles are requested again in every tile that has them, so each tile
        // counts its own bad pixels.
        for &w in &self.bad_words {
            let slot = &mut self.slots[Self::hash(w)];
            if *slot == w {
                *slot = VIS_NONE;
            }
        }
        let mut bad = 0;
        let mut ignore = PixelStats::default();
        f.for_each_pixel(t, &mut ignore, |x, y, word, valid, _| {
            if valid && self.bad_words.binary_search(&word).is_ok() && f.first_of_run(x, y, word) {
                bad += 1;
            }
        });
        bad
    }
}

/// Appends the cull-buffer chunks of the triangle of a valid pixel to `out` (those that
/// exist); false if an index was bad (past the index buffer, at or past the vertex count,
/// or a chunk past the buffer).
#[inline(always)]
fn triangle_chunks(
    row: &MicroBatchInfo,
    instance: u32,
    prim: u32,
    indices: &[u32],
    chunk_count: u32,
    out: &mut Vec<u32>,
) -> bool {
    let first = u64::from(row.first_index) + 3 * u64::from(prim);
    let Some(tri) = indices.get(first as usize..first as usize + 3) else {
        return false;
    };
    let base = u64::from(instance) * u64::from(row.vertex_count);
    let mut ok = true;
    for &v in tri {
        if v >= row.vertex_count {
            ok = false;
            continue;
        }
        let chunk =
            u64::from(row.first_chunk) + (base + u64::from(v)) / u64::from(VERTEX_CHUNK_SIZE);
        if chunk >= u64::from(chunk_count) {
            ok = false;
            continue;
        }
        out.push(chunk as u32);
    }
    ok
}
