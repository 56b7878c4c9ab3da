//! The viewer in a real window: the `view` binary runs under Xvfb (on lavapipe where there
//! is no GPU) for a few scripted frames from a fixed camera, writes its screenshot (the
//! window's blit, read back), and the screenshot must match a headless render of the same
//! scene and camera within the frame tests' thresholds (`gpu/tests/frame.rs`: mean
//! absolute error 1.0 / 255, 99th percentile 24 / 255).
//!
//! Xvfb is required: without it the test fails and says how to install it
//! (`apt-get install -y xvfb`; `scripts/ensure-env` does so as root).

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use demo::{DemoOptions, DemoScene};
use gpu::glam::Vec3;
use gpu::inspect::diff_metrics;
use gpu::{Camera, FrameInput, RenderPath, Renderer, RendererConfig, Rgba8Image};
use testkit::device::ctx;

/// The frame tests' thresholds (`gpu/tests/frame.rs`), for the viewer and the headless
/// render on one adapter.
const MAX_MEAN_ERROR: f64 = 1.0;
const MAX_P99_ERROR: u8 = 24;

/// The golden images' bounds across adapters (`gpu/tests/frame.rs`), for a machine whose
/// window adapter is not the headless one (a GPU that cannot present to Xvfb leaves the
/// viewer on lavapipe while the headless device takes the GPU).
const CROSS_ADAPTER_MEAN_ERROR: f64 = 3.0;
const CROSS_ADAPTER_P99_ERROR: u8 = 96;

const WIDTH: u32 = 320;
const HEIGHT: u32 = 180;
const FRAMES: u32 = 4;
const EYE: Vec3 = Vec3::new(2.0, 3.0, 14.0);
const TARGET: Vec3 = Vec3::new(0.0, 1.0, 0.0);

/// An X server of its own (the display number Xvfb picks, `-displayfd`), killed on drop.
struct Xvfb {
    child: Child,
    display: String,
}

