//! FC5's water in the frame on a device (lavapipe in CI, validation on): the GPU tiles
//! equal `water::tiles`' CPU twin (subgroup ballots and the workgroup fallback); the
//! displacement equals the CPU FBM and decals; the river scene matches its golden image;
//! water on or off leaves every pixel without water as the opaque frame drew it; a world
//! over a limit is an error, never a panic; a garbage mini G-buffer makes no validation
//! error and only bounded outputs; the f16 and f32 composites agree.
//!
//! `GPU_BLESS=1 cargo test -p gpu --test water` rewrites the golden image from this
//! machine's device.

mod common;

use std::path::PathBuf;
use std::sync::OnceLock;

use demo::river::{RiverDemo, river};
use gpu::glam::{Affine3A, Quat, UVec2, Vec2, Vec3};
use gpu::inspect::diff_metrics;
use gpu::water;
use gpu::water::decal::{DecalTexture, DisplacementDecal, combined_displacement};
use gpu::water::material::WaterMaterial;
use gpu::water::noise::Fbm;
use gpu::water::optics::WaterType;
use gpu::water::tiles::{GridMesh, TILE_SIZE, TileGrid, classify};
use gpu::water::world::{Lake, Ocean, WaterWorldBuilder};
use gpu::water_scene::WaterDecal;
use gpu::{
    Camera, Error, FrameInput, RenderPath, Renderer, RendererConfig, Rgba8Image, Scene,
    WaterOptions, WaterScene,
};
use testkit::device::{GoldenBounds, check_golden, ctx};

/// The river demo, built once (the bakes take a second or two unoptimised).
fn demo() -> &'static RiverDemo {
    static DEMO: OnceLock<RiverDemo> = OnceLock::new();
    DEMO.get_or_init(|| river(3, 0.15, &mut water::no_progress).unwrap())
}

fn config(width: u32, height: u32, subgroups: bool) -> RendererConfig {
    {
        let mut rc = RendererConfig::sized(width, height);
        rc.geometry.subgroups = subgroups;
        rc.lighting.shadows = common::test_shadows();
        rc
    }
}

/// A renderer of the river at `width` x `height` with its water (and `options`), the
/// prepared scene.
fn river_renderer(
    width: u32,
    height: u32,
    subgroups: bool,
    options: WaterOptions,
) -> (Renderer, gpu::PreparedScene) {
    let d = demo();
    let mut r = common::renderer_with(config(width, height, subgroups));
    let p = r.prepare(&d.scene).unwrap();
    let mut water = d.water.clone();
    water.options = options;
    r.set_water(Some(&water)).unwrap();
    r.set_water_decals(&d.decals).unwrap();
    (r, p)
}

fn subgroup_settings() -> Vec<bool> {
    testkit::device::subgroup_variants()
        .into_iter()
        .map(|f| !f.is_empty())
        .collect()
}

/// The mini G-buffer's tiles, counts and list from the GPU, against `water::tiles::classify`
/// over the same data words read back.
fn check_tiles(r: &Renderer, what: &str) -> u32 {
    let g = r.inspect().read_water_gbuffer().unwrap().unwrap();
    let t = r.inspect().read_water_tiles().unwrap().unwrap();
    let grid = TileGrid::new(g.size[0], g.size[1], TILE_SIZE).unwrap();
    let mesh = GridMesh::new(16).unwrap();
    let cpu = classify(&grid, &g.data, &mesh).unwrap();
    assert_eq!(t.tiles, [grid.tiles_x(), grid.tiles_y()], "{what}");
    assert_eq!(t.counts, cpu.counts, "{what}: per-tile counts");
    let mut list = t.list.clone();
    list.sort_unstable();
    assert_eq!(list, cpu.tiles, "{what}: the tile list (as a set)");
    assert_eq!(t.instance_count, cpu.args.instance_count, "{what}");
    assert_eq!(t.index_count, cpu.args.vertex_count, "{what}: 6 * 16 * 16");
    assert_eq!(t.index_count, 1536, "the talk's 1536 indices a tile");
    t.instance_count
}

