//! Tiled light culling against a per-pixel brute force, the sphere projection against
//! sampled silhouettes, and KZ2's light classification.

use deferred::lights::*;
use deferred::{DeferredLight, DeferredTileDepth, DepthMode, Error, Perspective};
use glam::{Vec2, Vec3};
use proptest::prelude::*;
use testkit::Rng;

const W: u32 = 160;
const H: u32 = 96;

fn perspective(mode: DepthMode) -> Perspective {
    Perspective::try_new(1.1, W as f32 / H as f32, 0.1, Some(200.0), mode).unwrap()
}

/// A depth buffer of a few slanted planes in front of a far wall, with sky above a
/// horizon: tiles of one depth, tiles of wide ranges, empty tiles.
fn scene_depth(p: &Perspective, rng: &mut Rng) -> Vec<f32> {
    let proj = p.gpu(Vec2::new(W as f32, H as f32));
    let l = p.linearize();
    let planes: Vec<(f32, f32, f32)> = (0..4)
        .map(|_| {
            (
                rng.range(2.0, 30.0),
                rng.range(-0.05, 0.05),
                rng.range(-0.05, 0.05),
            )
        })
        .collect();
    let mut depth = vec![0.0; (W * H) as usize];
    for y in 0..H {
        for x in 0..W {
            let i = (y * W + x) as usize;
            if y < H / 5 && x > W / 3 {
                depth[i] = p.mode.far_depth();
                continue;
            }
            // Each plane covers a vertical band; distance varies across it.
            let (d0, sx, sy) = planes[(x * 4 / W) as usize];
            let d = (d0 + sx * x as f32 + sy * y as f32 * 3.0).max(0.5);
            depth[i] = l.depth(d);
            let _ = proj;
        }
    }
    depth
}

fn random_lights(rng: &mut Rng, n: usize) -> Vec<DeferredLight> {
    (0..n)
        .map(|i| {
            let d = rng.range(0.5, 35.0);
            let pos = Vec3::new(rng.range(-1.0, 1.0) * d, rng.range(-0.6, 0.6) * d, -d);
            let range = rng.range(0.2, 8.0);
            if i % 3 == 0 {
                let dir = Vec3::new(
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                );
                let dir = if dir.length() < 0.1 { Vec3::NEG_Z } else { dir };
                DeferredLight::spot(pos, dir, range, rng.range(0.1, 1.4), Vec3::ONE)
            } else {
                DeferredLight::point(pos, range, Vec3::ONE)
            }
        })
        .collect()
}

/// The light touches `p` with a little margin (so float rounding at the exact boundary
/// cannot make a correct culler look wrong).
fn affects_with_margin(l: &DeferredLight, p: Vec3) -> bool {
    let mut inner = *l;
    inner.range *= 0.999;
    if inner.is_spot() {
        inner.cos_outer = (inner.cos_outer + 1e-3).min(0.999_999);
    }
    inner.affects(p)
}

fn cull(
    p: &Perspective,
    depth: &[f32],
    lights: &[DeferredLight],
) -> (Vec<DeferredTileDepth>, Vec<u32>, Vec<u32>, CullStats) {
    let proj = p.gpu(Vec2::new(W as f32, H as f32));
    let (tx, ty) = tile_counts(W, H);
    let n = (tx * ty) as usize;
    let mut tiles = vec![DeferredTileDepth::default(); n];
    tile_depth_ranges(depth, W, H, p.mode, &mut tiles).unwrap();
    let mut counts = vec![0; n];
    let mut indices = vec![0; n * MAX_LIGHTS_PER_TILE as usize];
    let stats = cull_tiles(&proj, &tiles, lights, &mut counts, &mut indices).unwrap();
    (tiles, counts, indices, stats)
}

