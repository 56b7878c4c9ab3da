//! The compute visibility laydown (issue 17): the planned draws' triangles rasterised in
//! compute into a 64-bit visibility target (depth bits high, vis word low, `atomicMax`),
//! small ones an invocation each, large ones a workgroup each (an indirect dispatch over
//! the list the first pass appends them to), the triangles the hardware must clip drawn
//! by a hybrid hardware part into the same target (a fragment `atomicMax`), then one
//! compute pass that unpacks the target into what the rest of the frame reads: the vis
//! words, the vis texture and the float depth, finalising the laydown for the
//! classification on the way (`tiling::finalize`'s masks; the classification's zero fill
//! runs beside the raster, after the large triangles in their pass) and reducing the depth
//! to the light tiles' depth ranges (the lights' pass 1, which such frames skip unless a
//! regular pass draws depth after the laydown). Frames whose later
//! raster passes test against the depth target (the stencil light volumes, the mixed
//! frame's regular pass, the water) also get it, from a full-screen raster pass over the
//! unpacked float depth: 1.05 ms of fill at 4K on the H200, which every other frame skips.
//!
//! Four described passes: `gpu::compute_laydown` (one dispatch, one invocation per
//! (instance, triangle) of the scene's planned draws: a draw table with per-draw item
//! prefixes, the draw found by binary search), `gpu::compute_laydown_hybrid` (the listed
//! triangles, one non-indexed indirect draw whose vertex stage fetches (instance, vertex)
//! from the list), `gpu::laydown_unpack` and `gpu::laydown_target` (the depth target).
//! Needs 64-bit storage-buffer atomics ([`COMPUTE_LAYDOWN_FEATURES`]); without them the
//! renderer keeps the hardware laydown. Frames with a static query keep the hardware
//! laydown (its draw lists are indirect).

use bytemuck::{Pod, Zeroable};
use shader::pipeline::{ComputePass, Layouts, RasterPass};
use shader::{Binding, Compare, Depth, Entry, Format, Group, Kind, Pass, Raster, Sample, Stage};

use super::context::FrameContext;
use super::raster::{DEPTH, GEOMETRY, SCENE_GROUP, depth_attachment};
use crate::error::Result;
pub(crate) use crate::resources::groups::ComputeLaydownGroups as Groups;
pub(crate) use crate::resources::groups::LaydownTargetGroups as TargetGroups;
use crate::resources::plan::Draw;
use crate::resources::targets::Targets;
use crate::resources::vis64::LaydownTarget;
use crate::resources::vis64::TargetResource;
use crate::shaders::LIBRARY;
use crate::timing::GpuTimer;

/// Most triangles the hardware part's list holds (4 bytes each: 16 MiB). Triangles past
/// it are dropped (never silently: [`LaydownStats::hybrid`] counts them all).
pub(crate) const HYBRID_CAPACITY: u32 = 1 << 22;

/// Most triangles the large-triangle list holds: with its header, 128 MiB, wgpu's default
/// largest storage binding (the rebuilt hillside at density 2 lists 6.3 million; a 16 MiB
/// list dropped a third of them). Past it, triangles are dropped and counted.
pub(crate) const LARGE_CAPACITY: u32 = (1 << 25) - 4;

/// Bytes of the hybrid list's header: a `DrawIndirectArgs`.
const HYBRID_HEADER: u64 = 16;
/// Bytes of the large list's header: `raster_large`'s dispatch arguments and the count.
const LARGE_HEADER: u64 = 16;

/// One row of the draw table (WGSL `GpuLaydownDraw`), 32 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub(crate) struct GpuLaydownDraw {
    /// First item (instance x triangle) of the draw: the sum over the rows before.
    pub first_item: u32,
    pub first_index: u32,
    pub base_vertex: u32,
    pub first_instance: u32,
    pub instance_count: u32,
    /// Triangles of the mesh, at least 1.
    pub triangles: u32,
    /// [`DRAW_ALPHA_TESTED`].
    pub flags: u32,
    pub pad: u32,
}
const _: () = assert!(size_of::<GpuLaydownDraw>() == 32);
// The unpack's workgroup covers a tiling block, which it reduces as 2x2 light tiles.
const _: () = assert!(tiling::wgsl::BLOCK_SIZE == 2 * deferred::lights::TILE_SIZE);

/// `GpuLaydownDraw::flags`: the material is alpha-tested.
pub(crate) const DRAW_ALPHA_TESTED: u32 = 1;