#[test]
fn gpu_tiles_equal_the_cpu_twin() {
    for subgroups in subgroup_settings() {
        // 300x170: a mini G-buffer of 150x85 with partial tiles right and bottom.
        let (mut r, p) = river_renderer(300, 170, subgroups, WaterOptions::default());
        let d = demo();
        r.render(&p, &d.frame, RenderPath::Deferred).unwrap();
        let what = format!("river, subgroups {subgroups}");
        let tiles = check_tiles(&r, &what);
        let total = r
            .inspect()
            .read_water_tiles()
            .unwrap()
            .unwrap()
            .counts
            .len() as u32;
        assert!(
            tiles > 2 && tiles <= total,
            "{what}: {tiles} of {total} tiles"
        );
        let stats = r.inspect().water_stats().unwrap().unwrap();
        assert_eq!(stats.tiles, tiles);
        assert_eq!(stats.triangles, u64::from(tiles) * 512);
        assert!(stats.near_bodies >= 2 && stats.far_sectors > 0, "{stats:?}");
        // And over random words (a third with the valid bit): the same twin.
        let mut rng = testkit::Rng::new(9);
        let [w, h] = stats.buffer;
        let n = (w * h) as usize;
        let data: Vec<u32> = (0..n)
            .map(|_| {
                let x = rng.next_u32();
                if rng.chance(33) {
                    x | 0x100
                } else {
                    x & !0x100
                }
            })
            .collect();
        r.hooks()
            .set_water_gbuffer(Some((
                &data,
                &vec![5.0; n],
                &vec![[0, 0x3c00, 0, 0x3c00]; n],
            )))
            .unwrap();
        r.render(&p, &d.frame, RenderPath::Deferred).unwrap();
        check_tiles(&r, &format!("random words, subgroups {subgroups}"));
    }
}

/// One big lake at height 0 under the whole view and an empty opaque scene: every pixel
/// of the mini G-buffer one material, no seams.
fn lake_scene(decal: bool) -> (WaterScene, Vec<WaterDecal>, FrameInput) {
    let mut b = WaterWorldBuilder::new();
    b.lakes.push(Lake {
        polygon: vec![
            Vec2::new(-600.0, -600.0),
            Vec2::new(600.0, -600.0),
            Vec2::new(600.0, 600.0),
            Vec2::new(-600.0, 600.0),
        ],
        height: 0.0,
        material: 0,
    });
    let world = b.build(&mut water::no_progress).unwrap();
    let mut m = WaterMaterial::from_type(&WaterType::RIVER);
    m.displacement_amplitude = 0.3;
    let mut water = WaterScene::new(world, vec![m]);
    water.fbm.frequency = 1.0 / 16.0;
    // Room for the decal's lift (the passes clamp displacement to the FBM's bound plus
    // this).
    water.options.decal_height = 4.0;
    let mut decals = Vec::new();
    if decal {
        let texels = (0..8 * 8 * 2)
            .map(|i| {
                let (x, y, f) = ((i % 8) as f32, ((i / 8) % 8) as f32, (i / 64) as f32);
                Vec3::new(0.1 * (x - 3.5), -0.05 * y, 0.4 + 0.05 * (x + y) + 0.2 * f)
            })
            .collect();
        water
            .decal_textures
            .push(DecalTexture::new(8, 8, 2, texels).unwrap());
        decals.push(WaterDecal {
            box_to_world: Affine3A::from_scale_rotation_translation(
                Vec3::new(6.0, 4.0, 2.0),
                Quat::from_rotation_z(0.4),
                Vec3::new(2.0, 18.0, 0.0),
            ),
            texture: 0,
            strength: 0.8,
            frame: 0.3,
            fade: 0.3,
        });
    }
    // Water (x, y) is +Y-up (x, -y): the camera 12 m above (0, 0) looks towards +y.
    let camera = Camera::look_at(Vec3::new(0.0, 12.0, 0.0), Vec3::new(0.0, 0.0, -30.0));
    (water, decals, FrameInput::new(camera))
}

