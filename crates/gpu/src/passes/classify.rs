//! GPU classification of the laid-down vis buffer: `tiling`'s three phases (seed 000:
//! laydown finalise, mid classify, classify output) run from their descriptions in
//! `tiling::wgsl`, after a zero fill of the buffers they expect zeroed (`gpu::zero`, one
//! dispatch), over buffers sized for the worst case of a frame. After the compute laydown
//! the zero fill runs in the raster's pass and laydown finalise in the laydown's unpack
//! (`tiling::finalize`), so the classification starts at mid classify.
//!
//! Buffer sizes, per prepared scene, for a `width x height` image, `T` 128x128 tiles, `P`
//! passes and `G` batch groups over all passes: masks and counter offsets `T * P` words;
//! counters at most `T * G` (a counter is a (tile, pass, group) triple with pixels);
//! pixel commands at most `width * height` (two per word); wave commands at most
//! `counters + width * height / wave width`. Nothing is sized from a CPU classification.

use shader::pipeline::ComputePass;
use shader::{Binding, Entry, Group, Kind, Pass};
use tiling::{ClassifyConfig, PassDispatch, PixelStats, TilingParams, Totals, WaveCommand};

use super::context::FrameContext;
use crate::error::{Error, Result};
use crate::resources::buffers::{buffer_init, storage_buffer};
pub(crate) use crate::resources::groups::ClassifyBuffers as Buffers;
use crate::resources::groups::{Sizes, words_of};
use crate::shaders::LIBRARY;
use crate::timing::GpuTimer;

/// Zeroes one buffer, one word per invocation (`gpu::zero`), over its word count; with the
/// `override` `ZERO_FILL` set, fills it with that word.
pub(crate) const ZERO: Pass<u32> = Pass {
    name: "classify 0: zero buffers",
    module: "gpu::zero",
    library: LIBRARY,
    features: &[],
    groups: &[Group {
        name: "words",
        bindings: &[Binding::new("words", Kind::read_write(4))],
    }],
    entries: &[Entry::items("zero", 256, |words| *words)],
    zeroed: &[],
};

/// Words each invocation of [`ZERO_MANY`] zeroes (WGSL `ZERO_MANY_WORDS`).
const ZERO_MANY_WORDS: u32 = 4;

/// Buffers [`ZERO_MANY`] zeroes in one dispatch (bind a one-word buffer to those left over):
/// its description's bindings.
pub(crate) const ZERO_BINDINGS: usize = ZERO_MANY.groups[0].bindings.len();

/// [`ZERO`] over [`ZERO_BINDINGS`] buffers in one dispatch (feature `many`), over the sum of
/// their word counts: the classification's zeroed buffers.
pub(crate) const ZERO_MANY: Pass<u32> = Pass {
    name: "classify 0: zero buffers",
    features: &["many"],
    groups: &[Group {
        name: "words",
        bindings: &[
            Binding::new("words0", Kind::read_write(4)),
            Binding::new("words1", Kind::read_write(4)),
            Binding::new("words2", Kind::read_write(4)),
            Binding::new("words3", Kind::read_write(4)),
            Binding::new("words4", Kind::read_write(4)),
            Binding::new("words5", Kind::read_write(4)),
            Binding::new("words6", Kind::read_write(4)),
            Binding::new("words7", Kind::read_write(4)),
            Binding::new("words8", Kind::read_write(4)),
            Binding::new("words9", Kind::read_write(4)),
        ],
    }],
    entries: &[Entry::items("zero", 256, |words| {
        words.div_ceil(ZERO_MANY_WORDS)
    })],
    ..ZERO
};

