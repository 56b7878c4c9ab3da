//! The renderer's API on a device (testkit's; lavapipe in CI): a scene prepared once and
//! rendered from per-frame inputs, an empty scene, a device without the required limits,
//! values the scene or the frame must not accept, and a scene given to the wrong renderer.

mod common;

use demo::{DemoOptions, DemoScene};
use gpu::glam::{Affine3A, Vec3};
use gpu::{
    Camera, Error, FrameError, FrameInput, PointLight, RenderPath, Renderer, RendererConfig, Scene,
    SceneError,
};
use testkit::device::ctx;

const W: u32 = 96;
const H: u32 = 64;

fn renderer() -> Renderer {
    common::renderer(W, H, true)
}

fn small_forest() -> (Scene, FrameInput) {
    demo::build(&DemoOptions {
        scene: DemoScene::Forest,
        seed: 3,
        density: 0.05,
    })
}

#[test]
fn an_empty_scene_renders_the_sky() {
    let mut r = renderer();
    let camera = Camera::look_at(Vec3::new(0.0, 1.0, 5.0), Vec3::ZERO);
    let frame = FrameInput::new(camera);
    let sky = frame.lighting.sky;
    // No batches at all, and a batch without instances: both valid, both sky.
    let (forest, _) = small_forest();
    let mut no_instances = forest.clone();
    for b in &mut no_instances.batches {
        b.instances.clear();
    }
    for scene in [Scene::default(), no_instances] {
        let prepared = r.prepare(&scene).unwrap_or_else(|e| panic!("{e}"));
        for path in [RenderPath::Deferred, RenderPath::Baseline] {
            r.render(&prepared, &frame, path)
                .unwrap_or_else(|e| panic!("{}: {e}", path.name()));
            let image = r.read_output().unwrap();
            let first = image.pixels[0];
            assert!(
                image.pixels.iter().all(|&p| p == first),
                "{}: the sky is one colour",
                path.name()
            );
            // ACES of the sky colour, sRGB-encoded: blue above red.
            assert!(first[2] > first[0], "{first:?} for sky {sky}");
        }
        assert_eq!(
            r.inspect()
                .read_classification(&prepared)
                .unwrap()
                .totals
                .counter_count,
            0
        );
    }
}

/// The output texture a window blits (`Renderer::output_texture`) is the image
/// `read_output` reads: Rgba8Unorm of the configured size, sampleable and copyable.
#[test]
fn the_output_texture_is_the_read_back_image() {
    let mut r = renderer();
    let (scene, frame) = small_forest();
    let p = r.prepare(&scene).unwrap();
    r.render(&p, &frame, RenderPath::Deferred).unwrap();
    let t = r.output_texture();
    assert_eq!(t.format(), wgpu::TextureFormat::Rgba8Unorm);
    assert_eq!((t.width(), t.height()), (W, H));
    assert!(
        t.usage()
            .contains(wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_SRC)
    );
    assert_eq!(r.output_view().texture(), t);
    let c = ctx();
    let padded = (W * 4).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let buffer = c.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("output copy"),
        size: u64::from(padded * H),
        usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = c.device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        t.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(H),
            },
        },
        t.size(),
    );
    c.queue.submit([encoder.finish()]);
    let bytes = gpu::inspect::read_buffer(&c.device, &c.queue, &buffer, 0, buffer.size()).unwrap();
    let image = r.read_output().unwrap();
    for (y, row) in bytes.chunks_exact(padded as usize).enumerate() {
        let row: Vec<[u8; 4]> = row[..(W * 4) as usize]
            .chunks_exact(4)
            .map(|p| [p[0], p[1], p[2], p[3]])
            .collect();
        assert_eq!(row, image.pixels[y * W as usize..][..W as usize], "row {y}");
    }
}

