//! The statistics table the `render` binary prints: adapter, scene, classification
//! counters (the talk's tables), image comparison and per-pass GPU times.

use std::fmt;
use std::path::{Path, PathBuf};

use gpu::inspect::{ClassificationStats, diff_metrics};
use gpu::{FrameOutput, GpuContext, PreparedScene, RenderPath, Renderer, Rgba8Image};

/// Everything printed after a run.
pub struct Report {
    lines: Vec<(String, String)>,
    timings: Vec<(String, FrameOutput)>,
    images: Vec<(String, PathBuf)>,
}

impl Report {
    /// Starts a report with the adapter, the active paths and the scene's size.
    pub fn new(ctx: &GpuContext, renderer: &Renderer, prepared: &PreparedScene) -> Self {
        let mut r = Report {
            lines: Vec::new(),
            timings: Vec::new(),
            images: Vec::new(),
        };
        let paths = renderer.paths();
        r.row("adapter", ctx.adapter_line());
        r.row("primitive ID path", paths.primitive_id.name().to_string());
        r.row(
            "pixel-pull barycentrics",
            if paths.barycentrics {
                "hardware (@builtin(barycentric))"
            } else {
                "ray-triangle fallback (visbuf::ray)"
            }
            .to_string(),
        );
        r.row(
            "mixed frame (deferred path)",
            if renderer.config().geometry.mixed_frame {
                "on: terrain and rocks by the regular geometry pass"
            } else {
                "off: every batch through the vis buffer"
            }
            .to_string(),
        );
        let c = renderer.config();
        r.row(
            "laydown (deferred paths)",
            match (c.geometry.laydown, renderer.laydown_target()) {
                (gpu::Laydown::Hardware, _) => "hardware".to_string(),
                (asked, None) => format!(
                    "hardware ({} asked for: the adapter lacks SHADER_INT64_ATOMIC_MIN_MAX)",
                    asked.name()
                ),
                (asked, Some(target)) => format!(
                    "{}: compute into a 64-bit {}, triangles over {} pixels a workgroup each",
                    asked.name(),
                    target.name(),
                    c.geometry.compute_laydown_max_extent
                ),
            },
        );
        r.row(
            "appends",
            match paths.subgroup_size {
                Some((lo, hi)) => format!("subgroups (size {lo}..{hi})"),
                None => "workgroup-atomic fallback".to_string(),
            },
        );
        r.row(
            "timestamps",
            if paths.timestamps {
                "yes"
            } else {
                "no (times are wall-clock only)"
            }
            .to_string(),
        );
        r.row(
            "resolution",
            format!("{} x {}", c.image.width, c.image.height),
        );
        r.row(
            "G-buffer",
            format!(
                "{:?}: {} bytes a pixel + 4 of depth",
                c.image.gbuffer,
                c.image.gbuffer.color_bytes_per_sample()
            ),
        );
        let s = prepared.summary();
        r.row("instances", group_digits(s.instances));
        r.row("triangles", group_digits(s.triangles));
        r.row("micro batches", group_digits(s.micro_batches as u64));
        r.row(
            "resolve pipelines",
            format!(
                "{} ({})",
                s.resolve_pipelines,
                if c.geometry.material_permutations {
                    "one per material permutation"
                } else {
                    "the uber resolve"
                }
            ),
        );
        r.row(
            "vertices added by the primitive-ID encoding",
            group_digits(s.added_vertices),
        );
        r
    }

    fn row(&mut self, k: &str, v: String) {
        self.lines.push((k.to_string(), v));
    }

    /// The local lights and what the tiled culling made of them.
    pub fn light_tiles(&mut self, lights: usize, t: &gpu::inspect::LightTiles) {
        let tiles = u64::from(t.tiles[0]) * u64::from(t.tiles[1]);
        let s = &t.stats;
        self.row(
            "local lights (point + spot) / light tiles with geometry",
            format!(
                "{} / {} of {}",
                group_digits(lights as u64),
                group_digits(u64::from(s.tiles_with_geometry)),
                group_digits(tiles)
            ),
        );
        let per_tile = s.pairs as f64 / f64::from(s.tiles_with_geometry.max(1));
        self.row(
            "(tile, light) pairs / lights per tile / tiles over the list cap",
            format!(
                "{} / {per_tile:.1} (every light at every tile: {}) / {}",
                group_digits(s.pairs),
                group_digits(lights as u64),
                s.overflowed_tiles
            ),
        );
    }

