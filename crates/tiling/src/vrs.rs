//! Software variable-rate shading (seed 000, "VRS"): quad commands and the wave's work
//! expansion.
//!
//! With [`VisLayout::Vrs`](visbuf::VisLayout::Vrs) the top two bits of each vis word hold a
//! DirectX tier-1 shading rate ([`visbuf::ShadingRate`]). The classification then emits one
//! **quad command** per shading sample instead of one pixel command per pixel:
//!
//! | bits | 15..12 | 11..6 | 5..0 |
//! | --- | --- | --- | --- |
//! | field | pixel mask: bit `2 * dy + dx` set for each pixel of the quad that receives the result | quad y within the tile (0..64) | quad x within the tile (0..64) |
//!
//! **Which pixels share a sample.** A pixel's rate picks the block of its 2x2 quad that one
//! sample covers: the whole quad for 2x2, the pixel's row pair for 2x1, its column pair
//! for 1x2, the pixel alone for 1x1 (blocks are aligned to even coordinates, so they never
//! cross a quad, a tile or, clipped, the image edge). The valid pixels of a block whose
//! 32-bit words are equal (same micro batch, instance, primitive and rate: the hardware
//! also never merges two triangles into one coarse pixel) share one sample; it is shaded
//! at the first of them in row-major order ([`sample_pixel`]) and carried by that pixel's
//! command.
//!
//! **Work expansion** ([`expand_wave`]): the CPU twin of the talk's LDS expansion. Each
//! lane of a shading wave shades one sample; before the stores the wave builds a list of
//! `(lane, dx, dy)` bytes, one per receiving pixel (the talk's `sPixelCommands[256]`),
//! each lane's run starting at the prefix sum of the popcounts of the lanes below it, and
//! the per-lane quad origin (`sIntermediatePixelX/Y`). The output loop then walks the
//! list with all lanes, each entry reading its lane's stashed result.

use alloc::vec::Vec;

use visbuf::VisId;
use wave::{PerLane, Wave, WaveWidth};

use crate::Error;
use crate::layout::{QUAD_COORD_MASK, QUAD_PIXELS_SHIFT, QUAD_Y_SHIFT, VisBuffer};

/// Bit of a broadcast entry holding the x offset within the quad (the lane is in the bits
/// below).
pub const BROADCAST_DX_BIT: u32 = 6;
/// Bit of a broadcast entry holding the y offset within the quad.
pub const BROADCAST_DY_BIT: u32 = 7;
/// Mask of the lane in a broadcast entry.
pub const BROADCAST_LANE_MASK: u32 = 0x3f;

/// The quad command of quad `(qx, qy)` within its tile (each `0..64`, masked) with pixel
/// mask `mask` (low 4 bits).
#[must_use]
#[inline]
pub const fn quad_command(qx: u32, qy: u32, mask: u32) -> u16 {
    ((qx & QUAD_COORD_MASK)
        | ((qy & QUAD_COORD_MASK) << QUAD_Y_SHIFT)
        | ((mask & 0xf) << QUAD_PIXELS_SHIFT)) as u16
}

/// `(quad x, quad y, pixel mask)` of a quad command.
#[must_use]
#[inline]
pub const fn unpack_quad_command(cmd: u16) -> (u32, u32, u32) {
    let c = cmd as u32;
    (
        c & QUAD_COORD_MASK,
        (c >> QUAD_Y_SHIFT) & QUAD_COORD_MASK,
        c >> QUAD_PIXELS_SHIFT,
    )
}

/// The pixel `(x, y)` within the tile where a quad command's sample is shaded: its quad's
/// top-left plus the offset of the mask's lowest set bit (the top-left if the mask is
/// empty).
#[must_use]
#[inline]
pub const fn sample_pixel(cmd: u16) -> (u32, u32) {
    let (qx, qy, mask) = unpack_quad_command(cmd);
    let b = if mask == 0 { 0 } else { mask.trailing_zeros() };
    (2 * qx + (b & 1), 2 * qy + (b >> 1))
}

/// The pixel mask of the sample pixel `(x, y)` (image coordinates, holding the valid word
/// `word`) carries, or `None` when an earlier pixel of its block carries it.
#[inline(always)]
pub(crate) fn sample_mask(vis: &VisBuffer<'_>, x: u32, y: u32, word: u32) -> Option<u32> {
    let rate = VisId(word).shading_rate(vis.layout());
    let (rw, rh) = (rate.width(), rate.height());
    if rw == 1 && rh == 1 {
        return Some(1 << (((y & 1) << 1) | (x & 1)));
    }
    let (bx, by) = (x & !(rw - 1), y & !(rh - 1));
    let (w, h) = (vis.width(), vis.height());
    let words = vis.words();
    let mut mask = 0;
    for py in by..(by + rh).min(h) {
        for px in bx..(bx + rw).min(w) {
            let i = (py * w + px) as usize;
            if words[i] != word || !vis.mask_bit(i) {
                continue;
            }
            if py < y || (py == y && px < x) {
                return None;
            }
            mask |= 1 << (((py & 1) << 1) | (px & 1));
        }
    }
    Some(mask)
}

