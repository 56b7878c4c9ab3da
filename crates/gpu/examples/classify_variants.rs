//! Timing experiment: the classification phases with parts of their work switched off, on
//! one demo scene, to see where the time goes. Each variant composes `tiling`'s passes
//! with timing features, sets an `override` or leaves entry points out; variants that drop work give wrong commands,
//! only their timings mean anything. Run on a GPU with timestamps:
//!
//! ```sh
//! cargo run --release -p gpu --example classify_variants -- --width 3840 --height 2160 --scene forest
//! ```

use clap::{Parser, ValueEnum};
use demo::{DemoOptions, DemoScene};
use gpu::inspect::ClassificationVariant;
use gpu::{HeadlessOptions, RenderPath, Renderer, RendererConfig};

#[derive(Clone, Copy, Debug, ValueEnum)]
enum SceneArg {
    Forest,
    Grass,
    Hillside,
    HillsideGrass,
}

/// Time the classification's phases with parts of their WGSL switched off.
#[derive(Debug, Parser)]
#[command()]
struct Args {
    /// Image width in pixels.
    #[arg(long, default_value_t = 3840, value_parser = clap::value_parser!(u32).range(1..=16384))]
    width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 2160, value_parser = clap::value_parser!(u32).range(1..=16384))]
    height: u32,
    /// Demo scene.
    #[arg(long, value_enum, default_value = "forest")]
    scene: SceneArg,
    /// Frames measured per variant (after a 0.5 s warm-up).
    #[arg(long, default_value_t = 20, value_parser = clap::value_parser!(u32).range(1..=10_000))]
    frames: u32,
}

fn main() -> anyhow::Result<()> {
    let args = Args::parse();
    let ctx = gpu::headless(&HeadlessOptions::default())?;
    println!("{}", ctx.adapter_line());
    let mut r = Renderer::new(
        &ctx.device,
        &ctx.queue,
        RendererConfig::sized(args.width, args.height),
    )?;
    let (scene, frame) = demo::build(&DemoOptions {
        scene: match args.scene {
            SceneArg::Forest => DemoScene::Forest,
            SceneArg::Grass => DemoScene::Grass,
            SceneArg::Hillside => DemoScene::Hillside,
            SceneArg::HillsideGrass => DemoScene::HillsideGrass,
        },
        ..DemoOptions::default()
    });
    let prepared = r.prepare(&scene)?;
    let variant = |features: &[&'static str],
                   overrides: &[(&'static str, f64)],
                   skip: &[&'static str]| ClassificationVariant {
        features: features.to_vec(),
        overrides: overrides.to_vec(),
        skip: skip.to_vec(),
    };
    // Scans switched off keep the previous frame's (identical) values in the buffers they
    // write, so the other entry points still see valid offsets.
    let variants = [
        ("as shipped (keyed histogram)", variant(&[], &[], &[])),
        (
            "wave-append key loop instead (the >256-counter path)",
            variant(&[], &[("TILING_HIST_LIMIT", 0.0)], &[]),
        ),
        (
            "finalize: vis loads only",
            variant(&["timing_load_only"], &[], &[]),
        ),
        (
            "finalize: no table row (decode from the word)",
            variant(&["timing_no_table"], &[], &[]),
        ),
        (
            "no workgroup stats atomics",
            variant(&["timing_omit_stats"], &[], &[]),
        ),
        (
            "no command atomicOr (plain store)",
            variant(&["timing_store_commands"], &[], &[]),
        ),
        (
            "mid: no per-pixel records",
            variant(&["timing_omit_records"], &[], &[]),
        ),
        (
            "no vertex-cull atomics",
            variant(&["timing_omit_cull_marks"], &[], &[]),
        ),
        (
            "no index reads in mid (no vertex culling)",
            variant(&["timing_omit_index_reads"], &[], &[]),
        ),
        (
            "mid: count_pixels only",
            variant(&[], &[], &["counter_offsets_pass"]),
        ),
        (
            "mid: no append-loop code (tiles past 256 counters)",
            variant(&["timing_omit_append_loop"], &[], &[]),
        ),
        (
            "mid: neither index reads nor append-loop code",
            variant(
                &["timing_omit_index_reads", "timing_omit_append_loop"],
                &[],
                &[],
            ),
        ),
    ];
    for (name, v) in &variants {
        r.hooks().set_classification_variant(v)?;
        let t = r.render_frames(&prepared, &frame, RenderPath::Deferred, args.frames)?;
        let get = |label: &str| {
            t.gpu
                .iter()
                .find(|x| x.label == label)
                .map_or(0.0, |x| x.ms)
        };
        let g = r.inspect().read_classification(&prepared)?;
        let (_, mismatch) = r.inspect().classification_statistics(&prepared, &g)?;
        println!(
            "{name:<52} finalize {:>6.3}  mid {:>6.3} (count_pixels {:>6.3})  output {:>6.3} (with a mask write_commands, without scatter_write_waves {:>6.3}) ms  equal to the CPU twin: {}",
            get("laydown_finalize"),
            get("counter_offsets_pass") + get("count_pixels"),
            get("count_pixels"),
            get("pixel_offsets_pass")
                + get("write_commands")
                + get("entry_waves")
                + get("write_waves")
                + get("pixel_offsets_entry_waves")
                + get("scatter_write_waves"),
            get("write_commands") + get("scatter_write_waves"),
            if mismatch.is_none() { "yes" } else { "no" }
        );
    }
    Ok(())
}
