//! The overlay: the egui window (adapter, path, view and renderer switches, camera,
//! per-pass GPU times averaged over half a second, counters, messages, keys) and the
//! classification counters it reads back.

use std::time::{Duration, Instant};

use gpu::config::{LightPaths, MsaaLighting};
use gpu::{FrameOutput, RenderPath, Timing};

use super::{OCCLUSIONS, State};
use crate::views::DebugView;

/// How often the overlay's averaged timings and the classification counters refresh.
const REFRESH: Duration = Duration::from_millis(500);

/// Per-label GPU times averaged over [`REFRESH`].
#[derive(Default)]
pub(super) struct Averages {
    sums: Vec<Timing>,
    wall_ms: f64,
    frames: u32,
    since: Option<Instant>,
    shown: Vec<Timing>,
    shown_wall_ms: f64,
    shown_fps: f64,
}

impl Averages {
    pub(super) fn add(&mut self, out: &FrameOutput) {
        let since = *self.since.get_or_insert_with(Instant::now);
        for t in &out.gpu {
            match self.sums.iter_mut().find(|s| s.label == t.label) {
                Some(s) => {
                    s.ms += t.ms;
                    s.passes += t.passes;
                }
                None => self.sums.push(t.clone()),
            }
        }
        self.wall_ms += out.wall_ms;
        self.frames += 1;
        let elapsed = since.elapsed();
        if elapsed >= REFRESH || self.shown.is_empty() && self.shown_fps == 0.0 {
            let n = f64::from(self.frames);
            self.shown = std::mem::take(&mut self.sums)
                .into_iter()
                .map(|t| Timing {
                    label: t.label,
                    ms: t.ms / n,
                    passes: (f64::from(t.passes) / n).round() as u32,
                })
                .collect();
            self.shown_wall_ms = self.wall_ms / n;
            self.shown_fps = n / elapsed.as_secs_f64().max(1e-3);
            self.wall_ms = 0.0;
            self.frames = 0;
            self.since = Some(Instant::now());
        }
    }
}

impl State {
    /// The classification counters, read back every [`REFRESH`] while they are switched
    /// on (deferred frames only).
    pub(super) fn refresh_stats(&mut self, path: RenderPath) {
        if !self.stats_on || path != RenderPath::Deferred {
            return;
        }
        if self
            .stats
            .as_ref()
            .is_some_and(|(_, at)| at.elapsed() < REFRESH)
        {
            return;
        }
        let read = self
            .renderer
            .inspect()
            .read_classification(&self.prepared)
            .and_then(|c| {
                self.renderer
                    .inspect()
                    .classification_statistics(&self.prepared, &c)
            });
        match read {
            Ok((stats, mismatch)) => {
                if let Some(m) = mismatch {
                    self.message = Some(format!("GPU classification differs from the CPU: {m}"));
                }
                self.stats = Some((stats, Instant::now()));
            }
            Err(e) => self.message = Some(format!("classification read-back: {e}")),
        }
    }

