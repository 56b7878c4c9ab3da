//! The window, the device on it, the frame loop and the overlay.
//!
//! One device serves the renderer, the blit and egui: it is requested from an adapter that
//! can present to the window's surface, with every optional feature of
//! [`gpu::Renderer::optional_features`] the adapter has and the adapter's own limits (as
//! [`gpu::headless`] does), which cover [`gpu::Renderer::required_limits`] at every size
//! the adapter supports: a resize makes a new renderer, never a new device.
//!
//! Here the window, its device and the viewer's state (made once, rebuilt on a change of
//! configuration); by concern beside it: `input` (window events, keys, the fly camera's
//! movement), `frame` (one frame: render, debug view, overlay, blit, present,
//! screenshots) and `overlay` (the egui window and the averaged timings it shows).

mod frame;
mod input;
mod overlay;

use std::collections::HashSet;
use std::sync::{Arc, Mutex};
use std::time::Instant;

use anyhow::{Context as _, Result, anyhow};
use gpu::inspect::ClassificationStats;
use gpu::{FrameOutput, PreparedScene, RenderPath, Renderer, RendererConfig};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::KeyCode;
use winit::window::{Window, WindowId};

use crate::blit::Blit;
use crate::camera::FlyCamera;
use crate::views::DebugView;
use crate::{Args, LoadedScene};
use overlay::Averages;

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
                    wanted.image.width,
                    wanted.image.height,
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
}
