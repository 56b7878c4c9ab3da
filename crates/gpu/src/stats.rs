//! Statistics of a deferred frame: what the GPU classification wrote, read back and
//! compared with `tiling`'s CPU twin, and the talk's tables measured on the same vis buffer
//! (`tiling::measure`).

use tiling::{Classification, PassDispatch, PixelStats, Totals, WaveCommand, canonical_sort};

use crate::error::{Error, Result, SceneError};
use crate::resources::PreparedScene;
use crate::resources::groups::ClassifyBuffers;
use crate::resources::readback::read_buffer;

/// Counters of one frame's classification, as in seed 000's closing tables.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ClassificationStats {
    /// Pixels with vis-buffer geometry.
    pub vis_pixels: u64,
    /// Passes used.
    pub passes: u32,
    /// Batch groups over all passes.
    pub batch_groups: u32,
    /// (tile, pass, group) triples with pixels.
    pub tile_groups: u64,
    /// Pixel commands written.
    pub pixel_commands: u64,
    /// Wave commands written.
    pub wave_commands: u64,
    /// The wave width the commands were built for.
    pub wave_width: u32,
    /// Lanes of those waves with no pixel (rounding each (tile, pass, group) up to waves).
    pub unfilled_lanes: u64,
    /// Pixel-shading waves HZD's depth-equal pass would launch (distinct 2x2 quad ×
    /// primitive pairs × 4 lanes, rounded up to waves per draw).
    pub depth_equal_waves: u64,
    /// Vertices of all instances in the scene.
    pub scene_vertices: u64,
    /// Vertices in 64-vertex chunks that a visible primitive uses.
    pub vertices_after_chunk_culling: u64,
    /// Bytes of command buffers (pixel + wave commands + dispatch arguments).
    pub command_bytes: u64,
    /// Whether the GPU classification matched the CPU twin on this frame.
    pub gpu_matches_cpu: Option<bool>,
}

/// Everything the GPU classification wrote for one frame, read back.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct GpuClassification {
    /// Phase 1: per (tile, pass), the batch groups used.
    pub masks: Vec<u32>,
    /// Phase 2: first counter of each (tile, pass).
    pub counter_offsets: Vec<u32>,
    /// Phase 2: pixels per counter.
    pub counts: Vec<u32>,
    /// Phase 2: first pixel command of each counter.
    pub pixel_offsets: Vec<u32>,
    /// Phase 2: the vertex cull buffer, one byte per 64-vertex chunk (padded to whole words).
    pub vertex_cull: Vec<u8>,
    /// Lengths the passes wrote.
    pub totals: Totals,
    /// Phase 2's pixel counters.
    pub mid_stats: PixelStats,
    /// Phase 3: commands written per counter.
    pub final_counts: Vec<u32>,
    /// Phase 3: pixel commands, canonically sorted within each counter.
    pub commands: Vec<u16>,
    /// Phase 3: first wave command of each counter.
    pub wave_offsets: Vec<u32>,
    /// Phase 3: the wave commands.
    pub waves: Vec<WaveCommand>,
    /// Phase 3: one indirect dispatch per pass.
    pub passes: Vec<PassDispatch>,
    /// Phase 3's pixel counters.
    pub output_stats: PixelStats,
    /// The vis words the passes read (row-major).
    pub vis: Vec<u32>,
    /// The mixed frame's validity bitmask as classify output read it (bit `i % 32` of
    /// word `i / 32` for pixel `i`; laydown finalize and mid classify saw every bit set);
    /// `None` outside the mixed frame.
    pub validity: Option<Vec<u32>>,
}

