//! The flow bake against an analytic reference: a half-annulus channel, where the flow
//! must run along the circles (tangent `(-sin a, cos a)`), seeded only at its upstream end.
//! A naive flood fill (4-connected breadth-first, each texel copying the first neighbour
//! that reached it) is the baseline the SDF-guided fill must beat.

use std::collections::VecDeque;

use glam::{Vec2, Vec3};
use water::edt::{DistanceField, signed_edt};
use water::flowbake::{FlowBakeInput, FlowBakeSettings, FlowField, FlowSource, bake_flow};
use water::world::{River, RiverPoint};

const N: u32 = 160;
// The channel's two ends run off the bottom of the grid (no wall across them).
const C: Vec2 = Vec2::new(80.0, 0.0);
const R0: f32 = 30.0;
const R1: f32 = 55.0;

/// Water where `R0 <= |p - C| <= R1` (the upper half: the grid starts at `C.y`); the mask
/// is 1 (solid) elsewhere,
/// plus a round rock in the middle of the channel at the top.
fn channel(rock: bool) -> Vec<u8> {
    (0..N * N)
        .map(|i| {
            let p = Vec2::new((i % N) as f32 + 0.5, (i / N) as f32 + 0.5);
            let r = (p - C).length();
            let water = (R0..=R1).contains(&r) && p.y >= C.y;
            let on_rock = rock && (p - (C + Vec2::new(0.0, 42.5))).length() < 5.0;
            u8::from(!water || on_rock)
        })
        .collect()
}

fn sdf(mask: &[u8]) -> DistanceField {
    signed_edt(mask, N, N, &mut water::no_progress).unwrap()
}

/// The source: the upstream end of the channel (angle 0, right side), flowing +y.
fn sources() -> Vec<FlowSource> {
    vec![FlowSource {
        position: C + Vec2::new((R0 + R1) * 0.5, 1.5),
        velocity: Vec2::new(0.0, 2.0),
        radius: (R1 - R0) * 0.5,
    }]
}

fn angle_error(flow: Vec2, p: Vec2) -> f32 {
    let d = p - C;
    let tangent = Vec2::new(-d.y, d.x).normalize();
    let f = flow.normalize_or_zero();
    f.dot(tangent).clamp(-1.0, 1.0).acos().to_degrees()
}

/// Mean and 95th-percentile angle error over water texels at least 2 texels from the
/// banks and outside `skip` (a disk where the reference does not hold).
fn errors(
    field: &[Vec2],
    mask: &[u8],
    d: &DistanceField,
    skip: Option<(Vec2, f32)>,
) -> (f32, f32, usize) {
    let mut e: Vec<f32> = Vec::new();
    let mut unreached = 0;
    for i in 0..(N * N) as usize {
        if mask[i] != 0 || d.values()[i] < 2.0 {
            continue;
        }
        let p = Vec2::new((i as u32 % N) as f32 + 0.5, (i as u32 / N) as f32 + 0.5);
        if skip.is_some_and(|(c, r)| (p - c).length() < r) {
            continue;
        }
        if field[i] == Vec2::ZERO {
            unreached += 1;
            continue;
        }
        e.push(angle_error(field[i], p));
    }
    e.sort_by(f32::total_cmp);
    let mean = e.iter().sum::<f32>() / e.len() as f32;
    (mean, e[e.len() * 95 / 100], unreached)
}

/// The baseline: breadth-first over 4-neighbours, copying the flow of the texel that
/// reached each one first.
fn naive_flood(mask: &[u8], seeds: &[FlowSource]) -> Vec<Vec2> {
    let n = N as usize;
    let mut flow = vec![Vec2::ZERO; n * n];
    let mut seen = vec![false; n * n];
    let mut q = VecDeque::new();
    for i in 0..n * n {
        let p = Vec2::new((i % n) as f32 + 0.5, (i / n) as f32 + 0.5);
        if mask[i] == 0 && seeds.iter().any(|s| (p - s.position).length() <= s.radius) {
            flow[i] = seeds[0].velocity;
            seen[i] = true;
            q.push_back(i);
        }
    }
    while let Some(i) = q.pop_front() {
        let (x, y) = (i % n, i / n);
        for (dx, dy) in [(1i32, 0i32), (-1, 0), (0, 1), (0, -1)] {
            let (nx, ny) = (x as i32 + dx, y as i32 + dy);
            if nx < 0 || ny < 0 || nx >= n as i32 || ny >= n as i32 {
                continue;
            }
            let j = ny as usize * n + nx as usize;
            if mask[j] == 0 && !seen[j] {
                seen[j] = true;
                flow[j] = flow[i];
                q.push_back(j);
            }
        }
    }
    flow
}