#[test]
fn the_camera_moves_without_preparing_again() {
    let (scene, frame) = small_forest();
    let mut moving = renderer();
    let prepared = moving.prepare(&scene).unwrap();
    let mut moved = frame.clone();
    moved.camera.position += Vec3::new(1.5, 0.3, 2.0);
    moved.camera.target += Vec3::new(-2.0, 0.0, 1.0);
    moving
        .render(&prepared, &frame, RenderPath::Deferred)
        .unwrap();
    let before = moving.read_output().unwrap();
    moving
        .render(&prepared, &moved, RenderPath::Deferred)
        .unwrap();
    let after = moving.read_output().unwrap();
    assert_ne!(before, after, "the frame input's camera is used");
    // The same frame from a renderer that saw only it: identical.
    let mut fresh = renderer();
    let prepared_fresh = fresh.prepare(&scene).unwrap();
    fresh
        .render(&prepared_fresh, &moved, RenderPath::Deferred)
        .unwrap();
    assert_eq!(fresh.read_output().unwrap(), after);
}

#[test]
fn point_lights_change_per_frame() {
    let (scene, frame) = small_forest();
    let mut r = renderer();
    let prepared = r.prepare(&scene).unwrap();
    let mut lit = frame.clone();
    lit.lighting.point_lights = (0..40)
        .map(|i| PointLight {
            position: frame.camera.target + Vec3::new(i as f32 * 0.3 - 6.0, 1.0, 2.0),
            color: Vec3::new(3.0, 1.0, 0.2),
            radius: 6.0,
            specular: true,
        })
        .collect();
    let mut dark = frame.clone();
    dark.lighting.point_lights.clear();
    r.render(&prepared, &dark, RenderPath::Deferred).unwrap();
    let a = r.read_output().unwrap();
    // More lights than the buffer held: it grows, the image brightens.
    r.render(&prepared, &lit, RenderPath::Deferred).unwrap();
    let b = r.read_output().unwrap();
    let sum = |i: &gpu::Rgba8Image| i.pixels.iter().map(|p| u64::from(p[0])).sum::<u64>();
    assert!(sum(&b) > sum(&a), "{} vs {}", sum(&b), sum(&a));
    // And back: identical to the first frame.
    r.render(&prepared, &dark, RenderPath::Deferred).unwrap();
    assert_eq!(r.read_output().unwrap(), a);
}

#[test]
fn a_device_with_default_limits_gets_an_error_naming_the_limit() {
    let c = ctx();
    let (device, queue) = pollster::block_on(c.adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("default limits"),
        required_features: wgpu::Features::empty(),
        required_limits: wgpu::Limits::default(),
        experimental_features: wgpu::ExperimentalFeatures::disabled(),
        memory_hints: wgpu::MemoryHints::Performance,
        trace: wgpu::Trace::Off,
    }))
    .unwrap();
    let config = RendererConfig::default();
    match Renderer::new(&device, &queue, config.clone()) {
        Err(Error::DeviceLimit {
            limit,
            needed,
            available,
        }) => {
            assert_eq!(limit, "max_storage_buffers_per_shader_stage");
            assert_eq!(available, 8, "wgpu's default");
            assert!(needed >= 14, "the classification binds 14: {needed}");
            let msg = Renderer::new(&device, &queue, config.clone())
                .err()
                .unwrap()
                .to_string();
            assert!(
                msg.contains("max_storage_buffers_per_shader_stage"),
                "{msg}"
            );
        }
        Err(e) => panic!("{e}"),
        Ok(_) => {
            panic!("Limits::default() has 8 storage buffers per stage; the classification binds 14")
        }
    }
    // With the limits the renderer asks for, it works.
    let (device, queue) = pollster::block_on(c.adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("required limits"),
        required_features: Renderer::required_features(),
        required_limits: Renderer::required_limits(&config),
        experimental_features: wgpu::ExperimentalFeatures::disabled(),
        memory_hints: wgpu::MemoryHints::Performance,
        trace: wgpu::Trace::Off,
    }))
    .unwrap();
    let mut r = Renderer::new(&device, &queue, config).unwrap_or_else(|e| panic!("{e}"));
    let (scene, frame) = small_forest();
    let prepared = r.prepare(&scene).unwrap();
    r.render(&prepared, &frame, RenderPath::Deferred).unwrap();
}

fn frame_field(e: Error) -> String {
    match e {
        Error::Frame(FrameError::OutOfRange { field, .. }) => field,
        Error::Frame(FrameError::CameraBasis { detail }) => detail.into(),
        other => panic!("not a frame error: {other}"),
    }
}