/// A timing experiment on the classification (`examples/classify_variants.rs`): `tiling`'s
/// timing features to compose with (`timing_omit_stats`, ...; each phase takes those it
/// declares), `override`s to set (`TILING_HIST_LIMIT`), and entry points not to dispatch.
/// Variants that drop work give wrong commands; only their times mean anything.
#[doc(hidden)]
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ClassificationVariant {
    /// Features of the classification modules besides `subgroups`.
    pub features: Vec<&'static str>,
    /// `override` values of the classification modules.
    pub overrides: Vec<(&'static str, f64)>,
    /// Entry points recorded not at all (their outputs keep the last frame's values).
    pub skip: Vec<&'static str>,
}

/// The classification's pipelines.
pub(crate) struct Classify {
    zero: ComputePass<u32>,
    /// `gpu::zero` writing all ones: the mixed frame's validity bitmask, every pixel valid
    /// until the regular geometry pass clears its bit.
    fill: ComputePass<u32>,
    phases: Vec<ComputePass<TilingParams>>,
    /// Mid classify without the vertex-cull code (`TILING_VERTEX_CULL_CODE` false), for
    /// frames without `FLAG_VERTEX_CULL`: the code's registers alone slow count_pixels.
    mid_without_cull: Option<ComputePass<TilingParams>>,
    features: &'static [&'static str],
    skip: Vec<&'static str>,
}

impl Classify {
    /// Creates the pipelines; `subgroups` picks `wave`'s subgroup appends (the device must
    /// have `Features::SUBGROUP`) over the workgroup fallback.
    pub(crate) fn new(device: &wgpu::Device, subgroups: bool) -> Result<Self> {
        let features: &'static [&'static str] = if subgroups { &["subgroups"] } else { &[] };
        let mut c = Self {
            zero: ComputePass::new(device, &ZERO_MANY, &["many"], &[])?,
            fill: ComputePass::new(device, &ZERO, &[], &[("ZERO_FILL", f64::from(u32::MAX))])?,
            phases: Vec::new(),
            mid_without_cull: None,
            features,
            skip: Vec::new(),
        };
        c.set_variant(device, &ClassificationVariant::default())?;
        Ok(c)
    }

    /// Rebuilds the phases with `variant`'s overrides and skipped entry points (the
    /// layouts, and so every prepared scene's bind groups, stay).
    pub(crate) fn set_variant(
        &mut self,
        device: &wgpu::Device,
        variant: &ClassificationVariant,
    ) -> Result<()> {
        // Each phase takes the features and overrides its module declares.
        let build = |pass: &'static Pass<TilingParams>, extra: &[(&'static str, f64)]| {
            let wanted: Vec<&str> = self
                .features
                .iter()
                .chain(&variant.features)
                .copied()
                .collect();
            let features: Vec<&str> = wanted
                .into_iter()
                .filter(|f| pass.features.contains(f))
                .collect();
            let src = pass.source(&features)?;
            let constants: Vec<(&str, f64)> = variant
                .overrides
                .iter()
                .chain(extra)
                .copied()
                .filter(|(name, _)| src.contains(&format!("override {name}")))
                .collect();
            ComputePass::new(device, pass, &features, &constants)
        };
        self.phases = tiling::wgsl::CLASSIFICATION
            .iter()
            .map(|pass| build(pass, &[]))
            .collect::<Result<_, shader::Error>>()?;
        self.mid_without_cull = Some(build(
            &tiling::wgsl::MID_CLASSIFY,
            &[("TILING_VERTEX_CULL_CODE", 0.0)],
        )?);
        self.skip.clone_from(&variant.skip);
        Ok(())
    }

    /// Records the zero fill and the three phases, each a timed pass.
    pub(crate) fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
    ) {
        self.record_zero(encoder, f, timer);
        self.record_mid(encoder, f, timer, false);
        self.record_output(encoder, f, timer);
    }

    /// Records the zero fill of every buffer the phases expect zeroed (and, in the mixed
    /// frame, the validity bitmask's fill with ones: seed 000's laydown finalize writing
    /// the stencil bit) as a timed pass of its own.
    pub(crate) fn record_zero(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
    ) {
        let mut pass = timer.begin_compute(encoder, ZERO.name);
        self.record_zero_in(&mut pass, f);
    }

    /// [`record_zero`](Self::record_zero)'s dispatches in `pass`: the compute laydown
    /// records them after the large triangles' dispatch in its pass, whose work they
    /// share no buffer with, so they run on the SMs its last workgroups leave idle (they
    /// must precede its unpack, which finalises the laydown into the zeroed masks).
    pub(crate) fn record_zero_in(&self, pass: &mut wgpu::ComputePass<'_>, f: &FrameContext<'_>) {
        let b = &f.scene.classification;
        if let Some((group, words)) = &b.zero_group {
            self.zero.record(pass, &[group], words);
        }
        if let Some((group, words)) = &b.fill_group {
            self.fill.record(pass, &[group], words);
        }
    }

    /// Records laydown finalize (unless `finalized`: the compute laydown's unpack did it)
    /// and mid classify, after [`record_zero`](Self::record_zero): what the talk runs
    /// before (and beside) its geometry pass. Mid classify reads the validity before the
    /// regular geometry pass clears any bit, so its counts and offsets may only
    /// overestimate (the talk's "conservative").
    pub(crate) fn record_mid(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
        finalized: bool,
    ) {
        self.record_phases(encoder, f, timer, usize::from(finalized)..2);
    }

    /// Records classify output: the pixel and wave commands from the final validity.
    pub(crate) fn record_output(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
    ) {
        self.record_phases(encoder, f, timer, 2..3);
    }

    /// Records the phases `range` of `tiling::wgsl::CLASSIFICATION`, each entry point a
    /// pass timed under its name (the phases' parts differ by an order of magnitude).
    fn record_phases(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
        range: std::ops::Range<usize>,
    ) {
        let b = &f.scene.classification;
        let cull = b.params.flags & tiling::classify::FLAG_VERTEX_CULL != 0;
        for (k, (phase, group)) in self
            .phases
            .iter()
            .zip(&b.groups)
            .enumerate()
            .take(range.end)
            .skip(range.start)
        {
            // Mid classify without the vertex-cull code where the frame culls no vertices.
            let phase = match &self.mid_without_cull {
                Some(mid) if k == 1 && !cull => mid,
                _ => phase,
            };
            for step in &phase.steps {
                if self.skip.contains(&step.entry.name) {
                    continue;
                }
                if let Some([x, y, z]) = phase.workgroups(step, &b.params)
                    && x != 0
                    && y != 0
                    && z != 0
                {
                    let mut pass =
                        timer.begin_compute_as(encoder, phase.pass.name, step.entry.name);
                    pass.set_bind_group(0, group, &[]);
                    pass.set_pipeline(&step.pipeline);
                    pass.dispatch_workgroups(x, y, z);
                }
            }
        }
    }
}