/// The draw table's rows and its item count (the raster's invocations) for `draws`, or
/// `None` when the items do not fit a `u32`. Empty draws are left out.
pub(crate) fn draw_table(draws: &[Draw]) -> Option<(Vec<GpuLaydownDraw>, u32)> {
    let mut rows = Vec::new();
    let mut items = 0u64;
    for d in draws {
        let triangles = d.index_count / 3;
        if triangles == 0 || d.instance_count == 0 {
            continue;
        }
        rows.push(GpuLaydownDraw {
            first_item: u32::try_from(items).ok()?,
            first_index: d.first_index,
            base_vertex: d.base_vertex,
            first_instance: d.first_instance,
            instance_count: d.instance_count,
            triangles,
            flags: if d.alpha_tested { DRAW_ALPHA_TESTED } else { 0 },
            pad: 0,
        });
        items += u64::from(triangles) * u64::from(d.instance_count);
    }
    Some((rows, u32::try_from(items).ok()?))
}

/// The first three bindings of group 1 of the raster and of the hardware part.
const DRAWS: Binding = Binding::new(
    "laydown_draws",
    Kind::read(16 + size_of::<GpuLaydownDraw>()),
);
const INDICES: Binding = Binding::new("laydown_indices", Kind::read(4));
const TARGET: Binding = Binding::new("laydown_target", Kind::read_write(8));
const TEXTURE_TARGET: Binding = Binding::new(
    "laydown_target",
    Kind::atomic_storage_texture_2d(Format::R64Uint),
);

/// Group 1 of the raster, which appends to the list the hardware part reads.
const RASTER_GROUP: Group = Group {
    name: "laydown",
    bindings: &[
        DRAWS,
        INDICES,
        TARGET,
        Binding::new("hybrid", Kind::read_write(HYBRID_HEADER as usize + 4)),
        // The large triangles' list: dispatch arguments, count, then one item.
        Binding::new("large", Kind::read_write(LARGE_HEADER as usize + 4)),
    ],
};

/// [`RASTER_GROUP`] over the texture target.
const TEXTURE_RASTER_GROUP: Group = Group {
    name: "laydown",
    bindings: &[
        DRAWS,
        INDICES,
        TEXTURE_TARGET,
        RASTER_GROUP.bindings[3],
        RASTER_GROUP.bindings[4],
    ],
};

/// Group 1 of the hardware part.
const HYBRID_GROUP: Group = Group {
    name: "laydown",
    bindings: &[
        DRAWS,
        INDICES,
        TARGET,
        Binding::new("hybrid", Kind::read(HYBRID_HEADER as usize + 4)),
    ],
};

/// [`HYBRID_GROUP`] over the texture target.
const TEXTURE_HYBRID_GROUP: Group = Group {
    name: "laydown",
    bindings: &[DRAWS, INDICES, TEXTURE_TARGET, HYBRID_GROUP.bindings[3]],
};

/// The raster, one invocation per item (the parameter: the item count).
pub(crate) const COMPUTE_LAYDOWN: Pass<u32> = Pass {
    name: "compute laydown",
    module: "gpu::compute_laydown",
    library: LIBRARY,
    features: &["subgroups"],
    groups: &[SCENE_GROUP, RASTER_GROUP],
    entries: &[
        Entry::items("raster", 64, |items| *items),
        Entry::once("large_args", 1),
        Entry {
            name: "raster_large",
            stage: Stage::compute(256, 1, 1),
            dispatch: shader::Dispatch::Indirect("large"),
        },
    ],
    zeroed: &["laydown_target", "hybrid", "large"],
};

/// [`COMPUTE_LAYDOWN`] into the texture target (feature `texture_target`).
pub(crate) const COMPUTE_LAYDOWN_TEXTURE: Pass<u32> = Pass {
    groups: &[SCENE_GROUP, TEXTURE_RASTER_GROUP],
    features: &["subgroups", "texture_target"],
    // The texture starts at 0 and the unpack resets it.
    zeroed: &["hybrid", "large"],
    ..COMPUTE_LAYDOWN
};

