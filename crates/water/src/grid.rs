//! What the crate's row-major grids (decals, distance fields, flow fields, screen tiles)
//! share: their `width()` and `height()` getters and the clamped texel index.

/// The `width()` and `height()` getters of a type with `width: u32` and `height: u32`
/// fields, documented as `"<prefix>width in <unit>."` and `"<prefix>height in <unit>."`.
macro_rules! size_getters {
    ($width:literal, $height:literal) => {
        #[doc = $width]
        #[must_use]
        pub fn width(&self) -> u32 {
            self.width
        }
        #[doc = $height]
        #[must_use]
        pub fn height(&self) -> u32 {
            self.height
        }
    };
}
pub(crate) use size_getters;

/// The row-major index of texel `(x, y)` of a `width x height` grid, `x` and `y` clamped
/// to the grid (the edge texels repeat outwards).
#[inline]
pub(crate) fn clamped_index(width: u32, height: u32, x: i64, y: i64) -> usize {
    let x = x.clamp(0, i64::from(width) - 1) as usize;
    let y = y.clamp(0, i64::from(height) - 1) as usize;
    y * width as usize + x
}
