//! "hillside": a scene shaped like HFW's foliage views, where the talk's tables come from
//! (seed 000): a meadow of tall grass, every blade its own geometry, before a forest of
//! dense canopies on the valley's far side, built for one of two cameras ([`View`]).
//!
//! At 3840x2160 nearly every grass triangle is under a pixel wide, so most 2x2 quads hold
//! four triangles: the case deferred texturing was built for. The grass is built the way
//! a game streams it, in rings of level of detail around the camera: each ring twice as
//! far holds blades twice as wide (at most about a pixel at the base where the ring
//! begins, narrowing to a point) and about a quarter as many per square metre (the view
//! grazes the ground about twice as flat there, so they still hide it). Blades face the
//! camera's side (the laydown culls back faces, and double-sided blades would double the
//! vertices for no pixel) and lean across the views' lines of sight.

use glam::{Affine3A, Quat, Vec2, Vec3};

use super::{
    MeshBuilder, Rng, bark_layer, blade_layer, count, fbm, ground_layer, lattice, leaf_layer,
    material, morton_order, rock_layer, rock_mesh, terrain_mesh_with, trunk_mesh,
};
use scene::{Batch, Camera, FrameInput, Material, MaterialId, Mesh, MeshId, Scene, ShaderKind};

/// The camera the hillside is built for (its grass rings are centred on it; the terrain,
/// trees and rocks are the same for both).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum View {
    /// From 15 m above the meadow, 100 m south of the forest's edge, over the grass to
    /// the forest climbing the valley's far side: the talk's forest case.
    Rise,
    /// 5 m above the meadow near the forest's edge, across the tall grass to the south:
    /// the talk's tall-grass case. This high, the nearest blades in view are 6 m away and
    /// about a pixel wide at 2-4 mm; from eye height (the nearest blades under a metre
    /// away) they would have to be under half a millimetre.
    TallGrass,
}

/// The terrain's side (metres).
const SIZE: f32 = 500.0;
/// Trees in the forest at density 1.0 (about one per 30 m² north of the meadow).
pub(super) const TREES: f32 = 4000.0;
/// Rocks in the meadow at density 1.0.
pub(super) const ROCKS: f32 = 40.0;
/// Blade heights (metres): tall grass, as HFW's that Aloy hides in.
const BLADE_HEIGHT: (f32, f32) = (0.7, 1.3);
/// Grass levels of detail; the last one reaches the terrain's corners from either camera.
const LODS: usize = 6;
/// Directions the blades of a patch mesh face, spread over the camera's horizontal field
/// of view (each patch takes the one nearest the way to the camera).
const FACINGS: usize = 4;
/// Patch meshes per level of detail and facing: green, green and dry mixed, dry (see
/// [`grass_patch_mesh`]).
const VARIANTS: usize = 3;
/// Grass meshes per level of detail.
const PER_LOD: usize = FACINGS * VARIANTS;
/// Meshes before the grass patches: terrain, trunk, crown, rock.
const FIRST_GRASS_MESH: usize = 4;
/// Largest patch side (metres): a flat patch tilted to the terrain's broad swells stays
/// within about 30 cm of the ground at this size (blades are 0.7-1.3 m tall).
const MAX_PATCH: f32 = 10.0;
/// Levels from 3 on hold this many times a quarter of the level before's blades per
/// square metre (without it the far grass showed 5-10% of its ground).
const FAR_BOOST: f32 = 1.5;
/// How blades lean: within this angle (radians) of +x (east, combed by the prevailing
/// west wind, across both views' lines of sight: upright sub-pixel blades would cover
/// columns of pixels, leaning ones cross them), by `TILT` of their height at the base and
/// up to `DROOP` more at the tip (horizontal offset over height).
const LEAN_SPREAD: f32 = 0.5;
const TILT: (f32, f32) = (0.25, 0.6);
const DROOP: f32 = 0.3;
/// Leaf cards per crown and their half-side (metres).
const CROWN_CARDS: u32 = 420;
const CARD_HALF: f32 = 0.4;
/// The image aspect the grass is laid out for (a wider image sees patches left out at its
/// sides).
const ASPECT: f32 = 16.0 / 9.0;

