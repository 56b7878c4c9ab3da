//! `render`: the README's main command. Renders a procedural demo scene through the full
//! pipeline (deferred texturing, the depth-equal baseline, or both), writes the image and
//! its debug views as PNGs, and prints the statistics table.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::{Parser, ValueEnum};

use gpu::context::{self, HeadlessOptions, PrimitiveIdPath};
use gpu::demo::{self, DemoOptions, DemoScene};
use gpu::renderer::{RenderPath, Renderer, RendererConfig};

#[derive(Clone, Copy, Debug, ValueEnum)]
enum SceneArg {
    /// Alpha-tested foliage cards, grass tufts, trees and rocks over a terrain.
    Forest,
    /// A tall-grass field of very high vertex density.
    Grass,
    /// Both, one after the other (the same renderer and device).
    All,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum PathArg {
    /// Visibility buffer, GPU classification, compute material resolve (HFW).
    Deferred,
    /// Depth prepass + depth-equal geometry pass (HZD), the method the talk replaces.
    Baseline,
    /// Both, on the same scene, with an image comparison.
    Both,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum PrimitiveIdArg {
    /// The best the adapter supports.
    Auto,
    /// `@builtin(primitive_index)`.
    Builtin,
    /// HFW's XOR of per-vertex payloads.
    Xor,
    /// A flat payload on the provoking vertex.
    Provoking,
}

/// Render a procedural demo scene with HFW's deferred texturing and/or HZD's depth-equal
/// baseline; write PNGs and print statistics.
#[derive(Debug, Parser)]
#[command(version, about)]
struct Args {
    /// Which demo scene.
    #[arg(long, value_enum, default_value = "all")]
    scene: SceneArg,
    /// Image width in pixels.
    #[arg(long, default_value_t = 1280)]
    width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 720)]
    height: u32,
    /// Output directory for the PNGs.
    #[arg(long, default_value = "out")]
    out: PathBuf,
    /// Which rendering path.
    #[arg(long, value_enum, default_value = "both")]
    path: PathArg,
    /// Frames to measure, after 0.5 s of warm-up frames (timings are their mean).
    #[arg(long, default_value_t = 3)]
    frames: u32,
    /// Scene seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Instance density multiplier (1.0 renders in seconds on lavapipe).
    #[arg(long, default_value_t = 1.0)]
    density: f32,
    /// How the laydown gets primitive IDs.
    #[arg(long, value_enum, default_value = "auto")]
    primitive_id: PrimitiveIdArg,
    /// Use the workgroup-atomic fallback even where subgroups exist.
    #[arg(long)]
    no_subgroups: bool,
    /// Skip writing the debug views.
    #[arg(long)]
    no_debug_views: bool,
}

fn main() -> Result<()> {
    let args = Args::parse();
    if args.width == 0 || args.height == 0 || args.width > 16384 || args.height > 16384 {
        anyhow::bail!(
            "--width and --height must be in 1..=16384 (got {}x{})",
            args.width,
            args.height
        );
    }
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;

    let mut disable = wgpu::Features::empty();
    if args.no_subgroups {
        disable |= wgpu::Features::SUBGROUP;
    }
    let ctx = context::headless(&HeadlessOptions {
        disable_features: disable,
        ..Default::default()
    })?;
    let primitive_id = match args.primitive_id {
        PrimitiveIdArg::Auto => None,
        PrimitiveIdArg::Builtin => Some(PrimitiveIdPath::Builtin),
        PrimitiveIdArg::Xor => Some(PrimitiveIdPath::PerVertexXor),
        PrimitiveIdArg::Provoking => Some(PrimitiveIdPath::ProvokingVertex),
    };
    let config = RendererConfig {
        width: args.width,
        height: args.height,
        primitive_id,
        ..RendererConfig::default()
    };
    let mut renderer = Renderer::new(&ctx.device, &ctx.queue, config)?;
    let scenes: &[DemoScene] = match args.scene {
        SceneArg::Forest => &[DemoScene::Forest],
        SceneArg::Grass => &[DemoScene::Grass],
        SceneArg::All => &DemoScene::ALL,
    };
    for (k, &scene_kind) in scenes.iter().enumerate() {
        if k > 0 {
            println!();
        }
        println!("== {} ==", scene_kind.name());
        render_scene(&args, &ctx, &mut renderer, scene_kind)?;
    }
    Ok(())
}

