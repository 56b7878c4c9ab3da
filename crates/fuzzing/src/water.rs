//! Fuzz bodies for the `water` crate: the water query over arbitrary worlds and positions
//! (built from the input, and decoded from arbitrary words), the signed distance transform
//! of arbitrary masks against brute force, the flow bake of arbitrary masks and seeds, the
//! flow atlas decoder, and the mini G-buffer word. Nothing here may panic except a check.

use glam::{Vec2, Vec3};
use water::world::{Lake, Ocean, River, RiverPoint, WaterWorld, WaterWorldBuilder};

use crate::Input;

/// A coordinate in [-256, 256) m, or (one time in 16) an arbitrary f32.
fn coord(input: &mut Input<'_>) -> f32 {
    let raw = input.u32();
    if raw & 0xf == 0xf {
        f32::from_bits(input.u32())
    } else {
        (raw >> 4) as f32 / (1 << 28) as f32 * 512.0 - 256.0
    }
}

fn small(input: &mut Input<'_>, max: f32) -> f32 {
    f32::from(input.u16()) / 65535.0 * max
}

/// The water query: worlds from the input (lakes, rivers, an ocean, settings), queried at
/// input positions and at arbitrary floats. Every answer is finite where it should be, the
/// ocean makes every finite position wet, and the words survive `from_words`.
pub fn water_query(data: &[u8]) {
    let mut input = Input::new(data);
    let mut b = WaterWorldBuilder::new();
    let flags = input.u8();
    if flags & 1 != 0 {
        b.ocean = Some(Ocean {
            level: coord(&mut input) * 0.1,
            material: u32::from(input.u8()),
        });
    }
    b.settings.texel_size = 0.5 + small(&mut input, 4.0);
    b.settings.tile_texels = 4 + u32::from(input.u8() % 60);
    b.settings.max_leaf_edges = 1 + u32::from(input.u8() % 24);
    b.settings.max_depth = u32::from(input.u8() % 14);
    for l in 0..input.u8() % 4 {
        let n = 3 + input.u8() % 24;
        let c = Vec2::new(coord(&mut input), coord(&mut input));
        let polygon = (0..n)
            .map(|_| c + Vec2::new(coord(&mut input), coord(&mut input)) * 0.25)
            .collect();
        b.lakes.push(Lake {
            polygon,
            height: coord(&mut input) * 0.1,
            material: u32::from(l),
        });
    }
    for r in 0..input.u8() % 3 {
        let n = 1 + input.u8() % 8;
        let points = (0..n)
            .map(|_| RiverPoint {
                position: Vec3::new(
                    coord(&mut input),
                    coord(&mut input),
                    coord(&mut input) * 0.1,
                ),
                width: small(&mut input, 30.0),
                depth: small(&mut input, 5.0),
                speed: small(&mut input, 8.0) - 2.0,
            })
            .collect();
        b.rivers.push(River {
            points,
            material: 10 + u32::from(r),
        });
    }
    let world = match b.build(&mut water::no_progress) {
        Ok(w) => w,
        Err(e) => {
            assert!(!e.to_string().is_empty());
            return;
        }
    };
    let again = WaterWorld::from_words(world.words().to_vec()).expect("a baked world validates");
    assert_eq!(again, world);
    while input.remaining() > 0 {
        let p = Vec2::new(coord(&mut input), coord(&mut input));
        let q = world.query(p);
        if !p.is_finite() {
            assert!(q.is_none(), "non-finite position {p} answered {q:?}");
            continue;
        }
        if b.ocean.is_some() {
            assert!(q.is_some(), "the ocean is everywhere: {p}");
        }
        if let Some(l) = q {
            assert!(
                l.height.is_finite() && l.flow.is_finite() && !l.depth.is_nan(),
                "{p}: {l:?}"
            );
            assert!(l.body.kind().is_some());
        }
    }
}

/// `data` as little-endian words, the last one zero-padded.
fn le_words(data: &[u8]) -> Vec<u32> {
    let mut input = Input::new(data);
    (0..data.len().div_ceil(4)).map(|_| input.u32()).collect()
}

/// Arbitrary words as a world: `from_words` either rejects them or queries never panic.
pub fn water_world_decode(data: &[u8]) {
    let mut words: Vec<u32> = le_words(data);
    // Often give it a plausible header so the checks past it get exercised.
    if words.len() > 20 && words[0] & 1 == 0 {
        words[0] = water::world::WORLD_MAGIC;
        words[1] = water::world::WORLD_VERSION;
        words[19] = words.len() as u32;
    }
    if let Ok(world) = WaterWorld::from_words(words) {
        for k in 0..64u32 {
            let h = water::hash::hash2(k, data.len() as u32);
            let p = Vec2::new(f32::from_bits(h), f32::from_bits(water::hash::pcg(h)));
            let _ = world.query(p);
            let _ = world.query(Vec2::new(
                (h % 1024) as f32 - 512.0,
                (h >> 22) as f32 - 512.0,
            ));
        }
    }
}

/// The distance transform of an arbitrary mask (up to 40 x 40) equals brute force, bit for
/// bit; bad dimensions are errors.
pub fn water_edt(data: &[u8]) {
    let mut input = Input::new(data);
    let (w, h) = (u32::from(input.u8() % 41), u32::from(input.u8() % 41));
    let bits = input.rest();
    let n = (w * h) as usize;
    let mask: Vec<u8> = (0..n)
        .map(|i| bits.get(i / 8).map_or(0, |b| (b >> (i % 8)) & 1))
        .collect();
    match water::edt::signed_squared_edt(&mask, w, h) {
        Ok(d) => assert_eq!(
            d,
            water::edt::brute_signed_squared_edt(&mask, w as usize, h as usize)
        ),
        Err(_) => assert!(w == 0 || h == 0),
    }
}

