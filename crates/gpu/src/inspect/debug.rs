//! Debug views the `render` binary writes: the vis buffer colour-coded by ID (the talk's
//! slide), wave commands per 128x128 tile as a heat map, and the quad overdraw HZD's
//! depth-equal pass has. All are computed on the CPU from read-back buffers, so they show
//! what the GPU wrote.

use crate::image::{Rgba8Image, heat_color, id_color};
use crate::statics::{StaticDebug, StaticPixel};
use crate::stats::GpuClassification;

/// Colour of pixels without vis-buffer geometry (sky) in the views.
const EMPTY: [u8; 4] = [230, 200, 40, 255];

/// The vis buffer colour-coded by its word (micro batch, instance, primitive): each
/// triangle of each instance gets its own colour; pixels without geometry are yellow.
pub fn vis_ids(width: u32, height: u32, vis: &[u32]) -> Rgba8Image {
    let mut img = Rgba8Image::new(width, height, EMPTY);
    for (p, &w) in img.pixels.iter_mut().zip(vis) {
        if w != visbuf::VIS_NONE {
            *p = id_color(w);
        }
    }
    img
}

/// HFW's software VRS: the shading rate of every pixel from the rate bits of its vis word
/// (visbuf's VRS layout: `RendererConfig::geometry.vrs`): 1x1 dark green, 1x2 blue, 2x1 orange,
/// 2x2 red; pixels without geometry yellow. Returns the image and the pixels at each rate
/// (code order: 1x1, 1x2, 2x1, 2x2).
pub fn shading_rate(width: u32, height: u32, vis: &[u32]) -> (Rgba8Image, [u64; 4]) {
    const COLOURS: [[u8; 4]; 4] = [
        [20, 90, 30, 255],
        [40, 90, 230, 255],
        [240, 150, 30, 255],
        [220, 30, 30, 255],
    ];
    let mut img = Rgba8Image::new(width, height, EMPTY);
    let mut counts = [0u64; 4];
    for (p, &w) in img.pixels.iter_mut().zip(vis) {
        if w != visbuf::VIS_NONE {
            let code = (w >> 30) as usize;
            counts[code] += 1;
            *p = COLOURS[code];
        }
    }
    (img, counts)
}

/// Wave commands per 128x128 tile (summed over passes and batch groups) as a heat map
/// scaled to the busiest tile, blended over a grey version of the vis buffer so the scene
/// shows through; tile borders are drawn dark. Returns the image and the busiest tile's
/// wave count.
pub fn wave_heatmap(width: u32, height: u32, c: &GpuClassification) -> (Rgba8Image, u32) {
    let tiles_x = width.div_ceil(tiling::TILE_SIZE);
    let tiles_y = height.div_ceil(tiling::TILE_SIZE);
    let mut per_tile = vec![0u32; (tiles_x * tiles_y) as usize];
    for w in &c.waves {
        let (x, y) = w.tile_xy();
        if x < tiles_x && y < tiles_y {
            per_tile[(y * tiles_x + x) as usize] += 1;
        }
    }
    let max = per_tile.iter().copied().max().unwrap_or(0).max(1);
    let mut img = Rgba8Image::new(width, height, [0, 0, 0, 255]);
    for y in 0..height {
        for x in 0..width {
            let i = (y * width + x) as usize;
            let t = (y / tiling::TILE_SIZE) * tiles_x + x / tiling::TILE_SIZE;
            let heat = heat_color(per_tile[t as usize] as f32 / max as f32);
            let border = x % tiling::TILE_SIZE == 0 || y % tiling::TILE_SIZE == 0;
            let grey = if c.vis.get(i).is_some_and(|&w| w != visbuf::VIS_NONE) {
                90u16
            } else {
                40
            };
            img.pixels[i] = if border {
                [20, 20, 20, 255]
            } else {
                let mix = |h: u8| ((u16::from(h) * 3 + grey) / 4) as u8;
                [mix(heat[0]), mix(heat[1]), mix(heat[2]), 255]
            };
        }
    }
    (img, max)
}

