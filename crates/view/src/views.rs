//! The debug views the viewer can show instead of the image: every view of `gpu::inspect::debug`
//! that a demo frame has (the static query's views belong to the city, which the viewer
//! does not open). Each is made on the CPU from read-backs of the frame just rendered,
//! which is fine at viewer rates.

use anyhow::{Result, bail};
use clap::ValueEnum;
use gpu::{FrameInput, PreparedScene, RenderPath, Renderer, Rgba8Image};

/// What the window shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, ValueEnum)]
pub enum DebugView {
    /// The rendered frame.
    #[default]
    Image,
    /// The vis buffer colour-coded by word: one colour per triangle of each instance.
    VisIds,
    /// Wave commands per 128x128 tile (the classification's output) as a heat map.
    WavesPerTile,
    /// HZD's depth-equal quad overdraw: distinct triangles per 2x2 quad.
    QuadOverdraw,
    /// Local lights per 16x16 light tile, with the legend along the bottom.
    LightsPerTile,
    /// KZ2's path per local light: screen rectangles, green tiles / red volumes.
    LightPaths,
    /// The sun's depth slice each pixel falls in.
    Cascades,
    /// The G-buffer's motion vectors (move the camera to see them).
    Motion,
    /// The sun's shadow maps side by side.
    ShadowAtlas,
}

impl DebugView {
    /// Every view, in the order of the number keys (0 the image).
    pub const ALL: [DebugView; 9] = [
        DebugView::Image,
        DebugView::VisIds,
        DebugView::WavesPerTile,
        DebugView::QuadOverdraw,
        DebugView::LightsPerTile,
        DebugView::LightPaths,
        DebugView::Cascades,
        DebugView::Motion,
        DebugView::ShadowAtlas,
    ];

    /// The name the CLI and the overlay use.
    pub fn name(self) -> &'static str {
        match self {
            DebugView::Image => "image",
            DebugView::VisIds => "vis IDs",
            DebugView::WavesPerTile => "waves per tile",
            DebugView::QuadOverdraw => "quad overdraw",
            DebugView::LightsPerTile => "lights per tile",
            DebugView::LightPaths => "light paths",
            DebugView::Cascades => "cascades",
            DebugView::Motion => "motion vectors",
            DebugView::ShadowAtlas => "shadow atlas",
        }
    }

    /// Whether the view reads the vis buffer or the classification, which only the
    /// deferred path writes: the viewer renders such frames on the deferred path.
    pub fn needs_deferred(self) -> bool {
        matches!(
            self,
            DebugView::VisIds | DebugView::WavesPerTile | DebugView::QuadOverdraw
        )
    }

    /// The next view (`step` 1) or the previous (`step` -1), wrapping.
    pub fn cycle(self, step: i32) -> DebugView {
        let n = Self::ALL.len() as i32;
        let i = Self::ALL.iter().position(|&v| v == self).unwrap_or(0) as i32;
        Self::ALL[(i + step).rem_euclid(n) as usize]
    }

    /// The path a frame shown in this view renders: `path`, or the deferred path for the
    /// views that read its buffers.
    pub fn frame_path(self, path: RenderPath) -> RenderPath {
        if self.needs_deferred() {
            RenderPath::Deferred
        } else {
            path
        }
    }
}

/// The image of `view` for the frame `frame` just rendered by `renderer` on `scene`, with
/// a caption (its scale), or `None` for [`DebugView::Image`] (the output texture is shown
/// as it is).
///
/// # Errors
/// A read-back failed, or the view has nothing to show (the cascades and the shadow atlas
/// with the sun's shadows off).
pub fn debug_image(
    view: DebugView,
    renderer: &Renderer,
    scene: &PreparedScene,
    frame: &FrameInput,
) -> Result<Option<(Rgba8Image, String)>> {
    let config = renderer.config();
    let (w, h) = (config.image.width, config.image.height);
    let out = match view {
        DebugView::Image => return Ok(None),
        DebugView::VisIds => (
            gpu::inspect::debug::vis_ids(w, h, &renderer.inspect().read_vis()?),
            "one colour per triangle and instance; sky yellow".to_string(),
        ),
        DebugView::WavesPerTile => {
            let c = renderer.inspect().read_classification(scene)?;
            let (img, max) = gpu::inspect::debug::wave_heatmap(w, h, &c);
            (
                img,
                format!("wave commands per 128x128 tile (white: {max})"),
            )
        }
        DebugView::QuadOverdraw => {
            let (img, mean) =
                gpu::inspect::debug::quad_overdraw(w, h, &renderer.inspect().read_vis()?);
            (
                img,
                format!("triangles per 2x2 quad, blue 1 .. red 4 (mean {mean:.2})"),
            )
        }
        DebugView::LightsPerTile => {
            let tiles = renderer.inspect().read_light_tiles()?;
            let (img, max) = gpu::inspect::debug::lights_per_tile(w, h, &tiles, 0);
            (
                img,
                format!("lights per 16x16 tile (0 black .. {max} white)"),
            )
        }
        DebugView::LightPaths => {
            let (img, [culled, bounds, volume]) =
                gpu::inspect::debug::light_paths(&renderer.read_output()?, frame);
            (
                img,
                format!("{bounds} depth-bounds (green), {volume} volume (red), {culled} culled"),
            )
        }
        DebugView::Cascades => {
            let Some(cascades) = renderer.inspect().shadow_cascades() else {
                bail!("the cascades view needs the sun's shadows (O switches them on)");
            };
            let splits: Vec<f64> = cascades.cascades().iter().map(|c| c.split[1]).collect();
            let img = gpu::inspect::debug::cascade_index(
                w,
                h,
                &renderer.inspect().read_depth()?,
                frame.camera.near,
                &splits,
            );
            let ends: Vec<String> = splits.iter().map(|d| format!("{d:.1}")).collect();
            (
                img,
                format!(
                    "slices red, green, blue, yellow; end at {} m",
                    ends.join(" / ")
                ),
            )
        }
        DebugView::Motion => {
            let (img, scale) =
                gpu::inspect::debug::motion_vectors(w, h, &renderer.inspect().read_gbuffer()?, 0.0);
            (
                img,
                format!("hue: direction; full brightness at {scale:.1} px"),
            )
        }
        DebugView::ShadowAtlas => {
            let Some(shadows) = config.lighting.shadows else {
                bail!("the shadow atlas needs the sun's shadows (O switches them on)");
            };
            let maps = renderer.inspect().read_shadow_maps()?;
            let step = shadows.resolution.div_ceil(512);
            (
                gpu::inspect::debug::shadow_atlas(&maps, shadows.resolution, step),
                format!("sun shadow maps, nearest slice first (1 in {step} texels)"),
            )
        }
    };
    Ok(Some(out))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn views_cycle_through_all() {
        let mut v = DebugView::Image;
        for _ in 0..DebugView::ALL.len() {
            v = v.cycle(1);
        }
        assert_eq!(v, DebugView::Image);
        assert_eq!(DebugView::Image.cycle(-1), DebugView::ShadowAtlas);
        assert_eq!(
            DebugView::QuadOverdraw.frame_path(RenderPath::Baseline),
            RenderPath::Deferred
        );
        assert_eq!(
            DebugView::Motion.frame_path(RenderPath::Baseline),
            RenderPath::Baseline
        );
    }
}