    /// How the lights were drawn: tiles, stencil volumes (and of those, from inside).
    pub fn light_paths(&mut self, c: gpu::inspect::LightPathCounts) {
        self.row(
            "lights by tiles / by stencil volumes (drawn from inside, tested) / spot shadow maps (skipped by the CPU)",
            format!(
                "{} / {} ({}, {}) / {} ({})",
                group_digits(u64::from(c.tiled)),
                group_digits(u64::from(c.volumes)),
                group_digits(u64::from(c.volumes_from_inside)),
                c.volumes_tested,
                c.spot_shadow_maps,
                c.spot_shadow_maps_skipped
            ),
        );
    }

    /// What KZ2's emulated conditional rendering decided on the GPU for the tested lights
    /// (nothing when none was tested).
    pub fn conditional_volumes(&mut self, tested: &[gpu::inspect::ConditionalLight]) {
        if tested.is_empty() {
            return;
        }
        let skipped = tested.iter().filter(|t| t.volume_instances == 0).count();
        self.row(
            "tested volume lights skipped by the GPU (no pixel: neither map nor shading)",
            format!("{skipped} of {}", tested.len()),
        );
    }

    /// Wall-clock per frame, waiting for each frame against submitting them back to back
    /// (with the CPU time of a submission, the pacing wait included).
    pub fn frame_pacing(
        &mut self,
        waited_ms: f64,
        pipelined_ms: f64,
        submit_ms: f64,
        in_flight: u32,
    ) {
        self.row(
            "wall-clock per frame: waiting for each / back to back (submit call; most in flight)",
            format!("{waited_ms:.2} ms / {pipelined_ms:.2} ms ({submit_ms:.2} ms; {in_flight})"),
        );
    }

    /// The last frame's per-frame uploads through the framealloc pool.
    pub fn uploads(&mut self, u: &gpu::inspect::UploadStats, pool: gpu::framealloc::PoolConfig) {
        self.row(
            "per-frame uploads (framealloc pool) / blocks / CPU time in framealloc, whole commit",
            format!(
                "{} bytes in {} writes / {} of {} blocks of {} KiB / {:.1} us, {:.1} us",
                group_digits(u.bytes),
                u.writes,
                u.blocks.len(),
                u.pool_blocks,
                pool.block_bytes / 1024,
                u.allocator_ns as f64 / 1e3,
                u.commit_ns as f64 / 1e3
            ),
        );
    }

    /// How many geometry pixels skip the sun's shader (KZ2: close to half): in full baked
    /// sun shadow, or facing away from the sun.
    pub fn sun_skip(&mut self, geometry: u64, baked: u64, away: u64) {
        let pct = |n: u64| 100.0 * n as f64 / geometry.max(1) as f64;
        self.row(
            "sun's shader skipped: in full baked shadow / facing away (of geometry pixels)",
            format!(
                "{:.1}% / {:.1}% = {:.1}% (KZ2: close to 50%)",
                pct(baked),
                pct(away),
                pct(baked + away)
            ),
        );
    }

    /// What `set_water` built: bodies and their meshes, the far sectors, the world.
    pub fn water_summary(&mut self, s: &gpu::water_scene::WaterSummary) {
        self.row(
            "water: bodies drawn per body (mesh triangles) / far sectors (levels, with water) / world words",
            format!(
                "{} ({}) / {}x{} ({}, {}) / {}",
                s.bodies,
                group_digits(s.mesh_triangles),
                s.sectors_per_side,
                s.sectors_per_side,
                s.quadtree_levels,
                s.water_sectors,
                group_digits(s.world_words)
            ),
        );
        self.cpu_ms(
            "water: meshes, sector quadtree, material map, upload (CPU)",
            s.build_ms,
        );
    }