impl Buffers {
    /// The vis words' layout the phases decode (VRS: quad commands).
    pub(crate) fn layout(&self) -> visbuf::VisLayout {
        if self.params.flags & tiling::classify::FLAG_VRS != 0 {
            visbuf::VisLayout::Vrs
        } else {
            visbuf::VisLayout::Standard
        }
    }

    /// The MicroBatchInfoTable the phases read (indexed by micro-batch ID).
    pub(crate) fn table(&self) -> &wgpu::Buffer {
        &self._kept[2]
    }

    /// The buffers and bind groups of one prepared scene: `plan`'s table and order
    /// buffer, classified at `sizes` with `config`, reading `vis_words` and `indices`;
    /// with `validity` (the mixed frame), a validity bitmask of `ceil(width * height / 32)`
    /// words that the classification applies (`tiling::FLAG_VALIDITY`), filled with ones
    /// before each frame's laydown finalize.
    pub(crate) fn new(
        c: &Classify,
        device: &wgpu::Device,
        plan: &tiling::Plan,
        (sizes, config): (Sizes, ClassifyConfig),
        vis_words: &wgpu::Buffer,
        indices: &wgpu::Buffer,
        validity: bool,
    ) -> Result<Self> {
        let table = &plan.table;
        let micro_batch_count = plan.order.len() as u32;
        let s = sizes;
        // The validity bitmask applies (the mixed frame); the plan's word layout (with VRS
        // the commands are quad commands); the config's vertex culling.
        let params = TilingParams::for_frame(
            (s.width, s.height),
            plan.layout,
            validity,
            &config,
            table.len() as u32,
            micro_batch_count,
        );
        let zeroed = |label: &str, words: u32, extra: wgpu::BufferUsages| {
            storage_buffer(device, label, u64::from(words) * 4, extra)
        };
        let none = wgpu::BufferUsages::empty();
        let tp = s.tiles * s.passes;
        let params_buffer = buffer_init(
            device,
            "tiling params",
            bytemuck::bytes_of(&params),
            0,
            wgpu::BufferUsages::UNIFORM,
        );
        let valid = if validity {
            zeroed(
                "validity bitmask (the talk's stencil bit)",
                (s.width * s.height).div_ceil(32),
                none,
            )?
        } else {
            zeroed("validity (unused: no stencil bit)", 1, none)?
        };
        let table_buffer = buffer_init(
            device,
            "MicroBatchInfoTable",
            bytemuck::cast_slice(table),
            size_of::<tiling::MicroBatchInfo>() as u64,
            wgpu::BufferUsages::STORAGE,
        );
        let b = Buffers {
            masks: zeroed("batch-group masks", tp, none)?,
            counter_offsets: zeroed("counter offsets", tp, none)?,
            counts: zeroed("counts", s.max_counters, none)?,
            pixel_offsets: zeroed("pixel offsets", s.max_counters, none)?,
            vertex_cull: zeroed("vertex cull", s.chunk_count.div_ceil(4), none)?,
            totals: zeroed("totals", words_of::<Totals>(1), none)?,
            stats_mid: zeroed("mid stats", words_of::<PixelStats>(1), none)?,
            final_counts: zeroed("final counts", s.max_counters, none)?,
            commands: zeroed("pixel commands", s.max_commands.div_ceil(2), none)?,
            wave_offsets: zeroed("wave offsets", s.max_counters, none)?,
            waves: zeroed("wave commands", words_of::<WaveCommand>(s.max_waves), none)?,
            pass_dispatch: zeroed(
                "pass dispatches",
                words_of::<PassDispatch>(s.passes),
                wgpu::BufferUsages::INDIRECT,
            )?,
            stats_out: zeroed("output stats", words_of::<PixelStats>(1), none)?,
            wave_scratch: zeroed(
                "wave sums",
                tiling::wgsl::wave_scratch_words(s.tiles, s.passes),
                none,
            )?,
            offset_scratch: zeroed(
                "counter sums",
                tiling::wgsl::offset_scratch_words(s.tiles, s.passes),
                none,
            )?,
            slots: zeroed(
                "pixel records",
                4 * tiling::wgsl::record_quads(s.width, s.height),
                none,
            )?,
            sizes,
            config,
            params,
            _kept: [params_buffer, valid, table_buffer],
            zero_group: None,
            _spare: Vec::new(),
            fill_group: None,
            groups: Vec::new(),
        };
        // Every phase's bindings by name: the buffers are shared, `stats` is each pixel
        // phase's own.
        let resource = |phase: usize, name: &str| -> Option<&wgpu::Buffer> {
            Some(match name {
                "params" => &b._kept[0],
                "vis" => vis_words,
                "valid" => &b._kept[1],
                "table" => &b._kept[2],
                "masks" => &b.masks,
                "counter_offsets" => &b.counter_offsets,
                "counts" => &b.counts,
                "pixel_offsets" => &b.pixel_offsets,
                "vertex_cull" => &b.vertex_cull,
                "indices" => indices,
                "totals" => &b.totals,
                "stats" if phase == 1 => &b.stats_mid,
                "stats" => &b.stats_out,
                "final_counts" => &b.final_counts,
                "commands" => &b.commands,
                "wave_offsets" => &b.wave_offsets,
                "waves" => &b.waves,
                "passes" => &b.pass_dispatch,
                "wave_scratch" => &b.wave_scratch,
                "slots" => &b.slots,
                "mid_stats" => &b.stats_mid,
                "offset_scratch" => &b.offset_scratch,
                _ => return None,
            })
        };
        let mut groups = Vec::new();
        let mut zeroed_names: Vec<(usize, &str)> = Vec::new();
        for (k, (phase, compute)) in tiling::wgsl::CLASSIFICATION
            .iter()
            .zip(&c.phases)
            .enumerate()
        {
            let mut resources = Vec::new();
            for binding in phase.groups[0].bindings {
                let buffer = resource(k, binding.name).ok_or(Error::Shader(
                    shader::Error::MissingResource {
                        pass: phase.name,
                        group: phase.groups[0].name,
                        binding: binding.name,
                    },
                ))?;
                resources.push((binding.name, buffer.as_entire_binding()));
            }
            groups.push(compute.bind_group(device, phase.groups[0].name, &resources)?);
            zeroed_names.extend(phase.zeroed.iter().map(|&n| (k, n)));
        }
        assert!(
            zeroed_names.len() <= ZERO_BINDINGS,
            "ZERO_MANY binds every zeroed buffer"
        );
        let spare = (zeroed_names.len()..ZERO_BINDINGS)
            .map(|_| zeroed("zero fill's spare binding", 1, none))
            .collect::<Result<Vec<_>>>()?;
        let mut zero_words = 0u32;
        let mut zero_resources = Vec::new();
        for (k, binding) in ZERO_MANY.groups[0].bindings.iter().enumerate() {
            let buffer = match zeroed_names.get(k) {
                Some(&(phase, name)) => resource(phase, name)
                    .expect("zeroed buffers are bindings (checked by tiling's tests)"),
                None => &spare[k - zeroed_names.len()],
            };
            zero_words += (buffer.size() / 4) as u32;
            zero_resources.push((binding.name, buffer.as_entire_binding()));
        }
        let zero_group = Some((
            c.zero.bind_group(device, "words", &zero_resources)?,
            zero_words,
        ));
        let fill_group = if validity {
            let buffer = &b._kept[1];
            let group =
                c.fill
                    .bind_group(device, "words", &[("words", buffer.as_entire_binding())])?;
            Some((group, (buffer.size() / 4) as u32))
        } else {
            None
        };
        Ok(Buffers {
            zero_group,
            _spare: spare,
            fill_group,
            groups,
            ..b
        })
    }