/// The hardware part: the listed triangles, drawn into the 64-bit target.
pub(crate) const COMPUTE_LAYDOWN_HYBRID: Pass = Pass {
    name: "compute laydown hybrid",
    module: "gpu::compute_laydown_hybrid",
    library: LIBRARY,
    features: &[],
    groups: &[SCENE_GROUP, HYBRID_GROUP],
    entries: &[
        Entry::draw("vs_hybrid", Stage::Vertex),
        Entry::draw("fs_hybrid", Stage::Fragment),
    ],
    zeroed: &[],
};

/// [`COMPUTE_LAYDOWN_HYBRID`] into the texture target (feature `texture_target`).
pub(crate) const COMPUTE_LAYDOWN_HYBRID_TEXTURE: Pass = Pass {
    groups: &[SCENE_GROUP, TEXTURE_HYBRID_GROUP],
    features: &["texture_target"],
    ..COMPUTE_LAYDOWN_HYBRID
};

/// The 64-bit target into the vis words, the vis texture and the float depth, over the
/// image (`[width, height]`), the classification's laydown finalise over the words
/// (`tiling::finalize`) and the light tiles' depth ranges (a tiling block is 2x2 light
/// tiles): group 0 is tiling's with the vis words at binding 1 (a prepared
/// scene's, [`Groups`]), group 1 the target and the textures (the renderer's,
/// [`TargetGroups`]).
pub(crate) const LAYDOWN_UNPACK: Pass<[u32; 2]> = Pass {
    name: "laydown unpack",
    module: "gpu::laydown_unpack",
    library: LIBRARY,
    features: &[],
    groups: &[
        Group {
            name: "classification",
            bindings: &tiling::wgsl::finalize_bindings(Binding::new(
                "vis_words",
                Kind::read_write(4),
            )),
        },
        Group {
            name: "unpack",
            bindings: &[
                Binding::new("laydown_target", Kind::read(8)),
                Binding::new("vis_out", Kind::storage_texture_2d(Format::R32Uint)),
                Binding::new("depth_float", Kind::storage_texture_2d(Format::R32Float)),
                // The light tiles' depth ranges (passes::lights), a block's 2x2 tiles per
                // workgroup.
                Binding::new(
                    "tile_depths",
                    Kind::read_write(size_of::<deferred::DeferredTileDepth>()),
                ),
            ],
        },
    ],
    // Four pixels an invocation: a 16x16 workgroup per tiling block.
    entries: &[Entry::grid("unpack", 16, 16, |[w, h]| {
        let blocks = |n: u32| n.div_ceil(tiling::wgsl::BLOCK_SIZE) * 16;
        [blocks(*w), blocks(*h)]
    })],
    zeroed: &["masks"],
};

/// [`LAYDOWN_UNPACK`] of the texture target, which it resets (feature `texture_target`).
pub(crate) const LAYDOWN_UNPACK_TEXTURE: Pass<[u32; 2]> = Pass {
    groups: &[
        LAYDOWN_UNPACK.groups[0],
        Group {
            name: "unpack",
            bindings: &[
                TEXTURE_TARGET,
                LAYDOWN_UNPACK.groups[1].bindings[1],
                LAYDOWN_UNPACK.groups[1].bindings[2],
                LAYDOWN_UNPACK.groups[1].bindings[3],
            ],
        },
    ],
    features: &["texture_target"],
    ..LAYDOWN_UNPACK
};

/// The unpacked float depth into the depth target (full-screen triangle), for frames
/// whose later raster passes test against it.
pub(crate) const LAYDOWN_TARGET: Pass = Pass {
    name: "laydown target",
    module: "gpu::laydown_target",
    library: LIBRARY,
    features: &[],
    groups: &[Group {
        name: "target",
        bindings: &[Binding::new(
            "depth_float",
            Kind::texture_2d(Sample::Float { filterable: false }),
        )],
    }],
    entries: &[
        Entry::draw("vs_full", Stage::Vertex),
        Entry::draw("fs_target", Stage::Fragment),
    ],
    zeroed: &[],
};

/// The hardware part's pipeline: the hardware laydown's culling and clipping, a fragment
/// atomic into the target, no colour target; the depth attachment is there because a
/// render pass needs one: neither tested nor written. Only triangles the hardware must clip
/// come here: a fragment atomic with no early depth test cost 10.7 ms on the H200's forest
/// when the large triangles came too.
pub(crate) const HYBRID_PIPELINE: Raster<'static> =
    Raster::new(COMPUTE_LAYDOWN_HYBRID.name, "vs_hybrid")
        .fragment("fs_hybrid")
        .primitive(GEOMETRY)
        .depth(Depth::test(DEPTH, Compare::Always, false));

