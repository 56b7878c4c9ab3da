//! `tiling`'s WGSL unpack helpers (what the `gpu` resolve uses to find a wave command's
//! pixels) on a device against the Rust definitions of the same layouts.

use tiling::{WaveCommand, pixel_command, unpack_pixel_command};

use crate::gpu_common::{Rng, run};

#[test]
fn command_and_tile_unpacking_match_the_cpu() {
    let mut rng = Rng(0x7469_6c65);
    let mut input = Vec::new();
    for i in 0..20_000u32 {
        // A packed pair of commands, an index choosing one, and a wave command's tile word.
        let (a, b) = if i % 3 == 0 {
            (rng.u32() & 0xffff, rng.u32() & 0xffff)
        } else {
            (
                u32::from(pixel_command(rng.u32() % 128, rng.u32() % 128)),
                u32::from(pixel_command(i % 128, (i / 128) % 128)),
            )
        };
        let tile = (rng.u32() % 300) | ((rng.u32() % 200) << tiling::classify::WAVE_TILE_Y_SHIFT);
        input.extend_from_slice(&[a | (b << 16), i, tile]);
    }
    let n = (input.len() / 3) as u32;
    let body = "
    let word = input[3u * i];
    let k = input[3u * i + 1u];
    let cmd = tiling_command_in_word(word, k);
    let xy = tiling_unpack_pixel_command(cmd);
    let t = tiling_wave_tile_xy(input[3u * i + 2u]);
    output[5u * i] = cmd;
    output[5u * i + 1u] = xy.x;
    output[5u * i + 2u] = xy.y;
    output[5u * i + 3u] = t.x;
    output[5u * i + 4u] = t.y;";
    let out = run(tiling::wgsl::COMMON_WGSL, body, &input, n, 5);
    for (j, item) in input.chunks_exact(3).enumerate() {
        let (word, k, tile) = (item[0], item[1], item[2]);
        let cmd = if k % 2 == 0 {
            word as u16
        } else {
            (word >> 16) as u16
        };
        let (x, y) = unpack_pixel_command(cmd);
        let wave = WaveCommand {
            tile,
            ..WaveCommand::default()
        };
        let (tx, ty) = wave.tile_xy();
        assert_eq!(
            &out[5 * j..5 * j + 5],
            &[u32::from(cmd), x, y, tx, ty],
            "word {word:#x} index {k} tile {tile:#x}"
        );
    }
}
