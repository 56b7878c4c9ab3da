//! The conservative HiZ pyramid of the previous frame's depth, and the occlusion test
//! against it ("Bonus slides: Occlusion culling").
//!
//! Level 0 is the depth buffer (`width x height` f32, row-major, row 0 at the top). Level
//! `l + 1` has `ceil(w / 2) x ceil(h / 2)` texels, each the *farthest* of the (up to) 2x2
//! texels below it: the maximum for standard depth, the minimum for reversed depth. With
//! ceil-halving an odd last row or column has only one texel under it, and texel `(x, y)`
//! of level `l` covers exactly the level-0 texels `[x 2^l, (x + 1) 2^l) x [y 2^l, (y + 1)
//! 2^l)` clipped to the buffer, so any level is a conservative bound of the depth it
//! covers whatever the sizes (no power-of-two padding, no texel lost at odd edges).
//! NaN depth is treated as the far plane's side of everything (it never occludes).
//!
//! The test ([`HiZ::occluded`]) projects a box's eight corners, takes its nearest depth
//! and its pixel rectangle, picks the level at which the rectangle spans at most 2x2
//! texels ("four texels for small objects"), and, for boxes whose 2x2 level is coarse,
//! scans the rectangle some levels finer ("scan box of texels for larger objects"). The
//! box is occluded only if it is behind every texel read.

use alloc::vec::Vec;

use glam::{Mat4, Vec3, Vec4};

use crate::Error;

/// Extra depth an occluder must be in front by (absorbs f32 rounding of the projection).
pub const HIZ_DEPTH_EPSILON: f32 = 1.0 / (1 << 20) as f32;

/// One level of a [`HiZ`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HiZLevel {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Offset of the level's first texel in [`HiZ::texels`].
    pub offset: usize,
}

/// A conservative depth pyramid (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct HiZ {
    reversed: bool,
    levels: Vec<HiZLevel>,
    texels: Vec<f32>,
}

impl HiZ {
    /// Builds the pyramid of `depth` (`width * height` samples, row-major, top row first).
    /// `reversed`: near is 1 and far is 0, so levels keep the minimum.
    pub fn build(depth: &[f32], width: u32, height: u32, reversed: bool) -> Result<HiZ, Error> {
        if width == 0 || height == 0 || depth.len() as u64 != u64::from(width) * u64::from(height) {
            return Err(Error::DepthSize {
                width,
                height,
                len: depth.len(),
            });
        }
        let far = if reversed {
            f32::NEG_INFINITY
        } else {
            f32::INFINITY
        };
        let farthest = |a: f32, b: f32| if reversed { a.min(b) } else { a.max(b) };
        let mut texels: Vec<f32> = depth
            .iter()
            .map(|&d| if d.is_nan() { far } else { d })
            .collect();
        let mut levels = alloc::vec![HiZLevel {
            width,
            height,
            offset: 0
        }];
        let (mut w, mut h) = (width, height);
        while w > 1 || h > 1 {
            let (nw, nh) = (w.div_ceil(2), h.div_ceil(2));
            let src = levels[levels.len() - 1].offset;
            let dst = texels.len();
            texels.reserve((nw * nh) as usize);
            for y in 0..nh {
                let y0 = 2 * y;
                let y1 = (2 * y + 1).min(h - 1);
                for x in 0..nw {
                    let x0 = 2 * x;
                    let x1 = (2 * x + 1).min(w - 1);
                    let at = |xx: u32, yy: u32| texels[src + (yy * w + xx) as usize];
                    let v = farthest(
                        farthest(at(x0, y0), at(x1, y0)),
                        farthest(at(x0, y1), at(x1, y1)),
                    );
                    texels.push(v);
                }
            }
            levels.push(HiZLevel {
                width: nw,
                height: nh,
                offset: dst,
            });
            (w, h) = (nw, nh);
        }
        Ok(HiZ {
            reversed,
            levels,
            texels,
        })
    }

    /// Whether depth is reversed (levels hold minima).
    #[must_use]
    pub fn reversed(&self) -> bool {
        self.reversed
    }

    /// The levels, finest first; the last is 1x1.
    #[must_use]
    pub fn levels(&self) -> &[HiZLevel] {
        &self.levels
    }

    /// All texels, level after level.
    #[must_use]
    pub fn texels(&self) -> &[f32] {
        &self.texels
    }

