//! The shapes every other module of the crate shares: the 128x128 tile, the bits of a
//! pixel or quad command, the vis buffer with its validity rule and the indirect dispatch
//! of a pass. It imports nothing of the crate but [`Error`], so the classification, the
//! VRS quad commands and the vertex pass all build on it without importing one another.
//!
//! Everything here is public through [`crate::classify`] (and the crate root where it was
//! re-exported before).

use visbuf::VisLayout;

use crate::Error;

/// Side of a loose tile in pixels.
pub const TILE_SIZE: u32 = 128;
/// `log2(TILE_SIZE)`.
pub const TILE_SHIFT: u32 = 7;
/// Bit position of y in a pixel command (x is in the bits below).
pub const PIXEL_Y_SHIFT: u32 = 7;
/// Mask of one coordinate in a pixel command.
pub const PIXEL_COORD_MASK: u32 = TILE_SIZE - 1;
/// Bit position of the quad's y in a quad command.
pub const QUAD_Y_SHIFT: u32 = 6;
/// Mask of one quad coordinate in a quad command (64 quads per tile side).
pub const QUAD_COORD_MASK: u32 = TILE_SIZE / 2 - 1;
/// Mask of the 12-bit quad index in a quad command.
pub const QUAD_INDEX_MASK: u32 = 0xfff;
/// Bit position of the 4-bit pixel mask in a quad command.
pub const QUAD_PIXELS_SHIFT: u32 = 12;
/// Most workgroups in one dimension of a dispatch (WebGPU's default
/// `max_compute_workgroups_per_dimension`, [`shader::MAX_WORKGROUPS_X`]): larger wave
/// counts spill into `y`.
pub const MAX_DISPATCH_X: u32 = shader::MAX_WORKGROUPS_X;
/// Largest vis-buffer width or height.
pub const MAX_DIMENSION: u32 = 32_768;

/// Whether pixel `(x, y)`, holding `word`, starts a triangle run: neither its left nor its
/// upper neighbour (in the whole buffer, across tile edges) holds the same word with its
/// validity bit set. Every valid pixel's word is also held by a run start at or above-left
/// of it, so marking a triangle's vertex chunks only at run starts marks every visible
/// triangle. Out-of-range coordinates are run starts.
#[must_use]
pub fn first_of_run(vis: &VisBuffer<'_>, x: u32, y: u32, word: u32) -> bool {
    let w = vis.width as usize;
    let same = |i: usize| {
        vis.words.get(i) == Some(&word)
            && vis
                .valid
                .is_none_or(|m| m.get(i >> 5).is_some_and(|b| (b >> (i & 31)) & 1 == 1))
    };
    let i = y as usize * w + x as usize;
    !((x > 0 && x < vis.width && same(i - 1)) || (y > 0 && x < vis.width && same(i - w)))
}

/// The standard-layout pixel command of pixel `(x, y)` within its tile (each `0..128`,
/// masked).
#[must_use]
#[inline]
pub const fn pixel_command(x: u32, y: u32) -> u16 {
    ((x & PIXEL_COORD_MASK) | ((y & PIXEL_COORD_MASK) << PIXEL_Y_SHIFT)) as u16
}

/// The `(x, y)` within its tile of a pixel command.
#[must_use]
#[inline]
pub const fn unpack_pixel_command(cmd: u16) -> (u32, u32) {
    let c = cmd as u32;
    (
        c & PIXEL_COORD_MASK,
        (c >> PIXEL_Y_SHIFT) & PIXEL_COORD_MASK,
    )
}

/// A vis buffer with its validity rule: `width * height` words, row-major from the
/// top-left, and an optional bitmask (bit `i % 32` of word `i / 32` for pixel
/// `i = y * width + x`) that must also be set for a pixel to count (the talk's stencil
/// bit).
#[derive(Clone, Copy, Debug)]
pub struct VisBuffer<'a> {
    words: &'a [u32],
    valid: Option<&'a [u32]>,
    width: u32,
    height: u32,
    layout: VisLayout,
}

