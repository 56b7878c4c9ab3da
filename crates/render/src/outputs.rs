//! What a rendered scene leaves: its images (each path's, the diffs against the baseline)
//! and debug views as PNGs, and its statistics report ([`crate::report`]).

use anyhow::Result;
use gpu::{RenderPath, Renderer};

use crate::args::{Args, VrsArg};
use crate::report::Report;

/// A scene to render, built or imported.
pub(crate) struct Built<'a> {
    /// The images' file-name prefix.
    pub(crate) name: &'a str,
    pub(crate) scene: &'a gpu::Scene,
    pub(crate) frame: &'a gpu::FrameInput,
    /// What building it is called in the report, and its CPU time (ms).
    pub(crate) build: (&'a str, f64),
    /// Its water and this frame's decals, if any.
    pub(crate) water: Option<(&'a gpu::WaterScene, &'a [gpu::water_scene::WaterDecal])>,
}

/// Prepares and renders one scene; writes its images; prints its report.
pub(crate) fn render_scene(
    args: &Args,
    ctx: &gpu::GpuContext,
    renderer: &mut Renderer,
    mut every_sample: Option<&mut Renderer>,
    built: &Built<'_>,
) -> Result<()> {
    let (scene, frame) = (built.scene, built.frame);
    let t1 = std::time::Instant::now();
    let prepared = renderer.prepare(scene)?;
    let prepare_ms = t1.elapsed().as_secs_f64() * 1e3;

    let paths: &[RenderPath] = args.path.paths();
    let mut report = Report::new(ctx, renderer, &prepared);
    report.indirect_validation(args.indirect_validation);
    report.cpu_ms(built.build.0, built.build.1);
    report.cpu_ms(
        "prepare: encode meshes, micro batches, upload (CPU)",
        prepare_ms,
    );
    if let Some((water, decals)) = built.water {
        let summary = renderer.set_water(Some(water))?;
        renderer.set_water_decals(decals)?;
        if let Some(s) = summary {
            report.water_summary(&s);
        }
    }
    let mut images = Vec::new();
    for &path in paths {
        let frames = renderer.render_frames(&prepared, frame, path, args.frames)?;
        let image = renderer.read_output()?;
        let file = args.out.join(format!("{}_{}.png", built.name, path.name()));
        image.write_png(&file)?;
        report.image(path, &file);
        report.timings(path, &frames);
        report.laydown_ran(path, renderer, &frames);
        let name = built.name;
        if path == RenderPath::Baseline && renderer.config().image.msaa.is_some() {
            let edges = renderer.inspect().read_msaa_edges()?;
            if renderer.config().image.msaa == Some(gpu::config::MsaaLighting::Kz2) {
                report.msaa_edges(edges.len(), (args.width * args.height) as usize);
            }
            if let Some(r) = every_sample.as_deref_mut() {
                let p = r.prepare(scene)?;
                let t = r.render_frames(&p, frame, path, args.frames)?;
                report.timings_named("baseline, MSAA every sample", &t);
            }
        }
        if path == RenderPath::Deferred {
            // The same frames submitted back to back: the uploads of each in its own
            // blocks of the framealloc pool, no CPU wait between frames.
            // Warmed up as render_frames is: writing the image let the clocks fall.
            let warm = std::time::Instant::now();
            while warm.elapsed() < gpu::inspect::WARM_UP {
                renderer.submit(&prepared, frame, path)?;
            }
            let t = std::time::Instant::now();
            let mut in_flight = 0;
            let mut cpu_ms = 0.0;
            for _ in 0..args.frames {
                cpu_ms += renderer.submit(&prepared, frame, path)?.wall_ms;
                in_flight = in_flight.max(renderer.inspect().upload_stats().frames_in_flight);
            }
            renderer.wait()?;
            let n = f64::from(args.frames);
            let pipelined = t.elapsed().as_secs_f64() * 1e3 / n;
            report.frame_pacing(frames.wall_ms, pipelined, cpu_ms / n, in_flight);
            if let Some(s) = renderer.inspect().read_laydown_stats(&prepared)? {
                report.laydown_stats(&s);
            }
            if let Some(s) = renderer.inspect().water_stats()? {
                report.water_stats(&s);
            }
            report_lighting(args, &mut report, renderer, frame, name)?;
            let t = std::time::Instant::now();
            let classified = renderer.inspect().read_classification(&prepared)?;
            let (stats, mismatch) = renderer
                .inspect()
                .classification_statistics(&prepared, &classified)?;
            report.cpu_ms(
                "read-back + CPU twin + talk measurements (CPU)",
                t.elapsed().as_secs_f64() * 1e3,
            );
            report.classification(&stats);
            if let Some(ring) = renderer.inspect().read_vertex_ring(&prepared)? {
                report.vertex_ring(&ring, &stats);
            }
            if let Some(m) = &mismatch {
                eprintln!("GPU classification differs from the CPU twin: {m}");
            }
            if !args.no_debug_views {
                let (w, h) = (args.width, args.height);
                let file = args.out.join(format!("{name}_debug_vis_ids.png"));
                gpu::inspect::debug::vis_ids(w, h, &classified.vis).write_png(&file)?;
                report.image_named("vis IDs", &file);
                let (heat, max) = gpu::inspect::debug::wave_heatmap(w, h, &classified);
                let file = args.out.join(format!("{name}_debug_waves_per_tile.png"));
                heat.write_png(&file)?;
                report.image_named(&format!("waves per tile (max {max})"), &file);
                if args.vrs != VrsArg::Off {
                    let (rates, n) = gpu::inspect::debug::shading_rate(w, h, &classified.vis);
                    let file = args.out.join(format!("{name}_debug_shading_rate.png"));
                    rates.write_png(&file)?;
                    report.image_named(
                        &format!(
                            "VRS shading rate per pixel (1x1 dark green {}, 2x1 orange {}, 2x2 red {}; 1x2 blue {})",
                            n[0], n[2], n[3], n[1]
                        ),
                        &file,
                    );
                }
                let (quads, mean) = gpu::inspect::debug::quad_overdraw(w, h, &classified.vis);
                let file = args.out.join(format!("{name}_debug_quad_overdraw.png"));
                quads.write_png(&file)?;
                report.image_named(
                    &format!("depth-equal quad overdraw (mean {mean:.2})"),
                    &file,
                );
                motion_view(args, &mut report, renderer, &prepared, frame, name)?;
            }
            if mismatch.is_some() {
                print!("{report}");
                anyhow::bail!("the GPU classification differs from its CPU twin");
            }
        }
        images.push(image);
    }
    compare_with_baseline(&mut report, paths, &images);
    if let Some(b) = paths.iter().position(|&p| p == RenderPath::Baseline) {
        for (&path, image) in paths.iter().zip(&images) {
            if path == RenderPath::Baseline {
                continue;
            }
            let file = match path {
                RenderPath::Deferred => args.out.join(format!("{}_diff.png", built.name)),
                _ => args
                    .out
                    .join(format!("{}_diff_{}.png", built.name, path.name())),
            };
            gpu::inspect::diff_image(image, &images[b]).write_png(&file)?;
            report.image_named(&format!("diff, {} vs baseline", path.name()), &file);
        }
    }
    print!("{report}");
    Ok(())
}