    /// Level-0 size.
    #[must_use]
    pub fn size(&self) -> (u32, u32) {
        (self.levels[0].width, self.levels[0].height)
    }

    /// Texel `(x, y)` of level `level`; `None` outside.
    #[must_use]
    pub fn texel(&self, level: usize, x: u32, y: u32) -> Option<f32> {
        let l = self.levels.get(level)?;
        if x >= l.width || y >= l.height {
            return None;
        }
        Some(self.texels[l.offset + (y * l.width + x) as usize])
    }

    /// The occlusion test of the world box `[min, max]` (floating space), projected with
    /// `clip_from_floating` (the matrix the depth was rendered with) onto this pyramid;
    /// `scan_levels` as in [`occluded_rect`](Self::occluded_rect). True only if every
    /// pixel the box can cover
    /// has an occluder in front of the box's nearest point. Boxes reaching behind the
    /// camera (w <= 0 at a corner) are never occluded.
    #[must_use]
    #[inline]
    pub fn occluded(
        &self,
        clip_from_floating: &Mat4,
        min: Vec3,
        max: Vec3,
        scan_levels: u32,
    ) -> bool {
        let Some((rect, depth)) =
            project_box(clip_from_floating, min, max, self.reversed, self.size())
        else {
            return false;
        };
        self.occluded_rect(rect, depth, scan_levels)
    }

    /// The occlusion test of a level-0 pixel rectangle `[x0, x1] x [y0, y1]` (inclusive,
    /// inside the buffer) whose nearest depth is `depth`. The level is the finest `l` at
    /// which the rectangle spans at most 2x2 texels; if `l > scan_levels` and
    /// `scan_levels > 0`, the rectangle is scanned at level `l - scan_levels` instead (at
    /// most `(2^scan_levels + 1)^2` texels), a tighter test for large boxes. Level `l`'s
    /// 2x2 texels are read first either way: each is the farthest of the texels under it,
    /// so behind them is behind the scan (the verdict is the scan's, in four reads).
    #[must_use]
    pub fn occluded_rect(&self, rect: [u32; 4], depth: f32, scan_levels: u32) -> bool {
        let [x0, y0, x1, y1] = rect;
        let mut l = 0u32;
        while ((x1 >> l) - (x0 >> l)) > 1 || ((y1 >> l) - (y0 >> l)) > 1 {
            l += 1;
        }
        let top = self.levels.len() as u32 - 1;
        let l = l.min(top);
        if self.behind_texels(l, rect, depth) {
            return true;
        }
        scan_levels > 0 && l > scan_levels && self.behind_texels(l - scan_levels, rect, depth)
    }

    /// Whether `depth` is behind every texel of `level` under the level-0 rectangle.
    fn behind_texels(&self, level: u32, [x0, y0, x1, y1]: [u32; 4], depth: f32) -> bool {
        let lv = self.levels[level as usize];
        for y in (y0 >> level)..=(y1 >> level).min(lv.height - 1) {
            let row = lv.offset + (y * lv.width) as usize;
            for x in (x0 >> level)..=(x1 >> level).min(lv.width - 1) {
                let t = self.texels[row + x as usize];
                let behind = if self.reversed {
                    depth < t - HIZ_DEPTH_EPSILON
                } else {
                    depth > t + HIZ_DEPTH_EPSILON
                };
                if !behind {
                    return false;
                }
            }
        }
        true
    }
}

