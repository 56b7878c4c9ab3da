//! Mesh building: the demo scenes' meshes from primitives (terrain grids, trunks, leaf
//! cards, grass blades in Morton order, rocks).

use super::*;

#[derive(Default)]
pub(crate) struct MeshBuilder {
    pub(crate) mesh: Mesh,
}

impl MeshBuilder {
    pub(crate) fn new(name: &str) -> Self {
        Self {
            mesh: Mesh {
                name: name.to_owned(),
                ..Mesh::default()
            },
        }
    }

    pub(crate) fn vertex(&mut self, p: Vec3, n: Vec3, uv: Vec2) -> u16 {
        let i = self.mesh.positions.len();
        self.mesh.positions.push(p);
        self.mesh.normals.push(n.normalize_or(Vec3::Y));
        self.mesh.uvs.push(uv);
        self.mesh.tangents.push(Vec4::ZERO);
        u16::try_from(i).expect("demo meshes stay under 64k vertices")
    }

    pub(crate) fn tri(&mut self, a: u16, b: u16, c: u16) {
        self.mesh.indices.extend_from_slice(&[a, b, c]);
    }

    /// A quad a-b-c-d (counter-clockwise seen from the front).
    pub(crate) fn quad(&mut self, a: u16, b: u16, c: u16, d: u16) {
        self.tri(a, b, c);
        self.tri(a, c, d);
    }

    /// The quads of a `cells` x `cells` grid whose `(cells + 1)^2` vertices were added
    /// first, row-major (the terrains' height fields).
    pub(crate) fn grid_quads(&mut self, cells: u32) {
        let w = cells + 1;
        for j in 0..cells {
            for i in 0..cells {
                let v = |i: u32, j: u32| (j * w + i) as u16;
                self.quad(v(i, j), v(i, j + 1), v(i + 1, j + 1), v(i + 1, j));
            }
        }
    }

    /// A double-sided card: centre `o`, right `r` and up `u` half-extents, uv rect.
    pub(crate) fn card(&mut self, o: Vec3, r: Vec3, u: Vec3, uv0: Vec2, uv1: Vec2, bend: Vec3) {
        let n = r.cross(u).normalize_or(Vec3::Z);
        let top_n = (n + bend * 0.5).normalize_or(n);
        for side in [1.0f32, -1.0] {
            let nn = n * side;
            let tn = top_n * side;
            let a = self.vertex(o - r - u, nn, Vec2::new(uv0.x, uv1.y));
            let b = self.vertex(o + r - u, nn, Vec2::new(uv1.x, uv1.y));
            let c = self.vertex(o + r + u + bend, tn, Vec2::new(uv1.x, uv0.y));
            let d = self.vertex(o - r + u + bend, tn, Vec2::new(uv0.x, uv0.y));
            if side > 0.0 {
                self.quad(a, b, c, d);
            } else {
                self.quad(b, a, d, c);
            }
        }
    }

    /// Computes tangents from positions and UVs (per-triangle, accumulated, orthonormalised
    /// against the normal; handedness in w, glTF's: `w · n × t` points up the image, −v).
    pub(crate) fn finish(mut self) -> Mesh {
        let m = &mut self.mesh;
        let mut tan = vec![Vec3::ZERO; m.positions.len()];
        let mut bit = vec![Vec3::ZERO; m.positions.len()];
        for t in m.indices.chunks_exact(3) {
            let [a, b, c] = [t[0] as usize, t[1] as usize, t[2] as usize];
            let (e1, e2) = (
                m.positions[b] - m.positions[a],
                m.positions[c] - m.positions[a],
            );
            let (d1, d2) = (m.uvs[b] - m.uvs[a], m.uvs[c] - m.uvs[a]);
            let det = d1.x * d2.y - d2.x * d1.y;
            if det.abs() < 1e-12 {
                continue;
            }
            let s = (e1 * d2.y - e2 * d1.y) / det;
            let bt = (e2 * d1.x - e1 * d2.x) / det;
            for i in [a, b, c] {
                tan[i] += s;
                bit[i] += bt;
            }
        }
        for i in 0..m.positions.len() {
            let n = m.normals[i];
            let t = (tan[i] - n * n.dot(tan[i])).normalize_or(n.any_orthonormal_vector());
            // `bit` runs along +v, down the image.
            let w = if n.cross(t).dot(bit[i]) > 0.0 {
                -1.0
            } else {
                1.0
            };
            m.tangents[i] = t.extend(w);
        }
        self.mesh
    }
}