impl GpuClassification {
    /// Reads every output of the last classification back (waits for the GPU). Pixel
    /// commands are put in [`canonical_sort`] order, the only order the GPU's atomics
    /// leave undetermined.
    pub(crate) fn read(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        b: &ClassifyBuffers,
        vis_words: &wgpu::Buffer,
    ) -> Result<Self> {
        let words = |b: &wgpu::Buffer, n: u32| -> Result<Vec<u32>> {
            let bytes = read_buffer(device, queue, b, 0, u64::from(n) * 4)?;
            Ok(bytemuck::pod_collect_to_vec(&bytes))
        };
        let s = b.sizes;
        let tp = s.tiles * s.passes;
        let totals: Totals = bytemuck::pod_read_unaligned(&read_buffer(
            device,
            queue,
            &b.totals,
            0,
            size_of::<Totals>() as u64,
        )?);
        let counters = totals.counter_count.min(s.max_counters);
        let commands = totals.command_count.min(s.max_commands);
        let waves = totals.wave_count.min(s.max_waves);
        let pixel_offsets = words(&b.pixel_offsets, counters)?;
        let final_counts = words(&b.final_counts, counters)?;
        let mut cmds: Vec<u16> = words(&b.commands, commands.div_ceil(2))?
            .iter()
            .flat_map(|w| [*w as u16, (*w >> 16) as u16])
            .take(commands as usize)
            .collect();
        canonical_sort(&mut cmds, &pixel_offsets, &final_counts, b.layout());
        let cull_bytes = read_buffer(device, queue, &b.vertex_cull, 0, b.vertex_cull.size())?;
        let stats = |b: &wgpu::Buffer| -> Result<PixelStats> {
            Ok(bytemuck::pod_read_unaligned(&read_buffer(
                device,
                queue,
                b,
                0,
                size_of::<PixelStats>() as u64,
            )?))
        };
        Ok(GpuClassification {
            masks: words(&b.masks, tp)?,
            counter_offsets: words(&b.counter_offsets, tp)?,
            counts: words(&b.counts, counters)?,
            pixel_offsets,
            vertex_cull: cull_bytes[..s.chunk_count.next_multiple_of(4) as usize].to_vec(),
            totals,
            mid_stats: stats(&b.stats_mid)?,
            final_counts,
            commands: cmds,
            wave_offsets: words(&b.wave_offsets, counters)?,
            waves: bytemuck::pod_collect_to_vec(&read_buffer(
                device,
                queue,
                &b.waves,
                0,
                u64::from(waves) * size_of::<WaveCommand>() as u64,
            )?),
            passes: bytemuck::pod_collect_to_vec(&read_buffer(
                device,
                queue,
                &b.pass_dispatch,
                0,
                u64::from(s.passes) * size_of::<PassDispatch>() as u64,
            )?),
            output_stats: stats(&b.stats_out)?,
            vis: words(vis_words, s.width * s.height)?,
            validity: if b.has_validity() {
                Some(words(b.validity(), (s.width * s.height).div_ceil(32))?)
            } else {
                None
            },
        })
    }

    /// The first output that differs from the CPU twin's, by name, or `None` when all are
    /// equal (pixel commands compared after the canonical sort).
    pub fn mismatch(&self, cpu: &Classification) -> Option<String> {
        fn first<T: PartialEq + std::fmt::Debug>(name: &str, a: &[T], b: &[T]) -> Option<String> {
            if a.len() != b.len() {
                return Some(format!("{name}: GPU {} entries, CPU {}", a.len(), b.len()));
            }
            let i = a.iter().zip(b).position(|(x, y)| x != y)?;
            Some(format!("{name}[{i}]: GPU {:?}, CPU {:?}", a[i], b[i]))
        }
        first("masks", &self.masks, &cpu.masks)
            .or_else(|| {
                first(
                    "counter offsets",
                    &self.counter_offsets,
                    &cpu.mid.counter_offsets,
                )
            })
            .or_else(|| first("counts", &self.counts, &cpu.mid.counts))
            .or_else(|| first("pixel offsets", &self.pixel_offsets, &cpu.mid.pixel_offsets))
            .or_else(|| first("vertex cull", &self.vertex_cull, &cpu.mid.vertex_cull))
            .or_else(|| first("mid stats", &[self.mid_stats], &[cpu.mid.stats]))
            .or_else(|| first("final counts", &self.final_counts, &cpu.output.final_counts))
            .or_else(|| first("pixel commands", &self.commands, &cpu.output.commands))
            .or_else(|| first("wave offsets", &self.wave_offsets, &cpu.output.wave_offsets))
            .or_else(|| first("wave commands", &self.waves, &cpu.output.waves))
            .or_else(|| first("pass dispatches", &self.passes, &cpu.output.passes))
            .or_else(|| first("output stats", &[self.output_stats], &[cpu.output.stats]))
    }
}

