//! Floats crates down the river demo's rapids with the CPU water query and renders them
//! on the GPU water: Far Cry 5's "everything we do in the GPU, we have to replicate in the
//! CPU because we can have objects that are moving around in the world according to the
//! flow map" (seed 003). Each step, every crate asks `WaterWorld::query` (the same baked
//! words the GPU passes read) for the surface height and flow under it, drifts with the
//! flow and sits on the surface; a splash decal follows each one into the GPU's
//! displacement. After the run it compares, at every crate still afloat, the CPU query's
//! height with the GPU's water surface read back beside the crate (the depth with water
//! against the crate's own depth), and writes frames as PNGs.
//!
//! ```sh
//! cargo run --release -p gpu --example float_river -- --crates 12 --seconds 20 --out out
//! ```

use std::path::PathBuf;

use clap::Parser;
use demo::river::{RiverDemo, river};
use gpu::glam::{Affine3A, Quat, Vec2, Vec3, Vec4};
use gpu::scene::{AlbedoLayer, MaterialId, MeshId, ShaderKind};
use gpu::water;
use gpu::water::world::WaterWorld;
use gpu::water_scene::WaterDecal;
use gpu::{Batch, Material, Mesh, RenderPath, Renderer, RendererConfig, Scene};

/// Float crates down the river with the CPU water query; render them on the GPU water.
#[derive(Debug, Parser)]
struct Args {
    /// Crates dropped into the river's upper reach.
    #[arg(long, default_value_t = 12, value_parser = clap::value_parser!(u32).range(1..=64))]
    crates: u32,
    /// Simulated seconds.
    #[arg(long, default_value_t = 20.0, value_parser = seconds)]
    seconds: f32,
    /// Frames written, spread over the run (1 to 16).
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=16))]
    frames: u32,
    /// Image width in pixels.
    #[arg(long, default_value_t = 960, value_parser = clap::value_parser!(u32).range(16..=8192))]
    width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 540, value_parser = clap::value_parser!(u32).range(16..=8192))]
    height: u32,
    /// Output directory.
    #[arg(long, default_value = "out")]
    out: PathBuf,
}

fn seconds(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if (0.1..=600.0).contains(&v) => Ok(v),
        Ok(v) => Err(format!("{v} s: 0.1 to 600")),
        Err(e) => Err(e.to_string()),
    }
}

/// One floating crate, in water coordinates (+Z up).
#[derive(Clone, Copy, Debug)]
struct Crate {
    position: Vec3,
    velocity: Vec2,
    spin: f32,
    afloat: bool,
}

/// The physics step: drift towards the flow under the crate (drag), ride the surface.
fn step(world: &WaterWorld, c: &mut Crate, dt: f32, t: f32, k: usize) {
    if !c.afloat {
        return;
    }
    let Some(q) = world.query(c.position.truncate()) else {
        c.afloat = false;
        return;
    };
    let drag = 1.0 - (-1.5 * dt).exp();
    c.velocity += (q.flow - c.velocity) * drag;
    let next = c.position.truncate() + c.velocity * dt;
    // Washed against the bank: it stops where the query finds no water ahead.
    if world.query(next).is_none() {
        c.afloat = false;
        return;
    }
    let bob = 0.05 * (t * 2.3 + k as f32).sin();
    c.position = next.extend(q.height + bob);
    c.spin += c.velocity.length() * dt * 0.3;
}

