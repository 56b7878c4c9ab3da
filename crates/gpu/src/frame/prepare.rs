//! A scene prepared for one renderer: `resources` uploads its geometry, plan and tables,
//! then each pass makes its groups over them (its own `groups`/`buffers` function), and the
//! result is one [`PreparedScene`].

use glam::Vec3;

use super::Pipelines;
use crate::context::PrimitiveIdPath;
use crate::error::{Error, Result, SceneError};
use crate::passes::resolve::RESOLVE_FEATURE_BITS;
use crate::resources::buffers::storage;
use crate::resources::geometry::Geometry;
use crate::resources::plan::{Draw, Plan};
use crate::resources::rows::{self, GpuInstance, GpuMaterial, GpuMicroBatch, GpuStaticSetup};
use crate::resources::static_draws::StaticBuffers;
use crate::resources::{PreparedScene, SceneSummary, StaticShadowSet, targets};
use crate::resources::{albedo, static_pool};
use crate::scene::{Scene, ShaderKind};

/// The renderer-level resources a scene's bind groups refer to.
pub(crate) struct PrepareContext<'a> {
    pub device: &'a wgpu::Device,
    pub queue: &'a wgpu::Queue,
    pub pipelines: &'a Pipelines,
    pub frame: &'a wgpu::Buffer,
    pub sampler: &'a wgpu::Sampler,
    pub targets: &'a targets::Targets,
    pub path: PrimitiveIdPath,
    pub wave_width: wave::WaveWidth,
    pub id: u64,
    /// Whether the device draws indirect lists with a count buffer.
    pub multi_draw_count: bool,
    /// Whether indirect draws may start past instance 0 (static setups need it).
    pub indirect_first_instance: bool,
    /// Whether the renderer bakes KZ2's pre-rendered sun map.
    pub baked_sun: bool,
    /// The vertex ring's bytes (`RendererConfig::geometry.vertex_ring`; `None`: no ring).
    pub ring_bytes: Option<u64>,
    /// Whether the resolve reads the ring (`RendererConfig::geometry.ring_resolve`).
    pub ring_resolve: bool,
    /// HFW's software VRS (`RendererConfig::geometry.vrs`): the plan uses visbuf's VRS layout.
    pub vrs: bool,
    /// HFW's resolve per material shader
    /// (`RendererConfig::geometry.material_permutations`).
    pub material_permutations: bool,
}

/// The floating origin of `scene`: its instances' bounds centre snapped to 1 m (zero for
/// an empty scene).
fn origin(scene: &Scene) -> Vec3 {
    let mut it = scene
        .batches
        .iter()
        .flat_map(|b| b.instances.iter().map(|t| Vec3::from(t.translation)));
    let Some(first) = it.next() else {
        return Vec3::ZERO;
    };
    let (lo, hi) = it.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p)));
    ((lo + hi) * 0.5).round()
}

/// The world bounds of the scene's batch instances (each mesh's box through each
/// instance's transform), relative to `origin`; `None` without instances.
fn batch_bounds(scene: &Scene, origin: Vec3) -> Option<(Vec3, Vec3)> {
    let mut bounds: Option<(Vec3, Vec3)> = None;
    for b in &scene.batches {
        let Some(mesh) = scene.meshes.get(b.mesh.0) else {
            continue;
        };
        let Some(&first) = mesh.positions.first() else {
            continue;
        };
        let (lo, hi) = mesh
            .positions
            .iter()
            .fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        let (centre, half) = ((lo + hi) * 0.5, (hi - lo) * 0.5);
        for t in &b.instances {
            let c = t.transform_point3(centre) - origin;
            let m = glam::Mat3::from(t.matrix3);
            let e = m.x_axis.abs() * half.x + m.y_axis.abs() * half.y + m.z_axis.abs() * half.z;
            bounds = Some(match bounds {
                None => (c - e, c + e),
                Some((a, z)) => (a.min(c - e), z.max(c + e)),
            });
        }
    }
    bounds.filter(|(lo, hi)| lo.is_finite() && hi.is_finite())
}