/// The talk's counters for a read-back classification: runs `tiling`'s CPU twin
/// (`classify_phases`) on the same vis words, compares every output, and measures
/// depth-equal waves and chunk-culled vertices with `tiling::measure`. Returns the counters
/// and the first output that differs from the twin, if any.
pub(crate) fn classification_statistics(
    scene: &PreparedScene,
    gpu: &GpuClassification,
) -> Result<(ClassificationStats, Option<String>)> {
    let b = &scene.classification;
    let s = b.sizes;
    let t = &scene.tiling;
    let err = |e: tiling::Error| Error::Scene(SceneError::Tiling(e.to_string()));
    let vis = tiling::VisBuffer::new(&gpu.vis, s.width, s.height, b.layout()).map_err(err)?;
    let config = b.config;
    // The talk's chunk-culled vertices also where the frame marks no chunks (no ring),
    // marked as mid classify would (every validity bit set).
    let culled = if config.vertex_cull {
        None
    } else {
        let marking = tiling::ClassifyConfig {
            vertex_cull: true,
            ..config
        };
        Some(tiling::classify(&vis, &t.table, &scene.geometry.indices, &marking).map_err(err)?)
    };
    let (cpu, vis) = match &gpu.validity {
        None => (
            tiling::classify_phases(&vis, &t.table, &scene.geometry.indices, &config)
                .map_err(err)?,
            vis,
        ),
        // The mixed frame: laydown finalize and mid classify ran with every validity bit
        // set (before the regular geometry pass), classify output with the final mask.
        Some(mask) => {
            let (masks, _) = tiling::laydown_finalize(&vis, &t.table, &config).map_err(err)?;
            let mid =
                tiling::mid_classify(&vis, &t.table, &scene.geometry.indices, &config, &masks)
                    .map_err(err)?;
            let fin = vis.with_validity(mask).map_err(err)?;
            let output =
                tiling::classify_output(&fin, &t.table, &config, &masks, &mid).map_err(err)?;
            (Classification { masks, mid, output }, fin)
        }
    };
    let mismatch = gpu.mismatch(&cpu);
    let vertex = tiling::vertex_wave_commands(
        &culled.as_ref().unwrap_or(&cpu).mid.vertex_cull,
        t.chunk_count,
        &t.table,
        &t.order,
        &t.passes,
    )
    .map_err(err)?;
    let m = tiling::measure(&vis, &t.table, &config, &cpu, &vertex).map_err(err)?;
    let stats = ClassificationStats {
        vis_pixels: u64::from(gpu.output_stats.valid),
        passes: t.passes.len() as u32,
        batch_groups: t.pass_groups.iter().map(Vec::len).sum::<usize>() as u32,
        tile_groups: u64::from(gpu.totals.counter_count),
        pixel_commands: u64::from(gpu.totals.command_count),
        wave_commands: u64::from(gpu.totals.wave_count),
        wave_width: config.wave_width.lanes(),
        unfilled_lanes: (u64::from(gpu.totals.wave_count) * u64::from(config.wave_width.lanes()))
            .saturating_sub(u64::from(gpu.totals.command_count)),
        depth_equal_waves: m.depth_equal_waves,
        scene_vertices: m.scene_vertices,
        vertices_after_chunk_culling: m.visible_vertices,
        command_bytes: cpu.command_bytes(),
        gpu_matches_cpu: Some(mismatch.is_none()),
    };
    Ok((stats, mismatch))
}