#[test]
fn tile_lists_hold_every_light_that_lights_a_pixel() {
    for (seed, mode) in [
        (1u64, DepthMode::Reversed),
        (2, DepthMode::Standard),
        (3, DepthMode::Reversed),
    ] {
        let p = perspective(mode);
        let proj = p.gpu(Vec2::new(W as f32, H as f32));
        let mut rng = Rng::new(seed);
        let depth = scene_depth(&p, &mut rng);
        let lights = random_lights(&mut rng, 120);
        let (_, counts, indices, stats) = cull(&p, &depth, &lights);
        assert_eq!(stats.overflowed_tiles, 0);
        let (tx, _) = tile_counts(W, H);
        let mut needed_pairs = 0u64;
        let mut listed_pairs_needed = std::collections::HashSet::new();
        for y in 0..H {
            for x in 0..W {
                let d = depth[(y * W + x) as usize];
                if d == mode.far_depth() {
                    continue;
                }
                let pos = proj.view_position(Vec2::new(x as f32 + 0.5, y as f32 + 0.5), d);
                let t = ((y / TILE_SIZE) * tx + x / TILE_SIZE) as usize;
                let list = &indices[t * MAX_LIGHTS_PER_TILE as usize..][..counts[t] as usize];
                for (i, l) in lights.iter().enumerate() {
                    if affects_with_margin(l, pos) {
                        assert!(
                            list.contains(&(i as u32)),
                            "{mode:?}: light {i} {l:?} lights pixel ({x}, {y}) at {pos} but tile {t} lists {list:?}"
                        );
                        if listed_pairs_needed.insert((t, i)) {
                            needed_pairs += 1;
                        }
                    }
                }
            }
        }
        // Ascending indices, and the tiled lists are not "everything everywhere".
        for t in 0..counts.len() {
            let list = &indices[t * MAX_LIGHTS_PER_TILE as usize..][..counts[t] as usize];
            assert!(list.windows(2).all(|w| w[0] < w[1]));
        }
        eprintln!(
            "{mode:?}: {needed_pairs} needed tile-light pairs, {} listed, {} tiles with geometry",
            stats.pairs, stats.tiles_with_geometry
        );
        assert!(needed_pairs > 0);
        assert!(stats.pairs >= needed_pairs);
        assert!(
            stats.pairs < u64::from(stats.tiles_with_geometry) * lights.len() as u64 / 4,
            "{stats:?}"
        );
    }
}

#[test]
fn tile_depth_ranges_match_a_per_tile_loop() {
    for mode in [DepthMode::Reversed, DepthMode::Standard] {
        let p = perspective(mode);
        let depth = scene_depth(&p, &mut Rng::new(7));
        let (tiles, ..) = cull(&p, &depth, &[]);
        let (tx, ty) = tile_counts(W, H);
        for t_y in 0..ty {
            for t_x in 0..tx {
                let mut vals = vec![];
                for y in t_y * TILE_SIZE..((t_y + 1) * TILE_SIZE).min(H) {
                    for x in t_x * TILE_SIZE..((t_x + 1) * TILE_SIZE).min(W) {
                        let d = depth[(y * W + x) as usize];
                        if d != mode.far_depth() {
                            vals.push(d);
                        }
                    }
                }
                let t = tiles[(t_y * tx + t_x) as usize];
                if vals.is_empty() {
                    assert!(t.is_empty(mode));
                    continue;
                }
                let lo = vals.iter().cloned().fold(f32::INFINITY, f32::min);
                let hi = vals.iter().cloned().fold(f32::NEG_INFINITY, f32::max);
                let (near, far) = match mode {
                    DepthMode::Reversed => (hi, lo),
                    DepthMode::Standard => (lo, hi),
                };
                assert_eq!((t.nearest, t.farthest), (near, far));
            }
        }
    }
}

#[test]
fn overflowing_tiles_are_counted() {
    let p = perspective(DepthMode::Reversed);
    let depth = vec![p.linearize().depth(5.0); (W * H) as usize];
    let lights = vec![DeferredLight::point(Vec3::new(0.0, 0.0, -5.0), 100.0, Vec3::ONE); 300];
    let (_, counts, _, stats) = cull(&p, &depth, &lights);
    assert!(counts.iter().all(|&c| c == MAX_LIGHTS_PER_TILE));
    assert_eq!(stats.overflowed_tiles as usize, counts.len());
}

