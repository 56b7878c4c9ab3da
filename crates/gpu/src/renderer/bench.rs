//! Timing loops: frames rendered after a warm-up and their GPU times averaged (what
//! `render` and the benchmarks print).

use super::*;

/// Wall time [`Renderer::render_frames`] renders before it starts measuring.
pub const WARM_UP: Duration = Duration::from_millis(500);

impl Renderer {
    /// Renders `path` for at least [`WARM_UP`] of wall time (at least one frame) to bring the
    /// GPU's clocks up, then `frames` more, and returns the mean timings of those `frames`.
    /// Without the warm-up, a GPU that idled while the CPU worked (a read-back, the CPU
    /// twin) measures its first frames at idle clocks: on the H100 the SM clock falls to
    /// 345 MHz within ~0.5 s of idling and the next frames ran up to 2x slower.
    ///
    /// # Errors
    /// `frames` is 0, or as [`Renderer::render`].
    pub fn render_frames(
        &mut self,
        scene: &PreparedScene,
        frame: &FrameInput,
        path: RenderPath,
        frames: u32,
    ) -> Result<FrameOutput> {
        self.measure(frames, |r| r.render(scene, frame, path))
    }

    /// [`Renderer::render_static`] measured as [`Renderer::render_frames`] measures
    /// [`Renderer::render`]; the static statistics are the last frame's.
    ///
    /// # Errors
    /// `frames` is 0, or as [`Renderer::render_static`].
    pub fn render_static_frames(
        &mut self,
        scene: &PreparedScene,
        frame: &FrameInput,
        path: RenderPath,
        statics: &mut StaticView<'_>,
        frames: u32,
    ) -> Result<FrameOutput> {
        self.measure(frames, |r| r.render_static(scene, frame, path, statics))
    }

    /// [`Renderer::render_static_frames`] with a moving view: frame `i` (counting the
    /// warm-up frames from 0) is `sequence(i)`'s frame input and static view, so occlusion
    /// and LOD fade see motion. The static statistics are the last frame's.
    ///
    /// # Errors
    /// `frames` is 0, or as [`Renderer::render_static`].
    pub fn render_static_sequence(
        &mut self,
        scene: &PreparedScene,
        path: RenderPath,
        statics: &mut StaticView<'_>,
        frames: u32,
        mut sequence: impl FnMut(u32) -> (FrameInput, staticscene::ViewDesc),
    ) -> Result<FrameOutput> {
        let mut i = 0;
        self.measure(frames, |r| {
            let (frame, view) = sequence(i);
            i += 1;
            statics.view = view;
            r.render_static(scene, &frame, path, statics)
        })
    }

    /// Renders for [`WARM_UP`] (and on until [`Laydown::Auto`]'s trial has chosen, where
    /// these frames advance it), then `frames` more (at least one), and averages those.
    pub(super) fn measure(
        &mut self,
        frames: u32,
        mut render: impl FnMut(&mut Self) -> Result<FrameOutput>,
    ) -> Result<FrameOutput> {
        if frames == 0 {
            return Err(Error::Length {
                what: "frames to measure",
                got: 0,
                expected: 1,
            });
        }
        let start = Instant::now();
        loop {
            let out = render(self)?;
            // Measured frames all take the laydown Auto chose.
            let trial = matches!(self.laydown_choice().reason, LaydownReason::Trial { .. })
                && out.laydown.is_some()
                && out.statics.is_none();
            if start.elapsed() >= WARM_UP && !trial {
                break;
            }
        }
        let mut all = Vec::new();
        for _ in 0..frames {
            all.push(render(self)?);
        }
        let n = all.len() as f64;
        let mut gpu: Vec<Timing> = Vec::new();
        for f in &all {
            for t in &f.gpu {
                match gpu.iter_mut().find(|g| g.label == t.label) {
                    Some(g) => g.ms += t.ms / n,
                    None => gpu.push(Timing {
                        label: t.label,
                        ms: t.ms / n,
                        passes: t.passes,
                    }),
                }
            }
        }
        let wall_ms = all.iter().map(|f| f.wall_ms).sum::<f64>() / n;
        Ok(FrameOutput {
            gpu,
            wall_ms,
            statics: all.last().and_then(|f| f.statics.clone()),
            untimed_passes: all.iter().map(|f| f.untimed_passes).max().unwrap_or(0),
            laydown: all.last().and_then(|f| f.laydown),
        })
    }
}