impl Xvfb {
    fn start() -> Xvfb {
        let spawned = Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                "1280x1024x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn();
        let mut child = match spawned {
            Ok(c) => c,
            Err(e) => panic!(
                "cannot start Xvfb ({e}): the viewer test needs an X server. Install it:\n    \
                 apt-get install -y xvfb libx11-xcb1 libxcursor1 libxi6 libxkbcommon-x11-0\n\
                 (Debian/Ubuntu, as root; scripts/test does this through scripts/ensure-env \
                 when run as root)"
            ),
        };
        let mut line = String::new();
        let stdout = child.stdout.take().expect("piped stdout");
        BufReader::new(stdout)
            .read_line(&mut line)
            .expect("reading Xvfb's display number");
        let number = line.trim();
        assert!(
            !number.is_empty() && number.bytes().all(|b| b.is_ascii_digit()),
            "Xvfb did not report a display number (got {line:?})"
        );
        Xvfb {
            display: format!(":{number}"),
            child,
        }
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Runs the viewer on `display` (the forest, unless `extra` names a scene) with `extra`
/// flags after the scripted ones; returns its screenshot and whether it ran on the headless
/// device's adapter.
fn run_viewer(display: &str, name: &str, extra: &[&str]) -> (Rgba8Image, bool) {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("view-xvfb");
    std::fs::create_dir_all(&dir).unwrap();
    let shot = dir.join(format!("{name}.png"));
    let _ = std::fs::remove_file(&shot);
    let camera = format!(
        "{},{},{},{},{},{}",
        EYE.x, EYE.y, EYE.z, TARGET.x, TARGET.y, TARGET.z
    );
    let (w, h, frames) = (WIDTH.to_string(), HEIGHT.to_string(), FRAMES.to_string());
    let mut args = vec![];
    if !extra.contains(&"--scene") {
        args.extend(["--scene", "forest"]);
    }
    args.extend([
        "--width",
        &w,
        "--height",
        &h,
        "--script-frames",
        &frames,
        "--camera",
        &camera,
        "--screenshot",
        shot.to_str().unwrap(),
        "--exit",
    ]);
    args.extend_from_slice(extra);
    let mut child = Command::new(env!("CARGO_BIN_EXE_view"))
        .args(&args)
        .env("DISPLAY", display)
        .env_remove("WAYLAND_DISPLAY")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("starting the view binary: {e}"));
    let deadline = Instant::now() + Duration::from_secs(300);
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("view {args:?} ran for more than 300 s");
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let out = child.wait_with_output().unwrap();
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(
        status.success(),
        "view {args:?} failed ({status}):\n{stdout}\n{stderr}\n(winit needs the X11 client \
         libraries: apt-get install -y libx11-xcb1 libxcursor1 libxi6 libxkbcommon-x11-0, \
         which scripts/ensure-env does as root)"
    );
    eprint!("{stdout}");
    let same_adapter = stdout.contains(&format!(" on {}:", ctx().adapter_line()));
    (read(&shot), same_adapter)
}

fn read(path: &Path) -> Rgba8Image {
    Rgba8Image::read_png(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The headless renderer at the scripted size, in the viewer's default configuration.
fn headless_renderer() -> Renderer {
    let c = ctx();
    let config = RendererConfig::sized(WIDTH, HEIGHT);
    Renderer::new(&c.device, &c.queue, config).unwrap_or_else(|e| panic!("{e}"))
}

/// The scripted camera's still frame (`--camera`, time 0) under `lighting`.
fn scripted_frame(lighting: gpu::Lighting) -> FrameInput {
    FrameInput {
        camera: Camera::look_at(EYE, TARGET),
        time: 0.0,
        lighting,
    }
}

/// The same scene, camera and configuration on the headless device.
fn headless(path: RenderPath) -> (Renderer, gpu::PreparedScene, FrameInput) {
    let (scene, demo_frame) = demo::build(&DemoOptions {
        scene: DemoScene::Forest,
        ..DemoOptions::default()
    });
    let mut r = headless_renderer();
    let prepared = r.prepare(&scene).unwrap_or_else(|e| panic!("{e}"));
    let frame = scripted_frame(demo_frame.lighting);
    r.render(&prepared, &frame, path)
        .unwrap_or_else(|e| panic!("{e}"));
    (r, prepared, frame)
}

fn assert_close(what: &str, (window, same_adapter): &(Rgba8Image, bool), reference: &Rgba8Image) {
    let (max_mean, max_p99) = if *same_adapter {
        (MAX_MEAN_ERROR, MAX_P99_ERROR)
    } else {
        eprintln!("{what}: the window's adapter is not the headless one: cross-adapter bounds");
        (CROSS_ADAPTER_MEAN_ERROR, CROSS_ADAPTER_P99_ERROR)
    };
    assert_eq!(
        (window.width, window.height),
        (reference.width, reference.height),
        "{what}: the screenshot's size"
    );
    let (mean, _) = diff_metrics(window, reference, 0.5).unwrap();
    let (_, p99) = diff_metrics(window, reference, 0.99).unwrap();
    let differing = window
        .pixels
        .iter()
        .zip(&reference.pixels)
        .filter(|(a, b)| a != b)
        .count();
    eprintln!(
        "{what} on {}: window vs headless mean {mean:.3} / 255, p99 {p99} / 255, {differing} \
         of {} pixels differ",
        ctx().adapter_line(),
        window.pixels.len()
    );
    assert!(
        mean <= max_mean && p99 <= max_p99,
        "{what}: window vs headless mean {mean:.3} (max {max_mean}), p99 {p99} (max {max_p99})"
    );
    let colours: std::collections::BTreeSet<[u8; 4]> = window.pixels.iter().copied().collect();
    assert!(colours.len() > 500, "{what}: {} colours", colours.len());
}

/// Both paths and a debug view through the window, each against its headless twin.
#[test]
fn the_viewer_under_xvfb_shows_what_the_headless_renderer_renders() {
    let x = Xvfb::start();

    let window = run_viewer(&x.display, "forest_deferred", &[]);
    let (r, _, _) = headless(RenderPath::Deferred);
    assert_close("deferred", &window, &r.read_output().unwrap());

    let window = run_viewer(&x.display, "forest_baseline", &["--path", "baseline"]);
    let (r, _, _) = headless(RenderPath::Baseline);
    assert_close("baseline", &window, &r.read_output().unwrap());

    // A debug view is shown instead of the image: the vis IDs, exact up to rasterisation.
    let window = run_viewer(&x.display, "forest_vis_ids", &["--debug-view", "vis-ids"]);
    let (r, _, _) = headless(RenderPath::Deferred);
    let ids = gpu::inspect::debug::vis_ids(WIDTH, HEIGHT, &r.inspect().read_vis().unwrap());
    if window.1 {
        assert_close("vis IDs", &window, &ids);
    } else {
        // Another adapter rasterises edges differently, and an edge pixel's ID colour is
        // unrelated to its neighbour's: count the pixels instead.
        let same = window
            .0
            .pixels
            .iter()
            .zip(&ids.pixels)
            .filter(|(a, b)| a == b)
            .count();
        assert!(
            same * 10 >= ids.pixels.len() * 9,
            "vis IDs across adapters: {same} of {} pixels equal",
            ids.pixels.len()
        );
    }
}

/// The city through the window: HZD's static query in front of each of the scripted
/// frames (the LOD fade advancing frame by frame), against the same frames rendered
/// headless with the same query.
#[test]
fn the_city_through_the_window_is_the_headless_city() {
    let x = Xvfb::start();
    let window = run_viewer(
        &x.display,
        "city",
        &["--scene", "city", "--instances", "5000"],
    );
    let c = ctx();
    let city = demo::city::city(5000);
    let mut query = gpu::statics::StaticQuery::new(&c.device, &c.queue).unwrap();
    let mut scene = gpu::statics::stream_static_world(
        &c.device,
        &c.queue,
        &mut query,
        &city.world.resources,
        &city.world.groups,
    )
    .unwrap();
    let mut r = headless_renderer();
    let prepared = r.prepare(&city.scene).unwrap_or_else(|e| panic!("{e}"));
    let frame = scripted_frame(city.frame.lighting.clone());
    for _ in 0..FRAMES {
        let mut view = gpu::statics::StaticView {
            query: &mut query,
            scene: &mut scene,
            view: gpu::statics::static_view_desc(&frame.camera, WIDTH, HEIGHT),
            options: Default::default(),
            occlusion: gpu::statics::StaticOcclusion::PreviousFrame,
        };
        r.render_static(&prepared, &frame, RenderPath::Deferred, &mut view)
            .unwrap_or_else(|e| panic!("{e}"));
    }
    assert_close("city", &window, &r.read_output().unwrap());
}

/// Bad flags fail before any window opens, naming the flag (no display needed).
#[test]
fn bad_flags_are_named() {
    for (args, flag) in [
        (&["--camera", "1,2,3"][..], "--camera"),
        (&["--width", "0"][..], "--width"),
        (&["--exit"][..], "--script-frames"),
        (&["--density", "-1"][..], "--density"),
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_view"))
            .args(args)
            .env_remove("DISPLAY")
            .env_remove("WAYLAND_DISPLAY")
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} succeeded");
        assert!(stderr.contains(flag), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
}
