//! The scenes the arguments choose: the glTF file imported, the demo scenes built, the
//! river with its water bakes, each with the frame's lights, then rendered
//! ([`crate::outputs`]); the city has its own file ([`crate::city`]).

use std::path::Path;

use anyhow::{Context, Result};
use demo::DemoOptions;
use gpu::Renderer;

use crate::args::{Args, CameraArg, WaterPrecisionArg};
use crate::city::render_city;
use crate::config::with_lights;
use crate::outputs::{Built, render_scene};

/// The `--gltf` file imported (with a progress bar on stderr for a large one): its path,
/// what came of it and the import's CPU time in ms; `None` without `--gltf`.
///
/// # Errors
/// The file cannot be read or imported (the message names it).
pub(crate) fn import_gltf(args: &Args) -> Result<Option<(&Path, gltf_scene::Imported, f64)>> {
    Ok(match &args.gltf {
        Some(path) => {
            let t0 = std::time::Instant::now();
            // A progress bar on stderr for large files (small ones load in a blink).
            let large = std::fs::metadata(path).is_ok_and(|m| m.len() >= PROGRESS_BYTES);
            let mut bar = ProgressBar::default();
            let imported = gltf_scene::load_with_progress(
                path,
                &gltf_scene::LoadOptions::default(),
                &mut |p| {
                    if large {
                        bar.show(p);
                    }
                },
            )
            .with_context(|| format!("importing {}", path.display()))?;
            Some((path.as_path(), imported, t0.elapsed().as_secs_f64() * 1e3))
        }
        None => None,
    })
}

/// Renders what the arguments choose: the imported glTF file, else the demo scenes, then
/// the city and the river (each with its `== name ==` heading); writes the images; prints
/// the reports.
pub(crate) fn render_chosen(
    args: &Args,
    ctx: &gpu::GpuContext,
    renderer: &mut Renderer,
    mut every_sample: Option<&mut Renderer>,
    imported: Option<(&Path, gltf_scene::Imported, f64)>,
) -> Result<()> {
    if let Some((path, imported, build_ms)) = &imported {
        let gltf = (*path, imported, *build_ms);
        return render_gltf(args, ctx, renderer, every_sample, gltf);
    }
    for (k, &scene_kind) in args.scenes().iter().enumerate() {
        if k > 0 {
            println!();
        }
        println!("== {} ==", scene_kind.name());
        let t0 = std::time::Instant::now();
        let (mut scene, frame) = demo::build(&DemoOptions {
            scene: scene_kind,
            seed: args.seed,
            density: args.density,
        });
        scene.wind = (!args.no_wind).then(gpu::scene::Wind::default);
        if args.material_maps {
            demo::add_material_maps(&mut scene);
        }
        let frame = with_lights(args, frame, 25.0);
        let build_ms = t0.elapsed().as_secs_f64() * 1e3;
        let built = Built {
            name: scene_kind.name(),
            scene: &scene,
            frame: &frame,
            build: ("scene build (CPU)", build_ms),
            water: None,
        };
        render_scene(args, ctx, renderer, every_sample.as_deref_mut(), &built)?;
    }
    if args.city() {
        if !args.scenes().is_empty() {
            println!();
        }
        println!("== city ==");
        render_city(args, ctx, renderer)?;
    }
    if args.river() {
        if !args.scenes().is_empty() || args.city() {
            println!();
        }
        println!("== river ==");
        render_river(args, ctx, renderer, every_sample)?;
    }
    Ok(())
}

/// Files from this size on (bytes) show a progress bar while they import.
const PROGRESS_BYTES: u64 = 4 << 20;

/// A one-line text progress bar on stderr, redrawn when a step's percentage changes.
#[derive(Default)]
struct ProgressBar {
    last: Option<(gltf_scene::Stage, u64)>,
}

impl ProgressBar {
    fn show(&mut self, p: gltf_scene::Progress) {
        let percent = (p.done.min(p.total) * 100)
            .checked_div(p.total)
            .unwrap_or(100);
        if self.last == Some((p.stage, percent)) {
            return;
        }
        self.last = Some((p.stage, percent));
        let filled = (percent / 5) as usize;
        let stage = format!("{:?}", p.stage).to_lowercase();
        eprint!(
            "\rimporting: {stage:<8} [{}{}] {} / {}",
            "#".repeat(filled),
            "-".repeat(20 - filled),
            p.done,
            p.total
        );
        if percent == 100 {
            eprintln!();
        }
    }
}

/// A one-line progress bar on stderr for the water bakes (world, distance field, flow,
/// atlas), redrawn when a stage's percentage changes.
#[derive(Default)]
struct WaterProgressBar {
    last: Option<(gpu::water::Stage, u32)>,
}