/// The flow bake over an arbitrary mask (up to 48 x 48) with arbitrary sources and a river:
/// finite flow, none on land, no faster than the fastest seed, and parallel smoothing equal
/// to sequential.
pub fn water_flow_bake(data: &[u8]) {
    use water::flowbake::{FlowBakeInput, FlowBakeSettings, FlowSource, bake_flow};
    let mut input = Input::new(data);
    let (w, h) = (
        1 + u32::from(input.u8() % 48),
        1 + u32::from(input.u8() % 48),
    );
    let settings = FlowBakeSettings {
        bank_width: small(&mut input, 8.0),
        guide_distance: small(&mut input, 40.0),
        bank_penalty: small(&mut input, water::flowbake::MAX_BANK_PENALTY),
        smoothing_iterations: u32::from(input.u8() % 6),
    };
    let sources: Vec<FlowSource> = (0..input.u8() % 4)
        .map(|_| FlowSource {
            position: Vec2::new(small(&mut input, 48.0), small(&mut input, 48.0)),
            velocity: Vec2::new(small(&mut input, 6.0) - 3.0, small(&mut input, 6.0) - 3.0),
            radius: small(&mut input, 6.0),
        })
        .collect();
    let mut fastest = sources
        .iter()
        .map(|s| s.velocity.length())
        .fold(0.0f32, f32::max);
    let mut rivers = Vec::new();
    if input.u8() & 1 == 1 {
        let points: Vec<RiverPoint> = (0..2 + input.u8() % 3)
            .map(|_| RiverPoint {
                position: Vec3::new(small(&mut input, 48.0), small(&mut input, 48.0), 0.0),
                width: small(&mut input, 12.0),
                depth: 1.0,
                speed: small(&mut input, 4.0),
            })
            .collect();
        fastest = fastest.max(points.iter().map(|p| p.speed).fold(0.0, f32::max));
        rivers.push(River {
            points,
            material: 0,
        });
    }
    let bits = input.rest();
    let mask: Vec<u8> = (0..(w * h) as usize)
        .map(|i| bits.get(i / 8).map_or(0, |b| (b >> (i % 8)) & 1))
        .collect();
    let sdf =
        water::edt::signed_edt(&mask, w, h, &mut water::no_progress).expect("valid dimensions");
    let bake_input = FlowBakeInput {
        sdf: &sdf,
        texel_size: 1.0,
        origin: Vec2::ZERO,
        rivers: &rivers,
        sources: &sources,
    };
    let field = match bake_flow(&bake_input, &settings, &mut water::no_progress) {
        Ok(f) => f,
        Err(e) => {
            assert!(!e.to_string().is_empty());
            return;
        }
    };
    for (i, v) in field.flow().iter().enumerate() {
        assert!(v.is_finite());
        if mask[i] != 0 {
            assert_eq!(*v, Vec2::ZERO, "flow on land at {i}");
        }
        assert!(
            v.length() <= fastest * 1.0001 + 1e-5,
            "{v} faster than every seed ({fastest})"
        );
    }
    let par = water::parallel::bake_flow(&bake_input, &settings, &mut water::no_progress)
        .expect("same input");
    assert_eq!(par, field);
}

/// Arbitrary texels as a flow atlas: rejected, or sampling never panics.
pub fn water_atlas_decode(data: &[u8]) {
    let mut texels: Vec<u32> = le_words(data);
    if texels.len() >= 24 && texels[0] & 1 == 0 {
        texels[0] = water::atlas::ATLAS_MAGIC;
        texels[1] = water::atlas::ATLAS_VERSION;
        let n = texels.len() as u32;
        let wd = (texels[2] % 16).max(1);
        texels[2] = wd;
        texels[3] = n / wd;
        texels.truncate((wd * (n / wd)) as usize);
    }
    if let Ok(a) = water::atlas::FlowAtlas::from_texels(texels) {
        for k in 0..64u32 {
            let h = water::hash::hash2(k, data.len() as u32);
            let _ = a.sample(Vec2::new(
                f32::from_bits(h),
                f32::from_bits(water::hash::pcg(h)),
            ));
            let _ = a.sample(Vec2::new((h % 4096) as f32 - 64.0, (h >> 20) as f32 - 64.0));
        }
    }
}

/// Data words: unpack any word, repack it to the same word; pack arbitrary fields.
pub fn water_data_word(data: &[u8]) {
    use water::gbuffer::{DataFields, DataFlags, DataWord};
    let mut input = Input::new(data);
    while input.remaining() > 0 {
        let w = input.u32();
        assert_eq!(DataWord::pack(DataWord(w).unpack()), Ok(DataWord(w)));
        let f = DataFields {
            shader_id: input.u8(),
            flags: DataFlags(input.u8()),
            material: input.u16(),
            foam_mip: input.f32(),
            algae_mip: input.f32(),
        };
        if let Ok(word) = DataWord::pack(f) {
            let back = word.unpack();
            assert_eq!(
                (back.shader_id, back.flags, back.material),
                (f.shader_id, f.flags, f.material)
            );
            assert!((0.0..=water::gbuffer::MAX_MIP_LEVEL).contains(&back.foam_mip));
        } else {
            assert!(f.flags.0 > 7 || f.material >= 2048);
        }
    }
}
