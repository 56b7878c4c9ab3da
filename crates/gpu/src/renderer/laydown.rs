//! Which laydown a deferred frame takes: the one asked for, the hardware one where the
//! compute one cannot run, or [`Laydown::Auto`]'s trial and its verdict.

use super::*;

/// [`Laydown::Auto`]'s state: the frames timed so far, then the verdict.
#[derive(Clone, Debug, Default)]
pub(super) struct AutoLaydown {
    /// Frames of the trial recorded so far (warm-ups included).
    frames: usize,
    /// Frame times (ms) per laydown: hardware, compute.
    samples: [Vec<f64>; 2],
    /// Whether every sample was a GPU time.
    gpu_timed: bool,
    /// The verdict: (laydown, hardware median, compute median).
    chosen: Option<(Laydown, f64, f64)>,
}

/// Frames of the whole trial: a warm-up and the timed frames of each laydown.
const TRIAL_FRAMES: usize = 2 * (1 + AUTO_LAYDOWN_FRAMES);

fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    s.get(s.len() / 2).copied().unwrap_or(f64::INFINITY)
}

impl AutoLaydown {
    /// Whether the trial still runs.
    pub(super) fn trial(&self) -> bool {
        self.chosen.is_none()
    }

    /// The laydown the next deferred frame takes: the trial alternates, hardware first.
    pub(super) fn next(&self) -> Laydown {
        match self.chosen {
            Some((l, _, _)) => l,
            None if self.frames.is_multiple_of(2) => Laydown::Hardware,
            None => Laydown::Compute,
        }
    }

    /// Records a trial frame that ran `laydown` in `ms` (`gpu`: timestamps).
    pub(super) fn record(&mut self, laydown: Laydown, ms: f64, gpu: bool) {
        if self.chosen.is_some() || laydown != self.next() {
            return;
        }
        if self.frames >= 2 {
            if self.samples.iter().all(Vec::is_empty) {
                self.gpu_timed = gpu;
            }
            self.gpu_timed &= gpu;
            self.samples[usize::from(laydown == Laydown::Compute)].push(ms);
        }
        self.frames += 1;
        if self.frames >= TRIAL_FRAMES {
            let (h, c) = (median(&self.samples[0]), median(&self.samples[1]));
            let l = if c < h {
                Laydown::Compute
            } else {
                Laydown::Hardware
            };
            self.chosen = Some((l, h, c));
        }
    }

    fn reason(&self) -> LaydownReason {
        match self.chosen {
            Some((_, hardware_ms, compute_ms)) => LaydownReason::Measured {
                hardware_ms,
                compute_ms,
                gpu_timed: self.gpu_timed,
            },
            None => LaydownReason::Trial {
                frames_left: (TRIAL_FRAMES - self.frames) as u32,
            },
        }
    }
}

impl Renderer {
    /// Which laydown the deferred frames without a static query take, and why (frames
    /// with a static query take the hardware laydown: [`FrameOutput::laydown`] says what
    /// each frame ran).
    pub fn laydown_choice(&self) -> LaydownChoice {
        let can = self.pipelines.compute_laydown.is_some();
        let (laydown, reason) = match (self.config.geometry.laydown, can) {
            (Laydown::Hardware, _) => (Laydown::Hardware, LaydownReason::Asked),
            (_, false) => (Laydown::Hardware, LaydownReason::NoComputeFeatures),
            (Laydown::Compute, true) => (Laydown::Compute, LaydownReason::Asked),
            (Laydown::Auto, true) => (self.auto.next(), self.auto.reason()),
        };
        LaydownChoice { laydown, reason }
    }

    /// Whether a frame recording `what` (with a static query or not) asks for the compute
    /// laydown.
    pub(super) fn compute_laydown_for(&self, what: Recording, static_query: bool) -> bool {
        what.lays_down() && !static_query && self.laydown_choice().laydown == Laydown::Compute
    }

    /// Whether this frame is one of [`Laydown::Auto`]'s trial frames (it is then waited for
    /// and timed).
    pub(super) fn auto_trial_frame(&self, what: Recording, static_query: bool) -> bool {
        self.config.geometry.laydown == Laydown::Auto
            && self.pipelines.compute_laydown.is_some()
            && self.auto.trial()
            && !static_query
            && matches!(what, Recording::Deferred | Recording::DeferredFullScreen)
    }
}
