//! The albedo layers, painted with integer-hashed value noise, and the materials over
//! them.

use super::*;

pub(crate) const LAYER_SIZE: u32 = 256;

pub(crate) fn srgb(c: Vec3) -> [u8; 3] {
    let e = deferred::gbuffer::srgb8;
    [e(c.x), e(c.y), e(c.z)]
}

pub(crate) fn paint(f: impl Fn(Vec2) -> (Vec3, f32)) -> AlbedoLayer {
    let n = LAYER_SIZE;
    let mut texels = Vec::with_capacity((n * n) as usize);
    for y in 0..n {
        for x in 0..n {
            let uv = Vec2::new((x as f32 + 0.5) / n as f32, (y as f32 + 0.5) / n as f32);
            let (c, a) = f(uv);
            let [r, g, b] = srgb(c);
            texels.push([r, g, b, (a.clamp(0.0, 1.0) * 255.0 + 0.5) as u8]);
        }
    }
    AlbedoLayer { size: n, texels }
}

/// The forest's six layers, in the order its materials index them: ground, bark, leaves,
/// fern, grass, rock (the forest scene's and the river scene's).
pub(crate) fn forest_layers() -> Vec<AlbedoLayer> {
    vec![
        ground_layer(),
        bark_layer(),
        leaf_layer(),
        fern_layer(),
        grass_layer(),
        rock_layer(),
    ]
}

/// Tileable noise over the unit square with `cells` lattice cells per side.
pub(crate) fn tile_noise(uv: Vec2, cells: i32, seed: u32) -> f32 {
    fbm(uv * cells as f32, seed, 4, cells)
}

pub(crate) fn ground_layer() -> AlbedoLayer {
    paint(|uv| {
        let n = tile_noise(uv, 8, 11);
        let m = tile_noise(uv, 32, 12);
        let dirt = Vec3::new(0.23, 0.16, 0.09);
        let moss = Vec3::new(0.10, 0.17, 0.05);
        (
            dirt.lerp(moss, (n * 1.6 - 0.4).clamp(0.0, 1.0)) * (0.7 + 0.6 * m),
            1.0,
        )
    })
}

pub(crate) fn bark_layer() -> AlbedoLayer {
    paint(|uv| {
        let stripes = tile_noise(Vec2::new(uv.x * 4.0, uv.y * 0.25), 16, 21);
        let c = Vec3::new(0.16, 0.11, 0.07) * (0.55 + 0.9 * stripes);
        (c, 1.0)
    })
}

pub(crate) fn leaf_layer() -> AlbedoLayer {
    // Four leaf clusters in a 2x2 atlas; each cell a few elliptic leaves.
    paint(|uv| {
        let cell = (uv * 2.0).fract();
        let id = ((uv.y * 2.0) as u32) * 2 + (uv.x * 2.0) as u32;
        let mut alpha: f32 = 0.0;
        let mut shade: f32 = 0.0;
        for k in 0..7u32 {
            let h = hash2(k as i32, id as i32, 77);
            let c = Vec2::new(
                0.2 + 0.6 * ((h & 0xff) as f32 / 255.0),
                0.2 + 0.6 * (((h >> 8) & 0xff) as f32 / 255.0),
            );
            let ang = ((h >> 16) & 0xff) as f32 / 255.0 * std::f32::consts::PI;
            let d = cell - c;
            let (s, co) = ang.sin_cos();
            let q = Vec2::new(d.x * co + d.y * s, -d.x * s + d.y * co);
            let e = (q.x / 0.2).powi(2) + (q.y / 0.08).powi(2);
            if e < 1.0 {
                alpha = 1.0;
                shade = shade.max(1.0 - e * 0.5 + 0.3 * (q.y.abs() < 0.006) as u32 as f32);
            }
        }
        let c = Vec3::new(0.07, 0.19, 0.04)
            .lerp(Vec3::new(0.16, 0.29, 0.06), tile_noise(uv, 16, 31))
            * (0.6 + 0.5 * shade);
        (c, alpha)
    })
}

pub(crate) fn fern_layer() -> AlbedoLayer {
    paint(|uv| {
        // A central rib along v with leaflets either side, narrowing to the tip (v = 0).
        let x = (uv.x - 0.5) * 2.0;
        let t = 1.0 - uv.y;
        let width = 0.9 * (1.0 - t).powf(0.6) * t.powf(0.15);
        let leaflet = ((uv.y * 22.0).fract() - 0.5).abs() * 2.0;
        let inside = x.abs() < width * (0.55 + 0.45 * (1.0 - leaflet)) && x.abs() > 0.0;
        let rib = x.abs() < 0.03;
        let c = Vec3::new(0.05, 0.16, 0.03) * (0.8 + 0.5 * (1.0 - x.abs()));
        (c, if inside || rib { 1.0 } else { 0.0 })
    })
}

pub(crate) fn grass_layer() -> AlbedoLayer {
    paint(|uv| {
        // Vertical blades of varying height across u; 1 at the base (v = 1).
        let mut alpha: f32 = 0.0;
        let mut tone: f32 = 0.0;
        for k in 0..14u32 {
            let h = hash2(k as i32, 3, 99);
            let x0 = (h & 0xffff) as f32 / 65535.0;
            let height = 0.45 + 0.55 * ((h >> 16) as f32 / 65535.0);
            let t = 1.0 - uv.y;
            if t > height {
                continue;
            }
            let lean = (t / height).powi(2) * 0.08 * if h & 1 == 0 { 1.0 } else { -1.0 };
            let w = 0.022 * (1.0 - t / height);
            if (uv.x - x0 - lean).abs() < w {
                alpha = 1.0;
                tone = tone.max(0.5 + 0.5 * t / height);
            }
        }
        let c = Vec3::new(0.09, 0.2, 0.04).lerp(Vec3::new(0.3, 0.33, 0.1), tone * tone);
        (c, alpha)
    })
}

pub(crate) fn blade_layer() -> AlbedoLayer {
    paint(|uv| {
        // Four blade colour variants across u; alpha cut into a pointed tip near v = 0.
        let variant = (uv.x * 4.0) as u32;
        let x = (uv.x * 4.0).fract();
        let t = 1.0 - uv.y;
        let tip = 1.0 - ((x - 0.5).abs() * 2.0) > (t - 0.85).max(0.0) / 0.15;
        let base = [
            Vec3::new(0.10, 0.22, 0.05),
            Vec3::new(0.15, 0.25, 0.06),
            Vec3::new(0.22, 0.27, 0.08),
            Vec3::new(0.08, 0.18, 0.05),
        ];
        let c = base[variant as usize % 4] * (0.55 + 0.7 * t);
        (c, if tip { 1.0 } else { 0.0 })
    })
}

pub(crate) fn rock_layer() -> AlbedoLayer {
    paint(|uv| {
        let n = tile_noise(uv, 8, 41);
        let m = tile_noise(uv, 32, 42);
        (
            Vec3::splat(0.22 + 0.2 * n) * Vec3::new(1.0, 0.98, 0.94) * (0.8 + 0.4 * m),
            1.0,
        )
    })
}

pub(crate) fn material(name: &str, shader: ShaderKind, layer: u32, roughness: f32) -> Material {
    Material {
        name: name.to_owned(),
        shader,
        albedo_layer: layer,
        tint: Vec3::ONE,
        alpha_cutoff: 0.5,
        roughness,
        specular: 0.3,
        regular: false,
        ..Default::default()
    }
}

/// `m` drawn by the mixed frame's regular geometry pass (terrain and rocks, as in HFW).
pub(crate) fn regular(m: Material) -> Material {
    Material { regular: true, ..m }
}