    /// The resources of a `tiling::finalize` group (the compute laydown's unpack, which
    /// writes the vis words `vis_words` and finalises the laydown over them): params,
    /// `vis_words`, validity, table, masks.
    pub(crate) fn finalize_resources<'a>(
        &'a self,
        vis_words: &'a wgpu::Buffer,
    ) -> [(&'static str, wgpu::BindingResource<'a>); 5] {
        [
            ("params", self._kept[0].as_entire_binding()),
            ("vis_words", vis_words.as_entire_binding()),
            ("valid", self._kept[1].as_entire_binding()),
            ("table", self._kept[2].as_entire_binding()),
            ("masks", self.masks.as_entire_binding()),
        ]
    }

    /// The validity bitmask (one word, unused, outside the mixed frame).
    pub(crate) fn validity(&self) -> &wgpu::Buffer {
        &self._kept[1]
    }

    /// Whether the classification applies the validity bitmask (the mixed frame).
    pub(crate) fn has_validity(&self) -> bool {
        self.fill_group.is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_description_matches_its_module() {
        shadercheck::check_pass(&ZERO, |_| shadercheck::Caps::CORE);
        let many = shadercheck::check_pass_with(&ZERO_MANY, &["many"], |_| shadercheck::Caps::CORE);
        // Buffers::new binds every zeroed buffer of the phases to ZERO_MANY.
        let zeroed: usize = tiling::wgsl::CLASSIFICATION
            .iter()
            .map(|p| p.zeroed.len())
            .sum();
        assert!(zeroed <= ZERO_BINDINGS, "{zeroed} zeroed buffers");
        assert_eq!(
            shadercheck::const_u32(&many[0], "ZERO_MANY_WORDS"),
            Some(ZERO_MANY_WORDS)
        );
    }

    #[test]
    fn pod_rows_in_words() {
        assert_eq!(words_of::<PassDispatch>(3), 18);
        assert_eq!(words_of::<WaveCommand>(5), 20);
        assert_eq!(words_of::<PixelStats>(1), 8);
        assert_eq!(words_of::<Totals>(1), 4);
    }
}