#[test]
fn bad_input_is_an_error() {
    let p = perspective(DepthMode::Reversed);
    let proj = p.gpu(Vec2::new(W as f32, H as f32));
    let (tx, ty) = tile_counts(W, H);
    let n = (tx * ty) as usize;
    let tiles = vec![DeferredTileDepth::empty(DepthMode::Reversed); n];
    let mut counts = vec![0; n];
    let mut indices = vec![0; n * MAX_LIGHTS_PER_TILE as usize];
    let bad = DeferredLight::point(Vec3::ZERO, -1.0, Vec3::ONE);
    assert_eq!(
        cull_tiles(&proj, &tiles, &[bad], &mut counts, &mut indices),
        Err(Error::InvalidLight {
            index: 0,
            field: "range"
        })
    );
    let e = cull_tiles(&proj, &tiles, &[], &mut counts[..3], &mut indices).unwrap_err();
    assert!(e.to_string().contains("counts"), "{e}");
    let mut spot = DeferredLight::spot(Vec3::ZERO, Vec3::NEG_Z, 1.0, 0.5, Vec3::ONE);
    spot.cos_outer = 0.0;
    assert!(
        spot.validate(4)
            .unwrap_err()
            .to_string()
            .contains("light 4")
    );
    let mut out = vec![DeferredTileDepth::default(); 1];
    assert!(matches!(
        tile_depth_ranges(&[], 0, 10, DepthMode::Reversed, &mut out),
        Err(Error::ViewportOutOfRange { .. })
    ));
    assert!(tile_depth_ranges(&[0.0; 4], 4, 4, DepthMode::Reversed, &mut out).is_err());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// The rectangle holds every sampled silhouette point, and touches the extremes.
    #[test]
    fn sphere_rect_bounds_the_projection(
        cx in -30.0f32..30.0, cy in -20.0f32..20.0, d in 1.0f32..60.0, r in 0.05f32..10.0
    ) {
        let p = perspective(DepthMode::Reversed);
        let vp = Vec2::new(W as f32, H as f32);
        let proj = p.gpu(vp);
        let c = Vec3::new(cx, cy, -d);
        let rect = project_sphere(&proj, c, r);
        let (mut lo, mut hi) = (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY));
        let mut any_behind = false;
        for i in 0..4000 {
            let z = 2.0 * ((i as f32 + 0.5) / 4000.0) - 1.0;
            let phi = i as f32 * 2.399_963;
            let s = (1.0 - z * z).sqrt();
            let q = c + r * Vec3::new(s * phi.cos(), s * phi.sin(), z);
            if q.z >= -1e-3 { any_behind = true; continue; }
            let ndc = Vec2::new(q.x / -q.z / proj.tan_half[0], q.y / -q.z / proj.tan_half[1]);
            let px = Vec2::new((ndc.x + 1.0) * 0.5 * vp.x, (1.0 - ndc.y) * 0.5 * vp.y).clamp(Vec2::ZERO, vp);
            lo = lo.min(px);
            hi = hi.max(px);
        }
        if d - r <= 0.0 {
            prop_assert_eq!(rect.unwrap().area(), vp.x * vp.y);
            return Ok(());
        }
        prop_assert!(!any_behind);
        match rect {
            None => prop_assert!(hi.x - lo.x <= 0.0 || hi.y - lo.y <= 0.0, "{lo} {hi}"),
            Some(rect) => {
                let eps = 1e-3 * vp.x;
                prop_assert!(rect.min.cmple(lo + eps).all() && rect.max.cmpge(hi - eps).all(), "{rect:?} vs {lo} {hi}");
                // Tight: within a pixel of the sampled extremes.
                prop_assert!((rect.min - lo).abs().max_element() < 1.0 && (rect.max - hi).abs().max_element() < 1.0, "{rect:?} vs {lo} {hi}");
            }
        }
    }

    /// The spot's bounding sphere holds its sector.
    #[test]
    fn spot_bounding_sphere_holds_the_sector(angle in 0.05f32..1.5, range in 0.1f32..20.0, u in 0.0f32..1.0, v in 0.0f32..1.0, w in 0.0f32..1.0) {
        let l = DeferredLight::spot(Vec3::new(1.0, 2.0, -3.0), Vec3::new(0.3, -0.2, -1.0), range, angle, Vec3::ONE);
        let (c, r) = l.bounding_sphere();
        // A point of the sector: distance t <= range, angle phi <= half-angle.
        let d = Vec3::from(l.direction);
        let t = d.any_orthonormal_vector();
        let b = d.cross(t);
        let phi = angle * u;
        let rot = std::f32::consts::TAU * v;
        let dir = d * phi.cos() + (t * rot.cos() + b * rot.sin()) * phi.sin();
        let q = Vec3::from(l.position) + dir * range * w.cbrt();
        prop_assert!(l.affects(q) || (q - Vec3::from(l.position)).length() > range * 0.9999);
        prop_assert!((q - c).length() <= r * (1.0 + 1e-5) + 1e-5);
    }
}