/// Builds, prepares and renders one demo scene; writes its images; prints its report.
fn render_scene(
    args: &Args,
    ctx: &context::GpuContext,
    renderer: &mut Renderer,
    scene_kind: DemoScene,
) -> Result<()> {
    let t0 = std::time::Instant::now();
    let scene = demo::build(&DemoOptions {
        scene: scene_kind,
        seed: args.seed,
        density: args.density,
    });
    let build_ms = t0.elapsed().as_secs_f64() * 1e3;
    let t1 = std::time::Instant::now();
    let prepared = renderer.prepare(&scene)?;
    let prepare_ms = t1.elapsed().as_secs_f64() * 1e3;

    let paths: &[RenderPath] = match args.path {
        PathArg::Deferred => &[RenderPath::Deferred],
        PathArg::Baseline => &[RenderPath::Baseline],
        PathArg::Both => &[RenderPath::Deferred, RenderPath::Baseline],
    };
    let mut report = gpu::report::Report::new(ctx, &scene, renderer, &prepared);
    report.cpu_ms("scene build (CPU)", build_ms);
    report.cpu_ms(
        "prepare: encode meshes, micro batches, upload (CPU)",
        prepare_ms,
    );
    let mut images = Vec::new();
    for &path in paths {
        let frames = renderer.render_frames(&prepared, path, args.frames.max(1))?;
        let image = renderer.read_output()?;
        let file = args
            .out
            .join(format!("{}_{}.png", scene_kind.name(), path.name()));
        image.write_png(&file)?;
        report.image(path, &file);
        report.timings(path, &frames);
        let name = scene_kind.name();
        if path == RenderPath::Deferred {
            let t = std::time::Instant::now();
            let classified = renderer.read_classification(&prepared)?;
            let (stats, mismatch) = renderer.classification_statistics(&prepared, &classified)?;
            report.cpu_ms(
                "read-back + CPU twin + talk measurements (CPU)",
                t.elapsed().as_secs_f64() * 1e3,
            );
            report.classification(&stats);
            if let Some(m) = &mismatch {
                eprintln!("GPU classification differs from the CPU twin: {m}");
            }
            if !args.no_debug_views {
                let (w, h) = (args.width, args.height);
                let file = args.out.join(format!("{name}_debug_vis_ids.png"));
                gpu::debug::vis_ids(w, h, &classified.vis).write_png(&file)?;
                report.image_named("vis IDs", &file);
                let (heat, max) = gpu::debug::wave_heatmap(w, h, &classified);
                let file = args.out.join(format!("{name}_debug_waves_per_tile.png"));
                heat.write_png(&file)?;
                report.image_named(&format!("waves per tile (max {max})"), &file);
                let (quads, mean) = gpu::debug::quad_overdraw(w, h, &classified.vis);
                let file = args.out.join(format!("{name}_debug_quad_overdraw.png"));
                quads.write_png(&file)?;
                report.image_named(
                    &format!("depth-equal quad overdraw (mean {mean:.2})"),
                    &file,
                );
            }
            if mismatch.is_some() {
                print!("{report}");
                anyhow::bail!("the GPU classification differs from its CPU twin");
            }
        }
        images.push(image);
    }
    if let [deferred, baseline] = images.as_slice() {
        report.compare(deferred, baseline);
        let file = args.out.join(format!("{}_diff.png", scene_kind.name()));
        gpu::image::diff_image(deferred, baseline).write_png(&file)?;
        report.image_named("diff", &file);
    }
    print!("{report}");
    Ok(())
}
