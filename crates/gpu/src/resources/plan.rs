//! The frame's draw plan: `tiling`'s micro batches turned into the GPU's instance table,
//! the per-micro-batch-ID lookup table of the resolve, and one draw per micro batch.

use glam::{Affine3A, Mat4, Vec3};

use super::geometry::Geometry;
use super::rows::{GpuInstance, GpuMicroBatch};
use crate::scene::{Scene, ShaderKind};

/// Instances per [`DrawChunk`]: the grain at which shadow views cull casters.
pub(crate) const CHUNK_INSTANCES: u32 = 64;

/// A run of at most [`CHUNK_INSTANCES`] consecutive instances of one draw (spatially
/// coherent: a batch's instances are planned in Morton order), with a sphere holding
/// every one of them (origin-relative, metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct DrawChunk {
    /// First instance in the global instance table.
    pub first_instance: u32,
    /// Instances.
    pub instance_count: u32,
    /// Sphere centre, origin-relative.
    pub center: Vec3,
    /// Sphere radius.
    pub radius: f32,
}

/// One draw: a micro batch's instances of one mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Draw {
    /// First index in the index buffer.
    pub first_index: u32,
    /// Index count (3 × primitives).
    pub index_count: u32,
    /// Added to every index.
    pub base_vertex: u32,
    /// First instance in the global instance table.
    pub first_instance: u32,
    /// Instances.
    pub instance_count: u32,
    /// Whether the material is alpha-tested.
    pub alpha_tested: bool,
    /// Whether the material is [`Material::regular`](crate::Material::regular): the mixed
    /// frame draws it in the regular geometry pass, not the laydown.
    pub regular: bool,
    /// Its chunks: `Plan::chunks[first_chunk..first_chunk + chunk_count]`.
    pub first_chunk: u32,
    pub chunk_count: u32,
}

/// The GPU tables of a prepared scene.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Plan {
    /// Instances in micro-batch order.
    pub instances: Vec<GpuInstance>,
    /// Indexed by micro-batch ID.
    pub micro_batch_ids: Vec<GpuMicroBatch>,
    /// One draw per micro batch.
    pub draws: Vec<Draw>,
    /// The draws' chunks, in draw order.
    pub chunks: Vec<DrawChunk>,
}

/// The 3x4 rows of `transform` moved to `origin`-relative space.
pub(crate) fn origin_relative_rows(transform: &Affine3A, origin: Vec3) -> [[f32; 4]; 3] {
    let m = Mat4::from(Affine3A::from_translation(-origin) * *transform);
    let r = m.transpose();
    [
        r.x_axis.to_array(),
        r.y_axis.to_array(),
        r.z_axis.to_array(),
    ]
}

impl Plan {
    /// Lays out instances and lookup tables for `micro_batches` (tiling's processing
    /// order) of `scene` with transforms relative to `origin`; batch `b`'s instance `i` is
    /// `scene.batches[b].instances[order[b][i]]`.
    pub(crate) fn new(
        scene: &Scene,
        geometry: &Geometry,
        micro_batches: &[tiling::MicroBatchInfo],
        origin: Vec3,
        order: &[Vec<u32>],
    ) -> Self {
        let mut plan = Plan::default();
        // Each mesh's reach from its object origin.
        let reach: Vec<f32> = scene
            .meshes
            .iter()
            .map(|m| m.positions.iter().map(|p| p.length()).fold(0.0, f32::max))
            .collect();
        for mb in micro_batches {
            let batch = &scene.batches[mb.batch as usize];
            let mesh = geometry.meshes[batch.mesh.0];
            let bits = visbuf::PrimitiveBits::for_count(mesh.primitive_count.max(1))
                .expect("meshes were validated against the 64k primitive limit");
            let first_global = plan.instances.len() as u32;
            let first_chunk = plan.chunks.len() as u32;
            // The wind sways alpha-tested instances by at most 1.3 amplitudes (world
            // metres, `Wind`'s two sines), beyond their mesh's reach.
            let sway = match (&scene.wind, scene.materials.get(batch.material.0)) {
                (Some(w), Some(m)) if m.shader == ShaderKind::AlphaTested => 1.3 * w.amplitude,
                _ => 0.0,
            };
            let instance = |i: u32| {
                let k = mb.batch_first_instance + i;
                let k = order
                    .get(mb.batch as usize)
                    .and_then(|o| o.get(k as usize))
                    .copied()
                    .unwrap_or(k);
                &batch.instances[k as usize]
            };
            for start in (0..mb.instance_count).step_by(CHUNK_INSTANCES as usize) {
                let n = CHUNK_INSTANCES.min(mb.instance_count - start);
                let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
                for i in start..start + n {
                    let t = instance(i);
                    let scale = t
                        .matrix3
                        .x_axis
                        .length()
                        .max(t.matrix3.y_axis.length())
                        .max(t.matrix3.z_axis.length());
                    let r = reach[batch.mesh.0] * scale + sway;
                    let c = Vec3::from(t.translation) - origin;
                    lo = lo.min(c - r);
                    hi = hi.max(c + r);
                }
                plan.chunks.push(DrawChunk {
                    first_instance: first_global + start,
                    instance_count: n,
                    center: (lo + hi) * 0.5,
                    // Padded for the f32 rounding of the transforms.
                    radius: (hi - lo).length() * 0.5 * (1.0 + 1e-5) + 1e-3,
                });
            }
            for i in 0..mb.instance_count {
                let t = instance(i);
                let (micro_batch, field) = visbuf::split_instance(mb.first_id, i, bits);
                plan.instances.push(GpuInstance {
                    rows: origin_relative_rows(t, origin),
                    micro_batch,
                    instance_field: field,
                    primitive_bits: bits.get(),
                    material: batch.material.0 as u32,
                });
            }
            let row = GpuMicroBatch {
                first_instance: first_global,
                first_id: mb.first_id,
                mesh: batch.mesh.0 as u32,
                primitive_bits: bits.get(),
            };
            let end = (mb.first_id + mb.id_count) as usize;
            if plan.micro_batch_ids.len() < end {
                plan.micro_batch_ids.resize(end, GpuMicroBatch::default());
            }
            plan.micro_batch_ids[mb.first_id as usize..end].fill(row);
            plan.draws.push(Draw {
                first_index: mesh.first_index,
                index_count: mesh.primitive_count * 3,
                base_vertex: mesh.base_vertex,
                first_instance: first_global,
                instance_count: mb.instance_count,
                alpha_tested: scene.materials[batch.material.0].shader == ShaderKind::AlphaTested,
                regular: scene.materials[batch.material.0].regular,
                first_chunk,
                chunk_count: plan.chunks.len() as u32 - first_chunk,
            });
        }
        plan
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Quat, Vec4};

    #[test]
    fn origin_relative_transform_matches_the_world_transform() {
        let t = Affine3A::from_scale_rotation_translation(
            Vec3::splat(1.5),
            Quat::from_rotation_y(0.7),
            Vec3::new(100.0, 2.0, -40.0),
        );
        let origin = Vec3::new(98.0, 1.0, -45.0);
        let rows = origin_relative_rows(&t, origin);
        let p = Vec3::new(0.3, -0.2, 1.0);
        let world = t.transform_point3(p);
        for (k, row) in rows.iter().enumerate() {
            let rel = Vec4::from(*row).dot(p.extend(1.0));
            assert!((rel - (world - origin)[k]).abs() < 1e-4);
        }
    }
}