    /// What the last frame's water passes did.
    pub fn water_stats(&mut self, s: &gpu::water_scene::WaterStats) {
        self.row(
            "water: mini G-buffer (precision) / near bodies, far sectors drawn (nodes tested)",
            format!(
                "{} x {} ({}) / {}, {} ({})",
                s.buffer[0],
                s.buffer[1],
                if s.half_precision { "f16" } else { "f32" },
                s.near_bodies,
                s.far_sectors,
                s.nodes_tested
            ),
        );
        self.row(
            "water: pixels / 32x32 tiles visible / triangles tessellated",
            format!(
                "{} / {} of {} / {}",
                group_digits(s.water_pixels),
                group_digits(u64::from(s.tiles)),
                group_digits(u64::from(s.tiles_total)),
                group_digits(s.triangles)
            ),
        );
    }

    /// A CPU time.
    pub fn cpu_ms(&mut self, what: &str, ms: f64) {
        self.row(what, format!("{ms:.1} ms"));
    }

    /// The GPU time of a whole frame (the sum of its timed passes).
    pub fn gpu_frame_ms(&mut self, what: &str, frame: &FrameOutput) {
        let ms: f64 = frame.gpu.iter().map(|t| t.ms).sum();
        self.row(what, format!("{ms:.3} ms"));
    }

    /// The static query's counts (seed 001's funnel) and the placement into the frame.
    pub fn static_query(&mut self, s: &gpu::statics::StaticFrameStats, scene_instances: u64) {
        let q = &s.query;
        self.row(
            "static instances in the scene",
            group_digits(scene_instances),
        );
        self.row(
            "static: tiles / clusters after the pre-cull",
            format!(
                "{} of {} / {} of {}",
                group_digits(q.tiles - q.tiles_culled),
                group_digits(q.tiles),
                group_digits(q.clusters - q.clusters_culled),
                group_digits(q.clusters)
            ),
        );
        self.row(
            "static: instances after the pre-cull (threads run / dispatched)",
            format!(
                "{} / {}",
                group_digits(q.instances),
                group_digits(s.threads)
            ),
        );
        let mut left = q.instances;
        // Two-pass: the first pass's "occlusion" is last frame's visibility; the second
        // tests the rest against this frame's HiZ.
        let occlusion = if s.second_pass.is_some() {
            "occlusion pass 1 (not visible last frame)"
        } else {
            "occlusion"
        };
        for (what, n) in [
            ("filter and LOD", q.rejected_filter + q.rejected_lod),
            ("frustum", q.rejected_frustum),
            ("size", q.rejected_size),
            (occlusion, q.rejected_occlusion),
            ("LOD fade (faded out)", q.faded_out),
        ] {
            left = left.saturating_sub(n);
            self.row(
                &format!("static: after the {what} test"),
                format!("{} ({} rejected)", group_digits(left), group_digits(n)),
            );
        }
        if let Some(p2) = &s.second_pass {
            self.row(
                "static: occlusion pass 2 (this frame's HiZ): drawn early / added / hidden",
                format!(
                    "{} / {} / {}",
                    group_digits(p2.drawn_early),
                    group_digits(p2.visible),
                    group_digits(p2.rejected_occlusion)
                ),
            );
        }
        self.row(
            "static: instances / batches out",
            format!(
                "{} / {} (batching saves {:.0}% of render items; HZD 60-70%)",
                group_digits(u64::from(s.instances)),
                group_digits(u64::from(s.batches)),
                100.0 * (1.0 - f64::from(s.batches) / f64::from(s.instances.max(1)))
            ),
        );
        self.row(
            "static: placed / indirect draws (opaque, alpha)",
            format!(
                "{} / {} + {}{}",
                group_digits(s.placed),
                s.draws[0],
                s.draws[1],
                overflow(s.over_capacity, s.bad_batches)
            ),
        );
    }