#[test]
fn displacement_equals_the_cpu_fbm_and_decals() {
    let (water, decals, frame) = lake_scene(true);
    let mut r = common::renderer_with(config(192, 108, true));
    let p = r.prepare(&Scene::default()).unwrap();
    r.set_water(Some(&water)).unwrap();
    r.set_water_decals(&decals).unwrap();
    r.render(&p, &frame, RenderPath::Deferred).unwrap();
    let g = r.inspect().read_water_gbuffer().unwrap().unwrap();
    let disp = r.inspect().read_water_displacement().unwrap().unwrap();
    let view = r.water_view(&frame.camera).unwrap();
    let fbm = Fbm::new(&water.noise, water.fbm).unwrap();
    let amplitude = water.materials[0].displacement_amplitude;
    let texture = &water.decal_textures[0];
    let cpu_decals: Vec<DisplacementDecal<'_>> = decals
        .iter()
        .map(|d| DisplacementDecal {
            box_to_world: d.box_to_world,
            texture,
            strength: d.strength,
            frame: d.frame,
            fade: d.fade,
        })
        .collect();
    let [w, h] = g.size;
    let (mut checked, mut in_decal, mut worst) = (0, 0, 0.0f32);
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            if g.data[i] & 0x100 == 0 {
                assert_eq!(disp[i], [0.0; 4], "no water, no displacement");
                continue;
            }
            let p = view.world_position(&frame.camera, UVec2::new(x, y), g.depth[i]);
            let wp = Vec2::new(p.x, -p.z);
            let s = fbm.sample(wp, (p - frame.camera.position).length());
            let decal = combined_displacement(&cpu_decals, Vec3::new(p.x, -p.z, p.y));
            let want =
                Vec3::new(0.0, s.height * amplitude, 0.0) + water::axes::y_up_from_z_up(decal);
            let got = Vec3::new(disp[i][0], disp[i][1], disp[i][2]);
            let err = (got - want).abs().max_element();
            worst = worst.max(err);
            // Positions reconstructed on the CPU round apart from the GPU's by about
            // 1e-6 of their distance, which the FBM's steepest octaves turn into up to
            // 1e-4 m (8e-5 m measured on llvmpipe).
            assert!(err < 5e-4, "pixel ({x}, {y}) at {p}: GPU {got}, CPU {want}");
            checked += 1;
            in_decal += usize::from(decal != Vec3::ZERO);
        }
    }
    eprintln!("{checked} pixels, {in_decal} under the decal, worst {worst:e} m");
    assert!(checked > (w * h / 2) as usize, "{checked} of {}", w * h);
    assert!(in_decal > 20, "{in_decal}");
}

#[test]
fn the_river_matches_its_golden_image() {
    let (mut r, p) = river_renderer(160, 90, true, WaterOptions::default());
    r.render(&p, &demo().frame, RenderPath::Deferred).unwrap();
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden");
    check_golden(
        &dir.join("river_160x90.png"),
        &r.read_output().unwrap(),
        GoldenBounds::blessed_on_llvmpipe(),
    );
}

#[test]
fn water_on_and_off_leave_the_opaque_image_alone() {
    let d = demo();
    for path in [RenderPath::Deferred, RenderPath::Baseline] {
        let mut off = common::renderer_with(config(256, 144, true));
        let p_off = off.prepare(&d.scene).unwrap();
        off.render(&p_off, &d.frame, path).unwrap();
        let dry = off.read_output().unwrap();
        let (mut on, p_on) = river_renderer(256, 144, true, WaterOptions::default());
        on.render(&p_on, &d.frame, path).unwrap();
        let wet = on.read_output().unwrap();
        let surface = on.inspect().read_water_surface().unwrap().unwrap();
        let (mut water, mut changed) = (0, 0);
        for (i, s) in surface.iter().enumerate() {
            if s[0] > 0.0 {
                water += 1;
                changed += usize::from(dry.pixels[i] != wet.pixels[i]);
            } else {
                assert_eq!(
                    dry.pixels[i], wet.pixels[i],
                    "{path:?}: pixel {i} has no water but changed"
                );
            }
        }
        assert!(
            water > 2000 && changed > water / 2,
            "{path:?}: {water} water pixels, {changed} changed"
        );
        // The opaque depth is untouched; the depth with water is nearer where water is.
        let depth = on.inspect().read_depth().unwrap();
        assert_eq!(depth, off.inspect().read_depth().unwrap(), "{path:?}");
        let with = on.inspect().read_water_depth().unwrap().unwrap();
        for (i, s) in surface.iter().enumerate() {
            assert!(with[i] >= depth[i]);
            if s[0] == 0.0 {
                assert_eq!(with[i], depth[i]);
            }
        }
        // Taking the water away gives the opaque frame back.
        on.set_water(None).unwrap();
        on.render(&p_on, &d.frame, path).unwrap();
        assert_eq!(on.read_output().unwrap(), dry, "{path:?}");
    }
}