/// Each rendered path's image against the baseline's (`images[i]` is `paths[i]`'s), where
/// the baseline was rendered.
pub(crate) fn compare_with_baseline(
    report: &mut Report,
    paths: &[RenderPath],
    images: &[gpu::Rgba8Image],
) {
    let Some(baseline) = paths
        .iter()
        .position(|&p| p == RenderPath::Baseline)
        .and_then(|b| images.get(b))
    else {
        return;
    };
    for (&path, image) in paths.iter().zip(images) {
        if path != RenderPath::Baseline {
            report.compare(
                &format!("{} vs baseline image", path.name()),
                image,
                baseline,
            );
        }
    }
}

/// The light tiles of the frame just rendered, into the report, and (unless
/// `--no-debug-views`) their heat map as `{name}_debug_lights_per_tile.png` and the sun
/// shadows' views ([`shadow_views`]).
pub(crate) fn report_lighting(
    args: &Args,
    report: &mut Report,
    renderer: &Renderer,
    frame: &gpu::FrameInput,
    name: &str,
) -> Result<()> {
    let tiles = renderer.inspect().read_light_tiles()?;
    let lights = frame.lighting.point_lights.len() + frame.lighting.spot_lights.len();
    report.light_tiles(lights, &tiles);
    report.light_paths(renderer.inspect().light_path_counts());
    report.conditional_volumes(&renderer.inspect().read_conditional_volumes()?);
    report.uploads(
        renderer.inspect().upload_stats(),
        renderer.config().frames.upload_pool,
    );
    // KZ2's skip: pixels in full baked sun shadow, or facing away, run no sun shader.
    let (surfaces, depth) = (
        renderer.inspect().read_gbuffer()?,
        renderer.inspect().read_depth()?,
    );
    let to_sun = frame
        .lighting
        .sun_direction
        .normalize_or(gpu::glam::Vec3::Y);
    let (mut geometry, mut baked, mut away) = (0u64, 0u64, 0u64);
    for (s, &d) in surfaces.iter().zip(&depth) {
        if d <= 0.0 {
            continue;
        }
        geometry += 1;
        if s.normal.dot(to_sun) <= 0.0 {
            away += 1;
        } else if s.sun_shadow <= 0.0 {
            baked += 1;
        }
    }
    report.sun_skip(geometry, baked, away);
    if !args.no_debug_views {
        let (img, max) = gpu::inspect::debug::lights_per_tile(args.width, args.height, &tiles, 0);
        let file = args.out.join(format!("{name}_debug_lights_per_tile.png"));
        img.write_png(&file)?;
        report.image_named(
            &format!("lights per 16x16 tile (legend at the bottom: 0 black .. {max} white, ticks at quarters)"),
            &file,
        );
        let (img, [culled, bounds, volume]) =
            gpu::inspect::debug::light_paths(&renderer.read_output()?, frame);
        let file = args.out.join(format!("{name}_debug_light_paths.png"));
        img.write_png(&file)?;
        report.image_named(
            &format!(
                "KZ2's path per light: {bounds} depth-bounds (green), {volume} light-volume (red), {culled} culled"
            ),
            &file,
        );
        shadow_views(args, report, renderer, frame.camera.near, name)?;
    }
    Ok(())
}