    /// What the static query's shadow views sent to the sun's maps: per re-rendered slice
    /// (and the baked map, in a frame that re-baked it), its static casters, those KZ2's
    /// size threshold dropped, and its indirect draws.
    pub fn static_shadows(&mut self, s: &gpu::statics::StaticFrameStats) {
        let rows = s
            .shadow_slices
            .iter()
            .map(|v| (format!("slice {}", v.slice), v))
            .chain(s.baked.iter().map(|v| ("baked map".to_string(), v)));
        for (what, v) in rows {
            self.row(
                &format!(
                    "static shadows, {what} ({} texels): casters / dropped by size / outside",
                    v.texels
                ),
                format!(
                    "{} / {} / {} of {} after the pre-cull; {} placed, draws {} + {}{}",
                    group_digits(u64::from(v.instances)),
                    group_digits(v.query.rejected_size),
                    group_digits(v.query.rejected_frustum),
                    group_digits(v.query.instances),
                    group_digits(v.placed),
                    v.draws[0],
                    v.draws[1],
                    overflow(v.over_capacity, v.bad_batches)
                ),
            );
        }
    }

    /// HFW's vertex side, from the GPU's own counters: vertices transformed into the ring
    /// (the dispatches' items) against the scene's and the read-back measurement.
    pub fn vertex_ring(
        &mut self,
        ring: &gpu::inspect::VertexRingReadback,
        s: &ClassificationStats,
    ) {
        let held = ring.half_base.iter().filter(|&&h| h != u32::MAX).count();
        self.row(
            "vertex ring: vertices transformed (GPU counters) / scene",
            format!(
                "{} / {} = {:.0}% in {} chunks, {held} of {} passes in a {} MiB ring{}",
                group_digits(ring.vertices_transformed()),
                group_digits(s.scene_vertices),
                pct(ring.vertices_transformed(), s.scene_vertices),
                group_digits(u64::from(ring.visible_chunks)),
                ring.half_base.len(),
                (u64::from(ring.ring_vertices) * gpu::inspect::RING_VERTEX_BYTES) >> 20,
                if ring.vertices_transformed() == s.vertices_after_chunk_culling {
                    " (= read-back)"
                } else {
                    " (differs from the read-back's count)"
                }
            ),
        );
    }

    /// The classification counters and the talk's ratios.
    pub fn classification(&mut self, s: &ClassificationStats) {
        self.row("vis pixels", group_digits(s.vis_pixels));
        self.row(
            "passes / batch groups",
            format!("{} / {}", s.passes, s.batch_groups),
        );
        self.row("pixel commands", group_digits(s.pixel_commands));
        self.row(
            "wave commands",
            format!(
                "{} (wave width {})",
                group_digits(s.wave_commands),
                s.wave_width
            ),
        );
        let lanes = s.wave_commands * u64::from(s.wave_width);
        self.row(
            "unfilled lanes",
            format!(
                "{} ({:.1}% of lanes)",
                group_digits(s.unfilled_lanes),
                pct(s.unfilled_lanes, lanes)
            ),
        );
        self.row(
            "pixel-shading waves: deferred / depth-equal",
            format!(
                "{} / {} = {:.0}% (HFW: forest 40%, tall grass 25%)",
                group_digits(s.wave_commands),
                group_digits(s.depth_equal_waves),
                pct(s.wave_commands, s.depth_equal_waves)
            ),
        );
        // Each (quad, triangle) pair costs the depth-equal pass 4 lanes and has at least one
        // pixel, which costs deferred one: the ratio cannot go below these deferred waves
        // over 4 lanes a vis pixel (25% but for the rounding to waves).
        let pair_lanes = s.depth_equal_waves * u64::from(s.wave_width);
        let floor_waves = (4 * s.vis_pixels).div_ceil(u64::from(s.wave_width).max(1));
        self.row(
            "pixel-shading waves: floor (a triangle per pixel of every quad)",
            format!(
                "{} / {} = {:.1}%; (quad, triangle) pairs per vis pixel now about {:.3}",
                group_digits(s.wave_commands),
                group_digits(floor_waves),
                pct(s.wave_commands, floor_waves),
                pair_lanes as f64 / 4.0 / s.vis_pixels.max(1) as f64
            ),
        );
        self.row(
            "vertices: after chunk culling / scene",
            format!(
                "{} / {} = {:.0}% (HFW: forest 32%, tall grass 55%)",
                group_digits(s.vertices_after_chunk_culling),
                group_digits(s.scene_vertices),
                pct(s.vertices_after_chunk_culling, s.scene_vertices)
            ),
        );
        self.row(
            "command buffer bytes",
            format!(
                "{} ({:.2} per vis pixel)",
                group_digits(s.command_bytes),
                s.command_bytes as f64 / s.vis_pixels.max(1) as f64
            ),
        );
        if let Some(m) = s.gpu_matches_cpu {
            self.row(
                "GPU classification == CPU twin",
                if m { "yes" } else { "NO" }.to_string(),
            );
        }
    }