/// The hillside's terrain height (metres) at world (x, z): [`broad`] and a few
/// centimetres of bumps.
pub(super) fn height(x: f32, z: f32, seed: u32) -> f32 {
    broad(x, z, seed) + (fbm(Vec2::new(x, z) / 5.0, seed ^ 0x5a5a, 2, 0) - 0.5) * 0.15
}

/// Swells over a few hundred metres (flat enough under a patch of grass) and the valley's
/// far side, rising 60 m to the north under the forest (metres).
fn broad(x: f32, z: f32, seed: u32) -> f32 {
    let t = ((z + 40.0) / 280.0).clamp(0.0, 1.0);
    (fbm(Vec2::new(x, z) / 180.0, seed, 2, 0) - 0.5) * 14.0 + 60.0 * t * t * (3.0 - 2.0 * t)
}

/// The unit normal of [`broad`] at (x, z): what a patch of grass is tilted to.
fn normal(x: f32, z: f32, seed: u32) -> Vec3 {
    let e = 2.0;
    let h = |x: f32, z: f32| broad(x, z, seed);
    Vec3::new(
        h(x - e, z) - h(x + e, z),
        2.0 * e,
        h(x, z - e) - h(x, z + e),
    )
    .normalize()
}

/// The forest's southern edge (world z, metres) at world x: the meadow lies south of it
/// (the grass grows under the trees too).
fn forest_edge(x: f32) -> f32 {
    -20.0 + 8.0 * (x / 37.0).sin() + 4.0 * (x / 13.0).cos()
}

/// One level of detail of the grass: a square patch of blades.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Lod {
    /// Side of a patch (metres), also the spacing of the patches at density 1.0.
    side: f32,
    /// Blades per patch.
    blades: u32,
    /// Blade width at the base (metres), least and most; blades narrow to a point.
    width: (f32, f32),
    /// Segments along a blade, the last one a single triangle to the tip.
    segments: u32,
}

/// How a view's grass is built. Level `k > 0` covers horizontal distances
/// `reach * 2^(k-1) .. reach * 2^k` metres from the camera (level 0 everything nearer
/// than `reach`, the last level everything beyond); its blades are `2^k` times as wide
/// as level 0's and about `4^k` times as sparse ([`GrassSetup::blades_per_m2`]); its
/// patches `2^k` times as wide, up to [`MAX_PATCH`], so that every level's patches tile
/// one quadtree.
#[derive(Clone, Copy, Debug, PartialEq)]
struct GrassSetup {
    /// Where level 1 begins (metres from the camera, horizontally).
    reach: f32,
    /// Level 0's patch side (metres).
    side: f32,
    /// Level 0's blade widths at the base (metres).
    width: (f32, f32),
    /// Level 0's blades per square metre at density 1.0.
    blades_per_m2: f32,
}

impl GrassSetup {
    /// The quadtree's levels of patch size: the largest `j` with `side * 2^j` within
    /// [`MAX_PATCH`].
    fn top(&self) -> usize {
        let mut j = 0;
        while j + 1 < LODS && self.side * (2u32 << j) as f32 <= MAX_PATCH {
            j += 1;
        }
        j
    }

    /// Level `k`'s blades per square metre at density 1.0: a quarter of the level before's,
    /// from level 3 on [`FAR_BOOST`] times that: the ground is not flat, and slopes
    /// facing the camera are seen less grazing than the rings assume.
    fn blades_per_m2(&self, k: usize) -> f32 {
        let scale = (1u32 << k) as f32;
        self.blades_per_m2 / (scale * scale) * FAR_BOOST.powi(k.saturating_sub(2) as i32)
    }