/// Projects a floating-space box: its level-0 pixel rectangle (inclusive, clamped to the
/// buffer) and nearest depth. `None` when a corner has `w <= 0` (the box reaches behind
/// the eye: never occluded) or the rectangle misses the buffer.
#[inline]
pub(crate) fn project_box(
    m: &Mat4,
    min: Vec3,
    max: Vec3,
    reversed: bool,
    size: (u32, u32),
) -> Option<([u32; 4], f32)> {
    // Corners by adding the scaled columns to the clip position of `min`.
    let base = *m * Vec4::new(min.x, min.y, min.z, 1.0);
    let e = max - min;
    let cx = m.x_axis * e.x;
    let cy = m.y_axis * e.y;
    let cz = m.z_axis * e.z;
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for i in 0..8 {
        let mut c = base;
        if i & 1 != 0 {
            c += cx;
        }
        if i & 2 != 0 {
            c += cy;
        }
        if i & 4 != 0 {
            c += cz;
        }
        if c.w.is_nan() || c.w <= 1e-6 {
            return None;
        }
        let inv = 1.0 / c.w;
        let p = Vec3::new(c.x * inv, c.y * inv, c.z * inv);
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let (w, h) = (size.0 as f32, size.1 as f32);
    // Pixel x grows with NDC x, pixel y shrinks with NDC y; a small margin absorbs rounding.
    const MARGIN: f32 = 1.0 / 64.0;
    let px0 = (lo.x * 0.5 + 0.5) * w - MARGIN;
    let px1 = (hi.x * 0.5 + 0.5) * w + MARGIN;
    let py0 = (0.5 - hi.y * 0.5) * h - MARGIN;
    let py1 = (0.5 - lo.y * 0.5) * h + MARGIN;
    if !(px1 >= 0.0 && py1 >= 0.0 && px0 < w && py0 < h) {
        return None;
    }
    let clamp = |v: f32, n: u32| -> u32 {
        if v <= 0.0 {
            0
        } else {
            (crate::math::floor(v) as u32).min(n - 1)
        }
    };
    let rect = [
        clamp(px0, size.0),
        clamp(py0, size.1),
        clamp(px1, size.0),
        clamp(py1, size.1),
    ];
    let depth = if reversed { hi.z } else { lo.z };
    Some((rect, depth))
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::vec;

    #[test]
    fn every_level_bounds_the_depth_it_covers() {
        let mut rng = testkit::Rng::new(7);
        for (w, h) in [
            (1, 1),
            (2, 1),
            (3, 5),
            (37, 23),
            (64, 64),
            (65, 17),
            (100, 1),
        ] {
            for reversed in [false, true] {
                let depth: Vec<f32> = (0..w * h).map(|_| rng.f32()).collect();
                let z = HiZ::build(&depth, w, h, reversed).unwrap();
                assert_eq!(z.levels().last().map(|l| (l.width, l.height)), Some((1, 1)));
                for (li, l) in z.levels().iter().enumerate() {
                    for y in 0..l.height {
                        for x in 0..l.width {
                            let t = z.texel(li, x, y).unwrap();
                            // Brute force over the level-0 texels it covers.
                            let s = 1u32 << li;
                            let mut far = if reversed {
                                f32::INFINITY
                            } else {
                                f32::NEG_INFINITY
                            };
                            for yy in y * s..((y + 1) * s).min(h) {
                                for xx in x * s..((x + 1) * s).min(w) {
                                    let d = depth[(yy * w + xx) as usize];
                                    far = if reversed { far.min(d) } else { far.max(d) };
                                }
                            }
                            assert_eq!(t, far, "{w}x{h} level {li} ({x},{y})");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn rejects_bad_sizes() {
        assert!(HiZ::build(&[], 0, 0, false).is_err());
        assert!(HiZ::build(&[0.5; 5], 2, 2, false).is_err());
    }

    #[test]
    fn nan_never_occludes() {
        let z = HiZ::build(&[f32::NAN, 0.1, 0.1, 0.1], 2, 2, false).unwrap();
        assert!(!z.occluded_rect([0, 0, 1, 1], 0.5, 0));
        assert!(z.occluded_rect([1, 0, 1, 1], 0.5, 0));
        let z = HiZ::build(&[f32::NAN, 0.9, 0.9, 0.9], 2, 2, true).unwrap();
        assert!(!z.occluded_rect([0, 0, 1, 1], 0.5, 0));
        assert!(z.occluded_rect([1, 1, 1, 1], 0.5, 0));
    }

    #[test]
    fn scan_is_tighter_than_four_texels() {
        // A wall at depth 0.2 everywhere except one far pixel at the corner of the screen.
        let (w, h) = (64u32, 64u32);
        let mut depth = vec![0.2f32; (w * h) as usize];
        depth[0] = 1.0;
        let z = HiZ::build(&depth, w, h, false).unwrap();
        // A box covering pixels 8..40: its 2x2 level (5) includes the far pixel's texel...
        let rect = [8, 8, 40, 40];
        assert!(!z.occluded_rect(rect, 0.5, 0));
        // ...a scan two levels finer does not.
        assert!(z.occluded_rect(rect, 0.5, 2));
    }
}