/// The float depth into the depth target: every pixel written, both faces of the
/// full-screen triangle.
pub(crate) const TARGET_PIPELINE: Raster<'static> = Raster::new(LAYDOWN_TARGET.name, "vs_full")
    .fragment("fs_target")
    .depth(Depth::test(DEPTH, Compare::Always, true));

/// What the last compute laydown drew (read back by
/// [`Inspect::read_laydown_stats`](crate::inspect::Inspect::read_laydown_stats)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LaydownStats {
    /// Triangles sent (instances x mesh triangles of every planned draw).
    pub triangles: u64,
    /// Of those, handed to the hardware part (crossing the near or far plane, or a box over
    /// a million pixels), including any past the list's capacity.
    pub hybrid: u64,
    /// Of those, rasterised by the large-triangle pass (a box wider or taller than
    /// [`RendererConfig::geometry.compute_laydown_max_extent`](crate::config::GeometryConfig::compute_laydown_max_extent) pixels, or
    /// larger than a quarter of its square).
    pub large: u64,
    /// Listed triangles past either list's capacity (not drawn; the report shows them).
    pub dropped: u64,
}

/// The compute laydown's pipelines.
pub(crate) struct ComputeLaydown {
    raster: ComputePass<u32>,
    hybrid_layouts: Layouts,
    hybrid: wgpu::RenderPipeline,
    target_layouts: Layouts,
    target: wgpu::RenderPipeline,
    unpack: ComputePass<[u32; 2]>,
    kind: LaydownTarget,
}

impl ComputeLaydown {
    /// The pipelines over a target of `kind`; `subgroups`: the list appends aggregated
    /// per subgroup; `max_extent`: the largest box (pixels) rasterised in compute.
    pub(crate) fn new(
        device: &wgpu::Device,
        kind: LaydownTarget,
        subgroups: bool,
        max_extent: f32,
    ) -> Result<Self> {
        let texture = kind == LaydownTarget::Texture;
        let target_feature: &[&str] = if texture { &["texture_target"] } else { &[] };
        let mut features = target_feature.to_vec();
        if subgroups {
            features.push("subgroups");
        }
        let (raster_pass, hybrid_pass, unpack_pass) = if texture {
            (
                &COMPUTE_LAYDOWN_TEXTURE,
                &COMPUTE_LAYDOWN_HYBRID_TEXTURE,
                &LAYDOWN_UNPACK_TEXTURE,
            )
        } else {
            (&COMPUTE_LAYDOWN, &COMPUTE_LAYDOWN_HYBRID, &LAYDOWN_UNPACK)
        };
        let extent = f64::from(max_extent.clamp(0.0, crate::config::COMPUTE_LAYDOWN_EXTENT_LIMIT));
        let raster = ComputePass::new(
            device,
            raster_pass,
            &features,
            &[("GPU_COMPUTE_LAYDOWN_MAX_EXTENT", extent)],
        )?;
        let hybrid_pass = RasterPass::new(device, hybrid_pass, target_feature, &[])?;
        let hybrid = hybrid_pass.pipeline(device, &HYBRID_PIPELINE)?;
        let hybrid_layouts = hybrid_pass.layouts;
        let target_pass = RasterPass::new(device, &LAYDOWN_TARGET, &[], &[])?;
        let target = target_pass.pipeline(device, &TARGET_PIPELINE)?;
        let target_layouts = target_pass.layouts;
        Ok(Self {
            raster,
            hybrid_layouts,
            hybrid,
            target_layouts,
            target,
            unpack: ComputePass::new(device, unpack_pass, target_feature, &[])?,
            kind,
        })
    }

    /// The target these pipelines write.
    pub(crate) fn kind(&self) -> LaydownTarget {
        self.kind
    }