    /// Level `k`'s patch.
    fn lod(&self, k: usize) -> Lod {
        let scale = (1u32 << k) as f32;
        let side = self.side * (1u32 << k.min(self.top())) as f32;
        Lod {
            side,
            blades: (self.blades_per_m2(k) * side * side).round().max(1.0) as u32,
            width: (self.width.0 * scale, self.width.1 * scale),
            // Fewer segments far away, where a blade is a few pixels tall.
            segments: if k < 2 { 3 } else { 2 },
        }
    }

    /// The level of detail at horizontal distance `d` (metres) from the camera.
    fn level(&self, d: f32) -> usize {
        if d < self.reach {
            0
        } else {
            ((d / self.reach).log2().floor() as usize + 1).min(LODS - 1)
        }
    }
}

/// Where a view's camera is, what it looks at and how its grass is built.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Setup {
    eye: Vec3,
    target: Vec3,
    grass: GrassSetup,
}

fn setup(view: View, seed: u32) -> Setup {
    match view {
        View::Rise => Setup {
            eye: Vec3::new(0.0, height(0.0, -120.0, seed) + 15.0, -120.0),
            target: Vec3::new(0.0, height(0.0, -20.0, seed) + 2.0, -20.0),
            grass: GrassSetup {
                reach: 40.0,
                side: 1.25,
                width: (0.005, 0.009),
                blades_per_m2: 800.0,
            },
        },
        View::TallGrass => Setup {
            eye: Vec3::new(20.0, height(20.0, -40.0, seed) + 5.0, -40.0),
            target: Vec3::new(20.0, height(20.0, -100.0, seed) - 4.0, -100.0),
            grass: GrassSetup {
                reach: 12.0,
                side: 1.25,
                width: (0.002, 0.004),
                blades_per_m2: 1500.0,
            },
        },
    }
}

/// The camera's four side planes (inward unit normals through the eye), for culling
/// the grass patches out of view.
struct Frustum {
    eye: Vec3,
    planes: [Vec3; 4],
}

impl Frustum {
    fn new(camera: &Camera, aspect: f32) -> Self {
        let f = (camera.target - camera.position).normalize();
        let r = f.cross(camera.up).normalize();
        let u = r.cross(f);
        let ty = (camera.fov_y * 0.5).tan();
        let tx = ty * aspect;
        Self {
            eye: camera.position,
            planes: [f * tx - r, f * tx + r, f * ty - u, f * ty + u].map(Vec3::normalize),
        }
    }

    /// Whether a sphere (centre, radius in metres) is at least partly inside.
    fn sees(&self, centre: Vec3, radius: f32) -> bool {
        let p = centre - self.eye;
        self.planes.iter().all(|n| p.dot(*n) >= -radius)
    }
}

/// The centres (world x, z) of the grass patches a view needs, with their level of
/// detail: a quadtree over the terrain whose cell of size level `j` is split while its
/// nearest point is in a level below `j`, kept where it may be in view (so every point of
/// the ground in view is under exactly one patch at density 1.0). Patch spacing is
/// `side / sqrt(density)`. Deterministic and free of random numbers: the vertex estimate
/// counts the same.
fn patch_cells(s: &Setup, density: f32, seed: u32) -> Vec<(usize, Vec2)> {
    let mut cells = Vec::new();
    if !(density.is_finite() && density > 0.0) {
        return cells;
    }
    let frustum = Frustum::new(&Camera::look_at(s.eye, s.target), ASPECT);
    let top = s.grass.top();
    let unit = s.grass.side / density.sqrt();
    let big = unit * (1u32 << top) as f32;
    let n = ((SIZE - 10.0) / big).floor() as i32;
    let eye = Vec2::new(s.eye.x, s.eye.z);
    let mut stack = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let c =
                Vec2::new(i as f32 + 0.5, j as f32 + 0.5) * big - Vec2::splat(n as f32 * big * 0.5);
            stack.push((top, c));
        }
    }
    while let Some((j, c)) = stack.pop() {
        let cell = unit * (1u32 << j) as f32;
        let patch = s.grass.lod(j).side.max(cell);
        // Bounding sphere: the patch's half-diagonal, the blades' height and lean.
        let centre = Vec3::new(c.x, height(c.x, c.y, seed) + 0.7, c.y);
        if !frustum.sees(centre, patch * std::f32::consts::FRAC_1_SQRT_2 + 1.2) {
            continue;
        }
        let nearest = ((eye - c).abs() - Vec2::splat(cell * 0.5)).max(Vec2::ZERO);
        let k = s.grass.level(nearest.length());
        if k >= j || j == 0 {
            cells.push((if j == top { k.max(top) } else { j }, c));
        } else {
            let q = cell * 0.25;
            for d in [
                Vec2::new(-q, -q),
                Vec2::new(q, -q),
                Vec2::new(-q, q),
                Vec2::new(q, q),
            ] {
                stack.push((j - 1, c + d));
            }
        }
    }
    cells
}