fn bake(mask: &[u8], d: &DistanceField, s: &FlowBakeSettings) -> FlowField {
    let src = sources();
    let input = FlowBakeInput {
        sdf: d,
        texel_size: 1.0,
        origin: Vec2::ZERO,
        rivers: &[],
        sources: &src,
    };
    let _ = mask;
    bake_flow(&input, s, &mut water::no_progress).unwrap()
}

#[test]
fn flow_follows_a_bending_channel_and_beats_a_naive_flood() {
    let mask = channel(false);
    let d = sdf(&mask);
    let ours = bake(&mask, &d, &FlowBakeSettings::default());
    let (mean, p95, unreached) = errors(ours.flow(), &mask, &d, None);
    let naive = naive_flood(&mask, &sources());
    let (nmean, np95, _) = errors(&naive, &mask, &d, None);
    eprintln!(
        "half annulus: SDF-guided mean {mean:.1} deg, p95 {p95:.1}; naive mean {nmean:.1}, p95 {np95:.1}"
    );
    assert_eq!(unreached, 0);
    assert!(mean < 5.5 && p95 < 15.0, "mean {mean} p95 {p95}");
    assert!(
        nmean > 4.0 * mean,
        "the naive flood should be far worse: {nmean}"
    );
    // Speed is carried around the bend.
    let mid = ours.sample(C + Vec2::new(-(R0 + R1) * 0.5, 2.0));
    assert!(mid.length() > 1.0, "{mid}");
}

#[test]
fn flow_goes_around_a_rock() {
    let mask = channel(true);
    let d = sdf(&mask);
    let ours = bake(&mask, &d, &FlowBakeSettings::default());
    let rock = C + Vec2::new(0.0, 42.5);
    // Within 2 m of the rock, flow runs along its outline: perpendicular to the radius.
    let mut worst: f32 = 0.0;
    let mut n = 0;
    for (i, &m) in mask.iter().enumerate() {
        let p = Vec2::new((i as u32 % N) as f32 + 0.5, (i as u32 / N) as f32 + 0.5);
        let r = (p - rock).length();
        if m == 0 && r > 6.0 && r < 7.0 {
            let f = ours.flow()[i].normalize_or_zero();
            let radial = (p - rock).normalize();
            worst = worst.max(f.dot(radial).abs());
            n += 1;
        }
    }
    assert!(n > 10);
    assert!(worst < 0.45, "flow into or out of the rock: {worst}");
    // Away from the rock (beyond 15 m) the flow is the channel's again, downstream too.
    let (mean, p95, unreached) = errors(ours.flow(), &mask, &d, Some((rock, 15.0)));
    eprintln!("with a rock: mean {mean:.1} deg, p95 {p95:.1} beyond 15 m of it");
    assert_eq!(unreached, 0);
    assert!(mean < 6.0 && p95 < 15.0, "{mean} {p95}");
}

#[test]
fn rivers_seed_the_bake_and_land_stays_still() {
    // A straight channel along x with a river spline down its middle.
    let mask: Vec<u8> = (0..N * N)
        .map(|i| u8::from(!((40..80).contains(&(i / N)))))
        .collect();
    let d = sdf(&mask);
    let river = River {
        points: vec![
            RiverPoint {
                position: Vec3::new(10.0, 60.0, 0.0),
                width: 10.0,
                depth: 1.0,
                speed: 2.0,
            },
            RiverPoint {
                position: Vec3::new(40.0, 60.0, 0.0),
                width: 10.0,
                depth: 1.0,
                speed: 2.0,
            },
        ],
        material: 0,
    };
    let input = FlowBakeInput {
        sdf: &d,
        texel_size: 1.0,
        origin: Vec2::ZERO,
        rivers: std::slice::from_ref(&river),
        sources: &[],
    };
    let f = bake_flow(
        &input,
        &FlowBakeSettings::default(),
        &mut water::no_progress,
    )
    .unwrap();
    for (i, v) in f.flow().iter().enumerate() {
        if mask[i] != 0 {
            assert_eq!(*v, Vec2::ZERO);
        } else {
            // Everything in the channel flows along +x, upstream of the seed too.
            assert!(v.x > 0.0 && v.normalize().x > 0.95, "texel {i}: {v}");
        }
    }
}

#[cfg(feature = "parallel")]
#[test]
fn parallel_bakes_equal_sequential_bit_for_bit() {
    let mask = channel(true);
    let d = sdf(&mask);
    let par_d = water::parallel::signed_edt(&mask, N, N, &mut water::no_progress).unwrap();
    assert_eq!(par_d, d);
    let src = sources();
    let input = FlowBakeInput {
        sdf: &d,
        texel_size: 1.0,
        origin: Vec2::ZERO,
        rivers: &[],
        sources: &src,
    };
    let s = FlowBakeSettings::default();
    let a = bake_flow(&input, &s, &mut water::no_progress).unwrap();
    let b = water::parallel::bake_flow(&input, &s, &mut water::no_progress).unwrap();
    assert_eq!(a, b);
}