impl WaterProgressBar {
    fn show(&mut self, p: gpu::water::Progress) -> std::ops::ControlFlow<()> {
        let percent = (p.fraction() * 100.0) as u32;
        if self.last == Some((p.stage, percent)) {
            return std::ops::ControlFlow::Continue(());
        }
        if self.last.is_some_and(|(s, pc)| s != p.stage && pc < 100) {
            eprintln!();
        }
        self.last = Some((p.stage, percent));
        let filled = (percent / 5) as usize;
        let stage = format!("{:?}", p.stage);
        eprint!(
            "\rwater bake: {stage:<16} [{}{}] {percent:3}%",
            "#".repeat(filled),
            "-".repeat(20 - filled),
        );
        if percent == 100 {
            eprintln!();
        }
        std::ops::ControlFlow::Continue(())
    }
}

/// The river: built (the water bakes behind a progress bar), given to the renderer as its
/// water, rendered as a demo scene with the water passes' statistics; the renderer's water
/// taken away after.
fn render_river(
    args: &Args,
    ctx: &gpu::GpuContext,
    renderer: &mut Renderer,
    every_sample: Option<&mut Renderer>,
) -> Result<()> {
    if renderer.config().image.msaa.is_some() {
        eprintln!("--msaa: the river renders without water (its passes are single-sample)");
    }
    let t0 = std::time::Instant::now();
    let mut bar = WaterProgressBar::default();
    let demo = demo::river::river(args.seed, args.density, &mut |p| bar.show(p))
        .context("building the river scene")?;
    let frame = with_lights(args, demo.frame.clone(), 40.0);
    let build_ms = t0.elapsed().as_secs_f64() * 1e3;
    let mut water = demo.water.clone();
    water.options.half_precision = args.water_precision == WaterPrecisionArg::F16;
    water.options.resolution_scale = args.water_scale;
    let built = Built {
        name: "river",
        scene: &demo.scene,
        frame: &frame,
        build: ("scene build and water bakes (CPU)", build_ms),
        water: (renderer.config().image.msaa.is_none()).then_some((&water, demo.decals.as_slice())),
    };
    let out = render_scene(args, ctx, renderer, every_sample, &built);
    renderer.set_water(None)?;
    out
}

/// A glTF file (`--gltf`) imported (its path, what came of it, the import's CPU time in
/// ms): prints the import summary and warnings, picks the camera (`--camera`), then renders
/// it as a demo scene: images, debug views, report.
fn render_gltf(
    args: &Args,
    ctx: &gpu::GpuContext,
    renderer: &mut Renderer,
    every_sample: Option<&mut Renderer>,
    (path, imported, build_ms): (&Path, &gltf_scene::Imported, f64),
) -> Result<()> {
    let name = path
        .file_stem()
        .map(|s| {
            s.to_string_lossy()
                .replace(|c: char| !c.is_ascii_alphanumeric() && c != '-', "_")
        })
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "gltf".to_owned());
    println!("== {name} (glTF) ==");
    println!("{}", imported.summary);
    // Each material's shader permutation (HFW's material shaders; glTF's maps).
    for (i, m) in imported.scene.materials.iter().enumerate() {
        println!(
            "  material {i} {:?}: metallic {:.2}, roughness {:.2}, {}",
            m.name,
            m.metallic,
            m.roughness,
            m.features().names().join(", ")
        );
    }
    for w in &imported.warnings {
        println!("  warning: {w}");
    }
    let aspect = args.width as f32 / args.height as f32;
    let auto = || gltf_scene::framing_camera(&imported.scene, aspect);
    let camera = match args.camera {
        CameraArg::File => imported.camera.unwrap_or_else(auto),
        CameraArg::Auto => auto(),
        CameraArg::LookAt { eye, target } => gpu::Camera::look_at(eye.into(), target.into()),
    };
    let which = match (args.camera, imported.camera) {
        (CameraArg::File, Some(_)) => "the file's",
        (CameraArg::LookAt { .. }, _) => "--camera's",
        _ => "framing the scene's bounds",
    };
    println!(
        "  camera ({which}): eye {:.2}, looking at {:.2}, {:.0}° vertical field of view",
        camera.position,
        camera.target,
        camera.fov_y.to_degrees()
    );
    // Lights over the square the framed view covers.
    let half_extent = (0.5 * camera.position.distance(camera.target)).clamp(1.0, 10_000.0);
    let frame = with_lights(args, gpu::FrameInput::new(camera), half_extent);
    let built = Built {
        name: &name,
        scene: &imported.scene,
        frame: &frame,
        build: (
            "glTF import: parse, decode, build the scene (CPU)",
            build_ms,
        ),
        water: None,
    };
    render_scene(args, ctx, renderer, every_sample, &built)
}