/// Reserves instance slots and micro-batch IDs for every static setup (`tiling`'s
/// reservations, in shader and material order so they share passes) and returns the GPU
/// table of setups, indexed by setup handle.
fn reserve_static(
    scene: &Scene,
    geometry: &Geometry,
    plan: &mut tiling::Plan,
    config: &tiling::PlanConfig,
) -> Result<Vec<GpuStaticSetup>> {
    let mut order: Vec<usize> = (0..scene.static_setups.len()).collect();
    let key = |i: usize| {
        let m = &scene.materials[scene.static_setups[i].material.0];
        (m.shader_key(), scene.static_setups[i].material.0)
    };
    order.sort_by_key(|&i| key(i));
    let reservations: Vec<tiling::Reservation> = order
        .iter()
        .map(|&i| {
            let s = &scene.static_setups[i];
            let m = geometry.meshes[s.mesh.0];
            tiling::Reservation {
                shader: scene.materials[s.material.0].shader_key(),
                batch_data: s.material.0 as u64,
                geometry: tiling::Geometry {
                    vertex_count: m.vertex_count,
                    primitive_count: m.primitive_count,
                    first_index: m.first_index,
                    base_vertex: m.base_vertex,
                },
                capacity: s.capacity,
            }
        })
        .collect();
    let first_new = plan.micro_batches.len();
    let ranges = plan.reserve(&reservations, config).map_err(|e| {
        let setup = match e {
            tiling::Error::MicroBatchIdsExhausted { batch, .. }
            | tiling::Error::TooManyPasses { batch, .. }
            | tiling::Error::EmptyGeometry { batch }
            | tiling::Error::GeometryTooLarge { batch, .. } => order[batch as usize],
            // A sum over every setup (slots, chunks): no one setup to name.
            _ => return Error::Scene(SceneError::Tiling(format!("static setups: {e}"))),
        };
        Error::Scene(SceneError::StaticSetup {
            setup,
            problem: e.to_string(),
        })
    })?;
    // The rows name the reservation; make them name the setup handle.
    for mb in &mut plan.micro_batches[first_new..] {
        mb.batch = order[mb.batch as usize] as u32;
    }
    for row in plan
        .table
        .iter_mut()
        .skip_while(|r| (r.order as usize) < first_new)
    {
        row.batch = order[row.batch as usize] as u32;
    }
    let mut setups = vec![GpuStaticSetup::default(); scene.static_setups.len()];
    for (&i, r) in order.iter().zip(&ranges) {
        let s = &scene.static_setups[i];
        let m = geometry.meshes[s.mesh.0];
        setups[i] = GpuStaticSetup {
            first_index: m.first_index,
            index_count: m.primitive_count * 3,
            base_vertex: m.base_vertex,
            first_slot: r.first_instance,
            capacity: r.capacity,
            first_id: r.first_id,
            primitive_bits: r.primitive_bits,
            material: s.material.0 as u32,
            list: u32::from(scene.materials[s.material.0].shader == ShaderKind::AlphaTested),
            ..GpuStaticSetup::default()
        };
    }
    Ok(setups)
}

/// Per batch, its instances' order along a Morton curve over the scene's instance
/// positions (21 bits per axis); the given order where the positions are degenerate.
fn spatial_order(scene: &Scene) -> Vec<Vec<u32>> {
    let all = scene
        .batches
        .iter()
        .flat_map(|b| b.instances.iter().map(|t| Vec3::from(t.translation)));
    let (lo, hi) = all.fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(p), hi.max(p)),
    );
    let quantizer = morton::Quantizer3::new(lo, hi, morton::BITS3_U64).ok();
    scene
        .batches
        .iter()
        .map(|b| {
            let identity = || (0..b.instances.len() as u32).collect();
            let Some(q) = &quantizer else {
                return identity();
            };
            let keys: Option<Vec<u64>> = b
                .instances
                .iter()
                .map(|t| {
                    q.quantize(Vec3::from(t.translation))
                        .ok()
                        .map(|c| morton::encode3_u64(c.x, c.y, c.z))
                })
                .collect();
            keys.and_then(|k| morton::sort_permutation(&k).ok())
                .unwrap_or_else(identity)
        })
        .collect()
}