/// A crate: a 0.9 x 0.6 x 0.9 m box, its base 0.25 m under its origin (the waterline).
fn crate_mesh() -> Mesh {
    let (lo, hi) = (Vec3::new(-0.45, -0.25, -0.45), Vec3::new(0.45, 0.35, 0.45));
    let c = [lo, hi];
    let corner = |x: usize, y: usize, z: usize| Vec3::new(c[x].x, c[y].y, c[z].z);
    type Face = ([(usize, usize, usize); 4], Vec3);
    let faces: [Face; 6] = [
        ([(1, 0, 0), (1, 1, 0), (1, 1, 1), (1, 0, 1)], Vec3::X),
        ([(0, 0, 1), (0, 1, 1), (0, 1, 0), (0, 0, 0)], Vec3::NEG_X),
        ([(0, 1, 0), (0, 1, 1), (1, 1, 1), (1, 1, 0)], Vec3::Y),
        ([(0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1)], Vec3::NEG_Y),
        ([(0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)], Vec3::Z),
        ([(1, 0, 0), (0, 0, 0), (0, 1, 0), (1, 1, 0)], Vec3::NEG_Z),
    ];
    let mut m = Mesh {
        name: "crate".into(),
        ..Mesh::default()
    };
    for (corners, n) in faces {
        let base = m.positions.len() as u16;
        for (k, &(x, y, z)) in corners.iter().enumerate() {
            m.positions.push(corner(x, y, z));
            m.normals.push(n);
            m.uvs.push(Vec2::new(
                (k == 1 || k == 2) as u8 as f32,
                (k >= 2) as u8 as f32,
            ));
            m.tangents.push(n.any_orthonormal_vector().extend(1.0));
        }
        m.indices
            .extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    m
}

/// Planks: a 64-texel wood layer.
fn wood_layer(size: u32) -> AlbedoLayer {
    let texels = (0..size * size)
        .map(|i| {
            let (x, y) = (i % size, i / size);
            let plank = (y / 16) % 2;
            let grain = ((x * 7 + y * 3) % 11) as u8;
            let edge = y % 16 == 0 || x % 32 == 0;
            if edge {
                [60, 38, 20, 255]
            } else {
                [150 + grain * 3 - plank as u8 * 20, 100 + grain * 2, 55, 255]
            }
        })
        .collect();
    AlbedoLayer { size, texels }
}

/// The demo's scene with the crates added as a batch (and their material and layer).
fn with_crates(demo: &RiverDemo, crates: &[Crate]) -> Scene {
    let mut scene = demo.scene.clone();
    let size = scene.albedo_layers.first().map_or(64, |l| l.size);
    let mesh = MeshId(scene.meshes.len());
    scene.meshes.push(crate_mesh());
    let layer = scene.albedo_layers.len() as u32;
    scene.albedo_layers.push(wood_layer(size));
    let material = MaterialId(scene.materials.len());
    scene.materials.push(Material {
        name: "crate".into(),
        shader: ShaderKind::Opaque,
        albedo_layer: layer,
        tint: Vec3::ONE,
        alpha_cutoff: 0.5,
        roughness: 0.8,
        specular: 0.2,
        regular: false,
        ..Default::default()
    });
    let instances = crates
        .iter()
        .map(|c| {
            let p = c.position;
            Affine3A::from_rotation_translation(
                Quat::from_rotation_y(c.spin),
                Vec3::new(p.x, p.z, -p.y),
            )
        })
        .collect();
    scene.batches.push(Batch {
        mesh,
        material,
        instances,
    });
    scene
}

/// A splash under each crate afloat (the demo's splash texture), in water coordinates.
fn splashes(crates: &[Crate], t: f32) -> Vec<WaterDecal> {
    crates
        .iter()
        .filter(|c| c.afloat)
        .enumerate()
        .map(|(k, c)| WaterDecal {
            box_to_world: Affine3A::from_scale_rotation_translation(
                Vec3::new(1.6, 1.6, 0.5),
                Quat::from_rotation_z(c.spin),
                c.position,
            ),
            texture: 0,
            strength: 0.35,
            frame: t * 4.0 + k as f32,
            fade: 0.3,
        })
        .collect()
}

fn main() -> anyhow::Result<()> {
    let args = Args::parse();
    std::fs::create_dir_all(&args.out)?;
    let demo = river(1, 0.4, &mut water::no_progress)?;
    let world = &demo.water.world;
    // Drop the crates along the upper reach, across its width.
    let reach = &demo.builder.rivers[0].points;
    let mut crates: Vec<Crate> = (0..args.crates)
        .map(|k| {
            let t = k as f32 / args.crates as f32 * 3.0;
            let i = (t as usize).min(reach.len() - 2);
            let f = t - i as f32;
            let a = reach[i].position.truncate();
            let b = reach[i + 1].position.truncate();
            let side = (b - a).perp().normalize_or_zero() * ((k % 3) as f32 - 1.0) * 3.0;
            let p = a + (b - a) * f + side;
            let h = world.query(p).map_or(0.0, |q| q.height);
            Crate {
                position: p.extend(h),
                velocity: Vec2::ZERO,
                spin: k as f32,
                afloat: world.query(p).is_some(),
            }
        })
        .collect();
    let ctx = gpu::headless(&gpu::HeadlessOptions::default())?;
    let mut renderer = Renderer::new(
        &ctx.device,
        &ctx.queue,
        RendererConfig::sized(args.width, args.height),
    )?;
    renderer.set_water(Some(&demo.water))?;
    // A camera over the rapids, looking down the river.
    let mut frame = demo.frame.clone();
    frame.camera =
        gpu::Camera::look_at(Vec3::new(110.0, 52.0, -130.0), Vec3::new(40.0, 18.0, -30.0));
    let dt = 1.0 / 30.0;
    let steps = (args.seconds / dt).ceil() as u32;
    let every = (steps / args.frames).max(1);
    let mut written = 0;
    let mut rendered = crates.clone();
    println!("{}", ctx.adapter_line());
    for s in 0..=steps {
        let t = s as f32 * dt;
        for (k, c) in crates.iter_mut().enumerate() {
            step(world, c, dt, t, k);
        }
        if s % every != 0 || written >= args.frames {
            continue;
        }
        let scene = with_crates(&demo, &crates);
        let prepared = renderer.prepare(&scene)?;
        renderer.set_water_decals(&splashes(&crates, t))?;
        frame.time = t;
        renderer.render(&prepared, &frame, RenderPath::Deferred)?;
        rendered.clone_from(&crates);
        let file = args.out.join(format!("float_river_{written}.png"));
        renderer.read_output()?.write_png(&file)?;
        let afloat = crates.iter().filter(|c| c.afloat).count();
        let fastest = crates
            .iter()
            .map(|c| c.velocity.length())
            .fold(0.0f32, f32::max);
        println!(
            "t = {t:5.1} s: {afloat} of {} crates afloat, fastest {fastest:.2} m/s -> {}",
            crates.len(),
            file.display()
        );
        written += 1;
    }
    // The CPU query against the GPU's water: beside each crate afloat, the surface the GPU
    // drew (depth with water) against the height the CPU answered.
    let view_proj = frame
        .camera
        .view_projection(args.width as f32 / args.height as f32);
    let depth = renderer.inspect().read_water_depth()?.unwrap_or_default();
    let inv = view_proj.inverse();
    let (mut compared, mut worst) = (0, 0.0f32);
    for c in rendered.iter().filter(|c| c.afloat) {
        // Two metres downstream of the crate, clear of it.
        let dir = c.velocity.normalize_or(Vec2::X);
        let p2 = c.position.truncate() + dir * 2.0;
        let Some(q) = world.query(p2) else { continue };
        let clip = view_proj * Vec4::new(p2.x, q.height, -p2.y, 1.0);
        if clip.w <= 0.0 {
            continue;
        }
        let ndc = clip.truncate() / clip.w;
        if ndc.x.abs() >= 1.0 || ndc.y.abs() >= 1.0 {
            continue;
        }
        let px = ((ndc.x * 0.5 + 0.5) * args.width as f32) as u32;
        let py = ((0.5 - ndc.y * 0.5) * args.height as f32) as u32;
        let d = depth[(py.min(args.height - 1) * args.width + px.min(args.width - 1)) as usize];
        let w = inv * Vec4::new(ndc.x, ndc.y, d, 1.0);
        let gpu_height = w.y / w.w;
        let err = (gpu_height - q.height).abs();
        worst = worst.max(err);
        compared += 1;
    }
    println!(
        "CPU query against the GPU surface beside {compared} crates: largest difference {worst:.2} m \
         (the GPU's waves, up to {:.2} m, and its one-pixel footprint)",
        demo.water.materials[1].displacement_amplitude * 2.0
    );
    Ok(())
}