/// HZD's depth-equal quad overdraw: for every 2x2 pixel quad, the number of distinct
/// triangles (vis words) visible in it, each of which launches a whole quad in the
/// depth-equal pass (1: blue, 4: red). Assumes no two triangles tie in depth, as the
/// vis buffer's single winner already does. Returns the image and the mean quads shaded
/// per covered quad.
pub fn quad_overdraw(width: u32, height: u32, vis: &[u32]) -> (Rgba8Image, f64) {
    const QUAD: [(u32, u32); 4] = [(0, 0), (1, 0), (0, 1), (1, 1)];
    let mut img = Rgba8Image::new(width, height, EMPTY);
    let (mut quads, mut shaded) = (0u64, 0u64);
    // A pixel past the buffer reads as sky.
    let word = |x: u32, y: u32| -> Option<u32> {
        (x < width && y < height)
            .then(|| vis.get((y * width + x) as usize).copied())
            .flatten()
            .filter(|&w| w != visbuf::VIS_NONE)
    };
    for qy in (0..height).step_by(2) {
        for qx in (0..width).step_by(2) {
            // Distinct words among the quad's (up to) four pixels.
            let mut ids = [0u32; 4];
            let mut n = 0;
            for (dx, dy) in QUAD {
                if let Some(w) = word(qx + dx, qy + dy)
                    && !ids[..n].contains(&w)
                {
                    ids[n] = w;
                    n += 1;
                }
            }
            if n == 0 {
                continue;
            }
            quads += 1;
            shaded += n as u64;
            let colour = heat_color(0.2 + 0.2 * (n as f32 - 1.0));
            for (dx, dy) in QUAD {
                let (x, y) = (qx + dx, qy + dy);
                if x < width && y < height {
                    img.pixels[(y * width + x) as usize] = colour;
                }
            }
        }
    }
    (img, shaded as f64 / quads.max(1) as f64)
}

/// The HiZ pyramid the static query tested against (`StaticQuery::read_hiz`: texels level
/// after level, ceil-halved from `size`) as a mip atlas: level 0 on the left, level 1 to
/// its right, each further level below the one before. Reversed depth in grey on a log
/// scale (1, the near plane, white; 10^-4 black); texels at 0 (nothing drawn: the far
/// plane) in the empty colour.
pub fn hiz_mips(texels: &[f32], size: (u32, u32)) -> Rgba8Image {
    let (w0, h0) = size;
    let w1 = w0.div_ceil(2);
    let mut img = Rgba8Image::new(w0 + w1, h0, [0, 0, 0, 255]);
    if w0 == 0 || h0 == 0 {
        return img;
    }
    let grey = |d: f32| -> [u8; 4] {
        if d <= 0.0 {
            return EMPTY;
        }
        let v = (1.0 + d.log10() / 4.0).clamp(0.0, 1.0);
        let g = (v * 255.0).round() as u8;
        [g, g, g, 255]
    };
    let (mut w, mut h) = (w0, h0);
    let (mut ox, mut oy) = (0u32, 0u32);
    let mut at = 0usize;
    let mut level = 0;
    loop {
        for y in 0..h {
            for x in 0..w {
                let (px, py) = (ox + x, oy + y);
                if let (Some(&t), true) = (texels.get(at + (y * w + x) as usize), py < h0) {
                    img.pixels[(py * img.width + px) as usize] = grey(t);
                }
            }
        }
        at += (w * h) as usize;
        if w == 1 && h == 1 {
            break;
        }
        if level == 0 {
            ox = w0;
        } else {
            oy += h;
        }
        level += 1;
        (w, h) = (w.div_ceil(2), h.div_ceil(2));
    }
    img
}

