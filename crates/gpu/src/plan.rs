//! The frame's draw plan: micro batches (from `tiling`) turned into the GPU's instance
//! table, the per-micro-batch-ID lookup table of the resolve, and one draw per micro batch.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use crate::frame::{GpuInstance, camera_relative_rows};
use crate::geometry::Geometry;
use crate::laydown::Draw;
use crate::scene::{Scene, ShaderKind};

/// What the resolve looks up per micro-batch ID (WGSL `GpuMicroBatch`), indexed by the
/// 16-bit ID in the vis word: every ID of a micro batch's range holds the same row. 16 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct GpuMicroBatch {
    /// Global index (in the instance table) of the micro batch's instance 0.
    pub first_instance: u32,
    /// The first micro-batch ID of the micro batch's range.
    pub first_id: u32,
    /// Index of the mesh record ([`crate::geometry::GpuMesh`]).
    pub mesh: u32,
    /// The mesh's primitive bits.
    pub primitive_bits: u32,
}
const _: () = assert!(size_of::<GpuMicroBatch>() == 16);

/// WGSL of [`GpuMicroBatch`].
pub const PLAN_WGSL: &str = r"
struct GpuMicroBatch {
    first_instance: u32,
    first_id: u32,
    mesh: u32,
    primitive_bits: u32,
}
";

/// One micro batch as the plan needs it: which batch, which of its instances, and the
/// micro-batch IDs it occupies in the vis buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PlannedMicroBatch {
    /// Index of the scene batch.
    pub batch: u32,
    /// First instance of the batch in this micro batch.
    pub first_instance: u32,
    /// Instances in this micro batch.
    pub instance_count: u32,
    /// First micro-batch ID of its range (instance overflow continues in the next IDs).
    pub first_id: u32,
    /// How many consecutive IDs it occupies.
    pub id_count: u32,
    /// Its pass.
    pub pass: u32,
    /// Its batch group within the pass.
    pub batch_group: u32,
}

/// The GPU tables of a frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Plan {
    /// Instances in micro-batch order.
    pub instances: Vec<GpuInstance>,
    /// Indexed by micro-batch ID.
    pub micro_batch_ids: Vec<GpuMicroBatch>,
    /// One draw per micro batch.
    pub draws: Vec<Draw>,
    /// The micro batches, in order.
    pub micro_batches: Vec<PlannedMicroBatch>,
}

impl Plan {
    /// Lays out instances and lookup tables for `micro_batches` of `scene` with camera-
    /// relative transforms around `camera`.
    pub fn new(
        scene: &Scene,
        geometry: &Geometry,
        micro_batches: &[PlannedMicroBatch],
        camera: Vec3,
    ) -> Self {
        let mut plan = Plan {
            micro_batches: micro_batches.to_vec(),
            ..Plan::default()
        };
        for mb in micro_batches {
            let batch = &scene.batches[mb.batch as usize];
            let mesh = geometry.meshes[batch.mesh.0];
            let bits = visbuf::PrimitiveBits::for_count(mesh.primitive_count.max(1))
                .expect("meshes were validated against the 64k primitive limit");
            let first_global = plan.instances.len() as u32;
            for i in 0..mb.instance_count {
                let t = &batch.instances[(mb.first_instance + i) as usize];
                let (micro_batch, field) = visbuf::split_instance(mb.first_id, i, bits);
                let rows = camera_relative_rows(t, camera);
                plan.instances.push(GpuInstance {
                    row0: rows[0],
                    row1: rows[1],
                    row2: rows[2],
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
            });
        }
        plan
    }
}
