//! Times HZD's static query on the GPU: the demo city (default 1.5M instances) streamed
//! into a `StaticQuery`, one camera view queried with and without occlusion (HiZ of the
//! buildings' boxes), GPU time from timestamp queries after a warm-up, the CPU pre-cull
//! timed on its own, the CPU twin (`Scene::par_query` on every core) on the same view as
//! the baseline, and the HiZ reduction of a full-size depth buffer timed per pyramid.
//!
//! ```sh
//! cargo run --release -p gpu --example static_query -- --instances 1500000 --width 3840 --height 2160
//! ```

use std::time::{Duration, Instant};

use clap::{Parser, ValueEnum};
use gpu::HeadlessOptions;
use gpu::statics::{QueryReadback, StaticQuery};
use gpu::staticscene::demo::{CityConfig, aerial_camera, city, raster_boxes, street_camera};
use gpu::staticscene::pass::{HIZ_PASS, HizGrid, HizStep, TileSlots, hiz_header};
use gpu::staticscene::{
    BuildConfig, DrawableSetupInstance, HiZ, QueryOptions, QueryOutput, QueryParams, QueryStats,
    ResourceLibrary, Scene, TileStreamer, ViewDesc, snap_origin,
};

#[derive(Clone, Copy, Debug, ValueEnum)]
enum CameraArg {
    Street,
    Aerial,
    /// A sun shadow view: orthographic, 300 m across, centred 100 m ahead of the street
    /// camera, the sun-shadow filter, LODs from the street camera. Timed through the
    /// pass's shadow variant and, for comparison, through the general pass.
    Sun,
}

/// Time the GPU static query on the demo city.
#[derive(Debug, Parser)]
struct Args {
    /// Static instances in the city (about).
    #[arg(long, default_value_t = 1_500_000, value_parser = clap::value_parser!(u64).range(1..=4_000_000))]
    instances: u64,
    /// Viewport width in pixels.
    #[arg(long, default_value_t = 3840, value_parser = clap::value_parser!(u32).range(1..=16384))]
    width: u32,
    /// Viewport height in pixels.
    #[arg(long, default_value_t = 2160, value_parser = clap::value_parser!(u32).range(1..=16384))]
    height: u32,
    /// Camera.
    #[arg(long, value_enum, default_value = "aerial")]
    camera: CameraArg,
    /// HiZ scan levels of the camera view (`ViewDesc::hiz_scan_levels`: large boxes are
    /// tested this many levels finer than their 2x2-texel level).
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u32).range(0..=8))]
    scan_levels: u32,
    /// Leave subgroups off (the query's workgroup-wide batch output, W64 batches).
    #[arg(long)]
    no_subgroups: bool,
    /// Queries measured per mode (after a 0.5 s warm-up).
    #[arg(long, default_value_t = 50, value_parser = clap::value_parser!(u32).range(1..=10_000))]
    frames: u32,
}