/// Validates `scene`, encodes it, plans it with `tiling`, uploads it and makes every pass's
/// bind groups.
pub(crate) fn prepare(c: &PrepareContext<'_>, scene: &Scene) -> Result<PreparedScene> {
    scene.validate()?;
    let device = c.device;
    let geometry = Geometry::build(&scene.meshes, c.path)?;
    // Each batch's instances in Morton order: consecutive instances (micro batches and
    // their draw chunks) stay close together, so shadow views can cull chunks.
    let order = spatial_order(scene);
    let positions: Vec<Vec<[f32; 3]>> = scene
        .batches
        .iter()
        .zip(&order)
        .map(|(b, o)| {
            o.iter()
                .map(|&i| b.instances[i as usize].translation.to_array())
                .collect()
        })
        .collect();
    let batches = scene.tiling_batches(&positions, |m| {
        let m = geometry.meshes[m];
        tiling::Geometry {
            vertex_count: m.vertex_count,
            primitive_count: m.primitive_count,
            first_index: m.first_index,
            base_vertex: m.base_vertex,
        }
    });
    let config = tiling::PlanConfig {
        ring_bytes: c.ring_bytes.unwrap_or(tiling::RING_BYTES_PS5),
        // HFW's VRS steals the micro-batch ID's top two bits for the shading rate.
        layout: if c.vrs {
            visbuf::VisLayout::Vrs
        } else {
            visbuf::VisLayout::Standard
        },
        ..tiling::PlanConfig::default()
    };
    let mut tiling_plan = tiling::build_plan(&batches, &config)
        .map_err(|e| Error::Scene(SceneError::Tiling(e.to_string())))?;
    let planned = tiling_plan.micro_batches.len();
    let origin = origin(scene);
    let mut plan = Plan::new(scene, &geometry, &tiling_plan.micro_batches, origin, &order);
    let static_setups = reserve_static(scene, &geometry, &mut tiling_plan, &config)?;
    if !static_setups.is_empty() && !c.indirect_first_instance {
        return Err(Error::MissingFeature {
            feature: "INDIRECT_FIRST_INSTANCE",
            needed_by: "static setups (indirect draws of reserved instance slots)",
        });
    }
    // Reserved slots start zeroed (a zero scale: nothing drawn until placed); their IDs
    // resolve to their setup's mesh.
    plan.instances
        .resize(tiling_plan.instance_count as usize, GpuInstance::default());
    for mb in &tiling_plan.micro_batches[planned..] {
        let mesh = scene.static_setups[mb.batch as usize].mesh.0 as u32;
        let end = (mb.first_id + mb.id_count) as usize;
        if plan.micro_batch_ids.len() < end {
            plan.micro_batch_ids.resize(end, GpuMicroBatch::default());
        }
        plan.micro_batch_ids[mb.first_id as usize..end].fill(GpuMicroBatch {
            first_instance: mb.first_instance,
            first_id: mb.first_id,
            mesh,
            primitive_bits: mb.primitive_bits,
        });
    }
    let materials: Vec<GpuMaterial> = scene.materials.iter().map(GpuMaterial::new).collect();
    crate::context::scoped(device, || {
        let none = wgpu::BufferUsages::empty();
        let vertices = storage(
            device,
            "vertices",
            bytemuck::cast_slice(&geometry.vertices),
            size_of::<rows::GpuVertex>(),
            none,
        )?;
        let payloads = storage(
            device,
            "payloads",
            bytemuck::cast_slice(&geometry.payloads),
            4,
            none,
        )?;
        let index_buffer = storage(
            device,
            "indices",
            bytemuck::cast_slice(&geometry.indices),
            4,
            wgpu::BufferUsages::INDEX,
        )?;
        let instances = storage(
            device,
            "instances",
            bytemuck::cast_slice(&plan.instances),
            size_of::<GpuInstance>(),
            none,
        )?;
        let materials = storage(
            device,
            "materials",
            bytemuck::cast_slice(&materials),
            size_of::<GpuMaterial>(),
            none,
        )?;
        let meshes = storage(
            device,
            "meshes",
            bytemuck::cast_slice(&geometry.meshes),
            size_of::<rows::GpuMesh>(),
            none,
        )?;
        let micro_batches = storage(
            device,
            "micro batches",
            bytemuck::cast_slice(&plan.micro_batch_ids),
            size_of::<GpuMicroBatch>(),
            none,
        )?;
        let albedo = albedo::albedo_texture(device, c.queue, &scene.albedo_layers)?;
        let albedo_view = albedo.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let data = albedo::data_texture(device, c.queue, &scene.data_layers)?;
        let data_view = data.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let scene_group = [
            ("frame", c.frame.as_entire_binding()),
            ("vertices", vertices.as_entire_binding()),
            ("instances", instances.as_entire_binding()),
            ("materials", materials.as_entire_binding()),
            ("albedo", wgpu::BindingResource::TextureView(&albedo_view)),
            ("albedo_sampler", wgpu::BindingResource::Sampler(c.sampler)),
            (
                "baked_sun_map",
                wgpu::BindingResource::TextureView(&c.targets.shadows.baked_view),
            ),
            ("data_maps", wgpu::BindingResource::TextureView(&data_view)),
        ];
        let p = c.pipelines;
        // The bake pass's group: its own frame, the stand-in where the map it renders is.
        let mut bake_group = scene_group.clone();
        bake_group[0].1 = c.targets.shadows.baked_frame.as_entire_binding();
        bake_group[6].1 = wgpu::BindingResource::TextureView(&c.targets.shadows.stand_in_view);
        let bake_scene = p.laydown.scene_group(device, &bake_group)?;
        // The chunk marks are read only by the vertex ring's passes.
        let config = tiling::ClassifyConfig {
            vertex_cull: c.ring_bytes.is_some(),
            ..tiling::ClassifyConfig::for_plan(&tiling_plan, c.wave_width)
        };
        let batch_groups: usize = tiling_plan.pass_groups.iter().map(Vec::len).sum();
        let sizes = crate::resources::groups::Sizes::new(
            c.targets.width,
            c.targets.height,
            &config,
            batch_groups as u32,
        );
        let classification = crate::resources::groups::ClassifyBuffers::new(
            &p.classify,
            device,
            &tiling_plan,
            (sizes, config),
            &c.targets.vis_words,
            &index_buffer,
            p.regular.is_some(),
        )?;
        let regular = p
            .regular
            .as_ref()
            .map(|r| r.groups(device, &scene_group, classification.validity()))
            .transpose()?;
        let pixel_pull = p.pixel_pull.groups(
            device,
            &scene_group,
            [&payloads, &index_buffer, &meshes, &micro_batches],
        )?;
        let vertex_ring = c
            .ring_bytes
            .map(|bytes| {
                p.vertex_ring.buffers(
                    device,
                    &tiling_plan,
                    classification.params,
                    &classification.vertex_cull,
                    &scene_group,
                    &meshes,
                    &micro_batches,
                    bytes,
                )
            })
            .transpose()?;
        // HFW's resolve per material shader: each pass's permutation.
        let pass_pipelines = if c.material_permutations {
            tiling_plan
                .passes
                .iter()
                .map(|pass| p.resolve.permutation(device, pass.shader))
                .collect::<Result<Vec<_>>>()?
        } else {
            Vec::new()
        };
        let resolve_pipelines = {
            let mut keys: Vec<u32> = tiling_plan
                .passes
                .iter()
                .map(|pass| pass.shader & RESOLVE_FEATURE_BITS)
                .collect();
            keys.sort_unstable();
            keys.dedup();
            if c.material_permutations {
                keys.len()
            } else {
                1
            }
        };
        let resolve = p.resolve.groups(
            device,
            &scene_group,
            &index_buffer,
            &meshes,
            &micro_batches,
            &c.targets.vis_view,
            &classification,
            vertex_ring.as_ref().filter(|_| c.ring_resolve),
            pass_pipelines,
        )?;
        let summary = SceneSummary {
            instances: scene.instance_count() as u64,
            triangles: scene.triangle_count(),
            vertices: scene.vertex_count(),
            micro_batches: tiling_plan.micro_batches.len(),
            passes: tiling_plan.passes.len(),
            batch_groups,
            resolve_pipelines,
            added_vertices: geometry.added_vertices.iter().map(|&a| u64::from(a)).sum(),
            origin,
        };
        let statics = (!static_setups.is_empty())
            .then(|| StaticBuffers::new(device, &static_setups, c.multi_draw_count));
        let cascades = c.targets.shadows.cascades();
        let static_shadows = match &statics {
            Some(camera) => (0..cascades.max(u32::from(c.baked_sun)))
                .map(|k| {
                    let buffers = camera.for_shadow_view(device);
                    let rows = buffers.reserved_slots().max(1);
                    let instances = static_pool::empty_storage(
                        device,
                        "static shadow instances",
                        rows * size_of::<GpuInstance>() as u64,
                    )?;
                    let mut group = scene_group.clone();
                    group[2].1 = instances.as_entire_binding();
                    let slice_group =
                        (k < cascades)
                            .then(|| {
                                group[0].1 = wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                                    buffer: &c.targets.shadows.frames,
                                    offset: u64::from(k) * crate::shadows::CASCADE_FRAME_STRIDE,
                                    size: wgpu::BufferSize::new(
                                        size_of::<rows::FrameUniforms>() as u64
                                    ),
                                });
                                p.laydown.scene_group(device, &group)
                            })
                            .transpose()?;
                    let bake = (k == 0 && c.baked_sun)
                        .then(|| {
                            let mut bindings = bake_group.clone();
                            bindings[2].1 = instances.as_entire_binding();
                            p.laydown.scene_group(device, &bindings)
                        })
                        .transpose()?;
                    Ok(StaticShadowSet {
                        buffers,
                        instances,
                        slice_group,
                        bake_group: bake,
                    })
                })
                .collect::<Result<Vec<_>>>()?,
            None => Vec::new(),
        };
        let compute_laydown = match (&p.compute_laydown, &c.targets.vis64) {
            (Some(cl), Some(target)) => {
                // The mixed frame's laydown leaves the regular draws to their own pass.
                let draws: Vec<Draw> = plan
                    .draws
                    .iter()
                    .filter(|d| !(regular.is_some() && d.regular))
                    .copied()
                    .collect();
                let finalize = classification.finalize_resources(&c.targets.vis_words);
                cl.groups(
                    device,
                    &scene_group,
                    &finalize,
                    &draws,
                    &index_buffer,
                    target,
                )?
            }
            _ => None,
        };
        Ok(PreparedScene {
            id: c.id,
            summary,
            wind: scene.wind,
            vertex_ring,
            compute_laydown,
            laydown: p.laydown.groups(device, &scene_group, &payloads)?,
            bake_scene,
            bounds: batch_bounds(scene, origin),
            shadow_scene: (0..c.targets.shadows.cascades())
                .map(|i| {
                    let mut group = scene_group.clone();
                    group[0].1 = wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &c.targets.shadows.frames,
                        offset: u64::from(i) * crate::shadows::CASCADE_FRAME_STRIDE,
                        size: wgpu::BufferSize::new(size_of::<rows::FrameUniforms>() as u64),
                    });
                    p.laydown.scene_group(device, &group)
                })
                .collect::<Result<_>>()?,
            spot_shadow_scene: (0..c.targets.spot_shadows.layers())
                .map(|i| {
                    let mut group = scene_group.clone();
                    group[0].1 = wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &c.targets.spot_shadows.frames,
                        offset: u64::from(i) * crate::shadows::CASCADE_FRAME_STRIDE,
                        size: wgpu::BufferSize::new(size_of::<rows::FrameUniforms>() as u64),
                    });
                    p.laydown.scene_group(device, &group)
                })
                .collect::<Result<_>>()?,
            baseline: p.baseline.group(device, &scene_group)?,
            regular,
            pixel_pull,
            classification,
            resolve,
            draws: plan.draws,
            chunks: plan.chunks,
            instance_order: order,
            statics,
            static_shadows,
            instances: instances.clone(),
            static_capacities: scene.static_setups.iter().map(|s| s.capacity).collect(),
            static_table: static_setups.clone(),
            index_buffer,
            geometry,
            tiling: tiling_plan,
            _kept: vec![
                vertices,
                payloads,
                instances,
                materials,
                meshes,
                micro_batches,
            ],
            _albedo: albedo,
            _data: data,
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Affine3A;

    #[test]
    fn the_origin_is_the_snapped_bounds_centre() {
        let mut scene = Scene::default();
        assert_eq!(origin(&scene), Vec3::ZERO);
        scene.batches.push(scene::Batch {
            mesh: scene::MeshId(0),
            material: scene::MaterialId(0),
            instances: vec![
                Affine3A::from_translation(Vec3::new(10.2, -3.0, 100.0)),
                Affine3A::from_translation(Vec3::new(20.9, 5.0, 300.6)),
            ],
        });
        assert_eq!(origin(&scene), Vec3::new(16.0, 1.0, 200.0));
    }
}
