//! Vertex wave commands from the vertex cull buffer (seed 000, bonus slides: "how we
//! generate the vertex wave commands").
//!
//! 1. **Uber chunks.** The cull buffer (one byte per 64-vertex chunk) is read 64 chunks at
//!    a time: each uber chunk gets a 64-bit mask of its visible chunks and their count
//!    ([`UberChunk`]).
//! 2. **Histogram pyramid** ([`HistogramPyramid`]) over the uber counts, fan-out
//!    [`PYRAMID_FANOUT`]: level 0 holds the counts, each level above the sums of
//!    [`PYRAMID_FANOUT`] entries below, the top one entry (the visible-chunk total).
//!    Descending it maps a linear work index to (uber chunk, child rank), and the mask
//!    maps the rank to the global chunk ([`HistogramPyramid::locate`]); ascending it
//!    counts the visible chunks before any chunk ([`HistogramPyramid::rank_of_chunk`]).
//! 3. **Micro batches.** For each entry of the micro-batch order buffer the pass finds its
//!    visible chunks' range in the command stream (the rank of its first chunk) and writes
//!    the *delta* of its micro-batch ID against the previous entry's at that position
//!    (added atomically: micro batches with no visible chunk share the position of the
//!    next, and their deltas sum). An inclusive prefix sum turns the deltas into the
//!    micro-batch ID of every command.
//! 4. **Commands.** One [`VertexWaveCommand`] per visible chunk, in chunk order (= the
//!    order buffer's order, pass by pass), and one [`PassDispatch`] per pass.
//!
//! Requirements on the inputs, which [`build_plan`](crate::build_plan) meets and
//! [`vertex_wave_commands`] checks: every order entry names a row whose chunks lie inside
//! the cull buffer, and each entry's chunks start at or after the previous entry's end.

use alloc::vec;
use alloc::vec::Vec;

use crate::Error;
use crate::layout::PassDispatch;
use crate::plan::{MicroBatchInfo, PassInfo, VERTEX_CHUNK_SIZE};

/// Chunks per uber chunk (the bits of its mask).
pub const UBER_CHUNK_CHUNKS: u32 = 64;
/// Children per node of the histogram pyramid.
pub const PYRAMID_FANOUT: u32 = 4;
/// Deltas per workgroup of the GPU's prefix sum over the micro-batch-ID deltas (WGSL
/// `TILING_DELTA_BLOCK`): the size of the block sums buffer is `ceil(chunk_count /
/// DELTA_BLOCK)` words ([`delta_block_count`]).
pub const DELTA_BLOCK: u32 = 1024;

/// Words of the GPU's block sums buffer (`delta_blocks` of
/// [`wgsl::VERTEX_WAVES`](crate::wgsl::VERTEX_WAVES)) for a cull buffer of `chunk_count`
/// entries: one per [`DELTA_BLOCK`] chunks, at least one.
#[must_use]
pub const fn delta_block_count(chunk_count: u32) -> u32 {
    let n = chunk_count.div_ceil(DELTA_BLOCK);
    if n == 0 { 1 } else { n }
}

/// 64 chunks of the cull buffer (WGSL `TilingUberChunk`), 16 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, bytemuck::Pod, bytemuck::Zeroable)]
pub struct UberChunk {
    /// Chunks `64 u + 0..32`: bit `j` set when chunk `64 u + j` is visible.
    pub mask_lo: u32,
    /// Chunks `64 u + 32..64`.
    pub mask_hi: u32,
    /// Visible chunks, `popcount(mask)`.
    pub count: u32,
    /// Padding (zero).
    pub pad: u32,
}

const _: () = assert!(size_of::<UberChunk>() == 16);

impl UberChunk {
    /// The 64-bit mask.
    #[must_use]
    pub const fn mask(&self) -> u64 {
        self.mask_lo as u64 | ((self.mask_hi as u64) << 32)
    }
}

/// One wave of vertex transform (WGSL `TilingVertexWaveCommand`), 8 bytes: 64 vertices
/// `64 * chunk ..` (the last chunk of a micro batch may be partial) of a micro batch,
/// numbered instance-major (`instance * vertex_count + vertex`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, bytemuck::Pod, bytemuck::Zeroable)]
pub struct VertexWaveCommand {
    /// The micro batch's (first) micro-batch ID: its row of the table.
    pub micro_batch: u32,
    /// The chunk within the micro batch.
    pub chunk: u32,
}

const _: () = assert!(size_of::<VertexWaveCommand>() == 8);

/// Levels of a pyramid over `uber_count` entries: `(offset, length)` of each level in the
/// flat buffer, bottom (the counts) first, top (length 1) last. Zero entries still make
/// one level of length 1 (holding 0).
#[must_use]
pub fn pyramid_levels(uber_count: u32) -> Vec<(u32, u32)> {
    let mut levels = Vec::new();
    let mut len = uber_count.max(1);
    let mut offset = 0;
    loop {
        levels.push((offset, len));
        if len == 1 {
            return levels;
        }
        offset += len;
        len = len.div_ceil(PYRAMID_FANOUT);
    }
}