pub(crate) fn terrain_mesh(size: f32, cells: u32, seed: u32) -> Mesh {
    terrain_mesh_with(size, cells, |x, z| terrain_height(x, z, seed))
}

/// A square height field of `size` metres and `cells` cells a side centred on the origin,
/// heights (metres) from `h(x, z)`.
pub(crate) fn terrain_mesh_with(size: f32, cells: u32, h: impl Fn(f32, f32) -> f32) -> Mesh {
    let mut b = MeshBuilder::new("terrain");
    for j in 0..=cells {
        for i in 0..=cells {
            let x = (i as f32 / cells as f32 - 0.5) * size;
            let z = (j as f32 / cells as f32 - 0.5) * size;
            let e = 0.25;
            let n = Vec3::new(
                h(x - e, z) - h(x + e, z),
                2.0 * e,
                h(x, z - e) - h(x, z + e),
            );
            b.vertex(Vec3::new(x, h(x, z), z), n, Vec2::new(x, z) / 4.0);
        }
    }
    b.grid_quads(cells);
    b.finish()
}

pub(crate) fn trunk_mesh() -> Mesh {
    let mut b = MeshBuilder::new("trunk");
    let (segs, rings, height) = (10u32, 8u32, 9.0f32);
    for r in 0..=rings {
        let t = r as f32 / rings as f32;
        let radius = 0.32 * (1.0 - 0.75 * t);
        for s in 0..=segs {
            let a = s as f32 / segs as f32 * std::f32::consts::TAU;
            let n = Vec3::new(a.cos(), 0.25, a.sin());
            b.vertex(
                Vec3::new(a.cos() * radius, t * height, a.sin() * radius),
                n,
                Vec2::new(s as f32 / segs as f32 * 2.0, t * 6.0),
            );
        }
    }
    for r in 0..rings {
        for s in 0..segs {
            let v = |s: u32, r: u32| (r * (segs + 1) + s) as u16;
            b.quad(v(s, r), v(s + 1, r), v(s + 1, r + 1), v(s, r + 1));
        }
    }
    b.finish()
}

/// Leaf cards scattered over an ellipsoid crown, facing outwards.
pub(crate) fn canopy_mesh(rng: &mut Rng, cards: u32) -> Mesh {
    let mut b = MeshBuilder::new("canopy");
    for _ in 0..cards {
        let dir = Vec3::new(
            rng.range(-1.0, 1.0),
            rng.range(-0.6, 1.0),
            rng.range(-1.0, 1.0),
        )
        .normalize_or(Vec3::Y);
        let centre =
            Vec3::new(0.0, 7.5, 0.0) + dir * Vec3::new(2.6, 2.4, 2.6) * rng.range(0.35, 1.0);
        let out = dir;
        let r = out.cross(Vec3::Y).normalize_or(Vec3::X) * 0.75;
        let u = r.cross(out).normalize_or(Vec3::Y) * 0.75;
        let q = Quat::from_axis_angle(out, rng.range(0.0, std::f32::consts::TAU));
        let cell = (rng.f32() * 4.0) as u32;
        let uv0 = Vec2::new((cell % 2) as f32 * 0.5, (cell / 2) as f32 * 0.5);
        b.card(
            centre,
            q * r,
            q * u,
            uv0,
            uv0 + Vec2::splat(0.5),
            out * 0.15,
        );
    }
    b.finish()
}

/// A fern / bush: cards around a centre, leaning outwards.
pub(crate) fn bush_mesh(rng: &mut Rng, fronds: u32) -> Mesh {
    let mut b = MeshBuilder::new("bush");
    for k in 0..fronds {
        let a = (k as f32 + rng.f32() * 0.5) / fronds as f32 * std::f32::consts::TAU;
        let out = Vec3::new(a.cos(), 0.0, a.sin());
        let lean = rng.range(0.35, 0.8);
        let up = (Vec3::Y + out * lean).normalize() * 0.45;
        let r = out.cross(Vec3::Y).normalize() * 0.22;
        b.card(out * 0.25 + up, r, up, Vec2::ZERO, Vec2::ONE, out * 0.2);
    }
    b.finish()
}

