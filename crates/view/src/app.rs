//! The window, the device on it, the frame loop and the overlay.
//!
//! One device serves the renderer, the blit and egui: it is requested from an adapter that
//! can present to the window's surface, with every optional feature of
//! [`gpu::Renderer::optional_features`] the adapter has and the adapter's own limits (as
//! [`gpu::headless`] does), which cover [`gpu::Renderer::required_limits`] at every size
//! the adapter supports: a resize makes a new renderer, never a new device.

use std::collections::HashSet;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use anyhow::{Context as _, Result, anyhow, bail};
use gpu::config::{LightPaths, MsaaLighting};
use gpu::inspect::ClassificationStats;
use gpu::{FrameInput, FrameOutput, PreparedScene, RenderPath, Renderer, RendererConfig, Timing};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

use crate::blit::{self, Blit};
use crate::camera::FlyCamera;
use crate::views::{self, DebugView};
use crate::{Args, LoadedScene};

/// Radians the view turns per pixel of mouse motion.
const LOOK_PER_PIXEL: f32 = 0.003;

/// How often the overlay's averaged timings and the classification counters refresh.
const REFRESH: Duration = Duration::from_millis(500);

/// Opens the window and runs the viewer on `loaded` until it closes.
///
/// # Errors
/// As [`crate::run`].
pub fn run(args: Args, loaded: LoadedScene) -> Result<()> {
    let event_loop = EventLoop::new().map_err(|e| {
        anyhow!(
            "cannot open a window ({e}): the viewer needs a display (a desktop session, or \
             Xvfb: `Xvfb :99 & DISPLAY=:99 view`) and, on X11, the client libraries winit \
             loads (Debian: libx11-xcb1 libxcursor1 libxi6 libxkbcommon-x11-0)"
        )
    })?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = App {
        args,
        loaded: Some(loaded),
        state: None,
        error: None,
    };
    event_loop
        .run_app(&mut app)
        .context("the window's event loop")?;
    match app.error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

struct App {
    args: Args,
    loaded: Option<LoadedScene>,
    state: Option<State>,
    error: Option<anyhow::Error>,
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.state.is_some() {
            return;
        }
        let Some(loaded) = self.loaded.take() else {
            return;
        };
        match State::new(event_loop, &self.args, loaded) {
            Ok(state) => {
                state.window.request_redraw();
                self.state = Some(state);
            }
            Err(e) => {
                self.error = Some(e);
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let Some(state) = self.state.as_mut() else {
            return;
        };
        if let Err(e) = state.window_event(event_loop, &self.args, event) {
            self.error = Some(e);
            event_loop.exit();
        }
    }

    fn about_to_wait(&mut self, _: &ActiveEventLoop) {
        if let Some(state) = &self.state {
            state.window.request_redraw();
        }
    }

    fn exiting(&mut self, _: &ActiveEventLoop) {
        // Drop the surface (and the renderer) before the window and the event loop go.
        self.state = None;
    }
}

/// Per-label GPU times averaged over [`REFRESH`].
#[derive(Default)]
struct Averages {
    sums: Vec<Timing>,
    wall_ms: f64,
    frames: u32,
    since: Option<Instant>,
    shown: Vec<Timing>,
    shown_wall_ms: f64,
    shown_fps: f64,
}

impl Averages {
    fn add(&mut self, out: &FrameOutput) {
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

/// A debug view's image on the GPU.
struct DebugTexture {
    _texture: wgpu::Texture,
    view: wgpu::TextureView,
    size: (u32, u32),
}

/// Everything that lives while the window is open.
struct State {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    surface_config: wgpu::SurfaceConfiguration,
    /// The non-sRGB view format the blit and egui write.
    view_format: wgpu::TextureFormat,
    device: wgpu::Device,
    queue: wgpu::Queue,
    adapter_line: String,
    /// Errors wgpu raised outside an error scope (shown; fatal in scripted mode).
    device_errors: Arc<Mutex<Vec<String>>>,
    blit: Blit,
    egui_ctx: egui::Context,
    egui_state: egui_winit::State,
    egui_renderer: egui_wgpu::Renderer,
    /// egui textures to free once a frame has been painted.
    egui_free: Vec<egui::TextureId>,
    loaded: LoadedScene,
    /// The city's static world on this device, with a scene that has one.
    statics: Option<Statics>,
    renderer: Renderer,
    prepared: PreparedScene,
    /// The configuration asked for (the renderer is rebuilt when it differs).
    wanted: RendererConfig,
    path: RenderPath,
    view: DebugView,
    camera: FlyCamera,
    home: gpu::Camera,
    lighting: gpu::Lighting,
    keys: HashSet<KeyCode>,
    shift: bool,
    looking: bool,
    cursor: Option<(f64, f64)>,
    averages: Averages,
    last_output: FrameOutput,
    debug: Option<DebugTexture>,
    caption: String,
    message: Option<String>,
    overlay: bool,
    stats_on: bool,
    stats: Option<(ClassificationStats, Instant)>,
    frames: u64,
    started: Instant,
    last_frame: Instant,
    /// Frames still to render from the script (`None`: interactive).
    script: Option<u32>,
    screenshot_requested: bool,
    screenshots: u32,
}

/// The city's static world: the GPU query with its tiles activated, the CPU side, and
/// where its occlusion gets its HiZ (`C` switches).
struct Statics {
    query: gpu::statics::StaticQuery,
    scene: gpu::staticscene::Scene,
    occlusion: gpu::statics::StaticOcclusion,
}

/// The occlusion modes `C` cycles through, with their overlay names.
const OCCLUSIONS: [(gpu::statics::StaticOcclusion, &str); 3] = [
    (gpu::statics::StaticOcclusion::Given, "off (no HiZ given)"),
    (
        gpu::statics::StaticOcclusion::PreviousFrame,
        "previous frame's depth (HZD)",
    ),
    (gpu::statics::StaticOcclusion::TwoPass, "two-pass"),
];

impl State {
    fn new(event_loop: &ActiveEventLoop, args: &Args, loaded: LoadedScene) -> Result<Self> {
        let (width, height) = (args.width, args.height);
        let attributes = Window::default_attributes()
            .with_title(format!("view: {}", loaded.name))
            .with_inner_size(PhysicalSize::new(width, height));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .context("creating the window")?,
        );
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_with_display_handle_from_env(
                Box::new(event_loop.owned_display_handle()),
            ));
        let surface = instance
            .create_surface(Arc::clone(&window))
            .context("creating the window's wgpu surface")?;
        let adapter = [false, true]
            .into_iter()
            .find_map(|fallback| {
                pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
                    power_preference: if fallback {
                        wgpu::PowerPreference::None
                    } else {
                        wgpu::PowerPreference::HighPerformance
                    },
                    force_fallback_adapter: fallback,
                    compatible_surface: Some(&surface),
                    apply_limit_buckets: false,
                }))
                .ok()
            })
            .ok_or_else(|| {
                anyhow!(
                    "no GPU adapter can present to this window (a Vulkan driver is needed: \
                     scripts/ensure-env installs lavapipe)"
                )
            })?;
        let info = adapter.get_info();
        let features = adapter.features() & Renderer::optional_features();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("view device"),
            required_features: features | Renderer::required_features(),
            required_limits: adapter.limits(),
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        }))
        .context("requesting the device")?;
        let device_errors = Arc::new(Mutex::new(Vec::new()));
        let sink = Arc::clone(&device_errors);
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            if let Ok(mut v) = sink.lock() {
                v.push(e.to_string());
            }
        }));

        let caps = surface.get_capabilities(&adapter);
        let format = caps
            .formats
            .iter()
            .copied()
            .find(|f| {
                matches!(
                    f,
                    wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Rgba8Unorm
                )
            })
            .or_else(|| caps.formats.first().copied())
            .ok_or_else(|| anyhow!("the window's surface offers no format on this adapter"))?;
        let view_format = format.remove_srgb_suffix();
        let size = window.inner_size();
        let surface_config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            format,
            color_space: wgpu::SurfaceColorSpace::Auto,
            width: size.width.max(1),
            height: size.height.max(1),
            desired_maximum_frame_latency: 2,
            present_mode: wgpu::PresentMode::AutoVsync,
            alpha_mode: caps
                .alpha_modes
                .first()
                .copied()
                .unwrap_or(wgpu::CompositeAlphaMode::Auto),
            view_formats: if view_format == format {
                vec![]
            } else {
                vec![view_format]
            },
        };
        surface.configure(&device, &surface_config);

        // The first renderer at the asked size (the window may come out another size: the
        // first frame rebuilds it to fit, but for scripted runs).
        let wanted = args.renderer_config(width, height);
        let renderer =
            gpu::inspect::scoped(&device, || Renderer::new(&device, &queue, wanted.clone()))?;
        let t = Instant::now();
        let prepared = gpu::inspect::scoped(&device, || renderer.prepare(&loaded.scene))?;
        let statics = match &loaded.city {
            Some(city) => Some(gpu::inspect::scoped(&device, || {
                let mut query = gpu::statics::StaticQuery::new(&device, &queue)?;
                let scene = gpu::statics::stream_static_world(
                    &device,
                    &queue,
                    &mut query,
                    &city.world.resources,
                    &city.world.groups,
                )?;
                Ok(Statics {
                    query,
                    scene,
                    occlusion: gpu::statics::StaticOcclusion::PreviousFrame,
                })
            })?),
            None => None,
        };
        let s = prepared.summary();
        println!(
            "view: {} on {}: {} instances, {} triangles, prepared in {:.0} ms",
            loaded.name,
            gpu::adapter_line(&info),
            s.instances,
            s.triangles,
            t.elapsed().as_secs_f64() * 1e3
        );

        let egui_ctx = egui::Context::default();
        let egui_state = egui_winit::State::new(
            egui_ctx.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            Some(device.limits().max_texture_dimension_2d as usize),
        );
        let egui_renderer =
            egui_wgpu::Renderer::new(&device, view_format, egui_wgpu::RendererOptions::default());

        let home = args.camera.or(loaded.camera).unwrap_or_else(|| {
            let size = window.inner_size();
            let aspect = size.width.max(1) as f32 / size.height.max(1) as f32;
            gltf_scene::framing_camera(&loaded.scene, aspect)
        });
        let lighting = args.lighting(loaded.lighting.clone(), home.target);
        let now = Instant::now();
        Ok(Self {
            blit: Blit::new(&device),
            window,
            surface,
            surface_config,
            view_format,
            device,
            queue,
            adapter_line: gpu::adapter_line(&info),
            device_errors,
            egui_ctx,
            egui_state,
            egui_renderer,
            egui_free: Vec::new(),
            loaded,
            statics,
            renderer,
            prepared,
            wanted,
            path: args.path.path(),
            view: args.debug_view,
            camera: FlyCamera::new(home),
            home,
            lighting,
            keys: HashSet::new(),
            shift: false,
            looking: false,
            cursor: None,
            averages: Averages::default(),
            last_output: FrameOutput::default(),
            debug: None,
            caption: String::new(),
            message: None,
            overlay: !args.no_overlay,
            stats_on: false,
            stats: None,
            frames: 0,
            started: now,
            last_frame: now,
            script: args.script_frames,
            screenshot_requested: false,
            screenshots: 0,
        })
    }

    fn window_event(
        &mut self,
        event_loop: &ActiveEventLoop,
        args: &Args,
        event: WindowEvent,
    ) -> Result<()> {
        let response = self.egui_state.on_window_event(&self.window, &event);
        let egui_pointer = self.overlay && self.egui_ctx.egui_wants_pointer_input();
        let egui_keys = self.overlay && self.egui_ctx.egui_wants_keyboard_input();
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::RedrawRequested => self.frame(event_loop, args)?,
            WindowEvent::ModifiersChanged(m) => self.shift = m.state().shift_key(),
            WindowEvent::Focused(false) => {
                self.keys.clear();
                self.looking = false;
            }
            WindowEvent::KeyboardInput { event, .. } => {
                let PhysicalKey::Code(code) = event.physical_key else {
                    return Ok(());
                };
                if event.state == ElementState::Released {
                    self.keys.remove(&code);
                } else if !(egui_keys || response.consumed && code == KeyCode::Tab) {
                    self.keys.insert(code);
                    if !event.repeat {
                        self.key(event_loop, code);
                    }
                }
            }
            WindowEvent::MouseInput { state, button, .. } => {
                if matches!(button, MouseButton::Left | MouseButton::Right) {
                    self.looking = state == ElementState::Pressed && !egui_pointer;
                }
            }
            WindowEvent::CursorMoved { position, .. } => {
                let now = (position.x, position.y);
                if let (true, Some(before)) = (self.looking, self.cursor)
                    && self.script.is_none()
                {
                    let (dx, dy) = ((now.0 - before.0) as f32, (now.1 - before.1) as f32);
                    self.camera.look(dx * LOOK_PER_PIXEL, -dy * LOOK_PER_PIXEL);
                }
                self.cursor = Some(now);
            }
            WindowEvent::CursorLeft { .. } => self.cursor = None,
            WindowEvent::MouseWheel { delta, .. } if !egui_pointer => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => (p.y / 40.0) as f32,
                };
                self.camera.wheel(steps);
            }
            _ => {}
        }
        Ok(())
    }

    /// A key pressed (not a repeat) that the overlay did not take.
    fn key(&mut self, event_loop: &ActiveEventLoop, code: KeyCode) {
        let digit = [
            KeyCode::Digit0,
            KeyCode::Digit1,
            KeyCode::Digit2,
            KeyCode::Digit3,
            KeyCode::Digit4,
            KeyCode::Digit5,
            KeyCode::Digit6,
            KeyCode::Digit7,
            KeyCode::Digit8,
        ]
        .iter()
        .position(|&k| k == code);
        if let Some(i) = digit {
            self.view = DebugView::ALL[i];
            return;
        }
        match code {
            KeyCode::Escape => event_loop.exit(),
            KeyCode::KeyP => {
                self.path = match self.path {
                    RenderPath::Deferred => RenderPath::Baseline,
                    RenderPath::Baseline => RenderPath::PixelPull,
                    _ => RenderPath::Deferred,
                }
            }
            KeyCode::KeyV => self.view = self.view.cycle(if self.shift { -1 } else { 1 }),
            KeyCode::KeyM => {
                self.wanted.msaa = match self.wanted.msaa {
                    None => Some(MsaaLighting::Kz2),
                    Some(MsaaLighting::Kz2) => Some(MsaaLighting::EverySample),
                    Some(MsaaLighting::EverySample) => None,
                }
            }
            KeyCode::KeyL => {
                self.wanted.light_paths = match self.wanted.light_paths {
                    LightPaths::Tiled => LightPaths::Classified,
                    LightPaths::Classified => LightPaths::Volumes,
                    LightPaths::Volumes => LightPaths::EveryPixel,
                    LightPaths::EveryPixel => LightPaths::Tiled,
                }
            }
            KeyCode::KeyO => {
                self.wanted.shadows = match self.wanted.shadows {
                    Some(_) => None,
                    None => Some(gpu::config::ShadowConfig::default()),
                }
            }
            KeyCode::KeyC => {
                if let Some(s) = &mut self.statics {
                    let i = OCCLUSIONS
                        .iter()
                        .position(|(o, _)| *o == s.occlusion)
                        .map_or(0, |i| (i + 1) % OCCLUSIONS.len());
                    s.occlusion = OCCLUSIONS[i].0;
                }
            }
            KeyCode::KeyR => self.camera = FlyCamera::new(self.home),
            KeyCode::F1 => self.overlay = !self.overlay,
            KeyCode::F12 => self.screenshot_requested = true,
            _ => {}
        }
    }

    /// Moves the camera by the held keys over `seconds`.
    fn fly(&mut self, seconds: f32) {
        let held = |k: KeyCode| f32::from(u8::from(self.keys.contains(&k)));
        let fast = if self.shift { 4.0 } else { 1.0 };
        self.camera.fly(
            held(KeyCode::KeyD) - held(KeyCode::KeyA),
            held(KeyCode::KeyE) - held(KeyCode::KeyQ),
            held(KeyCode::KeyW) - held(KeyCode::KeyS),
            seconds * fast,
        );
    }

    /// Makes a renderer of `self.wanted` and prepares the scene on it; on failure keeps
    /// the old one and says why.
    fn rebuild(&mut self) {
        let wanted = self.wanted.clone();
        let t = Instant::now();
        let made = gpu::inspect::scoped(&self.device, || {
            let r = Renderer::new(&self.device, &self.queue, wanted.clone())?;
            let p = r.prepare(&self.loaded.scene)?;
            Ok((r, p))
        });
        match made {
            Ok((r, p)) => {
                // Let the old renderer's frames finish before its buffers go.
                let _ = gpu::inspect::wait_idle(&self.device);
                self.renderer = r;
                self.prepared = p;
                self.debug = None;
                self.stats = None;
                self.message = Some(format!(
                    "renderer rebuilt at {}x{} and scene prepared in {:.0} ms",
                    wanted.width,
                    wanted.height,
                    t.elapsed().as_secs_f64() * 1e3
                ));
            }
            Err(e) => {
                self.message = Some(format!("kept the previous renderer: {e}"));
                // A failed resize keeps the old size until the window changes again.
                self.wanted = self.renderer.config().clone();
            }
        }
    }

    fn configure_surface(&mut self, size: PhysicalSize<u32>) {
        self.surface_config.width = size.width;
        self.surface_config.height = size.height;
        self.surface.configure(&self.device, &self.surface_config);
    }

    fn frame(&mut self, event_loop: &ActiveEventLoop, args: &Args) -> Result<()> {
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
            && (self.wanted.width, self.wanted.height) != (size.width, size.height)
            && size.width <= self.device.limits().max_texture_dimension_2d
            && size.height <= self.device.limits().max_texture_dimension_2d
        {
            self.wanted.width = size.width;
            self.wanted.height = size.height;
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
        let (width, height) = (self.renderer.config().width, self.renderer.config().height);
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
            let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("view blit and overlay"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &target,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            let mut pass = pass.forget_lifetime();
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
                (self.renderer.output_view(), (c.width, c.height))
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

    /// The classification counters, read back every [`REFRESH`] while they are switched
    /// on (deferred frames only).
    fn refresh_stats(&mut self, path: RenderPath) {
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
    fn ui(&mut self, ctx: &egui::Context) {
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
                    c.width,
                    c.height,
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
                    .selected_text(msaa_name(self.wanted.msaa))
                    .show_ui(ui, |ui| {
                        for m in [None, Some(MsaaLighting::Kz2), Some(MsaaLighting::EverySample)] {
                            ui.selectable_value(&mut self.wanted.msaa, m, msaa_name(m));
                        }
                    });
                egui::ComboBox::from_label("light paths (L)")
                    .selected_text(light_paths_name(self.wanted.light_paths))
                    .show_ui(ui, |ui| {
                        for l in [
                            LightPaths::Tiled,
                            LightPaths::Classified,
                            LightPaths::Volumes,
                            LightPaths::EveryPixel,
                        ] {
                            ui.selectable_value(
                                &mut self.wanted.light_paths,
                                l,
                                light_paths_name(l),
                            );
                        }
                    });
                ui.horizontal(|ui| {
                    let mut sun = self.wanted.shadows.is_some();
                    if ui.checkbox(&mut sun, "sun shadows (O)").changed() {
                        self.wanted.shadows = sun.then(gpu::config::ShadowConfig::default);
                    }
                    let mut spots = self.wanted.spot_shadows.is_some();
                    if ui.checkbox(&mut spots, "spot shadows").changed() {
                        self.wanted.spot_shadows = spots.then(gpu::config::SpotShadowConfig::default);
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
                let s = self.prepared.summary();
                let lights = self.renderer.inspect().light_path_counts();
                let uploads = self.renderer.inspect().upload_stats();
                egui::Grid::new("counters")
                    .striped(true)
                    .num_columns(2)
                    .show(ui, |ui| {
                        let mut row = |k: &str, v: String| {
                            ui.label(k);
                            ui.label(v);
                            ui.end_row();
                        };
                        row("instances", s.instances.to_string());
                        row("triangles", s.triangles.to_string());
                        row(
                            "micro batches / passes",
                            format!("{} / {}", s.micro_batches, s.passes),
                        );
                        row(
                            "local lights",
                            (self.lighting.point_lights.len() + self.lighting.spot_lights.len())
                                .to_string(),
                        );
                        row(
                            "lights tiled / volumes",
                            format!("{} / {}", lights.tiled, lights.volumes),
                        );
                        row("spot shadow maps", lights.spot_shadow_maps.to_string());
                        row(
                            "uploads",
                            format!("{} B in {} blocks", uploads.bytes, uploads.blocks.len()),
                        );
                        if let Some((st, _)) = &self.stats {
                            row("vis pixels", st.vis_pixels.to_string());
                            row("tile groups", st.tile_groups.to_string());
                            row("pixel commands", st.pixel_commands.to_string());
                            row(
                                "wave commands",
                                format!("{} (width {})", st.wave_commands, st.wave_width),
                            );
                            row("unfilled lanes", st.unfilled_lanes.to_string());
                            row("depth-equal waves (HZD)", st.depth_equal_waves.to_string());
                            row(
                                "vertices after chunk culling",
                                format!("{} of {}", st.vertices_after_chunk_culling, st.scene_vertices),
                            );
                            row(
                                "GPU = CPU twin",
                                match st.gpu_matches_cpu {
                                    Some(true) => "yes",
                                    Some(false) => "NO",
                                    None => "-",
                                }
                                .to_string(),
                            );
                        }
                    });
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
