//! Timing experiment: the classification phases with parts of their WGSL switched off or
//! replaced, on one demo scene, to see where the time goes. Variants that drop work give
//! wrong commands; only the timings mean anything. Run on a GPU with timestamps:
//!
//! ```sh
//! cargo run --release -p gpu --example classify_variants -- 3840 2160 forest
//! ```

use gpu::context::{self, HeadlessOptions};
use gpu::demo::{self, DemoOptions, DemoScene};
use gpu::renderer::{RenderPath, Renderer, RendererConfig};

fn replaced(src: &str, pairs: &[(&str, &str)]) -> String {
    let mut s = src.to_string();
    for (a, b) in pairs {
        assert!(s.contains(a), "pattern not found: {a}");
        s = s.replace(a, b);
    }
    s
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let width = args.get(1).map_or(Ok(3840), |a| a.parse())?;
    let height = args.get(2).map_or(Ok(2160), |a| a.parse())?;
    let scene_kind = match args.get(3).map(String::as_str) {
        Some("grass") => DemoScene::Grass,
        _ => DemoScene::Forest,
    };
    let ctx = context::headless(&HeadlessOptions::default())?;
    println!("{}", ctx.adapter_line());
    let subgroups = ctx.paths.subgroup_size.is_some();
    let mut r = Renderer::new(
        &ctx.device,
        &ctx.queue,
        RendererConfig {
            width,
            height,
            ..RendererConfig::default()
        },
    )?;
    let scene = demo::build(&DemoOptions {
        scene: scene_kind,
        ..DemoOptions::default()
    });
    let prepared = r.prepare(&scene)?;
    let features: &[&str] = if subgroups { &["subgroups"] } else { &[] };
    let mid = &tiling::wgsl::MID_CLASSIFY.source(features)?;
    let out = &tiling::wgsl::CLASSIFY_OUTPUT.source(features)?;
    let no_stats = [("atomicAdd(&tiling_wg_stats[field], n);", "")];
    let no_or = [(
        "atomicOr(&commands[at / 2u], cmd << ((at % 2u) * 16u));",
        "atomicStore(&commands[at / 2u], cmd);",
    )];
    let no_cull = [(
        "atomicOr(&vertex_cull[chunk / 4u], 1u << ((chunk % 4u) * 8u));",
        "",
    )];
    let no_index_reads = [(
        "tiling_first_of_run(gid.x, gid.y, word) && !tiling_mark_triangle(px)",
        "false",
    )];
    let key_loop = [(
        "const TILING_HIST_LIMIT: u32 = TILING_HIST_SLOTS;",
        "const TILING_HIST_LIMIT: u32 = 0u;",
    )];
    // Single-workgroup scans switched off: the buffers they write keep the previous
    // frame's (identical) values, so the other entry points still see valid offsets.
    let dummy = |src: &str, entries: &[&str]| {
        let mut s = src.to_string();
        for e in entries {
            let a = format!("fn {e}(");
            assert!(s.contains(&a), "entry point {e} not found");
            s = s.replace(&a, &format!("fn {e}_measured("));
            s.push_str(&format!("\n@compute @workgroup_size(1) fn {e}() {{}}\n"));
        }
        s
    };
    let variants: Vec<(&str, String, String)> = vec![
        (
            "as shipped (keyed histogram)",
            mid.to_string(),
            out.to_string(),
        ),
        (
            "wave-append key loop instead (the >256-counter path)",
            replaced(mid, &key_loop),
            replaced(out, &key_loop),
        ),
        (
            "no workgroup stats atomics",
            replaced(mid, &no_stats),
            replaced(out, &no_stats),
        ),
        (
            "no command atomicOr (plain store)",
            mid.to_string(),
            replaced(out, &no_or),
        ),
        (
            "no vertex-cull atomics",
            replaced(mid, &no_cull),
            out.to_string(),
        ),
        (
            "no index reads in mid (no vertex culling)",
            replaced(mid, &no_index_reads),
            out.to_string(),
        ),
        (
            "mid: count_pixels only",
            dummy(mid, &["counter_offsets_pass", "pixel_offsets_pass"]),
            out.to_string(),
        ),
        (
            "output: write_commands only",
            mid.to_string(),
            dummy(out, &["wave_offsets_pass", "write_waves"]),
        ),
        (
            "output: write_commands + write_waves",
            mid.to_string(),
            dummy(out, &["wave_offsets_pass"]),
        ),
    ];
    for (name, m, o) in &variants {
        r.set_classification_sources(m, o)?;
        let t = r.render_frames(&prepared, RenderPath::Deferred, 20)?;
        let get = |label: &str| {
            t.gpu
                .iter()
                .find(|x| x.label == label)
                .map_or(0.0, |x| x.ms)
        };
        let (mid_ms, out_ms) = (get("classify 2: mid classify"), get("classify 3: output"));
        let g = r.read_classification(&prepared)?;
        let (_, mismatch) = r.classification_statistics(&prepared, &g)?;
        println!(
            "{name:<45} mid {:>7.3} ms  output {:>7.3} ms  finalize {:>6.3} ms  equal to the CPU twin: {}",
            mid_ms,
            out_ms,
            get("classify 1: laydown finalize"),
            if mismatch.is_none() { "yes" } else { "no" }
        );
    }
    Ok(())
}