impl<'a> VisBuffer<'a> {
    /// Checks the size: `words.len() == width * height`, both sides in
    /// `1..=`[`MAX_DIMENSION`].
    pub fn new(
        words: &'a [u32],
        width: u32,
        height: u32,
        layout: VisLayout,
    ) -> Result<Self, Error> {
        for (what, v) in [("width", width), ("height", height)] {
            if v == 0 || v > MAX_DIMENSION {
                return Err(Error::InvalidConfig {
                    what,
                    value: v.into(),
                    min: 1,
                    max: MAX_DIMENSION.into(),
                });
            }
        }
        Error::check_len(
            "vis buffer",
            u64::from(width) * u64::from(height),
            words.len(),
        )?;
        Ok(Self {
            words,
            valid: None,
            width,
            height,
            layout,
        })
    }

    /// Adds the validity bitmask: `ceil(width * height / 32)` words.
    pub fn with_validity(self, mask: &'a [u32]) -> Result<Self, Error> {
        let n = (u64::from(self.width) * u64::from(self.height)).div_ceil(32);
        Error::check_len("validity mask", n, mask.len())?;
        Ok(Self {
            valid: Some(mask),
            ..self
        })
    }

    /// The words.
    #[must_use]
    pub fn words(&self) -> &'a [u32] {
        self.words
    }

    /// The validity bitmask, if any.
    #[must_use]
    pub fn validity(&self) -> Option<&'a [u32]> {
        self.valid
    }

    /// Width in pixels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The word layout.
    #[must_use]
    pub fn layout(&self) -> VisLayout {
        self.layout
    }

    /// Tiles across.
    #[must_use]
    pub fn tiles_x(&self) -> u32 {
        self.width.div_ceil(TILE_SIZE)
    }

    /// Tiles down.
    #[must_use]
    pub fn tiles_y(&self) -> u32 {
        self.height.div_ceil(TILE_SIZE)
    }

    /// Tiles in all.
    #[must_use]
    pub fn tile_count(&self) -> u32 {
        self.tiles_x() * self.tiles_y()
    }

    /// Whether pixel `i` passes the validity bitmask (true without one).
    #[inline(always)]
    pub(crate) fn mask_bit(&self, i: usize) -> bool {
        match self.valid {
            None => true,
            Some(m) => (m[i >> 5] >> (i & 31)) & 1 == 1,
        }
    }
}

/// One pass's indirect dispatch (WGSL `TilingPassDispatch`), 24 bytes. The first three
/// words are `dispatch_workgroups_indirect`'s arguments (at byte offset `24 * p`): one
/// workgroup per command, `x = min(count, 65535)`, `y = ceil(count / 65535)`, `z = 1`
/// (zero workgroups when the pass has no work). A shader finds its command as
/// `first + workgroup_id.y * 65535 + workgroup_id.x` and returns when that passes
/// `first + count`.
///
/// For pixel shading a command is a [`WaveCommand`](crate::WaveCommand) and `items` counts pixel commands;
/// for the vertex transform a command is a [`VertexWaveCommand`](crate::VertexWaveCommand)
/// and `items` counts vertices in its chunks.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PassDispatch {
    /// Workgroups in x.
    pub x: u32,
    /// Workgroups in y.
    pub y: u32,
    /// Workgroups in z (1, or 0 with no work).
    pub z: u32,
    /// Index of the pass's first command.
    pub first: u32,
    /// Commands of the pass.
    pub count: u32,
    /// Work items of the pass (pixel commands or vertices).
    pub items: u32,
}

const _: () = assert!(size_of::<PassDispatch>() == 24);

impl PassDispatch {
    /// The arguments for `count` commands starting at `first`.
    #[must_use]
    pub const fn new(first: u32, count: u32, items: u32) -> Self {
        let x = if count < MAX_DISPATCH_X {
            count
        } else {
            MAX_DISPATCH_X
        };
        let y = count.div_ceil(MAX_DISPATCH_X);
        Self {
            x,
            y,
            z: if count == 0 { 0 } else { 1 },
            first,
            count,
            items,
        }
    }
}