/// Static instances coloured by setup (each LOD level's mesh is a setup of its own, so a
/// LOD switch shows as a change of colour) and LOD fade state: steady instances in a pale
/// version of their setup's colour, instances fading in green and fading out red, darker
/// the more transparent they are; planned instances grey, the sky in the empty colour.
pub fn static_lod_fade(width: u32, height: u32, vis: &[u32], statics: &StaticDebug) -> Rgba8Image {
    static_view(width, height, vis, statics, |p| {
        let target = if p.flags & staticscene::STATE_FADING_OUT != 0 {
            [220, 40, 40]
        } else if p.flags & staticscene::STATE_FADING != 0 {
            [40, 200, 60]
        } else {
            return blend(
                id_color(p.setup.wrapping_mul(0x9e37_79b9)),
                [255, 255, 255],
                0.55,
            );
        };
        blend([0, 0, 0, 255], target, 0.3 + 0.7 * p.fade)
    })
}

/// Occlusion's work over `image` (the frame of `params`' view): the screen rectangle of
/// every static instance the query would draw without occlusion (`unoccluded`, e.g. the
/// CPU twin's output with occlusion off) outlined in green if it is also in `visible` (the
/// output with occlusion on) and in red if occlusion culled it; the red ones on top, so the
/// culled instances behind the drawn ones show through. Boxes are the instances' setup
/// bounds through their floating-space transforms; one crossing the near plane is skipped.
pub fn occlusion_overlay(
    image: &Rgba8Image,
    scene: &staticscene::Scene,
    params: &staticscene::QueryParams,
    unoccluded: &[staticscene::DrawableSetupInstance],
    visible: &[staticscene::DrawableSetupInstance],
) -> Rgba8Image {
    let key = |d: &staticscene::DrawableSetupInstance| (d.state.tile, d.state.instance);
    let drawn: std::collections::HashSet<_> = visible.iter().map(key).collect();
    let m = params.clip_from_floating();
    let (w, h) = (image.width as f32, image.height as f32);
    let rect = |d: &staticscene::DrawableSetupInstance| -> Option<[u32; 4]> {
        let tile = scene.tiles().iter().find(|t| t.id().0 == d.state.tile)?;
        let q = tile.instances().get(d.state.instance as usize)?;
        let setup = tile.setups().get(q.setup() as usize)?;
        let (lo, hi) = (setup.min(), setup.max());
        let to_floating = d.local_to_floating.to_affine();
        let (mut min, mut max) = (glam::Vec2::splat(f32::MAX), glam::Vec2::splat(f32::MIN));
        for i in 0..8 {
            let c = glam::Vec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            );
            let p = m * to_floating.transform_point3(c).extend(1.0);
            if p.w <= 0.0 {
                return None;
            }
            let s = glam::Vec2::new((p.x / p.w * 0.5 + 0.5) * w, (0.5 - p.y / p.w * 0.5) * h);
            min = min.min(s);
            max = max.max(s);
        }
        if max.x < 0.0 || max.y < 0.0 || min.x >= w || min.y >= h {
            return None;
        }
        let clamp = |v: f32, hi: f32| v.clamp(0.0, hi - 1.0) as u32;
        Some([
            clamp(min.x, w),
            clamp(min.y, h),
            clamp(max.x, w),
            clamp(max.y, h),
        ])
    };
    let mut out = image.clone();
    for occluded in [false, true] {
        let colour = if occluded {
            [230, 30, 30, 255]
        } else {
            [40, 220, 60, 255]
        };
        for d in unoccluded
            .iter()
            .filter(|d| drawn.contains(&key(d)) != occluded)
        {
            if let Some([x0, y0, x1, y1]) = rect(d) {
                for x in x0..=x1 {
                    out.pixels[(y0 * out.width + x) as usize] = colour;
                    out.pixels[(y1 * out.width + x) as usize] = colour;
                }
                for y in y0..=y1 {
                    out.pixels[(y * out.width + x0) as usize] = colour;
                    out.pixels[(y * out.width + x1) as usize] = colour;
                }
            }
        }
    }
    out
}