/// A square patch of `lod.blades` blades, `lod.side` metres a side, each facing within
/// 60° of the horizontal direction `yaw` (radians about +y from +z: the way to the
/// camera), leaning east; variant 0 takes the blade layer's greener colours, 1 and 2 its
/// yellower ones (and 2 the dry material's tint).
fn grass_patch_mesh(rng: &mut Rng, lod: &Lod, yaw: f32, variant: usize) -> Mesh {
    let dry = variant > 0;
    let mut b = MeshBuilder::new(if dry { "dry grass" } else { "tall grass" });
    let e = lod.side * 0.5;
    // Columns of the blade layer's four colours (2 the yellowest, 3 the darkest green).
    let colours: [u32; 4] = if dry { [1, 2, 2, 2] } else { [0, 1, 3, 3] };
    // The blades' draws first, then their geometry in Morton order of their bases.
    let blades: Vec<Blade> = (0..lod.blades)
        .map(|_| Blade::draw(rng, lod, yaw, &colours))
        .collect();
    let bases: Vec<Vec2> = blades
        .iter()
        .map(|bl| Vec2::new(bl.base.x, bl.base.z))
        .collect();
    for k in morton_order(&bases, e) {
        let bl = &blades[k as usize];
        let (base, lean, h) = (bl.base, bl.lean, bl.height);
        let side = Vec3::Y.cross(bl.facing);
        let (tilt, droop, width, u0) = (bl.tilt, bl.droop, bl.width, bl.u0);
        let centre = |t: f32| base + Vec3::Y * (h * t) + lean * (h * (tilt * t + droop * t * t));
        let mut prev: Option<(u16, u16)> = None;
        for s in 0..=lod.segments {
            let t = s as f32 / lod.segments as f32;
            let tangent = (Vec3::Y + lean * (tilt + 2.0 * droop * t)).normalize();
            let n = side.cross(tangent);
            let v = 1.0 - t;
            if s == lod.segments {
                let tip = b.vertex(centre(t), n, Vec2::new(u0 + 0.095, v));
                if let Some((pl, pr)) = prev {
                    b.tri(pl, pr, tip);
                }
                break;
            }
            let w = 0.5 * width * (1.0 - t);
            let l = b.vertex(centre(t) - side * w, n, Vec2::new(u0, v));
            let r = b.vertex(centre(t) + side * w, n, Vec2::new(u0 + 0.19, v));
            if let Some((pl, pr)) = prev {
                b.quad(pl, pr, r, l);
            }
            prev = Some((l, r));
        }
    }
    b.finish()
}

/// One blade's random draws, in [`grass_patch_mesh`]'s order.
struct Blade {
    base: Vec3,
    facing: Vec3,
    lean: Vec3,
    height: f32,
    tilt: f32,
    droop: f32,
    width: f32,
    u0: f32,
}

