//! One frame: the renderer's (with the city's static query in front), the debug view's
//! image, the overlay's UI, the blit and egui in one pass to the window, the device's
//! errors, and the scripted frames' and F12's screenshots.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context as _, Result, anyhow, bail};
use gpu::FrameInput;
use winit::event_loop::ActiveEventLoop;

use super::{DebugTexture, State};
use crate::Args;
use crate::blit;
use crate::views;

impl State {
    pub(super) fn frame(&mut self, event_loop: &ActiveEventLoop, args: &Args) -> Result<()> {
        let now = Instant::now();
        let seconds = (now - self.last_frame).as_secs_f32().min(0.25);
        self.last_frame = now;
        let scripted = self.script.is_some();
        if !scripted {
            self.fly(seconds);
        }
        let size = self.window.inner_size();
        if size.width == 0 || size.height == 0 {
            return Ok(());
        }
        if (self.surface_config.width, self.surface_config.height) != (size.width, size.height) {
            self.configure_surface(size);
        }
        // Scripted frames keep the asked size; interactive ones follow the window.
        if !scripted
            && (self.wanted.image.width, self.wanted.image.height) != (size.width, size.height)
            && size.width <= self.device.limits().max_texture_dimension_2d
            && size.height <= self.device.limits().max_texture_dimension_2d
        {
            self.wanted.image.width = size.width;
            self.wanted.image.height = size.height;
        }
        if self.wanted != *self.renderer.config() {
            if let Err(e) = self.wanted.validate() {
                self.message = Some(format!("not applied: {e}"));
                self.wanted = self.renderer.config().clone();
            } else {
                self.rebuild();
            }
        }

        // The frame.
        let frame = FrameInput {
            camera: self.camera.camera(),
            time: if scripted {
                0.0
            } else {
                self.started.elapsed().as_secs_f32()
            },
            lighting: self.lighting.clone(),
        };
        let path = self.view.frame_path(self.path);
        let (width, height) = (
            self.renderer.config().image.width,
            self.renderer.config().image.height,
        );
        let rendered = gpu::inspect::scoped(&self.device, || match &mut self.statics {
            // The city: HZD's static query in front of the frame, for this camera.
            Some(s) => {
                let mut view = gpu::statics::StaticView {
                    query: &mut s.query,
                    scene: &mut s.scene,
                    view: gpu::statics::static_view_desc(&frame.camera, width, height),
                    options: Default::default(),
                    occlusion: s.occlusion,
                };
                self.renderer
                    .render_static(&self.prepared, &frame, path, &mut view)
            }
            None => self.renderer.render(&self.prepared, &frame, path),
        });
        match rendered {
            Ok(out) => {
                self.averages.add(&out);
                self.last_output = out;
            }
            Err(e) if scripted => return Err(e).context("rendering a scripted frame"),
            Err(e) => self.message = Some(format!("frame failed: {e}")),
        }
        self.debug = None;
        match views::debug_image(self.view, &self.renderer, &self.prepared, &frame) {
            Ok(Some((image, caption))) => {
                let texture = blit::upload(&self.device, &self.queue, &image);
                self.debug = Some(DebugTexture {
                    view: texture.create_view(&Default::default()),
                    _texture: texture,
                    size: (image.width, image.height),
                });
                self.caption = caption;
            }
            Ok(None) => self.caption.clear(),
            Err(e) if scripted => return Err(e).context("making the debug view"),
            Err(e) => self.caption = format!("{e:#}"),
        }
        self.refresh_stats(path);

        // The overlay's UI (run every frame so that it sees the input, drawn when shown).
        let raw = self.egui_state.take_egui_input(&self.window);
        let ctx = self.egui_ctx.clone();
        let full = ctx.run_pass(raw, |ctx| {
            if self.overlay {
                self.ui(ctx);
            }
        });
        self.egui_state
            .handle_platform_output(&self.window, full.platform_output);
        let primitives = ctx.tessellate(full.shapes, full.pixels_per_point);
        let mut textures = full.textures_delta;
        for (id, deltas) in &textures.set {
            for delta in deltas {
                self.egui_renderer
                    .update_texture(&self.device, &self.queue, *id, delta);
            }
        }
        // Freed after this frame's painting (or the next painted frame's).
        self.egui_free.extend(textures.free.drain());
        textures.clear();

        let surface_texture = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t)
            | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => {
                return Ok(());
            }
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                self.configure_surface(size);
                return Ok(());
            }
            wgpu::CurrentSurfaceTexture::Validation => {
                bail!("acquiring the window's next image failed validation")
            }
        };
        let target = surface_texture
            .texture
            .create_view(&wgpu::TextureViewDescriptor {
                format: Some(self.view_format),
                ..Default::default()
            });
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [self.surface_config.width, self.surface_config.height],
            pixels_per_point: full.pixels_per_point,
        };
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("view present"),
            });
        let egui_commands = self.egui_renderer.update_buffers(
            &self.device,
            &self.queue,
            &mut encoder,
            &primitives,
            &screen,
        );
        {
            let mut pass =
                blit::clear_pass(&mut encoder, "view blit and overlay", &target).forget_lifetime();
            let (source, source_size) = self.source();
            let source = source.clone();
            self.blit.draw(
                &self.device,
                &mut pass,
                self.view_format,
                &source,
                source_size,
                (self.surface_config.width, self.surface_config.height),
            );
            if self.overlay {
                self.egui_renderer.render(&mut pass, &primitives, &screen);
            }
        }
        self.queue
            .submit(egui_commands.into_iter().chain([encoder.finish()]));
        self.window.pre_present_notify();
        self.queue.present(surface_texture);
        for id in std::mem::take(&mut self.egui_free) {
            self.egui_renderer.free_texture(&id);
        }
        self.frames += 1;

        let errors = std::mem::take(
            &mut *self
                .device_errors
                .lock()
                .map_err(|_| anyhow!("the device error log was poisoned"))?,
        );
        if let Some(first) = errors.first() {
            if scripted {
                bail!("device error: {first}");
            }
            self.message = Some(format!("device error: {first}"));
        }

        if let Some(left) = self.script.as_mut() {
            *left -= 1;
            if *left == 0 {
                self.script = None;
                if let Some(file) = &args.screenshot {
                    self.screenshot(file)?;
                }
                if args.exit {
                    event_loop.exit();
                }
            }
        }
        if self.screenshot_requested {
            self.screenshot_requested = false;
            self.screenshots += 1;
            let file = args.screenshot.clone().unwrap_or_else(|| {
                PathBuf::from(format!("view-{}-{}.png", self.loaded.name, self.frames))
            });
            if let Err(e) = self.screenshot(&file) {
                self.message = Some(format!("screenshot failed: {e:#}"));
            }
        }
        Ok(())
    }

    /// What the window shows: the debug view's image, or the renderer's output.
    fn source(&self) -> (&wgpu::TextureView, (u32, u32)) {
        match &self.debug {
            Some(d) => (&d.view, d.size),
            None => {
                let c = self.renderer.config();
                (self.renderer.output_view(), (c.image.width, c.image.height))
            }
        }
    }

    /// Writes the displayed image (without the overlay) to `file` as PNG.
    fn screenshot(&mut self, file: &std::path::Path) -> Result<()> {
        let (source, size) = self.source();
        let source = source.clone();
        let image = self
            .blit
            .capture(&self.device, &self.queue, &source, size)?;
        image
            .write_png(file)
            .with_context(|| format!("--screenshot: writing {}", file.display()))?;
        println!(
            "view: wrote {} ({}x{}, {})",
            file.display(),
            size.0,
            size.1,
            self.view.name()
        );
        self.message = Some(format!("wrote {}", file.display()));
        Ok(())
    }
}