#[test]
fn kz2_classification() {
    let p = perspective(DepthMode::Reversed);
    let proj = p.gpu(Vec2::new(1280.0, 720.0));
    let k = LightClassifier::default();
    // A big light close by: volume path.
    let big = DeferredLight::point(Vec3::new(0.0, 0.0, -6.0), 4.0, Vec3::ONE);
    let c = k.classify(&proj, &big);
    assert_eq!(c.path, LightPath::Volume);
    assert!(c.coverage >= KZ2_VOLUME_COVERAGE, "{c:?}");
    // A small light far away: depth bounds are enough.
    let small = DeferredLight::point(Vec3::new(2.0, 1.0, -40.0), 1.0, Vec3::ONE);
    let c = k.classify(&proj, &small);
    assert_eq!(c.path, LightPath::DepthBounds);
    assert!(c.coverage < 0.02 && c.shadow == 0.0, "{c:?}");
    // Its depth bounds bracket its distance range (reversed: nearest is the larger).
    let l = p.linearize();
    assert!((c.depth_bounds[0] - l.depth(39.0)).abs() < 1e-6);
    assert!((c.depth_bounds[1] - l.depth(41.0)).abs() < 1e-6);
    // The same light casting shadows: small enough that its shadow has faded out.
    let c = k.classify(&proj, &small.with_shadow());
    assert_eq!((c.path, c.shadow), (LightPath::DepthBounds, 0.0), "{c:?}");
    // A mid-size shadow caster keeps (part of) its shadow and takes the volume path.
    let mid = DeferredLight::point(Vec3::new(0.0, 0.0, -20.0), 2.0, Vec3::ONE).with_shadow();
    let c = k.classify(&proj, &mid);
    assert!(c.shadow > 0.0 && c.coverage < KZ2_VOLUME_COVERAGE, "{c:?}");
    assert_eq!(c.path, LightPath::Volume);
    // Behind the camera: culled. Around the camera: volume, camera inside.
    let behind = DeferredLight::point(Vec3::new(0.0, 0.0, 5.0), 1.0, Vec3::ONE);
    assert_eq!(k.classify(&proj, &behind).path, LightPath::Culled);
    let around = DeferredLight::point(Vec3::new(0.0, 0.0, -0.5), 3.0, Vec3::ONE);
    let c = k.classify(&proj, &around);
    assert!(
        c.camera_inside && c.path == LightPath::Volume && c.coverage == 1.0,
        "{c:?}"
    );
    assert_eq!(c.depth_bounds[0], 1.0, "clamped to the near plane");
}

#[test]
fn shadow_fade_is_monotonic_between_its_thresholds() {
    let f = ShadowFade::default();
    assert_eq!(f.strength(0.0), 0.0);
    assert_eq!(f.strength(f.zero), 0.0);
    assert_eq!(f.strength(f.full), 1.0);
    assert_eq!(f.strength(0.5), 1.0);
    let mut last = 0.0;
    for i in 0..=100 {
        let s = f.strength(f.zero + (f.full - f.zero) * i as f32 / 100.0);
        assert!(s >= last && (0.0..=1.0).contains(&s));
        last = s;
    }
}

#[test]
fn depth_bounds_test_matches_per_pixel_depths() {
    let p = perspective(DepthMode::Reversed);
    let proj = p.gpu(Vec2::new(W as f32, H as f32));
    let mut rng = Rng::new(11);
    let depth = scene_depth(&p, &mut rng);
    let (tiles, ..) = cull(&p, &depth, &[]);
    let (tx, _) = tile_counts(W, H);
    let k = LightClassifier::default();
    for l in random_lights(&mut rng, 60) {
        let b = k.classify(&proj, &l).depth_bounds;
        for (t, tile) in tiles.iter().enumerate() {
            let (x0, y0) = ((t as u32 % tx) * TILE_SIZE, (t as u32 / tx) * TILE_SIZE);
            let mut any = false;
            for y in y0..(y0 + TILE_SIZE).min(H) {
                for x in x0..(x0 + TILE_SIZE).min(W) {
                    let d = depth[(y * W + x) as usize];
                    any |= d != 0.0 && d <= b[0] && d >= b[1];
                }
            }
            if any {
                assert!(depth_bounds_overlap(*tile, b, DepthMode::Reversed));
            }
        }
    }
}