#[test]
fn a_world_over_the_limits_is_an_error_never_a_panic() {
    let d = demo();
    let mut r = common::renderer_with(config(64, 36, true));
    let p = r.prepare(&d.scene).unwrap();
    let named = |e: Error| match e {
        Error::WaterLimit { limit_name, .. } => limit_name,
        other => panic!("{other}"),
    };
    // More far sectors than Far Cry's 64 x 64.
    let mut w = d.water.clone();
    w.options.ocean_extent = 64.0 * 64.0 * 2.0;
    assert_eq!(
        named(r.set_water(Some(&w)).unwrap_err()),
        "MAX_WATER_SECTORS_PER_SIDE"
    );
    // More materials than the data word's 11 bits leave.
    let mut w = d.water.clone();
    w.materials = vec![w.materials[0]; gpu::water_scene::MAX_WATER_MATERIALS as usize + 1];
    assert_eq!(
        named(r.set_water(Some(&w)).unwrap_err()),
        "MAX_WATER_MATERIALS"
    );
    // A material the world names, missing.
    let mut w = d.water.clone();
    w.materials.truncate(2);
    assert!(matches!(
        r.set_water(Some(&w)),
        Err(Error::WaterLimit { .. })
    ));
    // More lakes than the near path draws.
    let mut b = WaterWorldBuilder::new();
    b.ocean = Some(Ocean {
        level: 0.0,
        material: 0,
    });
    for k in 0..=gpu::water_scene::MAX_WATER_BODIES {
        let c = Vec2::new((k % 40) as f32 * 6.0, (k / 40) as f32 * 6.0);
        b.lakes.push(Lake {
            polygon: vec![c, c + Vec2::X * 3.0, c + Vec2::ONE * 3.0, c + Vec2::Y * 3.0],
            height: 1.0,
            material: 0,
        });
    }
    let many = WaterScene::new(
        b.build(&mut water::no_progress).unwrap(),
        vec![WaterMaterial::from_type(&WaterType::RIVER)],
    );
    assert_eq!(
        named(r.set_water(Some(&many)).unwrap_err()),
        "MAX_WATER_BODIES"
    );
    // Options out of range, NaN included.
    let mut w = d.water.clone();
    w.options.fov_scale = f32::NAN;
    assert!(matches!(r.set_water(Some(&w)), Err(Error::Water(_))));
    let mut w = d.water.clone();
    w.options.resolution_scale = 4.0;
    assert!(matches!(r.set_water(Some(&w)), Err(Error::Water(_))));
    // Decals: too many, a missing texture, a box that is not invertible.
    r.set_water(Some(&d.water)).unwrap();
    let decal = d.decals[0];
    let too_many = vec![decal; gpu::water_scene::MAX_WATER_DECALS as usize + 1];
    assert_eq!(
        named(r.set_water_decals(&too_many).unwrap_err()),
        "MAX_WATER_DECALS"
    );
    let missing = WaterDecal {
        texture: 7,
        ..decal
    };
    assert!(r.set_water_decals(&[missing]).is_err());
    let flat = WaterDecal {
        box_to_world: Affine3A::from_scale(Vec3::new(1.0, 0.0, 1.0)),
        ..decal
    };
    assert!(r.set_water_decals(&[flat]).is_err());
    // The renderer still draws (with water, and after a failed set_water, without).
    r.render(&p, &d.frame, RenderPath::Deferred).unwrap();
    let _ = r.set_water(Some(&w));
    assert!(!r.has_water());
    r.render(&p, &d.frame, RenderPath::Deferred).unwrap();
}

#[test]
fn a_garbage_mini_gbuffer_reads_and_writes_nothing_out_of_bounds() {
    let mut rng = testkit::Rng::new(17);
    for half in [true, false] {
        let (mut r, p) = river_renderer(
            200,
            120,
            true,
            WaterOptions {
                half_precision: half,
                ..WaterOptions::default()
            },
        );
        let d = demo();
        let [w, h] = [100u32, 60u32];
        let n = (w * h) as usize;
        for round in 0..3 {
            let data = rng.words(n);
            let depth: Vec<f32> = (0..n)
                .map(|i| match (round + i) % 5 {
                    0 => f32::from_bits(rng.next_u32()),
                    1 => rng.range(-10.0, 1.0e4),
                    2 => [f32::NAN, f32::INFINITY, -f32::INFINITY, 3.0e38, -0.0][i % 5],
                    _ => rng.range(0.1, 300.0),
                })
                .collect();
            let normal: Vec<[u16; 4]> = (0..n)
                .map(|_| {
                    let x = rng.next_u64();
                    [
                        x as u16,
                        (x >> 16) as u16,
                        (x >> 32) as u16,
                        (x >> 48) as u16,
                    ]
                })
                .collect();
            r.hooks()
                .set_water_gbuffer(Some((&data, &depth, &normal)))
                .unwrap();
            r.render(&p, &d.frame, RenderPath::Deferred)
                .unwrap_or_else(|e| panic!("half {half}, round {round}: {e}"));
            let t = r.inspect().read_water_tiles().unwrap().unwrap();
            let total = t.counts.len() as u32;
            assert!(t.instance_count <= total);
            assert!(t.list.iter().all(|&tile| tile < total));
            assert!(t.counts.iter().sum::<u32>() <= w * h);
            let limit = 10.0;
            for v in r.inspect().read_water_displacement().unwrap().unwrap() {
                assert!(v.iter().all(|c| c.is_finite() && c.abs() <= limit), "{v:?}");
            }
            for s in r.inspect().read_water_surface().unwrap().unwrap() {
                assert!(s.iter().all(|c| !c.is_nan()), "{s:?}");
            }
            let _ = r.read_output().unwrap();
        }
        // And back to the position pass.
        r.hooks().set_water_gbuffer(None).unwrap();
        r.render(&p, &d.frame, RenderPath::Deferred).unwrap();
        assert!(r.inspect().water_stats().unwrap().unwrap().tiles > 0);
    }
}