/// The sun-shadow debug views of the frame just rendered (with shadows on): the shadow
/// maps side by side as `{name}_debug_shadow_atlas.png` (512 texels a side at most) and
/// each pixel's depth slice (for a camera whose near plane is `near` metres) as
/// `{name}_debug_cascades.png`.
fn shadow_views(
    args: &Args,
    report: &mut Report,
    renderer: &Renderer,
    near: f32,
    name: &str,
) -> Result<()> {
    let Some(cascades) = renderer.inspect().shadow_cascades() else {
        return Ok(());
    };
    let maps = renderer.inspect().read_shadow_maps()?;
    let Some(config) = renderer.config().lighting.shadows else {
        return Ok(());
    };
    let resolution = config.resolution;
    let step = resolution.div_ceil(512);
    let slices: Vec<String> = (0..config.cascades as usize)
        .map(|k| config.slice_resolution(k).to_string())
        .collect();
    let file = args.out.join(format!("{name}_debug_shadow_atlas.png"));
    gpu::inspect::debug::shadow_atlas(&maps, resolution, step).write_png(&file)?;
    report.image_named(
        &format!(
            "sun shadow maps, nearest slice first ({} texels, each in the corner of a {resolution}-texel layer; 1 in {step} shown; black nearest the sun)",
            slices.join(" / ")
        ),
        &file,
    );
    let splits: Vec<f64> = cascades.cascades().iter().map(|c| c.split[1]).collect();
    let depth = renderer.inspect().read_depth()?;
    let file = args.out.join(format!("{name}_debug_cascades.png"));
    gpu::inspect::debug::cascade_index(args.width, args.height, &depth, near, &splits)
        .write_png(&file)?;
    let ends: Vec<String> = splits.iter().map(|d| format!("{d:.1}")).collect();
    report.image_named(
        &format!(
            "sun depth slice per pixel (red, green, blue, yellow; slices end at {} m)",
            ends.join(" / ")
        ),
        &file,
    );
    Ok(())
}

/// The motion-vector debug view: one frame from the camera 0.3 m to the left and 0.2 m
/// back a 30th of a second earlier, then the scene's own frame (the measured frames hold
/// the camera still, so their motion is the wind's alone), its G-buffer motion (camera
/// and swaying foliage) as `{name}_debug_motion.png`.
fn motion_view(
    args: &Args,
    report: &mut Report,
    renderer: &mut Renderer,
    prepared: &gpu::PreparedScene,
    frame: &gpu::FrameInput,
    name: &str,
) -> Result<()> {
    let mut before = frame.clone();
    let c = &frame.camera;
    let forward = (c.target - c.position).normalize();
    let right = forward.cross(c.up).normalize();
    let shift = -0.3 * right - 0.2 * forward;
    before.camera.position += shift;
    before.camera.target += shift;
    before.time = frame.time - 1.0 / 30.0;
    renderer.render(prepared, &before, RenderPath::Deferred)?;
    renderer.render(prepared, frame, RenderPath::Deferred)?;
    let (img, scale) = gpu::inspect::debug::motion_vectors(
        args.width,
        args.height,
        &renderer.inspect().read_gbuffer()?,
        0.0,
    );
    let file = args.out.join(format!("{name}_debug_motion.png"));
    img.write_png(&file)?;
    report.image_named(
        &format!(
            "motion vectors after a 0.3 m step right and 0.2 m forward and 1/30 s of wind \
             (hue: direction, full brightness at {scale:.1} px)"
        ),
        &file,
    );
    Ok(())
}
