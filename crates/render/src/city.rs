//! The city: HZD's static world streamed into the GPU static query, its frames with the
//! query in front (and `--occlusion`'s HiZ), its images, debug views and report, then
//! HZD's own mode (the query read back and planned on the CPU) on the same view.

use anyhow::Result;
use gpu::{RenderPath, Renderer};

use crate::args::{Args, OcclusionArg};
use crate::config::with_lights;
use crate::outputs::{compare_with_baseline, report_lighting};
use crate::report::Report;

/// The city: streamed into the GPU static query, prepared with its static setups, rendered
/// with the query in front of the frame (optionally with occlusion: `--occlusion`); images
/// and the query's statistics.
pub(crate) fn render_city(
    args: &Args,
    ctx: &gpu::GpuContext,
    renderer: &mut Renderer,
) -> Result<()> {
    use gpu::staticscene::{HiZ, QueryOptions};
    let t0 = std::time::Instant::now();
    let city = demo::city::city(args.instances as usize);
    let mut query = gpu::statics::StaticQuery::new(&ctx.device, &ctx.queue)?;
    let mut cpu = gpu::statics::stream_static_world(
        &ctx.device,
        &ctx.queue,
        &mut query,
        &city.world.resources,
        &city.world.groups,
    )?;
    let build_ms = t0.elapsed().as_secs_f64() * 1e3;
    let t1 = std::time::Instant::now();
    let prepared = renderer.prepare(&city.scene)?;
    let prepare_ms = t1.elapsed().as_secs_f64() * 1e3;
    let frame = with_lights(args, city.frame.clone(), 60.0);
    let mut report = Report::new(ctx, renderer, &prepared);
    report.indirect_validation(args.indirect_validation);
    report.cpu_ms("city build, tiles built and activated (CPU)", build_ms);
    report.cpu_ms("prepare: meshes, reservations, upload (CPU)", prepare_ms);
    let paths: &[RenderPath] = match args.path {
        // The MSAA baseline takes no static frames (its HiZ would read single-sample
        // depth): the city's frames stay on the deferred path.
        _ if renderer.config().image.msaa.is_some() => {
            eprintln!("--msaa: the city's static frames render the deferred path only");
            &[RenderPath::Deferred]
        }
        path => path.paths(),
    };
    let (w, h) = (args.width, args.height);
    let mut desc = gpu::statics::static_view_desc(&frame.camera, w, h);
    let occlusion = match args.occlusion {
        OcclusionArg::Off | OcclusionArg::Readback => gpu::statics::StaticOcclusion::Given,
        OcclusionArg::Previous => gpu::statics::StaticOcclusion::PreviousFrame,
        OcclusionArg::TwoPass => gpu::statics::StaticOcclusion::TwoPass,
    };
    // A freshly streamed city fades in over `fade_frames` frames: render them first, so
    // the measured frames (whose warm-up is 0.5 s, a few frames on a slow adapter) and the
    // images of both paths show it settled, not at different steps of the dither. With
    // `readback`, the last of them (at least one) is the previous frame whose depth is read
    // back and reduced into the HiZ the measured frames test against (the camera holds
    // still).
    let readback = args.occlusion == OcclusionArg::Readback;
    for _ in 0..desc.fade_frames.max(u32::from(readback)) {
        let mut view = static_view(&mut query, &mut cpu, desc, occlusion);
        renderer.render_static(&prepared, &frame, RenderPath::Deferred, &mut view)?;
    }
    if readback {
        let hiz = HiZ::build(&renderer.inspect().read_depth()?, w, h, true)?;
        query.set_hiz(&ctx.device, &ctx.queue, Some(&hiz))?;
        desc.occlusion_camera = Some(desc.camera);
    }
    let mut images = Vec::new();
    for &path in paths {
        let mut view = static_view(&mut query, &mut cpu, desc, occlusion);
        let frames = if args.walk > 0.0 {
            let base = frame.clone();
            let ahead = (base.camera.target - base.camera.position).normalize();
            let occlusion_camera = desc.occlusion_camera.is_some();
            renderer.render_static_sequence(&prepared, path, &mut view, args.frames, |i| {
                let step = ahead * args.walk * i as f32;
                let mut frame = base.clone();
                frame.camera.position += step;
                frame.camera.target += step;
                let mut d = gpu::statics::static_view_desc(&frame.camera, w, h);
                if occlusion_camera {
                    d.occlusion_camera = Some(d.camera);
                }
                (frame, d)
            })?
        } else {
            renderer.render_static_frames(&prepared, &frame, path, &mut view, args.frames)?
        };
        let image = renderer.read_output()?;
        let file = args.out.join(format!("city_{}.png", path.name()));
        image.write_png(&file)?;
        report.image(path, &file);
        report.timings(path, &frames);
        report.laydown_ran(path, renderer, &frames);
        if path == RenderPath::Deferred {
            report_lighting(args, &mut report, renderer, &frame, "city")?;
        }
        if let (Some(s), true) = (&frames.statics, images.is_empty()) {
            report.static_query(s, cpu.instance_count() as u64);
            report.static_shadows(s);
        }
        if path == RenderPath::Deferred {
            let classified = renderer.inspect().read_classification(&prepared)?;
            let (stats, mismatch) = renderer
                .inspect()
                .classification_statistics(&prepared, &classified)?;
            report.classification(&stats);
            if !args.no_debug_views {
                let file = args.out.join("city_debug_vis_ids.png");
                gpu::inspect::debug::vis_ids(w, h, &classified.vis).write_png(&file)?;
                report.image_named("vis IDs", &file);
                let statics = renderer.inspect().read_static_debug(&prepared)?;
                let file = args.out.join("city_debug_lod_fade.png");
                gpu::inspect::debug::static_lod_fade(w, h, &classified.vis, &statics)
                    .write_png(&file)?;
                report.image_named("static setups and LOD fade", &file);
                if args.occlusion == OcclusionArg::TwoPass {
                    let file = args.out.join("city_debug_two_pass.png");
                    gpu::inspect::debug::static_two_pass(w, h, &classified.vis, &statics)
                        .write_png(&file)?;
                    report.image_named("two-pass: drawn early / found late", &file);
                }
            }
            if let Some(m) = &mismatch {
                print!("{report}");
                anyhow::bail!("the GPU classification differs from its CPU twin: {m}");
            }
        }
        images.push(image);
    }
    compare_with_baseline(&mut report, paths, &images);
    if args.occlusion != OcclusionArg::Off && !args.no_debug_views {
        let (texels, size) = query.read_hiz(&ctx.device, &ctx.queue)?;
        let file = args.out.join("city_debug_hiz.png");
        gpu::inspect::debug::hiz_mips(&texels, size).write_png(&file)?;
        report.image_named("HiZ mips the query tested against", &file);
    }
    if args.occlusion != OcclusionArg::Off && !args.no_debug_views && args.walk == 0.0 {
        // What occlusion culls, from the CPU twin on this view: without occlusion, and
        // against the last frame's depth (the camera holds still).
        let hiz = HiZ::build(&renderer.inspect().read_depth()?, w, h, true)?;
        let mut off_view = desc;
        off_view.occlusion_camera = None;
        let mut on_view = desc;
        on_view.occlusion_camera = Some(desc.camera);
        let mut outputs = Vec::new();
        for (view, hiz) in [(off_view, None), (on_view, Some(&hiz))] {
            let mut out = gpu::staticscene::QueryOutput::new();
            cpu.clone().query(
                &gpu::staticscene::QueryParams::new(&view)?,
                hiz,
                &QueryOptions::default(),
                &mut out,
            )?;
            outputs.push(out);
        }
        let overlay = gpu::inspect::debug::occlusion_overlay(
            &images[0],
            &cpu,
            &gpu::staticscene::QueryParams::new(&desc)?,
            &outputs[0].instances,
            &outputs[1].instances,
        );
        let file = args.out.join("city_debug_occlusion.png");
        overlay.write_png(&file)?;
        report.image_named("occlusion: drawn (green) / culled (red)", &file);
    }
    // HZD's mode on the same view: the CPU waits for the query, reads its batches back
    // and plans them (tiling::build_plan at prepare), then renders them as any scene.
    let params = gpu::staticscene::QueryParams::new(&desc)?;
    let t = std::time::Instant::now();
    let out = query.run(
        &ctx.device,
        &ctx.queue,
        &mut cpu,
        &params,
        &QueryOptions::default(),
        gpu::statics::QueryReadback::Full,
    )?;
    let read_ms = t.elapsed().as_secs_f64() * 1e3;
    let t = std::time::Instant::now();
    let planned = gpu::statics::scene_from_query(&city.scene, &out, &params)?;
    let prepared_hzd = renderer.prepare(&planned)?;
    let plan_ms = t.elapsed().as_secs_f64() * 1e3;
    let frames =
        renderer.render_frames(&prepared_hzd, &frame, RenderPath::Deferred, args.frames)?;
    report.cpu_ms("HZD's mode: query, wait, read back (wall)", read_ms);
    report.cpu_ms(
        "HZD's mode: batches planned (tiling::build_plan) and uploaded (CPU)",
        plan_ms,
    );
    report.gpu_frame_ms(
        "HZD's mode: deferred frame on the planned batches (GPU)",
        &frames,
    );
    print!("{report}");
    Ok(())
}

/// The city's static view of one frame: `desc` with the query's default options.
fn static_view<'a>(
    query: &'a mut gpu::statics::StaticQuery,
    scene: &'a mut gpu::staticscene::Scene,
    desc: gpu::staticscene::ViewDesc,
    occlusion: gpu::statics::StaticOcclusion,
) -> gpu::statics::StaticView<'a> {
    gpu::statics::StaticView {
        query,
        scene,
        view: desc,
        options: gpu::staticscene::QueryOptions::default(),
        occlusion,
    }
}