/// The histogram pyramid over uber-chunk counts, levels flat in one buffer
/// ([`pyramid_levels`]).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct HistogramPyramid {
    /// `(offset, length)` per level, bottom first.
    pub levels: Vec<(u32, u32)>,
    /// All levels, bottom first.
    pub data: Vec<u32>,
}

impl HistogramPyramid {
    /// Builds the pyramid over `counts` (one per uber chunk).
    #[must_use]
    pub fn build(counts: &[u32]) -> Self {
        let levels = pyramid_levels(counts.len() as u32);
        let total_len = levels.last().map_or(1, |&(o, l)| (o + l) as usize);
        let mut data = vec![0u32; total_len];
        data[..counts.len()].copy_from_slice(counts);
        for k in 1..levels.len() {
            let (below, blen) = levels[k - 1];
            let (here, len) = levels[k];
            for i in 0..len {
                let mut s = 0u32;
                for c in 0..PYRAMID_FANOUT {
                    let child = i * PYRAMID_FANOUT + c;
                    if child < blen {
                        s = s.wrapping_add(data[(below + child) as usize]);
                    }
                }
                data[(here + i) as usize] = s;
            }
        }
        Self { levels, data }
    }

    /// The sum of all counts (the top entry).
    #[must_use]
    pub fn total(&self) -> u32 {
        self.levels
            .last()
            .map_or(0, |&(o, _)| self.data[o as usize])
    }

    /// The uber chunk and child rank of linear work index `i`, or `None` past the total.
    #[must_use]
    pub fn locate(&self, mut i: u32) -> Option<(u32, u32)> {
        if i >= self.total() {
            return None;
        }
        let mut node = 0u32;
        for k in (0..self.levels.len() - 1).rev() {
            let (off, len) = self.levels[k];
            let mut next = node * PYRAMID_FANOUT;
            for c in 0..PYRAMID_FANOUT {
                let child = node * PYRAMID_FANOUT + c;
                if child >= len {
                    break;
                }
                next = child;
                let n = self.data[(off + child) as usize];
                if i < n {
                    break;
                }
                i -= n;
            }
            node = next;
        }
        Some((node, i))
    }

    /// The sum of the counts of entries `0..u` (`u` at most the level-0 length).
    #[must_use]
    pub fn prefix(&self, u: u32) -> u32 {
        let mut sum = 0u32;
        let mut idx = u;
        for &(off, len) in &self.levels {
            // The siblings left of `idx` under its parent (all of them past the end).
            for j in (idx / PYRAMID_FANOUT * PYRAMID_FANOUT)..idx.min(len) {
                sum = sum.wrapping_add(self.data[(off + j) as usize]);
            }
            idx /= PYRAMID_FANOUT;
        }
        sum
    }

    /// Visible chunks before global chunk `chunk`, given the uber chunks' masks.
    #[must_use]
    pub fn rank_of_chunk(&self, ubers: &[UberChunk], chunk: u32) -> u32 {
        let u = chunk / UBER_CHUNK_CHUNKS;
        let Some(uc) = ubers.get(u as usize) else {
            return self.total();
        };
        let below = chunk % UBER_CHUNK_CHUNKS;
        let mask = uc.mask() & ((1u64 << below) - 1);
        self.prefix(u).wrapping_add(mask.count_ones())
    }
}

/// The `n`-th (from 0) set bit of `mask`; 64 if there are not that many.
#[must_use]
pub fn nth_set_bit(mask: u64, n: u32) -> u32 {
    let mut m = mask;
    for _ in 0..n {
        if m == 0 {
            return 64;
        }
        m &= m - 1;
    }
    if m == 0 { 64 } else { m.trailing_zeros() }
}

/// The uber chunks of a cull buffer of `chunk_count` entries (bytes, nonzero = visible).
#[must_use]
pub fn uber_chunks(cull: &[u8], chunk_count: u32) -> Vec<UberChunk> {
    let n = (chunk_count as usize).min(cull.len());
    cull[..n]
        .chunks(UBER_CHUNK_CHUNKS as usize)
        .map(|c| {
            let mut mask = 0u64;
            for (j, &b) in c.iter().enumerate() {
                mask |= u64::from(b != 0) << j;
            }
            UberChunk {
                mask_lo: mask as u32,
                mask_hi: (mask >> 32) as u32,
                count: mask.count_ones(),
                pad: 0,
            }
        })
        .collect()
}