#[test]
fn the_f16_and_f32_composites_agree() {
    if !ctx().paths.f16 {
        eprintln!(
            "{} has no SHADER_F16: the f32 composite only",
            ctx().adapter_line()
        );
    }
    let image = |half: bool| -> (Rgba8Image, bool) {
        let (mut r, p) = river_renderer(
            256,
            144,
            true,
            WaterOptions {
                half_precision: half,
                ..WaterOptions::default()
            },
        );
        r.render(&p, &demo().frame, RenderPath::Deferred).unwrap();
        let used = r.inspect().water_stats().unwrap().unwrap().half_precision;
        (r.read_output().unwrap(), used)
    };
    let (full, used_full) = image(false);
    assert!(!used_full);
    let (half, used_half) = image(true);
    assert_eq!(used_half, ctx().paths.f16);
    let (mean, _) = diff_metrics(&full, &half, 0.5).unwrap();
    let (_, p99) = diff_metrics(&full, &half, 0.99).unwrap();
    eprintln!("f16 against f32: mean {mean:.3}, p99 {p99}");
    assert!(mean < 0.5 && p99 <= 8, "mean {mean}, p99 {p99}");
}

/// The water over issue 17's compute laydown, which then writes the depth target the
/// water's HiZ, depth copy and tessellation read (without it they would see the previous
/// frame's depth, or none): the same water as over the hardware laydown, and the image
/// within the deferred-vs-baseline bounds (mean 1.0 / 255, p99 24).
#[test]
fn the_water_over_the_compute_laydown_matches_the_hardware_laydown() {
    assert!(
        ctx().paths.int64_atomics,
        "no 64-bit atomics on {}: the compute laydown needs them (lavapipe has them)",
        ctx().adapter_line()
    );
    let d = demo();
    let frame = |laydown| {
        let mut r = common::renderer_with(RendererConfig {
            geometry: gpu::config::GeometryConfig {
                laydown,
                ..config(256, 144, true).geometry
            },
            ..config(256, 144, true)
        });
        assert_eq!(r.laydown(), laydown);
        let p = r.prepare(&d.scene).unwrap();
        r.set_water(Some(&d.water)).unwrap();
        r.set_water_decals(&d.decals).unwrap();
        r.render(&p, &d.frame, RenderPath::Deferred).unwrap();
        let water = r
            .inspect()
            .read_water_surface()
            .unwrap()
            .unwrap()
            .iter()
            .filter(|s| s[0] > 0.0)
            .count();
        (r.read_output().unwrap(), water)
    };
    let (hardware, hw_water) = frame(gpu::Laydown::Hardware);
    let (compute, cs_water) = frame(gpu::Laydown::Compute);
    assert!(hw_water > 2000, "{hw_water} water pixels");
    assert!(
        cs_water.abs_diff(hw_water) * 100 <= hw_water,
        "water pixels: compute laydown {cs_water}, hardware {hw_water}"
    );
    let (mean, _) = diff_metrics(&compute, &hardware, 0.5).unwrap();
    let (_, p99) = diff_metrics(&compute, &hardware, 0.99).unwrap();
    assert!(
        mean <= 1.0 && p99 <= 24,
        "compute vs hardware laydown under water: mean {mean:.3}, p99 {p99}"
    );
}