impl Blade {
    fn draw(rng: &mut Rng, lod: &Lod, yaw: f32, colours: &[u32; 4]) -> Self {
        let e = lod.side * 0.5;
        let base = Vec3::new(rng.range(-e, e), 0.0, rng.range(-e, e));
        let a = yaw + rng.range(-1.05, 1.05);
        let facing = Vec3::new(a.sin(), 0.0, a.cos());
        let lean_a = rng.range(-LEAN_SPREAD, LEAN_SPREAD);
        let lean = Vec3::new(lean_a.cos(), 0.0, lean_a.sin());
        let height = rng.range(BLADE_HEIGHT.0, BLADE_HEIGHT.1);
        let (tilt, droop) = (rng.range(TILT.0, TILT.1), rng.range(0.0, DROOP));
        let width = rng.range(lod.width.0, lod.width.1);
        let u0 = colours[((rng.f32() * 4.0) as usize).min(3)] as f32 * 0.25 + 0.03;
        Self {
            base,
            facing,
            lean,
            height,
            tilt,
            droop,
            width,
            u0,
        }
    }
}

/// A tree crown: `cards` single-sided leaf cards (`half` metres half-side) over an
/// ellipsoid, facing out (those facing away are behind the crown).
fn crown_mesh(rng: &mut Rng, cards: u32, half: f32) -> Mesh {
    let mut b = MeshBuilder::new("crown");
    for _ in 0..cards {
        let dir = Vec3::new(
            rng.range(-1.0, 1.0),
            rng.range(-0.5, 1.0),
            rng.range(-1.0, 1.0),
        )
        .normalize_or(Vec3::Y);
        // Up to 10.2 m: over the 9 m trunk's tip.
        let o = Vec3::new(0.0, 7.2, 0.0) + dir * Vec3::new(3.2, 3.0, 3.2) * rng.range(0.5, 1.0);
        let r0 = dir.cross(Vec3::Y).normalize_or(Vec3::X);
        let u0 = r0.cross(dir).normalize_or(Vec3::Y);
        let q = Quat::from_axis_angle(dir, rng.range(0.0, std::f32::consts::TAU));
        let (r, u) = (q * r0 * half, q * u0 * half);
        let cell = (rng.f32() * 4.0) as u32;
        let uv0 = Vec2::new((cell % 2) as f32 * 0.5, (cell / 2) as f32 * 0.5);
        let uv1 = uv0 + Vec2::splat(0.5);
        let n = (dir + Vec3::Y * 0.3).normalize();
        let a = b.vertex(o - r - u, n, Vec2::new(uv0.x, uv1.y));
        let c = b.vertex(o + r - u, n, Vec2::new(uv1.x, uv1.y));
        let d = b.vertex(o + r + u, n, Vec2::new(uv1.x, uv0.y));
        let e = b.vertex(o - r + u, n, Vec2::new(uv0.x, uv0.y));
        b.quad(a, c, d, e);
    }
    b.finish()
}

/// Half the camera's horizontal field of view (radians) at [`ASPECT`].
fn half_fov_x(s: &Setup) -> f32 {
    ((Camera::look_at(s.eye, s.target).fov_y * 0.5).tan() * ASPECT).atan()
}

/// The yaw (radians about +y from +z) the blades of facing `f` face: back to the camera,
/// turned across its horizontal field of view.
fn facing_yaw(s: &Setup, f: usize) -> f32 {
    let back = s.eye - s.target;
    let t = (f as f32 + 0.5) / FACINGS as f32 * 2.0 - 1.0;
    back.x.atan2(back.z) + t * half_fov_x(s)
}

/// The mesh for a level-`k` patch at `c` (world x, z): the facing nearest the way to the
/// camera and the colour a low-frequency noise gives, each dithered between its two
/// nearest choices by a hash of the cell (no seams where they change).
fn grass_mesh_index(s: &Setup, k: usize, c: Vec2, seed: u32) -> usize {
    let to_eye = Vec2::new(s.eye.x, s.eye.z) - c;
    let back = s.eye - s.target;
    let off = (to_eye.x.atan2(to_eye.y) - back.x.atan2(back.z) + std::f32::consts::PI)
        .rem_euclid(std::f32::consts::TAU)
        - std::f32::consts::PI;
    let cell = ((c.x * 4.0).round() as i32, (c.y * 4.0).round() as i32);
    let pick = |x: f32, salt: u32, n: usize| {
        let dither = lattice(cell.0, cell.1, seed ^ salt);
        ((x + dither).floor().max(0.0) as usize).min(n - 1)
    };
    let f = pick(
        (off / half_fov_x(s) + 1.0) * 0.5 * FACINGS as f32 - 0.5,
        0xfa,
        FACINGS,
    );
    let dryness = (fbm(c / 45.0, seed ^ 0xd27, 3, 0) - 0.42) / 0.16;
    let v = pick(dryness, 0xd1, VARIANTS);
    FIRST_GRASS_MESH + k * PER_LOD + f * VARIANTS + v
}