/// Two-pass occlusion's split: static instances the first pass drew (visible last frame)
/// in blue, those the second pass found in orange; planned instances grey.
pub fn static_two_pass(width: u32, height: u32, vis: &[u32], statics: &StaticDebug) -> Rgba8Image {
    static_view(width, height, vis, statics, |p| {
        if p.late {
            [250, 150, 30, 255]
        } else {
            [50, 110, 230, 255]
        }
    })
}

fn static_view(
    width: u32,
    height: u32,
    vis: &[u32],
    statics: &StaticDebug,
    colour: impl Fn(StaticPixel) -> [u8; 4],
) -> Rgba8Image {
    let mut img = Rgba8Image::new(width, height, EMPTY);
    for (p, &w) in img.pixels.iter_mut().zip(vis) {
        if w == visbuf::VIS_NONE {
            continue;
        }
        *p = match statics.lookup(w) {
            Some(s) => colour(s),
            None => [120, 120, 120, 255],
        };
    }
    img
}

/// The G-buffer's motion vectors: hue by direction (right red, down green-yellow, left
/// cyan, up blue-violet), brightness by length, full at `scale` pixels (0: the longest in
/// the image); pixels without motion black. Returns the image and the length at full
/// brightness.
pub fn motion_vectors(
    width: u32,
    height: u32,
    surfaces: &[deferred::Surface],
    scale: f32,
) -> (Rgba8Image, f32) {
    let longest = surfaces
        .iter()
        .map(|s| s.motion.length())
        .filter(|l| l.is_finite())
        .fold(0.0f32, f32::max);
    let scale = if scale > 0.0 {
        scale
    } else {
        longest.max(1e-6)
    };
    let mut img = Rgba8Image::new(width, height, [0, 0, 0, 255]);
    for (px, s) in img.pixels.iter_mut().zip(surfaces) {
        let m = s.motion;
        let length = m.length();
        if !(length.is_finite() && length > 0.0) {
            continue;
        }
        let hue = (m.y.atan2(m.x) / core::f32::consts::TAU).rem_euclid(1.0) * 6.0;
        let v = (length / scale).min(1.0);
        let f = hue.fract();
        let (r, g, b) = match hue as u32 {
            0 => (1.0, f, 0.0),
            1 => (1.0 - f, 1.0, 0.0),
            2 => (0.0, 1.0, f),
            3 => (0.0, 1.0 - f, 1.0),
            4 => (f, 0.0, 1.0),
            _ => (1.0, 0.0, 1.0 - f),
        };
        let c = |x: f32| (x * v * 255.0).round() as u8;
        *px = [c(r), c(g), c(b), 255];
    }
    (img, scale)
}

/// The sun's shadow maps side by side, one `resolution`² layer per cascade (nearest first,
/// left to right), depth as grey (black nearest the sun, white where nothing casts), each
/// map downsampled by `step` (1: every texel) by taking the nearest of its texels.
pub fn shadow_atlas(maps: &[Vec<f32>], resolution: u32, step: u32) -> Rgba8Image {
    let step = step.max(1);
    let side = resolution.div_ceil(step);
    let mut img = Rgba8Image::new(side * maps.len() as u32, side, [0, 0, 0, 255]);
    for (k, map) in maps.iter().enumerate() {
        for y in 0..side {
            for x in 0..side {
                let mut nearest = 1.0f32;
                for sy in y * step..((y + 1) * step).min(resolution) {
                    for sx in x * step..((x + 1) * step).min(resolution) {
                        if let Some(&d) = map.get((sy * resolution + sx) as usize) {
                            nearest = nearest.min(d);
                        }
                    }
                }
                let g = (nearest.clamp(0.0, 1.0) * 255.0).round() as u8;
                img.pixels[(y * img.width + k as u32 * side + x) as usize] = [g, g, g, 255];
            }
        }
    }
    img
}