    /// GPU and wall times of a path.
    pub fn timings(&mut self, path: RenderPath, t: &FrameOutput) {
        self.timings.push((path.name().to_string(), t.clone()));
    }

    /// The laydown `path`'s frames ran, and why (a frame with a static query runs the
    /// hardware laydown; `Laydown::Auto` reports what it measured).
    pub fn laydown_ran(&mut self, path: RenderPath, renderer: &Renderer, t: &FrameOutput) {
        let Some(ran) = t.laydown else {
            return;
        };
        let why = match renderer.laydown_choice().reason {
            _ if t.statics.is_some() && ran == gpu::Laydown::Hardware => {
                "frames with a static query take the hardware laydown".to_string()
            }
            gpu::config::LaydownReason::Asked => "asked for".to_string(),
            gpu::config::LaydownReason::NoComputeFeatures => {
                "the adapter lacks the compute laydown's 64-bit atomics".to_string()
            }
            gpu::config::LaydownReason::Trial { frames_left } => {
                format!("auto: still timing both, {frames_left} frames to go")
            }
            gpu::config::LaydownReason::Measured {
                hardware_ms,
                compute_ms,
                gpu_timed,
            } => format!(
                "auto, {} frame medians: hardware {hardware_ms:.3} ms, compute {compute_ms:.3} ms",
                if gpu_timed { "GPU" } else { "wall" }
            ),
        };
        self.row(
            &format!("laydown ran ({})", path.name()),
            format!("{} ({why})", ran.name()),
        );
    }

    /// GPU and wall times of a named variant of a path.
    pub fn timings_named(&mut self, name: &str, t: &FrameOutput) {
        self.timings.push((name.to_string(), t.clone()));
    }

    /// The compute laydown's triangles and its hardware part's share.
    pub fn laydown_stats(&mut self, s: &gpu::inspect::LaydownStats) {
        let share = if s.triangles == 0 {
            0.0
        } else {
            100.0 * s.hybrid as f64 / s.triangles as f64
        };
        self.row(
            "compute laydown",
            format!(
                "{} triangles, {} a workgroup each, {} ({share:.3}%) to the hardware part, {} past the lists",
                group_digits(s.triangles),
                group_digits(s.large),
                group_digits(s.hybrid),
                group_digits(s.dropped)
            ),
        );
    }

    /// Whether wgpu validated the indirect arguments (its injected pass).
    pub fn indirect_validation(&mut self, on: bool) {
        self.row(
            "wgpu indirect-argument validation",
            if on {
                "on"
            } else {
                "off (the renderer's arguments are valid by construction)"
            }
            .to_string(),
        );
    }

    /// KZ2's MSAA edge pixels of the baseline frame just rendered.
    pub fn msaa_edges(&mut self, edges: usize, pixels: usize) {
        self.row(
            "MSAA 4x edge pixels (lit per sample)",
            format!(
                "{} of {} ({:.1}%)",
                group_digits(edges as u64),
                group_digits(pixels as u64),
                100.0 * edges as f64 / pixels.max(1) as f64
            ),
        );
    }

    /// An output image of a path.
    pub fn image(&mut self, path: RenderPath, file: &Path) {
        self.images
            .push((path.name().to_string(), file.to_path_buf()));
    }