/// The meshes of the hillside for `s` (grass level `k`'s facing `f`, green or dry `v` at
/// `FIRST_GRASS_MESH + k * PER_LOD + f * VARIANTS + v`); the crown from `world`.
fn meshes(rng: &mut Rng, world: &mut Rng, s: &Setup, seed: u32) -> Vec<Mesh> {
    let mut meshes = vec![
        // 180 cells: 64 800 triangles, under the 16-bit index limit.
        terrain_mesh_with(SIZE, 180, |x, z| height(x, z, seed)),
        trunk_mesh(),
        crown_mesh(world, CROWN_CARDS, CARD_HALF),
        rock_mesh(seed ^ 0x77),
    ];
    for k in 0..LODS {
        for f in 0..FACINGS {
            for v in 0..VARIANTS {
                let lod = s.grass.lod(k);
                meshes.push(grass_patch_mesh(rng, &lod, facing_yaw(s, f), v));
            }
        }
    }
    meshes
}

/// Instance vertices of the hillside built for `view` at `density`, counted without
/// placing an instance (`meshes` from a build at any density), in time proportional to
/// the density (the grass patches are enumerated).
pub(super) fn instance_vertices(seed: u64, density: f32, view: View, meshes: &[Mesh]) -> u64 {
    let tseed = seed as u32;
    let s = setup(view, tseed);
    let v = |m: usize| meshes[m].positions.len() as u64;
    let grass: u64 = patch_cells(&s, density, tseed)
        .iter()
        .map(|&(k, c)| v(grass_mesh_index(&s, k, c, tseed)))
        .sum();
    vertices_but_grass(density, meshes) + grass
}

/// Instance vertices of the hillside's terrain, trees and rocks at `density` (the same
/// for both views; `meshes` from a build at any density).
pub(super) fn vertices_but_grass(density: f32, meshes: &[Mesh]) -> u64 {
    let v = |m: usize| meshes[m].positions.len() as u64;
    let n = |x: f32| count(x, density) as u64;
    v(0) + n(TREES) * (v(1) + v(2)) + n(ROCKS) * v(3)
}