/// The vertex pass's outputs.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct VertexWaves {
    /// One per 64 chunks.
    pub ubers: Vec<UberChunk>,
    /// The pyramid over their counts.
    pub pyramid: HistogramPyramid,
    /// Per visible chunk: the micro-batch-ID delta written at the first command of each
    /// micro batch (0 elsewhere), before the prefix sum. Wrapping `u32` arithmetic.
    pub deltas: Vec<u32>,
    /// Per order entry: the vertex waves (visible chunks) of that micro batch.
    pub micro_batch_waves: Vec<u32>,
    /// One per visible chunk, in chunk order.
    pub commands: Vec<VertexWaveCommand>,
    /// Per pass: the vertex-transform dispatch (`items` = vertices in its visible chunks).
    pub passes: Vec<PassDispatch>,
}

impl VertexWaves {
    /// Vertices in visible chunks (what is transformed after chunk culling).
    #[must_use]
    pub fn visible_vertices(&self) -> u64 {
        self.passes.iter().map(|p| u64::from(p.items)).sum()
    }
}

/// Vertices of chunk `chunk` of micro batch `row` (64, or fewer for its last chunk).
#[must_use]
pub fn chunk_vertices(row: &MicroBatchInfo, chunk: u32) -> u32 {
    let start = u64::from(chunk) * u64::from(VERTEX_CHUNK_SIZE);
    row.total_vertices()
        .saturating_sub(start)
        .min(VERTEX_CHUNK_SIZE.into()) as u32
}

fn mismatch(what: &'static str) -> Error {
    Error::MismatchedPhase { what }
}

/// Builds the vertex wave commands from the vertex cull buffer (`chunk_count` entries of
/// `cull`), the table, the micro-batch order buffer and the passes.
///
/// GPU twin: [`wgsl::VERTEX_WAVES`](crate::wgsl::VERTEX_WAVES).
pub fn vertex_wave_commands(
    cull: &[u8],
    chunk_count: u32,
    table: &[MicroBatchInfo],
    order: &[u32],
    passes: &[PassInfo],
) -> Result<VertexWaves, Error> {
    if (cull.len() as u64) < u64::from(chunk_count) {
        return Err(Error::BufferSize {
            what: "vertex cull buffer",
            expected: chunk_count.into(),
            got: cull.len() as u64,
        });
    }
    // Check the order buffer: rows exist, chunks inside the buffer, in increasing order.
    let mut end = 0u64;
    for &id in order {
        let row = table
            .get(id as usize)
            .ok_or(mismatch("micro-batch order buffer"))?;
        let first = u64::from(row.first_chunk);
        let last = first + u64::from(row.chunk_count());
        if first < end || last > u64::from(chunk_count) {
            return Err(mismatch("micro-batch order buffer"));
        }
        end = last;
    }
    for p in passes {
        if u64::from(p.first_chunk) + u64::from(p.chunk_count) > u64::from(chunk_count) {
            return Err(mismatch("pass chunks"));
        }
    }

    let ubers = uber_chunks(cull, chunk_count);
    let counts: Vec<u32> = ubers.iter().map(|u| u.count).collect();
    let pyramid = HistogramPyramid::build(&counts);
    let total = pyramid.total();

    // Deltas at each micro batch's first command.
    let mut deltas = vec![0u32; total as usize];
    let mut micro_batch_waves = Vec::with_capacity(order.len());
    let mut prev = 0u32;
    for &id in order {
        let row = &table[id as usize];
        let start = pyramid.rank_of_chunk(&ubers, row.first_chunk);
        let stop = pyramid.rank_of_chunk(&ubers, row.first_chunk + row.chunk_count());
        micro_batch_waves.push(stop - start);
        if let Some(d) = deltas.get_mut(start as usize) {
            *d = d.wrapping_add(id.wrapping_sub(prev));
        }
        prev = id;
    }

    // Prefix sum → micro batch per command; the pyramid → its chunk.
    let mut commands = Vec::with_capacity(total as usize);
    let mut id = 0u32;
    for (i, &d) in deltas.iter().enumerate() {
        id = id.wrapping_add(d);
        let chunk = pyramid.locate(i as u32).map_or(0, |(u, r)| {
            u * UBER_CHUNK_CHUNKS + nth_set_bit(ubers[u as usize].mask(), r)
        });
        let first = table.get(id as usize).map_or(0, |r| r.first_chunk);
        commands.push(VertexWaveCommand {
            micro_batch: id,
            chunk: chunk.wrapping_sub(first),
        });
    }

    // Per pass: its commands are those of its chunks.
    let passes = passes
        .iter()
        .map(|p| {
            let first = pyramid.rank_of_chunk(&ubers, p.first_chunk);
            let stop = pyramid.rank_of_chunk(&ubers, p.first_chunk + p.chunk_count);
            let items = commands[first as usize..stop as usize]
                .iter()
                .map(|c| {
                    table
                        .get(c.micro_batch as usize)
                        .map_or(0, |r| chunk_vertices(r, c.chunk))
                })
                .fold(0u32, u32::wrapping_add);
            PassDispatch::new(first, stop - first, items)
        })
        .collect();

    Ok(VertexWaves {
        ubers,
        pyramid,
        deltas,
        micro_batch_waves,
        commands,
        passes,
    })
}