/// Colours of [`cascade_index`]'s slices, nearest first.
pub const CASCADE_COLOURS: [[u8; 3]; 8] = [
    [230, 60, 60],
    [60, 200, 80],
    [70, 110, 240],
    [240, 200, 50],
    [200, 80, 220],
    [60, 210, 220],
    [240, 140, 60],
    [160, 160, 160],
];

/// The sun's depth slice each pixel falls in, by its view distance (from the reversed-Z
/// `depth` of a camera with `near`, `fov_y` and this image's aspect) against the
/// slices' far distances `splits` (nearest first): [`CASCADE_COLOURS`] over a grey of the
/// depth; beyond the last slice dark grey, sky black.
pub fn cascade_index(
    width: u32,
    height: u32,
    depth: &[f32],
    near: f32,
    splits: &[f64],
) -> Rgba8Image {
    let mut img = Rgba8Image::new(width, height, [0, 0, 0, 255]);
    for (px, &d) in img.pixels.iter_mut().zip(depth) {
        // Sky (0) and NaN hold no slice.
        if d.is_nan() || d <= 0.0 {
            continue;
        }
        // Infinite reversed Z: depth = near / distance.
        let distance = f64::from(near) / f64::from(d);
        *px = match splits.iter().position(|&far| distance <= far) {
            Some(k) => {
                let c = CASCADE_COLOURS[k % CASCADE_COLOURS.len()];
                [c[0], c[1], c[2], 255]
            }
            None => [50, 50, 50, 255],
        };
    }
    img
}

/// KZ2's decision per local light (`deferred::LightClassifier`): each light's screen
/// rectangle outlined over `image` (a frame of `frame`), green for the depth-bounds path
/// (small lights), red for the stencil light-volume path (large, shadow-casting, or around
/// the eye). Returns the image and the counts of lights culled, on the depth-bounds path
/// and on the volume path. (The frame lights both kinds through the tile lists; the
/// volume path's own passes are not built.)
pub fn light_paths(image: &Rgba8Image, frame: &crate::FrameInput) -> (Rgba8Image, [u32; 3]) {
    use deferred::lights::{LightClassifier, LightPath};
    let (w, h) = (image.width, image.height);
    let mut out = image.clone();
    let mut counts = [0u32; 3];
    if w == 0 || h == 0 || out.pixels.len() < (w * h) as usize {
        return (out, counts);
    }
    let Ok(perspective) = deferred::Perspective::try_new(
        frame.camera.fov_y,
        w.max(1) as f32 / h.max(1) as f32,
        frame.camera.near,
        None,
        deferred::DepthMode::Reversed,
    ) else {
        return (out, counts);
    };
    let proj = perspective.gpu(glam::Vec2::new(w as f32, h as f32));
    let classifier = LightClassifier::default();
    for light in crate::inspect::local_light_rows(&frame.lighting, &frame.camera) {
        let class = classifier.classify(&proj, &light);
        let colour = match class.path {
            LightPath::Culled => {
                counts[0] += 1;
                continue;
            }
            LightPath::DepthBounds => {
                counts[1] += 1;
                [40, 230, 60, 255]
            }
            LightPath::Volume => {
                counts[2] += 1;
                [240, 40, 40, 255]
            }
        };
        let clamp_x = |v: f32| (v.max(0.0) as u32).min(w.saturating_sub(1));
        let clamp_y = |v: f32| (v.max(0.0) as u32).min(h.saturating_sub(1));
        let (x0, x1) = (clamp_x(class.rect.min.x), clamp_x(class.rect.max.x));
        let (y0, y1) = (clamp_y(class.rect.min.y), clamp_y(class.rect.max.y));
        for x in x0..=x1 {
            for y in [y0, y1] {
                out.pixels[(y * w + x) as usize] = colour;
            }
        }
        for y in y0..=y1 {
            for x in [x0, x1] {
                out.pixels[(y * w + x) as usize] = colour;
            }
        }
    }
    (out, counts)
}