/// A wave's quad commands expanded into its per-pixel broadcast list.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct BroadcastList {
    /// One byte per receiving pixel, lane order then pixel-bit order: lane in bits 5..0,
    /// `dx` in bit [`BROADCAST_DX_BIT`], `dy` in bit [`BROADCAST_DY_BIT`] (the talk's
    /// `sPixelCommands`, at most 64 lanes x 4 = 256 entries).
    pub entries: Vec<u8>,
    /// Per lane: the index of its first entry (the exclusive prefix sum of the masks'
    /// popcounts over the lanes below it).
    pub first_entry: Vec<u32>,
    /// Per lane: the top-left pixel `(x, y)` of its quad within the tile
    /// (`sIntermediatePixelX/Y`).
    pub quad_origin: Vec<(u8, u8)>,
    /// Whether any lane broadcasts (a mask with more than one pixel): without, the shader
    /// takes the plain output path and needs no list.
    pub needs_broadcast: bool,
}

impl BroadcastList {
    /// Each entry as `(lane, x, y)`: the lane whose result is stored and the pixel within
    /// the tile it is stored to.
    #[must_use]
    pub fn pixels(&self) -> Vec<(u32, u32, u32)> {
        self.entries
            .iter()
            .map(|&e| {
                let e = u32::from(e);
                let lane = e & BROADCAST_LANE_MASK;
                let (ox, oy) = self.quad_origin[lane as usize];
                (
                    lane,
                    u32::from(ox) + ((e >> BROADCAST_DX_BIT) & 1),
                    u32::from(oy) + ((e >> BROADCAST_DY_BIT) & 1),
                )
            })
            .collect()
    }
}

/// Expands one wave's quad commands (lane `i` holds `commands[i]`; at most `width` of
/// them) into the broadcast list. Errors when there are more commands than lanes.
///
/// ```
/// use tiling::vrs::{expand_wave, quad_command};
/// use wave::WaveWidth;
///
/// // Lane 0: a 2x2 sample over quad (3, 1); lane 1: one pixel, bottom-right of quad (0, 0).
/// let cmds = [quad_command(3, 1, 0b1111), quad_command(0, 0, 0b1000)];
/// let list = expand_wave(&cmds, WaveWidth::W8)?;
/// assert_eq!(list.first_entry, [0, 4]);
/// assert_eq!(list.pixels(), [(0, 6, 2), (0, 7, 2), (0, 6, 3), (0, 7, 3), (1, 1, 1)]);
/// # Ok::<(), tiling::Error>(())
/// ```
pub fn expand_wave(commands: &[u16], width: WaveWidth) -> Result<BroadcastList, Error> {
    if commands.len() > width.len() {
        return Err(Error::BufferSize {
            what: "quad commands of one wave",
            expected: width.len() as u64,
            got: commands.len() as u64,
        });
    }
    let lanes = commands.len() as u32;
    let wave = Wave::with_lane_count(width, lanes).map_err(|_| Error::InvalidConfig {
        what: "wave lanes",
        value: lanes.into(),
        min: 0,
        max: width.lanes().into(),
    })?;
    let mask_of = |lane: u32| {
        commands
            .get(lane as usize)
            .map_or(0, |&c| unpack_quad_command(c).2)
    };
    // Each lane's run length, then MaskBitCnt-style starts: the wave's exclusive add.
    let counts = PerLane::from_fn(width, |lane| mask_of(lane).count_ones());
    let starts = wave.exclusive_add(&counts);
    let mut list = BroadcastList {
        entries: Vec::with_capacity(wave.sum(&counts) as usize),
        ..BroadcastList::default()
    };
    for lane in 0..lanes {
        let (qx, qy, mask) = unpack_quad_command(commands[lane as usize]);
        list.first_entry.push(starts.as_slice()[lane as usize]);
        list.quad_origin.push(((2 * qx) as u8, (2 * qy) as u8));
        list.needs_broadcast |= mask.count_ones() > 1;
        let mut bits = mask;
        while bits != 0 {
            let b = bits.trailing_zeros();
            bits &= bits - 1;
            list.entries.push(
                (lane | ((b & 1) << BROADCAST_DX_BIT) | ((b >> 1) << BROADCAST_DY_BIT)) as u8,
            );
        }
    }
    Ok(list)
}