    /// The overlay.
    pub(super) fn ui(&mut self, ctx: &egui::Context) {
        // As tall as the window allows (scrolling beyond).
        let height = (ctx.content_rect().height() - 48.0).max(120.0);
        egui::Window::new("view")
            .default_pos([8.0, 8.0])
            .default_width(330.0)
            .max_height(height)
            .default_height(height)
            .resizable(false)
            .vscroll(true)
            .show(ctx, |ui| {
                let c = self.renderer.config().clone();
                ui.label(&self.adapter_line);
                ui.label(format!(
                    "{}: {}x{}, {:.1} fps, {:.2} ms a frame (wall, waited)",
                    self.loaded.name,
                    c.image.width,
                    c.image.height,
                    self.averages.shown_fps,
                    self.averages.shown_wall_ms
                ));
                ui.horizontal(|ui| {
                    ui.label("path (P)");
                    ui.selectable_value(&mut self.path, RenderPath::Deferred, "deferred (HFW)");
                    ui.selectable_value(&mut self.path, RenderPath::Baseline, "baseline (HZD)");
                    ui.selectable_value(&mut self.path, RenderPath::PixelPull, "pixel pull (004)");
                });
                egui::ComboBox::from_label("view (0-8, V)")
                    .selected_text(self.view.name())
                    .show_ui(ui, |ui| {
                        for v in DebugView::ALL {
                            ui.selectable_value(&mut self.view, v, v.name());
                        }
                    });
                if self.view != DebugView::Image {
                    ui.label(&self.caption);
                    if self.view.needs_deferred() && self.path != RenderPath::Deferred {
                        ui.label("(from a deferred frame: this path writes no vis buffer)");
                    }
                }
                if let Some(s) = &mut self.statics {
                    let name = |o| OCCLUSIONS.iter().find(|(m, _)| *m == o).map_or("", |m| m.1);
                    egui::ComboBox::from_label("static occlusion (C)")
                        .selected_text(name(s.occlusion))
                        .show_ui(ui, |ui| {
                            for (o, n) in OCCLUSIONS {
                                ui.selectable_value(&mut s.occlusion, o, n);
                            }
                        });
                    if let Some(st) = &self.last_output.statics {
                        ui.label(format!(
                            "static query: {} instances drawn ({} placed, {} over capacity)",
                            st.instances, st.placed, st.over_capacity
                        ));
                    }
                }
                egui::ComboBox::from_label("MSAA, baseline (M)")
                    .selected_text(msaa_name(self.wanted.image.msaa))
                    .show_ui(ui, |ui| {
                        for m in [None, Some(MsaaLighting::Kz2), Some(MsaaLighting::EverySample)] {
                            ui.selectable_value(&mut self.wanted.image.msaa, m, msaa_name(m));
                        }
                    });
                egui::ComboBox::from_label("light paths (L)")
                    .selected_text(light_paths_name(self.wanted.lighting.light_paths))
                    .show_ui(ui, |ui| {
                        for l in [
                            LightPaths::Tiled,
                            LightPaths::Classified,
                            LightPaths::Volumes,
                            LightPaths::EveryPixel,
                        ] {
                            ui.selectable_value(
                                &mut self.wanted.lighting.light_paths,
                                l,
                                light_paths_name(l),
                            );
                        }
                    });
                ui.horizontal(|ui| {
                    let mut sun = self.wanted.lighting.shadows.is_some();
                    if ui.checkbox(&mut sun, "sun shadows (O)").changed() {
                        self.wanted.lighting.shadows = sun.then(gpu::config::ShadowConfig::default);
                    }
                    let mut spots = self.wanted.lighting.spot_shadows.is_some();
                    if ui.checkbox(&mut spots, "spot shadows").changed() {
                        self.wanted.lighting.spot_shadows = spots.then(gpu::config::SpotShadowConfig::default);
                    }
                });
                ui.label(format!(
                    "camera {:.1}, {:.1}, {:.1}; speed {:.2} m/s (wheel)",
                    self.camera.camera().position.x,
                    self.camera.camera().position.y,
                    self.camera.camera().position.z,
                    self.camera.speed
                ));

                ui.separator();
                let shown = &self.averages.shown;
                if shown.is_empty() {
                    ui.label("GPU times: none (the adapter has no timestamp queries)");
                } else {
                    ui.label(format!(
                        "GPU time per pass, ms ({} frame, mean over 0.5 s)",
                        self.view.frame_path(self.path).name()
                    ));
                    egui::Grid::new("timings")
                        .striped(true)
                        .num_columns(2)
                        .show(ui, |ui| {
                            for t in shown {
                                ui.label(if t.passes > 1 {
                                    format!("{} (x{})", t.label, t.passes)
                                } else {
                                    t.label.to_string()
                                });
                                ui.label(format!("{:.3}", t.ms));
                                ui.end_row();
                            }
                            ui.strong("total");
                            ui.strong(format!(
                                "{:.3}",
                                shown.iter().map(|t| t.ms).sum::<f64>()
                            ));
                            ui.end_row();
                        });
                }

                ui.separator();
                self.counters(ui);
                ui.checkbox(
                    &mut self.stats_on,
                    "classification counters (read back and checked on the CPU twice a second; deferred frames)",
                );
                if let Some(m) = &self.message {
                    ui.separator();
                    ui.label(m);
                }
                ui.collapsing("keys", |ui| {
                    ui.label(
                        "WASD move, Q/E down/up, Shift faster, wheel speed, hold a mouse button \
                         to look; P path; 0-8 or V/Shift+V views; M MSAA; L light paths; \
                         O sun shadows; R reset camera; F1 overlay; F12 screenshot; Esc quit",
                    );
                });
            });
    }

    /// The counters' grid: the scene's and the renderer's, then (while switched on) the
    /// classification's.
    fn counters(&self, ui: &mut egui::Ui) {
        let s = self.prepared.summary();
        let lights = self.renderer.inspect().light_path_counts();
        let uploads = self.renderer.inspect().upload_stats();
        let local = self.lighting.point_lights.len() + self.lighting.spot_lights.len();
        let mut rows = vec![
            ("instances", s.instances.to_string()),
            ("triangles", s.triangles.to_string()),
            (
                "micro batches / passes",
                format!("{} / {}", s.micro_batches, s.passes),
            ),
            ("local lights", local.to_string()),
            (
                "lights tiled / volumes",
                format!("{} / {}", lights.tiled, lights.volumes),
            ),
            ("spot shadow maps", lights.spot_shadow_maps.to_string()),
            (
                "uploads",
                format!("{} B in {} blocks", uploads.bytes, uploads.blocks.len()),
            ),
        ];
        if let Some((st, _)) = &self.stats {
            let twin = match st.gpu_matches_cpu {
                Some(true) => "yes",
                Some(false) => "NO",
                None => "-",
            };
            let vertices = format!(
                "{} of {}",
                st.vertices_after_chunk_culling, st.scene_vertices
            );
            rows.extend([
                ("vis pixels", st.vis_pixels.to_string()),
                ("tile groups", st.tile_groups.to_string()),
                ("pixel commands", st.pixel_commands.to_string()),
                (
                    "wave commands",
                    format!("{} (width {})", st.wave_commands, st.wave_width),
                ),
                ("unfilled lanes", st.unfilled_lanes.to_string()),
                ("depth-equal waves (HZD)", st.depth_equal_waves.to_string()),
                ("vertices after chunk culling", vertices),
                ("GPU = CPU twin", twin.to_string()),
            ]);
        }
        egui::Grid::new("counters")
            .striped(true)
            .num_columns(2)
            .show(ui, |ui| {
                for (k, v) in rows {
                    ui.label(k);
                    ui.label(v);
                    ui.end_row();
                }
            });
    }
}

fn msaa_name(m: Option<MsaaLighting>) -> &'static str {
    match m {
        None => "off",
        Some(MsaaLighting::Kz2) => "4x, KZ2's edges",
        Some(MsaaLighting::EverySample) => "4x, every sample",
    }
}

fn light_paths_name(l: LightPaths) -> &'static str {
    match l {
        LightPaths::Tiled => "tiled",
        LightPaths::Classified => "KZ2 classified",
        LightPaths::Volumes => "stencil volumes",
        LightPaths::EveryPixel => "every pixel",
    }
}
