//! HFW's software VRS on the GPU: the rate bits the laydown writes, the classification's
//! quad commands (equal to `tiling`'s CPU twin), and the resolve's broadcast. Checked on the
//! forest, stationary and moving, with and without the vertex ring:
//! - the read-back quad commands' pixel masks cover every valid pixel exactly once (each
//!   receiving pixel is one entry of the resolve's expanded list: written once);
//! - every pixel of a quad command holds, bit for bit, the G-buffer of the command's sample
//!   pixel (the broadcast), and the sample sits in its mask;
//! - pixels rated 1x1 are bit-identical to the frame without VRS;
//! - moving the camera fast coarsens rates (HFW: "everything blends towards using 2x2"),
//!   and the pixel-shading waves (the GPU's own wave count, and the read-back's) drop.

mod common;

use demo::{DemoOptions, DemoScene};
use glam::Vec3;
use gpu::config::VrsConfig;
use gpu::scene::Wind;
use gpu::{RenderPath, RendererConfig};

const W: u32 = 200;
const H: u32 = 120;

#[test]
fn quad_commands_cover_every_pixel_once_and_the_broadcast_equals_the_sample() {
    let (mut scene, frame) = demo::build(&DemoOptions {
        scene: DemoScene::Forest,
        seed: 11,
        density: 0.05,
    });
    scene.wind = Some(Wind::default());
    let vrs = VrsConfig {
        distance_2x1: 6.0,
        distance_2x2: 14.0,
        speed_2x1: 6.0,
        speed_2x2: 16.0,
    };
    let mut twox2 = Vec::new();
    for ring in [None, Some(gpu::config::RING_BYTES_PS4)] {
        for step in [0.0_f32, 0.5] {
            let mut before = frame.clone();
            before.camera.position -= Vec3::new(step, 0.0, 0.0);
            before.camera.target -= Vec3::new(step, 0.0, 0.0);
            let mut runs = Vec::new();
            for vrs in [None, Some(vrs)] {
                let mut r = common::renderer_with({
                    let mut rc = RendererConfig::sized(W, H);
                    rc.geometry.vertex_ring = ring;
                    rc.geometry.vrs = vrs;
                    rc.lighting.shadows = None;
                    rc
                });
                let prepared = r.prepare(&scene).unwrap();
                r.render(&prepared, &before, RenderPath::Deferred).unwrap();
                r.render(&prepared, &frame, RenderPath::Deferred).unwrap();
                let class = r.inspect().read_classification(&prepared).unwrap();
                let stats = common::equals_twin(
                    &r,
                    &prepared,
                    &class,
                    &format!("GPU classification vs CPU twin (VRS {vrs:?})"),
                );
                runs.push((r.inspect().read_gbuffer().unwrap(), class, stats));
            }
            let (plain, _, plain_stats) = &runs[0];
            let (rated, class, stats) = &runs[1];
            let what = format!("ring {ring:?}, step {step} m");

            // Coverage: the masks of the quad commands partition the valid pixels.
            let mut hits = vec![0u8; (W * H) as usize];
            let mut broadcast_pixels = 0usize;
            for w in &class.waves {
                let (tx, ty) = w.tile_xy();
                for &cmd in &class.commands
                    [w.first_command as usize..(w.first_command + w.command_count) as usize]
                {
                    let (qx, qy, mask) = tiling::vrs::unpack_quad_command(cmd);
                    let (sx, sy) = tiling::vrs::sample_pixel(cmd);
                    let (ox, oy) = (tx * tiling::TILE_SIZE, ty * tiling::TILE_SIZE);
                    let sample = ((oy + sy) * W + ox + sx) as usize;
                    assert!(
                        mask & (1 << ((sy & 1) * 2 + (sx & 1))) != 0,
                        "sample in its mask"
                    );
                    broadcast_pixels += usize::from(mask.count_ones() > 1);
                    for b in 0..4 {
                        if mask & (1 << b) == 0 {
                            continue;
                        }
                        let (x, y) = (ox + 2 * qx + (b & 1), oy + 2 * qy + (b >> 1));
                        let i = (y * W + x) as usize;
                        hits[i] += 1;
                        assert!(
                            rated[i] == rated[sample],
                            "{what}: pixel ({x}, {y}) is not its sample's ({}, {})",
                            ox + sx,
                            oy + sy
                        );
                    }
                }
            }
            let mut rates = [0usize; 4];
            let mut one_by_one = 0usize;
            for (i, &word) in class.vis.iter().enumerate() {
                if word == visbuf::VIS_NONE {
                    assert_eq!(hits[i], 0, "{what}: sky pixel {i} in a command");
                    continue;
                }
                assert_eq!(hits[i], 1, "{what}: pixel {i} covered {} times", hits[i]);
                let rate = (word >> 30) as usize;
                rates[rate] += 1;
                if rate == 0 {
                    one_by_one += 1;
                    assert!(
                        rated[i] == plain[i],
                        "{what}: 1x1 pixel {i} differs from the frame without VRS"
                    );
                }
            }
            eprintln!(
                "{what}: rates 1x1 {} 1x2 {} 2x1 {} 2x2 {}; {broadcast_pixels} broadcasting commands; \
                 waves {} with VRS / {} without (depth-equal {})",
                rates[0],
                rates[1],
                rates[2],
                rates[3],
                class.totals.wave_count,
                plain_stats.wave_commands,
                stats.depth_equal_waves
            );
            assert!(rates[2] + rates[3] > 1000, "{rates:?}");
            if step == 0.0 {
                assert!(one_by_one > 1000, "{rates:?}");
            }
            assert!(broadcast_pixels > 100);
            // The talk's table: fewer pixel-shading waves, from the GPU's counter and the
            // read-back measurement alike.
            assert_eq!(u64::from(class.totals.wave_count), stats.wave_commands);
            assert!(stats.wave_commands < plain_stats.wave_commands);
            twox2.push(rates[3]);
        }
    }
    // Moving fast coarsens the rates.
    assert!(twox2[1] > twox2[0] && twox2[3] > twox2[2], "{twox2:?}");
}