#[test]
fn frames_with_wrong_values_are_rejected_by_name() {
    let (scene, frame) = small_forest();
    let mut r = renderer();
    let prepared = r.prepare(&scene).unwrap();
    let mut bad = |edit: &dyn Fn(&mut FrameInput)| -> String {
        let mut f = frame.clone();
        edit(&mut f);
        frame_field(r.render(&prepared, &f, RenderPath::Deferred).unwrap_err())
    };
    assert_eq!(
        bad(&|f| f.camera.fov_y = std::f32::consts::PI),
        "camera.fov_y"
    );
    assert_eq!(bad(&|f| f.camera.near = -1.0), "camera.near");
    assert!(bad(&|f| f.camera.target = f.camera.position + Vec3::Y).contains("parallel"));
    assert_eq!(
        bad(&|f| f.lighting.sun_direction = Vec3::new(f32::NAN, 1.0, 0.0)),
        "lighting.sun_direction.x"
    );
    assert_eq!(
        bad(&|f| f.lighting.point_lights = vec![PointLight {
            position: Vec3::ZERO,
            color: Vec3::ONE,
            radius: f32::NAN,
            specular: true,
        }]),
        "lighting.point_lights[0].radius"
    );
    // The renderer still renders a good frame afterwards.
    r.render(&prepared, &frame, RenderPath::Deferred).unwrap();
}

#[test]
fn scenes_with_wrong_values_are_rejected_by_name() {
    let (scene, _) = small_forest();
    let r = renderer();
    let field = |edit: &dyn Fn(&mut Scene)| -> String {
        let mut s = scene.clone();
        edit(&mut s);
        match r.prepare(&s) {
            Err(Error::Scene(SceneError::OutOfRange { field, allowed, .. })) => {
                format!("{field} {allowed}")
            }
            Err(e) => panic!("{e}"),
            Ok(_) => panic!("accepted"),
        }
    };
    assert!(field(&|s| s.materials[2].alpha_cutoff = 1.5).ends_with("alpha_cutoff [0, 1]"));
    assert!(field(&|s| s.materials[0].roughness = -0.1).ends_with("roughness [0, 1]"));
    assert!(field(&|s| s.materials[1].specular = f32::NAN).contains("specular"));
    assert!(field(&|s| s.materials[1].tint.y = -1.0).contains("tint.g"));
    let mut s = scene.clone();
    s.batches[1].instances[0] = Affine3A::from_translation(Vec3::splat(f32::INFINITY));
    assert!(matches!(
        r.prepare(&s),
        Err(Error::Scene(SceneError::NonFinite { .. }))
    ));
}

#[test]
fn renderer_misuse_is_an_error() {
    let (scene, frame) = small_forest();
    let mut a = renderer();
    let mut b = renderer();
    let prepared = a.prepare(&scene).unwrap();
    assert!(matches!(
        b.render(&prepared, &frame, RenderPath::Deferred),
        Err(Error::ForeignScene)
    ));
    assert!(matches!(
        a.hooks().classify_words(&prepared, &[0; 10]),
        Err(Error::Length { got: 10, .. })
    ));
    assert!(matches!(
        a.render_frames(&prepared, &frame, RenderPath::Deferred, 0),
        Err(Error::Length { .. })
    ));
    let c = ctx();
    for (bad, name) in [
        (
            RendererConfig {
                image: gpu::config::ImageConfig {
                    width: 0,
                    ..Default::default()
                },
                ..RendererConfig::default()
            },
            "RendererConfig::image.width",
        ),
        (
            RendererConfig {
                image: gpu::config::ImageConfig {
                    height: 0,
                    ..Default::default()
                },
                ..RendererConfig::default()
            },
            "RendererConfig::image.height",
        ),
        (
            RendererConfig {
                image: gpu::config::ImageConfig {
                    mip_bias: f32::NAN,
                    ..Default::default()
                },
                ..RendererConfig::default()
            },
            "RendererConfig::image.mip_bias",
        ),
        (
            RendererConfig {
                image: gpu::config::ImageConfig {
                    mip_bias: -17.0,
                    ..Default::default()
                },
                ..RendererConfig::default()
            },
            "RendererConfig::image.mip_bias",
        ),
    ] {
        match Renderer::new(&c.device, &c.queue, bad) {
            Err(Error::Config { field, .. }) => assert_eq!(field, name),
            Err(e) => panic!("{name}: {e}"),
            Ok(_) => panic!("{name}: accepted"),
        }
    }
}