/// Height in pixels of the colour legend along the bottom of [`lights_per_tile`].
pub const LEGEND_HEIGHT: u32 = 12;

/// Local lights per 16x16 light tile as a heat map (black: none, white: `max` or more;
/// tiles without geometry dark grey; tile borders dark), with the colour legend along the
/// bottom [`LEGEND_HEIGHT`] rows: the scale from 0 at the left to `max` at the right, a
/// white tick at every quarter. `max` 0 scales to the busiest tile. Returns the image and
/// the count the scale ends at.
pub fn lights_per_tile(
    width: u32,
    height: u32,
    tiles: &crate::inspect::LightTiles,
    max: u32,
) -> (Rgba8Image, u32) {
    use deferred::lights::TILE_SIZE;
    let busiest = tiles.counts.iter().copied().max().unwrap_or(0);
    let max = if max == 0 { busiest.max(1) } else { max };
    let mut img = Rgba8Image::new(width, height, [0, 0, 0, 255]);
    let [tx, ty] = tiles.tiles;
    for y in 0..height {
        for x in 0..width {
            let (cx, cy) = (x / TILE_SIZE, y / TILE_SIZE);
            let t = (cy * tx + cx) as usize;
            let border = x % TILE_SIZE == 0 || y % TILE_SIZE == 0;
            let colour = match (tiles.counts.get(t), tiles.depths.get(t)) {
                _ if cx >= tx || cy >= ty => [0, 0, 0, 255],
                _ if border => [20, 20, 20, 255],
                (Some(_), Some(d)) if d.is_empty(deferred::DepthMode::Reversed) => {
                    [45, 45, 45, 255]
                }
                (Some(&n), _) => heat_color(n as f32 / max as f32),
                _ => [0, 0, 0, 255],
            };
            img.pixels[(y * width + x) as usize] = colour;
        }
    }
    let legend = LEGEND_HEIGHT.min(height);
    for y in height - legend..height {
        for x in 0..width {
            let f = if width > 1 {
                x as f32 / (width - 1) as f32
            } else {
                0.0
            };
            let tick = (1..4).any(|q| x == (width - 1) * q / 4) && y < height - legend / 2;
            img.pixels[(y * width + x) as usize] = if tick {
                [255, 255, 255, 255]
            } else {
                heat_color(f)
            };
        }
    }
    (img, max)
}