/// A grass tuft: crossed cards with the grass layer.
pub(crate) fn tuft_mesh(rng: &mut Rng, cards: u32, height: f32) -> Mesh {
    let mut b = MeshBuilder::new("grass tuft");
    for k in 0..cards {
        let a = k as f32 / cards as f32 * std::f32::consts::PI + rng.range(0.0, 0.3);
        let r = Vec3::new(a.cos(), 0.0, a.sin()) * 0.35;
        let off = Vec3::new(rng.range(-0.15, 0.15), 0.0, rng.range(-0.15, 0.15));
        let u = Vec3::Y * height * 0.5;
        b.card(
            off + u,
            r,
            u,
            Vec2::ZERO,
            Vec2::ONE,
            Vec3::new(rng.range(-0.1, 0.1), 0.0, rng.range(-0.1, 0.1)),
        );
    }
    b.finish()
}

/// A field patch of individual curved blades (geometry, alpha-tested tips).
pub(crate) fn blade_patch_mesh(
    rng: &mut Rng,
    blades: u32,
    segments: u32,
    extent: f32,
    height: f32,
) -> Mesh {
    let mut b = MeshBuilder::new("grass blades");
    // The draws first, then the geometry in Morton order of the bases ([`morton_order`]).
    let draws: Vec<(Vec3, f32, f32, f32, f32, f32)> = (0..blades)
        .map(|_| {
            let base = Vec3::new(rng.range(-extent, extent), 0.0, rng.range(-extent, extent));
            let a = rng.range(0.0, std::f32::consts::TAU);
            let h = height * rng.range(0.6, 1.2);
            let bend = rng.range(0.1, 0.5);
            let width = rng.range(0.004, 0.012);
            (base, a, h, bend, width, rng.f32() * 0.75)
        })
        .collect();
    let bases: Vec<Vec2> = draws.iter().map(|d| Vec2::new(d.0.x, d.0.z)).collect();
    for k in morton_order(&bases, extent) {
        let (base, a, h, bend, width, u0) = draws[k as usize];
        let side = Vec3::new(a.cos(), 0.0, a.sin());
        let face = side.cross(Vec3::Y);
        let bend = face * bend * h;
        let mut prev: Option<(u16, u16)> = None;
        for s in 0..=segments {
            let t = s as f32 / segments as f32;
            let centre = base + Vec3::Y * h * t + bend * t * t;
            let w = width * (1.0 - t * 0.85);
            let tangent = (Vec3::Y * h + bend * 2.0 * t).normalize();
            let n = side.cross(tangent).normalize_or(face);
            let l = b.vertex(centre - side * w, n, Vec2::new(u0, 1.0 - t));
            let r = b.vertex(centre + side * w, n, Vec2::new(u0 + 0.25, 1.0 - t));
            if let Some((pl, pr)) = prev {
                b.quad(pl, pr, r, l);
            }
            prev = Some((l, r));
        }
    }
    b.finish()
}

/// The order in which a patch's blades are laid out: Morton order of their bases (`x`,
/// `z` in metres, within `-half..half`), as a mesh tool would. Blades side by side then
/// share the vertex ring's 64-vertex chunks and have neighbouring triangle numbers (in
/// draw order each chunk would hold blades from all over the patch). Draw order if the
/// bounds are unusable.
pub(crate) fn morton_order(bases: &[Vec2], half: f32) -> Vec<u32> {
    let mut keys = vec![0u32; bases.len()];
    morton::Quantizer2::new(Vec2::splat(-half), Vec2::splat(half), morton::BITS2_U32)
        .and_then(|q| q.morton_u32_slice(bases, &mut keys))
        .and_then(|()| morton::sort_permutation(&keys))
        .unwrap_or_else(|_| (0..bases.len() as u32).collect())
}

/// A rock: an icosphere with hashed radial displacement.
pub(crate) fn rock_mesh(seed: u32) -> Mesh {
    let mut b = MeshBuilder::new("rock");
    let (rings, segs) = (8u32, 12u32);
    for r in 0..=rings {
        let v = r as f32 / rings as f32;
        let theta = v * std::f32::consts::PI;
        for s in 0..=segs {
            let u = s as f32 / segs as f32;
            let phi = u * std::f32::consts::TAU;
            let d = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            let k = if s == segs { 0 } else { s };
            let bump = 0.75 + 0.5 * lattice(k as i32, r as i32, seed);
            let p = d * bump * Vec3::new(1.0, 0.6, 0.9);
            b.vertex(p, d, Vec2::new(u * 3.0, v * 2.0));
        }
    }
    for r in 0..rings {
        for s in 0..segs {
            let v = |s: u32, r: u32| (r * (segs + 1) + s) as u16;
            b.quad(v(s, r), v(s + 1, r), v(s + 1, r + 1), v(s, r + 1));
        }
    }
    b.finish()
}