    /// A named debug image.
    pub fn image_named(&mut self, name: &str, file: &Path) {
        self.images.push((name.to_string(), file.to_path_buf()));
    }

    /// Compares a path's image with the baseline's, in a row named `label`.
    pub fn compare(&mut self, label: &str, deferred: &Rgba8Image, baseline: &Rgba8Image) {
        if let (Some((mean, _)), Some((_, p99))) = (
            diff_metrics(deferred, baseline, 0.5),
            diff_metrics(deferred, baseline, 0.99),
        ) {
            let differing = deferred
                .pixels
                .iter()
                .zip(&baseline.pixels)
                .filter(|(a, b)| a[..3] != b[..3])
                .count();
            self.row(
                label,
                format!(
                    "mean abs error {mean:.3} / 255, 99th percentile {p99} / 255, {:.2}% of pixels differ",
                    100.0 * differing as f64 / deferred.pixels.len().max(1) as f64
                ),
            );
        }
    }
}

fn pct(a: u64, b: u64) -> f64 {
    if b == 0 {
        0.0
    } else {
        100.0 * a as f64 / b as f64
    }
}

/// 1234567 -> "1 234 567".
pub fn group_digits(n: u64) -> String {
    let s = n.to_string();
    let mut out = String::new();
    for (i, c) in s.chars().enumerate() {
        if i > 0 && (s.len() - i).is_multiple_of(3) {
            out.push(' ');
        }
        out.push(c);
    }
    out
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let w = self.lines.iter().map(|(k, _)| k.len()).max().unwrap_or(0);
        for (k, v) in &self.lines {
            writeln!(f, "{k:<w$}  {v}")?;
        }
        for (path, t) in &self.timings {
            writeln!(
                f,
                "\n{path} path, GPU times (timestamp queries, mean over the measured frames after a 0.5 s warm-up):",
            )?;
            let total: f64 = t.gpu.iter().map(|x| x.ms).sum();
            for x in &t.gpu {
                writeln!(f, "  {:<28} {:>10.4} ms", x.label, x.ms)?;
            }
            if t.gpu.is_empty() {
                writeln!(f, "  (no timestamp queries on this adapter)")?;
            } else {
                writeln!(f, "  {:<28} {:>10.4} ms", "total", total)?;
            }
            if t.untimed_passes > 0 {
                writeln!(
                    f,
                    "  ({} passes of a measured frame untimed: the timestamp queries ran out; the total is short)",
                    t.untimed_passes
                )?;
            }
            writeln!(f, "  {:<28} {:>10.3} ms", "wall clock per frame", t.wall_ms)?;
        }
        if !self.images.is_empty() {
            writeln!(f, "\nimages:")?;
            for (name, p) in &self.images {
                writeln!(f, "  {name:<18} {}", p.display())?;
            }
        }
        Ok(())
    }
}

/// ` (N over capacity, M bad batches)` after a static query's placed instances and draws,
/// where either count is above zero; nothing otherwise.
fn overflow(over_capacity: u32, bad_batches: u32) -> String {
    if over_capacity > 0 || bad_batches > 0 {
        format!(" ({over_capacity} over capacity, {bad_batches} bad batches)")
    } else {
        String::new()
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn digits_are_grouped() {
        assert_eq!(super::group_digits(0), "0");
        assert_eq!(super::group_digits(999), "999");
        assert_eq!(super::group_digits(1000), "1 000");
        assert_eq!(super::group_digits(1_234_567), "1 234 567");
    }

    #[test]
    fn overflow_is_named_only_when_there_is_some() {
        assert_eq!(super::overflow(0, 0), "");
        assert_eq!(super::overflow(3, 0), " (3 over capacity, 0 bad batches)");
        assert_eq!(super::overflow(0, 1), " (0 over capacity, 1 bad batches)");
        assert_eq!(
            super::overflow(u32::MAX, u32::MAX),
            " (4294967295 over capacity, 4294967295 bad batches)"
        );
    }
}