/// The hillside built for `view` at `density` (instance counts; not checked), with its
/// albedo layers painted if `paint`, and its frame (camera, the sun behind it).
pub(super) fn hillside(seed: u64, density: f32, paint: bool, view: View) -> (Scene, FrameInput) {
    let mut rng = Rng::new(seed ^ 0x6869_6c6c);
    // Trees and rocks from their own stream: the same in both views.
    let mut world = Rng::new(seed ^ 0x0077_6f72_6c64);
    let tseed = seed as u32;
    let s = setup(view, tseed);
    let meshes = meshes(&mut rng, &mut world, &s, tseed);
    let albedo_layers = if paint {
        vec![
            ground_layer(),
            blade_layer(),
            bark_layer(),
            leaf_layer(),
            rock_layer(),
        ]
    } else {
        Vec::new()
    };
    let materials = vec![
        Material {
            // Moss-green and dark, as the ground in the grass's shade.
            tint: Vec3::new(0.5, 0.65, 0.35),
            ..material("ground", ShaderKind::Opaque, 0, 0.9)
        },
        material("tall grass", ShaderKind::AlphaTested, 1, 0.6),
        material("bark", ShaderKind::Opaque, 2, 0.8),
        Material {
            tint: Vec3::new(0.7, 0.8, 0.6),
            ..material("canopy", ShaderKind::AlphaTested, 3, 0.6)
        },
        Material {
            tint: Vec3::new(0.75, 0.9, 0.7),
            ..material("rock", ShaderKind::Opaque, 4, 0.7)
        },
        Material {
            tint: Vec3::new(1.12, 1.06, 0.8),
            ..material("dry grass", ShaderKind::AlphaTested, 1, 0.6)
        },
    ];
    let place = |x: f32, z: f32, yaw: f32, scale: f32| {
        Affine3A::from_scale_rotation_translation(
            Vec3::splat(scale),
            Quat::from_rotation_y(yaw),
            Vec3::new(x, height(x, z, tseed), z),
        )
    };
    // The grass: square patches of one quadtree (no gaps), each tilted to the ground.
    let mut grass = vec![Vec::new(); LODS * PER_LOD];
    for (k, c) in patch_cells(&s, density, tseed) {
        let tilt = Quat::from_rotation_arc(Vec3::Y, normal(c.x, c.y, tseed));
        grass[grass_mesh_index(&s, k, c, tseed) - FIRST_GRASS_MESH].push(
            Affine3A::from_rotation_translation(tilt, Vec3::new(c.x, height(c.x, c.y, tseed), c.y)),
        );
    }
    // The forest: trees north of the meadow's edge to the terrain's end.
    let half = SIZE * 0.5 - 5.0;
    let trees: Vec<Affine3A> = (0..count(TREES, density))
        .map(|_| {
            let x = world.range(-half, half);
            let z = (forest_edge(x) + world.range(2.0, half + 25.0)).min(half);
            let yaw = world.range(0.0, std::f32::consts::TAU);
            place(x, z, yaw, world.range(0.9, 1.4))
        })
        .collect();
    // Rocks in the meadow, none within 25 m of either camera (their large triangles
    // would fill the bottom of the image).
    let eyes = [View::Rise, View::TallGrass].map(|v| {
        let e = setup(v, tseed).eye;
        Vec2::new(e.x, e.z)
    });
    let rocks = (0..count(ROCKS, density))
        .map(|_| {
            loop {
                let x = world.range(-half, half);
                let z = world.range(-half, forest_edge(x) - 5.0);
                let yaw = world.range(0.0, std::f32::consts::TAU);
                let scale = world.range(0.5, 1.4);
                if eyes.iter().all(|e| e.distance(Vec2::new(x, z)) > 25.0) {
                    break place(x, z, yaw, scale);
                }
            }
        })
        .collect();
    let mut batches = vec![
        Batch {
            mesh: MeshId(0),
            material: MaterialId(0),
            instances: vec![Affine3A::IDENTITY],
        },
        Batch {
            mesh: MeshId(1),
            material: MaterialId(2),
            instances: trees.clone(),
        },
        Batch {
            mesh: MeshId(2),
            material: MaterialId(3),
            instances: trees,
        },
        Batch {
            mesh: MeshId(3),
            material: MaterialId(4),
            instances: rocks,
        },
    ];
    for (m, instances) in grass.into_iter().enumerate() {
        batches.push(Batch {
            mesh: MeshId(FIRST_GRASS_MESH + m),
            material: MaterialId(if m % VARIANTS == 2 { 5 } else { 1 }),
            instances,
        });
    }
    let mut frame = FrameInput::new(Camera::look_at(s.eye, s.target));
    // The sun high behind the camera's right shoulder: the blades face the camera.
    let back = (s.eye - s.target).with_y(0.0).normalize_or(Vec3::NEG_Z);
    frame.lighting.sun_direction = (back * 0.5 + Vec3::Y * 0.8 + Vec3::X * 0.35).normalize();
    (
        Scene {
            data_layers: Vec::new(),
            meshes,
            materials,
            albedo_layers,
            batches,
            static_setups: Vec::new(),
            wind: None,
        },
        frame,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A patch mesh's blades follow each other along the ground (Morton order of their
    /// bases): consecutive blades are far closer than two random ones (0.52 of the side
    /// apart on average), so the vertex ring's chunks hold neighbouring blades.
    #[test]
    fn a_patch_lays_its_blades_out_side_by_side() {
        let s = setup(View::Rise, 7);
        let lod = s.grass.lod(0);
        let mesh = grass_patch_mesh(&mut Rng::new(11), &lod, 0.0, 0);
        // Each blade: two vertices per segment, then the tip; the first two straddle the base.
        let per_blade = 2 * lod.segments as usize + 1;
        assert_eq!(mesh.positions.len(), per_blade * lod.blades as usize);
        assert!(lod.blades > 100, "{} blades", lod.blades);
        let mean = super::super::mean_blade_step(&mesh, per_blade);
        assert!(
            mean < 0.1 * lod.side,
            "consecutive blades {mean} m apart in a {} m patch",
            lod.side
        );
    }

    /// Every point of the ground in view lies under exactly one grass patch at density 1,
    /// in both views: the quadtree's leaves tile it, with no gaps at the rings' edges.
    #[test]
    fn grass_patches_tile_the_ground_in_view_once() {
        for view in [View::Rise, View::TallGrass] {
            let s = setup(view, 1);
            let cells = patch_cells(&s, 1.0, 1);
            let frustum = Frustum::new(&Camera::look_at(s.eye, s.target), ASPECT);
            // Samples on a grid offset from every patch edge (patch sides are multiples
            // of 1.25 m, the samples 0.37 m apart).
            let (step, lo) = (0.37, -240.0 + 0.123);
            let n = (480.0 / step) as usize;
            let mut under = vec![0u8; n * n];
            for &(k, c) in &cells {
                let half = s.grass.lod(k).side * 0.5;
                let first = |x: f32| (((x - half - lo) / step).ceil().max(0.0) as usize).min(n);
                let last = |x: f32| (((x + half - lo) / step).floor() as usize + 1).min(n);
                for j in first(c.y)..last(c.y) {
                    for i in first(c.x)..last(c.x) {
                        under[j * n + i] += 1;
                    }
                }
            }
            let mut seen = 0;
            for j in 0..n {
                for i in 0..n {
                    let (x, z) = (lo + i as f32 * step, lo + j as f32 * step);
                    let p = Vec3::new(x, height(x, z, 1), z);
                    assert!(under[j * n + i] <= 1, "{view:?}: overlap at {p}");
                    if frustum.sees(p, 0.0) {
                        assert_eq!(under[j * n + i], 1, "{view:?}: no grass at {p}");
                        seen += 1;
                    }
                }
            }
            assert!(seen > 100_000, "{view:?}: {seen} samples in view");
        }
    }

    /// At 3840x2160 no blade is much over a pixel wide at its base where its patch comes
    /// nearest the camera (they narrow to a point), and the far levels are no wider in
    /// pixels than the near ones.
    #[test]
    fn blades_are_about_a_pixel_wide_at_4k() {
        for view in [View::Rise, View::TallGrass] {
            let s = setup(view, 1);
            let camera = Camera::look_at(s.eye, s.target);
            let pixel = 2.0 * (camera.fov_y * 0.5).tan() / 2160.0;
            let frustum = Frustum::new(&camera, ASPECT);
            let mut widest = [0.0f32; LODS];
            for (k, c) in patch_cells(&s, 1.0, 1) {
                let half = s.grass.lod(k).side * 0.5;
                let near = Vec2::new(s.eye.x, s.eye.z).clamp(c - half, c + half);
                let p = Vec3::new(near.x, height(near.x, near.y, 1), near.y);
                // Patches whose nearest corner is out of view: the grid's margin.
                if !frustum.sees(p, 0.0) {
                    continue;
                }
                let px = s.grass.lod(k).width.1 / (p.distance(s.eye) * pixel);
                widest[k] = widest[k].max(px);
            }
            assert!(widest.iter().all(|&w| w < 1.3), "{view:?}: {widest:?} px");
        }
    }
}