    /// A prepared scene's groups: `scene` resources by binding name (group 0), the
    /// scene's planned `draws`, its index buffer and the renderer's 64-bit `target`.
    /// `None` when the draws' items do not fit a `u32` (the frame keeps the hardware
    /// laydown).
    pub(crate) fn groups(
        &self,
        device: &wgpu::Device,
        scene: &[(&str, wgpu::BindingResource<'_>)],
        classification: &[(&str, wgpu::BindingResource<'_>)],
        draws: &[Draw],
        indices: &wgpu::Buffer,
        target: &TargetResource,
    ) -> Result<Option<Groups>> {
        use wgpu::util::DeviceExt;
        let Some((rows, items)) = draw_table(draws) else {
            return Ok(None);
        };
        let mut bytes = Vec::with_capacity(16 + 32 * rows.len().max(1));
        for w in [rows.len() as u32, items, 0, 0] {
            bytes.extend_from_slice(&w.to_le_bytes());
        }
        if rows.is_empty() {
            bytes.extend_from_slice(bytemuck::bytes_of(&GpuLaydownDraw::default()));
        }
        bytes.extend_from_slice(bytemuck::cast_slice(&rows));
        let table = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("compute laydown draws"),
            contents: &bytes,
            usage: wgpu::BufferUsages::STORAGE,
        });
        let capacity = items.clamp(1, HYBRID_CAPACITY);
        let list = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("compute laydown hybrid list"),
            size: HYBRID_HEADER + 4 * u64::from(capacity),
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::INDIRECT
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let large = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("compute laydown large list"),
            size: LARGE_HEADER + 4 * u64::from(items.clamp(1, LARGE_CAPACITY)),
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let large_dispatch = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("compute laydown large dispatch"),
            size: 12,
            usage: wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let group1 = [
            ("laydown_draws", table.as_entire_binding()),
            ("laydown_indices", indices.as_entire_binding()),
            ("laydown_target", target.binding()),
            ("hybrid", list.as_entire_binding()),
        ];
        let mut raster_group1 = group1.to_vec();
        raster_group1.push(("large", large.as_entire_binding()));
        Ok(Some(Groups {
            raster: [
                self.raster.bind_group(device, "scene", scene)?,
                self.raster.bind_group(device, "laydown", &raster_group1)?,
            ],
            hybrid: [
                self.hybrid_layouts.bind_group(device, "scene", scene)?,
                self.hybrid_layouts.bind_group(device, "laydown", &group1)?,
            ],
            list,
            large,
            large_dispatch,
            items,
            unpack: self
                .unpack
                .bind_group(device, "classification", classification)?,
            _draws: table,
        }))
    }

    /// The conversion's and the unpack's groups over the renderer's `targets` (whose
    /// 64-bit target is `target`).
    pub(crate) fn target_groups(
        &self,
        device: &wgpu::Device,
        targets: &Targets,
        target: &TargetResource,
        tile_depths: &wgpu::Buffer,
    ) -> Result<TargetGroups> {
        debug_assert_eq!(target.kind(), self.kind);
        Ok(TargetGroups {
            target: self.target_layouts.bind_group(
                device,
                "target",
                &[(
                    "depth_float",
                    wgpu::BindingResource::TextureView(&targets.depth_float_view),
                )],
            )?,
            unpack: self.unpack.bind_group(
                device,
                "unpack",
                &[
                    ("laydown_target", target.binding()),
                    (
                        "vis_out",
                        wgpu::BindingResource::TextureView(&targets.vis_view),
                    ),
                    (
                        "depth_float",
                        wgpu::BindingResource::TextureView(&targets.depth_float_view),
                    ),
                    ("tile_depths", tile_depths.as_entire_binding()),
                ],
            )?,
        })
    }

    /// Records the laydown: clear target and lists, the raster in one pass (timed
    /// "laydown"), the large triangles ("laydown large") and after them, in the same pass,
    /// `beside_raster`'s dispatches (which must share no buffer with the raster: they run
    /// on the SMs the large triangles' last workgroups leave idle; in the small triangles'
    /// pass where there is no large pass), the hardware part ("laydown hybrid"), with
    /// `depth_target` the depth target's conversion ("laydown target"), then the unpack
    /// ("laydown unpack": words, vis texture, float depth; no vis copy follows).
    /// Returns false, recording nothing, where the scene or the renderer has no compute
    /// resources.
    pub(crate) fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
        depth_target: bool,
        beside_raster: impl FnOnce(&mut wgpu::ComputePass<'_>),
    ) -> bool {
        let (Some(g), Some(target), Some(groups)) = (
            &f.scene.compute_laydown,
            &f.targets.vis64,
            &f.groups.laydown_target,
        ) else {
            return false;
        };
        let Ok(unpack) = self.unpack.step("unpack") else {
            return false;
        };
        let large = self.raster.step("raster_large");
        let mut beside_raster = Some(beside_raster);
        if let TargetResource::Buffer(target) = target {
            encoder.clear_buffer(target, 0, None);
        }
        encoder.clear_buffer(&g.list, 0, Some(HYBRID_HEADER));
        encoder.clear_buffer(&g.large, 0, Some(LARGE_HEADER));
        {
            // The small triangles, then the large list's count as arguments.
            let mut pass = timer.begin_compute_as(encoder, "compute laydown", "laydown");
            if g.items > 0 {
                self.raster
                    .record(&mut pass, &[&g.raster[0], &g.raster[1]], &g.items);
            }
            if (g.items == 0 || large.is_err())
                && let Some(beside) = beside_raster.take()
            {
                beside(&mut pass);
            }
        }
        if g.items > 0
            && let Ok(large) = large
        {
            encoder.copy_buffer_to_buffer(&g.large, 0, &g.large_dispatch, 0, 12);
            let mut pass = timer.begin_compute_as(
                encoder,
                "compute laydown, large triangles",
                "laydown large",
            );
            pass.set_bind_group(0, &g.raster[0], &[]);
            pass.set_bind_group(1, &g.raster[1], &[]);
            pass.set_pipeline(&large.pipeline);
            pass.dispatch_workgroups_indirect(&g.large_dispatch, 0);
            if let Some(beside) = beside_raster.take() {
                beside(&mut pass);
            }
        }
        // The hybrid part neither tests nor writes the attachment (loading it is cheap,
        // clearing it cost 0.6 ms at 4K on the H200); the conversion writes every pixel.
        let depth_pass =
            |encoder: &'_ mut wgpu::CommandEncoder, label: &'static str, timer: &mut GpuTimer| {
                let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some(label),
                    color_attachments: &[],
                    depth_stencil_attachment: Some(depth_attachment(&f.targets.depth_view, true)),
                    timestamp_writes: timer.render(label),
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                pass.forget_lifetime()
            };
        {
            let mut pass = depth_pass(encoder, "laydown hybrid", timer);
            pass.set_pipeline(&self.hybrid);
            pass.set_bind_group(0, &g.hybrid[0], &[]);
            pass.set_bind_group(1, &g.hybrid[1], &[]);
            pass.draw_indirect(&g.list, 0);
        }
        let size = [f.targets.width, f.targets.height];
        if let Some([x, y, z]) = self.unpack.workgroups(unpack, &size) {
            let mut pass = timer.begin_compute(encoder, "laydown unpack");
            pass.set_bind_group(0, &g.unpack, &[]);
            pass.set_bind_group(1, &groups.unpack, &[]);
            pass.set_pipeline(&unpack.pipeline);
            pass.dispatch_workgroups(x, y, z);
        }
        if depth_target {
            let mut pass = depth_pass(encoder, "laydown target", timer);
            pass.set_pipeline(&self.target);
            pass.set_bind_group(0, &groups.target, &[]);
            pass.draw(0..3, 0..1);
        }
        true
    }
}

/// The statistics of the hybrid list's header (its vertex count) for a scene of `items`
/// triangles.
pub(crate) fn stats(items: u32, vertex_count: u32, large: u32) -> LaydownStats {
    let hybrid = u64::from(vertex_count / 3);
    let hybrid_capacity = u64::from(items.clamp(1, HYBRID_CAPACITY));
    let large_capacity = u64::from(items.clamp(1, LARGE_CAPACITY));
    LaydownStats {
        triangles: u64::from(items),
        hybrid,
        large: u64::from(large),
        dropped: hybrid.saturating_sub(hybrid_capacity)
            + u64::from(large).saturating_sub(large_capacity),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::COMPUTE_LAYDOWN_MAX_EXTENT;
    use shadercheck::Caps;

    #[test]
    fn descriptions_match_their_modules_with_int64_atomics() {
        shadercheck::check_pass(&COMPUTE_LAYDOWN, |f| {
            if f.contains(&"subgroups") {
                Caps::INT64.union(Caps::SUBGROUP)
            } else {
                Caps::INT64
            }
        });
        shadercheck::check_pass(&COMPUTE_LAYDOWN_HYBRID, |_| Caps::INT64);
        shadercheck::check_pass(&LAYDOWN_TARGET, |_| Caps::CORE);
        shadercheck::check_pass(&LAYDOWN_UNPACK, |_| Caps::CORE);
        // The texture target's variants: the feature on, and naga's 64-bit texture atomics.
        shadercheck::check_pass_with(&COMPUTE_LAYDOWN_TEXTURE, &["texture_target"], |f| {
            if f.contains(&"subgroups") {
                Caps::TEXTURE_INT64.union(Caps::SUBGROUP)
            } else {
                Caps::TEXTURE_INT64
            }
        });
        shadercheck::check_pass_with(&COMPUTE_LAYDOWN_HYBRID_TEXTURE, &["texture_target"], |_| {
            Caps::TEXTURE_INT64
        });
        shadercheck::check_pass_with(&LAYDOWN_UNPACK_TEXTURE, &["texture_target"], |_| {
            Caps::TEXTURE_INT64
        });
        shadercheck::check_raster(&COMPUTE_LAYDOWN_HYBRID, &HYBRID_PIPELINE, &[], Caps::INT64);
        shadercheck::check_raster(
            &COMPUTE_LAYDOWN_HYBRID_TEXTURE,
            &HYBRID_PIPELINE,
            &["texture_target"],
            Caps::TEXTURE_INT64,
        );
        shadercheck::check_raster(&LAYDOWN_TARGET, &TARGET_PIPELINE, &[], Caps::CORE);
        let src = COMPUTE_LAYDOWN_TEXTURE.source(&["texture_target"]).unwrap();
        assert!(shadercheck::validate(&src, Caps::INT64).is_err());

        let src = COMPUTE_LAYDOWN.source(&[]).unwrap();
        assert!(shadercheck::validate(&src, Caps::CORE).is_err());
        // The lists' headers and the dispatch rows, as Rust sizes and records them.
        let m = shadercheck::validate(&src, Caps::INT64).unwrap();
        let items_at = |name: &str| {
            let (_, members) = shadercheck::struct_layout(&m, name).unwrap();
            members
                .iter()
                .find(|(n, _)| n == "items")
                .map(|&(_, o)| u64::from(o))
        };
        assert_eq!(items_at("GpuHybridList"), Some(HYBRID_HEADER));
        assert_eq!(items_at("GpuLargeList"), Some(LARGE_HEADER));
        assert_eq!(
            shadercheck::override_f32(&m, "GPU_COMPUTE_LAYDOWN_MAX_EXTENT"),
            Some(COMPUTE_LAYDOWN_MAX_EXTENT)
        );
        let rows = shader::MAX_WORKGROUPS_X;
        assert_eq!(shadercheck::const_u32(&m, "GPU_LAYDOWN_ROWS"), Some(rows));
        assert_eq!(
            shadercheck::const_u32(&m, "GPU_LAYDOWN_ROW_ITEMS"),
            Some(rows * 64)
        );
    }

    fn draw(index_count: u32, instances: u32, first_instance: u32) -> Draw {
        Draw {
            first_index: 30,
            index_count,
            base_vertex: 7,
            first_instance,
            instance_count: instances,
            alpha_tested: first_instance > 0,
            regular: false,
            first_chunk: 0,
            chunk_count: 0,
        }
    }

    #[test]
    fn the_draw_table_prefixes_items_and_leaves_out_empty_draws() {
        let (rows, items) =
            draw_table(&[draw(6, 3, 0), draw(0, 5, 3), draw(9, 0, 8), draw(9, 2, 8)]).unwrap();
        assert_eq!(items, 2 * 3 + 3 * 2);
        assert_eq!(rows.len(), 2);
        assert_eq!(
            (rows[0].first_item, rows[0].triangles, rows[0].flags),
            (0, 2, 0)
        );
        assert_eq!(
            (rows[1].first_item, rows[1].triangles, rows[1].flags),
            (6, 3, DRAW_ALPHA_TESTED)
        );
        // Past u32: refused (the frame keeps the hardware laydown).
        assert!(draw_table(&[draw(3 * 65_536, 65_536, 0)]).is_none());
    }

    #[test]
    fn stats_count_what_did_not_fit() {
        assert_eq!(stats(100, 30, 7).hybrid, 10);
        assert_eq!(stats(100, 30, 7).large, 7);
        assert_eq!(stats(100, 30, 7).dropped, 0);
        let s = stats(u32::MAX, 3 * (HYBRID_CAPACITY + 5), HYBRID_CAPACITY + 2);
        assert_eq!(s.dropped, 5);
        let s = stats(u32::MAX, 3 * (HYBRID_CAPACITY + 5), LARGE_CAPACITY + 2);
        assert_eq!(s.dropped, 7);
    }
}