fn blend(a: [u8; 4], b: [u8; 3], t: f32) -> [u8; 4] {
    let mix = |x: u8, y: u8| (f32::from(x) + (f32::from(y) - f32::from(x)) * t).round() as u8;
    [mix(a[0], b[0]), mix(a[1], b[1]), mix(a[2], b[2]), 255]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quad_overdraw_counts_distinct_triangles_per_quad() {
        let n = visbuf::VIS_NONE;
        // 4x2: left quad has 3 triangles, right quad one triangle and a hole.
        let vis = [1, 2, 7, 7, 3, 1, 7, n];
        let (_, mean) = quad_overdraw(4, 2, &vis);
        assert!((mean - 2.0).abs() < 1e-12, "{mean}");
        // A short buffer reads as sky where it ends, never out of bounds. Five words: the
        // left quad keeps 1, 2, 3, the right quad only 7. Three words: 1, 2 and 7.
        let (_, mean) = quad_overdraw(4, 2, &vis[..5]);
        assert!((mean - 2.0).abs() < 1e-12, "{mean}");
        let (_, mean) = quad_overdraw(4, 2, &vis[..3]);
        assert!((mean - 1.5).abs() < 1e-12, "{mean}");
    }

    /// Direction picks the hue, length the brightness; no motion is black.
    #[test]
    fn motion_vectors_colour_by_direction_and_length() {
        let at = |x: f32, y: f32| deferred::Surface {
            motion: glam::Vec2::new(x, y),
            ..deferred::Surface::default()
        };
        let surfaces = [
            at(4.0, 0.0),
            at(0.0, 2.0),
            at(-4.0, 0.0),
            at(0.0, 0.0),
            at(f32::NAN, 1.0),
        ];
        let (img, scale) = motion_vectors(5, 1, &surfaces, 0.0);
        assert_eq!(scale, 4.0);
        assert_eq!(img.pixels[0], [255, 0, 0, 255]);
        // Down (+y) at half the scale: a quarter turn, between yellow and green, half lit.
        assert_eq!(img.pixels[1], [64, 128, 0, 255]);
        assert_eq!(img.pixels[2], [0, 255, 255, 255]);
        assert_eq!(img.pixels[3], [0, 0, 0, 255]);
        assert_eq!(img.pixels[4], [0, 0, 0, 255]);
        // A given scale clamps longer motion to full brightness.
        let (img, _) = motion_vectors(5, 1, &surfaces, 1.0);
        assert_eq!(img.pixels[1], [128, 255, 0, 255]);
    }

    /// Layers side by side, nearest texel of each block; slices by view distance.
    #[test]
    fn shadow_atlas_and_cascade_index_lay_out_and_colour() {
        let maps = vec![vec![1.0, 0.5, 0.0, 1.0], vec![0.25; 4]];
        let img = shadow_atlas(&maps, 2, 1);
        assert_eq!((img.width, img.height), (4, 2));
        assert_eq!(img.pixels[0], [255, 255, 255, 255]);
        assert_eq!(img.pixels[1], [128, 128, 128, 255]);
        assert_eq!(img.pixels[4], [0, 0, 0, 255]);
        assert_eq!(img.pixels[2], [64, 64, 64, 255]);
        let small = shadow_atlas(&maps, 2, 2);
        assert_eq!((small.width, small.height), (2, 1));
        assert_eq!(small.pixels[0], [0, 0, 0, 255]);
        // near 0.1: depth 0.01 is 10 m, 0.001 is 100 m, 0.0001 is 1 km.
        let img = cascade_index(4, 1, &[0.0, 0.01, 0.001, 0.0001], 0.1, &[20.0, 200.0]);
        assert_eq!(img.pixels[0], [0, 0, 0, 255]);
        assert_eq!(img.pixels[1], [230, 60, 60, 255]);
        assert_eq!(img.pixels[2], [60, 200, 80, 255]);
        assert_eq!(img.pixels[3], [50, 50, 50, 255]);
    }

    /// A small light far ahead takes the depth-bounds path, one around the eye the volume
    /// path, one behind the eye is culled; outlines stay inside the image.
    #[test]
    fn light_paths_follow_kz2s_classifier() {
        use glam::Vec3;
        let camera = crate::Camera::look_at(Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 1.0, -10.0));
        let mut frame = crate::FrameInput::new(camera);
        let point = |z: f32, radius: f32| crate::PointLight {
            position: Vec3::new(0.0, 1.0, z),
            color: Vec3::ONE,
            radius,
            specular: true,
        };
        frame.lighting.point_lights = vec![point(-30.0, 1.0), point(0.5, 3.0), point(20.0, 1.0)];
        let base = Rgba8Image::new(64, 36, [0, 0, 0, 255]);
        let (img, counts) = light_paths(&base, &frame);
        assert_eq!(counts, [1, 1, 1]);
        // An empty or short image is returned as it is, never indexed out of bounds.
        let (empty, none) = light_paths(&Rgba8Image::new(0, 0, [0; 4]), &frame);
        assert_eq!((empty.pixels.len(), none), (0, [0; 3]));
        let mut short = base.clone();
        short.pixels.truncate(10);
        assert_eq!(light_paths(&short, &frame).0.pixels.len(), 10);
        assert!(img.pixels.contains(&[40, 230, 60, 255]));
        assert!(img.pixels.contains(&[240, 40, 40, 255]));
    }

    /// Tile colours follow the counts on the scale, empty tiles are grey, and the legend
    /// runs from the scale's bottom to its top.
    #[test]
    fn lights_per_tile_colours_tiles_by_count() {
        use deferred::DeferredTileDepth;
        let full = DeferredTileDepth {
            nearest: 0.5,
            farthest: 0.2,
        };
        let tiles = crate::inspect::LightTiles {
            tiles: [3, 2],
            depths: vec![
                full,
                full,
                DeferredTileDepth::empty(deferred::DepthMode::Reversed),
                full,
                full,
                full,
            ],
            counts: vec![0, 8, 0, 4, 2, 8],
            ..crate::inspect::LightTiles::default()
        };
        let (w, h) = (40u32, 44u32);
        let (img, max) = lights_per_tile(w, h, &tiles, 0);
        assert_eq!(max, 8);
        let px = |x: u32, y: u32| img.pixels[(y * w + x) as usize];
        assert_eq!(px(5, 5), heat_color(0.0));
        assert_eq!(px(21, 5), heat_color(1.0));
        assert_eq!(px(37, 5), [45, 45, 45, 255]);
        assert_eq!(px(5, 21), heat_color(0.5));
        assert_eq!(px(16, 5), [20, 20, 20, 255]);
        // The legend: 0 at the left, the top of the scale at the right, a tick at half.
        assert_eq!(px(0, h - 1), heat_color(0.0));
        assert_eq!(px(w - 1, h - 1), heat_color(1.0));
        assert_eq!(px((w - 1) / 2, h - LEGEND_HEIGHT), [255, 255, 255, 255]);
        // A given scale clamps: 8 lights on a scale of 4 is its top.
        let (img, max) = lights_per_tile(w, h, &tiles, 4);
        assert_eq!(max, 4);
        assert_eq!(img.pixels[(5 * w + 21) as usize], heat_color(1.0));
        // Fewer counts than tiles (a short read) leave black, never read out of bounds.
        let short = crate::inspect::LightTiles {
            counts: vec![1],
            ..tiles
        };
        let (img, _) = lights_per_tile(w, h, &short, 0);
        assert_eq!(img.pixels[(5 * w + 21) as usize], [0, 0, 0, 255]);
    }

    /// Each level lands where the atlas puts it: level 0 texel for texel at the left, the
    /// last (1x1) level below the others on the right.
    #[test]
    fn hiz_mips_lays_the_levels_out() {
        let (w, h) = (6u32, 4u32);
        // Levels 6x4, 3x2, 2x1, 1x1.
        let mut texels = vec![1.0f32; 24];
        texels[5] = 0.0; // level 0 (5, 0): nothing drawn
        texels.extend([1e-2; 6]);
        texels.extend([1e-4; 2]);
        texels.push(0.0);
        let img = hiz_mips(&texels, (w, h));
        assert_eq!((img.width, img.height), (9, 4));
        let px = |x: u32, y: u32| img.pixels[(y * img.width + x) as usize];
        assert_eq!(px(0, 0), [255, 255, 255, 255]);
        assert_eq!(px(5, 0), EMPTY);
        assert_eq!(px(6, 0), [128, 128, 128, 255]);
        assert_eq!(px(6, 2), [0, 0, 0, 255]);
        assert_eq!(px(6, 3), EMPTY);
        // A zero side is an empty atlas, not a hang; too few texels leave black.
        assert_eq!(hiz_mips(&[], (0, 4)).pixels.len(), 0);
        let short = hiz_mips(&[1.0], (2, 2));
        assert_eq!(short.pixels[0], [255, 255, 255, 255]);
        assert_eq!(short.pixels[1], [0, 0, 0, 255]);
    }
}