fn rayon_threads() -> usize {
    std::thread::available_parallelism().map_or(1, usize::from)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() -> anyhow::Result<()> {
    let args = Args::parse();
    let mut disable = wgpu::Features::empty();
    if args.no_subgroups {
        disable |= wgpu::Features::SUBGROUP;
    }
    let ctx = gpu::headless(&HeadlessOptions {
        disable_features: disable,
        ..HeadlessOptions::default()
    })?;
    println!("{}", ctx.adapter_line());
    let subgroups = ctx.device.features().contains(wgpu::Features::SUBGROUP);
    let (device, queue) = (&ctx.device, &ctx.queue);

    let t = Instant::now();
    let cfg = CityConfig::with_instances(args.instances as usize);
    let world = city(&cfg);
    let mut streamer = TileStreamer::new(
        ResourceLibrary::new(&world.resources),
        BuildConfig::default(),
    );
    let mut scene = Scene::new();
    let mut query = StaticQuery::new(device, queue)?;
    for g in &world.groups {
        let u = streamer.add_group(g)?;
        for tile in &u.add {
            query.activate(device, queue, tile.tile())?;
        }
        scene.apply(u);
    }
    let clusters: usize = scene.tiles().iter().map(|t| t.clusters().len()).sum();
    println!(
        "city: {} instances in {} tiles, {} clusters, {:.1} MB of GPU records (built and uploaded in {:.1} s)",
        scene.instance_count(),
        scene.tiles().len(),
        clusters,
        scene.gpu_bytes(true) as f64 / 1e6,
        t.elapsed().as_secs_f64()
    );

    let cam = match args.camera {
        CameraArg::Street | CameraArg::Sun => street_camera(&cfg),
        CameraArg::Aerial => aerial_camera(&cfg),
    };
    let (w, h) = (args.width, args.height);
    let origin = snap_origin(cam.position);
    let depth = raster_boxes(
        &world.building_boxes,
        origin,
        &cam.clip_from_floating(origin),
        w,
        h,
        false,
    );
    let hiz = HiZ::build(&depth, w, h, false)?;

    // (occlusion, shadow variant): the sun view has no occlusion; it runs through the
    // shadow variant and, with its flag cleared, the general pass (same tests, same output).
    let modes: &[(bool, bool)] = match args.camera {
        CameraArg::Sun => &[(false, true), (false, false)],
        _ => &[(false, false), (true, false)],
    };
    for &(occlusion, variant) in modes {
        let mut params = if matches!(args.camera, CameraArg::Sun) {
            let ahead = cam.rotation * glam::DVec3::NEG_Z;
            let target = cam.position + ahead * 100.0;
            let sun_dir = glam::DVec3::new(0.4, -0.8, 0.3).normalize();
            let ortho = glam::Mat4::orthographic_rh(-150.0, 150.0, -150.0, 150.0, 1.0, 2000.0);
            let sun = staticscene::Camera::look_at(
                target - sun_dir * 900.0,
                target,
                glam::DVec3::Y,
                ortho,
                false,
            );
            let view = ViewDesc::shadow(sun, [w, h], staticscene::FILTER_SUN_SHADOW, cam.position);
            QueryParams::new(&view)?
        } else {
            let mut view = ViewDesc::camera(cam, [w, h]);
            view.hiz_scan_levels = args.scan_levels;
            if occlusion {
                view.occlusion_camera = Some(cam);
            }
            QueryParams::new(&view)?
        };
        if matches!(args.camera, CameraArg::Sun) && !variant {
            params.flags &= !staticscene::QUERY_FLAG_SHADOW;
        }
        query.set_hiz(device, queue, occlusion.then_some(&hiz))?;
        // The GPU's batch width (its subgroup size, or 64): the twin batches alike.
        let options = QueryOptions {
            wave_width: query.wave_width().unwrap_or(staticscene::WaveWidth::W64),
            ..QueryOptions::default()
        };
        let mut run = || {
            query.run(
                device,
                queue,
                &mut scene,
                &params,
                &options,
                QueryReadback::Counters,
            )
        };
        // Warm-up: the SM clock drops when idle.
        let start = Instant::now();
        while start.elapsed() < Duration::from_millis(500) {
            run()?;
        }
        let mut gpu_ms = Vec::new();
        let mut last = None;
        for _ in 0..args.frames {
            let out = run()?;
            gpu_ms.extend(out.gpu_ms);
            last = Some(out);
        }
        let out = last.expect("at least one frame");
        // The CPU pre-cull alone, on a copy of the scene's bookkeeping.
        let mut copy = scene.clone();
        let slots = |_| Some(TileSlots::default());
        let mut cpu_ms = Vec::new();
        for _ in 0..args.frames {
            let t = Instant::now();
            let plan = copy.plan_gpu(&params, &options, slots);
            cpu_ms.push(t.elapsed().as_secs_f64() * 1e3);
            std::hint::black_box(plan);
        }
        // The baseline: the CPU twin (`Scene::par_query`, rayon on every core) on the same
        // view, its own copy of the scene.
        let mut cpu_scene = scene.clone();
        let mut cpu_out = QueryOutput::<DrawableSetupInstance>::new();
        let mut cpu_query_ms = Vec::new();
        for _ in 0..args.frames.min(20) {
            let t = Instant::now();
            cpu_scene.par_query(&params, occlusion.then_some(&hiz), &options, &mut cpu_out)?;
            cpu_query_ms.push(t.elapsed().as_secs_f64() * 1e3);
        }
        let s: QueryStats = out.stats;
        println!(
            "\nocclusion {}: {}x{}, {:?} camera{}, batch output {}",
            if occlusion { "on" } else { "off" },
            w,
            h,
            args.camera,
            match (args.camera, variant) {
                (CameraArg::Sun, true) => ", shadow variant",
                (CameraArg::Sun, false) => ", general pass",
                _ => "",
            },
            if subgroups {
                format!("per subgroup ({:?})", options.wave_width)
            } else {
                "workgroup-wide (W64)".to_string()
            }
        );
        println!(
            "  pre-cull: tiles {} (culled {}), clusters {} (culled {}), threads {}; CPU {:.3} ms (median)",
            s.tiles,
            s.tiles_culled,
            s.clusters,
            s.clusters_culled,
            out.threads,
            median(cpu_ms)
        );
        println!(
            "  rejected: filter {}, LOD {}, frustum {}, size {}, occlusion {}, faded out {}, invalid {}",
            s.rejected_filter,
            s.rejected_lod,
            s.rejected_frustum,
            s.rejected_size,
            s.rejected_occlusion,
            s.faded_out,
            s.invalid
        );
        println!(
            "  out: {} instances in {} batches ({:.1}% fewer render items than instances)",
            s.visible,
            s.batches,
            100.0 * (1.0 - s.batches as f64 / s.visible.max(1) as f64)
        );
        println!(
            "  baseline, CPU twin on {} threads: median {:.3} ms ({} instances out)",
            rayon_threads(),
            median(cpu_query_ms),
            cpu_out.stats.visible
        );
        if gpu_ms.is_empty() {
            println!("  query GPU time: no timestamp queries on this adapter");
        } else {
            let min = gpu_ms.iter().copied().fold(f64::INFINITY, f64::min);
            println!(
                "  query GPU time: median {:.1} us, min {:.1} us over {} queries",
                median(gpu_ms.clone()) * 1e3,
                min * 1e3,
                gpu_ms.len()
            );
        }
    }
    hiz_build_time(device, queue, &depth, w, h, args.frames)?;
    Ok(())
}

/// The HiZ reduction of the `w x h` depth (level 0 uploaded), every level in one compute
/// pass, timed.
fn hiz_build_time(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    depth: &[f32],
    w: u32,
    h: u32,
    frames: u32,
) -> anyhow::Result<()> {
    use shader::pipeline::ComputePass;
    let (header, len) = hiz_header(w, h)?;
    let levels = header[0] as usize;
    let mut words = header.clone();
    words.resize(len, 0);
    let l0 = header[6] as usize;
    for (i, d) in depth.iter().enumerate() {
        words[l0 + i] = d.to_bits();
    }
    let pass = ComputePass::new(device, &HIZ_PASS, &[], &[])?;
    let buffer = wgpu::util::DeviceExt::create_buffer_init(
        device,
        &wgpu::util::BufferInitDescriptor {
            label: Some("hiz"),
            contents: bytemuck::cast_slice(&words),
            usage: wgpu::BufferUsages::STORAGE,
        },
    );
    let align = device.limits().min_uniform_buffer_offset_alignment as usize;
    let mut steps = vec![0u8; align * levels];
    for l in 0..levels {
        let s = HizStep {
            level: l as u32,
            reversed: 0,
            pad: [0; 2],
        };
        steps[l * align..l * align + 16].copy_from_slice(bytemuck::bytes_of(&s));
    }
    let uniforms = wgpu::util::DeviceExt::create_buffer_init(
        device,
        &wgpu::util::BufferInitDescriptor {
            label: Some("hiz steps"),
            contents: &steps,
            usage: wgpu::BufferUsages::UNIFORM,
        },
    );
    let groups: Vec<wgpu::BindGroup> = (0..levels - 1)
        .map(|l| {
            pass.bind_group(
                device,
                "hiz",
                &[
                    (
                        "step",
                        wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                            buffer: &uniforms,
                            offset: (l * align) as u64,
                            size: std::num::NonZeroU64::new(16),
                        }),
                    ),
                    ("hiz", buffer.as_entire_binding()),
                ],
            )
        })
        .collect::<Result<_, _>>()?;
    let query_set = device.create_query_set(&wgpu::QuerySetDescriptor {
        label: None,
        ty: wgpu::QueryType::Timestamp,
        count: 2,
    });
    let resolve = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: 16,
        usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let mut times = Vec::new();
    let start = Instant::now();
    let mut n = 0;
    while n < frames {
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut cpass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("hiz"),
                timestamp_writes: Some(wgpu::ComputePassTimestampWrites {
                    query_set: &query_set,
                    beginning_of_pass_write_index: Some(0),
                    end_of_pass_write_index: Some(1),
                }),
            });
            for (l, g) in groups.iter().enumerate() {
                let next = HizGrid {
                    width: header[8 + 4 * l],
                    height: header[9 + 4 * l],
                };
                pass.record(&mut cpass, &[g], &next);
            }
        }
        encoder.resolve_query_set(&query_set, 0..2, &resolve, 0);
        queue.submit([encoder.finish()]);
        let ticks: Vec<u64> = bytemuck::pod_collect_to_vec(&gpu::inspect::read_buffer(
            device, queue, &resolve, 0, 16,
        )?);
        if start.elapsed() > Duration::from_millis(500) {
            times.push(
                ticks[1].saturating_sub(ticks[0]) as f64 * f64::from(queue.get_timestamp_period())
                    / 1e3,
            );
            n += 1;
        }
    }
    println!(
        "\nHiZ reduction of {w}x{h} ({} levels): median {:.1} us",
        levels,
        median(times)
    );
    Ok(())
}
